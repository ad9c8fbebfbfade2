//! The black box's trigger watcher: every received frame is decoded and the events that open an incident
//! come out as [`Trigger`]s. Pure: no clock, thread or I/O; time comes in with each frame (and each
//! [`Watcher::tick`]), so a replay at full speed finds what a live run finds.
//!
//! The rules, written once (docs: "Triggers"):
//! - Every trigger fires on an onset (false -> true) and re-arms only after its condition has been false for
//!   `rearm` (default 1 s) on the frames' clock; an instantaneous condition (a frame seen, a mode changed)
//!   re-arms after `rearm` without it. A clock that goes back re-arms (reported twice rather than lost).
//! - States that are faults fire when first seen true, even on the first frame: a robot already in E-stop,
//!   in exception, with a fault bit set or a low battery when recording starts is reported once. Changes
//!   need a before: the first system status only sets it (a robot already in RC mode is no mode change).
//! - E-stop: vehicle state 1. Vehicle exception: vehicle state 2.
//! - Fault: one trigger per bit of the system state's fault bytes (named by the wire's table) and of each
//!   motor driver's state byte (0x261/0x262) whose severity is above `[info]` (`protocol::faults`).
//! - Mode change: the reported control mode changes, except out of code 0 into a command mode (CAN or
//!   serial): that is a host taking control (V2 standby -> CAN; V1/RS232's 0 means "RC, or not yet in command
//!   mode"), the normal start of every session, and not an incident. Into standby (the robot's own power
//!   cycle, an E-stop) and every change to or from RC or between command modes are reported.
//! - RC override: the RC transmitter takes control from a host, that is the reported mode becomes RC (V2 code
//!   3; V1/RS232 code 0) after a command mode (CAN or serial), or, where the robot sends 0x241 (the SDK's RC
//!   state), switch SWB moves to the middle while the mode is a command mode. (TRACER manual 2.3: SWB at the
//!   top is command mode, in the middle RC mode; the transmitter has priority.) It lasts until the mode is no
//!   longer RC and SWB is not in the middle. V1/RS232 report standby as 0 too, so there a drop to 0 during an
//!   E-stop or exception (which fire their own triggers) is not called an RC override.
//! - Link silence: no system status for longer than its period x 5 (`catalog`: 100 ms on V2 and RS232, 500 ms
//!   on V1), watched once a status has been seen. Found in `tick` when nothing arrives and in `frame` when
//!   the next frame comes after the gap; `at` is the last status + the limit. Once per silence.
//! - Battery low: the system state's voltage below `battery_warning_volts`; it ends at that + 0.3 V, so a
//!   voltage that sags under load and recovers does not fire again and again.
//! - CAN error frames: the first error frame after a quiet `rearm`; bus state: the controller's error state
//!   getting worse (error-warning, error-passive, bus-off; a recovery is no trigger), which wins over the
//!   error-frame trigger of the same frame.
//! - `--trigger EXPR` ([`Expression`]): true while any message carrying the field satisfies it (motor 1 or
//!   motor 2), each judged by its latest value; `id=X` fires when such a frame appears.

use std::time::Duration;

pub use super::cause::{BusState, Cause, FaultSource};
use super::expr::kind_bit;
pub use super::expr::{Expression, ExpressionError, Op, Target};
use super::onset::{Onset, Pulse};
use super::state::{insert_stamp, nanos_of, stamp_at, value_text, Latest};
use crate::candump::{Timestamp, TimestampKind};
use crate::protocol::catalog::{identifier_of, periodic_frame};
use crate::protocol::constants::{volts, BATTERY_WARNING_DV};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ErrorFrame;
use crate::protocol::faults::{FlagTable, Severity};
use crate::protocol::message::{RcState, SystemState, VEHICLE_ESTOP, VEHICLE_EXCEPTION};
use crate::protocol::{
    for_each_field, serial, CanFrame, ControlMode, Decoded, FrameId, FrameKind, LinkFrame, Message,
    MessageKind, ProtocolHint, Wire,
};

/// A battery low ends this far above the threshold, V.
pub const BATTERY_HYSTERESIS_V: f64 = 0.3;

/// One trigger: when and why.
#[derive(Clone, Debug, PartialEq)]
pub struct Trigger {
    pub at: Timestamp,
    pub cause: Cause,
}

/// What to watch for.
#[derive(Clone, Debug, PartialEq)]
pub struct TriggerSettings {
    /// The default triggers (E-stop, faults, exception, mode change, RC override, link silence, battery,
    /// CAN errors).
    pub defaults: bool,
    /// `--trigger` expressions.
    pub expressions: Vec<Expression>,
    pub battery_warning_volts: f64,
    /// How long a condition must be false before it can fire again.
    pub rearm: Duration,
}

impl Default for TriggerSettings {
    fn default() -> Self {
        Self {
            defaults: true,
            expressions: Vec::new(),
            battery_warning_volts: volts(BATTERY_WARNING_DV),
            rearm: Duration::from_secs(1),
        }
    }
}

/// A `--trigger` expression with its state.
#[derive(Clone, Debug)]
struct Watch {
    expression: Expression,
    onset: Onset,
    pulse: Pulse,
    /// Bit n: the latest message of slot n satisfies it.
    satisfied: u64,
}

/// The last system status: when, on which wire, and how long it may be silent.
#[derive(Clone, Copy, Debug)]
struct Status {
    at: u64,
    kind: TimestampKind,
    id: FrameId,
    limit: u64,
}

/// The wires' order in per-wire tables.
fn wire_index(wire: Wire) -> usize {
    match wire {
        Wire::CanV2 => 0,
        Wire::CanV1 => 1,
        Wire::Serial => 2,
    }
}

const WIRES: [Wire; 3] = [Wire::CanV2, Wire::CanV1, Wire::Serial];

/// Whether the reported mode going from `from` to `to` is a mode change to report (see the module doc).
fn is_reported_change(wire: Wire, from: u8, to: u8) -> bool {
    let into_command =
        matches!(ControlMode::from_code(wire, to), Some(ControlMode::Can | ControlMode::Serial));
    from != to && !(from == 0 && into_command)
}

fn is_command_mode(wire: Wire, code: u8) -> bool {
    matches!(ControlMode::from_code(wire, code), Some(ControlMode::Can | ControlMode::Serial))
}

fn is_rc(wire: Wire, code: u8) -> bool {
    ControlMode::from_code(wire, code) == Some(ControlMode::Rc)
}

/// SWB's two bits of 0x241 byte 0 in the middle position.
const SWB_MIDDLE: u8 = 0b01;

/// Watches decoded frames for triggers.
#[derive(Clone, Debug)]
pub struct Watcher {
    defaults: bool,
    rearm: u64,
    battery_threshold: f64,
    protocol: ProtocolHint,
    detector: ProtocolDetector,
    latest: Latest,
    /// Silence limit of each wire's system status, ns: its catalog period x 5.
    silence_limits: [Option<u64>; 3],
    status: Option<Status>,
    silence: Onset,
    /// The last system status and its wire.
    system: Option<(Wire, SystemState)>,
    estop: Onset,
    exception: Onset,
    battery: Onset,
    /// Fault bits of the system state: V2's table, then V1/RS232's.
    system_bits: [[Onset; 16]; 2],
    system_codes: [u16; 2],
    driver_bits: [[Onset; 8]; 2],
    driver_states: [u8; 2],
    mode_pulse: Pulse,
    rc: Onset,
    rc_from: u8,
    swb: Option<u8>,
    bus: BusState,
    /// Error-warning or worse, error-passive or worse, bus-off.
    bus_levels: [Onset; 3],
    error_pulse: Pulse,
    error_frames: u64,
    last_error: Option<(Timestamp, ErrorFrame)>,
    undecodable: u64,
    watches: Vec<Watch>,
}

impl Watcher {
    pub fn new(settings: TriggerSettings) -> Self {
        let silence_limit = |wire| {
            let limit = periodic_frame(identifier_of(MessageKind::SystemState, wire)?)?.stale_after()?;
            Some(u64::try_from(limit.as_nanos()).unwrap_or(u64::MAX))
        };
        let watches = settings
            .expressions
            .into_iter()
            .map(|expression| Watch {
                expression,
                onset: Onset::default(),
                pulse: Pulse::default(),
                satisfied: 0,
            })
            .collect();
        Self {
            defaults: settings.defaults,
            rearm: u64::try_from(settings.rearm.as_nanos()).unwrap_or(u64::MAX),
            battery_threshold: settings.battery_warning_volts,
            protocol: ProtocolHint::Auto,
            detector: ProtocolDetector::default(),
            latest: Latest::default(),
            silence_limits: WIRES.map(silence_limit),
            status: None,
            silence: Onset::default(),
            system: None,
            estop: Onset::default(),
            exception: Onset::default(),
            battery: Onset::default(),
            system_bits: [[Onset::default(); 16]; 2],
            system_codes: [0; 2],
            driver_bits: [[Onset::default(); 8]; 2],
            driver_states: [0; 2],
            mode_pulse: Pulse::default(),
            rc: Onset::default(),
            rc_from: 0,
            swb: None,
            bus: BusState::ErrorActive,
            bus_levels: [Onset::default(); 3],
            error_pulse: Pulse::default(),
            error_frames: 0,
            last_error: None,
            undecodable: 0,
            watches,
        }
    }

    /// Decodes ambiguous CAN frames (0x151) as this protocol version rather than as the traffic says.
    #[must_use]
    pub fn with_protocol(mut self, protocol: ProtocolHint) -> Self {
        self.protocol = protocol;
        self
    }

    /// One received frame (CAN V2/V1 or RS232). Pushes the triggers it causes, in time order.
    pub fn frame(&mut self, at: Timestamp, frame: &LinkFrame, out: &mut Vec<Trigger>) {
        let now = nanos_of(at);
        self.check_silence(now, out);
        let decoded = match frame {
            LinkFrame::Can(can) if can.kind() == FrameKind::Error => {
                self.error_frame(at, now, can, out);
                return;
            }
            LinkFrame::Can(can) => self.detector.observe_and_decode(can, self.protocol),
            LinkFrame::Serial(serial_frame) => Ok(serial::decode(serial_frame)),
        };
        let id = frame.frame_id();
        self.watch_ids(at, now, id, out);
        match decoded {
            Ok(Some(decoded)) => self.message(at, now, id, decoded, out),
            Ok(None) => {}
            Err(_) => self.undecodable += 1,
        }
    }

    /// Time passes without frames (`now` on the frames' clock): finds a link silence.
    pub fn tick(&mut self, now: Timestamp, out: &mut Vec<Trigger>) {
        self.check_silence(nanos_of(now), out);
    }

    #[inline]
    fn push_default(&self, out: &mut Vec<Trigger>, at: Timestamp, cause: Cause) {
        if self.defaults {
            out.push(Trigger { at, cause });
        }
    }

    fn check_silence(&mut self, now: u64, out: &mut Vec<Trigger>) {
        let Some(status) = self.status else { return };
        let began = status.at.saturating_add(status.limit);
        if now <= began || self.silence.is_active() {
            return;
        }
        if self.silence.update(began, true, self.rearm) {
            let limit = Duration::from_nanos(status.limit);
            let cause = Cause::LinkSilence { id: status.id, limit };
            self.push_default(out, stamp_at(began, status.kind), cause);
        }
    }

    fn watch_ids(&mut self, at: Timestamp, now: u64, id: FrameId, out: &mut Vec<Trigger>) {
        let rearm = self.rearm;
        for watch in &mut self.watches {
            if watch.expression.target() == Target::Id
                && watch.expression.matches_id(id)
                && watch.pulse.hit(now, rearm)
            {
                let text = watch.expression.text().to_string();
                out.push(Trigger { at, cause: Cause::Expression { text, detail: format!("{id} seen") } });
            }
        }
    }

    #[inline]
    fn message(&mut self, at: Timestamp, now: u64, id: FrameId, decoded: Decoded, out: &mut Vec<Trigger>) {
        let slot = self.latest.store(id, at, decoded);
        match decoded.message {
            Message::SystemState(state) => self.system_state(at, now, id, decoded.wire, state, out),
            Message::MotorLowSpeed(motor) => self.driver_state(at, now, motor.motor, motor.driver_state, out),
            Message::RcState(rc) => self.rc_state(at, now, rc, out),
            _ => {}
        }
        if let Some(slot) = slot {
            if !self.watches.is_empty() {
                self.watch_fields(at, now, slot, &decoded, out);
            }
        }
    }

    fn system_state(
        &mut self,
        at: Timestamp,
        now: u64,
        id: FrameId,
        wire: Wire,
        state: SystemState,
        out: &mut Vec<Trigger>,
    ) {
        let rearm = self.rearm;
        if let Some(limit) = self.silence_limits[wire_index(wire)] {
            self.silence.update(now, false, rearm);
            self.status = Some(Status { at: now, kind: at.kind, id, limit });
        }
        let previous = self.system.replace((wire, state));
        if self.estop.update(now, state.vehicle_state == VEHICLE_ESTOP, rearm) {
            self.push_default(out, at, Cause::EStop);
        }
        if self.exception.update(now, state.vehicle_state == VEHICLE_EXCEPTION, rearm) {
            self.push_default(out, at, Cause::VehicleException);
        }
        self.battery_level(at, now, state.battery_decivolts, out);
        self.system_faults(at, now, wire, state.fault_code, out);
        let before =
            previous.filter(|(previous_wire, _)| *previous_wire == wire).map(|(_, s)| s.control_mode);
        self.control_mode(at, now, wire, before, state.control_mode, out);
    }

    fn battery_level(&mut self, at: Timestamp, now: u64, decivolts: u16, out: &mut Vec<Trigger>) {
        let voltage = volts(decivolts);
        let low = if self.battery.is_active() {
            voltage < self.battery_threshold + BATTERY_HYSTERESIS_V - 1e-9
        } else {
            voltage < self.battery_threshold
        };
        if self.battery.update(now, low, self.rearm) {
            self.push_default(
                out,
                at,
                Cause::BatteryLow { volts: voltage, threshold: self.battery_threshold },
            );
        }
    }

    fn system_faults(&mut self, at: Timestamp, now: u64, wire: Wire, code: u16, out: &mut Vec<Trigger>) {
        let (table, index) = match wire {
            Wire::CanV2 => (FlagTable::SystemV2, 0),
            Wire::CanV1 | Wire::Serial => (FlagTable::SystemV1Serial, 1),
        };
        let changed = self.system_codes[index] ^ code;
        if changed == 0 {
            return;
        }
        self.system_codes[index] = code;
        for bit in 0..16 {
            if changed & (1 << bit) == 0 {
                continue;
            }
            let flag = table.info(bit);
            let set = code & (1 << bit) != 0 && flag.severity > Severity::Info;
            if self.system_bits[index][bit as usize].update(now, set, self.rearm) {
                self.push_default(out, at, Cause::Fault { source: FaultSource::System, flag });
            }
        }
    }

    fn driver_state(&mut self, at: Timestamp, now: u64, motor: u8, state: u8, out: &mut Vec<Trigger>) {
        let Some(index) = motor.checked_sub(1).map(usize::from).filter(|index| *index < 2) else { return };
        let changed = self.driver_states[index] ^ state;
        if changed == 0 {
            return;
        }
        self.driver_states[index] = state;
        for bit in 0..8 {
            if changed & (1 << bit) == 0 {
                continue;
            }
            let flag = FlagTable::DriverState.info(bit);
            let set = state & (1 << bit) != 0 && flag.severity > Severity::Info;
            if self.driver_bits[index][bit as usize].update(now, set, self.rearm) {
                self.push_default(out, at, Cause::Fault { source: FaultSource::Driver { motor }, flag });
            }
        }
    }

    fn control_mode(
        &mut self,
        at: Timestamp,
        now: u64,
        wire: Wire,
        before: Option<u8>,
        code: u8,
        out: &mut Vec<Trigger>,
    ) {
        if let Some(from) = before.filter(|from| *from != code) {
            if is_reported_change(wire, from, code) && self.mode_pulse.hit(now, self.rearm) {
                self.push_default(out, at, Cause::ModeChange { wire, from, to: code });
            }
            // On V1/RS232 an E-stop or exception also drops the mode to 0 (standby reads as RC there): those
            // have their own triggers, and only a healthy robot at 0 is taken over by the transmitter.
            let explained = wire != Wire::CanV2 && (self.estop.is_active() || self.exception.is_active());
            if is_rc(wire, code) && is_command_mode(wire, from) && !explained && !self.rc.is_active() {
                self.rc_from = from;
                self.fire_rc(at, now, wire, true, out);
            }
        }
        if !is_rc(wire, code) && self.swb != Some(SWB_MIDDLE) {
            self.fire_rc(at, now, wire, false, out);
        }
    }

    fn rc_state(&mut self, at: Timestamp, now: u64, rc: RcState, out: &mut Vec<Trigger>) {
        let swb = (rc.switches >> 2) & 0b11;
        let before = self.swb.replace(swb);
        let Some((wire, state)) = self.system else { return };
        let mode = state.control_mode;
        let moved_to_middle = swb == SWB_MIDDLE && before.is_some_and(|before| before != SWB_MIDDLE);
        if moved_to_middle && is_command_mode(wire, mode) && !self.rc.is_active() {
            self.rc_from = mode;
            self.fire_rc(at, now, wire, true, out);
        } else if swb != SWB_MIDDLE && !is_rc(wire, mode) {
            self.fire_rc(at, now, wire, false, out);
        }
    }

    fn fire_rc(&mut self, at: Timestamp, now: u64, wire: Wire, active: bool, out: &mut Vec<Trigger>) {
        if self.rc.update(now, active, self.rearm) {
            self.push_default(out, at, Cause::RcOverride { wire, from: self.rc_from });
        }
    }

    fn error_frame(&mut self, at: Timestamp, now: u64, frame: &CanFrame, out: &mut Vec<Trigger>) {
        let Some(error) = ErrorFrame::from_frame(frame) else { return };
        self.error_frames += 1;
        self.last_error = Some((at, error));
        let from = self.bus;
        let to = from.after(&error);
        self.bus = to;
        let levels = [BusState::ErrorWarning, BusState::ErrorPassive, BusState::BusOff];
        let mut worse = false;
        for (onset, level) in self.bus_levels.iter_mut().zip(levels) {
            worse |= onset.update(now, to >= level, self.rearm);
        }
        let first_error = self.error_pulse.hit(now, self.rearm);
        if worse {
            self.push_default(out, at, Cause::BusState { from, to });
        } else if first_error {
            self.push_default(out, at, Cause::ErrorFrame { error });
        }
    }

    fn watch_fields(
        &mut self,
        at: Timestamp,
        now: u64,
        slot: usize,
        decoded: &Decoded,
        out: &mut Vec<Trigger>,
    ) {
        let bit = kind_bit(decoded.message.kind());
        let rearm = self.rearm;
        for watch in &mut self.watches {
            let Target::Field { name, kinds } = watch.expression.target() else { continue };
            if kinds & bit == 0 {
                continue;
            }
            let mut value = None;
            for_each_field(decoded, |field| {
                if field.name == name {
                    value = Some(field.value);
                }
            });
            let Some(value) = value else { continue };
            let mask = 1u64 << slot;
            if watch.expression.holds(&value) {
                watch.satisfied |= mask;
            } else {
                watch.satisfied &= !mask;
            }
            if watch.onset.update(now, watch.satisfied != 0, rearm) {
                let id = self.latest.get(slot).map_or_else(String::new, |kept| format!(" ({})", kept.id));
                let detail = format!("{} = {}{id}", name.as_str(), value_text(&value));
                let text = watch.expression.text().to_string();
                out.push(Trigger { at, cause: Cause::Expression { text, detail } });
            }
        }
    }

    /// The decoded state now, for incident.json: the latest message of each identifier (with decode's JSON
    /// field names), the vehicle state, control mode, battery, active faults, link and bus, and each
    /// `--trigger` with whether it holds.
    pub fn state(&self) -> serde_json::Value {
        let mut state = serde_json::Map::new();
        state.insert("messages".into(), self.latest.to_json());
        if let Some((wire, system)) = self.system {
            let named = |name: Option<&'static str>, raw: u8| name.map_or_else(|| raw.into(), Into::into);
            let vehicle = crate::protocol::message::vehicle_state_name(system.vehicle_state);
            state.insert("vehicle_state".into(), named(vehicle, system.vehicle_state));
            let mode = ControlMode::from_code(wire, system.control_mode).map(ControlMode::name);
            state.insert("control_mode".into(), named(mode, system.control_mode));
            state.insert("battery_voltage".into(), volts(system.battery_decivolts).into());
            state.insert("wire".into(), wire.as_str().into());
        }
        state.insert("estop".into(), self.estop.is_active().into());
        state.insert("vehicle_exception".into(), self.exception.is_active().into());
        state.insert("battery_low".into(), self.battery.is_active().into());
        state.insert("rc_override".into(), self.rc.is_active().into());
        state.insert("faults".into(), self.active_faults());
        state.insert("link".into(), self.link_json());
        state.insert("bus".into(), self.bus_json());
        let triggers: Vec<serde_json::Value> = self
            .watches
            .iter()
            .map(|watch| {
                let holds = match watch.expression.target() {
                    Target::Id => watch.pulse.last().is_some(),
                    Target::Field { .. } => watch.onset.is_active(),
                };
                serde_json::json!({ "trigger": watch.expression.text(), "holds": holds })
            })
            .collect();
        state.insert("triggers".into(), triggers.into());
        state.into()
    }

    /// `[{"source": "system", "name": ..., "severity": ...}, {"source": "motor 1 driver", ...}]`: the set bits
    /// above `[info]`.
    fn active_faults(&self) -> serde_json::Value {
        let mut faults = Vec::new();
        let mut add = |source: String, flag: crate::protocol::FlagInfo| {
            if flag.severity > Severity::Info {
                faults.push(serde_json::json!({
                    "source": source,
                    "name": flag.name,
                    "severity": flag.severity.as_str(),
                    "meaning": flag.meaning,
                }));
            }
        };
        if let Some((wire, system)) = self.system {
            system.faults(wire).iter().for_each(|flag| add("system".into(), flag));
        }
        for (index, bits) in self.driver_states.iter().enumerate() {
            let flags = crate::protocol::Flags::new(FlagTable::DriverState, u16::from(*bits));
            flags.iter().for_each(|flag| add(format!("motor {} driver", index + 1), flag));
        }
        faults.into()
    }

    fn link_json(&self) -> serde_json::Value {
        let mut link = serde_json::Map::new();
        match self.status {
            Some(status) => {
                insert_stamp(&mut link, "last_status", stamp_at(status.at, status.kind));
                link.insert("status_id".into(), status.id.to_string().into());
                link.insert("silence_limit_ms".into(), (status.limit / 1_000_000).into());
            }
            None => {
                link.insert("last_status".into(), serde_json::Value::Null);
            }
        }
        link.insert("silent".into(), self.silence.is_active().into());
        link.insert("protocol".into(), self.detector.describe().into());
        link.insert("undecodable_frames".into(), self.undecodable.into());
        link.into()
    }

    fn bus_json(&self) -> serde_json::Value {
        let mut bus = serde_json::Map::new();
        bus.insert("state".into(), self.bus.name().into());
        bus.insert("error_frames".into(), self.error_frames.into());
        let last = self.last_error.map_or(serde_json::Value::Null, |(at, error)| {
            let mut last = serde_json::Map::new();
            insert_stamp(&mut last, "ts", at);
            last.insert("classes".into(), error.class_names().collect::<Vec<_>>().into());
            last.insert("controller".into(), error.controller_names().collect::<Vec<_>>().into());
            if let Some((tx, rx)) = error.counters {
                last.insert("tx_errors".into(), tx.into());
                last.insert("rx_errors".into(), rx.into());
            }
            last.into()
        });
        bus.insert("last_error_frame".into(), last);
        bus.into()
    }
}

#[cfg(test)]
#[path = "triggers_tests.rs"]
mod tests;

#[cfg(test)]
#[path = "triggers_sim_tests.rs"]
mod sim_tests;
