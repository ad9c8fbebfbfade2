//! The host facts of the support bundle: tracerctl's version, the OS release, the kernel, the CAN driver
//! and modules, `ip -details -statistics link show IFACE`, the serial port's owner and mode. Each read from
//! a fixed file or command, never from the environment; the parsing is pure and tested on sample texts.

use std::fmt::Write as _;
use std::path::Path;

use crate::link::LinkChoice;

/// Kernel modules named here are CAN drivers worth listing even when their names do not start with
/// `can` (the adapters a TRACER is wired through: USB, PCI, SPI and SoC controllers).
const CAN_DRIVER_MODULES: &[&str] = &[
    "vcan",
    "vxcan",
    "slcan",
    "gs_usb",
    "peak_usb",
    "peak_pci",
    "peak_pciefd",
    "kvaser_usb",
    "kvaser_pci",
    "kvaser_pciefd",
    "ems_usb",
    "esd_usb",
    "esd_usb2",
    "usb_8dev",
    "ixxat_usb2can",
    "etas_es58x",
    "ucan",
    "mcba_usb",
    "mcp251x",
    "mcp251xfd",
    "mttcan",
    "flexcan",
    "m_can",
    "m_can_platform",
    "m_can_pci",
    "c_can",
    "c_can_platform",
    "c_can_pci",
    "sja1000",
    "sja1000_platform",
    "plx_pci",
    "ems_pci",
    "hi311x",
    "tcan4x5x",
];

/// The os-release fields worth a vendor's time (the file has URLs and marketing names besides).
const OS_RELEASE_FIELDS: &[&str] =
    &["PRETTY_NAME", "NAME", "ID", "ID_LIKE", "VERSION_ID", "VERSION_CODENAME"];

/// `KEY=value` pairs of an os-release file (freedesktop.org format), unquoted, in file order; comments,
/// blank and malformed lines skipped.
pub fn os_release(text: &str) -> Vec<(String, String)> {
    text.lines()
        .filter_map(|line| {
            let line = line.trim();
            if line.starts_with('#') {
                return None;
            }
            let (key, value) = line.split_once('=')?;
            let valid = !key.is_empty()
                && key.bytes().all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_');
            valid.then(|| (key.to_string(), unquote(value.trim())))
        })
        .collect()
}

/// A shell-quoted os-release value: `"Ubuntu 22.04.4 LTS"`, `'x'`, or bare; `\"`, `\\`, `\$` and `` \` ``
/// unescaped inside double quotes.
fn unquote(value: &str) -> String {
    if let Some(inner) = value.strip_prefix('\'').and_then(|v| v.strip_suffix('\'')) {
        return inner.to_string();
    }
    let Some(inner) = value.strip_prefix('"').and_then(|v| v.strip_suffix('"')) else {
        return value.to_string();
    };
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(c) = chars.next() {
        match (c, chars.clone().next()) {
            ('\\', Some(next @ ('"' | '\\' | '$' | '`'))) => {
                out.push(next);
                chars.next();
            }
            _ => out.push(c),
        }
    }
    out
}

/// The CAN lines of `/proc/modules` (`name size instances dependencies state address`), without the load
/// address: modules whose name starts with `can`, the known CAN drivers, and `driver_module` (the
/// interface's own, whatever its name).
pub fn can_modules(proc_modules: &str, driver_module: Option<&str>) -> Vec<String> {
    proc_modules
        .lines()
        .filter_map(|line| {
            let fields: Vec<&str> = line.split_whitespace().collect();
            let name = *fields.first()?;
            let wanted =
                name.starts_with("can") || CAN_DRIVER_MODULES.contains(&name) || Some(name) == driver_module;
            wanted.then(|| fields[..fields.len().min(5)].join(" "))
        })
        .collect()
}

/// A host name as it may appear in a file name: letters, digits, `-` and `.`, anything else `_`, at most
/// 64 characters; `host` when empty.
pub fn file_name_host(name: &str) -> String {
    let cleaned: String = name
        .trim()
        .chars()
        .take(64)
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '.' { c } else { '_' })
        .collect();
    if cleaned.is_empty() || cleaned.chars().all(|c| c == '.') {
        "host".to_string()
    } else {
        cleaned
    }
}

/// This machine's name, from the kernel (Linux); `host` elsewhere.
pub fn host_name() -> String {
    let name = read_trimmed("/proc/sys/kernel/hostname").or_else(|| read_trimmed("/etc/hostname"));
    file_name_host(name.as_deref().unwrap_or(""))
}

fn read_trimmed(path: &str) -> Option<String> {
    std::fs::read_to_string(path).ok().map(|text| text.trim().to_string()).filter(|text| !text.is_empty())
}

/// The host facts as `host.txt` holds them.
pub fn facts(link: &LinkChoice) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "tracerctl: {} ({})", env!("CARGO_PKG_VERSION"), std::env::consts::ARCH);
    let _ = writeln!(out, "host name: {}", host_name());
    os_section(&mut out);
    kernel_section(&mut out);
    match link {
        LinkChoice::SocketCan { iface } => can_section(&mut out, Some(iface)),
        LinkChoice::Serial { path, baud } => {
            serial_section(&mut out, path, *baud);
            can_section(&mut out, None);
        }
        LinkChoice::Sim => {
            let _ = writeln!(out, "\nlink: the in-process virtual TRACER (--sim), no hardware");
            can_section(&mut out, None);
        }
        LinkChoice::Replay { .. } => {
            let _ = writeln!(out, "\nlink: a replayed log (--replay), no hardware");
            can_section(&mut out, None);
        }
    }
    out
}

fn os_section(out: &mut String) {
    let _ = writeln!(out, "\nOS release:");
    let text = std::fs::read_to_string("/etc/os-release")
        .or_else(|_| std::fs::read_to_string("/usr/lib/os-release"));
    match text {
        Ok(text) => {
            for (key, value) in
                os_release(&text).iter().filter(|(key, _)| OS_RELEASE_FIELDS.contains(&key.as_str()))
            {
                let _ = writeln!(out, "  {key}: {value}");
            }
        }
        Err(_) => {
            let _ = writeln!(out, "  no /etc/os-release ({})", std::env::consts::OS);
        }
    }
    // NVIDIA Jetson: the L4T release (the kernel and its CAN driver, mttcan, come with it).
    if let Some(line) = std::fs::read_to_string("/etc/nv_tegra_release")
        .ok()
        .and_then(|t| t.lines().next().map(str::to_string))
    {
        let _ = writeln!(out, "  nv_tegra_release: {}", line.trim_start_matches('#').trim());
    }
}

fn kernel_section(out: &mut String) {
    let field = |name: &str| read_trimmed(&format!("/proc/sys/kernel/{name}"));
    match (field("ostype"), field("osrelease")) {
        (Some(kind), Some(release)) => {
            let version = field("version").unwrap_or_default();
            let _ = writeln!(out, "kernel: {kind} {release} {version} {}", std::env::consts::ARCH);
        }
        _ => {
            let _ = writeln!(out, "kernel: not readable here ({})", std::env::consts::OS);
        }
    }
}

/// The interface's driver and module (sysfs), the CAN modules loaded, the CAN interfaces, and `ip`'s view.
fn can_section(out: &mut String, iface: Option<&str>) {
    let _ = writeln!(out, "\nCAN:");
    let mut driver_module = None;
    if let Some(iface) = iface {
        let device = Path::new("/sys/class/net").join(iface).join("device");
        let base = |path: &Path| {
            std::fs::read_link(path)
                .ok()
                .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        };
        let driver = base(&device.join("driver"));
        driver_module = base(&device.join("driver/module"));
        let exists = Path::new("/sys/class/net").join(iface).exists();
        let _ = writeln!(
            out,
            "  interface {iface}: {}",
            match (exists, &driver) {
                (false, _) => "does not exist".to_string(),
                (true, Some(driver)) =>
                    format!("driver {driver}, module {}", driver_module.as_deref().unwrap_or("built in")),
                (true, None) => "no device driver (a virtual interface)".to_string(),
            }
        );
    }
    let interfaces = can_interfaces();
    let _ = writeln!(
        out,
        "  CAN interfaces: {}",
        if interfaces.is_empty() { "none".to_string() } else { interfaces.join(", ") }
    );
    match std::fs::read_to_string("/proc/modules") {
        Ok(text) => {
            let modules = can_modules(&text, driver_module.as_deref());
            let _ = writeln!(out, "  CAN modules loaded (name size instances used-by state):");
            if modules.is_empty() {
                let _ = writeln!(out, "    none");
            }
            for line in modules {
                let _ = writeln!(out, "    {line}");
            }
        }
        Err(_) => {
            let _ = writeln!(out, "  no /proc/modules here");
        }
    }
    if let Some(iface) = iface {
        let _ = writeln!(out, "\nip -details -statistics link show {iface}:");
        out.push_str(&indent(&ip_link(iface)));
    }
}

#[cfg(target_os = "linux")]
fn can_interfaces() -> Vec<String> {
    crate::link::can_interface::can_interfaces()
}

#[cfg(not(target_os = "linux"))]
fn can_interfaces() -> Vec<String> {
    Vec::new()
}

/// `ip -details -statistics link show IFACE`, run from its usual places with an empty environment; what
/// it printed (standard error too), or why it did not run.
fn ip_link(iface: &str) -> String {
    const PLACES: &[&str] = &["/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"];
    let Some(ip) = PLACES.iter().find(|place| Path::new(place).is_file()) else {
        return "no ip command (iproute2) on this machine\n".to_string();
    };
    let output = std::process::Command::new(ip)
        .args(["-details", "-statistics", "link", "show", iface])
        .env_clear()
        .stdin(std::process::Stdio::null())
        .output();
    match output {
        Ok(output) => {
            let mut text = String::from_utf8_lossy(&output.stdout).into_owned();
            text.push_str(&String::from_utf8_lossy(&output.stderr));
            if !output.status.success() {
                let _ = writeln!(text, "({ip} exited with {})", output.status);
            }
            text
        }
        Err(error) => format!("{ip} could not run: {error}\n"),
    }
}

fn indent(text: &str) -> String {
    text.lines().map(|line| format!("  {line}\n")).collect()
}

/// The serial port: what it is (a by-id link resolved), its owner, group and mode.
fn serial_section(out: &mut String, path: &Path, baud: u32) {
    let _ = writeln!(out, "\nserial port {} at {baud} baud:", path.display());
    if let Ok(target) = std::fs::canonicalize(path) {
        if target != path {
            let _ = writeln!(out, "  resolves to {}", target.display());
        }
    }
    match crate::link::serial_access::device_access(path) {
        Some(access) => {
            let _ = writeln!(
                out,
                "  {} {}:{} (mode {:o}); this process {} in group {}",
                crate::link::serial_access::mode_text(access.mode),
                access.owner,
                access.group,
                access.mode & 0o7777,
                if access.in_group { "is" } else { "is not" },
                access.group
            );
        }
        None if path.exists() => {
            let _ = writeln!(out, "  owner and mode not available on this system");
        }
        None => {
            let _ = writeln!(out, "  does not exist");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn os_release_is_unquoted_and_comments_are_skipped() {
        let text = "# written by the vendor\nNAME=\"Ubuntu\"\nVERSION_ID=\"20.04\"\nID=ubuntu\n\
                    PRETTY_NAME='Ubuntu 20.04.6 LTS'\nQUOTED=\"say \\\"hi\\\" \\$HOME\"\nbad line\nlower=x\n";
        let fields = os_release(text);
        assert_eq!(
            fields,
            [
                ("NAME".to_string(), "Ubuntu".to_string()),
                ("VERSION_ID".to_string(), "20.04".to_string()),
                ("ID".to_string(), "ubuntu".to_string()),
                ("PRETTY_NAME".to_string(), "Ubuntu 20.04.6 LTS".to_string()),
                ("QUOTED".to_string(), "say \"hi\" $HOME".to_string()),
            ]
        );
    }

    #[test]
    fn can_modules_keep_can_and_driver_lines_without_the_address() {
        let text = "can_raw 20480 2 - Live 0xffffffffc0a1b000\n\
                    can 24576 1 can_raw, Live 0x0000000000000000\n\
                    gs_usb 28672 0 - Live 0x0000000000000000\n\
                    ext4 999 1 - Live 0x0\n\
                    my_board_can2 1000 0 - Live 0x0\n\
                    scanner 1 0 - Live 0x0\n";
        assert_eq!(
            can_modules(text, Some("my_board_can2")),
            [
                "can_raw 20480 2 - Live",
                "can 24576 1 can_raw, Live",
                "gs_usb 28672 0 - Live",
                "my_board_can2 1000 0 - Live"
            ]
        );
        assert_eq!(can_modules(text, None).len(), 3, "scanner and ext4 are not CAN modules");
    }

    #[test]
    fn host_names_fit_in_file_names() {
        assert_eq!(file_name_host("jetson-nano.local\n"), "jetson-nano.local");
        assert_eq!(file_name_host("a b/c:d"), "a_b_c_d");
        assert_eq!(file_name_host(""), "host");
        assert_eq!(file_name_host(".."), "host");
        assert_eq!(file_name_host(&"x".repeat(100)).len(), 64);
    }
}
