//! Invariant checks for the fuzz targets: each takes arbitrary bytes and panics when an invariant fails.
//!
//! Public for the fuzz crate (`fuzz/`, coverage-guided with cargo-afl) and for the main crate's test that
//! runs every committed seed through its check (`tests/integration/fuzz.rs`): one copy of the checks, so
//! the seeds are replayed by every `cargo test` without afl, and an API change breaks the main build.
//! Not part of the tool's interface.

use std::io::{self, Read};

use crate::candump::{
    self, Line, LineParser, LineReader, LogFormat, RawLine, TextFormat, Timestamp, TimestampKind,
};
use crate::commands::decode::summary::Summary;
use crate::commands::decode::InputStats;
use crate::commands::send_raw;
use crate::link::LinkFrame;
use crate::output::{Event, FrameRef};
use crate::protocol::can::{self, v1_checksum};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::frame::FD_LENGTHS;
use crate::protocol::id;
use crate::protocol::serial::{self, SerialFrame, StreamDecoder, StreamEvent, StreamStats, FRAME_SIZE};
use crate::protocol::{CanFrame, Decoded, FrameKind, ProtocolHint, Wire};

/// A fuzz target: its name (the directory of its seeds, the binary in `fuzz/`) and its check.
pub struct Target {
    pub name: &'static str,
    pub check: fn(&[u8]),
}

/// Every target, in the order the smoke run takes them.
pub const TARGETS: &[Target] = &[
    Target { name: "candump_line", check: candump_line },
    Target { name: "candump_reader", check: candump_reader },
    Target { name: "serial_stream", check: serial_stream },
    Target { name: "can_decode", check: can_decode },
    Target { name: "summary", check: summary },
    Target { name: "send_raw_plan", check: send_raw_plan },
];

const HINTS: [ProtocolHint; 3] = [ProtocolHint::Auto, ProtocolHint::V1, ProtocolHint::V2];

/// The input as one candump line, under both parser modes. An error names a column within the line; a
/// frame written back with the candump writer parses to the same frame, interface, direction and stamp
/// (to the microsecond the log format keeps).
pub fn candump_line(data: &[u8]) {
    for mut parser in [LineParser::new(), LineParser::new().with_delta_timestamps()] {
        match parser.parse(data) {
            Err(error) => assert!(
                (1..=data.len() + 1).contains(&error.column),
                "column {} outside a line of {} bytes: {error}",
                error.column,
                data.len()
            ),
            Ok(Line::Frame(record)) => {
                let mut written = Vec::new();
                candump::write_log_record(&mut written, &record);
                assert_eq!(written.pop(), Some(b'\n'));
                let mut reparser = LineParser::new();
                let again = reparser.parse(&written);
                let Ok(Line::Frame(again)) = again else {
                    panic!(
                        "{:?} written back as {:?} parses as {again:?}",
                        record,
                        String::from_utf8_lossy(&written)
                    )
                };
                assert_eq!(again.frame, record.frame, "frame of {:?}", String::from_utf8_lossy(&written));
                assert_eq!(again.iface, record.iface);
                assert_eq!(again.dir, record.dir);
                let expected = record.ts.map(|ts| {
                    let nanos = ts.nanos / 1_000 * 1_000;
                    let kind = match ts.secs < candump::RELATIVE_LIMIT_SECS {
                        true => TimestampKind::Relative,
                        false => TimestampKind::Absolute,
                    };
                    Timestamp { secs: ts.secs, nanos, kind }
                });
                assert_eq!(again.ts, expected, "stamp of {:?}", String::from_utf8_lossy(&written));
            }
            Ok(_) => {}
        }
    }
    in_place_line(data);
    // The other dialects `decode` and `--replay` read: no panic, and errors inside the line.
    let trc = [10, 11, 12, 13, 20, 21].map(|version| TextFormat::PeakTrc { version });
    for text in [TextFormat::VectorAsc].into_iter().chain(trc) {
        let mut parser = LineParser::for_format(LogFormat { text, compression: None });
        if let Err(error) = parser.parse(data) {
            assert!(
                (1..=data.len() + 1).contains(&error.column),
                "{}: column {} outside a line of {} bytes: {error}",
                text.name(),
                error.column,
                data.len()
            );
        }
    }
}

/// The input as a buffer of lines for the in-place parser of `decode -j`: it takes the first line only
/// where that line ends (at the first `\n`), within the line limit, and reads it as `parse` reads the line
/// alone.
fn in_place_line(data: &[u8]) {
    let end = memchr::memchr(b'\n', data).unwrap_or(data.len());
    let mut alone = LineParser::new();
    let expected = match alone.parse(&data[..end]) {
        Ok(Line::Frame(record)) if end <= candump::DEFAULT_MAX_LINE_LEN => Some(record),
        _ => None,
    };
    let mut in_place = LineParser::new();
    if let Some((record, length)) = in_place.parse_log_line_at(data) {
        assert_eq!(length, end, "the line ends at its newline");
        assert_eq!(Some(record.to_record()), expected, "read as the line alone");
    }
}

/// A reader that hands out the input in chunks of fuzzer-chosen sizes; a size of 0 is an
/// `Interrupted` error, which the line reader must retry (the retry then gets at least one byte).
struct ChunkedReader<'a> {
    data: &'a [u8],
    sizes: &'a [u8],
    next: usize,
    interrupted: bool,
}

impl<'a> ChunkedReader<'a> {
    fn new(data: &'a [u8], sizes: &'a [u8]) -> Self {
        Self { data, sizes, next: 0, interrupted: false }
    }
}

impl Read for ChunkedReader<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let size = match self.sizes {
            [] => usize::MAX,
            sizes => usize::from(sizes[self.next % sizes.len()]),
        };
        self.next = self.next.wrapping_add(1);
        if size == 0 && !self.interrupted && !self.data.is_empty() {
            self.interrupted = true;
            return Err(io::ErrorKind::Interrupted.into());
        }
        self.interrupted = false;
        let take = size.max(1).min(buf.len()).min(self.data.len());
        buf[..take].copy_from_slice(&self.data[..take]);
        self.data = &self.data[take..];
        Ok(take)
    }
}

/// Every line of `reader`, as (number, text or over-long length).
fn read_lines(mut reader: LineReader<impl Read>) -> Vec<(u64, Result<Vec<u8>, usize>)> {
    let mut lines = Vec::new();
    while let Some(line) = reader.next_line().expect("reading from memory cannot fail") {
        lines.push(match line {
            RawLine::Line { number, text } => (number, Ok(text.to_vec())),
            RawLine::TooLong { number, len } => (number, Err(len)),
        });
    }
    lines
}

/// Input: `capacity, max_line_len, n, n chunk sizes, text`. The line reader gives the same lines (the
/// input split at `\n`, a last line without `\n` included, over-long ones reported with their length)
/// whatever its buffer capacity and the sizes of the reads; line numbers are consecutive from 1; line
/// lengths plus newlines add up to the input's length.
pub fn candump_reader(data: &[u8]) {
    let (capacity, max_len, sizes, text) = match data {
        [capacity, max_len, n, rest @ ..] => {
            let n = usize::from(*n % 8).min(rest.len());
            (usize::from(*capacity), usize::from(*max_len) * 4, &rest[..n], &rest[n..])
        }
        _ => (1, 0, &[][..], data),
    };
    let mut expected: Vec<&[u8]> = text.split(|&b| b == b'\n').collect();
    if text.is_empty() || text.ends_with(b"\n") {
        expected.pop();
    }
    let chunked = ChunkedReader::new(text, sizes);
    let mut reader = LineReader::with_capacity(capacity, chunked).with_max_line_len(max_len);
    let mut lines = Vec::new();
    let mut accounted = 0usize;
    while let Some(line) = reader.next_line().expect("the chunked reader only interrupts") {
        let (number, len) = match line {
            RawLine::Line { number, text } => {
                assert!(
                    text.len() <= max_len,
                    "line {number} of {} bytes above the limit {max_len}",
                    text.len()
                );
                (number, text.len())
            }
            RawLine::TooLong { number, len } => {
                assert!(len > max_len, "line {number} of {len} bytes reported too long (limit {max_len})");
                (number, len)
            }
        };
        assert_eq!(number, lines.len() as u64 + 1, "line numbers are consecutive");
        lines.push(len);
        accounted += len + 1;
    }
    if !text.is_empty() && !text.ends_with(b"\n") {
        accounted -= 1; // the last line has no newline
    }
    assert_eq!(accounted, text.len(), "line lengths and newlines add up to the input");
    assert_eq!(reader.bytes_read(), text.len() as u64);
    let expected_lens: Vec<usize> = expected.iter().map(|line| line.len()).collect();
    assert_eq!(lines, expected_lens);

    // The same lines, with the same texts, as one read into a large buffer.
    let chunked = read_lines(
        LineReader::with_capacity(capacity, ChunkedReader::new(text, sizes)).with_max_line_len(max_len),
    );
    let reference = read_lines(LineReader::new(text).with_max_line_len(max_len));
    assert_eq!(chunked, reference, "lines depend on buffer capacity {capacity} and read sizes {sizes:?}");
    for ((_, line), text) in reference.iter().zip(&expected) {
        if let Ok(line) = line {
            assert_eq!(line.as_slice(), *text);
        }
    }
}

/// Feeds `data` split at the given lengths (cycled) and finishes.
fn stream(data: &[u8], splits: &[usize]) -> (Vec<StreamEvent>, StreamStats) {
    let mut decoder = StreamDecoder::new();
    let mut events = Vec::new();
    let mut rest = data;
    let mut turn = 0;
    while !rest.is_empty() {
        let size = splits.get(turn % splits.len().max(1)).copied().unwrap_or(rest.len()).clamp(1, rest.len());
        decoder.feed(&rest[..size], |event| events.push(event));
        rest = &rest[size..];
        turn += 1;
    }
    (events, decoder.finish())
}

/// Input: `split, stream bytes`. Byte accounting (`bytes = frames * 13 + skipped_bytes`, `bytes` = the
/// input), every frame event is the 13 bytes at its offset, in order without overlap, the counters agree
/// with the events, and the events and counters are the same for one feed, byte-by-byte feeds and
/// fuzzer-chosen splits. Every decoded frame re-encodes to a frame that decodes to the same message.
pub fn serial_stream(data: &[u8]) {
    let (split, bytes) = match data {
        [split, rest @ ..] => (usize::from(*split), rest),
        [] => (1, data),
    };
    let (events, stats) = stream(bytes, &[]);
    assert_eq!(stats.bytes, bytes.len() as u64);
    assert_eq!(stats.bytes, stats.frames * FRAME_SIZE as u64 + stats.skipped_bytes, "{stats:?}");
    let mut frames = 0;
    let mut bad_checksums = 0;
    let mut next_free = 0u64;
    for event in &events {
        match *event {
            StreamEvent::Frame { offset, frame } => {
                assert!(offset >= next_free, "frame at {offset} overlaps the one before");
                let at = usize::try_from(offset).expect("offset within the input");
                assert_eq!(bytes.get(at..at + FRAME_SIZE), Some(&frame.to_bytes()[..]));
                next_free = offset + FRAME_SIZE as u64;
                frames += 1;
                if let Some(decoded) = serial::decode(&frame) {
                    let again = serial::encode(&decoded.message, frame.frame_id)
                        .expect("decoded serial messages encode");
                    assert_eq!(serial::decode(&again), Some(decoded), "{frame:?}");
                }
            }
            StreamEvent::BadChecksum { offset, computed, found } => {
                assert!(offset + FRAME_SIZE as u64 <= stats.bytes);
                assert_ne!(computed, found);
                bad_checksums += 1;
            }
        }
    }
    assert_eq!((stats.frames, stats.bad_checksum), (frames, bad_checksums), "{stats:?}");
    assert!(stats.sync_losses <= stats.frames, "{stats:?}");
    for splits in [&[1][..], &[split % 29 + 1, split % 7 + 1, 13][..]] {
        let chunked = stream(bytes, splits);
        assert_eq!(chunked, (events.clone(), stats), "split as {splits:?}");
    }
}

/// The TRACER identifiers, V2 and V1, so that most fuzzed frames mean something.
const TRACER_IDS: [u32; 22] = [
    0x111, 0x121, 0x211, 0x221, 0x231, 0x241, 0x251, 0x252, 0x261, 0x262, 0x311, 0x411, 0x41A, 0x421, 0x441,
    0x151, 0x130, 0x131, 0x140, 0x141, 0x201, 0x202,
];

/// Takes `n` bytes from the front (zero-padded when the input runs out).
fn take<const N: usize>(bytes: &mut &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    let n = N.min(bytes.len());
    out[..n].copy_from_slice(&bytes[..n]);
    *bytes = &bytes[n..];
    out
}

/// One CAN frame of any kind from the front of the input: `kind, id..., len, data...`. Mostly standard
/// data frames with TRACER identifiers; `None` when the bytes do not make a valid frame.
fn take_frame(bytes: &mut &[u8]) -> Option<CanFrame> {
    let [kind] = take::<1>(bytes);
    let id = match kind & 0x08 {
        0 => TRACER_IDS[usize::from(take::<1>(bytes)[0]) % TRACER_IDS.len()],
        _ => u32::from_be_bytes(take::<4>(bytes)),
    };
    let [len] = take::<1>(bytes);
    let frame = match kind & 0x07 {
        0..=3 => {
            let data = take::<8>(bytes);
            CanFrame::new(id, &data[..usize::from(len % 9)])
        }
        4 => {
            let data = take::<8>(bytes);
            CanFrame::new_extended(id, &data[..usize::from(len % 9)])
        }
        5 => CanFrame::new_remote(id, kind & 0x10 != 0, len % 9),
        6 => {
            let data = take::<8>(bytes);
            CanFrame::new_error(id, &data[..usize::from(len % 9)])
        }
        _ => {
            let data = take::<64>(bytes);
            CanFrame::new_fd(
                id,
                kind & 0x10 != 0,
                kind >> 5,
                &data[..usize::from(FD_LENGTHS[usize::from(len % 16)])],
            )
        }
    };
    let frame = frame.ok()?;
    match kind & 0x80 != 0 && frame.len() == 8 {
        true => frame.with_raw_dlc(9 + len % 7).ok(),
        false => Some(frame),
    }
}

/// The command frames the tool can also encode: identifier, encoded length, which bytes carry the
/// message (the rest are reserved and encode as 0), whether it is V1 (count in byte 6, checksum in 7).
const COMMANDS: [(u32, usize, u8, bool); 7] = [
    (0x111, 8, 0b0000_1111, false),
    (0x121, 8, 0b1001_1111, false),
    (0x421, 1, 0b0000_0001, false),
    (0x441, 1, 0b0000_0001, false),
    (0x411, 1, 0b0000_0000, false),
    (0x130, 8, 0b0101_1111, true),
    (0x140, 8, 0b0101_1111, true),
];

/// The canonical form of a command frame: its meaningful bytes kept, reserved ones as the encoder writes
/// them, the V1 checksum recomputed.
fn canonical_command(frame: &CanFrame) -> Option<CanFrame> {
    let &(id, len, meaningful, v1) = COMMANDS.iter().find(|command| command.0 == frame.id())?;
    if !frame.is_standard_data() || frame.raw_dlc().is_some() {
        return None;
    }
    let mut data = [0u8; 8];
    for (at, byte) in frame.data().iter().enumerate().take(len) {
        if meaningful & (1 << at) != 0 {
            data[at] = *byte;
        }
    }
    if id == 0x411 {
        data[0] = 0x01; // the version request the tool sends
    }
    if v1 {
        data[7] = v1_checksum(id, &data);
    }
    CanFrame::new(id, &data[..len]).ok()
}

/// Input: one frame (see `take_frame`). Decoding under every hint never panics; a decoded message the
/// tool can encode re-encodes to a frame that decodes to the same message; a command frame in its
/// canonical form (reserved bytes as sent) decodes and re-encodes byte for byte: encode(decode(x)) == x.
pub fn can_decode(data: &[u8]) {
    let mut bytes = data;
    let Some(frame) = take_frame(&mut bytes) else { return };
    for hint in HINTS {
        let decoded = can::decode(&frame, hint);
        check_reencodes(&decoded);
        if !frame.is_standard_data() {
            assert_eq!(decoded, Ok(None), "{frame:?} is not a TRACER message");
        }
    }
    if let Some(canonical) = canonical_command(&frame) {
        for hint in HINTS {
            match can::decode(&canonical, hint) {
                Ok(Some(decoded)) => {
                    assert_eq!(can::encode(&decoded), Ok(canonical), "{canonical:?} decoded as {decoded:?}")
                }
                // V1 identifiers under the V2 hint are not TRACER messages; nothing else may fail.
                Ok(None) if hint == ProtocolHint::V2 && can::is_v1_only_id(canonical.id()) => {}
                other => panic!("{canonical:?} under {hint:?}: {other:?}"),
            }
        }
    }
}

/// A decoded message with an encoding on its wire comes back from that encoding unchanged.
fn check_reencodes(decoded: &Result<Option<Decoded>, can::DecodeError>) {
    let Ok(Some(decoded)) = decoded else { return };
    let Ok(encoded) = can::encode(decoded) else { return };
    let hint = match decoded.wire {
        Wire::CanV1 => ProtocolHint::V1,
        _ => ProtocolHint::V2,
    };
    assert_eq!(can::decode(&encoded, hint), Ok(Some(*decoded)), "re-encoded as {encoded:?}");
}

/// A timestamp from the front of the input: none, small relative, a 2023 wall clock, or any value.
fn take_stamp(selector: u8, bytes: &mut &[u8]) -> Option<Timestamp> {
    let nanos = u32::from_be_bytes(take::<4>(bytes)) % 1_000_000_000;
    let (secs, kind) = match selector & 0x03 {
        0 => return None,
        1 => (u64::from(u16::from_be_bytes(take::<2>(bytes))), TimestampKind::Relative),
        2 => (1_700_000_000 + u64::from(u16::from_be_bytes(take::<2>(bytes))), TimestampKind::Absolute),
        _ => (u64::from_be_bytes(take::<8>(bytes)), TimestampKind::Absolute),
    };
    Some(Timestamp { secs, nanos, kind })
}

const IFACES: [&str; 4] = ["can0", "can1", "vcan0", "slcan-usb0"];

/// Input: records of `selector, stamp..., frame...` (a CAN frame, or with bit 7 of the selector a
/// 12-byte RS232 frame whose checksum is filled in). The summary takes every event; its text report and
/// JSON are produced, the JSON serialises and parses back to the same value, and its frame counts add up
/// to the events fed.
pub fn summary(data: &[u8]) {
    let mut summary = Summary::default();
    let mut detector = ProtocolDetector::default();
    let mut stats = InputStats::default();
    let mut bytes = data;
    let mut serial_bytes = 0;
    while !bytes.is_empty() {
        let [selector] = take::<1>(&mut bytes);
        let ts = take_stamp(selector, &mut bytes);
        let iface = IFACES[usize::from(selector >> 2) % IFACES.len()];
        let hint = HINTS[usize::from(selector >> 4) % HINTS.len()];
        stats.lines += 1;
        if selector & 0x80 != 0 {
            let mut raw = [0u8; FRAME_SIZE];
            raw[..12].copy_from_slice(&take::<12>(&mut bytes));
            raw[..3].copy_from_slice(&[serial::SOF1, serial::SOF2, serial::FRAME_LEN_BYTE]);
            raw[3] = if raw[3] & 1 == 0 { id::TYPE_FEEDBACK } else { id::TYPE_CONTROL };
            raw[12] = serial::checksum(&raw[..12]);
            let frame = SerialFrame::from_bytes(&raw).expect("a well-formed frame");
            let event = Event {
                ts,
                iface,
                dir: None,
                frame: FrameRef::Serial(&frame),
                decoded: Ok(serial::decode(&frame)),
            };
            summary.event(&event);
            serial_bytes += FRAME_SIZE as u64;
        } else {
            let Some(frame) = take_frame(&mut bytes) else {
                stats.invalid_frames += 1;
                continue;
            };
            detector.observe(&frame);
            let decoded = can::decode(&frame, hint);
            let event = Event { ts, iface, dir: None, frame: FrameRef::Can(&frame), decoded };
            summary.event(&event);
        }
        stats.frames += 1;
    }
    if serial_bytes > 0 {
        let serial = StreamStats {
            bytes: serial_bytes,
            frames: serial_bytes / FRAME_SIZE as u64,
            ..StreamStats::default()
        };
        stats.serial.push(("fuzz.bin".to_string(), serial));
    }
    let report = summary.report(&stats, &detector);
    assert!(report.starts_with("Input\n"), "{report}");
    let json = summary.to_json(&stats, &detector);
    let text = serde_json::to_string(&json).expect("the summary serialises");
    let parsed: serde_json::Value = serde_json::from_str(&text).expect("the summary JSON parses back");
    assert!(same_json(&parsed, &json), "{text}\nparses back as\n{parsed}");
    assert_eq!(json["frames"], stats.frames);
    let ids = json["ids"].as_array().expect("an ids array");
    let per_id: u64 = ids.iter().map(|id| id["frames"].as_u64().expect("a frame count")).sum();
    assert_eq!(per_id, stats.frames, "the identifiers' frames add up to the frames fed");
}

/// Equal JSON values, numbers within a few units in the last place: serde_json's default parser is not
/// correctly rounded (`1700000001.000065` may come back one f64 step away), a JSON reader's limit, not the
/// writer's.
fn same_json(a: &serde_json::Value, b: &serde_json::Value) -> bool {
    use serde_json::Value;
    match (a, b) {
        (Value::Number(x), Value::Number(y)) if x.is_f64() || y.is_f64() => match (x.as_f64(), y.as_f64()) {
            (Some(x), Some(y)) => x == y || (x - y).abs() <= x.abs().max(y.abs()) * 4.0 * f64::EPSILON,
            _ => false,
        },
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(x, y)| same_json(x, y))
        }
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(key, x)| y.get(key).is_some_and(|y| same_json(x, y)))
        }
        _ => a == b,
    }
}

/// Input: `flags, frame text`. Planning never panics; an error that names a column names one within
/// the text; a planned frame is the frame the text says; every frame that can move the robot on any
/// protocol (or enables motion) needs `--force`, and a frame that can move the robot is followed by
/// zero-velocity frames on the wire it moves on.
pub fn send_raw_plan(data: &[u8]) {
    let Some((&flags, text)) = data.split_first() else { return };
    let text = String::from_utf8_lossy(text);
    let (serial_link, fix_checksum) = (flags & 1 != 0, flags & 2 != 0);
    for hint in HINTS {
        let planned = match send_raw::plan(&text, serial_link, fix_checksum, hint) {
            Ok(planned) => planned,
            Err(reason) => {
                assert!(!reason.is_empty());
                if let Some(column) = reason.strip_prefix("column ").and_then(|rest| rest.split(':').next()) {
                    let column: usize = column.parse().expect("a column number");
                    assert!((1..=text.len() + 1).contains(&column), "{reason:?} for {text:?}");
                }
                continue;
            }
        };
        assert!(!planned.meaning.is_empty() && !planned.meaning.contains('\n'), "{:?}", planned.meaning);
        if planned.moves_on.is_some() {
            assert!(planned.needs_force, "{planned:?} moves the robot without --force");
        }
        match planned.frame {
            LinkFrame::Can(frame) => {
                assert!(!serial_link);
                assert_eq!(candump::parse_cansend(text.as_bytes()), Ok(frame));
                let standard = frame.is_standard_data();
                for any_hint in HINTS {
                    let moves =
                        matches!(can::decode(&frame, any_hint), Ok(Some(d)) if d.message.moves_robot());
                    if moves {
                        assert!(planned.needs_force, "{planned:?} moves under {any_hint:?}");
                    }
                }
                let motion_id = matches!(frame.id(), 0x111 | 0x130);
                if standard && motion_id {
                    // Anything but a well-formed zero command may move the robot.
                    let wire = if frame.id() == 0x111 { Wire::CanV2 } else { Wire::CanV1 };
                    let zero = matches!(
                        can::decode(&frame, if wire == Wire::CanV2 { ProtocolHint::V2 } else { ProtocolHint::V1 }),
                        Ok(Some(d)) if !d.message.moves_robot()
                    );
                    assert_eq!(planned.moves_on, (!zero).then_some(wire), "{planned:?}");
                } else {
                    assert_eq!(planned.moves_on, None, "{planned:?}");
                }
                if frame.kind() == FrameKind::Data
                    && !frame.is_extended()
                    && matches!(frame.id(), 0x111 | 0x130 | 0x421)
                {
                    assert!(planned.needs_force, "{planned:?}");
                }
            }
            LinkFrame::Serial(frame) => {
                assert!(serial_link);
                assert_eq!(send_raw::parse_serial(&planned.text, false), Ok(frame), "{planned:?}");
                let motion = frame.frame_type == id::TYPE_CONTROL && frame.command == id::CMD_MOTION_CONTROL;
                assert_eq!(planned.needs_force, motion);
                let moves = serial::decode(&frame).is_some_and(|d| d.message.moves_robot());
                assert_eq!(planned.moves_on.is_some(), motion && moves, "{planned:?}");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All-zero read sizes once made the harness's reader return `Interrupted` forever (a hang that was
    /// the harness's, not the line reader's).
    #[test]
    fn chunked_reader_gives_a_byte_after_each_interruption() {
        let mut reader = ChunkedReader::new(b"ab", &[0]);
        let mut buf = [0u8; 4];
        assert_eq!(reader.read(&mut buf).unwrap_err().kind(), io::ErrorKind::Interrupted);
        assert_eq!(reader.read(&mut buf).unwrap(), 1);
        assert_eq!(reader.read(&mut buf).unwrap_err().kind(), io::ErrorKind::Interrupted);
        assert_eq!(reader.read(&mut buf).unwrap(), 1);
        assert_eq!(reader.read(&mut buf).unwrap(), 0);
        candump_reader(&[1, 255, 1, 0, 0x10, 0, 0, b'\r', b'\n', b'\n', b'l', b'a', b's', b't']);
    }

    /// serde_json's default parser reads 1700000001.000065 one f64 step away: equal within rounding,
    /// while any other difference still counts.
    #[test]
    fn same_json_allows_float_rounding_only() {
        let written = serde_json::json!({"first": 1_700_000_001.000_065_f64, "frames": 2});
        let read: serde_json::Value =
            serde_json::from_str(&serde_json::to_string(&written).unwrap()).unwrap();
        assert!(same_json(&read, &written));
        let next = f64::from_bits(1_700_000_001.000_065_f64.to_bits() + 1);
        assert!(same_json(&serde_json::json!({"first": next, "frames": 2}), &written));
        assert!(!same_json(&serde_json::json!({"first": 1_700_000_001.000_1, "frames": 2}), &written));
        assert!(!same_json(&serde_json::json!({"first": next, "frames": 3}), &written));
        assert!(!same_json(&serde_json::json!({"first": next}), &written));
    }
}
