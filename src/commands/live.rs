//! What the live commands share: opening the session, describing the robot's state in words, and the
//! checks that decide whether the robot can be driven.

use std::time::Duration;

use anyhow::Result;

use super::Global;
use crate::link::LinkChoice;
use crate::protocol::detect::Verdict;
use crate::protocol::message::{control_mode_name, vehicle_state_name, SystemState, MODE_RC};
use crate::protocol::{Severity, Wire};
use crate::session::{RobotStatus, Session};

/// How long to wait for the first status frame (the robot sends one every 20 ms).
pub const STATUS_WAIT: Duration = Duration::from_secs(1);

/// Opens the link the global options choose. `--replay` is refused for commands that send.
pub fn open(global: &Global, sends: bool) -> Result<Session> {
    let choice = &global.link;
    if sends && matches!(choice, LinkChoice::Replay { .. }) {
        return Err(crate::exit::Failure {
            code: crate::exit::USAGE,
            message: "--replay is read-only: this command sends frames and needs a live link (--iface, --serial or --sim)"
                .to_string(),
        }
        .into());
    }
    let session = Session::open(choice, global.protocol, None)?;
    Ok(session)
}

/// Waits for the robot's protocol (auto mode) and for a status frame; describes what was seen.
pub fn first_status(session: &Session) -> Option<(SystemState, Wire)> {
    first_status_unless(session, || false)
}

/// As [`first_status`], giving up at once (`None`) when `cancelled` says so (a signal arrived).
pub fn first_status_unless(session: &Session, cancelled: impl Fn() -> bool) -> Option<(SystemState, Wire)> {
    const SLICE: Duration = Duration::from_millis(20);
    let until = |wait: Duration, found: &dyn Fn(&RobotStatus) -> bool| {
        let deadline = std::time::Instant::now() + wait;
        while std::time::Instant::now() < deadline && !cancelled() {
            if session.wait_for(SLICE, |status| found(status).then_some(())).is_some() {
                return;
            }
        }
    };
    if session.wire() != Wire::Serial {
        until(STATUS_WAIT / 2, &|status| status.detector.verdict() != Verdict::Unknown);
        session.settle_protocol(Duration::ZERO);
    }
    until(STATUS_WAIT, &|status| status.fresh_system(STATUS_WAIT).is_some());
    if cancelled() {
        return None;
    }
    session.status().fresh_system(STATUS_WAIT)
}

/// `normal, mode can, 25.9 V, faults: none`
pub fn describe(state: &SystemState, wire: Wire) -> String {
    let vehicle = vehicle_state_name(state.vehicle_state).unwrap_or("unknown state");
    let mode = mode_name(state.control_mode, wire);
    format!("{vehicle}, mode {mode}, {:.1} V, faults: {}", state.battery_voltage(), fault_list(state, wire))
}

pub fn mode_name(mode: u8, wire: Wire) -> String {
    control_mode_name(wire, mode).map_or_else(|| format!("0x{mode:02X}"), str::to_string)
}

/// `none`, or `name [severity], ...`
pub fn fault_list(state: &SystemState, wire: Wire) -> String {
    let faults = state.faults(wire);
    if faults.is_empty() {
        return "none".to_string();
    }
    faults.iter().map(|f| format!("{} [{}]", f.name, f.severity)).collect::<Vec<_>>().join(", ")
}

/// Why the robot cannot be driven now, if it cannot: E-stop, exception, a fault or latched protection.
pub fn not_drivable(state: &SystemState, wire: Wire) -> Option<String> {
    if state.is_estop() {
        return Some("the E-stop is pressed: release both E-stop buttons".to_string());
    }
    let blocking: Vec<String> = state
        .faults(wire)
        .iter()
        .filter(|f| matches!(f.severity, Severity::Fault | Severity::Protection))
        .map(|f| format!("{} [{}]: {}", f.name, f.severity, f.action))
        .collect();
    if !blocking.is_empty() {
        return Some(format!("fault set: {}", blocking.join("; ")));
    }
    if wire == Wire::CanV2 && state.control_mode == MODE_RC {
        return Some("the RC transmitter has control: put switch SWB at the top (command mode)".to_string());
    }
    None
}

/// Likely reasons the robot did not switch to or stay in command mode.
pub fn why_not_command_mode(state: &SystemState, wire: Wire) -> String {
    if state.is_estop() {
        return "the E-stop is pressed: release both E-stop buttons, then try again".to_string();
    }
    let rc = match wire {
        Wire::CanV2 => state.control_mode == MODE_RC,
        _ => state.control_mode == 0,
    };
    if rc {
        return "the RC transmitter overrides commands: put switch SWB at the top, or switch the transmitter off"
            .to_string();
    }
    if state.faults(wire).worst().is_some_and(|s| s >= Severity::Fault) {
        return format!(
            "a fault is set ({}): clear it with `tracerctl clear-errors`",
            fault_list(state, wire)
        );
    }
    "no reason visible in the status: check the firmware version and that nothing else sends 0x421"
        .to_string()
}

/// Explains a silent robot.
pub fn no_status_message(session: &Session, status: &RobotStatus) -> String {
    if let Some(error) = &status.link_error {
        return format!("the link {} failed: {error}", session.name);
    }
    if status.frames == 0 {
        return format!(
            "nothing received on {} within {} s: {}",
            session.name,
            STATUS_WAIT.as_secs_f64(),
            crate::link::silence_advice(session.wire())
        );
    }
    let seen = match status.detector.verdict() {
        Verdict::V1 => "protocol V1 traffic",
        Verdict::V2 => "protocol V2 traffic",
        Verdict::Mixed => "mixed V1 and V2 traffic",
        Verdict::Unknown => "traffic from other devices",
    };
    format!(
        "{} frames received on {} ({seen}) but no system status (0x211): is this a TRACER, and is --protocol right?",
        status.frames, session.name
    )
}
