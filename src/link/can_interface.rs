//! What the kernel knows about a CAN interface: SocketCAN support, the interface's existence and type,
//! whether it is up, its bitrate, and its error state with counters (sysfs and rtnetlink).
//!
//! `open` and `doctor` share these checks, so a missing or down interface gets the same words from both.

use std::io;
use std::path::Path;

use socketcan::nl::{CanInterface, CanState};

/// The CAN controller's error state (ISO 11898-1 fault confinement), as the kernel reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BusState {
    /// Error counters below 96: normal.
    ErrorActive,
    /// A counter at 96 or more.
    ErrorWarning,
    /// A counter at 128 or more: the controller may no longer flag errors.
    ErrorPassive,
    /// Transmit errors reached 256: the controller is off the bus until restarted.
    BusOff,
    Stopped,
    Sleeping,
}

impl BusState {
    pub fn as_str(self) -> &'static str {
        match self {
            BusState::ErrorActive => "error-active",
            BusState::ErrorWarning => "error-warning",
            BusState::ErrorPassive => "error-passive",
            BusState::BusOff => "bus-off",
            BusState::Stopped => "stopped",
            BusState::Sleeping => "sleeping",
        }
    }
}

/// What kind of network interface a name refers to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Presence {
    Missing,
    /// It exists but is not CAN (an Ethernet or Wi-Fi interface, say).
    NotCan,
    /// A CAN interface; `driver` is the kernel driver of its hardware (gs_usb, peak_usb, mttcan, ...),
    /// `None` for virtual ones (vcan, vxcan).
    Can {
        driver: Option<String>,
    },
}

/// The CAN parameters of an interface (rtnetlink `IFLA_CAN_*`); all `None` on a virtual interface.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BusDetails {
    pub bitrate: Option<u32>,
    /// Sample point, 0..1.
    pub sample_point: Option<f64>,
    pub state: Option<BusState>,
    /// Transmit and receive error counters.
    pub error_counters: Option<(u16, u16)>,
    /// Automatic restart after bus-off, ms (0 = never).
    pub restart_ms: Option<u32>,
}

/// Interface counters from /sys/class/net/*/statistics, since the interface came up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    pub rx_errors: u64,
    pub tx_errors: u64,
    pub rx_dropped: u64,
    pub tx_dropped: u64,
    pub rx_over_errors: u64,
}

fn sys_net(iface: &str, file: &str) -> Option<String> {
    std::fs::read_to_string(Path::new("/sys/class/net").join(iface).join(file))
        .ok()
        .map(|s| s.trim().to_string())
}

/// `Err` with what to do when this kernel cannot open CAN sockets.
pub fn kernel_support() -> Result<(), String> {
    // SAFETY: a plain socket(2) call; the descriptor is closed right away.
    let probe = unsafe { libc::socket(libc::PF_CAN, libc::SOCK_RAW, libc::CAN_RAW) };
    if probe < 0 {
        let error = io::Error::last_os_error();
        if error.raw_os_error() == Some(libc::EAFNOSUPPORT) {
            return Err(format!(
                "this kernel has no SocketCAN support ({error}): load it with `sudo modprobe can can-raw` \
                 (plus your adapter's driver, e.g. gs_usb or peak_usb), or use --serial PORT or --sim"
            ));
        }
        return Err(format!("cannot create a CAN socket: {error}"));
    }
    // SAFETY: `probe` is a descriptor we own.
    unsafe { libc::close(probe) };
    Ok(())
}

pub fn presence(iface: &str) -> Presence {
    let Some(kind) = sys_net(iface, "type") else { return Presence::Missing };
    if kind.parse::<u16>().ok() != Some(libc::ARPHRD_CAN) {
        return Presence::NotCan;
    }
    let driver = std::fs::read_link(Path::new("/sys/class/net").join(iface).join("device/driver"))
        .ok()
        .and_then(|path| path.file_name().map(|name| name.to_string_lossy().into_owned()));
    Presence::Can { driver }
}

/// The CAN interfaces this machine has, sorted.
pub fn can_interfaces() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir("/sys/class/net")
        .into_iter()
        .flatten()
        .flatten()
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .filter(|name| matches!(presence(name), Presence::Can { .. }))
        .collect();
    names.sort();
    names
}

/// The message for a missing interface: which CAN interfaces exist instead, and how to get one.
pub fn missing_message(iface: &str) -> String {
    let others = can_interfaces();
    let found = if others.is_empty() {
        "this machine has no CAN interface; check the adapter with `dmesg | tail`".to_string()
    } else {
        format!("CAN interfaces here: {} (choose one with --iface)", others.join(", "))
    };
    format!(
        "CAN interface {iface} does not exist: {found}; list them with `ip -br link show type can`; \
         to test without hardware: `sudo ip link add dev vcan0 type vcan && sudo ip link set up vcan0` \
         and --iface vcan0"
    )
}

pub fn not_can_message(iface: &str) -> String {
    format!("{iface} is not a CAN interface (see `ip -br link show type can`)")
}

pub fn is_up(iface: &str) -> bool {
    sys_net(iface, "flags")
        .and_then(|flags| u32::from_str_radix(flags.trim_start_matches("0x"), 16).ok())
        .is_some_and(|flags| flags & libc::IFF_UP as u32 != 0)
}

/// How to bring `iface` up: with the robot's bitrate on hardware; a virtual interface has none to set.
pub fn down_message(iface: &str) -> String {
    match presence(iface) {
        Presence::Can { driver: None } => {
            format!("virtual CAN interface {iface} is down: bring it up with `sudo ip link set up {iface}`")
        }
        _ => format!(
            "CAN interface {iface} is down: bring it up with `sudo ip link set {iface} up type can bitrate 500000`"
        ),
    }
}

/// Bitrate, error state and counters over rtnetlink (no privileges needed).
pub fn bus_details(iface: &str) -> Result<BusDetails, String> {
    let interface = CanInterface::open(iface).map_err(|error| format!("cannot query {iface}: {error}"))?;
    let params = interface.can_params().map_err(|error| format!("cannot query {iface}: {error}"))?;
    Ok(BusDetails {
        bitrate: params.bit_timing.as_ref().map(|timing| timing.bitrate).filter(|&rate| rate > 0),
        sample_point: params
            .bit_timing
            .as_ref()
            .map(|timing| f64::from(timing.sample_point) / 1000.0)
            .filter(|&point| point > 0.0),
        state: params.state.map(|state| match state {
            CanState::ErrorActive => BusState::ErrorActive,
            CanState::ErrorWarning => BusState::ErrorWarning,
            CanState::ErrorPassive => BusState::ErrorPassive,
            CanState::BusOff => BusState::BusOff,
            CanState::Stopped => BusState::Stopped,
            CanState::Sleeping => BusState::Sleeping,
        }),
        error_counters: params.berr_counter.map(|counter| (counter.txerr, counter.rxerr)),
        restart_ms: params.restart_ms,
    })
}

pub fn counters(iface: &str) -> Counters {
    let read = |name: &str| {
        sys_net(iface, &format!("statistics/{name}")).and_then(|text| text.parse().ok()).unwrap_or(0)
    };
    Counters {
        rx_errors: read("rx_errors"),
        tx_errors: read("tx_errors"),
        rx_dropped: read("rx_dropped"),
        tx_dropped: read("tx_dropped"),
        rx_over_errors: read("rx_over_errors"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_interface_is_missing_and_its_message_says_what_to_do() {
        assert_eq!(presence("tracerctl-none0"), Presence::Missing);
        assert!(!is_up("tracerctl-none0"));
        let message = missing_message("tracerctl-none0");
        assert!(message.contains("ip -br link show type can"), "{message}");
        assert!(message.contains("vcan0"), "{message}");
    }

    #[test]
    fn loopback_exists_but_is_not_can() {
        assert_eq!(presence("lo"), Presence::NotCan);
        assert!(is_up("lo"));
        assert!(!can_interfaces().contains(&"lo".to_string()));
    }
}
