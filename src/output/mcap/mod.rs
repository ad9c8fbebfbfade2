//! MCAP output (Foxglove, PlotJuggler, ROS 2 tools): the same [`Event`]s the text, JSON and CSV writers get,
//! as JSON messages with JSON Schemas on one channel per message kind, plus every frame on `/tracer/raw`,
//! status changes as `foxglove.Log` on `/tracer/events`, and the dead-reckoned pose (`/tracer/pose`, `/tf`).
//! The container (chunks, compression, indexes) is the `mcap` crate's. docs/foxglove.md lists the channels.
//!
//! Time: a message's log and publish time is its frame's stamp in ns; a frame without a stamp takes the
//! previous log time (0 before any), and log time never decreases (`max(stamp, previous)`), while the
//! message's own `ts_ns` keeps the stamp as captured.

mod pipe;
pub mod schema;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{Seek, Write};

use mcap::records::{MessageHeader, Metadata};

use self::pipe::Pipe;
use strum::IntoEnumIterator;

use super::json::{push_frame_keys, push_message_fields, push_string};
use super::number::{push_decimal, push_int};
use super::{direction_name, Event, Shape};
use crate::protocol::message::{
    control_mode_name, vehicle_state_name, Message, MessageKind, Wire, VEHICLE_ESTOP,
};
use crate::protocol::pose::DeadReckoning;
use crate::protocol::transitions::{StatusTracker, Transition};
use crate::protocol::{Decoded, Severity};

/// How chunks are compressed (Foxglove reads all three).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Compression {
    #[default]
    Zstd,
    Lz4,
    None,
}

impl Compression {
    fn mcap(self) -> Option<mcap::Compression> {
        match self {
            Compression::Zstd => Some(mcap::Compression::Zstd),
            Compression::Lz4 => Some(mcap::Compression::Lz4),
            Compression::None => None,
        }
    }
}

/// Whether a path names an MCAP file (by its extension): `decode -o`, `monitor --log` and
/// `dashboard --record` then write MCAP.
pub fn is_mcap_path(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|extension| extension.eq_ignore_ascii_case("mcap"))
}

/// What the file's `tracerctl` metadata record says besides the protocol.
#[derive(Clone, Debug)]
pub struct Provenance {
    /// The command that wrote it: decode, monitor or dashboard.
    pub command: &'static str,
    /// Input names (files, interfaces).
    pub sources: Vec<String>,
}

/// foxglove.Log levels.
const INFO: u8 = 2;
const WARNING: u8 = 3;
const ERROR: u8 = 4;
/// Frame names of the pose.
const ODOM_FRAME: &str = "odom";
const BASE_FRAME: &str = "base_link";

/// Channel ids, looked up without hashing on the hot path.
struct Channels {
    /// By `MessageKind as usize` (the motor kinds' entries unused).
    messages: Vec<u16>,
    /// High-speed and low-speed channels by motor number, added when first seen.
    motors: [[Option<u16>; 256]; 2],
    /// Schema ids of the two motor kinds, for motors beyond the fixed ones.
    motor_schemas: [u16; 2],
    raw: u16,
    events: u16,
    pose: u16,
    tf: u16,
}

/// Writes events into an MCAP file. Call [`McapWriter::finish`] at the end: it writes the metadata, the
/// summary and the index. Dropped unfinished, the file is still finished (without the metadata record).
///
/// The calling thread formats the message bodies into batches; a writer thread of its own owns the
/// `mcap::Writer` (see [`pipe`]). A write error there is returned by the next call that hands over a batch
/// (every few thousand messages), by [`McapWriter::flush`] or by [`McapWriter::finish`].
pub struct McapWriter<W: Write + Seek + Send + 'static> {
    pipe: Pipe<W>,
    channels: Channels,
    sequences: Vec<u32>,
    text: String,
    log_time: u64,
    /// Frames written to `/tracer/raw`.
    frames: u64,
    pose: DeadReckoning,
    last_odometry_ns: Option<u64>,
    status: StatusTracker,
    provenance: Provenance,
}

impl<W: Write + Seek + Send + 'static> McapWriter<W> {
    pub fn new(out: W, compression: Compression, provenance: Provenance) -> mcap::McapResult<Self> {
        let library = format!("tracerctl {}", env!("CARGO_PKG_VERSION"));
        let mut writer = mcap::WriteOptions::new()
            .compression(compression.mcap())
            // Compressed on the writer thread (the pipe's): a zstd worker thread of the crate's own on top
            // measured slower on two cores, and zstd level 1 faster than the default 3 and no larger
            // (docs/performance.md, "MCAP output").
            .compression_threads(0)
            .compression_level(1)
            .profile("")
            .library(library)
            .create(out)?;
        let mut schema_ids = BTreeMap::new();
        let mut topic_ids = BTreeMap::new();
        for (topic, schema_name) in schema::fixed_topics() {
            let schema_id = add_schema(&mut writer, &mut schema_ids, &schema_name)?;
            let id = writer.add_channel(schema_id, &topic, schema::MESSAGE_ENCODING, &BTreeMap::new())?;
            topic_ids.insert(topic, id);
        }
        let topic = |name: &str| topic_ids.get(name).copied().unwrap_or_default();
        let mut motors = [[None; 256]; 2];
        let motor_kinds = [MessageKind::MotorHighSpeed, MessageKind::MotorLowSpeed];
        for (slot, kind) in motor_kinds.into_iter().enumerate() {
            for motor in schema::MOTORS {
                motors[slot][usize::from(motor)] = Some(topic(&schema::motor_topic(kind, motor)));
            }
        }
        let motor_schemas = motor_kinds
            .map(|kind| schema_ids.get(&schema::message_schema_name(kind)).copied().unwrap_or_default());
        let channels = Channels {
            messages: MessageKind::iter()
                .map(|kind| schema::message_topic(kind).map_or(0, |name| topic(&name)))
                .collect(),
            motors,
            motor_schemas,
            raw: topic(schema::RAW_TOPIC),
            events: topic(schema::EVENTS_TOPIC),
            pose: topic(schema::POSE_TOPIC),
            tf: topic(schema::TF_TOPIC),
        };
        Ok(Self {
            pipe: Pipe::start(writer)?,
            channels,
            sequences: vec![0; 64],
            text: String::with_capacity(256),
            log_time: 0,
            frames: 0,
            pose: DeadReckoning::default(),
            last_odometry_ns: None,
            status: StatusTracker::default(),
            provenance,
        })
    }

    /// The input names the metadata record lists (a live recording knows its interface only once started).
    pub fn set_sources(&mut self, sources: Vec<String>) {
        self.provenance.sources = sources;
    }

    /// Frames written so far (the `/tracer/raw` count).
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// One frame: on `/tracer/raw`, on its message's channel, and any status change, fault or pose it
    /// brings.
    pub fn event(&mut self, event: &Event) -> mcap::McapResult<()> {
        let stamp = event.ts.map(|ts| u64::try_from(ts.as_nanos()).unwrap_or(u64::MAX));
        self.log_time = self.log_time.max(stamp.unwrap_or(0));
        self.frames += 1;
        self.raw(event, stamp)?;
        match event.shape() {
            Shape::Message(decoded) => {
                self.message(event, &decoded)?;
                self.transitions(event, &decoded)?;
                if let Message::Odometry(odometry) = decoded.message {
                    let elapsed = match (stamp, self.last_odometry_ns) {
                        (Some(now), Some(before)) => now.saturating_sub(before) as f64 / 1e9,
                        _ => 0.0,
                    };
                    self.last_odometry_ns = stamp.or(self.last_odometry_ns);
                    self.pose.step(odometry, elapsed);
                    self.write_pose()?;
                }
            }
            Shape::Invalid(error) => {
                self.text.clear();
                let _ = write!(self.text, "invalid frame {} on {}: {error}", FrameIdText(event), event.iface);
                self.log(WARNING, event.iface)?;
            }
            Shape::ErrorFrame(error) => {
                self.text.clear();
                let _ = write!(self.text, "CAN error frame on {}:", event.iface);
                for name in error.class_names().chain(error.controller_names()) {
                    let _ = write!(self.text, " {name}");
                }
                if let Some((tx, rx)) = error.counters {
                    let _ = write!(self.text, " (tx errors {tx}, rx errors {rx})");
                }
                self.log(ERROR, event.iface)?;
            }
            Shape::Remote | Shape::Raw => {}
        }
        Ok(())
    }

    fn header(&mut self, channel_id: u16) -> MessageHeader {
        let index = usize::from(channel_id);
        if index >= self.sequences.len() {
            self.sequences.resize(index + 1, 0);
        }
        self.sequences[index] = self.sequences[index].wrapping_add(1);
        MessageHeader {
            channel_id,
            sequence: self.sequences[index],
            log_time: self.log_time,
            publish_time: self.log_time,
        }
    }

    /// Ends the body begun with [`Pipe::body`] as a message on `channel_id`.
    fn write_body(&mut self, channel_id: u16) -> mcap::McapResult<()> {
        let header = self.header(channel_id);
        self.pipe.message(header)
    }

    /// `{"ts_ns":..,"iface":..,"id":..,"data":..,"dir":..,"msg":..,"wire":..}`. `ts_ns`, `dir` and `wire`
    /// are left out when the frame has none: Foxglove's JSON Schema parser takes one type per field, no
    /// `null` (docs/foxglove.md section 1).
    fn raw(&mut self, event: &Event, stamp: Option<u64>) -> mcap::McapResult<()> {
        let out = self.pipe.body();
        out.push(b'{');
        if let Some(ns) = stamp {
            out.extend_from_slice(b"\"ts_ns\":");
            push_int(out, ns);
            out.push(b',');
        }
        push_frame_keys(out, event);
        if let Some(dir) = event.dir {
            out.extend_from_slice(b",\"dir\":\"");
            out.extend_from_slice(direction_name(dir).as_bytes());
            out.push(b'"');
        }
        out.extend_from_slice(b",\"msg\":\"");
        out.extend_from_slice(event.msg_name().as_bytes());
        out.push(b'"');
        if let Some(wire) = event.wire_name() {
            out.extend_from_slice(b",\"wire\":\"");
            out.extend_from_slice(wire.as_bytes());
            out.push(b'"');
        }
        out.push(b'}');
        self.write_body(self.channels.raw)
    }

    /// The fields at top level, plus `iface` and `wire`.
    fn message(&mut self, event: &Event, decoded: &Decoded) -> mcap::McapResult<()> {
        let channel = match decoded.message {
            Message::MotorHighSpeed(motor) => self.motor_channel(0, motor.motor)?,
            Message::MotorDriverState(motor) => self.motor_channel(0, motor.motor)?,
            Message::MotorLowSpeed(motor) => self.motor_channel(1, motor.motor)?,
            message => self.channels.messages[message.kind() as usize],
        };
        let out = self.pipe.body();
        let start = out.len();
        out.push(b'{');
        push_message_fields(out, decoded);
        if out.len() > start + 1 {
            out.push(b',');
        }
        out.extend_from_slice(b"\"iface\":");
        push_string(out, event.iface);
        out.extend_from_slice(b",\"wire\":\"");
        out.extend_from_slice(decoded.wire.as_str().as_bytes());
        out.extend_from_slice(b"\"}");
        self.write_body(channel)
    }

    /// The channel of motor `motor`'s high-speed (`slot` 0) or low-speed (1) feedback, added when first seen.
    fn motor_channel(&mut self, slot: usize, motor: u8) -> mcap::McapResult<u16> {
        if let Some(id) = self.channels.motors[slot][usize::from(motor)] {
            return Ok(id);
        }
        let kind = [MessageKind::MotorHighSpeed, MessageKind::MotorLowSpeed][slot];
        let topic = schema::motor_topic(kind, motor);
        let schema_id = self.channels.motor_schemas[slot];
        let id = self.pipe.add_channel(schema_id, topic)?;
        self.channels.motors[slot][usize::from(motor)] = Some(id);
        Ok(id)
    }

    fn transitions(&mut self, event: &Event, decoded: &Decoded) -> mcap::McapResult<()> {
        if !matches!(decoded.message, Message::SystemState(_) | Message::MotorLowSpeed(_)) {
            return Ok(());
        }
        let mut found = [None; 8];
        let mut count = 0;
        let mut more = 0u32;
        self.status.observe(decoded, |transition| {
            if count < found.len() {
                found[count] = Some(transition);
                count += 1;
            } else {
                more += 1;
            }
        });
        for transition in found.into_iter().flatten() {
            let level = describe(&mut self.text, &transition);
            self.log(level, event.iface)?;
        }
        if more > 0 {
            self.text.clear();
            let _ = write!(self.text, "{more} more status changes in the same frame");
            self.log(WARNING, event.iface)?;
        }
        Ok(())
    }

    /// A foxglove.Log of `self.text`; `line` is the frame's number on `/tracer/raw` (1-based).
    fn log(&mut self, level: u8, iface: &str) -> mcap::McapResult<()> {
        let out = self.pipe.body();
        out.extend_from_slice(b"{\"timestamp\":");
        push_time(out, self.log_time);
        out.extend_from_slice(b",\"level\":");
        push_int(out, level);
        out.extend_from_slice(b",\"message\":");
        push_string(out, &self.text);
        out.extend_from_slice(b",\"name\":\"tracerctl\",\"file\":");
        push_string(out, iface);
        out.extend_from_slice(b",\"line\":");
        push_int(out, self.frames);
        out.push(b'}');
        self.write_body(self.channels.events)
    }

    fn write_pose(&mut self) -> mcap::McapResult<()> {
        let (qx, qy, qz, qw) = self.pose.orientation();
        let (x, y) = (self.pose.x, self.pose.y);
        let out = self.pipe.body();
        out.extend_from_slice(b"{\"timestamp\":");
        push_time(out, self.log_time);
        out.extend_from_slice(b",\"frame_id\":\"");
        out.extend_from_slice(ODOM_FRAME.as_bytes());
        out.extend_from_slice(b"\",\"pose\":{\"position\":");
        push_vector(out, x, y, 0.0);
        out.extend_from_slice(b",\"orientation\":");
        push_quaternion(out, qx, qy, qz, qw);
        out.extend_from_slice(b"}}");
        self.write_body(self.channels.pose)?;
        let out = self.pipe.body();
        out.extend_from_slice(b"{\"timestamp\":");
        push_time(out, self.log_time);
        out.extend_from_slice(b",\"parent_frame_id\":\"");
        out.extend_from_slice(ODOM_FRAME.as_bytes());
        out.extend_from_slice(b"\",\"child_frame_id\":\"");
        out.extend_from_slice(BASE_FRAME.as_bytes());
        out.extend_from_slice(b"\",\"translation\":");
        push_vector(out, x, y, 0.0);
        out.extend_from_slice(b",\"rotation\":");
        push_quaternion(out, qx, qy, qz, qw);
        out.push(b'}');
        self.write_body(self.channels.tf)
    }

    /// Closes the current chunk and flushes it to the file: a reader (or a crash) then sees everything so far.
    /// Asynchronous: the writer thread flushes once it has written what came before; a failure is returned
    /// by a later call.
    pub fn flush(&mut self) -> mcap::McapResult<()> {
        self.pipe.flush()
    }

    /// Writes the `tracerctl` metadata record (with the detected `protocol`), the summary and the index.
    pub fn finish(self, protocol: &str) -> mcap::McapResult<W> {
        let sources = serde_json::to_string(&self.provenance.sources).unwrap_or_else(|_| "[]".into());
        let metadata = BTreeMap::from([
            ("version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
            ("sources".to_string(), sources),
            ("protocol".to_string(), protocol.to_string()),
            ("command".to_string(), self.provenance.command.to_string()),
        ]);
        self.pipe.finish(Metadata { name: "tracerctl".into(), metadata })
    }
}

fn add_schema<W: Write + Seek>(
    writer: &mut mcap::Writer<W>,
    ids: &mut BTreeMap<String, u16>,
    name: &str,
) -> mcap::McapResult<u16> {
    if let Some(id) = ids.get(name) {
        return Ok(*id);
    }
    let schema = schema::schema_named(name).unwrap_or_default();
    let data = serde_json::to_vec_pretty(&schema).unwrap_or_default();
    let id = writer.add_schema(name, schema::SCHEMA_ENCODING, &data)?;
    ids.insert(name.to_string(), id);
    Ok(id)
}

/// The identifier as printed, for a message text.
struct FrameIdText<'a, 'b>(&'a Event<'b>);

impl std::fmt::Display for FrameIdText<'_, '_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut id = Vec::with_capacity(12);
        self.0.push_id(&mut id);
        f.write_str(std::str::from_utf8(&id).unwrap_or("?"))
    }
}

/// A transition in words into `text`, and its level.
fn describe(text: &mut String, transition: &Transition) -> u8 {
    text.clear();
    match *transition {
        Transition::ControlMode(change) => {
            let name = |(code, wire): (u8, Wire)| {
                control_mode_name(wire, code)
                    .map_or_else(|| format!("unknown (0x{code:02X})"), str::to_string)
            };
            match change.previous {
                Some(previous) => {
                    let _ = write!(text, "control mode {} -> {}", name(previous), name(change.current));
                }
                None => {
                    let _ = write!(text, "control mode {} (first status)", name(change.current));
                }
            }
            INFO
        }
        Transition::VehicleState(change) => {
            let name = |state: u8| {
                vehicle_state_name(state).map_or_else(|| format!("unknown (0x{state:02X})"), str::to_string)
            };
            let estop = change.current == VEHICLE_ESTOP;
            let was_estop = change.previous == Some(VEHICLE_ESTOP);
            let _ = match change.previous {
                Some(previous) => {
                    write!(text, "vehicle state {} -> {}", name(previous), name(change.current))
                }
                None => write!(text, "vehicle state {} (first status)", name(change.current)),
            };
            if estop {
                text.push_str(": E-stop on");
                ERROR
            } else {
                if was_estop {
                    text.push_str(": E-stop off");
                }
                INFO
            }
        }
        Transition::BitSet { motor, info } => {
            let _ =
                write!(text, "{} set: {} ({}): {}", where_bit(motor), info.name, info.severity, info.meaning);
            match info.severity {
                Severity::Info => INFO,
                Severity::Warning | Severity::Unknown => WARNING,
                Severity::Fault | Severity::Protection => ERROR,
            }
        }
        Transition::BitCleared { motor, info } => {
            let _ = write!(text, "{} cleared: {} ({})", where_bit(motor), info.name, info.severity);
            INFO
        }
    }
}

fn where_bit(motor: Option<u8>) -> String {
    match motor {
        None => "fault".to_string(),
        Some(motor) => format!("motor {motor} driver fault"),
    }
}

/// `{"sec":S,"nsec":N}`
fn push_time(out: &mut Vec<u8>, ns: u64) {
    out.extend_from_slice(b"{\"sec\":");
    push_int(out, ns / 1_000_000_000);
    out.extend_from_slice(b",\"nsec\":");
    push_int(out, ns % 1_000_000_000);
    out.push(b'}');
}

fn push_float(out: &mut Vec<u8>, value: f64) {
    // Nine decimals (nanometres, 1e-9 of a quaternion) as an exact decimal: no float formatting on the hot
    // path, and always valid JSON (a non-finite value cannot come from finite odometers; it is written 0).
    let scaled = (value * 1e9).round();
    let raw = if scaled.is_finite() { scaled as i64 } else { 0 };
    push_decimal(out, raw, 9);
}

fn push_vector(out: &mut Vec<u8>, x: f64, y: f64, z: f64) {
    out.extend_from_slice(b"{\"x\":");
    push_float(out, x);
    out.extend_from_slice(b",\"y\":");
    push_float(out, y);
    out.extend_from_slice(b",\"z\":");
    push_float(out, z);
    out.push(b'}');
}

fn push_quaternion(out: &mut Vec<u8>, x: f64, y: f64, z: f64, w: f64) {
    out.extend_from_slice(b"{\"x\":");
    push_float(out, x);
    out.extend_from_slice(b",\"y\":");
    push_float(out, y);
    out.extend_from_slice(b",\"z\":");
    push_float(out, z);
    out.extend_from_slice(b",\"w\":");
    push_float(out, w);
    out.push(b'}');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_and_coordinates_are_exact_json_numbers() {
        let mut out = Vec::new();
        push_time(&mut out, 1_700_000_000_020_000_001);
        assert_eq!(out, b"{\"sec\":1700000000,\"nsec\":20000001}");
        out.clear();
        push_vector(&mut out, 1.0, -0.000_000_001, f64::NAN);
        assert_eq!(String::from_utf8(out).unwrap(), "{\"x\":1.0,\"y\":-0.000000001,\"z\":0.0}");
    }

    #[test]
    fn transitions_are_worded_with_their_levels() {
        use crate::protocol::transitions::Change;
        let mut text = String::new();
        let estop = Transition::VehicleState(Change { previous: Some(0), current: VEHICLE_ESTOP });
        assert_eq!(describe(&mut text, &estop), ERROR);
        assert_eq!(text, "vehicle state normal -> estop: E-stop on");
        let released = Transition::VehicleState(Change { previous: Some(VEHICLE_ESTOP), current: 0 });
        assert_eq!(describe(&mut text, &released), INFO);
        assert_eq!(text, "vehicle state estop -> normal: E-stop off");
        let info = crate::protocol::FlagTable::DriverState.info(0);
        assert_eq!(describe(&mut text, &Transition::BitCleared { motor: Some(2), info }), INFO);
        assert_eq!(text, format!("motor 2 driver fault cleared: {} ({})", info.name, info.severity));
        let mode = Transition::ControlMode(Change { previous: None, current: (0x7F, Wire::CanV2) });
        assert_eq!(describe(&mut text, &mode), INFO);
        assert_eq!(text, "control mode unknown (0x7F) (first status)");
    }
}
