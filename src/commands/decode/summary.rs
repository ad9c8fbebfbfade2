//! `decode --summary`: the report a technician reads. Memory is bounded: per-ID tables, capped event lists.

mod json;
mod report;
mod text;

use std::collections::{HashMap, HashSet};
use std::fmt;
use std::hash::{Hash, Hasher};

use serde_json::Value as Json;

use super::InputStats;
use crate::candump::Timestamp;
use crate::output::{Event, FrameRef, Shape};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ERROR_CLASSES;
use crate::protocol::frame::ERR_FLAG;
use crate::protocol::message::{control_mode_name, vehicle_state_name, Message, SystemState, Wire};
use crate::protocol::transitions::StatusTracker;
use crate::protocol::{Decoded, FrameId, FrameKind};

/// At most this many mode and vehicle-state events are listed; the rest are counted.
const MAX_LISTED_EVENTS: usize = 200;
/// Identifiers beyond this many (extended, serial, FD) share one "other" row, so memory stays bounded.
const MAX_OTHER_IDS: usize = 4096;

/// A wheel odometer step larger than this between consecutive frames is a reset, not travel.
const ODOMETER_JUMP_MM: i64 = 2_000;

/// At most this many interface names are listed; the rest are counted.
const MAX_LISTED_INTERFACES: usize = 64;
/// Names beyond the listed ones are counted by hash, up to this many (then "more than N").
const MAX_COUNTED_INTERFACES: usize = 65_536;

/// The interface names seen: a hash set (a log of 200,000 distinct names must not be searched linearly),
/// the first names listed in order, the rest only counted. A name already seen costs a lookup, no allocation.
#[derive(Debug, Default)]
struct Interfaces {
    names: Vec<String>,
    listed: HashSet<String>,
    /// Hashes of the names beyond the listed ones.
    extra: HashSet<u64>,
    /// More names than `MAX_COUNTED_INTERFACES` were not listed.
    extra_overflow: bool,
}

impl Interfaces {
    fn see(&mut self, name: &str) {
        if self.listed.contains(name) {
            return;
        }
        if self.names.len() < MAX_LISTED_INTERFACES {
            self.names.push(name.to_string());
            self.listed.insert(name.to_string());
            return;
        }
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        name.hash(&mut hasher);
        let hash = hasher.finish();
        if self.extra.len() < MAX_COUNTED_INTERFACES {
            self.extra.insert(hash);
        } else if !self.extra.contains(&hash) {
            self.extra_overflow = true;
        }
    }

    fn not_listed(&self) -> usize {
        self.extra.len()
    }
}

/// When something happened: the timestamp if the input has one, else the frame's position.
#[derive(Clone, Copy, Debug, PartialEq)]
struct At {
    ts: Option<Timestamp>,
    frame: u64,
}

/// What one row of the per-identifier table counts. The variants' order is the table's: standard then
/// extended CAN identifiers, error frames, RS232 identifiers, standard-ID CAN FD frames, the overflow row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum RowKey {
    /// A classic CAN data or remote frame (standard or extended; extended CAN FD frames too).
    Can(FrameId),
    /// A CAN error frame, by its error-class bits (an extended identifier without `ERR_FLAG`).
    Error(FrameId),
    /// An RS232 frame.
    Serial(FrameId),
    /// A CAN FD frame with a standard identifier: listed apart from the classic frame with that number.
    Fd(FrameId),
    /// Every identifier beyond the first `MAX_OTHER_IDS` non-standard ones.
    Other,
}

impl RowKey {
    fn of(event: &Event) -> Self {
        match event.frame {
            FrameRef::Can(frame) => match frame.kind() {
                FrameKind::Error => Self::Error(frame.frame_id()),
                _ if frame.is_extended() => Self::Can(frame.frame_id()),
                FrameKind::Fd => Self::Fd(frame.frame_id()),
                _ => Self::Can(frame.frame_id()),
            },
            FrameRef::Serial(frame) => Self::Serial(frame.frame_id()),
        }
    }

    /// The slot in the 2048-entry table, for a classic standard identifier.
    fn standard_index(self) -> Option<usize> {
        match self {
            Self::Can(id) => id.standard_index(),
            _ => None,
        }
    }
}

impl fmt::Display for RowKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Can(id) | Self::Serial(id) => write!(f, "{id}"),
            // As candump prints an error frame: with the error flag.
            Self::Error(id) => write!(f, "0x{:08X}", id.value() | ERR_FLAG),
            Self::Fd(id) => write!(f, "{id} (FD)"),
            Self::Other => write!(f, "other ids (beyond {MAX_OTHER_IDS})"),
        }
    }
}

#[derive(Debug)]
struct IdStats {
    key: RowKey,
    name: &'static str,
    count: u64,
    first: Option<Timestamp>,
    last: Option<Timestamp>,
    worst_gap_ns: u128,
    worst_gap_at: Option<Timestamp>,
    last_counter: Option<u8>,
    counter_skips: u64,
    frames_lost: u64,
    counter_repeats: u64,
    invalid: u64,
}

impl IdStats {
    fn new(key: RowKey) -> Self {
        Self {
            key,
            name: "",
            count: 0,
            first: None,
            last: None,
            worst_gap_ns: 0,
            worst_gap_at: None,
            last_counter: None,
            counter_skips: 0,
            frames_lost: 0,
            counter_repeats: 0,
            invalid: 0,
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
struct FaultSeen {
    first: Option<At>,
    last: Option<At>,
    frames: u64,
}

/// Records `at` for every bit set in `bits`, one slot per bit.
fn see_bits(slots: &mut [FaultSeen], bits: u16, at: At) {
    for (bit, seen) in slots.iter_mut().enumerate() {
        if bits & (1 << bit) != 0 {
            seen.first.get_or_insert(at);
            seen.last = Some(at);
            seen.frames += 1;
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Extreme {
    value: i64,
    at: At,
}

fn keep_max_abs(slot: &mut Option<Extreme>, value: i64, at: At) {
    if slot.is_none_or(|best| value.abs() > best.value.abs()) {
        *slot = Some(Extreme { value, at });
    }
}

#[derive(Debug, Default)]
struct Wheel {
    first: Option<i64>,
    last: Option<i64>,
    travelled_mm: i64,
    resets: u64,
}

impl Wheel {
    fn update(&mut self, mm: i64) {
        if let Some(last) = self.last {
            let step = mm - last;
            if step.abs() > ODOMETER_JUMP_MM {
                self.resets += 1;
            } else {
                self.travelled_mm += step.abs();
            }
        }
        self.first.get_or_insert(mm);
        self.last = Some(mm);
    }
}

/// Aggregates events into the report.
#[derive(Debug)]
pub struct Summary {
    frames: u64,
    first: Option<Timestamp>,
    last: Option<Timestamp>,
    /// Index into `ids` + 1 for each standard identifier; 0 = not seen.
    standard_index: Box<[u32; 2048]>,
    /// Index into `ids` for every other key (extended, error, serial, FD).
    other_index: HashMap<RowKey, usize>,
    ids: Vec<IdStats>,
    interfaces: Interfaces,
    last_iface: String,
    /// Control-mode and vehicle-state changes (the same tracker as the MCAP event channel).
    status: StatusTracker,
    events: Vec<(At, String)>,
    events_not_listed: u64,
    /// [table][bit] for the two system-state layouts, then [motor 1, motor 2, other] x 8 driver bits.
    system_faults: [[FaultSeen; 16]; 2],
    driver_faults: [[FaultSeen; 8]; 3],
    battery_min: Option<Extreme>,
    battery_max: Option<Extreme>,
    battery_last: Option<Extreme>,
    wheels: [Wheel; 2],
    measured_linear: Option<Extreme>,
    measured_angular: Option<Extreme>,
    commanded_linear: Option<Extreme>,
    commanded_angular: Option<Extreme>,
    rpm: [Option<Extreme>; 2],
    current: [Option<Extreme>; 2],
    error_classes: [u64; 10],
    raw_frames: u64,
}

impl Default for Summary {
    fn default() -> Self {
        Self {
            frames: 0,
            first: None,
            last: None,
            standard_index: Box::new([0; 2048]),
            other_index: HashMap::new(),
            ids: Vec::new(),
            interfaces: Interfaces::default(),
            last_iface: String::new(),
            status: StatusTracker::default(),
            events: Vec::new(),
            events_not_listed: 0,
            system_faults: [[FaultSeen::default(); 16]; 2],
            driver_faults: [[FaultSeen::default(); 8]; 3],
            battery_min: None,
            battery_max: None,
            battery_last: None,
            wheels: Default::default(),
            measured_linear: None,
            measured_angular: None,
            commanded_linear: None,
            commanded_angular: None,
            rpm: [None; 2],
            current: [None; 2],
            error_classes: [0; 10],
            raw_frames: 0,
        }
    }
}

/// Exact: every stamp the parser accepts (up to 19 digits of seconds) fits in u128 nanoseconds.
fn nanos(ts: &Timestamp) -> u128 {
    ts.as_nanos()
}

/// The rolling count byte a message carries, if any.
fn counter(decoded: &Decoded) -> Option<u8> {
    match decoded.message {
        Message::SystemState(state) => Some(state.count),
        Message::LightCommand(lights) | Message::LightState(lights) => Some(lights.count),
        Message::RcState(rc) => Some(rc.count),
        Message::PercentMotionCommand(cmd) => Some(cmd.count),
        Message::MotorDriverState(motor) => Some(motor.count),
        Message::MotionState(state) if decoded.wire != Wire::CanV2 => Some(state.count),
        _ => None,
    }
}

impl Summary {
    pub fn event(&mut self, event: &Event) {
        self.frames += 1;
        let at = At { ts: event.ts, frame: self.frames };
        if let Some(ts) = event.ts {
            self.first.get_or_insert(ts);
            self.last = Some(ts);
        }
        if event.iface != self.last_iface {
            self.last_iface.clear();
            self.last_iface.push_str(event.iface);
            self.interfaces.see(event.iface);
        }
        let shape = event.shape();
        let stats = self.id_stats(RowKey::of(event));
        stats.count += 1;
        stats.name = event.msg_name();
        if let Some(ts) = event.ts {
            if let Some(previous) = stats.last {
                let gap = nanos(&ts).saturating_sub(nanos(&previous));
                if gap > stats.worst_gap_ns {
                    stats.worst_gap_ns = gap;
                    stats.worst_gap_at = Some(ts);
                }
            }
            stats.first.get_or_insert(ts);
            stats.last = Some(ts);
        }
        match shape {
            Shape::Message(decoded) => {
                if let Some(count) = counter(&decoded) {
                    if let Some(previous) = stats.last_counter {
                        match count.wrapping_sub(previous) {
                            1 => {}
                            0 => stats.counter_repeats += 1,
                            step => {
                                stats.counter_skips += 1;
                                stats.frames_lost += u64::from(step - 1);
                            }
                        }
                    }
                    stats.last_counter = Some(count);
                }
                self.message(&decoded, at);
            }
            Shape::Invalid(_) => stats.invalid += 1,
            Shape::ErrorFrame(error) => {
                for (index, (mask, _)) in ERROR_CLASSES.iter().enumerate() {
                    if error.classes & mask != 0 {
                        self.error_classes[index] += 1;
                    }
                }
            }
            Shape::Remote | Shape::Raw => self.raw_frames += 1,
        }
    }

    fn id_stats(&mut self, key: RowKey) -> &mut IdStats {
        let slot = if let Some(standard) = key.standard_index() {
            let index = self.standard_index[standard];
            if index == 0 {
                self.ids.push(IdStats::new(key));
                self.standard_index[standard] = self.ids.len() as u32;
                self.ids.len() - 1
            } else {
                index as usize - 1
            }
        } else {
            let key = if self.other_index.len() >= MAX_OTHER_IDS && !self.other_index.contains_key(&key) {
                RowKey::Other
            } else {
                key
            };
            match self.other_index.get(&key) {
                Some(index) => *index,
                None => {
                    self.ids.push(IdStats::new(key));
                    self.other_index.insert(key, self.ids.len() - 1);
                    self.ids.len() - 1
                }
            }
        };
        &mut self.ids[slot]
    }

    fn note(&mut self, at: At, text: String) {
        if self.events.len() < MAX_LISTED_EVENTS {
            self.events.push((at, text));
        } else {
            self.events_not_listed += 1;
        }
    }

    fn message(&mut self, decoded: &Decoded, at: At) {
        match decoded.message {
            Message::SystemState(state) => self.system_state(&state, decoded.wire, at),
            Message::MotionState(state) => {
                keep_max_abs(&mut self.measured_linear, state.linear_mm_s.into(), at);
                keep_max_abs(&mut self.measured_angular, state.angular_mrad_s.into(), at);
            }
            Message::MotionCommand(cmd) => {
                keep_max_abs(&mut self.commanded_linear, cmd.linear_mm_s.into(), at);
                keep_max_abs(&mut self.commanded_angular, cmd.angular_mrad_s.into(), at);
            }
            Message::PercentMotionCommand(cmd) => {
                keep_max_abs(&mut self.commanded_linear, cmd.linear_mm_s(), at);
                // Percent commands are in 1e-5 rad/s; the table keeps mrad/s.
                keep_max_abs(&mut self.commanded_angular, cmd.angular_1e5() / 100, at);
            }
            Message::MotorHighSpeed(motor) if matches!(motor.motor, 1 | 2) => {
                self.motor_extremes(motor.motor, motor.rpm.into(), motor.current_deciamps.into(), at);
            }
            Message::MotorDriverState(motor) if matches!(motor.motor, 1 | 2) => {
                self.motor_extremes(motor.motor, motor.rpm.into(), motor.current_deciamps.into(), at);
            }
            Message::MotorLowSpeed(motor) => {
                let index = usize::from(motor.motor.clamp(1, 3) - 1);
                see_bits(&mut self.driver_faults[index], motor.driver_state.into(), at);
            }
            Message::Odometry(odo) => {
                self.wheels[0].update(odo.left_mm.into());
                self.wheels[1].update(odo.right_mm.into());
            }
            _ => {}
        }
    }

    fn system_state(&mut self, state: &SystemState, wire: Wire, at: At) {
        self.note_mode_change(state.control_mode, wire, at);
        self.note_vehicle_change(state, at);
        let table = usize::from(wire != Wire::CanV2);
        see_bits(&mut self.system_faults[table], state.fault_code, at);
        let volts = i64::from(state.battery_decivolts);
        if self.battery_min.is_none_or(|min| volts < min.value) {
            self.battery_min = Some(Extreme { value: volts, at });
        }
        if self.battery_max.is_none_or(|max| volts > max.value) {
            self.battery_max = Some(Extreme { value: volts, at });
        }
        self.battery_last = Some(Extreme { value: volts, at });
    }

    fn note_mode_change(&mut self, control_mode: u8, wire: Wire, at: At) {
        if let Some(change) = self.status.control_mode(control_mode, wire) {
            let name = |(value, wire): (u8, Wire)| mode_text(wire, value);
            let text = match change.previous {
                Some(previous) => format!("control mode {} -> {}", name(previous), name(change.current)),
                None => format!("control mode {} (first status)", name(change.current)),
            };
            self.note(at, text);
        }
    }

    fn note_vehicle_change(&mut self, state: &SystemState, at: At) {
        if let Some(change) = self.status.vehicle_state(state.vehicle_state) {
            let name = vehicle_state_name(state.vehicle_state).unwrap_or("unknown");
            let text = match change.previous {
                Some(previous) => format!(
                    "vehicle state {} -> {name}{}",
                    vehicle_state_name(previous).unwrap_or("unknown"),
                    if state.is_estop() { " (E-stop pressed)" } else { "" }
                ),
                None => format!("vehicle state {name} (first status)"),
            };
            self.note(at, text);
        }
    }

    /// Motor `number` (1 or 2): the largest speed and current seen.
    fn motor_extremes(&mut self, number: u8, rpm: i64, current_deciamps: i64, at: At) {
        let index = usize::from(number - 1);
        keep_max_abs(&mut self.rpm[index], rpm, at);
        keep_max_abs(&mut self.current[index], current_deciamps, at);
    }

    /// The text report.
    pub fn report(&self, stats: &InputStats, detector: &ProtocolDetector) -> String {
        text::render(&self.build_report(stats, detector))
    }

    /// The same report as JSON.
    pub fn to_json(&self, stats: &InputStats, detector: &ProtocolDetector) -> Json {
        json::render(&self.build_report(stats, detector))
    }
}

fn mode_text(wire: Wire, value: u8) -> String {
    control_mode_name(wire, value).map_or_else(|| format!("unknown (0x{value:02X})"), str::to_string)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_ordered_and_printed_as_the_table_lists_them() {
        let mut keys = [
            RowKey::Other,
            RowKey::Fd(FrameId::Standard(0x123)),
            RowKey::Serial(FrameId::Serial(0xAA01)),
            RowKey::Error(FrameId::Extended(0x4)),
            RowKey::Can(FrameId::Extended(0x123)),
            RowKey::Can(FrameId::Standard(0x7FF)),
            RowKey::Can(FrameId::Standard(0x1)),
        ];
        keys.sort();
        let printed: Vec<String> = keys.iter().map(RowKey::to_string).collect();
        assert_eq!(
            printed,
            ["0x001", "0x7FF", "0x00000123", "0x20000004", "0xAA01", "0x123 (FD)", "other ids (beyond 4096)"]
        );
        assert_eq!(RowKey::Can(FrameId::Standard(0x211)).standard_index(), Some(0x211));
        assert_eq!(RowKey::Fd(FrameId::Standard(0x211)).standard_index(), None);
        assert_eq!(RowKey::Can(FrameId::Extended(0x211)).standard_index(), None);
    }
}
