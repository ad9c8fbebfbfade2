//! `decode -j N`: a text log (candump, Vector ASC, PEAK trc; a file or a stream, plain or compressed) decoded
//! by N threads, written byte for byte as one thread would.
//!
//! A plain file is cut into ranges of whole lines that each worker reads itself as it decodes them, through
//! windows mapped into memory (`mapped.rs`) or with positioned reads into a small buffer of its own
//! ([`Ranges`]). Other input is cut into chunks that end after a `\n` ([`Splitter`]): a worker reads the next
//! chunk of a compressed file itself, one worker at a time, and a stream's chunks come from a reader thread.
//! Workers decode each chunk into its own output buffer with the line counts, rejections and stop
//! (`--strict`) it found, numbered within the chunk; this thread takes the chunks back in input order, writes
//! their output, and replays their counts and messages with the chunk's first line number, which is known
//! only then. Chunks travel in a fixed pool, so memory is bounded by the pool (threads x chunk size),
//! whatever the size of the input.
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
//!
//! With `--strict` a worker stops its chunk at the first bad line; this thread writes that chunk's output up
//! to there and fails with the message one thread gives, and the chunks after it are dropped. A chunk that
//! never comes back once every worker has ended is an error (`internal error: chunk N of FILE was lost`),
//! never a silent gap. RS232 captures (a byte stream with no lines to cut at) and frames given as arguments
//! stay on one thread.
//!
//! The parts: `settings.rs` (what every worker decodes with), `source.rs` (where chunks come from),
//! `worker.rs` (a chunk through the line loop of `../lines.rs` into the chunk recorder) and `merger.rs`
//! (chunks back in input order); a plain file is read by `../ranges.rs` and `../mapped.rs`, other input cut
//! by `../splitter.rs`.

mod merger;
mod settings;
mod source;
mod worker;

use std::fs::File;
use std::io::Read;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Result;
use parking_lot::Mutex;

use super::interrupt::StopReading;
use super::ranges::{Ranges, Sizing, SLICE_BYTES, WINDOW_BYTES};
use super::splitter::{Cut, Splitter};
use super::{Decoder, Sink};
use crate::candump::{self, DeltaSum, LineParser, LogFormat};
use merger::Merger;
use settings::{Settings, Start};
use source::{split, Idle, Source, Stopping};
use worker::{decode_chunk, publish_verdict, Chunk};

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

/// Decodes `reader` (the text of a regular file or of standard input, decompressed, after
/// [`candump::open_log`]) with the decoder's threads. A `stream` (standard input, a pipe) is cut into chunks
/// at whatever each read returns, so a live stream's lines are written as soon as they arrive.
#[expect(clippy::too_many_lines, reason = "the threads' set-up, each a few lines, reads best in one place.")]
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
            let windows = decoder.mapping.map(|handler| (handler, window_bytes));
            let ranges =
                Ranges::new(file, text_start, size, sizing, (slice_bytes, windows)).stopping(stop.clone());
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

/// Where a plain file's text starts: after a UTF-8 byte-order mark (as [`candump::open_log`] reads it).
fn byte_order_mark(file: &File) -> u64 {
    let mut head = [0u8; 3];
    match super::positioned::read_at(file, &mut head, 0) {
        Ok(3) if head == *candump::UTF8_BOM => 3,
        _ => 0,
    }
}
