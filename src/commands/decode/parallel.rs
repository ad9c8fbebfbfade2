//! `decode -j N`: a text log (candump, Vector ASC, PEAK trc; a file or a stream, plain or compressed) decoded
//! by N threads, written byte for byte as one thread would.
//!
//! A plain file is cut into ranges of whole lines that each worker reads itself as it decodes them, with
//! positioned reads into a small buffer of its own ([`Ranges`]). Other input is
//! cut into chunks that end after a `\n` ([`Splitter`]): a worker reads the next chunk of a compressed file
//! itself, one worker at a time, and a stream's chunks come from a reader thread. Workers decode each chunk
//! into its own output buffer with the line counts, rejections and stop (`--strict`) it found, numbered within the
//! chunk; this thread takes the chunks back in input order, writes their output, and replays their counts
//! and messages with the chunk's first line number, which is known only then. Chunks travel in a fixed pool,
//! so memory is bounded by the pool (threads x chunk size), whatever the size of the input.
//!
//! `--summary`, `--plot` and `--delta-stamps` (`-t d`) need state carried over every line before. For
//! `--summary` alone each worker feeds its chunk's events into a partial [`Summary`] of its own, and this
//! thread merges the partials in input order ([`Summary::absorb`]): what depends on the frames before the
//! chunk (gaps and count-byte steps across the boundary, the first status against the one before, odometer
//! steps, positions) is kept raw in the partial and resolved there, so the report is the single pass's. A
//! partial that cannot be merged exactly (more interface names or identifiers than the report lists,
//! [`Summary::can_absorb`]) is decoded again here into events and replayed. With `--plot` or `-t d` the
//! workers parse, decode and filter their chunk into a compact list of events ([`Events`]: stamp, interface
//! as an index into the chunk's names, direction, frame, what it decoded to), and this thread replays them in
//! input order through [`Decoder::deliver`], the code one thread feeds them to: exact by construction. `-t d`
//! stamps are summed within the chunk from zero and the run's sum before the chunk is added here, in order
//! (saturating sums of non-negative deltas are associative: exact too); with `-t d` this thread also writes
//! the text, since every stamp depends on all the lines before.
//!
//! State one line leaves for the next is guessed at a chunk's start and checked in order: the protocol
//! detector's verdict (which decodes the shared identifiers), the interface a Pengutronix header named,
//! whether an error frame came last, and what ASC and trc headers said of the lines after them (`base dec`,
//! the trc columns) ([`CarriedState`]). A worker starts from the state this thread last published; a chunk
//! decoded from a wrong guess is decoded again here, from the true state (rare: the verdict settles within
//! the first frames, and headers stand at the top of a file).
//!
//! Standard input and pipes (plain or compressed) are cut at whatever each read returns, at the last `\n`
//! (the rest is carried to the next chunk), so a live stream (`candump -L can0 | tracerctl decode -`) is
//! written line by line as it comes, while bulk input still makes large chunks. A stream's reader thread is not
//! joined (a read of a quiet stream may block until the process exits); the workers and this thread wake
//! every [`WAKE`] to see the end of decoding or a signal.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, Read};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Result};
use memchr::{memchr, memrchr};
use parking_lot::Mutex;

use super::interrupt::StopReading;
use super::ranges::{Piece, Range, Ranges, Sizing, SLICE_BYTES, WINDOW_BYTES};
use super::summary::Summary;
use super::{read_error, Decoder, Interrupted, Sink, Skipped};
use crate::candump::{
    self, CarriedState, DeltaSum, Direction, Line, LineParser, LogFormat, Reason, Rejected, Rejection,
    Timestamp, DEFAULT_MAX_LINE_LEN, MAX_SHOWN_REJECTS,
};
use crate::exit::Failure;
use crate::output::filter::Filter;
use crate::output::{Event, EventWriter, FrameRef};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::{CanFrame, DecodeError, Decoded, ProtocolHint};

/// Input bytes per chunk by default: large enough that the per-chunk work (a channel hop, one write) vanishes,
/// small enough that the pool stays a few megabytes.
pub const CHUNK_BYTES: usize = 256 * 1024;
/// `--summary` alone writes nothing per chunk, so larger chunks cost no memory beyond the input, and they cut
/// the hand-overs between threads, each a wake-up (measured on 10 M lines: 0.39 s with 256 KiB chunks, 0.27 s
/// with 1 MiB, 2 % less again with 2 MiB; 4 MiB left one core idle at the end of a 1 M-line log). Output modes
/// measured no faster with larger chunks and would hold that much more output.
pub const SUMMARY_CHUNK_BYTES: usize = 2 * 1024 * 1024;
/// More workers than this gain nothing (the reader and the writer are one thread each), and a `-j` of
/// thousands would only fail to spawn.
const MAX_THREADS: usize = 64;
/// How often a thread waiting for chunks looks whether decoding ended or a signal came: a live stream may
/// send nothing for hours.
const WAKE: Duration = Duration::from_millis(50);

impl Decoder {
    /// Whether inputs are decoded in parallel: every text format is (candump, ASC, trc), with exactly the
    /// single thread's output.
    pub(super) fn parallel_fits(&self) -> bool {
        self.threads > 1
    }
}

/// The state a chunk's first line is decoded from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
struct Start {
    carried: CarriedState,
    /// The detector's verdict: V1-only and V2-only identifiers seen before.
    v1_seen: bool,
    v2_seen: bool,
}

/// A chunk travelling from the reader to a worker and back; its buffers are reused.
#[derive(Default)]
struct Chunk {
    index: u64,
    /// A plain file's range, read by the worker that decodes it ([`Ranges`]); otherwise the text is `input`.
    range: Option<Range>,
    input: Vec<u8>,
    /// Lines the reader cut short because they exceeded the line limit: (offset in `input`, true length).
    long_lines: Vec<(usize, usize)>,
    /// Bytes of the input this chunk holds (for the progress bar).
    bytes: u64,
    /// Reading failed after `input`.
    read_error: Option<io::Error>,
    output: Vec<u8>,
    events: Events,
    /// `--summary` (without `--plot` or `-t d`): the chunk's own summary, merged here in order.
    summary: Box<Summary>,
    outcome: Outcome,
}

/// `--summary`, `--plot` and `-t d`: a chunk's events that passed the filter, replayed by this thread in
/// input order through the same code one thread feeds them to, so the merge is exact by construction.
#[derive(Default)]
struct Events {
    list: Vec<Replay>,
    /// The interface names the events point into, one after the other: a name is added each time it
    /// changes (nearly never), so a line costs no allocation and no search.
    names: String,
    /// Where each name ends in `names`.
    ends: Vec<usize>,
    /// `-t d`: what all the chunk's deltas (rejected lines' too) add up to.
    deltas: DeltaSum,
}

impl Events {
    fn clear(&mut self) {
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

    fn name(&self, index: u32) -> &str {
        let index = index as usize;
        let start = index.checked_sub(1).map_or(0, |before| self.ends[before]);
        &self.names[start..self.ends[index]]
    }
}

/// What [`Decoder::deliver`] needs of one event.
struct Replay {
    stamp: Stamp,
    iface: u32,
    dir: Option<Direction>,
    frame: CanFrame,
    decoded: Result<Option<Decoded>, DecodeError>,
}

#[derive(Clone, Copy)]
enum Stamp {
    /// The line's own stamp, or none.
    Given(Option<Timestamp>),
    /// `-t d`: the sum of the chunk's deltas up to this line; the run's sum before the chunk is added in order.
    Summed(Timestamp),
}

/// What decoding a chunk found besides its output; line numbers count from 1 within the chunk.
#[derive(Default)]
struct Outcome {
    start: Start,
    end: CarriedState,
    v1_frames: u64,
    v2_frames: u64,
    lines: u64,
    frames: u64,
    decoded_lines: u64,
    rejected_lines: u64,
    skipped: Skipped,
    candump_dropped: u64,
    invalid_frames: u64,
    /// The first rejections, each possibly shown (at most [`MAX_SHOWN_REJECTS`] + 1 in a run are).
    shown: Vec<Reject>,
    /// The chunk's further rejections, only counted: per reason, in order of first occurrence.
    counted: Vec<Reject>,
    /// `--strict`: the line that ended decoding, with the message.
    stop: Option<Stop>,
}

struct Reject {
    line: u64,
    message: String,
    reason: &'static str,
    length: Option<u64>,
    count: u64,
}

struct Stop {
    /// The line the message is located at (`name:line: `); `None` for messages said without a place.
    line: Option<u64>,
    message: String,
}

/// What every worker decodes with.
#[derive(Clone)]
struct Settings {
    /// candump, ASC or trc text (the format [`candump::open_log`] recognised).
    format: LogFormat,
    protocol: ProtocolHint,
    filter: Filter,
    /// Workers write the output (not with `-t d`, whose stamps are sums over everything before).
    writer: Option<EventWriter>,
    /// Workers keep the events for this thread to replay.
    record: bool,
    /// Workers summarize their chunk into a partial summary for this thread to merge (`--summary`).
    partial: bool,
    /// `partial` without a filter: frames go to the summary without an event built.
    summary_only: bool,
    delta_stamps: bool,
    strict: bool,
    /// A plain file: the ranges the workers read (and this thread reads again to decode a chunk again).
    ranges: Option<Arc<Ranges>>,
}

/// Decodes `reader` (the text of a regular file or of standard input, decompressed, after
/// [`candump::open_log`]) with the decoder's threads. A `stream` (standard input, a pipe) is cut into chunks
/// at whatever each read returns, so a live stream's lines are written as soon as they arrive.
// Long: the threads' set-up, each a few lines, reads best in one place.
pub(super) fn decode(
    decoder: &mut Decoder,
    name: &str,
    (reader, format): (impl Read + Send + 'static, LogFormat),
    size: Option<u64>,
    (stream, plain): (bool, Option<File>),
) -> Result<()> {
    let writer = match &decoder.sink {
        Sink::Lines { writer, .. } if !decoder.delta_stamps => Some(*writer),
        _ => None,
    };
    // Partial summaries merge exactly; the plot and `-t d` stamps need every event in order.
    let partial = matches!(decoder.sink, Sink::Summary(_)) && decoder.plot.is_none() && !decoder.delta_stamps;
    let settings = Settings {
        format,
        protocol: decoder.protocol,
        filter: decoder.filter.clone(),
        writer,
        record: (writer.is_none() || decoder.plot.is_some()) && !partial,
        partial,
        summary_only: partial && decoder.filter.is_empty(),
        delta_stamps: decoder.delta_stamps,
        strict: decoder.strict,
        ranges: None,
    };
    let chunk_bytes = decoder.chunk_bytes.unwrap_or(if partial { SUMMARY_CHUNK_BYTES } else { CHUNK_BYTES });
    let (threads, chunk_bytes) = (decoder.threads.min(MAX_THREADS), chunk_bytes.max(1));
    // Set when this thread stops taking chunks (the end, an error, --strict, a signal): the others stop too.
    let finished = Arc::new(AtomicBool::new(false));
    let stop = StopReading::new(decoder.signals.clone(), Arc::clone(&finished));
    // A plain file's size is its text's: the ranges are cut in it.
    let settings = match (plain, size) {
        (Some(file), Some(size)) => {
            let sizing = match decoder.chunk_bytes {
                None if partial => Sizing::Guided { threads: threads as u64 },
                _ => Sizing::Fixed(chunk_bytes as u64),
            };
            // Tests' tiny chunks cut reads inside ranges too, elsewhere than the ranges' own cuts.
            let slice_bytes = decoder.chunk_bytes.map_or(SLICE_BYTES, |bytes| bytes.div_ceil(3));
            let window_bytes = decoder.chunk_bytes.map_or(WINDOW_BYTES, |bytes| bytes.div_ceil(2));
            let text_start = byte_order_mark(&file);
            let ranges = Ranges::new(file, text_start, size, sizing, (slice_bytes, Some(window_bytes)))
                .stopping(stop.clone());
            Settings { ranges: Some(Arc::new(ranges)), ..settings }
        }
        _ => settings,
    };
    let before = decoder.input_start();
    let guess = Mutex::new(Start { carried: LineParser::for_format(format).carried(), ..Start::default() });
    let (pool_tx, pool_rx) = mpsc::channel::<Chunk>();
    let (done_tx, done_rx) = mpsc::channel::<Chunk>();
    for _ in 0..threads * 2 + 2 {
        let _ = pool_tx.send(Chunk::default());
    }
    let reader = Stopping { inner: reader, stop };
    let splitter = Splitter::new(reader, Cut { chunk_bytes, stream });
    let source = if let Some(ranges) = &settings.ranges {
        Source::Ranges { ranges: Arc::clone(ranges), pool: Mutex::new(pool_rx) }
    } else if stream {
        // The reader is not joined: a read of a quiet stream may block until the process exits.
        let (work_tx, work_rx) = mpsc::channel::<Chunk>();
        let reader_finished = Arc::clone(&finished);
        std::thread::spawn(move || split(splitter, pool_rx, work_tx, &reader_finished));
        Source::Queue(Mutex::new(work_rx))
    } else {
        Source::File { splitter: Mutex::new(splitter), pool: Mutex::new(pool_rx) }
    };
    let result = std::thread::scope(|scope| {
        for _ in 0..threads {
            let done_tx = done_tx.clone();
            let (source, guess, settings, finished) = (&source, &guess, &settings, &*finished);
            scope.spawn(move || loop {
                let (mut chunk, start) = match source.take(guess) {
                    Ok(taken) => taken,
                    Err(Idle::NotYet) if !finished.load(Ordering::Relaxed) => continue,
                    Err(_) => return,
                };
                if finished.load(Ordering::Relaxed) {
                    return;
                }
                decode_chunk(settings, &start, &mut chunk);
                publish_verdict(guess, &chunk.outcome);
                if done_tx.send(chunk).is_err() {
                    return;
                }
            });
        }
        drop(done_tx);
        let merger = Merger {
            decoder: &mut *decoder,
            name,
            settings: &settings,
            guess: &guess,
            size,
            lines_before: before.lines,
            deltas: DeltaSum::default(),
        };
        let result = merger.run(&done_rx, &pool_tx);
        // The reader stops at the flag or the closed pool, the workers at the flag or the closed queue.
        finished.store(true, Ordering::Relaxed);
        drop(pool_tx);
        drop(done_rx);
        result
    });
    if result.is_ok() {
        decoder.note_no_frames(name, before);
    }
    result
}

/// This thread's side: chunks back in order, merged into the decoder.
struct Merger<'a> {
    decoder: &'a mut Decoder,
    name: &'a str,
    settings: &'a Settings,
    guess: &'a Mutex<Start>,
    size: Option<u64>,
    /// The lines of the inputs before this one: a chunk's first line number counts from this input's start.
    lines_before: u64,
    /// `-t d`: the sum of the deltas of the chunks merged so far.
    deltas: DeltaSum,
}

impl Merger<'_> {
    fn run(mut self, done: &mpsc::Receiver<Chunk>, pool: &mpsc::Sender<Chunk>) -> Result<()> {
        let bar = self.decoder.progress_bar(self.size);
        let mut waiting = BTreeMap::new();
        let mut carried = LineParser::for_format(self.settings.format).carried();
        let (mut next, mut consumed) = (0u64, 0u64);
        // A plain file's last range reads on to the end: until it is merged, the file is not.
        let mut reached_end = self.settings.ranges.is_none();
        loop {
            let chunk = match done.recv_timeout(WAKE) {
                Ok(chunk) => chunk,
                Err(RecvTimeoutError::Timeout) if self.decoder.signals.received().is_some() => {
                    return Err(io::Error::other(Interrupted).into());
                }
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => break,
            };
            waiting.insert(chunk.index, chunk);
            while let Some(mut chunk) = waiting.remove(&next) {
                if self.decoder.signals.received().is_some() {
                    return Err(io::Error::other(Interrupted).into());
                }
                self.merge(&mut chunk, &mut carried)?;
                reached_end |= chunk.range.is_some_and(|range| range.end.is_none());
                consumed += chunk.bytes;
                if let Some(bar) = &bar {
                    bar.set_position(consumed);
                }
                next += 1;
                let _ = pool.send(chunk);
            }
        }
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        // Every worker ended: a chunk that never came back would leave the ones after it here, and the
        // input's tail unsaid. Never seen; said, should it happen, rather than lost.
        if !waiting.is_empty() || !reached_end {
            let after = waiting.len();
            bail!(
                "internal error: chunk {next} of {} was lost ({after} decoded after it not written)",
                self.name
            );
        }
        Ok(())
    }

    /// One chunk, in order: decoded again if its start was guessed wrong, then written and counted.
    fn merge(&mut self, chunk: &mut Chunk, carried: &mut CarriedState) -> Result<()> {
        let detector = &self.decoder.detector;
        let truth = Start {
            carried: carried.clone(),
            v1_seen: detector.v1_frames > 0,
            v2_seen: detector.v2_frames > 0,
        };
        settle(self.settings, chunk, &truth);
        if let (Sink::Lines { output, .. }, Some(_)) = (&self.decoder.sink, self.settings.writer) {
            output.borrow_mut().write_through(&chunk.output)?;
        }
        if self.settings.partial {
            self.absorb(chunk, &truth)?;
        }
        if self.settings.record {
            self.replay(&chunk.events)?;
            if let (Sink::Lines { output, .. }, None) = (&self.decoder.sink, self.settings.writer) {
                // Lines this thread wrote (-t d) leave with their chunk, as a live stream's must.
                output.borrow_mut().flush()?;
            }
        }
        let decoder = &mut *self.decoder;
        // Line numbers count within this input, as one thread's reader counts them.
        let base = decoder.stats.lines - self.lines_before;
        let outcome = &chunk.outcome;
        let stats = &mut decoder.stats;
        stats.lines += outcome.lines;
        stats.frames += outcome.frames;
        stats.decoded_lines += outcome.decoded_lines;
        stats.rejected_lines += outcome.rejected_lines;
        stats.invalid_frames += outcome.invalid_frames;
        stats.candump_dropped = stats.candump_dropped.saturating_add(outcome.candump_dropped);
        let (skipped, more) = (&mut stats.skipped, &outcome.skipped);
        skipped.blank += more.blank;
        skipped.comment += more.comment;
        skipped.error_text += more.error_text;
        skipped.can_xl += more.can_xl;
        skipped.dropcount += more.dropcount;
        decoder.detector.v1_frames += outcome.v1_frames;
        decoder.detector.v2_frames += outcome.v2_frames;
        self.tally(base, outcome);
        *carried = outcome.end.clone();
        // The next chunks' guess: the settled verdict and interface; an error frame rarely ends a chunk.
        let detector = &self.decoder.detector;
        let mut guess = self.guess.lock();
        *guess = Start {
            carried: CarriedState { after_error_frame: false, ..carried.clone() },
            // A worker may have seen further ahead (see publish_verdict).
            v1_seen: detector.v1_frames > 0 || guess.v1_seen,
            v2_seen: detector.v2_frames > 0 || guess.v2_seen,
        };
        drop(guess);
        if let Some(stop) = &outcome.stop {
            let message = match stop.line {
                Some(line) => format!("{}:{}: {}", self.name, base + line, stop.message),
                None => stop.message.clone(),
            };
            return Err(Failure::data(message).into());
        }
        match chunk.read_error.take() {
            Some(error) => Err(read_error(error, self.name)),
            None => Ok(()),
        }
    }

    /// The chunk's partial summary merged into the run's; one that cannot be merged exactly (see
    /// [`Summary::can_absorb`]: rare) is decoded again here into events and replayed.
    fn absorb(&mut self, chunk: &mut Chunk, truth: &Start) -> Result<()> {
        if let Sink::Summary(summary) = &mut self.decoder.sink {
            if summary.can_absorb(&chunk.summary) {
                summary.absorb(&chunk.summary);
                return Ok(());
            }
        }
        let settings =
            Settings { record: true, partial: false, summary_only: false, ..self.settings.clone() };
        decode_chunk(&settings, truth, chunk);
        self.replay(&chunk.events)
    }

    /// The chunk's events, delivered as one thread delivers them (the workers counted and filtered them).
    fn replay(&mut self, events: &Events) -> Result<()> {
        let decoder = &mut *self.decoder;
        let workers_wrote = self.settings.writer.is_some();
        // Events nearly all share one interface: its name is looked up when it changes.
        let (mut named, mut name) = (u32::MAX, "");
        for replay in &events.list {
            if replay.iface != named {
                (named, name) = (replay.iface, events.name(replay.iface));
            }
            let ts = match replay.stamp {
                Stamp::Given(ts) => ts,
                Stamp::Summed(sum) => Some({ self.deltas }.add(sum.secs, sum.nanos)),
            };
            let frame = FrameRef::Can(&replay.frame);
            let event = Event { ts, iface: name, dir: replay.dir, frame, decoded: replay.decoded };
            match &mut decoder.sink {
                Sink::Summary(summary) => summary.event(&event),
                // The workers wrote the output: only the plot is left.
                Sink::Lines { .. } if workers_wrote => {}
                // MCAP: the workers parse and decode, this thread writes the container (and the plot).
                Sink::Lines { .. } | Sink::Mcap(_) => {
                    decoder.deliver(&event)?;
                    continue;
                }
            }
            if let Some(plot) = &mut decoder.plot {
                plot.event(&event);
            }
        }
        let sum = events.deltas.total();
        self.deltas.add(sum.secs, sum.nanos);
        Ok(())
    }

    /// The chunk's rejections, said and counted as if they had come one by one.
    fn tally(&mut self, base: u64, outcome: &Outcome) {
        let tally = &mut self.decoder.stats.rejected;
        for reject in &outcome.shown {
            let location = format!("{}:{}", self.name, base + reject.line);
            let (message, reason, length) = (reject.message.as_str(), reject.reason, reject.length);
            if let Some(note) =
                tally.reject(Rejected { location: &location, message, reason, length, in_lines: true })
            {
                crate::say!("tracerctl: {note}");
            }
        }
        // Past the shown ones nothing more is said: only the counts, longest lines and first places.
        for reject in &outcome.counted {
            match tally.rejected.iter_mut().find(|known| known.reason == reject.reason) {
                Some(known) => {
                    known.count += reject.count;
                    known.longest = known.longest.max(reject.length);
                }
                None => tally.rejected.push(Rejection {
                    reason: reject.reason.to_string(),
                    count: reject.count,
                    first_at: format!("{}:{}", self.name, base + reject.line),
                    longest: reject.length,
                    in_lines: true,
                }),
            }
        }
    }
}

/// A worker's part of the guess: V1-only or V2-only frames in its chunk were seen before every chunk taken
/// after it (chunks are taken in order), so those start with the right verdict before this chunk is merged
/// (without it, every chunk taken before the first merge would be decoded twice). A guess is only a guess:
/// [`settle`] checks it.
fn publish_verdict(guess: &Mutex<Start>, outcome: &Outcome) {
    let (v1, v2) = (outcome.v1_frames > 0, outcome.v2_frames > 0);
    if v1 || v2 {
        let mut guess = guess.lock();
        guess.v1_seen |= v1;
        guess.v2_seen |= v2;
    }
}

/// Decodes the chunk again from `truth` when it was decoded from another start. Returns whether it did.
fn settle(settings: &Settings, chunk: &mut Chunk, truth: &Start) -> bool {
    if chunk.outcome.start == *truth {
        return false;
    }
    decode_chunk(settings, truth, chunk);
    true
}

/// Where the reader cuts chunks.
#[derive(Clone, Copy)]
struct Cut {
    chunk_bytes: usize,
    /// After every read that ends a line, not only after `chunk_bytes` (a stream).
    stream: bool,
}

/// Cuts the input into chunks of about `chunk_bytes` ending after a `\n` (or at the end), numbered in order.
/// A line longer than the line limit is kept only up to one byte past it, with its true length beside.
struct Splitter<R> {
    reader: R,
    cut: Cut,
    /// The unfinished last line of the previous read, and its true length when it was cut short.
    carry: Vec<u8>,
    carry_long: Option<usize>,
    next_index: u64,
    ended: bool,
}

impl<R: Read> Splitter<R> {
    fn new(reader: R, cut: Cut) -> Self {
        Self { reader, cut, carry: Vec::new(), carry_long: None, next_index: 0, ended: false }
    }

    /// Fills `chunk` with the next chunk. Returns whether it holds anything to decode (lines, or a read
    /// error); past the end of the input, nothing.
    fn next_chunk(&mut self, chunk: &mut Chunk) -> bool {
        if self.ended {
            return false;
        }
        chunk.index = self.next_index;
        self.next_index += 1;
        chunk.input.clear();
        chunk.long_lines.clear();
        chunk.input.extend_from_slice(&self.carry);
        let mut long = self.carry_long.take();
        let (last_newline, eof) = fill(&mut self.reader, chunk, self.cut, &mut long);
        self.carry.clear();
        if eof {
            self.ended = true;
            if let Some(length) = long.take() {
                chunk.long_lines.push((last_newline.map_or(0, |at| at + 1), length));
            }
        } else if let Some(at) = last_newline {
            self.carry.extend_from_slice(&chunk.input[at + 1..]);
            chunk.input.truncate(at + 1);
            self.carry_long = long.take();
        }
        let keep = DEFAULT_MAX_LINE_LEN + 1;
        chunk.bytes = chunk.input.len() as u64
            + chunk.long_lines.iter().map(|&(_, length)| (length - keep) as u64).sum::<u64>();
        !chunk.input.is_empty() || chunk.read_error.is_some()
    }
}

/// The reader thread of a stream: chunks from the pool, filled, to the workers' queue.
fn split(
    mut splitter: Splitter<impl Read>,
    pool: mpsc::Receiver<Chunk>,
    work: mpsc::Sender<Chunk>,
    finished: &AtomicBool,
) {
    while !splitter.ended {
        let Ok(mut chunk) = pool.recv() else { return };
        if finished.load(Ordering::Relaxed) {
            return;
        }
        if splitter.next_chunk(&mut chunk) && work.send(chunk).is_err() {
            return;
        }
    }
}

/// Where the workers get their chunks.
enum Source<R> {
    /// A stream: from the reader thread, whose reads may block for as long as the stream is quiet.
    Queue(Mutex<mpsc::Receiver<Chunk>>),
    /// A file through its decompressor (or a plain one whose handle could not be shared): each worker reads
    /// its next chunk itself, one worker at a time (no reader thread to hand chunks over: 2-7 % less time,
    /// measured in docs/performance.md).
    File { splitter: Mutex<Splitter<R>>, pool: Mutex<mpsc::Receiver<Chunk>> },
    /// A plain file: each worker claims the next range and reads it itself, as it decodes it.
    Ranges { ranges: Arc<Ranges>, pool: Mutex<mpsc::Receiver<Chunk>> },
}

/// Why a worker got no chunk.
enum Idle {
    /// Nothing yet: look again (unless decoding ended).
    NotYet,
    /// The input ended or the others stopped.
    Ended,
}

impl<R: Read> Source<R> {
    /// The next chunk, with the start its first line is guessed to be decoded from.
    fn take(&self, guess: &Mutex<Start>) -> Result<(Chunk, Start), Idle> {
        let received = match self {
            Source::Queue(work) => work.lock().recv_timeout(WAKE),
            Source::File { pool, .. } | Source::Ranges { pool, .. } => pool.lock().recv_timeout(WAKE),
        };
        let mut chunk = match received {
            Ok(chunk) => chunk,
            Err(RecvTimeoutError::Timeout) => return Err(Idle::NotYet),
            Err(RecvTimeoutError::Disconnected) => return Err(Idle::Ended),
        };
        if let Source::Ranges { ranges, .. } = self {
            // Guessed before the range is let go: only ranges before this one can have published their verdict.
            let Some(range) = ranges.claim_with(|| guess.lock().clone()) else { return Err(Idle::Ended) };
            chunk.index = range.0.index;
            chunk.range = Some(range.0);
            return Ok((chunk, range.1));
        }
        if let Source::File { splitter, .. } = self {
            let mut splitter = splitter.lock();
            if !splitter.next_chunk(&mut chunk) {
                return Err(Idle::Ended);
            }
            // Guessed while the file is held: only chunks before this one can have published their verdict.
            return Ok((chunk, guess.lock().clone()));
        }
        Ok((chunk, guess.lock().clone()))
    }
}

/// Reads into `chunk.input` until it holds `chunk_bytes` and a `\n`, or the end. `long` is the true length
/// of the open line when it was cut short. Returns the last `\n`'s offset and whether the input ended.
fn fill(
    reader: &mut impl Read,
    chunk: &mut Chunk,
    cut: Cut,
    long: &mut Option<usize>,
) -> (Option<usize>, bool) {
    let (keep, chunk_bytes) = (DEFAULT_MAX_LINE_LEN + 1, cut.chunk_bytes);
    let mut last_newline: Option<usize> = None;
    let mut eof = false;
    while !(last_newline.is_some() && (cut.stream || chunk.input.len() >= chunk_bytes)) {
        let old = chunk.input.len();
        let read = if cut.stream {
            // Whatever one read returns: a live stream's lines go out as they come.
            chunk.input.resize(old + chunk_bytes, 0);
            let read = reader.read(&mut chunk.input[old..]);
            chunk.input.truncate(old + *read.as_ref().unwrap_or(&0));
            read
        } else {
            // A file: up to a chunk at once, read into the buffer's spare room without zeroing it first
            // (zeroing 256 KiB per chunk cost as much as the reading).
            let mut limited = Read::take(&mut *reader, chunk_bytes as u64);
            limited.read_to_end(&mut chunk.input)
        };
        // Bytes read before an error are taken as a read of their own, then the error ends the input.
        let (read, error) = match read {
            Ok(_) => (chunk.input.len() - old, None),
            Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
            Err(error) => (chunk.input.len() - old, Some(error)),
        };
        if read == 0 {
            if let Some(error) = error {
                read_failed(chunk, last_newline, long, error);
            }
            eof = true;
            break;
        }
        let open = last_newline.map_or(0, |at| at + 1);
        if let Some(length) = long.as_mut() {
            // The open line is cut short: its further bytes are only counted, up to its newline.
            let cut = open + keep;
            match memchr(b'\n', &chunk.input[old..]) {
                Some(at) => {
                    *length += at;
                    chunk.input.drain(cut..old + at);
                    chunk.long_lines.push((open, *length));
                    *long = None;
                }
                None => {
                    *length += read;
                    chunk.input.truncate(cut);
                    if let Some(error) = error {
                        read_failed(chunk, last_newline, long, error);
                        eof = true;
                        break;
                    }
                    continue;
                }
            }
        }
        let searched_from = old.min(chunk.input.len());
        if let Some(at) = memrchr(b'\n', &chunk.input[searched_from..]) {
            last_newline = Some(searched_from + at);
        }
        let open = last_newline.map_or(0, |at| at + 1);
        if chunk.input.len() - open > keep {
            *long = Some(chunk.input.len() - open);
            chunk.input.truncate(open + keep);
        }
        if let Some(error) = error {
            read_failed(chunk, last_newline, long, error);
            eof = true;
            break;
        }
    }
    (last_newline, eof)
}

/// As the line reader: the lines read before the error count, the unfinished one does not.
fn read_failed(chunk: &mut Chunk, last_newline: Option<usize>, long: &mut Option<usize>, error: io::Error) {
    chunk.input.truncate(last_newline.map_or(0, |at| at + 1));
    chunk.read_error = Some(error);
    *long = None;
}

/// Decodes one chunk from `start` into its output (or events), as [`Decoder::candump`] decodes lines: its
/// text, or the lines of its range read now.
fn decode_chunk(settings: &Settings, start: &Start, chunk: &mut Chunk) {
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
                match piece {
                    Piece::Lines(text) => decode_lines(&mut lines, &mut parser, text, &[]),
                    Piece::TooLong(length) => {
                        lines.outcome.lines += 1;
                        lines.too_long(lines.outcome.lines, length);
                    }
                }
                lines.outcome.stop.is_none()
            });
            if end.reread {
                return true;
            }
            chunk.bytes = end.bytes;
            chunk.read_error = end.error;
        }
        _ => decode_lines(&mut lines, &mut parser, &chunk.input, &chunk.long_lines),
    }
    let mut outcome = lines.outcome;
    outcome.v1_frames = lines.detector.v1_frames - u64::from(start.v1_seen);
    outcome.v2_frames = lines.detector.v2_frames - u64::from(start.v2_seen);
    outcome.end = parser.carried();
    chunk.events.deltas = parser.delta_sum();
    chunk.outcome = outcome;
    false
}

// Long: the line loop of Decoder::candump with its arms (and the -t d one), kept in one piece like that one.
/// Decodes whole lines (`long_lines`: those the reader cut short, by offset, with their true length) until
/// the end of `input` or a stop.
fn decode_lines(
    lines: &mut ChunkLines<'_>,
    parser: &mut LineParser,
    input: &[u8],
    long_lines: &[(usize, usize)],
) {
    let settings = lines.settings;
    let mut long_lines = long_lines.iter().peekable();
    let mut at = 0;
    while at < input.len() {
        lines.outcome.lines += 1;
        let number = lines.outcome.lines;
        // Nearly every line: the common log line, whose end parsing it finds (no search for the `\n` first).
        // A line the reader cut short is never one (it is longer than the limit).
        if long_lines.peek().is_none_or(|&&(offset, _)| offset != at) {
            if let Some((record, length)) = parser.parse_log_line_at(&input[at..]) {
                at += length + 1;
                lines.decoded(number, Stamp::Given(record.ts), record.iface, record.dir, record.frame);
                if lines.outcome.stop.is_some() {
                    break;
                }
                continue;
            }
        }
        let end = memchr(b'\n', &input[at..]).map_or(input.len(), |offset| at + offset);
        let text = &input[at..end];
        let line_start = at;
        at = end + 1;
        let too_long = match long_lines.next_if(|&&(offset, _)| offset == line_start) {
            Some(&(_, length)) => Some(length),
            None => (text.len() > DEFAULT_MAX_LINE_LEN).then_some(text.len()),
        };
        if let Some(length) = too_long {
            lines.too_long(number, length);
        } else {
            let deltas_before = parser.delta_sum().added();
            match parser.parse(text) {
                Ok(Line::Frame(record)) if settings.record => {
                    lines.outcome.decoded_lines += 1;
                    // Interned first: the record borrows the parser, which is asked about its sum next.
                    let iface = Iface::Interned(lines.events.intern(record.iface));
                    let (ts, dir, frame) = (record.ts, record.dir, record.frame);
                    let stamp = match ts {
                        Some(sum) if parser.delta_sum().added() != deltas_before => Stamp::Summed(sum),
                        ts => Stamp::Given(ts),
                    };
                    if let Some(message) = lines.frame(stamp, iface, dir, &frame) {
                        lines.outcome.stop = Some(Stop { line: Some(number), message });
                    }
                }
                Ok(Line::Frame(record)) => {
                    lines.decoded(number, Stamp::Given(record.ts), record.iface, record.dir, &record.frame)
                }
                Ok(other) => lines.skipped(number, other),
                Err(error) => lines.unparsed(number, text, error),
            }
        }
        if lines.outcome.stop.is_some() {
            break;
        }
    }
}

/// A worker's decoder of lines: [`Decoder`]'s line handling, with counts and messages kept for the merge.
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
    /// As [`Decoder::frame`] and [`Decoder::event`]; returns the `--strict` message of an invalid frame.
    #[inline(always)]
    fn frame(
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

    /// A frame line (line `number` of the chunk) whose stamp needs no `-t d` sum.
    #[inline(always)]
    fn decoded(&mut self, number: u64, stamp: Stamp, iface: &str, dir: Option<Direction>, frame: &CanFrame) {
        self.outcome.decoded_lines += 1;
        let iface = self.iface(iface);
        if let Some(message) = self.frame(stamp, iface, dir, frame) {
            self.outcome.stop = Some(Stop { line: Some(number), message });
        }
    }

    /// `iface` as [`Self::frame`] takes it: interned when the events are kept.
    fn iface<'n>(&mut self, iface: &'n str) -> Iface<'n> {
        match self.settings.record {
            true => Iface::Interned(self.events.intern(iface)),
            false => Iface::Name(iface),
        }
    }

    /// As [`Decoder::skipped_line`].
    #[inline(never)]
    fn skipped(&mut self, number: u64, line: Line<'_>) {
        let skipped = &mut self.outcome.skipped;
        match line {
            Line::Frame(_) => {}
            Line::Blank => skipped.blank += 1,
            Line::Comment => skipped.comment += 1,
            Line::DropCount { dropped } => {
                skipped.dropcount += 1;
                self.outcome.candump_dropped = self.outcome.candump_dropped.saturating_add(dropped);
            }
            Line::ErrorText => skipped.error_text += 1,
            Line::CanXl => {
                skipped.can_xl += 1;
                if self.settings.strict {
                    let message = super::CAN_XL_NOT_SUPPORTED.to_string();
                    self.outcome.stop = Some(Stop { line: Some(number), message });
                }
            }
        }
    }

    /// As [`Decoder::unparsed_line`].
    #[inline(never)]
    fn unparsed(&mut self, number: u64, text: &[u8], error: candump::LineError) {
        let bare = text.trim_ascii();
        let looks_bare = bare.contains(&b'#') && !bare.iter().any(u8::is_ascii_whitespace);
        match candump::parse_cansend(bare) {
            Ok(frame) => {
                self.outcome.decoded_lines += 1;
                let iface = self.iface("-");
                if let Some(message) = self.frame(Stamp::Given(None), iface, None, &frame) {
                    // The single thread says this one without the place, too.
                    self.outcome.stop = Some(Stop { line: None, message });
                }
            }
            Err(frame_error) if looks_bare => {
                let message = format!("bare frame: {frame_error}");
                self.rejected(number, message, frame_error.reason.as_str(), None);
            }
            Err(_) => self.rejected(number, error.to_string(), error.reason.as_str(), None),
        }
    }

    /// Line `number`, longer than the line limit (`length` bytes without its `\n`).
    #[inline(never)]
    fn too_long(&mut self, number: u64, length: usize) {
        let message = candump::line_too_long(length);
        self.rejected(number, message, Reason::LineTooLong.as_str(), Some(length as u64));
    }

    /// As [`Decoder::rejected_line`]: kept to be said in order, or the stop with `--strict`.
    fn rejected(&mut self, line: u64, message: String, reason: &'static str, length: Option<u64>) {
        let outcome = &mut self.outcome;
        outcome.rejected_lines += 1;
        if self.settings.strict {
            outcome.stop = Some(Stop { line: Some(line), message });
            return;
        }
        if outcome.shown.len() <= MAX_SHOWN_REJECTS {
            outcome.shown.push(Reject { line, message, reason, length, count: 1 });
            return;
        }
        match outcome.counted.iter_mut().find(|known| known.reason == reason) {
            Some(known) => {
                known.count += 1;
                known.length = known.length.max(length);
            }
            None => outcome.counted.push(Reject { line, message: String::new(), reason, length, count: 1 }),
        }
    }
}

/// The input as the workers read it: every read looks at the stop first, so a worker inside an endless line
/// (a decompression bomb of zeros, which it reads on to its `\n`) lets go at a signal.
struct Stopping<R> {
    inner: R,
    stop: StopReading,
}

impl<R: Read> Read for Stopping<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.stop.now() {
            return Err(io::Error::other(Interrupted));
        }
        self.inner.read(buf)
    }
}

/// Where a plain file's text starts: after a UTF-8 byte-order mark (as [`candump::open_log`] reads it).
fn byte_order_mark(file: &File) -> u64 {
    let mut head = [0u8; 3];
    match super::positioned::read_at(file, &mut head, 0) {
        Ok(3) if head == *candump::UTF8_BOM => 3,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::TextFormat;
    use crate::output::Format;

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
        Chunk { input: text.to_vec(), ..Chunk::default() }
    }

    /// Gives its bytes `step` at a time, then fails (a disk that goes away mid-file).
    struct FailingAfter {
        data: &'static [u8],
        at: usize,
        step: usize,
    }

    impl Read for FailingAfter {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.at == self.data.len() {
                return Err(io::Error::other("the disk went away"));
            }
            let n = self.step.min(buf.len()).min(self.data.len() - self.at);
            buf[..n].copy_from_slice(&self.data[self.at..self.at + n]);
            self.at += n;
            Ok(n)
        }
    }

    /// As the line reader: whole lines read before an error count, the unfinished one does not, whether the
    /// bytes came in one read or many (files are read a chunk at a time, streams a read at a time).
    #[test]
    fn a_read_error_keeps_the_whole_lines_read_before_it() {
        for stream in [false, true] {
            for step in [1, 5, 64, 4096] {
                let mut reader = FailingAfter { data: b"a 1\nb 2\nc 3\npartial", at: 0, step };
                let mut chunk = Chunk::default();
                let mut long = None;
                let cut = Cut { chunk_bytes: 1 << 16, stream };
                let mut ended = false;
                let mut input = Vec::new();
                while !ended {
                    // As `split`: a chunk ends after its last newline, the rest opens the next one.
                    let (last_newline, eof) = fill(&mut reader, &mut chunk, cut, &mut long);
                    let end = if eof { chunk.input.len() } else { last_newline.map_or(0, |at| at + 1) };
                    input.extend_from_slice(&chunk.input[..end]);
                    chunk.input.drain(..end);
                    ended = eof;
                }
                assert_eq!(input, b"a 1\nb 2\nc 3\n", "stream {stream}, step {step}");
                let error = chunk.read_error.as_ref().map(|error| error.to_string());
                assert_eq!(error.as_deref(), Some("the disk went away"), "stream {stream}, step {step}");
            }
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

    fn split_all(text: &[u8], chunk_bytes: usize) -> Vec<Chunk> {
        let (pool_tx, pool_rx) = mpsc::channel();
        let (work_tx, work_rx) = mpsc::channel();
        for _ in 0..10_000 {
            pool_tx.send(Chunk::default()).unwrap();
        }
        let cut = Cut { chunk_bytes, stream: false };
        split(Splitter::new(text, cut), pool_rx, work_tx, &AtomicBool::new(false));
        work_rx.iter().collect()
    }

    #[test]
    fn chunks_end_after_a_newline_and_hold_every_byte() {
        let text = b"a\r\nbb\n\nccc\nlast";
        for chunk_bytes in 1..20 {
            let chunks = split_all(text, chunk_bytes);
            let joined: Vec<u8> = chunks.iter().flat_map(|chunk| chunk.input.clone()).collect();
            assert_eq!(joined, text, "chunk size {chunk_bytes}");
            for chunk in &chunks[..chunks.len() - 1] {
                assert_eq!(chunk.input.last(), Some(&b'\n'), "chunk size {chunk_bytes}");
            }
            assert_eq!(chunks.iter().map(|c| c.bytes).sum::<u64>(), text.len() as u64);
        }
        assert!(split_all(b"", 4).is_empty());
    }

    #[test]
    fn an_overlong_line_is_cut_short_with_its_length() {
        let long = DEFAULT_MAX_LINE_LEN * 3 + 5;
        let mut text = b"ok\n".to_vec();
        text.extend(std::iter::repeat_n(b'x', long));
        text.extend_from_slice(b"\nfine\n");
        text.extend(std::iter::repeat_n(b'y', long));
        for chunk_bytes in [1000, 70_000, 1 << 20] {
            let chunks = split_all(&text, chunk_bytes);
            let longs: Vec<usize> =
                chunks.iter().flat_map(|c| c.long_lines.iter().map(|&(_, len)| len)).collect();
            // Only the line still open when a read ends is cut; one read of all holds the first whole.
            let expected = if chunk_bytes > text.len() { vec![long] } else { vec![long, long] };
            assert_eq!(longs, expected, "chunk size {chunk_bytes}");
            assert!(chunks.iter().all(|c| c.input.len() <= chunk_bytes.max(DEFAULT_MAX_LINE_LEN) * 3));
            assert_eq!(chunks.iter().map(|c| c.bytes).sum::<u64>(), text.len() as u64);
        }
    }
}
