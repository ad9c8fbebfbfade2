//! The recorder's systemd unit, debian/tracerctl-record@.service: its ExecStart line run as systemd would run
//! it (the instance expanded, `--dry-run` added), its directives all known to systemd 237 (JetPack 4), and
//! `systemd-analyze verify` on it. tests/deb/check.sh checks the installed unit the same way as root.

use std::path::{Path, PathBuf};

use crate::util::{stderr, stdout};

const UNIT: &str = "debian/tracerctl-record@.service";

fn unit_text() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(UNIT)).unwrap()
}

/// (section, key, value) of every setting, in order; comments and blank lines left out.
fn settings(text: &str) -> Vec<(String, String, String)> {
    let mut section = String::new();
    let mut found = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') || line.starts_with(';') {
            continue;
        }
        if let Some(name) = line.strip_prefix('[').and_then(|rest| rest.strip_suffix(']')) {
            section = name.to_string();
            continue;
        }
        let (key, value) = line.split_once('=').unwrap_or_else(|| panic!("{UNIT}: not key=value: {line}"));
        found.push((section.clone(), key.trim().to_string(), value.trim().to_string()));
    }
    found
}

fn setting(text: &str, key: &str) -> String {
    let values: Vec<String> =
        settings(text).into_iter().filter(|(_, name, _)| name == key).map(|(_, _, value)| value).collect();
    assert_eq!(values.len(), 1, "{UNIT}: {key}= appears {} times", values.len());
    values[0].clone()
}

/// systemd's unescaping of an instance name for %I: '-' is '/', `\xNN` a byte (systemd.unit(5), "String
/// Escaping for Inclusion in Unit Names").
fn unescape_instance(instance: &str) -> String {
    let mut bytes = Vec::new();
    let mut rest = instance.as_bytes();
    while let Some((&byte, tail)) = rest.split_first() {
        if let [b'\\', b'x', high, low, after @ ..] = rest {
            let hex = std::str::from_utf8(&[*high, *low]).unwrap().to_string();
            bytes.push(u8::from_str_radix(&hex, 16).unwrap());
            rest = after;
            continue;
        }
        bytes.push(if byte == b'-' { b'/' } else { byte });
        rest = tail;
    }
    String::from_utf8(bytes).unwrap()
}

/// ExecStart's words for `instance`, with %i and %I expanded as systemd does.
fn exec_start(instance: &str) -> Vec<String> {
    let line = setting(&unit_text(), "ExecStart");
    // Words split on spaces are exactly systemd's words only without quotes or escapes.
    assert!(!line.contains(['"', '\'', '\\', '$', ';']), "ExecStart needs a real systemd parser: {line}");
    let unescaped = unescape_instance(instance);
    line.split_whitespace().map(|word| word.replace("%I", &unescaped).replace("%i", instance)).collect()
}

#[test]
fn the_unit_runs_the_command_line_the_docs_show() {
    assert_eq!(
        setting(&unit_text(), "ExecStart"),
        "/usr/bin/tracerctl record --instance %I --dir /var/lib/tracerctl/%i"
    );
    assert_eq!(
        exec_start("dev-ttyUSB0"),
        [
            "/usr/bin/tracerctl",
            "record",
            "--instance",
            "dev/ttyUSB0",
            "--dir",
            "/var/lib/tracerctl/dev-ttyUSB0"
        ]
    );
    assert_eq!(unescape_instance(r"dev-serial-by\x2did-usb\x2dFTDI"), "dev/serial/by-id/usb-FTDI");
}

#[test]
fn the_recorder_writes_where_systemd_lets_it() {
    let text = unit_text();
    // ProtectSystem=strict leaves only the state directory writable: --dir must be exactly it.
    assert_eq!(setting(&text, "ProtectSystem"), "strict");
    let exec_start = setting(&text, "ExecStart");
    let words: Vec<&str> = exec_start.split_whitespace().collect();
    let dir = words[words.iter().position(|word| *word == "--dir").expect("--dir") + 1];
    assert_eq!(dir, format!("/var/lib/{}", setting(&text, "StateDirectory")));
    assert_eq!(setting(&text, "User"), "tracerctl");
    assert!(setting(&text, "SupplementaryGroups").split_whitespace().any(|group| group == "dialout"));
    let families = setting(&text, "RestrictAddressFamilies");
    for family in ["AF_CAN", "AF_NETLINK", "AF_UNIX"] {
        assert!(families.split_whitespace().any(|name| name == family), "{family} not in {families}");
    }
    // Each would hide the link or stop the recorder when the adapter goes away.
    for (_, key, value) in settings(&text) {
        assert!(
            !matches!(key.as_str(), "PrivateNetwork" | "PrivateDevices" | "BindsTo" | "Requires" | "PartOf"),
            "{key}={value}"
        );
    }
    assert_eq!(setting(&text, "Restart"), "on-failure");
    assert_eq!(setting(&text, "WantedBy"), "multi-user.target");
}

/// Every directive the unit may use, with the systemd version that introduced it (or its value used here):
/// the unit must work on JetPack 4's systemd 237, where a newer directive is ignored with a warning.
const DIRECTIVES: &[(&str, u32)] = &[
    ("Description", 1),
    ("Documentation", 1),
    ("After", 1),
    ("Type", 1),
    ("ExecStart", 1),
    ("User", 1),
    ("Group", 1),
    ("SupplementaryGroups", 1),
    ("StandardOutput", 1),
    ("StandardError", 1),
    ("Restart", 1),
    ("RestartSec", 1),
    ("PrivateTmp", 1),
    ("CapabilityBoundingSet", 1),
    ("WantedBy", 1),
    ("RestartPreventExitStatus", 189),
    ("NoNewPrivileges", 187),
    ("SystemCallArchitectures", 209),
    ("RestrictAddressFamilies", 211),
    ("ProtectHome", 214),
    ("MemoryDenyWriteExecute", 231),
    ("RestrictRealtime", 231),
    // ProtectSystem= itself is from 214; "strict" from 232.
    ("ProtectSystem", 232),
    ("ProtectKernelTunables", 232),
    ("ProtectKernelModules", 232),
    ("ProtectControlGroups", 232),
    ("RestrictNamespaces", 233),
    ("StateDirectory", 235),
    ("LockPersonality", 235),
];

#[test]
fn every_directive_exists_in_systemd_237() {
    for (section, key, _) in settings(&unit_text()) {
        let Some((_, since)) = DIRECTIVES.iter().find(|(name, _)| *name == key) else {
            panic!(
                "[{section}] {key}= is not in DIRECTIVES: add it with the systemd version that introduced it"
            )
        };
        assert!(*since <= 237, "[{section}] {key}= needs systemd {since}; JetPack 4 has 237");
    }
}

/// `systemd-analyze verify` on instances of a copy whose ExecStart runs the built binary (verify checks that
/// it exists); man pages are not installed here (tests/deb/check.sh checks them too, on the installed unit).
/// Any output fails: an unknown directive is only a warning with exit 0.
#[cfg(target_os = "linux")]
#[test]
fn systemd_analyze_verify_accepts_the_instances() {
    let Ok(version) = std::process::Command::new("systemd-analyze").arg("--version").output() else {
        eprintln!(
            "systemd-analyze is not installed: skipped (tests/deb/check.sh installs it and runs verify)"
        );
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let text = unit_text().replace("/usr/bin/tracerctl", binary.to_str().unwrap());
    for instance in ["can0", "vcan0", "dev-ttyUSB0"] {
        let path = dir.path().join(format!("tracerctl-record@{instance}.service"));
        std::fs::write(&path, &text).unwrap();
        let output = std::process::Command::new("systemd-analyze")
            .args(["verify", "--man=no"])
            .arg(&path)
            .output()
            .unwrap();
        assert!(output.status.success(), "verify {instance}: {}", stderr(&output));
        assert_eq!(format!("{}{}", stdout(&output), stderr(&output)), "", "verify {instance}");
    }
    // And a wrong directive does make it speak: the check above can fail.
    let path = dir.path().join("tracerctl-record@can1.service");
    std::fs::write(&path, text.replace("LockPersonality=", "LockPersonalty=")).unwrap();
    let output = std::process::Command::new("systemd-analyze")
        .args(["verify", "--man=no"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(stderr(&output).contains("LockPersonalty"), "{}: {}", stdout(&version), stderr(&output));
}

/// ExecStart exactly as systemd runs it, for a CAN and a serial instance, the state directory moved to a
/// temporary one and `--dry-run` added: the recorder names the link it resolved and the directory, exit 0.
#[test]
fn exec_start_resolves_the_link_and_the_directory() {
    let state = tempfile::tempdir().unwrap();
    let config_home = tempfile::tempdir().unwrap();
    for (instance, link) in [("vcan0", "vcan0"), ("dev-ttyUSB0", "/dev/ttyUSB0")] {
        let words = exec_start(instance);
        assert_eq!(words[0], "/usr/bin/tracerctl");
        let dir: PathBuf = state.path().join(instance);
        let args: Vec<String> = words[1..]
            .iter()
            .map(|word| {
                word.strip_prefix("/var/lib/tracerctl/")
                    .map_or_else(|| word.clone(), |name| state.path().join(name).display().to_string())
            })
            .chain(["--dry-run".to_string()])
            .collect();
        assert!(args.contains(&dir.display().to_string()), "{args:?}");
        // A user's config file or profile must not take part: only the unit's own command line.
        let output = crate::util::tracerctl()
            .args(&args)
            .env("XDG_CONFIG_HOME", config_home.path())
            .env_remove("TRACERCTL_PROFILE")
            .output()
            .unwrap();
        let said = format!("{}{}", stdout(&output), stderr(&output));
        assert_eq!(output.status.code(), Some(0), "{args:?}: {said}");
        assert!(said.contains(link), "{instance}: the link {link} not in:\n{said}");
        assert!(said.contains(&dir.display().to_string()), "{instance}: {} not in:\n{said}", dir.display());
    }
}
