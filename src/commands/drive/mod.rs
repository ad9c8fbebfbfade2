//! `tracerctl drive`: drive at a fixed speed, ramped and capped, with zero-velocity frames on every way out.
//!
//! The stop rules (docs/architecture.md) as drive applies them: signals are handled from the very start;
//! SIGTSTP sends zeros before the process stops; any gap in the sender's clock (a suspension, a stalled
//! machine) or a watchdog trip ends the drive with zeros, since the robot has stopped by itself and only a
//! fresh command may move it again; and the report says whether the stop frames really left.

mod guard;
mod status;

pub(crate) use guard::{
    check_before_driving, report as stop_report, End, Follow, Guard, Strictness, WATCHDOG,
};

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;

use super::live;
use super::Global;
use crate::control::limits::Limits;
use crate::control::sender::{MotionSender, SenderStats, Stopper};
use crate::exit::{self, Failure, FAILURE};
use crate::output::palette::CLEAR_LINE;
use crate::output::Format;
use crate::protocol::Codec;
use crate::session::{Journaling, RobotStatus, Session};
use crate::signals::{self, SignalFlag};

/// The report's words for a pseudo-terminal's flush before the stop frames: it drops what the peer has not
/// taken in (a stalled peer's backlog, or the latest frames on a loaded machine) and cannot say how much.
pub const UNCOUNTED_DISCARD: &str =
    "output the pseudo-terminal still held flushed before the stop frames, uncounted";

/// The main loop refreshes the target this often; the watchdog zeroes it if that stops for this long.
pub(crate) const REFRESH: Duration = Duration::from_millis(20);
/// Status line rate on a terminal; in a pipe or log (or as JSON), one line a second.
const STATUS_EVERY_TTY: Duration = Duration::from_millis(250);
const STATUS_EVERY_PIPE: Duration = Duration::from_secs(1);
/// How long SIGTSTP waits for the zero frame to leave before the process stops anyway.
const SUSPEND_WAIT: Duration = Duration::from_millis(100);

/// `tracerctl drive`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// m/s, + forward (capped by the limits).
    pub linear: f64,
    /// rad/s, + counter-clockwise.
    pub angular: f64,
    /// How long to drive; `None`: until a signal.
    pub duration: Option<Duration>,
    pub limits: Limits,
    /// Start even with the E-stop pressed or a latched fault.
    pub ignore_faults: bool,
    /// Text or JSON status and report on stdout (no CSV).
    pub format: Format,
    /// Write every frame received and sent to this candump log (or MCAP), as `dashboard --record` does.
    pub record: Option<std::path::PathBuf>,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let limits = args.limits;
    // Signals first: a Ctrl-C while the link opens or the robot is awaited must end the command cleanly.
    let context = Context::listen()?;
    let journal = Journaling { record: args.record.as_deref().map(|path| (path, "drive")), tap: None };
    let session = live::open_journaled(global, journal)?;
    // Status and the report go to stdout, for scripts (`drive ... > run.txt`); diagnostics to stderr.
    let result = execute_with(&session, args, limits, &mut std::io::stdout(), &context).map_err(|error| {
        // A broken pipe is a quiet success for output nobody reads any more (decode | head), not for the
        // status of a robot being driven: whoever watched it must learn from the exit status that it is gone.
        if exit::is_broken_pipe(&error) {
            Failure { code: FAILURE, message: format!("the status output went away ({error:#})") }.into()
        } else {
            error
        }
    });
    // The robot is stopped: now the recording is written out, and what it lost is said.
    if let Some(loss) = session.finish().recording {
        crate::say!("tracerctl: {loss}");
    }
    result
}

/// What a drive sets up before the session: the signal flag and where the sender's stopper goes, so that
/// a signal stops the sender from the signal thread at once (`drive` and `commission`).
pub(crate) struct Context {
    pub(crate) signal: SignalFlag,
    sender_slot: Arc<Mutex<Option<Stopper>>>,
    suspended_early: Arc<AtomicBool>,
}

impl Context {
    /// Starts handling SIGINT, SIGTERM, SIGHUP (and SIGTSTP) before anything else.
    pub(crate) fn listen() -> Result<Self> {
        let sender_slot: Arc<Mutex<Option<Stopper>>> = Arc::default();
        let suspended_early = Arc::new(AtomicBool::new(false));
        let (on_signal, on_suspend) = (Arc::clone(&sender_slot), Arc::clone(&sender_slot));
        let early = Arc::clone(&suspended_early);
        let signal = signals::listen_suspendable(
            move |_| {
                if let Some(stopper) = on_signal.lock().as_ref() {
                    stopper.stop_now();
                }
            },
            move || match on_suspend.lock().as_ref() {
                Some(stopper) => {
                    stopper.suspend(SUSPEND_WAIT);
                }
                None => early.store(true, Ordering::SeqCst),
            },
        )?;
        Ok(Self { signal, sender_slot, suspended_early })
    }

    /// A signal from now on stops this sender at once.
    pub(crate) fn arm(&self, sender: &MotionSender) {
        *self.sender_slot.lock() = Some(sender.stopper());
    }

    /// The sender has stopped.
    pub(crate) fn disarm(&self) {
        self.sender_slot.lock().take();
    }

    /// A SIGTSTP before the sender started ends the command rather than driving after SIGCONT.
    pub(crate) fn refuse_if_suspended(&self) -> Result<()> {
        if self.suspended_early.load(Ordering::SeqCst) {
            return Err(Failure {
                code: FAILURE,
                message: "suspended before driving started: drive ended (run it again to drive)".to_string(),
            }
            .into());
        }
        Ok(())
    }
}

/// Drives on an open session; the status and the report go to `out`, diagnostics to stderr.
fn execute_with(
    session: &Session,
    args: &Options,
    limits: Limits,
    out: &mut impl Write,
    context: &Context,
) -> Result<u8> {
    let signal = &context.signal;
    let target = capped_target(args, limits);
    if let Some(status) = check_before_driving(session, args.format, args.ignore_faults, out, signal)? {
        return Ok(status);
    }
    context.refuse_if_suspended()?;

    let sender = MotionSender::start(session.tx.clone(), Codec::new(session.wire()), limits, WATCHDOG)?;
    context.arm(&sender);

    let mut drive = DriveLoop::new(session, args, target, &sender);
    let end = drive.run(out, signal);
    let DriveLoop { started, guard, style, .. } = drive;
    let follow = guard.follow;
    let stats = match end {
        End::TimeUp => sender.ramp_down_and_stop(&limits),
        _ => sender.stop(),
    };
    // A signal during the ramp down stopped it at once (the signal thread ends the sender): say so.
    let end = match (end, signal.caught()) {
        (End::TimeUp, Some(caught)) => End::Signal(caught),
        (end, _) => end,
    };
    context.disarm();
    // Ends the overwritten line; a failure shows again when the report is written.
    if style == Style::Overwrite && !matches!(end, End::OutputGone(_)) {
        let _ = writeln!(out);
    }
    let elapsed = started.elapsed().as_secs_f64();
    let parts = guard::report(&stats, &follow, session);
    let report = parts.join("; ");
    let result = guard::outcome(&end, &stats, &follow, elapsed, &report, session);
    if matches!(end, End::OutputGone(_)) {
        return result;
    }
    // The record a script reads last. In text, an error's message (stderr) already carries the report; a
    // normal end gives it one part a line, so it fits a narrow terminal.
    let lines = |reason: &str| format!("stopped after {elapsed:.2} s ({reason})\n  {}", parts.join("\n  "));
    let written = match (args.format, &end) {
        (Format::Json, _) => {
            let exit_status = result.as_ref().map_or_else(
                |error| error.downcast_ref::<Failure>().map_or(FAILURE, |failure| failure.code),
                |status| *status,
            );
            let record = report_json(&end, elapsed, exit_status, &stats, &follow, &report);
            writeln!(out, "{record}")
        }
        (_, End::TimeUp) => writeln!(out, "{}", lines("time up")),
        (_, End::Signal(caught)) => writeln!(out, "{}", lines(caught.name())),
        _ => Ok(()),
    };
    match (written.and_then(|()| out.flush()), result) {
        (Err(error), Ok(_)) => Err(error.into()),
        (_, result) => result,
    }
}

/// The end of the drive as one JSON object (docs/json.md, "drive").
fn report_json(
    end: &End,
    elapsed: f64,
    exit_status: u8,
    stats: &SenderStats,
    follow: &Follow,
    message: &str,
) -> serde_json::Value {
    let measured = follow.samples > 0;
    serde_json::json!({
        "type": "report",
        "end": end.name(),
        "signal": match end { End::Signal(caught) => Some(caught.name()), _ => None },
        "elapsed": status::round(elapsed, 3),
        "exit_status": exit_status,
        "frames_sent": stats.frames,
        "send_errors": stats.send_errors,
        "not_sent": stats.queue_full,
        "held_back": stats.held_back,
        "discarded": stats.discarded,
        "discarded_uncounted": stats.discarded_uncounted,
        "watchdog_trips": stats.watchdog_trips,
        "distance": measured.then(|| status::round(follow.distance, 3)),
        "peak_linear_velocity": measured.then(|| status::round(follow.peak_linear, 3)),
        "last_command": status::velocity_json((stats.sent.linear(), stats.sent.angular())),
        "stop_confirmed": stats.stop_confirmed(),
        "message": message,
    })
}

/// The speed to drive at, within the limits; says so (stderr) when the request was capped.
fn capped_target(args: &Options, limits: Limits) -> (f64, f64) {
    let target = (
        args.linear.clamp(-limits.max_linear, limits.max_linear),
        args.angular.clamp(-limits.max_angular, limits.max_angular),
    );
    if target != (args.linear, args.angular) {
        crate::say!(
            "tracerctl: capped: {:+.3} m/s {:+.3} rad/s -> {:+.3} m/s {:+.3} rad/s (--max-linear {}, --max-angular {})",
            args.linear,
            args.angular,
            target.0,
            target.1,
            limits.max_linear,
            limits.max_angular
        );
    }
    target
}

/// The main loop's state: it refreshes the target, watches the sender and the robot, and prints the status.
struct DriveLoop<'a> {
    session: &'a Session,
    args: &'a Options,
    target: (f64, f64),
    sender: &'a MotionSender,
    started: Instant,
    last_status: Instant,
    guard: Guard<'a>,
    style: Style,
    status_every: Duration,
}

/// How the status is written.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Style {
    /// On a terminal: one line fitted to its width, overwriting itself.
    Overwrite,
    /// In a pipe or a log: full lines.
    Lines,
    /// `--format json`: one object per line.
    Json,
}

impl<'a> DriveLoop<'a> {
    fn new(session: &'a Session, args: &'a Options, target: (f64, f64), sender: &'a MotionSender) -> Self {
        let style = match args.format {
            Format::Json => Style::Json,
            _ if std::io::stdout().is_terminal() => Style::Overwrite,
            _ => Style::Lines,
        };
        Self {
            session,
            args,
            target,
            sender,
            started: Instant::now(),
            last_status: Instant::now() - STATUS_EVERY_PIPE,
            guard: Guard::new(sender, Strictness::Lenient { ignore_faults: args.ignore_faults }),
            style,
            status_every: if style == Style::Overwrite { STATUS_EVERY_TTY } else { STATUS_EVERY_PIPE },
        }
    }

    /// Drives until something ends the drive.
    fn run(&mut self, out: &mut impl Write, signal: &SignalFlag) -> End {
        loop {
            if let Some(end) = self.step(out, signal) {
                return end;
            }
            std::thread::sleep(REFRESH);
        }
    }

    /// One iteration: `Some` when the drive must end.
    fn step(&mut self, out: &mut impl Write, signal: &SignalFlag) -> Option<End> {
        let stats = match self.guard.before_command(signal) {
            Ok(stats) => stats,
            Err(end) => return Some(end),
        };
        if self.args.duration.is_some_and(|duration| self.started.elapsed() >= duration) {
            return Some(End::TimeUp);
        }
        self.sender.set_target(self.target.0, self.target.1);
        let status = self.session.status();
        if let Some(end) = self.guard.after_command(&status, &stats, stats.sent) {
            return Some(end);
        }
        self.print_status(out, &status)
    }

    /// The status line, when it is due; `Some` when the output went away.
    fn print_status(&mut self, out: &mut impl Write, status: &RobotStatus) -> Option<End> {
        if self.last_status.elapsed() < self.status_every {
            return None;
        }
        let view = status_view(self.started.elapsed(), self.target, self.sender, status);
        let written = match self.style {
            Style::Overwrite => {
                let width = terminal_columns().unwrap_or(DEFAULT_COLUMNS);
                write!(out, "\r{CLEAR_LINE}{}", status::fit(&view, width))
            }
            Style::Lines => writeln!(out, "{}", status::full(&view)),
            Style::Json => writeln!(out, "{}", status::json(&view)),
        };
        if let Err(error) = written.and_then(|()| out.flush()) {
            return Some(End::OutputGone(error.to_string()));
        }
        self.last_status = Instant::now();
        None
    }
}

/// The status of this moment, for [`status::fit`], [`status::full`] or [`status::json`].
fn status_view(
    elapsed: Duration,
    target: (f64, f64),
    sender: &MotionSender,
    status: &RobotStatus,
) -> status::Status {
    let sent = sender.stats().sent;
    status::Status {
        elapsed,
        target,
        sent: (sent.linear(), sent.angular()),
        measured: status.motion.map(|(_, motion)| (motion.linear(), motion.angular())),
        robot: status
            .fresh_system(Duration::from_millis(500))
            .map(|(state, wire)| status::Robot::new(&state, wire)),
        send_error: sender.last_error(),
    }
}

/// A terminal that does not say its width is taken as this wide.
const DEFAULT_COLUMNS: usize = 80;

/// The width of the terminal on stdout, asked at every update (it may be resized).
#[cfg(unix)]
fn terminal_columns() -> Option<usize> {
    // SAFETY: winsize is four integers, for which all zeros is a valid value.
    let mut size: libc::winsize = unsafe { std::mem::zeroed() };
    // SAFETY: TIOCGWINSZ fills the winsize it is given and touches nothing else.
    let done = unsafe { libc::ioctl(libc::STDOUT_FILENO, libc::TIOCGWINSZ, &mut size) };
    (done == 0 && size.ws_col > 0).then_some(usize::from(size.ws_col))
}

#[cfg(not(unix))]
fn terminal_columns() -> Option<usize> {
    None
}
