//! What the live commands share: opening the session, describing the robot's state in words, and the
//! checks that decide whether the robot can be driven.

use std::time::Duration;

use anyhow::Result;

use super::Global;
use crate::link::LinkChoice;
use crate::protocol::detect::Verdict;
use crate::protocol::message::{vehicle_state_name, MessageKind, SystemState};
use crate::protocol::{catalog, ControlMode, Wire};
use crate::session::{Journaling, RobotStatus, Session};

/// How long to wait for the first status frame (the robot sends one every 20 ms).
pub const STATUS_WAIT: Duration = Duration::from_secs(1);

/// Opens the link the global options choose. `--replay` is refused for commands that send.
pub fn open(global: &Global, sends: bool) -> Result<Session> {
    if sends {
        return open_journaled(global, Journaling::default());
    }
    Session::open(&global.link, global.protocol, global.sim_config())
}

/// As [`open`] for a command that sends, with a recording (`--record`) and a tap on the frames.
pub fn open_journaled(global: &Global, journal: Journaling<'_>) -> Result<Session> {
    let choice = &global.link;
    if matches!(choice, LinkChoice::Replay { .. }) {
        return Err(crate::exit::Failure {
            code: crate::exit::USAGE,
            message: "--replay is read-only: this command sends frames and needs a live link (--iface, --serial or --sim)"
                .to_string(),
        }
        .into());
    }
    Session::open_journaled(choice, global.protocol, global.sim_config(), journal)
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
    let mode = ControlMode::describe(wire, state.control_mode);
    format!("{vehicle}, mode {mode}, {:.1} V, faults: {}", state.battery_voltage(), fault_list(state, wire))
}

/// `none`, or `name [severity], ...`
pub fn fault_list(state: &SystemState, wire: Wire) -> String {
    let faults = state.faults(wire);
    if faults.is_empty() {
        return "none".to_string();
    }
    faults.iter().map(|f| format!("{} [{}]", f.name, f.severity)).collect::<Vec<_>>().join(", ")
}

/// Likely reasons the robot did not switch to or stay in command mode.
pub fn why_not_command_mode(state: &SystemState, wire: Wire) -> String {
    if state.is_estop() {
        return "the E-stop is pressed: release both E-stop buttons, then try again".to_string();
    }
    if state.rc_has_control(wire) {
        return "the RC transmitter overrides commands: put switch SWB at the top, or switch the transmitter off"
            .to_string();
    }
    if state.faults(wire).worst().is_some_and(|s| s.blocks_driving()) {
        return format!(
            "a fault is set ({}): clear it with `tracerctl clear-errors`",
            fault_list(state, wire)
        );
    }
    // On V1 and RS232 the motion command carries the mode: another sender of it fights the mode too.
    let rival = catalog::identifier_of(MessageKind::ControlModeCommand, wire)
        .map_or_else(|| "motion commands".to_string(), |id| id.to_string());
    format!("no reason visible in the status: check the firmware version and that nothing else sends {rival}")
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
        "{} frames received on {} ({seen}) but no system status ({}): is this a TRACER, and is --protocol right?",
        status.frames,
        session.name,
        catalog::identifier_text(MessageKind::SystemState, session.wire())
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(control_mode: u8, fault_code: u16) -> SystemState {
        SystemState { vehicle_state: 0, control_mode, battery_decivolts: 259, fault_code, count: 0 }
    }

    /// A bit no document defines does not count as a fault (`Severity::blocks_driving`): it used to be
    /// given as the reason the mode did not change ("a fault is set").
    #[test]
    fn an_undocumented_bit_is_not_the_reason_for_the_mode() {
        let reason = why_not_command_mode(&state(0, 0x0080), Wire::CanV2);
        assert!(reason.starts_with("no reason visible in the status"), "{reason}");
        assert_eq!(state(1, 0x0080).why_not_drivable(Wire::CanV2), None);
        let reason = why_not_command_mode(&state(0, 0x0180), Wire::CanV2);
        assert_eq!(
            reason,
            "a fault is set (reserved_byte5_bit7 [unknown], battery_undervoltage_fault [fault]): clear it with \
             `tracerctl clear-errors`"
        );
    }

    #[test]
    fn describe_names_the_mode_per_wire() {
        assert_eq!(describe(&state(0, 0), Wire::CanV2), "normal, mode standby, 25.9 V, faults: none");
        assert_eq!(describe(&state(0, 0), Wire::Serial), "normal, mode rc, 25.9 V, faults: none");
        assert_eq!(describe(&state(7, 0), Wire::CanV2), "normal, mode 0x07, 25.9 V, faults: none");
        let reason = why_not_command_mode(&state(0, 0), Wire::Serial);
        assert!(reason.starts_with("the RC transmitter overrides commands"), "{reason}");
    }
}
