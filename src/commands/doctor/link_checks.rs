//! Checks of the link before any frame is read: SocketCAN support, the interface, its bitrate and error
//! state (Linux), or the serial port.

use std::path::Path;

use super::report::Check;

/// The robot's CAN bitrate.
#[cfg(target_os = "linux")]
const ROBOT_BITRATE: u32 = 500_000;
/// The robot's RS232 baud rate.
const ROBOT_BAUD: u32 = 115_200;

/// Interface checks, in order; `false` when the link cannot be opened (later checks are then skipped).
#[cfg(target_os = "linux")]
pub fn can_interface(iface: &str) -> (Vec<Check>, bool) {
    use crate::link::can_interface::{self as kernel, Presence};

    let mut checks = Vec::new();
    if let Err(message) = kernel::kernel_support() {
        checks.push(Check::fail("kernel_can", "kernel CAN", "no SocketCAN in this kernel", message));
        return (checks, false);
    }
    checks.push(Check::pass("kernel_can", "kernel CAN", "SocketCAN available (can, can-raw)"));

    let driver = match kernel::presence(iface) {
        Presence::Missing => {
            checks.push(Check::fail(
                "interface",
                "interface",
                format!("{iface} does not exist"),
                kernel::missing_message(iface),
            ));
            return (checks, false);
        }
        Presence::NotCan => {
            checks.push(Check::fail(
                "interface",
                "interface",
                format!("{iface} exists but is not a CAN interface"),
                kernel::not_can_message(iface),
            ));
            return (checks, false);
        }
        Presence::Can { driver } => driver,
    };
    let kind = match &driver {
        Some(driver) => format!("CAN, driver {driver}"),
        None => "virtual CAN (no hardware)".to_string(),
    };
    checks.push(Check::pass("interface", "interface", format!("{iface}: {kind}")));

    if !kernel::is_up(iface) {
        checks.push(Check::fail(
            "interface_up",
            "interface up",
            format!("{iface} is down"),
            kernel::down_message(iface),
        ));
        return (checks, false);
    }
    checks.push(Check::pass("interface_up", "interface up", format!("{iface} is up")));

    let details = match kernel::bus_details(iface) {
        Ok(details) => details,
        Err(message) => {
            checks.push(Check::warn(
                "bitrate",
                "bitrate",
                format!("cannot read the bit timing: {message}"),
                format!("check by hand with `ip -details link show {iface}`"),
            ));
            return (checks, true);
        }
    };
    checks.push(bitrate(iface, driver.is_some(), details.bitrate, details.sample_point));
    checks.push(bus_state(iface, &details, kernel::counters(iface)));
    (checks, true)
}

#[cfg(target_os = "linux")]
fn bitrate(iface: &str, hardware: bool, bitrate: Option<u32>, sample_point: Option<f64>) -> Check {
    let set = format!(
        "sudo ip link set {iface} down && sudo ip link set {iface} up type can bitrate {ROBOT_BITRATE}"
    );
    match bitrate {
        Some(ROBOT_BITRATE) => {
            let point =
                sample_point.map(|p| format!(", sample point {:.1} %", p * 100.0)).unwrap_or_default();
            Check::pass("bitrate", "bitrate", format!("{ROBOT_BITRATE} bit/s{point}"))
        }
        Some(other) => Check::fail(
            "bitrate",
            "bitrate",
            format!("{other} bit/s, but the robot uses {ROBOT_BITRATE}"),
            format!("set it: `{set}`"),
        ),
        None if !hardware => {
            Check::pass("bitrate", "bitrate", "none (a virtual interface has no bit timing)")
        }
        None => Check::warn(
            "bitrate",
            "bitrate",
            "the driver reports no bit timing",
            format!("check with `ip -details link show {iface}`; set it with `{set}`"),
        ),
    }
}

#[cfg(target_os = "linux")]
fn bus_state(
    iface: &str,
    details: &crate::link::can_interface::BusDetails,
    counters: crate::link::can_interface::Counters,
) -> Check {
    use crate::link::can_interface::BusState;

    const ID: &str = "bus_state";
    const TITLE: &str = "bus error state";
    let counted = details
        .error_counters
        .map(|(tx, rx)| format!(", error counters tx {tx} rx {rx}"))
        .unwrap_or_default();
    let totals = format!(
        "; since up: {} rx errors, {} tx errors, {} rx dropped, {} rx overruns",
        counters.rx_errors, counters.tx_errors, counters.rx_dropped, counters.rx_over_errors
    );
    let Some(state) = details.state else {
        return Check::pass(ID, TITLE, format!("not reported (virtual interface){totals}"));
    };
    let finding = format!("{}{counted}{totals}", state.as_str());
    let no_ack = "our frames are not acknowledged or the bus is disturbed: is the robot on, the bus wired \
                  (CAN_H, CAN_L, GND) and terminated, and the bitrate 500000 on every node?";
    match state {
        BusState::ErrorActive => Check::pass(ID, TITLE, finding),
        BusState::ErrorWarning | BusState::ErrorPassive => Check::warn(ID, TITLE, finding, no_ack),
        BusState::BusOff => {
            let restart = match details.restart_ms {
                Some(0) | None => format!(
                    "; the controller stays off until restarted: `sudo ip link set {iface} type can restart`, \
                     or bring it up with `restart-ms 100` to recover by itself"
                ),
                Some(ms) => format!("; it restarts by itself after {ms} ms"),
            };
            Check::fail(ID, TITLE, finding, format!("{no_ack}{restart}"))
        }
        BusState::Stopped | BusState::Sleeping => Check::fail(
            ID,
            TITLE,
            finding,
            format!("bring it up: `sudo ip link set {iface} up type can bitrate {ROBOT_BITRATE}`"),
        ),
    }
}

/// The port exists and the baud rate is the robot's; opening it is the next step.
pub fn serial_port(path: &Path, baud: u32) -> Vec<Check> {
    let mut checks = Vec::new();
    // A COM port is no file on Windows (COM3 "does not exist" as a path): opening it, next, tells.
    if cfg!(unix) && !path.exists() {
        checks.push(Check::fail(
            "serial_port",
            "serial port",
            format!("{} does not exist", path.display()),
            "plug in the adapter; list ports with `ls /dev/ttyUSB* /dev/ttyACM* /dev/serial/by-id/`",
        ));
        return checks;
    }
    if baud != ROBOT_BAUD {
        checks.push(Check::warn(
            "baud",
            "baud rate",
            format!("{baud} baud, but the robot uses {ROBOT_BAUD}"),
            format!("drop --baud, or give --baud {ROBOT_BAUD}"),
        ));
    }
    checks
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;
    use crate::commands::doctor::report::Outcome;
    use crate::link::can_interface::{BusDetails, BusState, Counters};

    #[test]
    fn bitrate_500k_passes_another_fails_with_the_command_and_virtual_has_none() {
        let check = bitrate("can0", true, Some(500_000), Some(0.875));
        assert_eq!(
            (check.outcome, check.finding.as_str()),
            (Outcome::Pass, "500000 bit/s, sample point 87.5 %")
        );
        let check = bitrate("can0", true, Some(250_000), None);
        assert_eq!(check.outcome, Outcome::Fail);
        assert_eq!(check.finding, "250000 bit/s, but the robot uses 500000");
        assert_eq!(
            check.action.unwrap(),
            "set it: `sudo ip link set can0 down && sudo ip link set can0 up type can bitrate 500000`"
        );
        assert_eq!(bitrate("vcan0", false, None, None).outcome, Outcome::Pass);
        assert_eq!(bitrate("can0", true, None, None).outcome, Outcome::Warn);
    }

    fn details(state: BusState, counters: (u16, u16), restart_ms: u32) -> BusDetails {
        BusDetails {
            bitrate: Some(500_000),
            sample_point: None,
            state: Some(state),
            error_counters: Some(counters),
            restart_ms: Some(restart_ms),
        }
    }

    #[test]
    fn error_states_with_counters() {
        let counters = Counters { rx_errors: 3, tx_errors: 140, ..Counters::default() };
        let check = bus_state("can0", &details(BusState::ErrorActive, (0, 0), 0), Counters::default());
        assert_eq!(check.outcome, Outcome::Pass);
        assert_eq!(
            check.finding,
            "error-active, error counters tx 0 rx 0; since up: 0 rx errors, 0 tx errors, 0 rx dropped, 0 rx overruns"
        );
        let check = bus_state("can0", &details(BusState::ErrorPassive, (136, 0), 0), counters);
        assert_eq!(check.outcome, Outcome::Warn);
        assert!(check
            .finding
            .starts_with("error-passive, error counters tx 136 rx 0; since up: 3 rx errors, 140 tx"));
        assert!(check.action.unwrap().contains("not acknowledged"));
        let check = bus_state("can0", &details(BusState::BusOff, (256, 0), 0), counters);
        assert_eq!(check.outcome, Outcome::Fail);
        assert!(check.action.unwrap().contains("`sudo ip link set can0 type can restart`"));
        let check = bus_state("can0", &details(BusState::BusOff, (256, 0), 100), counters);
        assert!(check.action.unwrap().ends_with("it restarts by itself after 100 ms"));
        let check = bus_state("can0", &details(BusState::Stopped, (0, 0), 0), counters);
        assert_eq!(check.outcome, Outcome::Fail);
        let check = bus_state("vcan0", &BusDetails::default(), Counters::default());
        assert_eq!(check.outcome, Outcome::Pass);
        assert!(check.finding.starts_with("not reported (virtual interface)"));
    }

    #[test]
    fn a_serial_port_that_does_not_exist_fails_and_a_wrong_baud_warns() {
        let checks = serial_port(Path::new("/dev/tracerctl-none"), 115_200);
        assert_eq!(checks.len(), 1);
        assert_eq!(checks[0].outcome, Outcome::Fail);
        let checks = serial_port(Path::new("/dev/null"), 9600);
        assert_eq!(checks.len(), 1);
        assert_eq!((checks[0].id, checks[0].outcome), ("baud", Outcome::Warn));
        assert!(serial_port(Path::new("/dev/null"), 115_200).is_empty());
    }
}

// Run under wine by tests/wine/run.sh (check e).
#[cfg(all(test, windows))]
mod windows_tests {
    use super::*;

    #[test]
    fn a_com_port_is_not_taken_for_a_missing_file() {
        assert!(
            serial_port(Path::new("COM3"), ROBOT_BAUD).is_empty(),
            "opening COM3 tells, not a path check"
        );
        assert_eq!(serial_port(Path::new("COM3"), 9600).len(), 1, "only the baud warning");
    }
}
