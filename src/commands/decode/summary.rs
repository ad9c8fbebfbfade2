//! `decode --summary`: the report a technician reads. Memory is bounded: per-ID tables, capped event lists.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::hash::{Hash, Hasher};
use std::time::{Duration, UNIX_EPOCH};

use serde_json::{json, Value as Json};

use super::{totals_line, InputStats};
use crate::candump::{Timestamp, TimestampKind};
use crate::output::{Event, FrameRef, Shape};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ERROR_CLASSES;
use crate::protocol::faults::{FlagTable, Flags};
use crate::protocol::message::{control_mode_name, vehicle_state_name, Message, Wire};
use crate::protocol::{Decoded, FrameKind};

/// At most this many mode and vehicle-state events are listed; the rest are counted.
const MAX_LISTED_EVENTS: usize = 200;
/// Identifiers beyond this many (extended, serial, FD) share one "other" row, so memory stays bounded.
const MAX_OTHER_IDS: usize = 4096;
/// The key of that row.
const OTHER_KEY: u64 = u64::MAX;

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

#[derive(Debug, Default)]
struct IdStats {
    key: u64,
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

#[derive(Clone, Copy, Debug, Default)]
struct FaultSeen {
    first: Option<At>,
    last: Option<At>,
    frames: u64,
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
    other_index: HashMap<u64, usize>,
    ids: Vec<IdStats>,
    interfaces: Interfaces,
    last_iface: String,
    mode: Option<(u8, Wire)>,
    vehicle: Option<u8>,
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
            mode: None,
            vehicle: None,
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

/// A key per identifier: standard CAN ids as-is, extended with bit 32, error frames bit 33, serial bit 34.
fn id_key(event: &Event) -> u64 {
    match event.frame {
        FrameRef::Can(frame) => {
            let id = u64::from(frame.id());
            match frame.kind() {
                FrameKind::Error => id | 1 << 33,
                _ if frame.is_extended() => id | 1 << 32,
                FrameKind::Fd => id | 1 << 35,
                _ => id,
            }
        }
        FrameRef::Serial(frame) => u64::from(frame.id()) | 1 << 34,
    }
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
        let stats = self.id_stats(id_key(event));
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

    fn id_stats(&mut self, key: u64) -> &mut IdStats {
        let slot = if key < 2048 {
            let index = self.standard_index[key as usize];
            if index == 0 {
                self.ids.push(IdStats { key, ..IdStats::default() });
                self.standard_index[key as usize] = self.ids.len() as u32;
                self.ids.len() - 1
            } else {
                index as usize - 1
            }
        } else {
            let key = if self.other_index.len() >= MAX_OTHER_IDS && !self.other_index.contains_key(&key) {
                OTHER_KEY
            } else {
                key
            };
            match self.other_index.get(&key) {
                Some(index) => *index,
                None => {
                    self.ids.push(IdStats { key, ..IdStats::default() });
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
            Message::SystemState(state) => {
                let wire = decoded.wire;
                let mode = (state.control_mode, wire);
                if self.mode.is_some_and(|previous| previous.0 != mode.0) || self.mode.is_none() {
                    let name = |(value, wire): (u8, Wire)| mode_text(wire, value);
                    let text = match self.mode {
                        Some(previous) => format!("control mode {} -> {}", name(previous), name(mode)),
                        None => format!("control mode {} (first status)", name(mode)),
                    };
                    self.note(at, text);
                }
                self.mode = Some(mode);
                if self.vehicle != Some(state.vehicle_state) {
                    let name = vehicle_state_name(state.vehicle_state).unwrap_or("unknown");
                    let text = match self.vehicle {
                        Some(previous) => format!(
                            "vehicle state {} -> {name}{}",
                            vehicle_state_name(previous).unwrap_or("unknown"),
                            if state.is_estop() { " (E-stop pressed)" } else { "" }
                        ),
                        None => format!("vehicle state {name} (first status)"),
                    };
                    self.note(at, text);
                }
                self.vehicle = Some(state.vehicle_state);
                let table = usize::from(wire != Wire::CanV2);
                for bit in 0..16 {
                    if state.fault_code & (1 << bit) != 0 {
                        let seen = &mut self.system_faults[table][bit];
                        seen.first.get_or_insert(at);
                        seen.last = Some(at);
                        seen.frames += 1;
                    }
                }
                let volts = i64::from(state.battery_decivolts);
                if self.battery_min.is_none_or(|min| volts < min.value) {
                    self.battery_min = Some(Extreme { value: volts, at });
                }
                if self.battery_max.is_none_or(|max| volts > max.value) {
                    self.battery_max = Some(Extreme { value: volts, at });
                }
                self.battery_last = Some(Extreme { value: volts, at });
            }
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
                let index = usize::from(motor.motor - 1);
                keep_max_abs(&mut self.rpm[index], motor.rpm.into(), at);
                keep_max_abs(&mut self.current[index], motor.current_deciamps.into(), at);
            }
            Message::MotorDriverState(motor) if matches!(motor.motor, 1 | 2) => {
                let index = usize::from(motor.motor - 1);
                keep_max_abs(&mut self.rpm[index], motor.rpm.into(), at);
                keep_max_abs(&mut self.current[index], motor.current_deciamps.into(), at);
            }
            Message::MotorLowSpeed(motor) => {
                let index = usize::from(motor.motor.clamp(1, 3) - 1);
                for bit in 0..8 {
                    if motor.driver_state & (1 << bit) != 0 {
                        let seen = &mut self.driver_faults[index][bit];
                        seen.first.get_or_insert(at);
                        seen.last = Some(at);
                        seen.frames += 1;
                    }
                }
            }
            Message::Odometry(odo) => {
                self.wheels[0].update(odo.left_mm.into());
                self.wheels[1].update(odo.right_mm.into());
            }
            _ => {}
        }
    }

    /// The text report.
    pub fn report(&self, stats: &InputStats, detector: &ProtocolDetector) -> String {
        let mut out = String::new();
        let w = &mut out;
        let _ = writeln!(w, "Input");
        let _ = writeln!(w, "  {}", totals_line(stats));
        for (name, serial) in &stats.serial {
            let _ = writeln!(
                w,
                "  serial {name}: {} bytes, {} frames, {} bad checksums, {} bad length bytes, {} bad frame types, \
                 {} bytes skipped, {} sync losses",
                serial.bytes,
                serial.frames,
                serial.bad_checksum,
                serial.bad_length,
                serial.bad_type,
                serial.skipped_bytes,
                serial.sync_losses
            );
        }
        if !self.interfaces.names.is_empty() {
            let _ = write!(w, "  interfaces: {}", self.interfaces.names.join(", "));
            match self.interfaces.not_listed() {
                0 => {}
                n if self.interfaces.extra_overflow => {
                    let _ = write!(w, " and more than {n} more");
                }
                n => {
                    let _ = write!(w, " and {n} more");
                }
            }
            let _ = writeln!(w);
        }
        let _ = writeln!(w, "  protocol: {}", detector.describe());
        let _ = writeln!(w, "  time span: {}", self.span_text());

        let _ = writeln!(w, "\nFrames per ID");
        let _ = writeln!(
            w,
            "  {:<10} {:<22} {:>10} {:>9} {:>10}  lost (count-byte skips)",
            "id", "message", "frames", "rate/s", "worst gap"
        );
        let mut ids: Vec<&IdStats> = self.ids.iter().collect();
        ids.sort_by_key(|stats| stats.key);
        for stats in ids {
            let rate = match (stats.first, stats.last) {
                (Some(first), Some(last)) if stats.count > 1 && nanos(&last) > nanos(&first) => {
                    format!("{:.1}", (stats.count - 1) as f64 / ((nanos(&last) - nanos(&first)) as f64 / 1e9))
                }
                _ => "-".to_string(),
            };
            let gap = if stats.worst_gap_ns > 0 {
                format!("{:.3} s", stats.worst_gap_ns as f64 / 1e9)
            } else {
                "-".to_string()
            };
            let lost = if stats.last_counter.is_some() {
                let mut text = format!("{} in {} skips", stats.frames_lost, stats.counter_skips);
                if stats.counter_repeats > 0 {
                    let _ = write!(text, ", {} repeated", stats.counter_repeats);
                }
                text
            } else {
                "-".to_string()
            };
            let mut lost = lost;
            if stats.invalid > 0 {
                let _ = write!(lost, " ({} invalid)", stats.invalid);
            }
            let _ = writeln!(
                w,
                "  {:<10} {:<22} {:>10} {:>9} {:>10}  {}",
                key_text(stats.key),
                stats.name,
                stats.count,
                rate,
                gap,
                lost
            );
        }

        let _ = writeln!(w, "\nControl mode and vehicle state");
        if self.events.is_empty() {
            let _ = writeln!(w, "  no system-state frames");
        }
        for (at, text) in &self.events {
            let _ = writeln!(w, "  {}  {text}", at_text(at));
        }
        if self.events_not_listed > 0 {
            let _ = writeln!(w, "  ... and {} more changes not listed", self.events_not_listed);
        }

        let _ = writeln!(w, "\nFaults (first and last seen)");
        let mut any_fault = false;
        for (table_index, table) in [FlagTable::SystemV2, FlagTable::SystemV1Serial].into_iter().enumerate() {
            for (bit, seen) in self.system_faults[table_index].iter().enumerate() {
                any_fault |= fault_line(w, "system", table, bit as u32, seen);
            }
        }
        for (motor, bits) in self.driver_faults.iter().enumerate() {
            let label = ["motor 1", "motor 2", "motor ?"][motor];
            for (bit, seen) in bits.iter().enumerate() {
                any_fault |= fault_line(w, label, FlagTable::DriverState, bit as u32, seen);
            }
        }
        if !any_fault {
            let _ = writeln!(w, "  none");
        }

        let _ = writeln!(w, "\nBattery");
        match (self.battery_min, self.battery_max, self.battery_last) {
            (Some(min), Some(max), Some(last)) => {
                let _ = writeln!(w, "  min {} at {}", volts(min.value), at_text(&min.at));
                let _ = writeln!(w, "  max {} at {}", volts(max.value), at_text(&max.at));
                let _ = writeln!(w, "  last {} at {}", volts(last.value), at_text(&last.at));
            }
            _ => {
                let _ = writeln!(w, "  no system-state frames");
            }
        }

        let _ = writeln!(w, "\nOdometry");
        for (name, wheel) in ["left", "right"].iter().zip(&self.wheels) {
            match (wheel.first, wheel.last) {
                (Some(first), Some(last)) => {
                    let _ = write!(
                        w,
                        "  {name:<5} travelled {:.3} m, net {:+.3} m (odometer {:.3} -> {:.3} m)",
                        wheel.travelled_mm as f64 / 1000.0,
                        (last - first) as f64 / 1000.0,
                        first as f64 / 1000.0,
                        last as f64 / 1000.0
                    );
                    if wheel.resets > 0 {
                        let _ = write!(w, ", {} odometer jumps ignored", wheel.resets);
                    }
                    let _ = writeln!(w);
                }
                _ => {
                    let _ = writeln!(w, "  {name:<5} no odometry frames");
                }
            }
        }

        let _ = writeln!(w, "\nTop speeds");
        let speed = |extreme: &Option<Extreme>, unit: &str| match extreme {
            Some(e) => format!("{:+.3} {unit} at {}", e.value as f64 / 1000.0, at_text(&e.at)),
            None => "-".to_string(),
        };
        let _ = writeln!(w, "  measured linear   {}", speed(&self.measured_linear, "m/s"));
        let _ = writeln!(w, "  measured angular  {}", speed(&self.measured_angular, "rad/s"));
        let _ = writeln!(w, "  commanded linear  {}", speed(&self.commanded_linear, "m/s"));
        let _ = writeln!(w, "  commanded angular {}", speed(&self.commanded_angular, "rad/s"));
        for motor in 0..2 {
            if let (Some(rpm), Some(current)) = (self.rpm[motor], self.current[motor]) {
                let _ = writeln!(
                    w,
                    "  motor {}           {:+} rpm at {}; current {:.1} A at {}",
                    motor + 1,
                    rpm.value,
                    at_text(&rpm.at),
                    current.value as f64 / 10.0,
                    at_text(&current.at)
                );
            }
        }

        let errors: Vec<String> = ERROR_CLASSES
            .iter()
            .zip(self.error_classes)
            .filter(|(_, count)| *count > 0)
            .map(|((_, name), count)| format!("{name} x{count}"))
            .collect();
        if !errors.is_empty() || stats.candump_dropped > 0 {
            let _ = writeln!(w, "\nBus errors");
            if !errors.is_empty() {
                let _ = writeln!(w, "  error frames: {}", errors.join(", "));
            }
            if stats.candump_dropped > 0 {
                let _ =
                    writeln!(w, "  candump reported {} frames dropped by the socket", stats.candump_dropped);
            }
        }

        let _ = writeln!(w, "\nRejected input");
        if stats.rejected.rejected.is_empty() {
            let _ = writeln!(w, "  none");
        }
        for rejection in &stats.rejected.rejected {
            let _ = writeln!(w, "  {:>8}  {}", rejection.count, rejection.describe_after_count());
        }
        if stats.skipped.total() > 0 {
            let _ = writeln!(w, "  skipped lines: {}", stats.skipped.describe());
        }
        out
    }

    /// The same report as JSON.
    pub fn to_json(&self, stats: &InputStats, detector: &ProtocolDetector) -> Json {
        let ts = |ts: Option<Timestamp>| ts.map(|t| exact_seconds(&t));
        let at = |at: &At| json!({ "ts": ts(at.ts), "frame": at.frame });
        let mut ids: Vec<&IdStats> = self.ids.iter().collect();
        ids.sort_by_key(|stats| stats.key);
        let ids: Vec<Json> = ids
            .iter()
            .map(|s| {
                json!({
                    "id": key_text(s.key), "msg": s.name, "frames": s.count,
                    "first": ts(s.first), "last": ts(s.last),
                    "worst_gap": (s.worst_gap_ns > 0).then(|| s.worst_gap_ns as f64 / 1e9),
                    "worst_gap_at": ts(s.worst_gap_at),
                    "frames_lost": s.last_counter.map(|_| s.frames_lost),
                    "count_skips": s.last_counter.map(|_| s.counter_skips),
                    "count_repeats": s.last_counter.map(|_| s.counter_repeats),
                    "invalid": s.invalid,
                })
            })
            .collect();
        let mut faults = Vec::new();
        for (table_index, table) in [FlagTable::SystemV2, FlagTable::SystemV1Serial].into_iter().enumerate() {
            for (bit, seen) in self.system_faults[table_index].iter().enumerate() {
                if let (Some(first), Some(last)) = (seen.first, seen.last) {
                    let info = table.info(bit as u32);
                    faults.push(json!({"source": "system", "name": info.name, "severity": info.severity.as_str(),
                        "action": info.action, "frames": seen.frames, "first": at(&first), "last": at(&last)}));
                }
            }
        }
        for (motor, bits) in self.driver_faults.iter().enumerate() {
            for (bit, seen) in bits.iter().enumerate() {
                if let (Some(first), Some(last)) = (seen.first, seen.last) {
                    let info = FlagTable::DriverState.info(bit as u32);
                    faults.push(json!({"source": format!("motor{}", motor + 1), "name": info.name,
                        "severity": info.severity.as_str(), "action": info.action, "frames": seen.frames,
                        "first": at(&first), "last": at(&last)}));
                }
            }
        }
        let extreme = |e: &Option<Extreme>, scale: f64| {
            e.map(|e| json!({"value": e.value as f64 / scale, "at": at(&e.at)}))
        };
        json!({
            "lines": stats.lines,
            "frames": stats.frames,
            "decoded_lines": stats.decoded_lines,
            "rejected_lines": stats.rejected_lines,
            "skipped": {"blank": stats.skipped.blank, "comment": stats.skipped.comment,
                "error_text": stats.skipped.error_text, "can_xl": stats.skipped.can_xl, "dropcount": stats.skipped.dropcount},
            "rejected": stats.rejected.rejected.iter().map(|r| {
                let mut object = json!({"reason": r.reason, "count": r.count, "first_at": r.first_at});
                if let Some(longest) = r.longest {
                    object["longest"] = json!(longest);
                }
                object
            }).collect::<Vec<_>>(),
            "invalid_frames": stats.invalid_frames,
            "candump_dropped": stats.candump_dropped,
            "protocol": detector.describe(),
            "interfaces": self.interfaces.names,
            "interfaces_not_listed": self.interfaces.not_listed(),
            "first": ts(self.first),
            "last": ts(self.last),
            "ids": ids,
            "events": self.events.iter().map(|(a, text)| json!({"at": at(a), "event": text})).collect::<Vec<_>>(),
            "events_not_listed": self.events_not_listed,
            "faults": faults,
            "battery": {"min": extreme(&self.battery_min, 10.0), "max": extreme(&self.battery_max, 10.0), "last": extreme(&self.battery_last, 10.0)},
            "odometry": self.wheels.iter().map(|w| json!({"travelled": w.travelled_mm as f64 / 1000.0,
                "net": w.first.zip(w.last).map(|(f, l)| (l - f) as f64 / 1000.0), "resets": w.resets})).collect::<Vec<_>>(),
            "top_speeds": {"measured_linear": extreme(&self.measured_linear, 1000.0), "measured_angular": extreme(&self.measured_angular, 1000.0),
                "commanded_linear": extreme(&self.commanded_linear, 1000.0), "commanded_angular": extreme(&self.commanded_angular, 1000.0)},
            "motors": (0..2).map(|m| json!({"motor": m + 1, "rpm": extreme(&self.rpm[m], 1.0), "current": extreme(&self.current[m], 10.0)})).collect::<Vec<_>>(),
            "error_frames": ERROR_CLASSES.iter().zip(self.error_classes).filter(|(_, n)| *n > 0).map(|((_, name), n)| json!({"class": name, "frames": n})).collect::<Vec<_>>(),
            "serial": stats.serial.iter().map(|(name, s)| json!({"input": name, "bytes": s.bytes, "frames": s.frames,
                "bad_checksum": s.bad_checksum, "bad_length": s.bad_length, "bad_type": s.bad_type,
                "skipped_bytes": s.skipped_bytes, "sync_losses": s.sync_losses})).collect::<Vec<_>>(),
        })
    }

    fn span_text(&self) -> String {
        match (self.first, self.last) {
            (Some(first), Some(last)) => {
                let length = nanos(&last).saturating_sub(nanos(&first)) as f64 / 1e9;
                format!("{} .. {} ({length:.3} s)", ts_text(&first), ts_text(&last))
            }
            _ => "no timestamps".to_string(),
        }
    }
}

fn fault_line(out: &mut String, source: &str, table: FlagTable, bit: u32, seen: &FaultSeen) -> bool {
    let (Some(first), Some(last)) = (seen.first, seen.last) else { return false };
    let info = Flags::new(table, 1 << bit).iter().next().unwrap_or_else(|| table.info(bit));
    let _ = writeln!(
        out,
        "  {source:<8} {} [{}] in {} frames, first {}, last {}\n           {}: {}",
        info.name,
        info.severity,
        seen.frames,
        at_text(&first),
        at_text(&last),
        info.meaning,
        info.action
    );
    true
}

/// Seconds as the nearest f64 to the exact decimal, so JSON shows `0.3`, not `0.30000000000000004`.
fn exact_seconds(ts: &Timestamp) -> f64 {
    let text = if ts.nanos % 1000 == 0 {
        format!("{}.{:06}", ts.secs, ts.nanos / 1000)
    } else {
        format!("{}.{:09}", ts.secs, ts.nanos)
    };
    text.parse().unwrap_or_else(|_| ts.as_secs_f64())
}

fn volts(decivolts: i64) -> String {
    format!("{:.1} V", decivolts as f64 / 10.0)
}

fn mode_text(wire: Wire, value: u8) -> String {
    control_mode_name(wire, value).map_or_else(|| format!("unknown (0x{value:02X})"), str::to_string)
}

fn key_text(key: u64) -> String {
    let id = key & 0xFFFF_FFFF;
    if key == OTHER_KEY {
        format!("other ids (beyond {MAX_OTHER_IDS})")
    } else if key & 1 << 34 != 0 {
        format!("0x{id:04X}")
    } else if key & 1 << 33 != 0 {
        format!("0x{:08X}", id | 0x2000_0000)
    } else if key & 1 << 32 != 0 {
        format!("0x{id:08X}")
    } else if key & 1 << 35 != 0 {
        format!("0x{id:03X} (FD)")
    } else {
        format!("0x{id:03X}")
    }
}

/// The first second of the year 10000, which RFC 3339 (four-digit years) cannot show.
const YEAR_10000_SECS: u64 = 253_402_300_800;

/// Absolute stamps as UTC date-time, relative ones as seconds since the start of the capture. A stamp
/// beyond the year 9999 (a corrupted line) is shown as the number of seconds it holds.
fn ts_text(ts: &Timestamp) -> String {
    match ts.kind {
        TimestampKind::Absolute if ts.secs < YEAR_10000_SECS => {
            let time = UNIX_EPOCH + Duration::new(ts.secs, ts.nanos);
            let mut text = String::new();
            match write!(text, "{}", humantime::format_rfc3339_micros(time)) {
                Ok(()) => text,
                Err(_) => seconds_text(ts),
            }
        }
        TimestampKind::Absolute => seconds_text(ts),
        TimestampKind::Relative => format!("+{}.{:06} s", ts.secs, ts.nanos / 1000),
    }
}

fn seconds_text(ts: &Timestamp) -> String {
    format!("{}.{:06} s", ts.secs, ts.nanos / 1000)
}

fn at_text(at: &At) -> String {
    match &at.ts {
        Some(ts) => ts_text(ts),
        None => format!("frame #{}", at.frame),
    }
}
