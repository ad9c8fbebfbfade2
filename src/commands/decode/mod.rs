//! `tracerctl decode`: candump logs, single frames and RS232 captures to text, JSON, CSV or a summary.
//!
//! Streams every input with flat memory: one line buffer, one output buffer, no allocation per line.

mod interrupt;
#[cfg(unix)]
mod mapped;
// No mapping elsewhere: the workers read by position (ranges.rs).
#[cfg(not(unix))]
#[path = "unmapped.rs"]
mod mapped;
mod parallel;
mod plot;
mod positioned;
mod ranges;
mod serial_input;
pub mod summary;

use std::cell::RefCell;
use std::fs::File;
use std::io::{self, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use super::same_file::{self, Named};
use super::Global;
use crate::candump::{
    self, Line, LineParser, LineReader, LogFormat, RawLine, Reason, RejectTally, Rejected, Rejection,
};
use crate::exit::{Failure, SUCCESS, USAGE};
use crate::output::filter::Filter;
use crate::output::mcap::{Compression as McapCompression, McapWriter, Provenance};
use crate::output::{Event, EventWriter, Format, FrameRef};
use crate::protocol::can::EXAMPLE_FRAME;
use crate::protocol::detect::{ProtocolDetector, Verdict};
use crate::protocol::{self, CanFrame, ProtocolHint};
use crate::signals::SignalFlag;
use summary::Summary;

/// Output is written in blocks of about this size.
const FLUSH_AT: usize = 64 * 1024;
/// What `--strict` says of a CAN XL frame, after the place.
const CAN_XL_NOT_SUPPORTED: &str = "CAN XL frame: not supported";
/// Files at least this large get a progress bar (on a terminal).
const PROGRESS_MIN_BYTES: u64 = 8 * 1024 * 1024;

/// `tracerctl decode`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// candump logs, `-` for standard input, or frames in cansend syntax.
    pub inputs: Vec<String>,
    /// RS232 captures (raw bytes or hex text).
    pub serial: Vec<PathBuf>,
    pub format: Format,
    /// A report instead of every frame.
    pub summary: bool,
    /// Stop at the first bad line, bad frame or corrupted serial frame.
    pub strict: bool,
    /// Only frames with these identifiers (none: all).
    pub ids: Vec<crate::protocol::FrameId>,
    /// Only these message names (none: all).
    pub messages: Vec<&'static str>,
    /// Console timestamps are deltas between frames.
    pub delta_stamps: bool,
    /// Never show a progress bar.
    pub no_progress: bool,
    /// Also draw the plot into this SVG file.
    pub plot: Option<PathBuf>,
    /// Threads decoding text logs (candump, ASC, trc), files or standard input (1: the single-thread path; see
    /// parallel.rs).
    pub threads: usize,
    /// Input bytes per parallel chunk (default: by mode, see [`parallel::CHUNK_BYTES`]; tests make it tiny).
    pub chunk_bytes: Option<usize>,
    /// Write to this file instead of standard output.
    pub output: Option<PathBuf>,
    /// MCAP output (into `output`, a seekable file) with this chunk compression, instead of `format`.
    pub mcap: Option<McapCompression>,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let (serial, protocol, color) = (args.serial.as_slice(), global.protocol, global.color);
    check_arguments(args)?;
    let signals = interrupt::listen()?;
    let stdout = io::stdout();
    let stdout_is_terminal = stdout.is_terminal();
    let color = color.enabled(stdout_is_terminal && args.output.is_none());
    let sink = if args.summary {
        Sink::Summary(Box::default())
    } else if let (Some(compression), Some(path)) = (args.mcap, &args.output) {
        Sink::Mcap(Some(Box::new(McapOutput::create(path, compression, &args.inputs, serial)?)))
    } else {
        let writer = EventWriter::new(args.format, color);
        let mut buffer = Vec::with_capacity(FLUSH_AT * 2);
        writer.header(&mut buffer);
        let output = match &args.output {
            Some(path) => {
                let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
                let out = Box::new(io::BufWriter::new(file));
                Output { buffer, out, line_buffered: false, name: path.display().to_string(), failed: false }
            }
            None => {
                let (out, name) = (Box::new(stdout.lock()), "standard output".to_string());
                Output { buffer, out, line_buffered: stdout_is_terminal, name, failed: false }
            }
        };
        Sink::Lines { writer, output: Rc::new(RefCell::new(output)) }
    };
    let mut decoder = Decoder {
        protocol,
        detector: ProtocolDetector::default(),
        seen: ProtocolDetector::default(),
        filter: Filter::new(&args.ids, &args.messages),
        sink,
        stats: InputStats::default(),
        strict: args.strict,
        delta_stamps: args.delta_stamps,
        progress: !args.no_progress && io::stderr().is_terminal(),
        plot: args.plot.as_ref().map(|_| Box::default()),
        signals,
        threads: args.threads,
        chunk_bytes: args.chunk_bytes,
        frameless: Vec::new(),
    };

    let mut inputs: Vec<&str> = args.inputs.iter().map(String::as_str).collect();
    if inputs.is_empty() && serial.is_empty() {
        if io::stdin().is_terminal() {
            crate::say!(
                "tracerctl: no input: give a candump log, '-' for standard input, \
                 or a frame such as {EXAMPLE_FRAME} (see tracerctl decode --help)"
            );
            return Ok(USAGE);
        }
        inputs.push("-");
    }
    let result = decoder.all_inputs(&inputs, serial);
    if let Some(status) = decoder.signals.exit_status() {
        // Interrupted (Ctrl-C, kill): what was decoded is written, with the totals, before exiting 128+n.
        decoder.write_out_or_say(args);
        crate::say!("tracerctl: {}: {}", decoder.signals.name(), totals_line(&decoder.stats));
        return Ok(status);
    }
    decoder.finish(args, result)
}

/// Usage errors found before any input is read.
fn check_arguments(args: &Options) -> Result<()> {
    if args.summary && args.format == crate::output::Format::Csv {
        return Err(Failure {
            code: USAGE,
            message: "--summary prints a report as text or JSON (--format text or json), not CSV".into(),
        }
        .into());
    }
    if let Some(path) = &args.plot {
        plot::check_path(path)?;
    }
    // Before any output is created: an output that is an input would be emptied before it is read.
    let input = |path| Named { option: "the input", path };
    let mut inputs: Vec<Named> = args.inputs.iter().map(|name| input(Path::new(name))).collect();
    if args.inputs.is_empty() && args.serial.is_empty() {
        inputs.push(input(Path::new("-")));
    }
    inputs.extend(args.serial.iter().map(|path| Named { option: "--serial", path }));
    let outputs = [("-o", &args.output), ("--plot", &args.plot)];
    let outputs: Vec<Named> =
        outputs.iter().filter_map(|(option, path)| Some(Named { option, path: path.as_deref()? })).collect();
    same_file::refuse_overwriting(&inputs, &outputs)
}

/// The decoded text not yet written. Shared with [`LiveInput`], which writes it out before each read of
/// the input, so a live stream leaves line by line while bulk input still goes out in large blocks.
struct Output {
    buffer: Vec<u8>,
    out: Box<dyn Write>,
    /// Every event is written at once (standard output is a terminal).
    line_buffered: bool,
    /// The file's path, or `standard output`, for messages.
    name: String,
    /// A write failed (a full disk): the error was returned once, and nothing more is written.
    failed: bool,
}

impl Output {
    fn flush(&mut self) -> io::Result<()> {
        if self.failed {
            return Ok(());
        }
        self.write_through(&[])?;
        self.out.flush().map_err(|error| self.failure(error))
    }

    /// Writes what is buffered, then `bytes` straight through (a decoded chunk: no copy into the buffer).
    fn write_through(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.failed {
            return Ok(());
        }
        if !self.buffer.is_empty() {
            let result = self.out.write_all(&self.buffer);
            self.buffer.clear();
            result.map_err(|error| self.failure(error))?;
        }
        self.out.write_all(bytes).map_err(|error| self.failure(error))?;
        if self.line_buffered {
            self.out.flush().map_err(|error| self.failure(error))?;
        }
        Ok(())
    }

    /// `error` with the output's name; the output is given up.
    fn failure(&mut self, error: io::Error) -> io::Error {
        self.failed = true;
        io::Error::new(error.kind(), OutputFailed { name: self.name.clone(), error })
    }
}

/// A failed write of the output, naming it: `cannot write out.csv: No space left on device (os error 28)`.
/// Inside an `io::Error` of the same kind, so a closed pipe is still told apart (and stays quiet).
#[derive(Debug, thiserror::Error)]
#[error("cannot write {name}: {error}")]
struct OutputFailed {
    name: String,
    error: io::Error,
}

enum Sink {
    Lines {
        writer: EventWriter,
        output: Rc<RefCell<Output>>,
    },
    Summary(Box<Summary>),
    /// `None` once finished.
    Mcap(Option<Box<McapOutput>>),
}

/// `--format mcap`: the writer and the file's name for messages.
struct McapOutput {
    writer: McapWriter<io::BufWriter<File>>,
    path: PathBuf,
}

impl McapOutput {
    fn create(
        path: &Path,
        compression: McapCompression,
        inputs: &[String],
        serial: &[PathBuf],
    ) -> Result<Self> {
        let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
        let mut sources = inputs.to_vec();
        sources.extend(serial.iter().map(|path| path.display().to_string()));
        let provenance = Provenance { command: "decode", sources };
        let writer = McapWriter::new(io::BufWriter::new(file), compression, provenance)
            .map_err(|error| mcap_error(path, error))?;
        Ok(Self { writer, path: path.to_path_buf() })
    }
}

/// A failed write of the MCAP file, with its path and the system's reason (what was written before stays
/// readable up to the last complete chunk).
fn mcap_error(path: &Path, error: ::mcap::McapError) -> anyhow::Error {
    match error {
        ::mcap::McapError::Io(error) => anyhow::anyhow!("cannot write {}: {error}", path.display()),
        other => anyhow::anyhow!("cannot write {}: {other}", path.display()),
    }
}

/// A write of the output failed inside a read of the input (see [`LiveInput`]).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
struct WriteFailed(io::Error);

/// A termination signal arrived while reading.
#[derive(Debug, thiserror::Error)]
#[error("interrupted")]
struct Interrupted;

/// The input as the decoder reads it: before every read (which may block on a pipe, a terminal or a serial
/// port) the decoded output is written out, and a termination signal ends the reading. On a regular file
/// this costs one write per read buffer (256 KiB of input), the same blocks as before.
struct LiveInput<R> {
    inner: R,
    output: Option<Rc<RefCell<Output>>>,
    signals: SignalFlag,
}

impl<R: Read> Read for LiveInput<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            if self.signals.received().is_some() {
                return Err(io::Error::other(Interrupted));
            }
            if let Some(output) = &self.output {
                output
                    .borrow_mut()
                    .flush()
                    .map_err(|error| io::Error::new(error.kind(), WriteFailed(error)))?;
            }
            match self.inner.read(buf) {
                // A signal interrupts a blocked read (see interrupt.rs); the loop looks at the flag.
                Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
                result => return result,
            }
        }
    }
}

/// A failure while decoding line `number` of `name`, with that place in its message.
fn in_line(error: anyhow::Error, name: &str, number: u64) -> anyhow::Error {
    match error.downcast::<Failure>() {
        Ok(failure) => Failure::data(format!("{name}:{number}: {}", failure.message)).into(),
        Err(other) => other,
    }
}

/// A read error of `name`, unless it was really a failed write of the output (or a signal).
fn read_error(error: io::Error, name: &str) -> anyhow::Error {
    let inner = error.get_ref();
    if inner.is_some_and(|inner| inner.is::<WriteFailed>() || inner.is::<Interrupted>()) {
        anyhow::Error::new(error)
    } else {
        anyhow::Error::new(error).context(format!("cannot read {name}"))
    }
}

/// What happened to the input besides frames: everything that was not decoded is counted here.
/// For candump text, `decoded_lines + rejected_lines + skipped.total() == lines`.
#[derive(Debug, Default)]
pub struct InputStats {
    pub lines: u64,
    pub frames: u64,
    /// Lines that gave a frame.
    pub decoded_lines: u64,
    /// Lines that could not be read (each also counted under its reason in `rejected`).
    pub rejected_lines: u64,
    pub skipped: Skipped,
    /// Frames candump itself reported dropped (DROPCOUNT lines).
    pub candump_dropped: u64,
    /// Rejected input per reason (lines, and bytes of RS232 captures), with the first place of each.
    pub rejected: RejectTally,
    /// Frames with a TRACER ID but invalid content (V1 checksum, too short).
    pub invalid_frames: u64,
    pub serial: Vec<(String, protocol::serial::StreamStats)>,
}

/// Lines that are not frames and not errors, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Skipped {
    pub blank: u64,
    pub comment: u64,
    /// Text following a console ERRORFRAME (`-e`).
    pub error_text: u64,
    /// CAN XL frames: valid, but not decoded.
    pub can_xl: u64,
    /// candump's `DROPCOUNT:` lines (the frames they report are in `candump_dropped`).
    pub dropcount: u64,
}

impl Skipped {
    pub fn total(&self) -> u64 {
        self.blank + self.comment + self.error_text + self.can_xl + self.dropcount
    }

    /// `1 blank, 2 comment, ...`: the non-zero kinds.
    pub fn describe(&self) -> String {
        let kinds = [
            (self.blank, "blank"),
            (self.comment, "comment"),
            (self.error_text, "error-frame text"),
            (self.can_xl, "CAN XL frame"),
            (self.dropcount, "DROPCOUNT"),
        ];
        let parts: Vec<String> = kinds
            .iter()
            .filter(|(count, _)| *count > 0)
            .map(|(count, kind)| format!("{count} {kind}"))
            .collect();
        parts.join(", ")
    }
}

impl InputStats {
    pub fn rejected_total(&self) -> u64 {
        self.rejected.total()
    }

    /// Whether the totals line is worth printing after plain decoding: when anything was lost or not
    /// decoded. Blank lines, comments (every ASC and trc file has a header of them) and the text candump
    /// prints after an error frame (which is decoded) lose nothing, so a clean log stays quiet.
    fn anything_lost(&self) -> bool {
        self.rejected_total() > 0
            || self.invalid_frames > 0
            || self.candump_dropped > 0
            || self.skipped.can_xl > 0
            || self.skipped.dropcount > 0
            || self.serial.iter().any(|(_, s)| serial_losses(s))
    }

    /// Whether any input was read at all (a refused or missing first input leaves nothing to report).
    fn anything_read(&self) -> bool {
        self.lines > 0 || self.frames > 0 || !self.serial.is_empty()
    }
}

fn serial_losses(stats: &protocol::serial::StreamStats) -> bool {
    stats.skipped_bytes > 0 || stats.bad_checksum > 0 || stats.bad_length > 0 || stats.bad_type > 0
}

/// The run's counts when an input began: what the input itself added is told from them.
#[derive(Clone, Copy)]
struct InputStart {
    lines: u64,
    decoded_lines: u64,
    rejected_lines: u64,
    skipped: Skipped,
}

/// The decoding pipeline shared by every input kind.
pub struct Decoder {
    protocol: ProtocolHint,
    /// Detection within the current input.
    detector: ProtocolDetector,
    /// Totals over every finished input, for the report.
    seen: ProtocolDetector,
    filter: Filter,
    sink: Sink,
    pub stats: InputStats,
    strict: bool,
    delta_stamps: bool,
    progress: bool,
    /// `--plot`: fed every event that passes the filter, written at the end.
    plot: Option<Box<plot::Plot>>,
    signals: SignalFlag,
    threads: usize,
    /// Chosen by the mode unless a test set it ([`parallel::CHUNK_BYTES`], [`parallel::SUMMARY_CHUNK_BYTES`]).
    chunk_bytes: Option<usize>,
    /// Why each input that gave no frame gave none (`no frames in NAME: empty`).
    frameless: Vec<String>,
}

impl Decoder {
    fn all_inputs(&mut self, inputs: &[&str], serial: &[PathBuf]) -> Result<()> {
        for input in inputs {
            self.input(input)?;
        }
        for path in serial {
            let file = File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
            let name = path.display().to_string();
            serial_input::decode(self, &name, candump::WatchedFile::new(file))?;
        }
        Ok(())
    }

    /// The input as read: flushing the output before each read, stopping at a signal (see [`LiveInput`]).
    fn live<R: Read>(&self, inner: R) -> LiveInput<R> {
        let output = match &self.sink {
            Sink::Lines { output, .. } => Some(Rc::clone(output)),
            Sink::Summary(_) | Sink::Mcap(_) => None,
        };
        LiveInput { inner, output, signals: self.signals.clone() }
    }

    /// One input: a file, standard input or a frame. Each starts with a fresh protocol detector, since
    /// separate captures may come from different robots; the run's totals are kept for the report.
    fn input(&mut self, input: &str) -> Result<()> {
        let result = self.input_inner(input);
        self.seen.v1_frames += self.detector.v1_frames;
        self.seen.v2_frames += self.detector.v2_frames;
        self.detector = ProtocolDetector::default();
        result
    }

    fn input_inner(&mut self, input: &str) -> Result<()> {
        if input == "-" {
            let (reader, format) = candump::open_log(io::stdin(), "<stdin>").map_err(Failure::from)?;
            if self.parallel_fits() {
                return parallel::decode(self, "<stdin>", (reader, format), None, (true, None));
            }
            return self.candump("<stdin>", reader, None, format);
        }
        let path = Path::new(input);
        if path.exists() {
            let file = File::open(path).with_context(|| format!("cannot open {input}"))?;
            let metadata = file.metadata().ok();
            let size = metadata.as_ref().map(|m| m.len());
            let regular = metadata.is_some_and(|m| m.is_file());
            // The workers read a plain file's ranges themselves, through a handle of their own.
            let plain = file.try_clone().ok();
            // A file that shrinks while read fails where it ends (candump/shrink.rs).
            let (reader, format) =
                candump::open_log(candump::WatchedFile::new(file), input).map_err(Failure::from)?;
            // The progress bar counts text bytes: unknown for a compressed file.
            let size = size.filter(|_| format.compression.is_none());
            if regular && self.parallel_fits() {
                let plain = plain.filter(|_| format.compression.is_none());
                return parallel::decode(self, input, (reader, format), size, (false, plain));
            }
            return self.candump(input, reader, size, format);
        }
        if input.contains('#') {
            let frame = candump::parse_cansend(input.as_bytes()).map_err(|error| Failure {
                code: USAGE,
                message: format!("'{input}' is neither a file nor a valid frame: {error}"),
            })?;
            self.frame(None, "-", None, &frame)?;
            return Ok(());
        }
        bail!("{input}: no such file (frames are written like {EXAMPLE_FRAME})")
    }

    fn candump(&mut self, name: &str, input: impl Read, size: Option<u64>, format: LogFormat) -> Result<()> {
        let mut reader = LineReader::new(self.live(input));
        let parser = LineParser::for_format(format);
        let mut parser = if self.delta_stamps { parser.with_delta_timestamps() } else { parser };
        let bar = self.progress_bar(size);
        let before = self.input_start();
        let mut consumed = 0u64;
        loop {
            // The common log lines buffered: parsing each finds its end (no search for the `\n` first).
            let (first, text) = reader.whole_lines();
            let (mut lines, mut at) = (0, 0);
            while let Some((record, length)) = text.get(at..).and_then(|rest| parser.parse_log_line_at(rest))
            {
                self.stats.lines += 1;
                self.stats.decoded_lines += 1;
                self.frame(record.ts, record.iface, record.dir, record.frame)
                    .map_err(|error| in_line(error, name, first + lines))?;
                lines += 1;
                at += length + 1;
            }
            reader.consume(lines, at);
            if at > 0 {
                consumed += at as u64;
                if let Some(bar) = &bar {
                    bar.set_position(consumed);
                }
            }
            // Any other line, one at a time.
            let Some(raw) = reader.next_line().map_err(|error| read_error(error, name))? else { break };
            self.stats.lines += 1;
            let (number, text) = match raw {
                RawLine::Line { number, text } => (number, text),
                RawLine::TooLong { number, len } => {
                    consumed += len as u64 + 1;
                    let message = candump::line_too_long(len);
                    self.rejected_line(
                        name,
                        number,
                        &message,
                        Reason::LineTooLong.as_str(),
                        Some(len as u64),
                    )?;
                    continue;
                }
            };
            consumed += text.len() as u64 + 1;
            if let Some(bar) = &bar {
                if number % 65_536 == 0 {
                    bar.set_position(consumed);
                }
            }
            match parser.parse(text) {
                // The hot arm stays in the loop, the rare ones out of it (measured: docs/performance.md).
                Ok(Line::Frame(record)) => {
                    self.stats.decoded_lines += 1;
                    let frame = record.frame;
                    self.frame(record.ts, record.iface, record.dir, &frame)
                        .map_err(|error| in_line(error, name, number))?;
                }
                Ok(other) => self.skipped_line(name, number, other)?,
                Err(error) => self.unparsed_line(name, number, text, error)?,
            }
        }
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        self.note_no_frames(name, before);
        Ok(())
    }

    /// A line that is not a frame: counted by kind (a CAN XL frame is an error with --strict).
    #[inline(never)]
    fn skipped_line(&mut self, name: &str, number: u64, line: Line<'_>) -> Result<()> {
        match line {
            Line::Frame(_) => {} // decoded by the caller
            Line::Blank => self.stats.skipped.blank += 1,
            Line::Comment => self.stats.skipped.comment += 1,
            Line::DropCount { dropped } => {
                self.stats.skipped.dropcount += 1;
                self.stats.candump_dropped = self.stats.candump_dropped.saturating_add(dropped);
            }
            Line::ErrorText => self.stats.skipped.error_text += 1,
            Line::CanXl => {
                self.stats.skipped.can_xl += 1;
                if self.strict {
                    return Err(Failure::data(format!("{name}:{number}: {CAN_XL_NOT_SUPPORTED}")).into());
                }
            }
        }
        Ok(())
    }

    /// A line the log format does not read: a bare cansend frame (a file of "211#00000103000000B1" lines is
    /// read too), or a rejected line with the reason.
    #[inline(never)]
    fn unparsed_line(
        &mut self,
        name: &str,
        number: u64,
        text: &[u8],
        error: candump::LineError,
    ) -> Result<()> {
        let bare = text.trim_ascii();
        let looks_bare = bare.contains(&b'#') && !bare.iter().any(u8::is_ascii_whitespace);
        match candump::parse_cansend(bare) {
            Ok(frame) => {
                self.stats.decoded_lines += 1;
                self.frame(None, "-", None, &frame)
            }
            Err(frame_error) if looks_bare => {
                let message = format!("bare frame: {frame_error}");
                self.rejected_line(name, number, &message, frame_error.reason.as_str(), None)
            }
            Err(_) => self.rejected_line(name, number, &error.to_string(), error.reason.as_str(), None),
        }
    }

    /// The run's counts as an input begins.
    fn input_start(&self) -> InputStart {
        let stats = &self.stats;
        InputStart {
            lines: stats.lines,
            decoded_lines: stats.decoded_lines,
            rejected_lines: stats.rejected_lines,
            skipped: stats.skipped,
        }
    }

    /// Notes why a log gave no frame at all (empty, only blank lines and comments, or nothing readable).
    #[inline(never)]
    fn note_no_frames(&mut self, name: &str, before: InputStart) {
        let lines = self.stats.lines - before.lines;
        let decoded = self.stats.decoded_lines - before.decoded_lines;
        let rejected = self.stats.rejected_lines - before.rejected_lines;
        let skipped = self.stats.skipped.total() - before.skipped.total();
        let skipped_blank = self.stats.skipped.blank - before.skipped.blank;
        let skipped_comment = self.stats.skipped.comment - before.skipped.comment;
        if decoded > 0 {
            return;
        }
        let why = if lines == 0 {
            "empty".to_string()
        } else if rejected + skipped == skipped_blank + skipped_comment {
            format!("all {lines} lines blank or comments")
        } else {
            format!(
                "all {} lines rejected or skipped ({rejected} rejected, {skipped} skipped)",
                rejected + skipped
            )
        };
        self.note_frameless(format!("no frames in {name}: {why}"));
    }

    /// An input that gave no frame: the error when no input gave one, otherwise said after the output.
    pub(super) fn note_frameless(&mut self, message: String) {
        self.frameless.push(message);
    }

    fn progress_bar(&self, size: Option<u64>) -> Option<ProgressBar> {
        let size = size.filter(|size| self.progress && *size >= PROGRESS_MIN_BYTES)?;
        let bar = ProgressBar::new(size);
        let style = ProgressStyle::with_template("{bar:40} {bytes}/{total_bytes} {bytes_per_sec} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        Some(bar)
    }

    /// One CAN frame from any source.
    #[inline]
    fn frame(
        &mut self,
        ts: Option<candump::Timestamp>,
        iface: &str,
        dir: Option<candump::Direction>,
        frame: &CanFrame,
    ) -> Result<()> {
        self.stats.frames += 1;
        let decoded = self.detector.observe_and_decode(frame, self.protocol);
        if let (Sink::Summary(summary), None) = (&mut self.sink, &self.plot) {
            // The hot case of `--summary`: no event built (see [`Summary::frame`]).
            if self.filter.is_empty() && (decoded.is_ok() || !self.strict) {
                if decoded.is_err() {
                    self.stats.invalid_frames += 1;
                }
                summary.frame(ts, iface, FrameRef::Can(frame), &decoded);
                return Ok(());
            }
        }
        let event = Event { ts, iface, dir, frame: FrameRef::Can(frame), decoded };
        self.event(&event)
    }

    /// Any event: counted, filtered, then written or summarised.
    pub fn event(&mut self, event: &Event) -> Result<()> {
        if let Err(error) = event.decoded {
            self.stats.invalid_frames += 1;
            if self.strict {
                return Err(Failure::data(format!("invalid frame: {error}")).into());
            }
        }
        if !self.filter.passes(event) {
            return Ok(());
        }
        self.deliver(event)
    }

    /// An event that passed the filter: written or summarised, and plotted. Always inlined: a call per
    /// event cost the single thread's summary 1.3% (callgrind).
    #[inline(always)]
    fn deliver(&mut self, event: &Event) -> Result<()> {
        match &mut self.sink {
            Sink::Lines { writer, output } => {
                let mut output = output.borrow_mut();
                writer.write(&mut output.buffer, event);
                if output.buffer.len() >= FLUSH_AT || output.line_buffered {
                    output.flush()?;
                }
            }
            Sink::Summary(summary) => summary.event(event),
            Sink::Mcap(slot) => {
                if let Some(mcap) = slot {
                    if let Err(error) = mcap.writer.event(event) {
                        let error = mcap_error(&mcap.path, error);
                        // The file takes nothing more (a full disk): not finished, and the error said once.
                        *slot = None;
                        return Err(error);
                    }
                }
            }
        }
        if let Some(plot) = &mut self.plot {
            plot.event(event);
        }
        Ok(())
    }

    fn rejected_line(
        &mut self,
        name: &str,
        number: u64,
        message: &str,
        reason: &str,
        length: Option<u64>,
    ) -> Result<()> {
        self.stats.rejected_lines += 1;
        self.reject_at(name, &format!("line {number}"), message, reason, length)
    }

    /// Reports a rejected piece of input: printed for the first few, always counted; fatal with --strict.
    pub fn reject_common(&mut self, name: &str, place: &str, message: &str, reason: &str) -> Result<()> {
        self.reject_at(name, place, message, reason, None)
    }

    fn reject_at(
        &mut self,
        name: &str,
        place: &str,
        message: &str,
        reason: &str,
        length: Option<u64>,
    ) -> Result<()> {
        let location = match place.strip_prefix("line ") {
            Some(number) => format!("{name}:{number}"),
            None => format!("{name}: {place}"),
        };
        if self.strict {
            return Err(Failure::data(format!("{location}: {message}")).into());
        }
        let in_lines = place.starts_with("line ");
        let rejected = Rejected { location: &location, message, reason, length, in_lines };
        if let Some(note) = self.stats.rejected.reject(rejected) {
            crate::say!("tracerctl: {note}");
        }
        Ok(())
    }

    /// The end of a run that was not interrupted: the output written out, then the exit status. No frame
    /// at all is bad input, whatever it was (empty, only comments, every line rejected): exit 3 with the
    /// reason as the last word, after what was written (a CSV header, the summary) and the totals.
    fn finish(&mut self, args: &Options, result: Result<()>) -> Result<u8> {
        match result {
            Ok(()) if self.stats.frames > 0 => {
                self.write_out(args)?;
                for reason in &self.frameless {
                    crate::say!("tracerctl: {reason}");
                }
                self.report_totals();
                Ok(SUCCESS)
            }
            Ok(()) => {
                self.write_out_before_error(args);
                self.report_totals();
                let reasons = std::mem::take(&mut self.frameless);
                let message = if reasons.is_empty() {
                    "no frames in the input".to_string()
                } else {
                    reasons.join("; ")
                };
                Err(Failure::data(message).into())
            }
            Err(error) => {
                self.write_out_before_error(args);
                Err(error)
            }
        }
    }

    /// Everything decoded before an error is written first; the error is the last word. A summary or plot
    /// of nothing (the first input was refused) would only hide the error. An MCAP file is finished
    /// (summary, index) whatever came before the error.
    fn write_out_before_error(&mut self, args: &Options) {
        if self.stats.anything_read() || matches!(self.sink, Sink::Lines { .. } | Sink::Mcap(_)) {
            self.write_out_or_say(args);
        }
    }

    /// Writes what was decoded: the rest of the output, or the summary; then the plot.
    fn write_out(&mut self, args: &Options) -> Result<()> {
        match &mut self.sink {
            Sink::Lines { output, .. } => output.borrow_mut().flush()?,
            Sink::Summary(summary) => {
                let report = if args.format == crate::output::Format::Json {
                    let mut text = serde_json::to_string_pretty(&summary.to_json(&self.stats, &self.seen))?;
                    text.push('\n');
                    text
                } else {
                    summary.report(&self.stats, &self.seen)
                };
                match &args.output {
                    Some(path) => std::fs::write(path, report.as_bytes())
                        .with_context(|| format!("cannot write {}", path.display()))?,
                    None => {
                        let mut out = io::stdout().lock();
                        // The kind kept (a closed pipe stays quiet), the message naming the output.
                        let named = |error: io::Error| {
                            let name = "standard output".to_string();
                            io::Error::new(error.kind(), OutputFailed { name, error })
                        };
                        out.write_all(report.as_bytes()).map_err(named)?;
                        out.flush().map_err(named)?;
                    }
                }
            }
            Sink::Mcap(mcap) => {
                if let Some(mcap) = mcap.take() {
                    let protocol = self.protocol_name();
                    let path = mcap.path;
                    let mut file = mcap.writer.finish(protocol).map_err(|error| mcap_error(&path, error))?;
                    file.flush().with_context(|| format!("cannot write {}", path.display()))?;
                }
            }
        }
        if let (Some(plot), Some(path)) = (self.plot.take(), &args.plot) {
            plot.write(path)?;
        }
        Ok(())
    }

    /// The protocol the inputs showed, as the MCAP metadata names it.
    fn protocol_name(&self) -> &'static str {
        let mut seen = self.seen;
        seen.v1_frames += self.detector.v1_frames;
        seen.v2_frames += self.detector.v2_frames;
        match seen.verdict() {
            Verdict::V1 => "can-v1",
            Verdict::V2 => "can-v2",
            Verdict::Unknown if !self.stats.serial.is_empty() => "serial",
            Verdict::Unknown | Verdict::Mixed => "unknown",
        }
    }

    /// [`Self::write_out`] when another outcome decides the exit status: a failed write is only said
    /// (nothing at all for a closed stdout).
    fn write_out_or_say(&mut self, args: &Options) {
        if let Err(error) = self.write_out(args) {
            if !crate::exit::is_broken_pipe(&error) {
                crate::say!("tracerctl: {error:#}");
            }
        }
    }

    /// The totals line on stderr after plain decoding, when anything but blank lines was not decoded (the
    /// summary has it in its report).
    fn report_totals(&self) {
        if matches!(self.sink, Sink::Lines { .. }) && self.stats.anything_lost() {
            crate::say!("tracerctl: {}", totals_line(&self.stats));
        }
    }
}

/// `decoded N frames from M lines; rejected K lines: ...; skipped S lines: ...; serial ...`
pub fn totals_line(stats: &InputStats) -> String {
    let mut line = format!("decoded {} frames", stats.frames);
    if stats.lines > 0 {
        if stats.decoded_lines == stats.frames {
            line.push_str(&format!(" from {} lines", stats.lines));
        } else {
            line.push_str(&format!(" ({} from {} lines)", stats.decoded_lines, stats.lines));
        }
    }
    let (line_reasons, other_reasons): (Vec<&Rejection>, Vec<&Rejection>) =
        stats.rejected.rejected.iter().partition(|r| r.in_lines);
    if stats.rejected_lines > 0 {
        let reasons: Vec<String> = line_reasons.iter().map(|r| r.describe()).collect();
        line.push_str(&format!("; rejected {} lines: {}", stats.rejected_lines, reasons.join("; ")));
    }
    if stats.skipped.total() > 0 {
        line.push_str(&format!("; skipped {} lines: {}", stats.skipped.total(), stats.skipped.describe()));
    }
    for (name, serial) in &stats.serial {
        line.push_str(&format!("; serial {name}: {} bytes, {} frames", serial.bytes, serial.frames));
        for (count, what) in [
            (serial.skipped_bytes, "bytes skipped"),
            (serial.sync_losses, "sync losses"),
            // Checksum mismatches are rejections, listed with their first place below.
            (serial.bad_length, "bad length bytes"),
            (serial.bad_type, "bad frame types"),
        ] {
            if count > 0 {
                line.push_str(&format!(", {count} {what}"));
            }
        }
    }
    if !other_reasons.is_empty() {
        let reasons: Vec<String> = other_reasons.iter().map(|r| r.describe()).collect();
        line.push_str(&format!("; rejected serial input: {}", reasons.join("; ")));
    }
    if stats.invalid_frames > 0 {
        line.push_str(&format!("; {} invalid frames", stats.invalid_frames));
    }
    if stats.candump_dropped > 0 {
        line.push_str(&format!("; candump reported {} dropped frames", stats.candump_dropped));
    }
    line
}
