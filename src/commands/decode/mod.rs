//! `tracerctl decode`: candump logs, single frames and RS232 captures to text, JSON, CSV or a summary.
//!
//! Streams every input with flat memory: one line buffer, one output buffer, no allocation per line.

mod damaged;
mod directory;
mod interrupt;
mod lines;
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
mod single;
mod splitter;
mod stats;
pub mod summary;
mod written;

use std::cell::RefCell;
use std::fs::File;
use std::io::{self, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use super::same_file::{self, Named};
use super::Global;
use crate::candump::{self, Rejected};
use crate::exit::{Failure, SUCCESS, USAGE};
use crate::output::filter::Filter;
use crate::output::mcap::{Compression as McapCompression, McapWriter, Provenance};
use crate::output::{Event, EventWriter, Format, FrameRef};
use crate::protocol::can::EXAMPLE_FRAME;
use crate::protocol::detect::{ProtocolDetector, Verdict};
use crate::protocol::{CanFrame, ProtocolHint};
use crate::signals::SignalFlag;
use directory::Input;
use stats::InputStart;
pub use stats::{totals_line, InputStats, Skipped};
use summary::Summary;
use written::{Interrupted, LiveInput, OutputFailed, Written};

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
    /// What is written, and where.
    pub output: Output,
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
    /// parallel/mod.rs).
    pub threads: usize,
    /// Input bytes per parallel chunk (default: by mode, see [`parallel::CHUNK_BYTES`]; tests make it tiny).
    pub chunk_bytes: Option<usize>,
    /// Read plain files through mapped windows (`--no-mmap`, `TRACERCTL_NO_MMAP`: positioned reads only).
    pub mmap: bool,
}

/// What decode writes: each kind with only the settings it takes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Output {
    /// A line per frame in `format`, to `file` or standard output.
    Lines { format: Format, file: Option<PathBuf> },
    /// The report, to `file` or standard output.
    Summary { format: ReportFormat, file: Option<PathBuf> },
    /// An MCAP file with this chunk compression (a file: the index is written last).
    Mcap { compression: McapCompression, file: PathBuf },
}

/// How `--summary` writes its report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportFormat {
    Text,
    Json,
}

impl Output {
    /// The file written instead of standard output.
    pub fn file(&self) -> Option<&Path> {
        match self {
            Output::Lines { file, .. } | Output::Summary { file, .. } => file.as_deref(),
            Output::Mcap { file, .. } => Some(file),
        }
    }
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let (serial, protocol, color) = (args.serial.as_slice(), global.protocol, global.color);
    // Before any output is created (an output inside a directory given is not read back).
    let mut inputs = directory::expand(&args.inputs)?;
    check_arguments(args, &inputs)?;
    let signals = interrupt::listen()?;
    let stdout = io::stdout();
    let stdout_is_terminal = stdout.is_terminal();
    let color = color.enabled(stdout_is_terminal && args.output.file().is_none());
    let sink = match &args.output {
        Output::Summary { .. } => Sink::Summary(Box::default()),
        Output::Mcap { compression, file } => {
            Sink::Mcap(Some(Box::new(McapOutput::create(file, *compression, &args.inputs, serial)?)))
        }
        Output::Lines { format, file } => lines_sink(*format, file.as_deref(), color)?,
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
        // Decided once, here: the workers map plain files only with the fault handler installed.
        mapping: if args.mmap { mapped::install_fault_handler() } else { None },
        frameless: Vec::new(),
        damaged: Vec::new(),
        input_bytes: None,
    };

    if inputs.is_empty() && serial.is_empty() {
        if io::stdin().is_terminal() {
            crate::say!(
                "tracerctl: no input: give a candump log, '-' for standard input, \
                 or a frame such as {EXAMPLE_FRAME} (see tracerctl decode --help)"
            );
            return Ok(USAGE);
        }
        inputs.push(Input { name: "-".to_string(), listed: false });
    }
    let result = decoder.all_inputs(&inputs, serial);
    if let Some(caught) = decoder.signals.caught() {
        // Interrupted (Ctrl-C, kill): what was decoded is written, with the totals, before exiting 128+n.
        decoder.write_out_or_say(args);
        decoder.say_damage();
        crate::say!("tracerctl: {}: {}", caught.name(), totals_line(&decoder.stats));
        return Ok(caught.exit_status());
    }
    decoder.finish(args, result)
}

/// The output of `Output::Lines`: a file written in blocks, or standard output (at once on a terminal).
fn lines_sink(format: Format, file: Option<&Path>, color: bool) -> Result<Sink> {
    let writer = EventWriter::new(format, color);
    let mut buffer = Vec::with_capacity(FLUSH_AT * 2);
    writer.header(&mut buffer);
    let output = match file {
        Some(path) => {
            let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
            let out = Box::new(io::BufWriter::new(file));
            Written { buffer, out, line_buffered: false, name: path.display().to_string(), failed: false }
        }
        None => {
            let stdout = io::stdout();
            let line_buffered = stdout.is_terminal();
            let (out, name) = (Box::new(stdout.lock()), "standard output".to_string());
            Written { buffer, out, line_buffered, name, failed: false }
        }
    };
    Ok(Sink::Lines { writer, output: Rc::new(RefCell::new(output)) })
}

/// Usage errors found before any input is read (`inputs`: with the directories given replaced by their logs).
fn check_arguments(args: &Options, inputs: &[Input]) -> Result<()> {
    if let Some(path) = &args.plot {
        plot::check_path(path)?;
    }
    // Before any output is created: an output that is an input would be emptied before it is read.
    let input = |path| Named { option: "the input", path };
    let mut inputs: Vec<Named> = inputs.iter().map(|given| input(Path::new(&given.name))).collect();
    if inputs.is_empty() && args.serial.is_empty() {
        inputs.push(input(Path::new("-")));
    }
    inputs.extend(args.serial.iter().map(|path| Named { option: "--serial", path }));
    let outputs = [("-o", args.output.file()), ("--plot", args.plot.as_deref())];
    let outputs: Vec<Named> =
        outputs.iter().filter_map(|&(option, path)| Some(Named { option, path: path? })).collect();
    same_file::refuse_overwriting(&inputs, &outputs)
}

enum Sink {
    Lines {
        writer: EventWriter,
        output: Rc<RefCell<Written>>,
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
    /// Plain files are mapped (the `SIGBUS` handler installed); `None`: read with positioned reads.
    mapping: Option<mapped::FaultHandler>,
    /// Why each input that gave no frame gave none (`no frames in NAME: empty`).
    frameless: Vec<String>,
    /// The compressed inputs that ended early or were corrupt, said last (see damaged.rs).
    damaged: Vec<String>,
    /// The size of the file being read (compressed or not), for messages.
    input_bytes: Option<u64>,
}

impl Decoder {
    fn all_inputs(&mut self, inputs: &[Input], serial: &[PathBuf]) -> Result<()> {
        for input in inputs {
            if input.listed && !directory::still_there(Path::new(&input.name))? {
                self.note_frameless(directory::vanished(&input.name));
                continue;
            }
            self.input(&input.name)?;
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
            self.input_bytes = None;
            if self.parallel_fits() {
                return parallel::decode(self, "<stdin>", (reader, format), None, (true, None));
            }
            return self.candump("<stdin>", reader, (None, true), format);
        }
        let path = Path::new(input);
        if path.exists() {
            let file = File::open(path).with_context(|| format!("cannot open {input}"))?;
            let metadata = file.metadata().ok();
            let size = metadata.as_ref().map(|m| m.len());
            self.input_bytes = size;
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
            return self.candump(input, reader, (size, !regular), format);
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

    /// The run's counts as an input begins.
    fn input_start(&self) -> InputStart {
        let stats = &self.stats;
        InputStart {
            lines: stats.lines,
            decoded_lines: stats.decoded_lines,
            rejected_lines: stats.rejected_lines,
            skipped: stats.skipped,
            damaged: self.damaged.len(),
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
        // A damaged input says so itself, with the lines it reached.
        if decoded > 0 || self.damaged.len() > before.damaged {
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

    /// One CAN frame from any source. Always inlined into the line loop: called through its sink, it was
    /// left out of line (+7 M instructions on 200,000 lines, callgrind).
    #[inline(always)]
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
                self.damage_error().map_or(Ok(SUCCESS), Err)
            }
            Ok(()) => {
                self.write_out_before_error(args);
                self.report_totals();
                let reasons = std::mem::take(&mut self.frameless);
                if let Some(damage) = self.damage_error() {
                    for reason in &reasons {
                        crate::say!("tracerctl: {reason}");
                    }
                    return Err(damage);
                }
                let message = if reasons.is_empty() {
                    "no frames in the input".to_string()
                } else {
                    reasons.join("; ")
                };
                Err(Failure::data(message).into())
            }
            Err(error) => {
                self.write_out_before_error(args);
                self.say_damage();
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
                let (format, file) = match &args.output {
                    Output::Summary { format, file } => (*format, file.as_deref()),
                    Output::Lines { .. } | Output::Mcap { .. } => (ReportFormat::Text, None),
                };
                let report = if format == ReportFormat::Json {
                    let mut text = serde_json::to_string_pretty(&summary.to_json(&self.stats, &self.seen))?;
                    text.push('\n');
                    text
                } else {
                    summary.report(&self.stats, &self.seen)
                };
                match file {
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
