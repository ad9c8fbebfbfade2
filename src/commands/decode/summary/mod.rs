//! `decode --summary`: the report a technician reads. Memory is bounded: per-ID tables, capped event lists.

mod health;
mod json;
mod merge;
mod report;
mod text;

use std::collections::HashSet;
use std::fmt;
use std::hash::{BuildHasher, Hash, Hasher};

use serde_json::Value as Json;

use super::InputStats;
use crate::candump::{same_bytes, Timestamp};
use crate::output::{Event, FrameRef, Shape};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ERROR_CLASSES;
use crate::protocol::frame::{ERR_FLAG, SFF_MAX};
use crate::protocol::message::{control_mode_name, vehicle_state_name, Message, SystemState, Wire};
use crate::protocol::transitions::StatusTracker;
use crate::protocol::{DecodeError, Decoded, FrameId, FrameKind};

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

/// Slots of [`OtherRows`]: a power of two, about twice the keys it holds (`MAX_OTHER_IDS` and the
/// overflow row).
const OTHER_SLOTS: usize = (2 * MAX_OTHER_IDS).next_power_of_two();
/// The bits of a hash that index [`OTHER_SLOTS`].
const OTHER_SLOT_BITS: u32 = OTHER_SLOTS.trailing_zeros();

/// The rows of every key but a classic standard identifier (extended, error, RS232, FD, the overflow row):
/// an open-addressing table of row numbers, probed linearly from a multiplicative hash of the packed key.
/// The multiplier is random per run, so a log cannot pick identifiers that collide; the table is never more
/// than half full. (A `HashMap` with SipHash cost about 340 instructions per extended frame.)
#[derive(Debug, Default)]
struct OtherRows {
    /// `(packed key, row + 1)`; row 0 = empty. Allocated at the first such key.
    slots: Vec<(u64, u32)>,
    multiplier: u64,
    len: usize,
}

impl OtherRows {
    fn len(&self) -> usize {
        self.len
    }

    /// The slot holding `key`, or the empty slot where it belongs.
    #[inline]
    fn slot(&mut self, key: u64) -> usize {
        if self.slots.is_empty() {
            self.slots = vec![(0, 0); OTHER_SLOTS];
            let mut hasher = std::collections::hash_map::RandomState::new().build_hasher();
            hasher.write_u64(key);
            self.multiplier = hasher.finish() | 1;
        }
        self.probe(key)
    }

    /// Whether `key` has a row (without allocating the table).
    fn contains(&self, key: RowKey) -> bool {
        if self.slots.is_empty() {
            return false;
        }
        matches!(self.slots.get(self.probe(key.packed())), Some(&(_, row)) if row != 0)
    }

    #[inline]
    fn probe(&self, key: u64) -> usize {
        let mut slot = (key.wrapping_mul(self.multiplier) >> (64 - OTHER_SLOT_BITS)) as usize;
        loop {
            match self.slots.get(slot) {
                Some(&(stored, row)) if row != 0 && stored != key => slot = (slot + 1) % OTHER_SLOTS,
                _ => return slot,
            }
        }
    }

    /// The row of `key`, if it has one.
    #[inline]
    fn get(&mut self, key: RowKey) -> Option<usize> {
        let slot = self.slot(key.packed());
        match self.slots.get(slot) {
            Some(&(_, row)) if row != 0 => Some(row as usize - 1),
            _ => None,
        }
    }

    /// Gives `key` (which has no row yet) the row `row`.
    fn insert(&mut self, key: RowKey, row: usize) {
        let packed = key.packed();
        let slot = self.slot(packed);
        if let Some(entry) = self.slots.get_mut(slot) {
            *entry = (packed, row as u32 + 1);
            self.len += 1;
        }
    }
}

/// When something happened: the timestamp if the input has one, else the frame's position.
#[derive(Clone, Copy, Debug, PartialEq)]
struct At {
    ts: Option<Timestamp>,
    frame: u64,
}

impl At {
    /// A partial summary's position counted from the run's start.
    fn after(self, frames_before: u64) -> Self {
        Self { frame: self.frame + frames_before, ..self }
    }
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
    fn of(frame: FrameRef<'_>) -> Self {
        match frame {
            FrameRef::Can(frame) => match frame.kind() {
                FrameKind::Error => Self::Error(frame.frame_id()),
                _ if frame.is_extended() => Self::Can(frame.frame_id()),
                FrameKind::Fd => Self::Fd(frame.frame_id()),
                _ => Self::Can(frame.frame_id()),
            },
            FrameRef::Serial(frame) => Self::Serial(frame.frame_id()),
        }
    }

    /// The key as one number, distinct for every key: the variant and the identifier's kind above its value.
    fn packed(self) -> u64 {
        let (variant, id) = match self {
            Self::Can(id) => (0, Some(id)),
            Self::Error(id) => (1, Some(id)),
            Self::Serial(id) => (2, Some(id)),
            Self::Fd(id) => (3, Some(id)),
            Self::Other => (4, None),
        };
        let (kind, value) = match id {
            Some(FrameId::Standard(value)) => (0, u32::from(value)),
            Some(FrameId::Extended(value)) => (1, value),
            Some(FrameId::Serial(value)) => (2, u32::from(value)),
            None => (3, 0),
        };
        ((variant * 4 + kind) << 32) | u64::from(value)
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
    /// `last` in nanoseconds, for the gap to the next frame.
    last_ns: u128,
    worst_gap_ns: u128,
    worst_gap_at: Option<Timestamp>,
    last_counter: Option<u8>,
    /// The first count byte: a partial summary's continuity with the frames before it is judged at the merge.
    first_counter: Option<u8>,
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
            last_ns: 0,
            worst_gap_ns: 0,
            worst_gap_at: None,
            last_counter: None,
            first_counter: None,
            counter_skips: 0,
            frames_lost: 0,
            counter_repeats: 0,
            invalid: 0,
        }
    }

    /// A frame of this row at `ts`: first and last times and the longest gap.
    #[inline]
    fn see_time(&mut self, ts: Timestamp) {
        let now = nanos(&ts);
        // `first` and `last` are only set here, together: one test for both.
        if self.last.is_none() {
            self.first = Some(ts);
        } else {
            let gap = now.saturating_sub(self.last_ns);
            if gap > self.worst_gap_ns {
                self.worst_gap_ns = gap;
                self.worst_gap_at = Some(ts);
            }
        }
        self.last = Some(ts);
        self.last_ns = now;
    }

    /// The rolling count byte of a frame of this row: a step of 1 is normal, 0 a repeat, more a skip.
    #[inline]
    fn count_byte(&mut self, count: u8) {
        if let Some(previous) = self.last_counter {
            match count.wrapping_sub(previous) {
                1 => {}
                0 => self.counter_repeats += 1,
                step => {
                    self.counter_skips += 1;
                    self.frames_lost += u64::from(step - 1);
                }
            }
        } else {
            self.first_counter = Some(count);
        }
        self.last_counter = Some(count);
    }

    /// The frames of `later` (the same row, from the next chunk) after this row's, as one pass counts them.
    fn absorb(&mut self, later: &Self) {
        self.count += later.count;
        self.name = later.name;
        self.invalid += later.invalid;
        if let Some(first) = later.first {
            // The gap across the boundary comes before the later chunk's own gaps.
            self.see_time(first);
            if later.worst_gap_ns > self.worst_gap_ns {
                self.worst_gap_ns = later.worst_gap_ns;
                self.worst_gap_at = later.worst_gap_at;
            }
            self.last = later.last;
            self.last_ns = later.last_ns;
        }
        if let Some(first) = later.first_counter {
            self.count_byte(first);
            self.counter_skips += later.counter_skips;
            self.frames_lost += later.frames_lost;
            self.counter_repeats += later.counter_repeats;
            self.last_counter = later.last_counter;
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
struct FaultSeen {
    first: Option<At>,
    last: Option<At>,
    frames: u64,
}

impl FaultSeen {
    fn absorb(&mut self, later: &Self, frames_before: u64) {
        if later.frames > 0 {
            self.first = self.first.or(later.first.map(|at| at.after(frames_before)));
            self.last = later.last.map(|at| at.after(frames_before));
            self.frames += later.frames;
        }
    }
}

/// Records `at` for every bit set in `bits`, one slot per bit (bits beyond the slots are ignored). Visits
/// only the set bits: nearly always none.
#[inline]
fn see_bits(slots: &mut [FaultSeen], bits: u16, at: At) {
    let mut bits = u32::from(bits) & ((1u32 << slots.len().min(16)) - 1);
    while bits != 0 {
        if let Some(seen) = slots.get_mut(bits.trailing_zeros() as usize) {
            seen.first.get_or_insert(at);
            seen.last = Some(at);
            seen.frames += 1;
        }
        bits &= bits - 1;
    }
}

#[derive(Clone, Copy, Debug)]
struct Extreme {
    value: i64,
    at: At,
}

fn keep_max_abs(slot: &mut Option<Extreme>, value: i64, at: At) {
    if slot.is_none_or(|best| larger_abs(value, best.value)) {
        *slot = Some(Extreme { value, at });
    }
}

/// `later`'s extreme (from the next chunk) if `better` than the one so far: a tie keeps the earlier one.
fn absorb_extreme(
    slot: &mut Option<Extreme>,
    later: Option<Extreme>,
    frames_before: u64,
    better: impl Fn(i64, i64) -> bool,
) {
    if let Some(later) = later {
        if slot.is_none_or(|best| better(later.value, best.value)) {
            *slot = Some(Extreme { value: later.value, at: later.at.after(frames_before) });
        }
    }
}

fn larger_abs(value: i64, best: i64) -> bool {
    value.abs() > best.abs()
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

    /// The odometer of the next chunk: the step across the boundary, then its own travel and resets.
    fn absorb(&mut self, later: &Self) {
        if let Some(first) = later.first {
            self.update(first);
            self.travelled_mm += later.travelled_mm;
            self.resets += later.resets;
            self.last = later.last;
        }
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
    other_index: OtherRows,
    ids: Vec<IdStats>,
    interfaces: Interfaces,
    last_iface: String,
    /// Control-mode and vehicle-state changes (the same tracker as the MCAP event channel).
    status: StatusTracker,
    events: Vec<(At, String)>,
    events_not_listed: u64,
    /// A partial summary (one chunk of `decode -j`): its first status is not a change from nothing but is
    /// kept here, to be compared with the status before the chunk when it is merged.
    partial: bool,
    first_status: Option<(SystemState, Wire, At)>,
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
    /// Response and health (issue 32): commands against feedback.
    health: crate::health::Analyzer,
}

impl Default for Summary {
    fn default() -> Self {
        Self {
            frames: 0,
            first: None,
            last: None,
            standard_index: Box::new([0; 2048]),
            other_index: OtherRows::default(),
            ids: Vec::new(),
            interfaces: Interfaces::default(),
            last_iface: String::new(),
            status: StatusTracker::default(),
            events: Vec::new(),
            events_not_listed: 0,
            partial: false,
            first_status: None,
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
            health: crate::health::Analyzer::new(),
        }
    }
}

/// Exact: every stamp the parser accepts (up to 19 digits of seconds) fits in u128 nanoseconds.
fn nanos(ts: &Timestamp) -> u128 {
    ts.as_nanos()
}

impl Summary {
    /// One event: a few direct-indexed table updates, nothing allocated or formatted (except the rare
    /// mode and vehicle-state changes listed).
    pub fn event(&mut self, event: &Event) {
        self.frame(event.ts, event.iface, event.frame, &event.decoded);
    }

    /// [`Self::event`] from its parts: the decode loops call this without building the event (moving the
    /// decoded message into one cost the parallel summary about a tenth of its time: perf annotate).
    #[inline(always)]
    pub fn frame(
        &mut self,
        ts: Option<Timestamp>,
        iface: &str,
        frame: FrameRef<'_>,
        decoded: &Result<Option<Decoded>, DecodeError>,
    ) {
        self.frames += 1;
        let at = At { ts, frame: self.frames };
        if let Some(ts) = ts {
            self.first.get_or_insert(ts);
            self.last = Some(ts);
        }
        if !same_bytes(iface.as_bytes(), self.last_iface.as_bytes()) {
            self.new_iface(iface);
        }
        let row = self.row(frame);
        let stats = &mut self.ids[row];
        stats.count += 1;
        if let Some(ts) = ts {
            stats.see_time(ts);
        }
        // A TRACER message (nearly every frame) by reference: no copy of the decoded message.
        match decoded {
            Ok(Some(decoded)) => {
                stats.name = decoded.message.name();
                self.message(row, decoded, at);
            }
            _ => self.not_a_message(row, Shape::of(frame, decoded)),
        }
    }

    /// Raw, remote, error and invalid frames.
    fn not_a_message(&mut self, row: usize, shape: Shape) {
        let stats = &mut self.ids[row];
        stats.name = shape.name();
        match shape {
            Shape::Message(_) => {} // taken by the caller
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

    /// Another interface than the last event's (rare: most logs have one).
    #[inline(never)]
    fn new_iface(&mut self, iface: &str) {
        self.last_iface.clear();
        self.last_iface.push_str(iface);
        self.interfaces.see(iface);
    }

    /// The index in `ids` of the event's row: a classic standard identifier straight from the 2048-entry
    /// table, every other key through the bounded map.
    #[inline]
    fn row(&mut self, frame: FrameRef<'_>) -> usize {
        if let FrameRef::Can(frame) = frame {
            if !frame.is_extended() && matches!(frame.kind(), FrameKind::Data | FrameKind::Remote) {
                let standard = (frame.id() & SFF_MAX) as usize;
                let index = self.standard_index[standard];
                if index != 0 {
                    return index as usize - 1;
                }
            }
        }
        self.new_or_other_row(RowKey::of(frame))
    }

    /// The row of a standard identifier seen for the first time, or of any other key.
    #[inline(never)]
    fn new_or_other_row(&mut self, key: RowKey) -> usize {
        if let Some(standard) = key.standard_index() {
            self.ids.push(IdStats::new(key));
            self.standard_index[standard] = self.ids.len() as u32;
            return self.ids.len() - 1;
        }
        if let Some(row) = self.other_index.get(key) {
            return row;
        }
        if self.other_index.len() >= MAX_OTHER_IDS {
            if let Some(row) = self.other_index.get(RowKey::Other) {
                return row;
            }
            return self.push_other_row(RowKey::Other);
        }
        self.push_other_row(key)
    }

    fn push_other_row(&mut self, key: RowKey) -> usize {
        self.ids.push(IdStats::new(key));
        self.other_index.insert(key, self.ids.len() - 1);
        self.ids.len() - 1
    }

    fn note(&mut self, at: At, text: String) {
        if self.events.len() < MAX_LISTED_EVENTS {
            self.events.push((at, text));
        } else {
            self.events_not_listed += 1;
        }
    }

    /// What a decoded message adds: its count byte (row `row`) and the values the report tracks. One match
    /// for both, so a message is dispatched once.
    #[inline]
    fn message(&mut self, row: usize, decoded: &Decoded, at: At) {
        match decoded.message {
            Message::SystemState(state) => {
                self.ids[row].count_byte(state.count);
                self.system_state(&state, decoded.wire, at);
                self.health(at, &decoded.message);
            }
            Message::MotionState(state) => {
                self.health(at, &decoded.message);
                if decoded.wire != Wire::CanV2 {
                    self.ids[row].count_byte(state.count);
                }
                keep_max_abs(&mut self.measured_linear, state.linear_mm_s.into(), at);
                keep_max_abs(&mut self.measured_angular, state.angular_mrad_s.into(), at);
            }
            Message::MotionCommand(cmd) => {
                self.health(at, &decoded.message);
                keep_max_abs(&mut self.commanded_linear, cmd.linear_mm_s.into(), at);
                keep_max_abs(&mut self.commanded_angular, cmd.angular_mrad_s.into(), at);
            }
            Message::PercentMotionCommand(cmd) => {
                self.health(at, &decoded.message);
                self.ids[row].count_byte(cmd.count);
                keep_max_abs(&mut self.commanded_linear, cmd.linear_mm_s(), at);
                // Percent commands are in 1e-5 rad/s; the table keeps mrad/s.
                keep_max_abs(&mut self.commanded_angular, cmd.angular_1e5() / 100, at);
            }
            Message::LightCommand(lights) | Message::LightState(lights) => {
                self.ids[row].count_byte(lights.count)
            }
            Message::RcState(rc) => self.ids[row].count_byte(rc.count),
            Message::MotorHighSpeed(motor) if matches!(motor.motor, 1 | 2) => {
                self.health(at, &decoded.message);
                self.motor_extremes(motor.motor, motor.rpm.into(), motor.current_deciamps.into(), at);
            }
            Message::MotorDriverState(motor) => {
                self.health(at, &decoded.message);
                self.ids[row].count_byte(motor.count);
                if matches!(motor.motor, 1 | 2) {
                    self.motor_extremes(motor.motor, motor.rpm.into(), motor.current_deciamps.into(), at);
                }
            }
            Message::MotorLowSpeed(motor) => {
                let index = usize::from(motor.motor.clamp(1, 3) - 1);
                see_bits(&mut self.driver_faults[index], motor.driver_state.into(), at);
            }
            Message::Odometry(odo) => {
                self.health(at, &decoded.message);
                self.wheels[0].update(odo.left_mm.into());
                self.wheels[1].update(odo.right_mm.into());
            }
            _ => {}
        }
    }

    /// A message the health analysis uses, at its stamp (messages without one cannot be timed).
    #[inline]
    fn health(&mut self, at: At, message: &Message) {
        if let Some(ts) = at.ts {
            self.health.observe(ts.as_micros_i64(), message);
        }
    }

    fn system_state(&mut self, state: &SystemState, wire: Wire, at: At) {
        if self.partial && self.first_status.is_none() {
            self.first_status = Some((*state, wire, at));
            let _ = self.status.control_mode(state.control_mode, wire);
            let _ = self.status.vehicle_state(state.vehicle_state);
        } else {
            self.note_mode_change(state.control_mode, wire, at);
            self.note_vehicle_change(state, at);
        }
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
    use crate::protocol::CanFrame;

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

    fn event_at<'a>(frame: &'a CanFrame, secs: u64, nanos: u32) -> Event<'a> {
        Event {
            ts: Some(Timestamp::from_numeric(secs, nanos)),
            iface: "can0",
            dir: None,
            frame: FrameRef::Can(frame),
            decoded: Ok(None),
        }
    }

    /// Classic standard identifiers find their row in the 2048-entry table; the same number as an FD or an
    /// extended frame, and error frames, get rows of their own through the map.
    #[test]
    fn each_key_gets_one_row_and_standard_ids_are_indexed_directly() {
        let classic = CanFrame::new(0x123, &[1, 2]).unwrap();
        let remote = CanFrame::new_remote(0x7FF, false, 8).unwrap();
        let fd = CanFrame::new_fd(0x123, false, 4, &[0; 12]).unwrap();
        let extended = CanFrame::new_extended(0x123, &[]).unwrap();
        let mut summary = Summary::default();
        for (frame, secs) in
            [(&classic, 1), (&fd, 1), (&classic, 2), (&extended, 2), (&remote, 3), (&classic, 5)]
        {
            summary.event(&event_at(frame, 1_700_000_000 + secs, 0));
        }
        let rows: Vec<(String, u64)> =
            summary.ids.iter().map(|row| (row.key.to_string(), row.count)).collect();
        assert_eq!(
            rows,
            [("0x123".into(), 3), ("0x123 (FD)".into(), 1), ("0x00000123".into(), 1), ("0x7FF".into(), 1)]
        );
        assert_eq!(summary.standard_index[0x123], 1);
        assert_eq!(summary.standard_index[0x7FF], 4);
        assert_eq!(summary.standard_index.iter().filter(|index| **index != 0).count(), 2);
        assert_eq!(summary.other_index.len(), 2);
        // 0x123's frames at 1, 2 and 5 s: the longest gap is 3 s, ended by the last frame.
        let row = &summary.ids[0];
        assert_eq!(row.worst_gap_ns, 3_000_000_000);
        assert_eq!(row.worst_gap_at.map(|ts| ts.secs), Some(1_700_000_005));
        assert_eq!(
            (row.first.map(|ts| ts.secs), row.last.map(|ts| ts.secs)),
            (Some(1_700_000_001), Some(1_700_000_005))
        );
        assert_eq!(row.name, "raw");
        assert_eq!(summary.ids[3].name, "remote_request");
        assert_eq!((summary.frames, summary.raw_frames), (6, 6));
    }

    #[test]
    fn a_gap_is_measured_in_nanoseconds_across_seconds_and_never_negative() {
        let mut row = IdStats::new(RowKey::Other);
        let at = |secs, nanos| Timestamp::from_numeric(secs, nanos);
        row.see_time(at(10, 900_000_000));
        row.see_time(at(11, 100_000_000)); // 0.2 s
        row.see_time(at(11, 50_000_000)); // backwards: no gap
        row.see_time(at(11, 400_000_000)); // 0.35 s after the previous frame
        assert_eq!(row.worst_gap_ns, 350_000_000);
        assert_eq!(row.worst_gap_at, Some(at(11, 400_000_000)));
        assert_eq!(row.first, Some(at(10, 900_000_000)));
        assert_eq!(row.last, Some(at(11, 400_000_000)));
    }

    #[test]
    fn count_bytes_count_repeats_skips_and_lost_frames_across_the_wrap() {
        let mut row = IdStats::new(RowKey::Other);
        for count in [254, 255, 0, 0, 3, 4, 2] {
            row.count_byte(count);
        }
        // 255 -> 0 is a normal step; 0 -> 0 a repeat; 0 -> 3 loses 2; 4 -> 2 wraps: 253 lost.
        assert_eq!((row.counter_repeats, row.counter_skips, row.frames_lost), (1, 2, 255));
        assert_eq!(row.last_counter, Some(2));
    }

    #[test]
    fn fault_bits_are_recorded_only_where_set_and_within_the_slots() {
        let at = |frame| At { ts: None, frame };
        let mut slots = [FaultSeen::default(); 8];
        see_bits(&mut slots, 0b1_1000_0101, at(1)); // bit 8 has no slot
        see_bits(&mut slots, 0b0000_0100, at(2));
        see_bits(&mut slots, 0, at(3));
        let frames: Vec<u64> = slots.iter().map(|seen| seen.frames).collect();
        assert_eq!(frames, [1, 0, 2, 0, 0, 0, 0, 1]);
        assert_eq!((slots[2].first, slots[2].last), (Some(at(1)), Some(at(2))));
        let mut wide = [FaultSeen::default(); 16];
        see_bits(&mut wide, 0x8001, at(4));
        assert_eq!((wide[0].frames, wide[15].frames, wide[1].frames), (1, 1, 0));
    }

    /// Every key packs to a number of its own (the variant, the identifier's kind and its value).
    #[test]
    fn packed_keys_are_distinct() {
        let keys = [
            RowKey::Can(FrameId::Standard(0x123)),
            RowKey::Can(FrameId::Extended(0x123)),
            RowKey::Error(FrameId::Extended(0x123)),
            RowKey::Serial(FrameId::Serial(0x123)),
            RowKey::Fd(FrameId::Standard(0x123)),
            RowKey::Fd(FrameId::Extended(0x123)),
            RowKey::Can(FrameId::Extended(0x1FFF_FFFF)),
            RowKey::Other,
        ];
        let packed: HashSet<u64> = keys.iter().map(|key| key.packed()).collect();
        assert_eq!(packed.len(), keys.len());
        assert_eq!(RowKey::Can(FrameId::Extended(0x1FFF_FFFF)).packed(), (1 << 32) | 0x1FFF_FFFF);
        assert_eq!(RowKey::Other.packed(), 19 << 32);
    }

    /// The first 4096 extended identifiers get rows of their own, found again when they repeat; every
    /// later one counts in the overflow row.
    #[test]
    fn other_keys_are_found_again_and_overflow_into_one_row() {
        let mut summary = Summary::default();
        let frames: Vec<CanFrame> =
            (0..5000u32).map(|n| CanFrame::new_extended(0x1800_0000 + n * 7, &[]).unwrap()).collect();
        for (n, frame) in frames.iter().enumerate() {
            summary.event(&event_at(frame, 1_700_000_000, n as u32));
        }
        for frame in frames.iter().take(10).chain(frames.iter().skip(4990)) {
            summary.event(&event_at(frame, 1_700_000_001, 0));
        }
        assert_eq!(summary.ids.len(), MAX_OTHER_IDS + 1);
        assert_eq!(summary.other_index.len(), MAX_OTHER_IDS + 1);
        assert_eq!(summary.ids[0].key, RowKey::Can(FrameId::Extended(0x1800_0000)));
        assert_eq!(summary.ids[4095].key, RowKey::Can(FrameId::Extended(0x1800_0000 + 4095 * 7)));
        assert_eq!(summary.ids[4096].key, RowKey::Other);
        // 0..10 repeated: two frames each; 4096..5000 and the ten repeats of the last ones: the overflow row.
        assert_eq!((summary.ids[0].count, summary.ids[9].count, summary.ids[10].count), (2, 2, 1));
        assert_eq!(summary.ids[4096].count, 904 + 10);
        assert_eq!(summary.ids.iter().map(|row| row.count).sum::<u64>(), 5020);
    }
}
