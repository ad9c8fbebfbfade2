//! Checks of what the robot reported while the doctor listened. Pure functions of one snapshot of the
//! session's status, so every verdict is testable without a robot.

use std::time::{Duration, Instant};

use super::report::{Check, Outcome};
use crate::link::LinkKind;
use crate::protocol::constants::{volts, BATTERY_CUTOFF_DV, BATTERY_FAULT_DV};
use crate::protocol::detect::Verdict;
use crate::protocol::message::{rc_switch_name, SystemState, VEHICLE_ESTOP, VEHICLE_EXCEPTION};
use crate::protocol::{catalog, ControlMode, MessageKind, ProtocolHint, Severity, Wire};
use crate::session::RobotStatus;

/// The robot sends its system status every 20 ms.
const STATUS_PER_SECOND: f64 = 50.0;
/// Motor driver temperatures (manual, V1 fault table): warning above 55 C, protection above 65 C.
const DRIVER_WARM_C: i16 = 55;
const DRIVER_HOT_C: i16 = 65;

/// What the doctor saw.
pub struct Observation<'a> {
    pub status: &'a RobotStatus,
    /// How long the session has been listening.
    pub listened: Duration,
    pub link: &'a str,
    pub kind: LinkKind,
    /// The wire commands are encoded for (serial, or CAN V1/V2 as given or detected).
    pub wire: Wire,
    /// `--protocol` as given.
    pub hint: ProtocolHint,
    pub now: Instant,
    /// The warning voltage, decivolts: the manual's, or the configuration's `battery.warning_volts`.
    pub battery_warning_dv: u16,
}

impl Observation<'_> {
    fn seconds(&self) -> String {
        format!("{:.1} s", self.listened.as_secs_f64())
    }

    fn system(&self) -> Option<(SystemState, Wire)> {
        self.status.system.map(|(_, state, wire)| (state, wire))
    }

    fn is_can(&self) -> bool {
        self.wire != Wire::Serial
    }
}

/// The checks of what the robot sends, in order (the protocol check is CAN's, the frame-stream check
/// RS232's).
const CHECKS: &[(&str, &str)] = &[
    ("frames", "frames arriving"),
    ("protocol", "protocol"),
    ("status", "system status"),
    ("control_mode", "control mode"),
    ("estop", "E-stop"),
    ("faults", "faults"),
    ("battery", "battery"),
    ("motors", "motors"),
];

/// The checks from `first` to `last` (inclusive), skipped for `reason` (no frames, no link, no status).
pub fn skipped(first: &str, last: &str, reason: &str, can: bool) -> Vec<Check> {
    let position = |wanted: &str| CHECKS.iter().position(|(id, _)| *id == wanted);
    let start = position(first).unwrap_or(0);
    let end = position(last).unwrap_or(CHECKS.len() - 1);
    CHECKS[start..=end]
        .iter()
        .filter(|(id, _)| can || *id != "protocol")
        .map(|(id, title)| Check::skip(id, title, reason))
        .collect()
}

/// Every check of the robot's reports, in order. Checks that need frames, or a system status, are
/// skipped with the reason when there is none.
pub fn checks(seen: &Observation) -> Vec<Check> {
    let mut checks = vec![frames(seen)];
    if seen.status.frames == 0 {
        checks.extend(skipped("protocol", "motors", "nothing received", seen.is_can()));
        return checks;
    }
    if seen.is_can() {
        checks.push(protocol(seen));
    } else {
        checks.push(serial_stream(seen));
    }
    checks.push(status_rate(seen));
    if seen.is_can() {
        checks.push(other_senders(seen));
    }
    match seen.system() {
        Some((state, wire)) => {
            checks.push(control_mode(seen, &state, wire));
            checks.push(estop(&state));
            checks.push(faults(seen, &state, wire));
            checks.push(battery(&state, seen.battery_warning_dv));
        }
        None => {
            checks.extend(skipped("control_mode", "battery", "no system status received", true));
        }
    }
    checks.push(motors(seen));
    checks
}

pub fn frames(seen: &Observation) -> Check {
    const ID: &str = "frames";
    const TITLE: &str = "frames arriving";
    let status = seen.status;
    if let Some(error) = &status.link_error {
        if status.frames == 0 || seen.kind != LinkKind::Replay {
            return Check::fail(
                ID,
                TITLE,
                format!("the link {} failed: {error}", seen.link),
                "check the adapter and its cable, then run doctor again",
            );
        }
    }
    if status.frames == 0 {
        return match seen.wire {
            Wire::Serial if status.rx.serial_bytes > 0 => Check::fail(
                ID,
                TITLE,
                format!(
                    "{} bytes in {} but not one valid frame ({} checksum errors)",
                    status.rx.serial_bytes,
                    seen.seconds(),
                    status.rx.serial_bad_checksum
                ),
                "the robot sends 115200 baud 8N1: check --baud, and that this port is the robot's RS232",
            ),
            wire => Check::fail(
                ID,
                TITLE,
                format!("nothing received on {} in {}", seen.link, seen.seconds()),
                crate::link::silence_advice(wire),
            ),
        };
    }
    let rate = status.frames as f64 / seen.listened.as_secs_f64().max(1e-3);
    let finding = format!("{} frames in {} ({rate:.0}/s)", status.frames, seen.seconds());
    let mut trouble = Vec::new();
    if status.rx.error_frames > 0 {
        // By class (and controller status), never as identifiers: an error frame's ID field is its classes.
        trouble.push(format!(
            "{} CAN error frames: {}",
            status.rx.error_frames,
            status.error_tally.describe()
        ));
    }
    if status.rx.socket_drops > 0 {
        trouble.push(format!("{} frames dropped by the kernel (socket queue full)", status.rx.socket_drops));
    }
    if trouble.is_empty() {
        Check::pass(ID, TITLE, finding)
    } else {
        Check::warn(
            ID,
            TITLE,
            format!("{finding}; {}", trouble.join("; ")),
            "error frames mean bus trouble: check wiring, termination and that every node runs at 500 kbit/s; \
             drops mean this machine is too busy to read the bus",
        )
    }
}

/// The identifiers seen, most frequent first: `0x211 x50, 0x221 x50`.
fn id_list(status: &RobotStatus, most: usize) -> String {
    let mut ids = status.id_counts.clone();
    ids.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut list: Vec<String> = ids.iter().take(most).map(|(id, count)| format!("{id} x{count}")).collect();
    if ids.len() > most {
        list.push(format!("and {} more", ids.len() - most));
    }
    list.join(", ")
}

pub fn protocol(seen: &Observation) -> Check {
    const ID: &str = "protocol";
    const TITLE: &str = "protocol";
    let detector = &seen.status.detector;
    let verdict = detector.verdict();
    let forced = match (seen.hint, verdict) {
        (ProtocolHint::V1, Verdict::V2) => Some(("v1", "V2")),
        (ProtocolHint::V2, Verdict::V1) => Some(("v2", "V1")),
        _ => None,
    };
    if let Some((given, spoken)) = forced {
        return Check::fail(
            ID,
            TITLE,
            format!("--protocol {given} was given but the robot speaks {spoken} ({})", detector.describe()),
            format!(
                "drop --protocol (the version is detected) or give --protocol {}",
                spoken.to_ascii_lowercase()
            ),
        );
    }
    match verdict {
        Verdict::V2 => Check::pass(ID, TITLE, format!("V2 ({} V2-only frames)", detector.v2_frames)),
        Verdict::V1 => Check::pass(
            ID,
            TITLE,
            format!(
                "V1 firmware ({} V1-only frames): commands go as {} with checksums; V1 has no {} mode command",
                detector.v1_frames,
                catalog::identifier_text(MessageKind::MotionCommand, Wire::CanV1),
                catalog::identifier_text(MessageKind::ControlModeCommand, Wire::CanV2),
            ),
        ),
        Verdict::Mixed => Check::warn(
            ID,
            TITLE,
            detector.describe(),
            "V1 and V2 identifiers on one bus: two robots, or a second node imitating one; unplug the other node \
             or give --protocol",
        ),
        Verdict::Unknown if seen.status.system.is_some() => {
            Check::pass(ID, TITLE, "not determined (only identifiers both versions use)")
        }
        Verdict::Unknown => Check::fail(
            ID,
            TITLE,
            format!("frames, but none a TRACER sends: {}", id_list(seen.status, 6)),
            format!("this is not the robot's bus, or the robot is off: check which interface is wired to the robot (--iface; {} here)", seen.link),
        ),
    }
}

pub fn serial_stream(seen: &Observation) -> Check {
    const ID: &str = "serial_stream";
    const TITLE: &str = "frame stream";
    let rx = seen.status.rx;
    let finding = format!(
        "{} bytes, {} frames, {} checksum errors, {} sync losses",
        rx.serial_bytes, rx.frames, rx.serial_bad_checksum, rx.serial_sync_losses
    );
    if rx.serial_bad_checksum == 0 && rx.serial_sync_losses == 0 {
        return Check::pass(ID, TITLE, finding);
    }
    Check::warn(
        ID,
        TITLE,
        finding,
        "bytes are being corrupted or lost: use a shorter cable, connect GND, keep it away from the motor \
         wires, and check that nothing else reads this port",
    )
}

pub fn status_rate(seen: &Observation) -> Check {
    const ID: &str = "status";
    const TITLE: &str = "system status";
    let status = seen.status;
    let Some((at, ..)) = status.system else {
        let id = |wire| catalog::identifier_text(MessageKind::SystemState, wire);
        let which = if seen.is_can() {
            format!("{} (or V1 {})", id(Wire::CanV2), id(Wire::CanV1))
        } else {
            format!("RS232 system status ({})", id(Wire::Serial))
        };
        return Check::fail(
            ID,
            TITLE,
            format!("no {which} among {} frames: {}", status.frames, id_list(status, 6)),
            "the robot reports its state every 20 ms; without it this is not a TRACER, or its firmware speaks \
             another protocol: check --protocol and the firmware version",
        );
    };
    let age = seen.now.saturating_duration_since(at);
    let rate = status.system_frames as f64 / seen.listened.as_secs_f64().max(1e-3);
    let finding = format!(
        "{} in {} ({rate:.0}/s), last {} ms ago",
        status.system_frames,
        seen.seconds(),
        age.as_millis()
    );
    if age > Duration::from_millis(250) && seen.kind != LinkKind::Replay {
        return Check::fail(
            ID,
            TITLE,
            finding,
            "the robot stopped reporting: check its power and the link (a loose connector?)",
        );
    }
    // A short listen cannot measure a rate; half the expected rate means frames are being lost.
    if seen.listened >= Duration::from_millis(500)
        && rate < STATUS_PER_SECOND / 2.0
        && seen.kind != LinkKind::Replay
    {
        return Check::warn(
            ID,
            TITLE,
            format!("{finding}, expected {STATUS_PER_SECOND:.0}/s"),
            "frames are being lost: check the bus load and the wiring",
        );
    }
    Check::pass(ID, TITLE, finding)
}

pub fn other_senders(seen: &Observation) -> Check {
    // The catalog's host commands (the version query is not one: it changes nothing).
    let found: Vec<String> = catalog::host_commands()
        .filter_map(|entry| {
            let count = seen.status.id_counts.iter().find(|(id, _)| *id == entry.id)?.1;
            let wire = if entry.wire == Wire::CanV1 { "V1 " } else { "" };
            Some(format!("{} {wire}{} x{count}", entry.id, entry.name().replace('_', " ")))
        })
        .collect();
    if found.is_empty() {
        return Check::pass("other_senders", "other senders", "no other node sends commands");
    }
    Check::warn(
        "other_senders",
        "other senders",
        format!("another node sends commands: {}", found.join(", ")),
        "stop the other controller (a ROS driver, another tracerctl) before driving: two senders fight and \
         the robot may not stop when you expect",
    )
}

pub fn control_mode(seen: &Observation, state: &SystemState, wire: Wire) -> Check {
    const ID: &str = "control_mode";
    const TITLE: &str = "control mode";
    let mode = ControlMode::describe(wire, state.control_mode);
    let swb = seen.status.rc.map(|(_, rc)| (rc.switches >> 2) & 0b11);
    let swb_text = swb.map(|bits| format!(", RC switch SWB {}", rc_switch_name(bits).unwrap_or("unknown")));
    let finding = format!("{mode}{}", swb_text.unwrap_or_default());
    let rc_action =
        "the RC transmitter overrides commands: put switch SWB at the top (command mode), or switch \
                     the transmitter off";
    // SWB in the middle is RC mode whatever the status says (0x241, when the robot sends it).
    if swb == Some(0b01) {
        return Check::fail(ID, TITLE, finding, rc_action);
    }
    match wire {
        Wire::CanV2 => match state.mode(wire) {
            Some(ControlMode::Can) => Check::pass(ID, TITLE, finding),
            Some(ControlMode::Rc) => Check::fail(ID, TITLE, finding, rc_action),
            Some(ControlMode::Standby) => Check::warn(
                ID,
                TITLE,
                format!("{finding} (the power-on mode: motion commands are ignored)"),
                format!(
                    "tracerctl drive and dashboard switch to CAN mode themselves; other software must send {} \
                     first, and again after every power cycle (`tracerctl mode can`)",
                    ControlMode::Can.request_text(wire).unwrap_or_default()
                ),
            ),
            Some(ControlMode::Serial) => Check::warn(
                ID,
                TITLE,
                format!("{finding}: CAN motion commands are ignored"),
                "is another host driving over RS232? `tracerctl mode can` switches to CAN",
            ),
            None => Check::warn(ID, TITLE, finding, "an unknown mode: check the firmware version"),
        },
        Wire::Serial | Wire::CanV1 => {
            if state.mode(wire) == Some(ControlMode::command_mode_of(wire)) {
                Check::pass(ID, TITLE, finding)
            } else if state.rc_has_control(wire) {
                Check::warn(
                    ID,
                    TITLE,
                    format!("{finding}: idle or RC (this protocol cannot tell them apart)"),
                    "a motion command selects command mode unless the RC transmitter has control (SWB must be at \
                     the top); --probe tells which",
                )
            } else {
                Check::warn(
                    ID,
                    TITLE,
                    format!("{finding}: another host may be commanding the robot"),
                    "a motion command from this link takes over; stop the other host first",
                )
            }
        }
    }
}

pub fn estop(state: &SystemState) -> Check {
    const ID: &str = "estop";
    const TITLE: &str = "E-stop";
    match state.vehicle_state {
        VEHICLE_ESTOP => Check::fail(
            ID,
            TITLE,
            "pressed: the robot will not move",
            "release the E-stop buttons (turn them clockwise); the robot reports normal within 20 ms",
        ),
        VEHICLE_EXCEPTION => {
            Check::pass(ID, TITLE, "released (the robot reports a system exception: see faults)")
        }
        _ => Check::pass(ID, TITLE, "released; vehicle state normal"),
    }
}

/// The fault bits of the system status and, on V2, of both motor drivers (0x261/0x262: latched driver
/// protections show there), plus a system exception no bit explains. Info bits (a driver disabled in
/// standby) are states, not faults.
pub fn faults(seen: &Observation, state: &SystemState, wire: Wire) -> Check {
    const ID: &str = "faults";
    const TITLE: &str = "faults";
    let mut named = Vec::new();
    let mut worst = Outcome::Pass;
    let mut actions = Vec::new();
    let system = state.faults(wire).iter().map(|flag| (String::new(), flag)).collect::<Vec<_>>();
    let drivers = seen.status.motor_low.iter().flatten().flat_map(|low| {
        low.driver_faults()
            .iter()
            .map(move |flag| (format!("motor {} ", low.motor), flag))
            .collect::<Vec<_>>()
    });
    for (prefix, flag) in system.into_iter().chain(drivers) {
        if !flag.severity.is_problem() {
            continue;
        }
        named.push(format!("{prefix}{} [{}]", flag.name, flag.severity));
        actions.push(format!("{prefix}{}: {}", flag.name, flag.action));
        worst = worst.max(outcome_of(flag.severity));
    }
    let exception = state.vehicle_state == VEHICLE_EXCEPTION;
    if named.is_empty() {
        if exception {
            return Check::fail(
                ID,
                TITLE,
                "system exception, but no fault bit says why",
                "power-cycle the robot; if it persists, note the firmware version and contact AgileX",
            );
        }
        return Check::pass(ID, TITLE, "no fault bits set");
    }
    let finding = format!("0x{:04X}: {}", state.fault_code, named.join(", "));
    if exception || worst == Outcome::Fail {
        actions.push("then `tracerctl clear-errors` for faults that latch".to_string());
        return Check::fail(ID, TITLE, finding, actions.join("; "));
    }
    Check::warn(ID, TITLE, finding, actions.join("; "))
}

pub fn battery(state: &SystemState, warning_dv: u16) -> Check {
    const ID: &str = "battery";
    const TITLE: &str = "battery";
    let decivolts = state.battery_decivolts;
    let finding = format!("{:.1} V", state.battery_voltage());
    // Strictly below, as the manual words it ("lower than"): a reported value at a threshold still passes.
    if decivolts < BATTERY_FAULT_DV {
        Check::fail(
            ID,
            TITLE,
            format!("{finding}: below the {} V protection voltage", volts(BATTERY_FAULT_DV)),
            format!(
                "charge or replace the battery: the robot cuts motion below {} V",
                volts(BATTERY_CUTOFF_DV)
            ),
        )
    } else if decivolts < warning_dv {
        Check::warn(
            ID,
            TITLE,
            format!("{finding}: below the {} V alarm voltage", volts(warning_dv)),
            "finish the task and charge soon",
        )
    } else {
        Check::pass(ID, TITLE, finding)
    }
}

pub fn motors(seen: &Observation) -> Check {
    const ID: &str = "motors";
    const TITLE: &str = "motors";
    let status = seen.status;
    let mut parts = Vec::new();
    let mut silent = Vec::new();
    let mut worst = Outcome::Pass;
    let mut actions = Vec::new();
    for index in 0..2 {
        let motor = index + 1;
        let (rpm, amps, temperature) = match (status.motor_high[index], status.motor_driver[index]) {
            (Some(high), _) => (high.rpm, f64::from(high.current_deciamps) / 10.0, None),
            (None, Some(driver)) => (
                driver.rpm,
                f64::from(driver.current_deciamps) / 10.0,
                Some(i16::from(driver.driver_temperature)),
            ),
            (None, None) => {
                silent.push(motor);
                continue;
            }
        };
        let low = status.motor_low[index];
        let temperature = low.map(|low| low.driver_temperature).or(temperature);
        let mut part = format!("motor {motor} {rpm} rpm {amps:.1} A");
        if let Some(celsius) = temperature {
            part.push_str(&format!(", driver {celsius} C"));
            if celsius > DRIVER_HOT_C {
                worst = worst.max(Outcome::Fail);
                actions
                    .push(format!("motor {motor}'s driver is above {DRIVER_HOT_C} C: stop and let it cool"));
            } else if celsius > DRIVER_WARM_C {
                worst = worst.max(Outcome::Warn);
                actions.push(format!("motor {motor}'s driver is above {DRIVER_WARM_C} C: reduce speed"));
            }
        }
        parts.push(part);
    }
    let expected =
        catalog::identifiers_text(&[MessageKind::MotorHighSpeed, MessageKind::MotorLowSpeed], seen.wire);
    if !silent.is_empty() {
        let names: Vec<String> = silent.iter().map(|motor| format!("motor {motor}")).collect();
        parts.push(format!("no feedback from {} ({expected})", names.join(" or ")));
        worst = worst.max(Outcome::Warn);
        actions.push("check the motor driver cables and power".into());
    }
    let finding = parts.join("; ");
    match worst {
        Outcome::Fail => Check::fail(ID, TITLE, finding, actions.join("; ")),
        Outcome::Warn => Check::warn(ID, TITLE, finding, actions.join("; ")),
        Outcome::Pass | Outcome::Skip => Check::pass(ID, TITLE, finding),
    }
}

/// Bits that stop the robot fail the check; other problems (warnings, bits no document defines) deserve a
/// look: `Severity`'s own answer.
fn outcome_of(severity: Severity) -> Outcome {
    if severity.blocks_driving() {
        Outcome::Fail
    } else if severity.is_problem() {
        Outcome::Warn
    } else {
        Outcome::Pass
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::constants::BATTERY_WARNING_DV;
    use crate::protocol::message::{MotorLowSpeed, RcState, MODE_CAN, MODE_RC, MODE_SERIAL, MODE_STANDBY};

    fn state(vehicle_state: u8, control_mode: u8, decivolts: u16, fault_code: u16) -> SystemState {
        SystemState { vehicle_state, control_mode, battery_decivolts: decivolts, fault_code, count: 0 }
    }

    fn seen(status: &RobotStatus, wire: Wire) -> Observation<'_> {
        Observation {
            status,
            listened: Duration::from_secs(1),
            link: "can0",
            kind: LinkKind::SocketCan,
            wire,
            hint: ProtocolHint::Auto,
            now: Instant::now(),
            battery_warning_dv: BATTERY_WARNING_DV,
        }
    }

    /// What an SJA1000 sends when its RX FIFO overruns (class controller_problem + error counters, status
    /// rx_overflow), read through a real session with foreign traffic: the report names the error frames by
    /// class and never lists them as identifiers (the bug: "0x204 x153" among foreign IDs).
    #[test]
    fn error_frames_are_reported_by_class_never_as_identifiers() {
        use crate::link::{channel, LinkFrame};
        use crate::protocol::CanFrame;
        use crate::session::Session;
        let (host, robot) = channel::pair(Wire::CanV2, LinkKind::SocketCan, "can0");
        let session = Session::from_link(host, ProtocolHint::Auto).unwrap();
        let foreign = LinkFrame::Can(CanFrame::new(0x7A0, &[1, 2, 3]).unwrap());
        let overrun = LinkFrame::Can(CanFrame::new_error(0x204, &[0, 0x01, 0, 0, 0, 0, 0, 0]).unwrap());
        for _ in 0..5 {
            robot.tx.send(&foreign).unwrap();
        }
        for _ in 0..153 {
            robot.tx.send(&overrun).unwrap();
        }
        let status =
            session.wait_for(Duration::from_secs(2), |s| (s.frames == 158).then(|| s.clone())).unwrap();
        assert_eq!(
            status.id_counts,
            vec![(crate::protocol::FrameId::Standard(0x7A0), 5)],
            "error frames are not identifiers"
        );
        assert_eq!(status.error_tally.frames, 153);
        let mut status = status;
        status.rx.error_frames = 153; // the SocketCAN receiver counts them; the in-process channel does not
        let seen = seen(&status, Wire::CanV2);
        let protocol = protocol(&seen);
        assert!(protocol.finding.contains("0x7A0 x5"), "{}", protocol.finding);
        assert!(!protocol.finding.contains("0x204"), "{}", protocol.finding);
        let frames = frames(&seen);
        assert_eq!(frames.outcome, Outcome::Warn);
        assert!(
            frames.finding.contains(
                "153 CAN error frames: controller_problem x153 (rx_overflow x153), error_counters x153"
            ),
            "{}",
            frames.finding
        );
    }

    #[test]
    fn battery_thresholds_follow_the_manual() {
        let outcome = |decivolts| battery(&state(0, 1, decivolts, 0), BATTERY_WARNING_DV).outcome;
        assert_eq!(outcome(259), Outcome::Pass);
        assert_eq!(outcome(225), Outcome::Pass);
        assert_eq!(outcome(224), Outcome::Warn);
        assert_eq!(outcome(220), Outcome::Warn);
        assert_eq!(outcome(219), Outcome::Fail);
    }

    #[test]
    fn control_modes_on_v2() {
        let status = RobotStatus::default();
        let seen = seen(&status, Wire::CanV2);
        let check = |mode| control_mode(&seen, &state(0, mode, 259, 0), Wire::CanV2);
        assert_eq!(check(MODE_CAN).outcome, Outcome::Pass);
        assert_eq!(check(MODE_STANDBY).outcome, Outcome::Warn);
        assert_eq!(check(MODE_SERIAL).outcome, Outcome::Warn);
        assert_eq!(check(MODE_RC).outcome, Outcome::Fail);
        assert_eq!(check(9).outcome, Outcome::Warn);
    }

    #[test]
    fn swb_in_the_middle_on_0x241_is_rc_override_whatever_the_mode_byte_says() {
        // SWA up (0b10), SWB middle (0b01 << 2).
        let status = RobotStatus {
            rc: Some((Instant::now(), RcState { switches: 0b0110, ..RcState::default() })),
            ..RobotStatus::default()
        };
        let seen = seen(&status, Wire::CanV2);
        let check = control_mode(&seen, &state(0, MODE_CAN, 259, 0), Wire::CanV2);
        assert_eq!(check.outcome, Outcome::Fail);
        assert_eq!(check.finding, "can, RC switch SWB middle");
        assert!(check.action.unwrap().contains("SWB at the top"));
        let mut up = status.clone();
        up.rc = Some((Instant::now(), RcState { switches: 0b1010, ..RcState::default() }));
        let seen = Observation { status: &up, ..seen };
        let check = control_mode(&seen, &state(0, MODE_CAN, 259, 0), Wire::CanV2);
        assert_eq!((check.outcome, check.finding.as_str()), (Outcome::Pass, "can, RC switch SWB up"));
    }

    #[test]
    fn faults_warn_for_warnings_fail_for_faults_and_name_driver_bits() {
        let status = RobotStatus::default();
        let seen = seen(&status, Wire::CanV2);
        let check = faults(&seen, &state(0, 1, 224, 0x0200), Wire::CanV2);
        assert_eq!(check.outcome, Outcome::Warn);
        assert_eq!(check.finding, "0x0200: battery_undervoltage_warning [warning]");
        let check = faults(&seen, &state(2, 1, 219, 0x0100), Wire::CanV2);
        assert_eq!(check.outcome, Outcome::Fail);
        assert!(check.action.unwrap().ends_with("then `tracerctl clear-errors` for faults that latch"));
        let check = faults(&seen, &state(2, 1, 259, 0), Wire::CanV2);
        assert_eq!(
            (check.outcome, check.finding.as_str()),
            (Outcome::Fail, "system exception, but no fault bit says why")
        );

        let mut status = RobotStatus::default();
        status.motor_low[1] =
            Some(MotorLowSpeed { motor: 2, driver_state: 0x04, ..MotorLowSpeed::default() });
        let seen = Observation { status: &status, ..seen };
        let check = faults(&seen, &state(0, 1, 259, 0), Wire::CanV2);
        assert_eq!(check.outcome, Outcome::Warn);
        assert_eq!(check.finding, "0x0000: motor 2 driver_overcurrent [warning]");
    }

    /// `Severity`'s order decides: a bit no document defines warns, alone or with a warning; with a fault
    /// the check fails for the fault.
    #[test]
    fn an_undocumented_bit_warns() {
        let status = RobotStatus::default();
        let seen = seen(&status, Wire::CanV2);
        let check = faults(&seen, &state(0, 1, 259, 0x0080), Wire::CanV2);
        assert_eq!(check.outcome, Outcome::Warn);
        assert_eq!(check.finding, "0x0080: reserved_byte5_bit7 [unknown]");
        assert_eq!(faults(&seen, &state(0, 1, 259, 0x0280), Wire::CanV2).outcome, Outcome::Warn);
        assert_eq!(faults(&seen, &state(0, 1, 259, 0x0180), Wire::CanV2).outcome, Outcome::Fail);
        assert_eq!(outcome_of(Severity::Unknown), Outcome::Warn);
    }

    #[test]
    fn hot_drivers_warn_then_fail() {
        let mut status = RobotStatus::default();
        for motor in 1..=2u8 {
            let index = usize::from(motor - 1);
            status.motor_high[index] =
                Some(crate::protocol::message::MotorHighSpeed { motor, ..Default::default() });
            status.motor_low[index] =
                Some(MotorLowSpeed { motor, driver_temperature: 40, ..MotorLowSpeed::default() });
        }
        assert_eq!(motors(&seen(&status, Wire::CanV2)).outcome, Outcome::Pass);
        status.motor_low[0].as_mut().unwrap().driver_temperature = 60;
        assert_eq!(motors(&seen(&status, Wire::CanV2)).outcome, Outcome::Warn);
        status.motor_low[1].as_mut().unwrap().driver_temperature = 70;
        let check = motors(&seen(&status, Wire::CanV2));
        assert_eq!(check.outcome, Outcome::Fail);
        assert!(check.action.unwrap().contains("motor 2's driver is above 65 C"));
    }

    #[test]
    fn stale_status_fails_and_a_slow_one_warns() {
        let mut status = RobotStatus::default();
        let now = Instant::now();
        status.system = Some((now - Duration::from_millis(400), state(0, 1, 259, 0), Wire::CanV2));
        status.system_frames = 50;
        let mut seen = seen(&status, Wire::CanV2);
        seen.now = now;
        assert_eq!(status_rate(&seen).outcome, Outcome::Fail);
        let mut status = status.clone();
        status.system = Some((now, state(0, 1, 259, 0), Wire::CanV2));
        status.system_frames = 10;
        let seen = Observation { status: &status, ..seen };
        let check = status_rate(&seen);
        assert_eq!(check.outcome, Outcome::Warn);
        assert!(check.finding.ends_with("expected 50/s"), "{}", check.finding);
    }
}
