//! `tracerctl mode can|serial|standby`: switch the control mode and report it from the system state.
//!
//! Protocol V2 CAN has a control-mode command (0x421, DLC 1: 0x00 standby, 0x01 CAN, 0x02 serial). RS232
//! and protocol V1 have none: there the motion command carries the mode, so a zero-speed motion command
//! selects serial mode (RS232) or CAN command mode (V1), and nothing can select the others.
//!
//! The mode is confirmed from a system state (0x211) received after the first send; the command is sent
//! again up to twice within `--timeout`, as real firmware may miss one.

use std::io::Write;
use std::time::Duration;

use anyhow::Result;

use super::live;
use super::Global;
use crate::exit::{Failure, SUCCESS, USAGE};
use crate::output::plural;
use crate::protocol::message::{vehicle_state_name, MessageKind, SystemState};
use crate::protocol::{catalog, ControlMode, Wire};
use crate::session::confirm::send_until;
use crate::session::Session;

/// Sends after the first one, if the robot has not switched yet.
const RESENDS: u32 = 2;

/// `tracerctl mode`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    pub mode: ControlMode,
    /// How long to wait for the robot to confirm.
    pub timeout: Duration,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let session = live::open(global, true)?;
    execute(&session, args, &mut std::io::stdout().lock())
}

/// Switches the mode on an open session; the result goes to `out`, a failure is the error.
pub fn execute(session: &Session, args: &Options, out: &mut impl Write) -> Result<u8> {
    // The link kind is known at once; V1 only after listening, so check RS232 before waiting.
    if session.wire() == Wire::Serial {
        mode_code(Wire::Serial, args.mode)?;
    }
    let before = live::first_status(session);
    let wire = session.wire();
    let code = mode_code(wire, args.mode)?;
    let wanted = ControlMode::describe(wire, code);

    if let Some((state, state_wire)) = before.filter(|(state, _)| state.control_mode == code) {
        writeln!(out, "control mode: already {wanted} ({})", condition(&state, state_wire))?;
        return Ok(SUCCESS);
    }

    let attempt = send_until(
        session,
        args.timeout,
        RESENDS,
        || vec![session.codec().select_mode(code).expect("the mode was checked for this wire")],
        |status, sent| {
            status
                .system
                .filter(|(at, state, _)| *at > sent && state.control_mode == code)
                .map(|(_, state, wire)| (state, wire))
        },
    )?;
    let sent = args.mode.request_text(wire).unwrap_or_else(|| wanted.clone());
    if let Some((state, state_wire)) = attempt.found {
        let from = before
            .map_or_else(|| "unknown".to_string(), |(state, w)| ControlMode::describe(w, state.control_mode));
        writeln!(out, "control mode: {from} -> {wanted} ({})", condition(&state, state_wire))?;
        return Ok(SUCCESS);
    }

    let status = session.status();
    let latest =
        status.system.filter(|(at, ..)| *at > attempt.first_sent).map(|(_, state, wire)| (state, wire));
    let timeout = humantime::format_duration(args.timeout);
    let message = match (latest, before) {
        (Some((state, state_wire)), _) => format!(
            "the robot is still in {} mode ({}), not {wanted}, {timeout} after sending {sent} {} time{}: {}",
            ControlMode::describe(state_wire, state.control_mode),
            condition(&state, state_wire),
            attempt.sends,
            plural(attempt.sends),
            live::why_not_command_mode(&state, state_wire),
        ),
        (None, None) => {
            format!("sent {sent} but cannot confirm the mode: {}", live::no_status_message(session, &status))
        }
        (None, Some(_)) => format!(
            "sent {sent} but no system status arrived within {timeout} afterwards: {}",
            live::no_status_message(session, &status)
        ),
    };
    Err(Failure::not_done(message).into())
}

/// The control-mode value the robot reports for `mode` on `wire` (0x211 byte 1, RS232 system status d1),
/// or a usage error when the link cannot select that mode.
pub fn mode_code(wire: Wire, mode: ControlMode) -> Result<u8, Failure> {
    let usage = |message: &str| Failure { code: USAGE, message: message.to_string() };
    mode.request_code(wire).ok_or_else(|| match wire {
        Wire::Serial => usage(
            "RS232 has no control-mode command: over --serial only `mode serial` works (zero-speed serial \
             motion commands select serial mode); use the CAN link for `mode can` or `mode standby`",
        ),
        Wire::CanV1 => usage(&format!(
            "protocol V1 has no control-mode command ({}): only `mode can` works ({} selects CAN mode); \
             standby and serial need V2 firmware",
            catalog::identifier_text(MessageKind::ControlModeCommand, Wire::CanV2),
            ControlMode::Can.request_text(Wire::CanV1).unwrap_or_default()
        )),
        Wire::CanV2 => usage("RC mode cannot be requested: the transmitter takes control with switch SWB"),
    })
}

/// `normal, 25.9 V, faults: none`
pub(crate) fn condition(state: &SystemState, wire: Wire) -> String {
    let vehicle = vehicle_state_name(state.vehicle_state)
        .map_or_else(|| format!("vehicle state 0x{:02X}", state.vehicle_state), str::to_string);
    format!("{vehicle}, {:.1} V, faults: {}", state.battery_voltage(), live::fault_list(state, wire))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impossible_modes_are_usage_errors_that_say_what_works() {
        let error = mode_code(Wire::Serial, ControlMode::Standby).unwrap_err();
        assert_eq!(error.code, USAGE);
        assert!(error.message.contains("only `mode serial` works"), "{}", error.message);
        let error = mode_code(Wire::CanV1, ControlMode::Serial).unwrap_err();
        assert_eq!(error.code, USAGE);
        assert!(error.message.contains("only `mode can` works"), "{}", error.message);
        assert_eq!(mode_code(Wire::CanV2, ControlMode::Standby).unwrap(), 0);
    }

    #[test]
    fn condition_names_state_voltage_and_faults() {
        let state = SystemState {
            vehicle_state: 0,
            control_mode: 1,
            battery_decivolts: 259,
            fault_code: 0,
            count: 0,
        };
        assert_eq!(condition(&state, Wire::CanV2), "normal, 25.9 V, faults: none");
        let state = SystemState { vehicle_state: 1, fault_code: 0x0200, ..state };
        assert_eq!(
            condition(&state, Wire::CanV2),
            "estop, 25.9 V, faults: battery_undervoltage_warning [warning]"
        );
    }
}
