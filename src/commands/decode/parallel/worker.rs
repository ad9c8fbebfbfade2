//! A worker of `decode -j`: a chunk's lines through the line loop into the chunk recorder ([`ChunkLines`]),
//! which keeps its output, events, counts, rejections and stop for the merge in input order.

use std::ops::ControlFlow;

use parking_lot::Mutex;

use super::super::lines::{decode_lines, FrameLine, LineSink, Scanned};
use super::super::ranges::{Piece, Range};
use super::super::splitter::Text;
use super::super::summary::Summary;
use super::super::Skipped;
use super::settings::{Settings, Start};
use crate::candump::{
    self, CarriedState, DeltaSum, Direction, Line, LineParser, Reason, Timestamp, MAX_SHOWN_REJECTS,
};
use crate::output::{Event, FrameRef};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::{CanFrame, DecodeError, Decoded};

/// A chunk travelling from the reader to a worker and back; its buffers are reused.
#[derive(Default)]
pub(super) struct Chunk {
    pub index: u64,
    /// A plain file's range, read by the worker that decodes it ([`super::super::ranges::Ranges`]);
    /// otherwise the lines are in `text`.
    pub range: Option<Range>,
    /// The lines (of a range: only its bytes read and its read error).
    pub text: Text,
    pub output: Vec<u8>,
    pub events: Events,
    /// `--summary` (without `--plot` or `-t d`): the chunk's own summary, merged here in order.
    pub summary: Box<Summary>,
    pub outcome: Outcome,
}

/// `--summary`, `--plot` and `-t d`: a chunk's events that passed the filter, replayed by this thread in
/// input order through the same code one thread feeds them to, so the merge is exact by construction.
#[derive(Default)]
pub(super) struct Events {
    pub list: Vec<Replay>,
    /// The interface names the events point into, one after the other: a name is added each time it
    /// changes (nearly never), so a line costs no allocation and no search.
    pub names: String,
    /// Where each name ends in `names`.
    pub ends: Vec<usize>,
    /// `-t d`: what all the chunk's deltas (rejected lines' too) add up to.
    pub deltas: DeltaSum,
}

impl Events {
    pub fn clear(&mut self) {
        self.list.clear();
        self.names.clear();
        self.ends.clear();
        self.deltas = DeltaSum::default();
    }

    /// The index of `iface`: the last name's, or a new one.
    #[inline]
    fn intern(&mut self, iface: &str) -> u32 {
        let start = self.ends.len().checked_sub(2).map_or(0, |before| self.ends[before]);
        let last = &self.names.as_bytes()[start..];
        // Compared byte by byte: names are a few bytes, a call to memcmp cost more than the comparison.
        let same = last.len() == iface.len() && last.iter().zip(iface.as_bytes()).all(|(a, b)| a == b);
        if self.ends.is_empty() || !same {
            self.names.push_str(iface);
            self.ends.push(self.names.len());
        }
        // A chunk holds far fewer than 2^32 lines (it is a few hundred kilobytes).
        (self.ends.len() - 1) as u32
    }

    pub fn name(&self, index: u32) -> &str {
        let index = index as usize;
        let start = index.checked_sub(1).map_or(0, |before| self.ends[before]);
        &self.names[start..self.ends[index]]
    }
}

/// What `Decoder::deliver` needs of one event.
pub(super) struct Replay {
    pub stamp: Stamp,
    pub iface: u32,
    pub dir: Option<Direction>,
    pub frame: CanFrame,
    pub decoded: Result<Option<Decoded>, DecodeError>,
}

#[derive(Clone, Copy)]
pub(super) enum Stamp {
    /// The line's own stamp, or none.
    Given(Option<Timestamp>),
    /// `-t d`: the sum of the chunk's deltas up to this line; the run's sum before the chunk is added in order.
    Summed(Timestamp),
}

/// What decoding a chunk found besides its output; line numbers count from 1 within the chunk.
#[derive(Default)]
pub(super) struct Outcome {
    pub start: Start,
    pub end: CarriedState,
    pub v1_frames: u64,
    pub v2_frames: u64,
    pub lines: u64,
    pub frames: u64,
    pub decoded_lines: u64,
    pub rejected_lines: u64,
    pub skipped: Skipped,
    pub candump_dropped: u64,
    pub invalid_frames: u64,
    /// The first rejections, each possibly shown (at most [`MAX_SHOWN_REJECTS`] + 1 in a run are).
    pub shown: Vec<Reject>,
    /// The chunk's further rejections, only counted: per reason, in order of first occurrence.
    pub counted: Vec<Reject>,
    /// `--strict`: the line that ended decoding, with the message.
    pub stop: Option<Stop>,
}

pub(super) struct Reject {
    pub line: u64,
    pub message: String,
    pub reason: &'static str,
    pub length: Option<u64>,
    pub count: u64,
}

pub(super) struct Stop {
    /// The line the message is located at (`name:line: `); `None` for messages said without a place.
    pub line: Option<u64>,
    pub message: String,
}

/// A worker's part of the guess: V1-only or V2-only frames in its chunk were seen before every chunk taken
/// after it (chunks are taken in order), so those start with the right verdict before this chunk is merged
/// (without it, every chunk taken before the first merge would be decoded twice). A guess is only a guess:
/// [`settle`] checks it.
pub(super) fn publish_verdict(guess: &Mutex<Start>, outcome: &Outcome) {
    let (v1, v2) = (outcome.v1_frames > 0, outcome.v2_frames > 0);
    if v1 || v2 {
        let mut guess = guess.lock();
        guess.v1_seen |= v1;
        guess.v2_seen |= v2;
    }
}

/// Decodes the chunk again from `truth` when it was decoded from another start. Returns whether it did.
pub(super) fn settle(settings: &Settings, chunk: &mut Chunk, truth: &Start) -> bool {
    if chunk.outcome.start == *truth {
        return false;
    }
    decode_chunk(settings, truth, chunk);
    true
}

/// Decodes one chunk from `start` into its output (or events), as `Decoder::candump` decodes lines: its
/// text, or the lines of its range read now.
pub(super) fn decode_chunk(settings: &Settings, start: &Start, chunk: &mut Chunk) {
    if decode_chunk_from(settings, start, chunk, true) {
        // A mapped page vanished under the lines decoded: all of them again, read from the file.
        decode_chunk_from(settings, start, chunk, false);
    }
}

/// [`decode_chunk`], its range's lines read from mapped windows if `mapped`; whether they must be read
/// again without ([`super::ranges::RangeEnd::reread`]).
fn decode_chunk_from(settings: &Settings, start: &Start, chunk: &mut Chunk, mapped: bool) -> bool {
    chunk.output.clear();
    chunk.events.clear();
    if settings.partial {
        *chunk.summary = Summary::partial();
    }
    let mut lines = ChunkLines {
        settings,
        detector: ProtocolDetector { v1_frames: start.v1_seen.into(), v2_frames: start.v2_seen.into() },
        output: &mut chunk.output,
        events: &mut chunk.events,
        summary: &mut chunk.summary,
        outcome: Outcome { start: start.clone(), ..Outcome::default() },
    };
    let parser = LineParser::for_format(settings.format);
    let mut parser = if settings.delta_stamps { parser.with_delta_timestamps() } else { parser };
    parser.carry_on_from(&start.carried);
    match (chunk.range, &settings.ranges) {
        (Some(range), Some(ranges)) => {
            let end = ranges.read(range, mapped, |piece| {
                let first = lines.outcome.lines + 1;
                let flow = match piece {
                    Piece::Lines(text) => {
                        let scanned = decode_lines(&mut lines, &mut parser, (text, &[]), first);
                        lines.outcome.lines += scanned.lines;
                        scanned.flow
                    }
                    Piece::TooLong(length) => {
                        lines.outcome.lines += 1;
                        lines.too_long(first, length)
                    }
                };
                flow.is_continue()
            });
            if end.reread {
                return true;
            }
            chunk.text.bytes = end.bytes;
            chunk.text.read_error = end.error;
        }
        _ => {
            let Scanned { lines: count, .. } =
                decode_lines(&mut lines, &mut parser, (&chunk.text.input[..], &chunk.text.long_lines), 1);
            lines.outcome.lines = count;
        }
    }
    let mut outcome = lines.outcome;
    outcome.v1_frames = lines.detector.v1_frames - u64::from(start.v1_seen);
    outcome.v2_frames = lines.detector.v2_frames - u64::from(start.v2_seen);
    outcome.end = parser.carried();
    chunk.events.deltas = parser.delta_sum();
    chunk.outcome = outcome;
    false
}

/// A worker's decoder of lines: `Decoder`'s line handling, with counts and messages kept for the merge.
struct ChunkLines<'a> {
    settings: &'a Settings,
    detector: ProtocolDetector,
    output: &'a mut Vec<u8>,
    events: &'a mut Events,
    summary: &'a mut Summary,
    outcome: Outcome,
}

/// An event's interface: the name, or (when the events are kept) its index among the chunk's names.
#[derive(Clone, Copy)]
enum Iface<'a> {
    Name(&'a str),
    Interned(u32),
}

impl ChunkLines<'_> {
    /// As `Decoder::frame` and `Decoder::event`; returns the `--strict` message of an invalid frame.
    #[inline(always)]
    fn event(
        &mut self,
        stamp: Stamp,
        iface: Iface<'_>,
        dir: Option<Direction>,
        frame: &CanFrame,
    ) -> Option<String> {
        self.outcome.frames += 1;
        let decoded = self.detector.observe_and_decode(frame, self.settings.protocol);
        if let Err(error) = decoded {
            self.outcome.invalid_frames += 1;
            if self.settings.strict {
                return Some(format!("invalid frame: {error}"));
            }
        }
        let ts = match stamp {
            Stamp::Given(ts) => ts,
            Stamp::Summed(sum) => Some(sum),
        };
        let name = match iface {
            Iface::Name(name) => name,
            Iface::Interned(index) => self.events.name(index),
        };
        if self.settings.summary_only {
            // The hot case of `--summary`: no event built (see [`Summary::frame`]).
            self.summary.frame(ts, name, FrameRef::Can(frame), &decoded);
            return None;
        }
        let event = Event { ts, iface: name, dir, frame: FrameRef::Can(frame), decoded };
        if !self.settings.filter.passes(&event) {
            return None;
        }
        if let Some(writer) = self.settings.writer {
            writer.write(self.output, &event);
        }
        if self.settings.partial {
            self.summary.event(&event);
        }
        if let Iface::Interned(iface) = iface {
            self.events.list.push(Replay { stamp, iface, dir, frame: *frame, decoded });
        }
        None
    }

    /// `iface` as [`Self::event`] takes it: interned when the events are kept.
    #[inline(always)]
    fn iface<'n>(&mut self, iface: &'n str) -> Iface<'n> {
        match self.settings.record {
            true => Iface::Interned(self.events.intern(iface)),
            false => Iface::Name(iface),
        }
    }

    /// As `Decoder::rejected_line`: kept to be said in order, or the stop with `--strict`.
    fn rejected(
        &mut self,
        line: u64,
        message: String,
        reason: &'static str,
        length: Option<u64>,
    ) -> ControlFlow<()> {
        let outcome = &mut self.outcome;
        outcome.rejected_lines += 1;
        if self.settings.strict {
            return self.stop(Some(line), message);
        }
        if outcome.shown.len() <= MAX_SHOWN_REJECTS {
            outcome.shown.push(Reject { line, message, reason, length, count: 1 });
        } else {
            match outcome.counted.iter_mut().find(|known| known.reason == reason) {
                Some(known) => {
                    known.count += 1;
                    known.length = known.length.max(length);
                }
                None => {
                    outcome.counted.push(Reject { line, message: String::new(), reason, length, count: 1 })
                }
            }
        }
        ControlFlow::Continue(())
    }

    /// The end of the chunk's decoding (`--strict`): `line` is where the message is located.
    #[cold]
    fn stop(&mut self, line: Option<u64>, message: String) -> ControlFlow<()> {
        self.outcome.stop = Some(Stop { line, message });
        ControlFlow::Break(())
    }
}

impl LineSink for ChunkLines<'_> {
    /// A frame line (line `number` of the chunk).
    #[inline(always)]
    fn frame(&mut self, number: u64, line: FrameLine<'_>) -> ControlFlow<()> {
        self.outcome.decoded_lines += 1;
        let stamp = match (line.ts, line.summed) {
            (Some(sum), true) => Stamp::Summed(sum),
            (ts, _) => Stamp::Given(ts),
        };
        let iface = self.iface(line.iface);
        match self.event(stamp, iface, line.dir, line.frame) {
            Some(message) => self.stop(Some(number), message),
            None => ControlFlow::Continue(()),
        }
    }

    /// As `Decoder::skipped_line`.
    #[inline(never)]
    fn skipped(&mut self, number: u64, line: Line<'_>) -> ControlFlow<()> {
        let dropped = self.outcome.skipped.count(&line);
        self.outcome.candump_dropped = self.outcome.candump_dropped.saturating_add(dropped);
        if matches!(line, Line::CanXl) && self.settings.strict {
            return self.stop(Some(number), super::super::CAN_XL_NOT_SUPPORTED.to_string());
        }
        ControlFlow::Continue(())
    }

    /// As `Decoder::unparsed_line`.
    #[inline(never)]
    fn unparsed(&mut self, number: u64, text: &[u8], error: candump::LineError) -> ControlFlow<()> {
        let bare = text.trim_ascii();
        let looks_bare = bare.contains(&b'#') && !bare.iter().any(u8::is_ascii_whitespace);
        match candump::parse_cansend(bare) {
            Ok(frame) => {
                self.outcome.decoded_lines += 1;
                let iface = self.iface("-");
                match self.event(Stamp::Given(None), iface, None, &frame) {
                    // The single thread says this one without the place, too.
                    Some(message) => self.stop(None, message),
                    None => ControlFlow::Continue(()),
                }
            }
            Err(frame_error) if looks_bare => {
                let message = format!("bare frame: {frame_error}");
                self.rejected(number, message, frame_error.reason.as_str(), None)
            }
            Err(_) => self.rejected(number, error.to_string(), error.reason.as_str(), None),
        }
    }

    /// Line `number`, longer than the line limit (`length` bytes without its `\n`).
    #[inline(never)]
    fn too_long(&mut self, number: u64, length: usize) -> ControlFlow<()> {
        let message = candump::line_too_long(length);
        self.rejected(number, message, Reason::LineTooLong.as_str(), Some(length as u64))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::{LogFormat, TextFormat};
    use crate::output::filter::Filter;
    use crate::output::{EventWriter, Format};
    use crate::protocol::ProtocolHint;

    fn settings() -> Settings {
        Settings {
            format: LogFormat { text: TextFormat::Candump, compression: None },
            protocol: ProtocolHint::Auto,
            filter: Filter::default(),
            writer: Some(EventWriter::new(Format::Json, false)),
            record: false,
            partial: false,
            summary_only: false,
            delta_stamps: false,
            strict: false,
            ranges: None,
        }
    }

    #[test]
    fn interface_names_are_kept_once_per_change() {
        let mut events = Events::default();
        let indexes: Vec<u32> =
            ["can0", "can0", "vcan12", "can0", "can0", "-"].iter().map(|name| events.intern(name)).collect();
        assert_eq!(indexes, [0, 0, 1, 2, 2, 3]);
        let names: Vec<&str> = (0..4).map(|index| events.name(index)).collect();
        assert_eq!(names, ["can0", "vcan12", "can0", "-"]);
        events.clear();
        assert_eq!(events.intern("can1"), 0);
        assert_eq!(events.name(0), "can1");
    }

    /// `-t d`: a chunk's stamps are its own sums from zero; added to the sum before, they are one thread's.
    #[test]
    fn chunk_delta_sums_add_up_to_the_single_sum() {
        let text = b" (000.600000)  can0  211   [8]  00 00 01 03 00 00 00 B1\n\
                     (001.700000)  can0  211   [8]  00 00 ZZ 03 00 00 00 B1\n\
                     (0.500000) can0 221#01F4000000000001\n\
                     (000.900000)  can0  221   [8]  01 F4 00 00 00 00 00 01\n";
        let settings = Settings { writer: None, record: true, delta_stamps: true, ..settings() };
        let mut chunk = chunk(text);
        decode_chunk(&settings, &Start::default(), &mut chunk);
        let stamps: Vec<(bool, u64, u32)> = chunk
            .events
            .list
            .iter()
            .map(|replay| match replay.stamp {
                Stamp::Summed(ts) => (true, ts.secs, ts.nanos),
                Stamp::Given(ts) => (false, ts.map_or(0, |ts| ts.secs), ts.map_or(0, |ts| ts.nanos)),
            })
            .collect();
        // The rejected line's delta counts; the log line's own stamp is not a delta.
        assert_eq!(stamps, [(true, 0, 600_000_000), (false, 0, 500_000_000), (true, 3, 200_000_000)]);
        assert_eq!(chunk.events.deltas.total().as_nanos(), 3_200_000_000);
    }

    fn chunk(text: &[u8]) -> Chunk {
        {
            let mut chunk = Chunk::default();
            chunk.text.input.extend_from_slice(text);
            chunk
        }
    }

    /// 0x151 decodes by the verdict on the traffic before it: a chunk decoded from a wrong guess differs,
    /// and is decoded again from the true start.
    #[test]
    fn a_wrong_guess_of_the_protocol_is_decoded_again() {
        // A V1 system state whose checksum byte is wrong: V2 unless the bus is known to be V1.
        let line = b"(1.000000) can0 151#0000000000000000\n";
        let (settings, v1) = (settings(), Start { v1_seen: true, ..Start::default() });
        let mut guessed = chunk(line);
        decode_chunk(&settings, &Start::default(), &mut guessed);
        let mut exact = chunk(line);
        decode_chunk(&settings, &v1, &mut exact);
        assert_ne!(guessed.output, exact.output, "the hint must matter for this line");
        assert!(settle(&settings, &mut guessed, &v1));
        assert_eq!(guessed.output, exact.output);
        assert!(!settle(&settings, &mut guessed, &v1), "a right guess is kept");
    }

    /// An error frame's continuation text is text only after the error frame.
    #[test]
    fn a_chunk_after_an_error_frame_is_decoded_again() {
        let text = b"\tcontroller-problem{rx-error-warning}\n";
        let settings = settings();
        let mut guessed = chunk(text);
        decode_chunk(&settings, &Start::default(), &mut guessed);
        assert_eq!(guessed.outcome.rejected_lines, 1);
        let truth = Start {
            carried: CarriedState { after_error_frame: true, ..CarriedState::default() },
            ..Start::default()
        };
        assert!(settle(&settings, &mut guessed, &truth));
        assert_eq!((guessed.outcome.rejected_lines, guessed.outcome.skipped.error_text), (0, 1));
    }

    /// What an ASC or trc header said holds for the lines after it: a chunk decoded without it is decoded
    /// again from the state the header left.
    #[test]
    fn a_chunk_after_an_asc_or_trc_header_is_decoded_again() {
        let files: [(TextFormat, &[u8], &[u8], &str); 2] = [
            // `base dec`: identifier 529 = 0x211, data bytes in decimal (200 is no hex byte).
            (
                TextFormat::VectorAsc,
                b"base dec  timestamps absolute\n",
                b"   1.000000 1  529  Rx d 2 10 200\n",
                "0AC8",
            ),
            // The columns named by the header: bus before the type, and no direction.
            (
                TextFormat::PeakTrc { version: 21 },
                b";$COLUMNS=N,O,B,T,I,L,D\n",
                b"      1      1000.000 1  DT 0211 2    0A 14\n",
                "0A14",
            ),
        ];
        for (text, header, line, data) in files {
            let settings = Settings { format: LogFormat { text, compression: None }, ..settings() };
            let initial =
                Start { carried: LineParser::for_format(settings.format).carried(), ..Start::default() };
            let mut first = chunk(header);
            decode_chunk(&settings, &initial, &mut first);
            assert_ne!(first.outcome.end, initial.carried, "{text:?}: the header must change the state");
            let mut guessed = chunk(line);
            decode_chunk(&settings, &initial, &mut guessed);
            assert_eq!(guessed.outcome.rejected_lines, 1, "{text:?}: read without its header");
            let truth = Start { carried: first.outcome.end.clone(), ..Start::default() };
            assert!(settle(&settings, &mut guessed, &truth));
            assert_eq!((guessed.outcome.rejected_lines, guessed.outcome.decoded_lines), (0, 1), "{text:?}");
            let json = String::from_utf8_lossy(&guessed.output);
            let expected = format!(r#""data":"{data}""#);
            assert!(json.contains(r#""id":"0x211""#) && json.contains(&expected), "{text:?}: {json}");
        }
    }
}
