//! The live monitor: what `run` feeds received frames and clock ticks to. It prints each frame as decode
//! does (or as a candump -L line) into one reusable buffer handed to the output in blocks, counts frames
//! per identifier, watches for stale frames, a silent bus, error frames, drops and a log losing frames, and
//! gathers warnings for standard error. Tests feed it made-up times and a `Vec` for standard output.

use std::io::{self, Write};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use super::counts::{Counts, MAX_OTHER_IDS};
use super::staleness::Staleness;
use super::text::{describe_error_frame, human};
use crate::exit::FAILURE;
use crate::link::{LinkFrame, Received, RxStats};
use crate::output::filter::Filter;
use crate::output::queue::{OutputQueue, Pushed, QUEUE_BYTES};
use crate::output::stamp::TimeMode;
use crate::output::text::{self, Columns};
use crate::output::{Event, EventWriter, Format, FrameRef};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ErrorFrame;
use crate::protocol::{self, CanFrame, FrameKind, ProtocolHint};
use crate::recorder::{push_raw_line, Recorder};
use crate::signals::SignalFlag;

/// Output is written at the latest when the buffer holds this much...
const FLUSH_AT: usize = 64 * 1024;
/// ...or when its oldest line has waited this long (a steady stream never lets the receive call time out).
const FLUSH_AGE: Duration = Duration::from_millis(50);
/// Repeated problems (error frames, socket drops, serial checksum errors) are reported at most this often.
const REPORT_EVERY: Duration = Duration::from_secs(1);
/// A write to standard output blocked this long means output has fallen behind (said once).
const BEHIND_AFTER: Duration = Duration::from_secs(1);
/// After a signal, how long the output still queued may take to leave before it is given up (and counted).
const OUTPUT_GRACE: Duration = Duration::from_secs(1);

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
    staleness: Staleness,
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
            staleness: Staleness::new(serial),
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
        if let Some(resumed) =
            self.staleness.arrived(&received.frame, now.saturating_duration_since(self.started), secs)
        {
            self.warnings.push(resumed);
        }
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
            let stale = self.staleness.check(now.saturating_duration_since(self.started), scale, &self.name);
            self.warnings.extend(stale);
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

    /// Lines shown (passed the filter) so far.
    pub fn printed(&self) -> u64 {
        self.printed
    }

    /// Also writes every frame to this `--log` recording.
    pub fn set_log(&mut self, log: Option<Recorder>) {
        self.log = log;
    }

    /// Adds warnings from elsewhere (the link's notes), printed with the monitor's own.
    pub fn add_warnings(&mut self, warnings: Vec<String>) {
        self.warnings.extend(warnings);
    }
}

impl Monitor<OutputQueue> {
    /// Standard output gets what is queued; after a signal (or a second one), only a moment more. Lines still
    /// queued when that moment is over count as dropped.
    pub fn drain_output(&mut self, flag: &SignalFlag) -> Result<()> {
        let mut grace: Option<Instant> = None;
        self.flush()?;
        self.out
            .finish(|| {
                flag.received().is_some() && grace.get_or_insert_with(Instant::now).elapsed() >= OUTPUT_GRACE
            })
            .context("cannot write to standard output")?;
        if self.out.dropped_lines > self.output_dropped {
            self.output_dropped = self.out.dropped_lines;
            self.fell_behind();
        }
        if let Some(stall) = self.out.stalled() {
            self.output_stall = self.output_stall.max(stall);
        }
        self.print_warnings();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::{Timestamp, TimestampKind};
    use crate::protocol::serial::SerialFrame;
    use crate::protocol::FrameId;
    use crate::recorder::LogFile;

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
