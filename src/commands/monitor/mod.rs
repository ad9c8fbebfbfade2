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
//!
//! The folder: this file opens the link and runs the receive loop; `live` is the monitor it feeds;
//! `counts` (per-identifier counts and rates), `staleness` (which periodic frames went missing) and `text`
//! are its pure parts.

mod counts;
mod live;
mod staleness;
mod text;

use std::io::{self, IsTerminal};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

pub use self::live::{Monitor, Output, Settings};
use super::Global;
use crate::exit::{self, DATA_ERROR, FAILURE, SUCCESS};
use crate::link::{FrameRx, LinkChoice, LinkKind};
use crate::output::filter::Filter;
use crate::output::queue::OutputQueue;
use crate::output::stamp::TimeMode;
use crate::output::Format;
use crate::protocol;
use crate::recorder::LogFile;
use crate::recorder::Recorder;
use crate::signals::{Caught, SignalFlag};
use crate::{session, signals};

/// The longest the receive call blocks: how soon a signal is noticed on a silent bus.
const POLL: Duration = Duration::from_millis(50);
/// How often staleness, silence and the link's counters are checked.
const TICK: Duration = Duration::from_millis(25);

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
    monitor.set_log(log.map(|file| Recorder::start(file, &iface)).transpose()?);
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
    monitor.add_warnings(rx.take_notes());
    monitor.print_warnings();
    if let Err(error) = monitor.drain_output(&flag) {
        return quiet_if_broken_pipe(&mut monitor, error);
    }
    // The totals below include drops and checksum errors not yet reported as warnings.
    let stats = rx.stats();
    let (mut status, why) = match &end {
        End::Duration => (SUCCESS, "duration reached".to_string()),
        End::Count => (SUCCESS, "frame count reached".to_string()),
        End::Eof => (SUCCESS, "end of the source".to_string()),
        End::Signal(caught) => (caught.exit_status(), caught.name().to_string()),
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
        if let Some(caught) = flag.caught() {
            return Ok(End::Signal(caught));
        }
        if count.is_some_and(|count| monitor.printed() >= count) {
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
        monitor.add_warnings(rx.take_notes());
        monitor.print_warnings();
        step?;
    }
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
    Signal(Caught),
    LinkError(io::Error),
}
