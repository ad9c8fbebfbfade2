//! `tracerctl monitor`: the live bus, decoded as `decode` prints it (text, JSON, CSV) or as candump -L lines,
//! with warnings on stderr when an expected periodic frame goes stale or the bus falls silent, an optional
//! candump -L log of every frame, and per-identifier counts and rates at the end. Text lines add what
//! candump users reach for: the raw bytes after the identifier and candump's `-t` time modes; `count`
//! ends the run after that many lines, as `candump -n` does.
//!
//! Frames are received, stamped and checked on the main thread straight from the link (no session: every
//! frame matters); what is printed goes through a bounded queue to a writer thread ([`OutputQueue`]), so a
//! reader of standard output that does not keep up (`monitor | less`, not scrolling) delays nothing: stamps
//! and silence warnings stay those of reception, and output beyond the queue is dropped and counted. Output
//! goes to one reusable buffer, handed over when the receive call finds no frame waiting, when the buffer
//! passes 64 KiB, or when its oldest line is 50 ms old; so a flood costs one block per 64 KiB and a quiet bus
//! sees each burst at once. The `--log` file is written by the recorder's own thread. Nothing is allocated
//! per frame.

use std::io::{self, IsTerminal, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use super::Global;
use crate::exit::{self, DATA_ERROR, FAILURE, SUCCESS};
use crate::link::{FrameRx, LinkChoice, LinkFrame, LinkKind, Received, RxStats};
use crate::output::filter::Filter;
use crate::output::queue::{OutputQueue, Pushed, QUEUE_BYTES};
use crate::output::stamp::TimeMode;
use crate::output::text::{self, Columns};
use crate::output::{Event, EventWriter, Format, FrameRef};
use crate::protocol::catalog::{Entry, PERIODIC, STALE_PERIODS};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ErrorFrame;
use crate::protocol::frame::ERR_FLAG;
use crate::protocol::{self, CanFrame, FrameId, FrameKind, ProtocolHint};
use crate::recorder::LogFile;
use crate::recorder::{push_raw_line, Recorder};
use crate::signals::SignalFlag;
use crate::{session, signals};

/// Output is written at the latest when the buffer holds this much...
const FLUSH_AT: usize = 64 * 1024;
/// ...or when its oldest line has waited this long (a steady stream never lets the receive call time out).
const FLUSH_AGE: Duration = Duration::from_millis(50);
/// The longest the receive call blocks: how soon a signal is noticed on a silent bus.
const POLL: Duration = Duration::from_millis(50);
/// How often staleness, silence and the link's counters are checked.
const TICK: Duration = Duration::from_millis(25);
/// Identifiers other than standard CAN ones counted individually (extended IDs from a flood are unbounded).
const MAX_OTHER_IDS: usize = 256;
/// Repeated problems (error frames, socket drops, serial checksum errors) are reported at most this often.
const REPORT_EVERY: Duration = Duration::from_secs(1);
/// A write to standard output blocked this long means output has fallen behind (said once).
const BEHIND_AFTER: Duration = Duration::from_secs(1);
/// After a signal, how long the output still queued may take to leave before it is given up (and counted).
const OUTPUT_GRACE: Duration = Duration::from_secs(1);

/// `tracerctl monitor`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    pub format: Format,
    /// candump -L lines instead of decoded ones.
    pub raw: bool,
    /// Only these identifiers (none: all).
    pub ids: Vec<crate::protocol::FrameId>,
    /// Only these message names (none: all).
    pub messages: Vec<&'static str>,
    /// Also write every frame to this candump log.
    pub log: Option<PathBuf>,
    /// Stop after this long; `None`: until a signal.
    pub duration: Option<Duration>,
    /// Warn when the bus is silent this long (zero: never).
    pub silence: Duration,
    /// The time column of text lines (candump -t).
    pub time_mode: TimeMode,
    /// The raw bytes after the identifier in text lines.
    pub data_column: bool,
    /// Stop after this many frames shown (candump -n); `None`: no limit.
    pub count: Option<u64>,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let choice = global.link.clone();
    // Timing warnings compare arrival times with periods: a replay at N times speed compresses both.
    let time_scale = match choice {
        LinkChoice::Replay { speed, .. } if speed > 0.0 => Some(1.0 / speed),
        LinkChoice::Replay { .. } => None,
        _ => Some(1.0),
    };
    let (link, simulator) = session::open_link(&choice, global.sim_config())?;
    // Created (truncated) only once the link opened: a log that cannot be read leaves the file as it was.
    let log =
        args.log.as_deref().map(|path| LogFile::create(path, "monitor", global.protocol)).transpose()?;
    let flag = signals::listen(|_| {})?;
    let options = Settings {
        format: args.format,
        color: global.color.enabled(io::stdout().is_terminal()),
        raw: args.raw,
        filter: Filter::new(&args.ids, &args.messages),
        hint: global.protocol,
        time_scale,
        silence: args.silence,
        time_mode: args.time_mode,
        data_column: args.data_column,
    };
    let iface = match link.kind {
        // The path of the log is no interface name (candump lines allow 15 characters).
        LinkKind::Replay => "replay".to_string(),
        _ => link.name.clone(),
    };
    let mut rx = link.rx;
    let output = OutputQueue::stdout().context("cannot start the output thread")?;
    let mut monitor = Monitor::new(&link.name, &iface, link.wire == protocol::Wire::Serial, options, output);
    monitor.log = log.map(|file| Recorder::start(file, &iface)).transpose()?;
    // When a frame arrived: the kernel's receive stamp on SocketCAN, else now (this loop never waits for
    // standard output, so now is when it was received).
    let kernel_stamps = link.kind == LinkKind::SocketCan;

    let start = Instant::now();
    let deadline = args.duration.map(|duration| start + duration);
    let until = Until { flag: &flag, deadline, count: args.count };
    let end = match receive_until_end(&mut monitor, rx.as_mut(), &until, kernel_stamps) {
        Ok(end) => end,
        Err(error) => return quiet_if_broken_pipe(&mut monitor, error),
    };
    let elapsed = start.elapsed();
    drop(simulator);
    monitor.warnings.extend(rx.take_notes());
    monitor.print_warnings();
    if let Err(error) = drain_output(&mut monitor, &flag) {
        return quiet_if_broken_pipe(&mut monitor, error);
    }
    // The totals below include drops and checksum errors not yet reported as warnings.
    let stats = rx.stats();
    let (mut status, why) = match &end {
        End::Duration => (SUCCESS, "duration reached".to_string()),
        End::Count => (SUCCESS, "frame count reached".to_string()),
        End::Eof => (SUCCESS, "end of the source".to_string()),
        End::Signal => (flag.exit_status().unwrap_or(exit::SIGNAL_BASE), flag.name().to_string()),
        End::LinkError(error) => {
            crate::say!("tracerctl: the link {} failed: {error}", link.name);
            (FAILURE, "link failed".to_string())
        }
    };
    crate::say_raw!("{}", monitor.summary(elapsed, stats, &why));
    if let Some(report) = rx.report() {
        crate::say!("tracerctl: {report}");
    }
    if monitor.close_log().is_some() && status == SUCCESS {
        status = FAILURE;
    }
    if let Some(nothing) = crate::link::replay::nothing_replayed(&link.name, &stats) {
        // The whole log was read: a signal or --duration before its first frame proves nothing.
        if matches!(end, End::Eof) {
            crate::say!("tracerctl: {nothing}");
            status = DATA_ERROR;
        }
    }
    Ok(status)
}

/// When the run ends besides the end of the source: a signal, a deadline, a number of frames shown.
struct Until<'a> {
    flag: &'a SignalFlag,
    deadline: Option<Instant>,
    count: Option<u64>,
}

/// Receives, prints and checks frames until a signal, the deadline, the frame count, the end of the source
/// or a link error. An error is one writing the output or the log.
fn receive_until_end(
    monitor: &mut Monitor<OutputQueue>,
    rx: &mut dyn FrameRx,
    until: &Until,
    kernel_stamps: bool,
) -> Result<End> {
    let Until { flag, deadline, count } = *until;
    let mut next_tick = Instant::now() + TICK;
    loop {
        if flag.received().is_some() {
            return Ok(End::Signal);
        }
        if count.is_some_and(|count| monitor.printed >= count) {
            return Ok(End::Count);
        }
        let now = Instant::now();
        if deadline.is_some_and(|deadline| now >= deadline) {
            return Ok(End::Duration);
        }
        if now >= next_tick {
            monitor.tick(now, rx.stats());
            next_tick = now + TICK;
            monitor.print_warnings();
        }
        // With output waiting, only take frames that are already there: none waiting means flush now.
        let wait = if monitor.has_unflushed() {
            Duration::ZERO
        } else {
            let mut wait = POLL.min(next_tick.saturating_duration_since(now));
            if let Some(deadline) = deadline {
                wait = wait.min(deadline.saturating_duration_since(now));
            }
            wait
        };
        let step = match rx.recv(wait) {
            Ok(Some(received)) => {
                let now = if kernel_stamps { session::sent_at(&received.ts) } else { Instant::now() };
                monitor.frame(&received, now)
            }
            Ok(None) => monitor.flush(),
            Err(error) if error.kind() == io::ErrorKind::UnexpectedEof => return Ok(End::Eof),
            Err(error) => return Ok(End::LinkError(error)),
        };
        monitor.warnings.extend(rx.take_notes());
        monitor.print_warnings();
        step?;
    }
}

/// Standard output gets what is queued; after a signal (or a second one), only a moment more. Lines still
/// queued when that moment is over count as dropped.
fn drain_output(monitor: &mut Monitor<OutputQueue>, flag: &SignalFlag) -> Result<()> {
    let mut grace: Option<Instant> = None;
    monitor.flush()?;
    monitor
        .out
        .finish(|| {
            flag.received().is_some() && grace.get_or_insert_with(Instant::now).elapsed() >= OUTPUT_GRACE
        })
        .context("cannot write to standard output")?;
    if monitor.out.dropped_lines > monitor.output_dropped {
        monitor.output_dropped = monitor.out.dropped_lines;
        monitor.fell_behind();
    }
    if let Some(stall) = monitor.out.stalled() {
        monitor.output_stall = monitor.output_stall.max(stall);
    }
    monitor.print_warnings();
    Ok(())
}

/// A reader of standard output that went away ends the monitor quietly (`monitor | head`).
fn quiet_if_broken_pipe<W: Output>(monitor: &mut Monitor<W>, error: anyhow::Error) -> Result<u8> {
    if exit::is_broken_pipe(&error) {
        return Ok(monitor.close_log().unwrap_or(SUCCESS));
    }
    Err(error)
}

enum End {
    Duration,
    /// As many frames shown as asked for.
    Count,
    Eof,
    Signal,
    LinkError(io::Error),
}

/// What to print and when to warn.
#[derive(Clone, Debug)]
pub struct Settings {
    pub format: Format,
    pub color: bool,
    /// candump -L lines instead of decoded ones.
    pub raw: bool,
    pub filter: Filter,
    pub hint: ProtocolHint,
    /// Wall-clock seconds per second of link time (1 live, 1/N for a replay at N times speed); `None` turns
    /// the staleness and silence warnings off (a replay as fast as possible has no timing).
    pub time_scale: Option<f64>,
    /// Warn when nothing arrives for this long (zero: never).
    pub silence: Duration,
    /// The time column of text lines.
    pub time_mode: TimeMode,
    /// The raw bytes after the identifier in text lines.
    pub data_column: bool,
}

/// Frames and the time span they were seen over, for one identifier.
#[derive(Clone, Copy, Debug, Default)]
struct Count {
    frames: u64,
    first: f64,
    last: f64,
    msg: &'static str,
}

impl Count {
    fn add(&mut self, secs: f64, msg: &'static str) {
        if self.frames == 0 {
            self.first = secs;
        }
        self.frames += 1;
        self.last = secs;
        self.msg = msg;
    }

    /// Mean frames per second from the link's timestamps; `None` below two frames.
    fn rate(&self) -> Option<f64> {
        let span = self.last - self.first;
        (self.frames >= 2 && span > 0.0).then(|| (self.frames - 1) as f64 / span)
    }
}

/// What kind of frame a row of the summary counts (besides standard CAN data frames), in the rows' order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum RowKind {
    Data,
    Remote,
    Fd,
    Error,
    Serial,
}

/// Per-identifier counts: a table for the 2048 standard identifiers, a bounded list for everything else.
struct Counts {
    standard: Box<[Count]>,
    others: Vec<((RowKind, FrameId), Count)>,
    /// Frames of identifiers beyond `MAX_OTHER_IDS`.
    overflow: u64,
}

impl Counts {
    fn new() -> Self {
        Self { standard: vec![Count::default(); 0x800].into_boxed_slice(), others: Vec::new(), overflow: 0 }
    }

    fn add(&mut self, frame: &LinkFrame, secs: f64, msg: &'static str) {
        let key = match frame {
            LinkFrame::Can(frame) if frame.is_standard_data() => {
                self.standard[(frame.id() & 0x7FF) as usize].add(secs, msg);
                return;
            }
            LinkFrame::Can(frame) => {
                let kind = match frame.kind() {
                    FrameKind::Error => RowKind::Error,
                    FrameKind::Remote => RowKind::Remote,
                    FrameKind::Fd => RowKind::Fd,
                    FrameKind::Data => RowKind::Data,
                };
                (kind, frame.frame_id())
            }
            LinkFrame::Serial(frame) => (RowKind::Serial, frame.frame_id()),
        };
        if let Some((_, count)) = self.others.iter_mut().find(|(k, _)| *k == key) {
            count.add(secs, msg);
        } else if self.others.len() < MAX_OTHER_IDS {
            let mut count = Count::default();
            count.add(secs, msg);
            self.others.push((key, count));
        } else {
            self.overflow += 1;
        }
    }

    /// Every identifier seen, in order: standard CAN, then the others by kind and identifier.
    fn rows(&self) -> Vec<(String, Count)> {
        let mut rows: Vec<(String, Count)> = (0..self.standard.len())
            .filter(|&id| self.standard[id].frames > 0)
            .map(|id| (FrameId::standard(id as u32).to_string(), self.standard[id]))
            .collect();
        let mut others = self.others.clone();
        others.sort_by_key(|(key, _)| *key);
        rows.extend(others.into_iter().map(|((kind, id), count)| {
            let label = match kind {
                // An error frame's "identifier" is its error classes, printed as candump does.
                RowKind::Error => format!("0x{:08X}", id.value() | ERR_FLAG),
                _ => id.to_string(),
            };
            (label, count)
        }));
        rows
    }
}

/// One expected periodic frame and whether it has gone stale.
#[derive(Clone, Copy, Debug)]
struct Tracker {
    what: &'static Entry,
    /// The entry's period.
    period: Duration,
    /// Wall-clock arrival and link timestamp of the last one.
    last: Option<(Instant, f64)>,
    stale: bool,
}

/// A problem counted by the link or by the monitor, reported at most once per `REPORT_EVERY`.
#[derive(Clone, Copy, Debug, Default)]
struct Reported {
    total: u64,
    reported: u64,
    at: Option<Instant>,
}

impl Reported {
    /// How many are new since the last report, if a report is due now.
    fn due(&mut self, now: Instant) -> Option<u64> {
        let new = self.total.saturating_sub(self.reported);
        if new == 0 || self.at.is_some_and(|at| now.duration_since(at) < REPORT_EVERY) {
            return None;
        }
        self.reported = self.total;
        self.at = Some(now);
        Some(new)
    }
}

/// Where the monitor's output goes: standard output through the writer thread; a `Vec` in tests.
pub trait Output {
    /// Takes the bytes in `buffer` (`lines` lines), leaving it empty; how many lines were dropped instead.
    fn block(&mut self, buffer: &mut Vec<u8>, lines: u64) -> Result<u64>;

    /// How long output has been waiting for its reader, if it is.
    fn stalled(&self) -> Option<Duration> {
        None
    }
}

impl Output for Vec<u8> {
    fn block(&mut self, buffer: &mut Vec<u8>, _lines: u64) -> Result<u64> {
        self.append(buffer);
        Ok(0)
    }
}

impl Output for OutputQueue {
    fn block(&mut self, buffer: &mut Vec<u8>, lines: u64) -> Result<u64> {
        match self.push(buffer, lines).context("cannot write to standard output")? {
            Pushed::Queued => Ok(0),
            Pushed::Dropped => Ok(lines),
        }
    }

    fn stalled(&self) -> Option<Duration> {
        OutputQueue::stalled(self)
    }
}

/// The monitor's state: output buffer, log, counters and warning trackers. Fed frames and clock ticks by
/// `run` (or by tests, with made-up times).
pub struct Monitor<W: Output> {
    /// The link, for messages.
    name: String,
    /// The interface name printed in output lines.
    iface: String,
    options: Settings,
    writer: EventWriter,
    /// Text lines' time and data columns (and what they remember: the first and previous stamps).
    columns: Columns,
    out: W,
    buffer: Vec<u8>,
    /// Lines in `buffer`.
    unflushed_lines: u64,
    unflushed_since: Option<Instant>,
    /// Lines the output could not take (its queue was full), and the longest wait for its reader seen.
    output_dropped: u64,
    output_stall: Duration,
    behind_warned: bool,
    log: Option<Recorder>,
    log_warned: bool,
    detector: ProtocolDetector,
    /// An RS232 link: no CAN protocol version to report.
    serial: bool,
    counts: Counts,
    trackers: Vec<Tracker>,
    started: Instant,
    last_frame: Option<Instant>,
    silent: bool,
    frames: u64,
    printed: u64,
    error_frames: Reported,
    last_error_frame: Option<ErrorFrame>,
    socket_drops: Reported,
    bad_checksums: Reported,
    warnings: Vec<String>,
}

impl<W: Output> Monitor<W> {
    pub fn new(name: &str, iface: &str, serial: bool, options: Settings, out: W) -> Self {
        Self::starting_at(name, iface, serial, options, out, Instant::now())
    }

    fn starting_at(
        name: &str,
        iface: &str,
        serial: bool,
        options: Settings,
        out: W,
        started: Instant,
    ) -> Self {
        let writer = EventWriter::new(options.format, options.color);
        let mut buffer = Vec::with_capacity(FLUSH_AT * 2);
        if !options.raw {
            writer.header(&mut buffer);
        }
        Self {
            name: name.to_string(),
            iface: iface.to_string(),
            columns: Columns::new(options.time_mode, options.data_column),
            options,
            writer,
            out,
            unflushed_since: (!buffer.is_empty()).then_some(started),
            buffer,
            unflushed_lines: 0,
            output_dropped: 0,
            output_stall: Duration::ZERO,
            behind_warned: false,
            log: None,
            log_warned: false,
            detector: ProtocolDetector::default(),
            serial,
            counts: Counts::new(),
            // The link's own wire only: CAN (V1 and V2; a tracker waits for its first frame) or RS232.
            trackers: PERIODIC
                .iter()
                .filter(|what| (what.wire == protocol::Wire::Serial) == serial)
                .filter_map(|what| Some(Tracker { what, period: what.period?, last: None, stale: false }))
                .collect(),
            started,
            last_frame: None,
            silent: false,
            frames: 0,
            printed: 0,
            error_frames: Reported::default(),
            last_error_frame: None,
            socket_drops: Reported::default(),
            bad_checksums: Reported::default(),
            warnings: Vec::new(),
        }
    }

    /// True when output is waiting to be written.
    pub fn has_unflushed(&self) -> bool {
        !self.buffer.is_empty()
    }

    /// One received frame, arrived at `now`.
    pub fn frame(&mut self, received: &Received, now: Instant) -> Result<()> {
        self.frames += 1;
        if self.silent {
            self.silent = false;
            let quiet = now.duration_since(self.last_frame.unwrap_or(self.started));
            let quiet = self.link_time(quiet);
            self.warnings.push(match self.last_frame {
                Some(_) => format!("traffic resumed on {} after {} of silence", self.name, human(quiet)),
                None => format!("first frame on {} after {}", self.name, human(quiet)),
            });
        }
        self.last_frame = Some(now);
        if let Some(log) = &self.log {
            log.push(*received);
        }
        let secs = received.ts.as_secs_f64();
        let (frame, decoded) = match &received.frame {
            LinkFrame::Can(frame) => {
                self.detector.observe(frame);
                let hint = match self.options.hint {
                    ProtocolHint::Auto => self.detector.hint(),
                    forced => forced,
                };
                if frame.kind() == FrameKind::Error {
                    self.error_frame(frame, now);
                }
                (FrameRef::Can(frame), protocol::decode(frame, hint))
            }
            LinkFrame::Serial(frame) => (FrameRef::Serial(frame), Ok(protocol::serial::decode(frame))),
        };
        let event = Event { ts: Some(received.ts), iface: &self.iface, dir: None, frame, decoded };
        self.counts.add(&received.frame, secs, event.msg_name());
        track(&mut self.trackers, &mut self.warnings, &received.frame, now, secs);
        if self.options.filter.passes(&event) {
            if self.buffer.is_empty() {
                self.unflushed_since = Some(now);
            }
            if self.options.raw {
                push_raw_line(&mut self.buffer, received, &self.iface);
            } else if self.options.format == Format::Text {
                text::write_with(&mut self.buffer, &event, self.options.color, &mut self.columns);
            } else {
                self.writer.write(&mut self.buffer, &event);
            }
            self.unflushed_lines += 1;
            self.printed += 1;
        }
        let old = self.unflushed_since.is_some_and(|since| now.duration_since(since) >= FLUSH_AGE);
        if self.buffer.len() >= FLUSH_AT || old {
            self.flush()?;
        }
        Ok(())
    }

    /// Hands what is buffered to the output.
    pub fn flush(&mut self) -> Result<()> {
        if !self.buffer.is_empty() {
            let dropped = self.out.block(&mut self.buffer, self.unflushed_lines)?;
            self.buffer.clear();
            self.unflushed_lines = 0;
            if dropped > 0 {
                self.output_dropped += dropped;
                self.fell_behind();
            }
        }
        self.unflushed_since = None;
        Ok(())
    }

    /// Says once that standard output does not keep up.
    fn fell_behind(&mut self) {
        if !self.behind_warned {
            self.behind_warned = true;
            self.warnings.push(format!(
                "warning: standard output is not keeping up (nobody reading it? a pager not scrolling?): frames \
                 are still received and stamped as they arrive; output beyond {} MiB queued is dropped and \
                 counted in the summary",
                QUEUE_BYTES >> 20
            ));
        }
    }

    fn error_frame(&mut self, frame: &CanFrame, now: Instant) {
        self.error_frames.total += 1;
        self.last_error_frame = ErrorFrame::from_frame(frame);
        self.report_error_frames(now);
    }

    fn report_error_frames(&mut self, now: Instant) {
        let Some(new) = self.error_frames.due(now) else { return };
        let Some(error) = self.last_error_frame else { return };
        let mut text = format!("warning: CAN error frame on {}: {}", self.name, describe_error_frame(&error));
        if new > 1 {
            text.push_str(&format!(" ({new} error frames since the last report)"));
        }
        self.warnings.push(text);
    }

    /// Converts a wall-clock duration to link time (a replay at 2x speed: 1 s of wall clock is 2 s of log).
    fn link_time(&self, wall: Duration) -> Duration {
        match self.options.time_scale {
            Some(scale) if scale > 0.0 => wall.div_f64(scale),
            _ => wall,
        }
    }

    /// Periodic checks: stale identifiers, a silent bus, the link's counters, the output and the log.
    pub fn tick(&mut self, now: Instant, stats: RxStats) {
        if let Some(stall) = self.out.stalled() {
            self.output_stall = self.output_stall.max(stall);
            if stall >= BEHIND_AFTER {
                self.fell_behind();
            }
        }
        if let Some(log) = &self.log {
            if !self.log_warned {
                if let Some(loss) = log.losses() {
                    self.log_warned = true;
                    self.warnings.push(format!(
                        "warning: the recording {} is losing frames: {} (counted; the exit status will be 1)",
                        log.path().display(),
                        loss.reason
                    ));
                }
            }
        }
        if let Some(scale) = self.options.time_scale {
            let since = self.last_frame.unwrap_or(self.started);
            let silence = self.options.silence;
            // --silence 0 turns the silence warning off.
            if !self.silent && !silence.is_zero() && now.duration_since(since) >= silence.mul_f64(scale) {
                self.silent = true;
                let silence = human(self.options.silence);
                self.warnings.push(match self.last_frame {
                    Some(_) => format!("warning: {} is silent: no frame for {silence}", self.name),
                    None => format!(
                        "warning: nothing received on {} for {silence}: {}",
                        self.name,
                        crate::link::silence_advice(if self.serial {
                            protocol::Wire::Serial
                        } else {
                            protocol::Wire::CanV2
                        })
                    ),
                });
            }
            self.stale_check(now, scale);
        }
        self.report_error_frames(now);
        self.socket_drops.total = stats.socket_drops;
        if let Some(new) = self.socket_drops.due(now) {
            self.warnings.push(format!(
                "warning: the kernel dropped {new} frames on {} (socket receive queue full; {} in all)",
                self.name, stats.socket_drops
            ));
        }
        self.bad_checksums.total = stats.serial_bad_checksum;
        if let Some(new) = self.bad_checksums.due(now) {
            self.warnings.push(format!(
                "warning: {new} corrupted RS232 frames (bad checksum) dropped on {} ({} in all)",
                self.name, stats.serial_bad_checksum
            ));
        }
    }

    fn stale_check(&mut self, now: Instant, scale: f64) {
        // One line per period: "no 0x211 system_state, 0x221 motion_state for 100 ms (expected every 20 ms)".
        let mut lines: Vec<(u128, String)> = Vec::new();
        for tracker in &mut self.trackers {
            let Some((seen, _)) = tracker.last else { continue };
            let limit = tracker.period * STALE_PERIODS;
            if tracker.stale || now.duration_since(seen) < limit.mul_f64(scale) {
                continue;
            }
            tracker.stale = true;
            let name = format!("{} {}", tracker.what.id, tracker.what.name());
            let period = tracker.period.as_millis();
            match lines.iter_mut().find(|(line_period, _)| *line_period == period) {
                Some((_, names)) => {
                    names.push_str(", ");
                    names.push_str(&name);
                }
                None => lines.push((period, name)),
            }
        }
        for (period, names) in lines {
            let limit = Duration::from_millis(period as u64) * STALE_PERIODS;
            self.warnings.push(format!(
                "warning: no {names} on {} for {} (expected every {period} ms)",
                self.name,
                human(limit)
            ));
        }
    }

    /// Prints and forgets the warnings gathered so far.
    pub fn print_warnings(&mut self) {
        if self.warnings.is_empty() {
            return;
        }
        let mut stderr = io::stderr().lock();
        for warning in self.warnings.drain(..) {
            let _ = writeln!(stderr, "tracerctl: {warning}");
        }
    }

    /// The end-of-run report: per-identifier counts and mean rates, then the totals.
    pub fn summary(&self, elapsed: Duration, stats: RxStats, why: &str) -> String {
        let mut text = format!(
            "tracerctl: monitored {} for {:.2} s ({why}): {} frames, {} shown\n",
            self.name,
            elapsed.as_secs_f64(),
            self.frames,
            self.printed
        );
        let rows = self.counts.rows();
        if !rows.is_empty() {
            text.push_str(&format!("  {:<12} {:<22} {:>10} {:>10}\n", "id", "msg", "frames", "rate/s"));
        }
        for (label, count) in rows {
            let rate = count.rate().map_or_else(|| "-".to_string(), |rate| format!("{rate:.1}"));
            text.push_str(&format!("  {label:<12} {:<22} {:>10} {rate:>10}\n", count.msg, count.frames));
        }
        if self.counts.overflow > 0 {
            text.push_str(&format!(
                "  (+{} frames of further identifiers, beyond {MAX_OTHER_IDS} counted one by one)\n",
                self.counts.overflow
            ));
        }
        text.push_str(&format!(
            "  total: {} frames, {} error frames, {} socket drops, {} serial checksum errors, {} skipped bytes\n",
            self.frames, self.error_frames.total, stats.socket_drops, stats.serial_bad_checksum, stats.serial_skipped_bytes
        ));
        if !self.serial {
            text.push_str(&format!("  protocol: {}\n", self.detector.describe()));
        }
        if self.behind_warned || self.output_dropped > 0 {
            text.push_str(&format!(
                "  output: standard output fell behind (a write waited up to {}); {} of {} lines not shown\n",
                human(self.output_stall),
                self.output_dropped,
                self.printed
            ));
        }
        text
    }

    /// Writes out the `--log` file; if it lost frames, says how many and why, and gives the exit status 1.
    /// (Also when standard output was closed: a quiet end for the output, not for the recording.)
    pub fn close_log(&mut self) -> Option<u8> {
        let log = self.log.as_mut()?;
        let loss = log.close()?;
        crate::say!("tracerctl: {}", log.describe(&loss));
        Some(FAILURE)
    }

    /// Lines the output dropped.
    pub fn output_dropped(&self) -> u64 {
        self.output_dropped
    }
}

/// Notes the arrival of an expected periodic frame; says so when a stale one resumes.
fn track(trackers: &mut [Tracker], warnings: &mut Vec<String>, frame: &LinkFrame, now: Instant, secs: f64) {
    let id = match frame {
        LinkFrame::Can(frame) if frame.is_standard_data() => frame.frame_id(),
        LinkFrame::Serial(frame) => frame.frame_id(),
        LinkFrame::Can(_) => return,
    };
    let Some(tracker) = trackers.iter_mut().find(|tracker| tracker.what.id == id) else { return };
    if tracker.stale {
        tracker.stale = false;
        // Link timestamps (kernel receive times on SocketCAN), to the millisecond.
        let gap = tracker.last.map_or(0.0, |(_, last)| (secs - last).max(0.0));
        let gap = Duration::from_millis((gap * 1000.0).round() as u64);
        warnings.push(format!("{} {} resumed after a gap of {}", id, tracker.what.name(), human(gap)));
    }
    tracker.last = Some((now, secs));
}

/// `bus off; controller: rx passive, tx passive; tx errors 128, rx errors 0`
fn describe_error_frame(error: &ErrorFrame) -> String {
    let words = |names: &mut dyn Iterator<Item = &'static str>| {
        names.map(|name| name.replace('_', " ")).collect::<Vec<_>>().join(", ")
    };
    let mut text = words(&mut error.class_names());
    if text.is_empty() {
        text.push_str("no error class set");
    }
    if error.controller != 0 {
        text.push_str("; controller: ");
        text.push_str(&words(&mut error.controller_names()));
    }
    if let Some((tx, rx)) = error.counters {
        text.push_str(&format!("; tx errors {tx}, rx errors {rx}"));
    }
    if error.is_bus_off() {
        text.push_str(" (the controller has stopped: check wiring, termination and bitrate)");
    }
    text
}

/// `100 ms`, `1.25 s`
fn human(duration: Duration) -> String {
    if duration < Duration::from_secs(1) {
        format!("{} ms", duration.as_millis())
    } else {
        format!("{:.2} s", duration.as_secs_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::{Timestamp, TimestampKind};
    use crate::protocol::serial::SerialFrame;

    /// The timestamp of a frame that arrived at `secs`.
    fn stamp(secs: f64) -> Timestamp {
        Timestamp {
            secs: secs.trunc() as u64,
            nanos: (secs.fract() * 1e9).round() as u32,
            kind: TimestampKind::Absolute,
        }
    }

    fn options(format: Format) -> Settings {
        Settings {
            format,
            color: false,
            raw: false,
            filter: Filter::default(),
            hint: ProtocolHint::Auto,
            time_scale: Some(1.0),
            silence: Duration::from_millis(500),
            time_mode: TimeMode::Absolute,
            data_column: false,
        }
    }

    fn can(id: u32, data: &[u8], secs: f64) -> Received {
        Received { ts: stamp(secs), frame: LinkFrame::Can(CanFrame::new(id, data).unwrap()) }
    }

    const STATE: [u8; 8] = [0, 0, 1, 3, 0, 0, 0, 0xB1];
    const T0: f64 = 1_700_000_000.0;

    #[test]
    fn frames_print_as_decode_prints_them_and_flush_by_age_or_size() {
        let start = Instant::now();
        let mut monitor =
            Monitor::starting_at("can0", "can0", false, options(Format::Json), Vec::new(), start);
        monitor.frame(&can(0x211, &STATE, T0), start).unwrap();
        assert!(monitor.has_unflushed() && monitor.out.is_empty(), "a burst is buffered");
        // A frame 50 ms after the first unflushed one forces the write even while frames keep coming.
        monitor.frame(&can(0x211, &STATE, T0 + 0.05), start + FLUSH_AGE).unwrap();
        assert!(!monitor.has_unflushed());
        let text = String::from_utf8(monitor.out.clone()).unwrap();
        let first: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
        assert_eq!(first["ts"].as_f64(), Some(T0));
        assert_eq!(first["iface"], "can0");
        assert_eq!(first["msg"], "system_state");
        assert_eq!(first["fields"]["battery_voltage"], 25.9);
        assert_eq!(text.lines().count(), 2);

        // A flood: written in blocks of about FLUSH_AT, never per frame.
        let mut monitor =
            Monitor::starting_at("can0", "can0", false, options(Format::Text), Vec::new(), start);
        let mut writes = 0;
        let mut last_len = 0;
        for i in 0..20_000u32 {
            monitor.frame(&can(0x123, &i.to_be_bytes(), T0), start).unwrap();
            if monitor.out.len() != last_len {
                writes += 1;
                assert!(monitor.out.len() - last_len >= FLUSH_AT, "a full block per write");
                last_len = monitor.out.len();
            }
        }
        assert!(writes >= 3, "{writes}");
        monitor.flush().unwrap();
        assert_eq!(String::from_utf8(monitor.out).unwrap().lines().count(), 20_000);
    }

    #[test]
    fn csv_header_comes_first_and_filters_apply() {
        let start = Instant::now();
        let mut opts = options(Format::Csv);
        opts.filter = Filter::new(&[FrameId::Standard(0x311)], &[]);
        let mut monitor = Monitor::starting_at("can0", "can0", false, opts, Vec::new(), start);
        monitor.frame(&can(0x211, &STATE, T0), start).unwrap();
        monitor.frame(&can(0x311, &[0, 0, 0, 10, 0, 0, 0, 20], T0 + 0.01), start).unwrap();
        monitor.flush().unwrap();
        let text = String::from_utf8(monitor.out.clone()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2, "{text}");
        assert!(lines[0].starts_with("ts,"), "{text}");
        assert!(lines[1].contains("odometry"), "{text}");
        assert_eq!((monitor.frames, monitor.printed), (2, 1));
    }

    #[test]
    fn raw_lines_are_candump_log_lines_and_serial_frames_hex_with_a_comment() {
        let start = Instant::now();
        let mut opts = options(Format::Text);
        opts.raw = true;
        let mut monitor = Monitor::starting_at("vcan0", "vcan0", false, opts.clone(), Vec::new(), start);
        monitor.frame(&can(0x211, &STATE, T0 + 0.0025), start).unwrap();
        monitor.flush().unwrap();
        assert_eq!(
            String::from_utf8(monitor.out).unwrap(),
            "(1700000000.002500) vcan0 211#00000103000000B1\n"
        );

        let frame = SerialFrame { frame_type: 0x55, command: 1, payload: [2, 0, 10, 0, 0, 0], frame_id: 0 };
        let mut monitor = Monitor::starting_at("/dev/pts/9", "/dev/pts/9", true, opts, Vec::new(), start);
        monitor.frame(&Received { ts: stamp(T0 + 1.0), frame: LinkFrame::Serial(frame) }, start).unwrap();
        monitor.flush().unwrap();
        assert_eq!(
            String::from_utf8(monitor.out).unwrap(),
            "5AA50A550102000A000000006B # (1700000001.000000) /dev/pts/9\n"
        );
    }

    #[test]
    fn stale_frames_warn_once_and_say_when_they_resume() {
        let start = Instant::now();
        let ms = |n: u64| start + Duration::from_millis(n);
        let mut monitor =
            Monitor::starting_at("can0", "can0", false, options(Format::Text), Vec::new(), start);
        monitor.tick(ms(90), RxStats::default());
        assert!(monitor.warnings.is_empty(), "nothing expected before it was seen");
        for i in 0..5u64 {
            monitor.frame(&can(0x211, &STATE, T0 + i as f64 * 0.02), ms(i * 20)).unwrap();
            monitor.frame(&can(0x221, &[0; 8], T0 + i as f64 * 0.02), ms(i * 20)).unwrap();
        }
        monitor.frame(&can(0x261, &[0; 8], T0), ms(0)).unwrap();
        monitor.tick(ms(150), RxStats::default());
        assert!(monitor.warnings.is_empty(), "{:?}", monitor.warnings);
        // 0x221 keeps coming, 0x211 stops at 80 ms.
        for i in 5..10u64 {
            monitor.frame(&can(0x221, &[0; 8], T0 + i as f64 * 0.02), ms(i * 20)).unwrap();
        }
        monitor.tick(ms(185), RxStats::default());
        assert_eq!(
            monitor.warnings,
            ["warning: no 0x211 system_state on can0 for 100 ms (expected every 20 ms)"]
        );
        monitor.warnings.clear();
        monitor.tick(ms(250), RxStats::default());
        assert!(monitor.warnings.is_empty(), "warned once: {:?}", monitor.warnings);
        monitor.tick(ms(500), RxStats::default());
        assert_eq!(
            monitor.warnings,
            [
                "warning: no 0x221 motion_state on can0 for 100 ms (expected every 20 ms)",
                "warning: no 0x261 motor_low_speed on can0 for 500 ms (expected every 100 ms)"
            ]
        );
        monitor.warnings.clear();
        monitor.frame(&can(0x211, &STATE, T0 + 0.4), ms(400)).unwrap();
        assert_eq!(monitor.warnings, ["0x211 system_state resumed after a gap of 320 ms"]);
    }

    #[test]
    fn catalog_ids_monitor_missed_before_are_watched_v1_status_and_rs232_lights() {
        let start = Instant::now();
        let ms = |n: u64| start + Duration::from_millis(n);
        // The silence warning off: only staleness is under test.
        let mut opts = options(Format::Text);
        opts.silence = Duration::ZERO;
        let mut monitor = Monitor::starting_at("can0", "can0", false, opts.clone(), Vec::new(), start);
        // V1 motion state (0x131), checksum in byte 7; V1 periods are taken as 100 ms.
        let mut data = [0u8; 8];
        data[7] = protocol::can::v1_checksum(0x131, &data);
        monitor.frame(&can(0x131, &data, T0), ms(0)).unwrap();
        monitor.tick(ms(499), RxStats::default());
        assert!(monitor.warnings.is_empty(), "{:?}", monitor.warnings);
        monitor.tick(ms(500), RxStats::default());
        assert_eq!(
            monitor.warnings,
            ["warning: no 0x131 motion_state on can0 for 500 ms (expected every 100 ms)"]
        );

        let lights = SerialFrame { frame_type: 0xAA, command: 0x07, payload: [0; 6], frame_id: 0 };
        let mut monitor = Monitor::starting_at("/dev/ttyUSB0", "ttyUSB0", true, opts, Vec::new(), start);
        monitor.frame(&Received { ts: stamp(T0), frame: LinkFrame::Serial(lights) }, ms(0)).unwrap();
        monitor.tick(ms(100), RxStats::default());
        assert_eq!(
            monitor.warnings,
            ["warning: no 0xAA07 light_state on /dev/ttyUSB0 for 100 ms (expected every 20 ms)"]
        );
    }

    #[test]
    fn silence_is_reported_and_so_is_the_traffic_coming_back() {
        let start = Instant::now();
        let ms = |n: u64| start + Duration::from_millis(n);
        let mut monitor = Monitor::starting_at("sim", "sim", false, options(Format::Text), Vec::new(), start);
        monitor.tick(ms(499), RxStats::default());
        assert!(monitor.warnings.is_empty());
        monitor.tick(ms(500), RxStats::default());
        assert!(monitor.warnings[0].contains("nothing received on sim for 500 ms"), "{:?}", monitor.warnings);
        monitor.warnings.clear();
        monitor.frame(&can(0x123, &[1], T0), ms(700)).unwrap();
        assert_eq!(monitor.warnings, ["first frame on sim after 700 ms"]);
        monitor.warnings.clear();
        monitor.tick(ms(1200), RxStats::default());
        assert_eq!(monitor.warnings, ["warning: sim is silent: no frame for 500 ms"]);
        monitor.warnings.clear();
        monitor.frame(&can(0x123, &[1], T0 + 2.0), ms(2700)).unwrap();
        assert_eq!(monitor.warnings, ["traffic resumed on sim after 2.00 s of silence"]);

        // A replay at twice the speed: 250 ms of wall clock is 500 ms of log.
        let mut opts = options(Format::Text);
        opts.time_scale = Some(0.5);
        let mut monitor = Monitor::starting_at("replay", "replay", false, opts, Vec::new(), start);
        monitor.tick(ms(250), RxStats::default());
        assert_eq!(monitor.warnings.len(), 1);
        // As fast as possible: no timing warnings at all.
        let mut opts = options(Format::Text);
        opts.time_scale = None;
        let mut monitor = Monitor::starting_at("replay", "replay", false, opts, Vec::new(), start);
        monitor.tick(ms(10_000), RxStats::default());
        assert!(monitor.warnings.is_empty());
    }

    #[test]
    fn error_frames_drops_and_checksum_errors_are_reported_in_words_and_rate_limited() {
        let start = Instant::now();
        let ms = |n: u64| start + Duration::from_millis(n);
        let mut opts = options(Format::Text);
        opts.time_scale = None; // no silence warnings here
        let mut monitor = Monitor::starting_at("can0", "can0", false, opts, Vec::new(), start);
        // Bus-off (class 0x40) plus controller problem with tx-passive and counters.
        let error = CanFrame::new_error(0x44, &[0, 0x20, 0, 0, 0, 0, 200, 3]).unwrap();
        let received = Received { ts: stamp(T0), frame: LinkFrame::Can(error) };
        monitor.frame(&received, ms(0)).unwrap();
        assert_eq!(monitor.warnings.len(), 1);
        let warning = &monitor.warnings[0];
        assert!(
            warning
                .contains("controller problem, bus off; controller: tx passive; tx errors 200, rx errors 3"),
            "{warning}"
        );
        monitor.warnings.clear();
        monitor.frame(&received, ms(10)).unwrap();
        monitor.frame(&received, ms(20)).unwrap();
        assert!(monitor.warnings.is_empty(), "rate limited");
        monitor.tick(ms(1000), RxStats::default());
        assert!(
            monitor.warnings[0].ends_with("(2 error frames since the last report)"),
            "{:?}",
            monitor.warnings
        );
        monitor.warnings.clear();
        monitor.flush().unwrap();
        let text = String::from_utf8(monitor.out.clone()).unwrap();
        assert!(text.lines().all(|line| line.contains("error_frame classes=")), "{text}");

        let stats = RxStats { socket_drops: 7, serial_bad_checksum: 2, ..RxStats::default() };
        monitor.tick(ms(1010), stats);
        assert_eq!(monitor.warnings.len(), 2, "{:?}", monitor.warnings);
        assert!(monitor.warnings[0].contains("dropped 7 frames on can0"));
        assert!(monitor.warnings[1].contains("2 corrupted RS232 frames"));
        let summary = monitor.summary(Duration::from_secs(1), stats, "duration reached");
        assert!(summary.contains("3 error frames, 7 socket drops, 2 serial checksum errors"), "{summary}");
    }

    #[test]
    fn summary_counts_and_rates_per_identifier() {
        let start = Instant::now();
        let mut monitor =
            Monitor::starting_at("can0", "can0", false, options(Format::Text), Vec::new(), start);
        for i in 0..51 {
            monitor.frame(&can(0x211, &STATE, T0 + f64::from(i) * 0.02), start).unwrap();
        }
        for i in 0..11 {
            monitor.frame(&can(0x261, &[0; 8], T0 + f64::from(i) * 0.1), start).unwrap();
        }
        let extended = CanFrame::new_extended(0x18FF_0001, &[1]).unwrap();
        monitor.frame(&Received { ts: stamp(T0), frame: LinkFrame::Can(extended) }, start).unwrap();
        let summary = monitor.summary(Duration::from_secs(1), RxStats::default(), "duration reached");
        let line =
            |id: &str| summary.lines().find(|line| line.trim_start().starts_with(id)).unwrap().to_string();
        let fields = |id: &str| line(id).split_whitespace().map(str::to_string).collect::<Vec<_>>();
        assert_eq!(fields("0x211"), ["0x211", "system_state", "51", "50.0"]);
        assert_eq!(fields("0x261"), ["0x261", "motor_low_speed", "11", "10.0"]);
        assert_eq!(fields("0x18FF0001"), ["0x18FF0001", "raw", "1", "-"]);
        assert!(summary.contains("63 frames"), "{summary}");
    }

    #[test]
    fn the_log_gets_every_frame_even_filtered_ones() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bus.log");
        let start = Instant::now();
        let mut opts = options(Format::Text);
        opts.filter = Filter::new(&[FrameId::Standard(0x999)], &[]);
        let mut monitor = Monitor::starting_at("can0", "can0", false, opts, Vec::new(), start);
        monitor.log = Some(
            Recorder::start(LogFile::create(&path, "monitor", ProtocolHint::Auto).unwrap(), "can0").unwrap(),
        );
        monitor.frame(&can(0x211, &STATE, T0), start).unwrap();
        // Written by the recorder's thread, whatever standard output does.
        assert_eq!(monitor.log.as_mut().unwrap().close(), None);
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "(1700000000.000000) can0 211#00000103000000B1\n"
        );
        let error = LogFile::create(&dir.path().join("missing/bus.log"), "monitor", ProtocolHint::Auto)
            .err()
            .unwrap();
        assert!(format!("{error:#}").contains("missing/bus.log"), "{error:#}");
    }

    // /dev/full is Linux's.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_log_that_loses_frames_warns_once_and_counts_them() {
        let start = Instant::now();
        let mut monitor =
            Monitor::starting_at("can0", "can0", false, options(Format::Text), Vec::new(), start);
        monitor.log = Some(
            Recorder::start(
                LogFile::create(std::path::Path::new("/dev/full"), "monitor", ProtocolHint::Auto).unwrap(),
                "can0",
            )
            .unwrap(),
        );
        for i in 0..10 {
            monitor.frame(&can(0x211, &STATE, T0 + f64::from(i) * 0.02), start).unwrap();
        }
        let deadline = Instant::now() + Duration::from_secs(5);
        while monitor.log.as_ref().unwrap().losses().is_none() && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        monitor.tick(start, RxStats::default());
        monitor.tick(start, RxStats::default());
        let warnings: Vec<&String> = monitor.warnings.iter().filter(|w| w.contains("/dev/full")).collect();
        assert_eq!(warnings.len(), 1, "{:?}", monitor.warnings);
        assert!(warnings[0].contains("is losing frames: No space left on device"), "{}", warnings[0]);
        let loss = monitor.log.as_mut().unwrap().close().unwrap();
        assert_eq!(loss.frames, 10);
    }

    /// An output whose reader is away: it takes nothing and reports a long wait.
    struct Blocked;

    impl Output for Blocked {
        fn block(&mut self, buffer: &mut Vec<u8>, lines: u64) -> Result<u64> {
            buffer.clear();
            Ok(lines)
        }

        fn stalled(&self) -> Option<Duration> {
            Some(Duration::from_secs(3))
        }
    }

    #[test]
    fn a_stalled_output_is_said_once_and_its_drops_counted_while_silence_goes_by_reception() {
        let start = Instant::now();
        let ms = |n: u64| start + Duration::from_millis(n);
        let mut monitor = Monitor::starting_at("sim", "sim", false, options(Format::Text), Blocked, start);
        for i in 0..100u64 {
            monitor.frame(&can(0x211, &STATE, T0 + i as f64 * 0.02), ms(i * 20)).unwrap();
            monitor.flush().unwrap();
            monitor.tick(ms(i * 20 + 10), RxStats::default());
        }
        let behind: Vec<&String> = monitor.warnings.iter().filter(|w| w.contains("not keeping up")).collect();
        assert_eq!(behind.len(), 1, "{:?}", monitor.warnings);
        assert!(monitor.warnings.iter().all(|w| !w.contains("silent")), "{:?}", monitor.warnings);
        assert_eq!(monitor.output_dropped(), 100);
        let summary = monitor.summary(Duration::from_secs(2), RxStats::default(), "duration reached");
        assert!(
            summary.contains("output: standard output fell behind (a write waited up to 3.00 s); 100 of 100 lines not shown"),
            "{summary}"
        );
    }
}
