//! `tracerctl decode`: candump logs, single frames and RS232 captures to text, JSON, CSV or a summary.
//!
//! Streams every input with flat memory: one line buffer, one output buffer, no allocation per line.

mod plot;
mod serial_input;
pub mod summary;

use std::fs::File;
use std::io::{self, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use crate::candump::{self, Line, LineParser, LineReader, LogFormat, RawLine, Reason};
use crate::cli::{ColorChoice, DecodeArgs};
use crate::exit::{Failure, SUCCESS, USAGE};
use crate::output::filter::Filter;
use crate::output::{Event, EventWriter, FrameRef};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::{self, CanFrame, ProtocolHint};
use summary::Summary;

/// Output is written in blocks of about this size.
const FLUSH_AT: usize = 64 * 1024;
/// Files at least this large get a progress bar (on a terminal).
const PROGRESS_MIN_BYTES: u64 = 8 * 1024 * 1024;
/// How many rejected lines are printed individually before only being counted.
const MAX_SHOWN_REJECTS: usize = 10;

pub fn run(args: &DecodeArgs, serial: &[PathBuf], protocol: ProtocolHint, color: ColorChoice) -> Result<u8> {
    let stdout = io::stdout();
    let color = color.enabled(stdout.is_terminal());
    let sink = if args.summary {
        Sink::Summary(Box::default())
    } else {
        let writer = EventWriter::new(args.format, color);
        let mut buffer = Vec::with_capacity(FLUSH_AT * 2);
        writer.header(&mut buffer);
        Sink::Lines { writer, buffer, out: Box::new(stdout.lock()) }
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
    };

    let mut inputs: Vec<&str> = args.inputs.iter().map(String::as_str).collect();
    if inputs.is_empty() && serial.is_empty() {
        if io::stdin().is_terminal() {
            crate::say!(
                "tracerctl: no input: give a candump log, '-' for standard input, \
                 or a frame such as 211#00000103000000B1 (see tracerctl decode --help)"
            );
            return Ok(USAGE);
        }
        inputs.push("-");
    }
    for input in inputs {
        decoder.input(input)?;
    }
    for path in serial {
        let file = File::open(path).with_context(|| format!("cannot open {}", path.display()))?;
        let name = path.display().to_string();
        serial_input::decode(&mut decoder, &name, file)?;
    }
    decoder.finish(args)
}

enum Sink {
    Lines { writer: EventWriter, buffer: Vec<u8>, out: Box<dyn Write> },
    Summary(Box<Summary>),
}

/// What happened to the input besides frames: everything that was not decoded is counted here.
#[derive(Debug, Default)]
pub struct InputStats {
    pub lines: u64,
    pub frames: u64,
    pub blank_or_comment: u64,
    pub error_text_lines: u64,
    pub can_xl_lines: u64,
    /// Frames candump itself reported dropped (DROPCOUNT lines).
    pub candump_dropped: u64,
    /// Rejected lines per reason, with the first place each reason occurred.
    pub rejected: Vec<Rejection>,
    /// Frames with a TRACER ID but invalid content (V1 checksum, too short).
    pub invalid_frames: u64,
    pub serial: Vec<(String, protocol::serial::StreamStats)>,
    pub shown_rejects: usize,
}

#[derive(Debug)]
pub struct Rejection {
    pub reason: String,
    pub count: u64,
    pub first_at: String,
}

impl InputStats {
    pub fn rejected_total(&self) -> u64 {
        self.rejected.iter().map(|r| r.count).sum()
    }

    fn reject(&mut self, reason: &str, at: impl FnOnce() -> String) {
        match self.rejected.iter_mut().find(|r| r.reason == reason) {
            Some(rejection) => rejection.count += 1,
            None => self.rejected.push(Rejection { reason: reason.to_string(), count: 1, first_at: at() }),
        }
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
}

impl Decoder {
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
            return self.candump("<stdin>", reader, None, format);
        }
        let path = Path::new(input);
        if path.exists() {
            let file = File::open(path).with_context(|| format!("cannot open {input}"))?;
            let size = file.metadata().map(|m| m.len()).ok();
            let (reader, format) = candump::open_log(file, input).map_err(Failure::from)?;
            // The progress bar counts text bytes: unknown for a compressed file.
            let size = size.filter(|_| format.compression.is_none());
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
        bail!("{input}: no such file (frames are written like 211#00000103000000B1)")
    }

    fn candump(&mut self, name: &str, input: impl Read, size: Option<u64>, format: LogFormat) -> Result<()> {
        let mut reader = LineReader::new(input);
        let parser = LineParser::for_format(format);
        let mut parser = if self.delta_stamps { parser.with_delta_timestamps() } else { parser };
        let bar = self.progress_bar(size);
        let mut consumed = 0u64;
        while let Some(raw) = reader.next_line().with_context(|| format!("cannot read {name}"))? {
            self.stats.lines += 1;
            let (number, text) = match raw {
                RawLine::Line { number, text } => (number, text),
                RawLine::TooLong { number, len } => {
                    consumed += len as u64 + 1;
                    self.rejected(
                        name,
                        number,
                        &format!("line of {len} bytes is too long for a candump line"),
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
                Ok(Line::Frame(record)) => {
                    let frame = record.frame;
                    self.frame(record.ts, record.iface, record.dir, &frame).map_err(|error| {
                        match error.downcast::<Failure>() {
                            Ok(failure) => {
                                Failure::data(format!("{name}:{number}: {}", failure.message)).into()
                            }
                            Err(other) => other,
                        }
                    })?;
                }
                Ok(Line::Blank | Line::Comment) => self.stats.blank_or_comment += 1,
                Ok(Line::DropCount { dropped }) => self.stats.candump_dropped += dropped,
                Ok(Line::ErrorText) => self.stats.error_text_lines += 1,
                Ok(Line::CanXl) => self.stats.can_xl_lines += 1,
                Err(error) => {
                    // A file of bare cansend frames ("211#00000103000000B1" per line) is read too.
                    let bare = text.trim_ascii();
                    let looks_bare = bare.contains(&b'#') && !bare.iter().any(u8::is_ascii_whitespace);
                    match candump::parse_cansend(bare) {
                        Ok(frame) => self.frame(None, "-", None, &frame)?,
                        Err(frame_error) if looks_bare => {
                            let message = format!("bare frame: {frame_error}");
                            self.rejected_with(name, number, &message, frame_error.reason)?
                        }
                        Err(_) => self.rejected_with(name, number, &error.to_string(), error.reason)?,
                    }
                }
            }
        }
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        Ok(())
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
    fn frame(
        &mut self,
        ts: Option<candump::Timestamp>,
        iface: &str,
        dir: Option<candump::Direction>,
        frame: &CanFrame,
    ) -> Result<()> {
        self.stats.frames += 1;
        self.detector.observe(frame);
        let hint = match self.protocol {
            ProtocolHint::Auto => self.detector.hint(),
            forced => forced,
        };
        let decoded = protocol::decode(frame, hint);
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
        match &mut self.sink {
            Sink::Lines { writer, buffer, out } => {
                writer.write(buffer, event);
                if buffer.len() >= FLUSH_AT {
                    out.write_all(buffer)?;
                    buffer.clear();
                }
            }
            Sink::Summary(summary) => summary.event(event),
        }
        if let Some(plot) = &mut self.plot {
            plot.event(event);
        }
        Ok(())
    }

    fn rejected(&mut self, name: &str, number: u64, reason: &str) -> Result<()> {
        self.reject_common(name, &format!("line {number}"), reason, reason)
    }

    fn rejected_with(&mut self, name: &str, number: u64, message: &str, reason: Reason) -> Result<()> {
        self.reject_common(name, &format!("line {number}"), message, reason.as_str())
    }

    /// Reports a rejected piece of input: printed for the first few, always counted; fatal with --strict.
    pub fn reject_common(&mut self, name: &str, place: &str, message: &str, reason: &str) -> Result<()> {
        let location = match place.strip_prefix("line ") {
            Some(number) => format!("{name}:{number}"),
            None => format!("{name}: {place}"),
        };
        if self.strict {
            return Err(Failure::data(format!("{location}: {message}")).into());
        }
        if self.stats.shown_rejects < MAX_SHOWN_REJECTS {
            crate::say!("tracerctl: {location}: {message}");
        } else if self.stats.shown_rejects == MAX_SHOWN_REJECTS {
            crate::say!("tracerctl: further rejected input is only counted (see the totals at the end)");
        }
        self.stats.shown_rejects += 1;
        self.stats.reject(reason, || location);
        Ok(())
    }

    fn finish(mut self, args: &DecodeArgs) -> Result<u8> {
        match &mut self.sink {
            Sink::Lines { buffer, out, .. } => {
                out.write_all(buffer)?;
                out.flush()?;
                let rejected = self.stats.rejected_total();
                if rejected > 0 || self.stats.invalid_frames > 0 || self.stats.candump_dropped > 0 {
                    crate::say!("tracerctl: {}", totals_line(&self.stats));
                }
            }
            Sink::Summary(summary) => {
                let report = if args.format == crate::output::Format::Json {
                    let mut text = serde_json::to_string_pretty(&summary.to_json(&self.stats, &self.seen))?;
                    text.push('\n');
                    text
                } else {
                    summary.report(&self.stats, &self.seen)
                };
                let mut out = io::stdout().lock();
                out.write_all(report.as_bytes())?;
                out.flush()?;
            }
        }
        if let (Some(plot), Some(path)) = (&self.plot, &args.plot) {
            plot.write(path)?;
        }
        Ok(SUCCESS)
    }
}

/// `decoded N frames from M lines; rejected K lines (...); ...`
pub fn totals_line(stats: &InputStats) -> String {
    let mut line = format!("decoded {} frames", stats.frames);
    if stats.lines > 0 {
        line.push_str(&format!(" from {} lines", stats.lines));
    }
    let rejected = stats.rejected_total();
    if rejected > 0 {
        let reasons: Vec<String> = stats
            .rejected
            .iter()
            .map(|r| format!("{} x {} (first at {})", r.count, r.reason, r.first_at))
            .collect();
        line.push_str(&format!("; rejected {rejected}: {}", reasons.join("; ")));
    }
    if stats.invalid_frames > 0 {
        line.push_str(&format!("; {} invalid frames", stats.invalid_frames));
    }
    if stats.candump_dropped > 0 {
        line.push_str(&format!("; candump reported {} dropped frames", stats.candump_dropped));
    }
    line
}
