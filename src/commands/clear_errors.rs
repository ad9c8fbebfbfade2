//! `tracerctl clear-errors [all|motor1|motor2]`: send a fault clear, then report which bits cleared and
//! which remain, each remaining one with its severity, the action to take and the likely reason.
//!
//! What is watched: the fault bits of the system state (0x211; RS232/V1 layout on those links), the
//! vehicle state (E-stop, system exception), and on V2 CAN the driver-state bits of 0x261/0x262 (latched
//! driver protections show there). Info bits (a driver disabled in standby) are states, not faults, and
//! are left out. V2 sends one 0x441 (DLC 1); RS232 and V1 send zero-speed motion commands carrying the
//! clear codes of the latching faults (3/4 motor communication, 7 over-temperature, 8 over-current).

use std::io::Write;
use std::time::Duration;

use anyhow::Result;

use super::live;
use super::Global;
use crate::exit::{Failure, SUCCESS};
use crate::link::LinkFrame;
use crate::output::plural;
use crate::protocol::codec::clear_description;
use crate::protocol::message::{VEHICLE_ESTOP, VEHICLE_NORMAL};
use crate::protocol::{ClearTarget, Codec};
use crate::protocol::{Severity, Wire};
use crate::session::confirm::send_until;
use crate::session::{RobotStatus, Session};

/// Motor low-speed feedback (0x261/0x262) comes every 100 ms: wait this long for the first of both.
const MOTOR_STATE_WAIT: Duration = Duration::from_millis(250);
/// The clear is sent once more halfway through `--timeout` if something is still set.
const RESENDS: u32 = 1;

/// One thing that is wrong: a fault bit, a driver-state bit, or the vehicle state.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Item {
    /// How it is printed: `battery_undervoltage_fault`, `motor1 can_disconnected`, `estop`.
    pub label: String,
    /// The bit's stable name (`can_disconnected`), or `estop` / `vehicle_exception`.
    pub name: &'static str,
    /// The motor it belongs to, if any.
    pub motor: Option<u8>,
    pub severity: Severity,
    pub action: &'static str,
}

/// `tracerctl clear-errors`' settings.
#[derive(Clone, Debug)]
pub struct Options {
    pub target: ClearTarget,
    /// How long to watch the status afterwards.
    pub timeout: Duration,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let session = live::open(global, true)?;
    execute(&session, args, &mut std::io::stdout().lock())
}

/// Clears faults on an open session; the report goes to `out`, a failure (something remains) is the
/// error.
pub fn execute(session: &Session, args: &Options, out: &mut impl Write) -> Result<u8> {
    let before_state = live::first_status(session);
    if session.wire() == Wire::CanV2 {
        session
            .wait_for(MOTOR_STATE_WAIT, |status| status.motor_low.iter().all(Option::is_some).then_some(()));
    }
    let before = before_state.map(|_| items(&session.status()));
    let target = args.target;

    let attempt = send_until(
        session,
        args.timeout,
        RESENDS,
        || frames(&mut session.codec(), target),
        |status, sent| {
            let fresh = status.system.is_some_and(|(at, ..)| at > sent);
            (fresh && items(status).is_empty()).then_some(())
        },
    )?;
    let sent = what_is_sent(session.wire(), target, attempt.sends);
    let status = session.status();
    let Some((after_state, wire)) =
        status.system.filter(|(at, ..)| *at > attempt.first_sent).map(|(_, state, wire)| (state, wire))
    else {
        let what =
            if before.is_some() { "no system status arrived afterwards" } else { "cannot tell what cleared" };
        return Err(Failure::not_done(format!(
            "sent {sent} but {what}: {}",
            live::no_status_message(session, &status)
        ))
        .into());
    };
    let after = items(&status);

    match &before {
        Some(before) if before.is_empty() && after.is_empty() => writeln!(out, "no faults were set")?,
        None if after.is_empty() => {
            writeln!(out, "no faults are set (the status before the clear was not seen)")?
        }
        _ => {}
    }
    let before = before.unwrap_or_default();
    for item in before.iter().filter(|item| !after.contains(item)) {
        writeln!(out, "cleared: {} [{}]", item.label, item.severity)?;
    }
    for item in &after {
        writeln!(out, "remaining: {} [{}] — {}", item.label, item.severity, item.action)?;
    }
    writeln!(out, "status: {}", live::describe(&after_state, wire))?;

    if after.is_empty() {
        return Ok(SUCCESS);
    }
    // Warnings follow their cause (a battery getting low, a warm driver) and latch nothing: no clear can
    // reset them, and they do not stop the robot. Only those left on a drivable robot is success.
    let only_warnings = after.iter().all(|item| item.severity == Severity::Warning);
    if only_warnings && after_state.why_not_drivable(wire).is_none() {
        let what = match after.len() {
            1 => "the warning remains and clears itself".to_string(),
            count => format!("{count} warnings remain and clear themselves"),
        };
        writeln!(
            out,
            "the robot can be driven: {what} once the cause goes (a fault clear cannot reset a warning)"
        )?;
        return Ok(SUCCESS);
    }
    let reasons: Vec<String> = after
        .iter()
        .map(|item| format!("{}: {}", item.label, likely_reason(item, target, &status)))
        .collect();
    Err(Failure::not_done(format!(
        "{} still set after sending {sent}: {}",
        count_items(after.len()),
        reasons.join("; ")
    ))
    .into())
}

/// The frames that clear `target` on the codec's wire.
pub fn frames(codec: &mut Codec, target: ClearTarget) -> Vec<LinkFrame> {
    codec.clear_faults(target)
}

/// Everything wrong in a status, in a fixed order: vehicle state, system fault bits, motor 1, motor 2.
pub fn items(status: &RobotStatus) -> Vec<Item> {
    let mut items = Vec::new();
    let Some((_, state, wire)) = status.system else { return items };
    match state.vehicle_state {
        VEHICLE_NORMAL => {}
        VEHICLE_ESTOP => items.push(Item {
            label: "estop".into(),
            name: "estop",
            motor: None,
            severity: Severity::Fault,
            action: "release both E-stop buttons (a fault clear cannot release them)",
        }),
        _ => items.push(Item {
            label: "vehicle_exception".into(),
            name: "vehicle_exception",
            motor: None,
            severity: Severity::Fault,
            action: "the robot reports a system exception: see the bits listed with it; power-cycle the \
                     robot if it stays with none",
        }),
    }
    for flag in state.faults(wire).iter().filter(|flag| flag.severity != Severity::Info) {
        let motor = match flag.name {
            "motor1_comm_fault" => Some(1),
            "motor2_comm_fault" => Some(2),
            _ => None,
        };
        items.push(Item {
            label: flag.name.into(),
            name: flag.name,
            motor,
            severity: flag.severity,
            action: flag.action,
        });
    }
    if wire == Wire::CanV2 {
        for motor in status.motor_low.iter().flatten() {
            for flag in motor.driver_faults().iter().filter(|flag| flag.severity != Severity::Info) {
                items.push(Item {
                    label: format!("motor{} {}", motor.motor, flag.name),
                    name: flag.name,
                    motor: Some(motor.motor),
                    severity: flag.severity,
                    action: flag.action,
                });
            }
        }
    }
    items
}

/// Whether a clear of `target` reaches this item at all.
fn targeted(item: &Item, target: ClearTarget) -> bool {
    match target {
        ClearTarget::All => true,
        ClearTarget::Motor1 => item.motor == Some(1),
        ClearTarget::Motor2 => item.motor == Some(2),
    }
}

/// Why an item is probably still set after the clear, judged from the status after it.
pub fn likely_reason(item: &Item, target: ClearTarget, status: &RobotStatus) -> String {
    let (volts, wire) =
        status.system.map_or((None, Wire::CanV2), |(_, state, wire)| (Some(state.battery_voltage()), wire));
    let battery =
        volts.map_or_else(|| "the battery is low".to_string(), |v| format!("the battery is at {v:.1} V"));
    match item.name {
        "estop" => return "the E-stop is still pressed: release both E-stop buttons".to_string(),
        "vehicle_exception" => {
            return "the robot still reports a system exception (a latched protection, battery cut-off or a \
                    lost RC link): see the other remaining bits, or power-cycle the robot"
                .to_string()
        }
        "rc_disconnected" => {
            return format!("the cause persists: the RC transmitter is still out of reach; {}", item.action)
        }
        "input_voltage_low" => return format!("the cause persists: {battery}; {}", item.action),
        name if name.starts_with("battery_") => {
            return format!("the cause persists: {battery}; {}", item.action)
        }
        name if name.contains("overheat") => {
            if let Some(hot) = hottest_driver(status, item.motor) {
                return format!("the cause persists: {hot}; {}", item.action);
            }
        }
        _ => {}
    }
    if item.severity == Severity::Warning {
        return format!("a warning clears by itself once its condition is gone: {}", item.action);
    }
    if !targeted(item, target) {
        let which = match (item.motor, wire) {
            (Some(motor), _) => format!("`tracerctl clear-errors motor{motor}` or `clear-errors all`"),
            (None, Wire::CanV2) => "`tracerctl clear-errors all`".to_string(),
            (None, _) => "`tracerctl clear-errors all` (only it sends the over-temperature and over-current \
                          clear codes)"
                .to_string(),
        };
        return format!("not targeted by this clear: run {which}");
    }
    format!("still set after the clear, so its cause persists: {}", item.action)
}

/// `motor 1's driver is at 70 °C` (one motor) or `the hottest driver is at 70 °C` (either), from 0x261/0x262
/// on V2 CAN or the motor driver status on RS232 / V1.
fn hottest_driver(status: &RobotStatus, motor: Option<u8>) -> Option<String> {
    let temperature = |index: usize| {
        status.motor_low[index]
            .map(|m| m.driver_temperature)
            .or(status.motor_driver[index].map(|m| i16::from(m.driver_temperature)))
    };
    match motor {
        Some(motor @ 1..=2) => {
            temperature(usize::from(motor - 1)).map(|t| format!("motor {motor}'s driver is at {t} °C"))
        }
        _ => (0..2).filter_map(temperature).max().map(|t| format!("the hottest driver is at {t} °C")),
    }
}

fn what_is_sent(wire: Wire, target: ClearTarget, sends: u32) -> String {
    format!("{} ({sends} time{})", clear_description(wire, target), plural(sends))
}

fn count_items(count: usize) -> String {
    if count == 1 {
        "1 fault".to_string()
    } else {
        format!("{count} faults")
    }
}

#[cfg(test)]
mod tests {
    use std::time::Instant;

    use super::*;
    use crate::protocol::message::{MotorLowSpeed, SystemState};

    fn status(state: SystemState, wire: Wire, driver_states: [u8; 2]) -> RobotStatus {
        let mut status =
            RobotStatus { system: Some((Instant::now(), state, wire)), ..RobotStatus::default() };
        for (index, driver_state) in driver_states.into_iter().enumerate() {
            status.motor_low[index] =
                Some(MotorLowSpeed { motor: index as u8 + 1, driver_state, ..MotorLowSpeed::default() });
        }
        status
    }

    fn healthy() -> SystemState {
        SystemState { vehicle_state: 0, control_mode: 0, battery_decivolts: 260, fault_code: 0, count: 0 }
    }

    #[test]
    fn v2_frames_are_0x441_with_dlc_1() {
        let mut codec = Codec::new(Wire::CanV2);
        let text = |frames: Vec<LinkFrame>| match frames.as_slice() {
            [LinkFrame::Can(frame)] => frame.to_string(),
            other => panic!("expected one CAN frame, got {other:?}"),
        };
        assert_eq!(text(frames(&mut codec, ClearTarget::All)), "441#00");
        assert_eq!(text(frames(&mut codec, ClearTarget::Motor1)), "441#01");
        assert_eq!(text(frames(&mut codec, ClearTarget::Motor2)), "441#02");
    }

    #[test]
    fn rs232_clear_all_carries_the_four_latching_codes() {
        let mut codec = Codec::new(Wire::Serial);
        let codes: Vec<u8> = frames(&mut codec, ClearTarget::All)
            .iter()
            .map(|frame| match frame {
                LinkFrame::Serial(frame) => frame.to_bytes()[6],
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(codes, [3, 4, 7, 8]);
    }

    #[test]
    fn info_bits_are_not_faults_and_motor_bits_are_named_per_motor() {
        // Standby: both drivers disabled (0x40, info) is normal; motor 1 lost its CAN link (0x10).
        let state = SystemState { vehicle_state: 2, ..healthy() };
        let found = items(&status(state, Wire::CanV2, [0x50, 0x40]));
        let labels: Vec<&str> = found.iter().map(|item| item.label.as_str()).collect();
        assert_eq!(labels, ["vehicle_exception", "motor1 can_disconnected"]);
        assert_eq!(found[1].motor, Some(1));
        assert_eq!(found[1].severity, Severity::Fault);
        assert!(items(&status(healthy(), Wire::CanV2, [0x40, 0x40])).is_empty());
    }

    #[test]
    fn serial_layout_bits_and_their_motors() {
        let state = SystemState { fault_code: 0x0048, ..healthy() };
        let found = items(&status(state, Wire::Serial, [0xFF, 0xFF]));
        let labels: Vec<&str> = found.iter().map(|item| item.label.as_str()).collect();
        // Driver-state bytes exist only on V2 CAN: ignored on RS232.
        assert_eq!(labels, ["motor2_comm_fault", "driver_overheat_protection"]);
        assert_eq!(found[0].motor, Some(2));
        assert_eq!(found[1].severity, Severity::Protection);
    }

    #[test]
    fn reasons_name_the_cause() {
        let low = SystemState { battery_decivolts: 219, fault_code: 0x0100, ..healthy() };
        let low_status = status(low, Wire::CanV2, [0, 0]);
        let battery = &items(&low_status)[0];
        assert_eq!(
            likely_reason(battery, ClearTarget::All, &low_status),
            "the cause persists: the battery is at 21.9 V; charge or replace the battery; motion is cut below 21.5 V"
        );

        let comm = status(SystemState { vehicle_state: 2, ..healthy() }, Wire::CanV2, [0x00, 0x10]);
        let found = items(&comm);
        let motor2 = found.iter().find(|item| item.label == "motor2 can_disconnected").unwrap();
        let reason = likely_reason(motor2, ClearTarget::Motor1, &comm);
        assert!(
            reason.starts_with("not targeted by this clear: run `tracerctl clear-errors motor2`"),
            "{reason}"
        );
        let reason = likely_reason(motor2, ClearTarget::All, &comm);
        assert!(
            reason.starts_with("still set after the clear, so its cause persists: check the internal"),
            "{reason}"
        );

        let mut hot = status(SystemState { vehicle_state: 2, ..healthy() }, Wire::CanV2, [0x08, 0x00]);
        hot.motor_low[0] = hot.motor_low[0].map(|m| MotorLowSpeed { driver_temperature: 70, ..m });
        let found = items(&hot);
        assert_eq!(found[1].label, "motor1 driver_overheat");
        let reason = likely_reason(&found[1], ClearTarget::All, &hot);
        assert!(
            reason.starts_with("the cause persists: motor 1's driver is at 70 °C; reduce speed"),
            "{reason}"
        );

        let estop = status(SystemState { vehicle_state: 1, ..healthy() }, Wire::CanV2, [0, 0]);
        let found = items(&estop);
        assert_eq!(found[0].label, "estop");
        assert!(likely_reason(&found[0], ClearTarget::All, &estop).contains("E-stop is still pressed"));
    }
}
