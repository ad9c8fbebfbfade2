//! Checks of the link before any frame is read: SocketCAN support, the interface, its bitrate and error
//! state (Linux), or the serial port.

use std::path::Path;

use super::report::Check;

/// The robot's CAN bitrate.
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
    if !path.exists() {
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
