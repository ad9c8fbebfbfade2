//! `doctor --probe`: does the robot take commands? Sends the command-mode command (0x421 = 0x01 on V2; a
//! zero-speed motion command on RS232 and V1, which carries the mode), then zero-velocity motion commands
//! at 50 Hz for half a second, and watches the status. Never commands motion. A standby or serial mode
//! that the probe changed is put back.

use std::time::{Duration, Instant};

use anyhow::Result;

use super::report::Check;
use crate::commands::live;
#[cfg(target_os = "linux")]
use crate::link::LinkKind;
use crate::protocol::message::{MessageKind, MotionCommand};
use crate::protocol::{catalog, ControlMode, Wire};
use crate::session::confirm::{send_until, Attempt};
use crate::session::Session;
use crate::signals::{Caught, SignalFlag};

/// How long to wait for the mode to switch (the command is sent up to three times).
const MODE_TIMEOUT: Duration = Duration::from_millis(600);
const MODE_RESENDS: u32 = 2;
/// Zero-velocity commands: 25 frames, one every 20 ms.
const MOTION_FRAMES: u32 = 25;
const MOTION_PERIOD: Duration = Duration::from_millis(20);
/// Speeds below these count as standing still.
const STILL_LINEAR: f64 = 0.01;
const STILL_ANGULAR: f64 = 0.01;

/// Runs the probe's checks, handing each to `found` as it completes (the report prints it at once). True
/// when a signal cut the zero-motion probe short: what it would have found is unknown.
pub fn run(
    session: &Session,
    signals: &SignalFlag,
    found: &mut dyn FnMut(Check) -> Result<()>,
) -> Result<bool> {
    let wire = session.wire();
    let choice = ControlMode::command_mode_of(wire);
    let wanted = choice.code(wire);
    let before = session.status().system.and_then(|(_, state, wire)| state.mode(wire));
    let mode = probe_mode(session, wanted)?;
    let mode_ok = mode.outcome == super::report::Outcome::Pass;
    found(mode)?;
    let motion = probe_motion(session, wanted, mode_ok, signals)?;
    // The motion probe skips only when a signal cut it short.
    let cut_short = motion.outcome == super::report::Outcome::Skip;
    found(motion)?;
    // 0x421 can put back standby or serial mode on V2; RC mode comes back by itself (it is a switch).
    if let (Wire::CanV2, Some(mode @ (ControlMode::Standby | ControlMode::Serial))) = (wire, before) {
        if mode_ok {
            found(restore(session, mode)?)?;
        }
    }
    Ok(cut_short)
}

fn probe_mode(session: &Session, wanted: u8) -> Result<Check> {
    const ID: &str = "probe_mode";
    const TITLE: &str = "probe: mode";
    let wire = session.wire();
    let sent = ControlMode::from_code(wire, wanted)
        .and_then(|mode| mode.request_text(wire))
        .unwrap_or_else(|| format!("control mode 0x{wanted:02X}"));
    let before =
        session.status().system.map(|(_, state, wire)| ControlMode::describe(wire, state.control_mode));
    let attempt = switch_mode(session, wanted);
    let attempt = match attempt {
        Ok(attempt) => attempt,
        Err(error) => return Ok(Check::fail(ID, TITLE, format!("cannot send {sent}"), format!("{error:#}"))),
    };
    let wanted_name = ControlMode::describe(wire, wanted);
    if let Some(after) = attempt.found {
        let from = before.unwrap_or_else(|| "unknown".to_string());
        return Ok(Check::pass(
            ID,
            TITLE,
            format!("{sent} accepted: {from} -> {wanted_name} in {:.1} ms", after.as_secs_f64() * 1000.0),
        ));
    }
    let status = session.status();
    let latest = status.system.filter(|(at, ..)| *at > attempt.first_sent);
    Ok(match latest {
        Some((_, state, state_wire)) => Check::fail(
            ID,
            TITLE,
            format!(
                "sent {sent} {} times; the robot stayed in {} mode",
                attempt.sends,
                ControlMode::describe(state_wire, state.control_mode)
            ),
            live::why_not_command_mode(&state, state_wire),
        ),
        None => Check::fail(
            ID,
            TITLE,
            format!("sent {sent}; no system status came back"),
            live::no_status_message(session, &status),
        ),
    })
}

fn probe_motion(session: &Session, wanted: u8, mode_ok: bool, signals: &SignalFlag) -> Result<Check> {
    const ID: &str = "probe_motion";
    const TITLE: &str = "probe: zero motion";
    let bus_before = bus_errors(session);
    let started = Instant::now();
    let (sent, send_error) = send_zero_frames(session, signals, started);
    let what = match session.wire() {
        Wire::Serial => "zero-velocity RS232".to_string(),
        wire => format!("zero-velocity {}", catalog::identifier_text(MessageKind::MotionCommand, wire)),
    };
    let elapsed = started.elapsed().as_secs_f64();
    if let Some(error) = send_error {
        return Ok(Check::fail(
            ID,
            TITLE,
            format!("{sent} {what} frames sent, then the link refused one"),
            error,
        ));
    }
    if let Some(name) = signals.caught().map(Caught::name) {
        // Cut short, the probe found nothing out either way: not a failure of the robot.
        return Ok(Check::skip(
            ID,
            TITLE,
            format!("interrupted by {name} after {sent} frames: the result is unknown"),
        ));
    }
    let mut finding = format!("{sent} {what} frames in {elapsed:.1} s, all sent");
    let problems = status_while_sending(session, started, wanted, mode_ok, bus_before, &mut finding);
    if problems.is_empty() {
        Ok(Check::pass(ID, TITLE, finding))
    } else {
        Ok(Check::fail(
            ID,
            TITLE,
            format!("{finding}; {}", problems.join("; ")),
            "fix what the earlier checks report; if they all pass, check the wiring and termination",
        ))
    }
}

/// Sends `MOTION_FRAMES` zero-velocity frames on an absolute grid, like the drive sender (a slow send does not
/// stretch the period), until a signal arrives or the link refuses one: how many left, and the refusal.
fn send_zero_frames(session: &Session, signals: &SignalFlag, started: Instant) -> (u32, Option<String>) {
    let mut sent = 0;
    for index in 0..MOTION_FRAMES {
        if signals.received().is_some() {
            break;
        }
        let frame = session.codec().motion(MotionCommand::STOP);
        if let Err(error) = session.send(&frame) {
            return (sent, Some(format!("{error:#}")));
        }
        sent += 1;
        let next = started + MOTION_PERIOD * (index + 1);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    (sent, None)
}

/// What the robot reported while the zero frames went out: the mode and speed join `finding`; a left
/// command mode, motion, a missing status or a rising transmit error counter are the problems returned.
fn status_while_sending(
    session: &Session,
    started: Instant,
    wanted: u8,
    mode_ok: bool,
    bus_before: Option<u16>,
    finding: &mut String,
) -> Vec<String> {
    let status = session.status();
    let mut problems = Vec::new();
    match status.system.filter(|(at, ..)| *at > started) {
        None => problems.push("no system status arrived while sending".to_string()),
        Some((_, state, state_wire)) => {
            let mode = ControlMode::describe(state_wire, state.control_mode);
            if mode_ok && state.control_mode != wanted {
                problems.push(format!("the robot left command mode ({mode})"));
            } else {
                finding.push_str(&format!("; mode {mode}"));
            }
        }
    }
    match status.motion.filter(|(at, _)| *at > started) {
        Some((_, motion)) if motion.linear().abs() < STILL_LINEAR && motion.angular().abs() < STILL_ANGULAR => {
            finding.push_str(&format!("; the robot reports {:.2} m/s, {:.2} rad/s", motion.linear(), motion.angular()))
        }
        Some((_, motion)) => problems.push(format!(
            "the robot reports motion ({:.2} m/s, {:.2} rad/s) although zero was commanded: another controller?",
            motion.linear(),
            motion.angular()
        )),
        None => {}
    }
    if let (Some(before), Some(after)) = (bus_before, bus_errors(session)) {
        if after > before {
            problems.push(format!(
                "the transmit error counter rose from {before} to {after}: our frames are not acknowledged"
            ));
        }
    }
    problems
}

/// Puts back the mode the robot was in.
fn restore(session: &Session, mode: ControlMode) -> Result<Check> {
    const ID: &str = "probe_restore";
    const TITLE: &str = "probe: restore";
    let name = mode.name();
    Ok(match switch_mode(session, mode.code(Wire::CanV2))?.found {
        Some(_) => Check::pass(ID, TITLE, format!("control mode back to {name}")),
        None => Check::warn(
            ID,
            TITLE,
            format!("could not put the control mode back to {name}"),
            format!("`tracerctl mode {name}` if the robot should stay in {name}"),
        ),
    })
}

/// Sends the command for `mode` (up to three times) until the status reports it; found = how long after
/// the first send the confirming status came.
fn switch_mode(session: &Session, mode: u8) -> Result<Attempt<Duration>> {
    send_until(
        session,
        MODE_TIMEOUT,
        MODE_RESENDS,
        || session.codec().select_mode(mode).into_iter().collect(),
        |status, sent| {
            status
                .system
                .filter(|(at, state, _)| *at > sent && state.control_mode == mode)
                .map(|(at, ..)| at.saturating_duration_since(sent))
        },
    )
}

/// The interface's transmit error counter (SocketCAN hardware only).
fn bus_errors(session: &Session) -> Option<u16> {
    #[cfg(target_os = "linux")]
    if session.kind == LinkKind::SocketCan {
        return crate::link::can_interface::bus_details(&session.name)
            .ok()
            .and_then(|details| details.error_counters)
            .map(|(tx, _)| tx);
    }
    let _ = session;
    None
}
