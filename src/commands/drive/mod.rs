//! `tracerctl drive`: drive at a fixed speed, ramped and capped, with zero-velocity frames on every way out.
//!
//! The stop rules (docs/architecture.md) as drive applies them: signals are handled from the very start;
//! SIGTSTP sends zeros before the process stops; any gap in the sender's clock (a suspension, a stalled
//! machine) or a watchdog trip ends the drive with zeros, since the robot has stopped by itself and only a
//! fresh command may move it again; and the report says whether the stop frames really left.

mod status;

use std::io::{IsTerminal, Write};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;

use super::live;
use super::Global;
use crate::control::limits::Limits;
use crate::control::sender::{Hold, MotionSender, SenderStats, Stopper, GAP_LIMIT, PERIOD};
use crate::exit::{self, Failure, FAILURE, NOT_DONE, SUCCESS};
use crate::link::queue_full_meaning;

/// The report's words for a pseudo-terminal's flush before the stop frames: it drops what the peer has not
/// taken in (a stalled peer's backlog, or the latest frames on a loaded machine) and cannot say how much.
pub const UNCOUNTED_DISCARD: &str =
    "output the pseudo-terminal still held flushed before the stop frames, uncounted";
use crate::output::palette::CLEAR_LINE;
use crate::output::Format;
use crate::protocol::detect::Verdict;
use crate::protocol::message::{MotionCommand, COMMAND_TIMEOUT};
use crate::protocol::Codec;
use crate::protocol::{ControlMode, Wire};
use crate::session::{RobotStatus, Session};
use crate::signals::{self, Caught, SignalFlag};

/// The main loop refreshes the target this often; the watchdog zeroes it if that stops for this long.
const REFRESH: Duration = Duration::from_millis(20);
const WATCHDOG: Duration = Duration::from_millis(250);
/// Status line rate on a terminal; in a pipe or log (or as JSON), one line a second.
const STATUS_EVERY_TTY: Duration = Duration::from_millis(250);
const STATUS_EVERY_PIPE: Duration = Duration::from_secs(1);
/// Re-enable command mode at most this often when the robot reports another mode.
const MODE_RETRY: Duration = Duration::from_millis(200);
/// The robot sends feedback every 20 ms; this long without any frame means the link is gone.
const FEEDBACK_LOST: Duration = Duration::from_secs(1);
/// A commanded speed at least this large (m/s or rad/s) should show in the robot's measured speed...
const MOVING_COMMAND: f64 = 0.05;
/// ... as at least this share of it ...
const FOLLOW_SHARE: f64 = 0.25;
/// ... within this long; otherwise the robot is not following and the drive ends.
const FOLLOW_WINDOW: Duration = Duration::from_millis(1500);
/// Motion feedback older than this is not a measurement of now.
const MOTION_FRESH: Duration = Duration::from_millis(200);
/// How long SIGTSTP waits for the zero frame to leave before the process stops anyway.
const SUSPEND_WAIT: Duration = Duration::from_millis(100);

/// Why the drive ended.
#[derive(Debug, PartialEq)]
enum End {
    TimeUp,
    Signal(Caught),
    EStop,
    /// The robot reported the vehicle state "exception" (a latched fault, battery cut-off, RC link lost).
    Exception,
    LinkLost(String),
    /// The sender's clock jumped by this much: suspended, or the machine stalled.
    Suspended(Duration),
    /// SIGTSTP sent zeros, and SIGCONT came before any gap showed.
    SuspendResumed,
    /// The main loop stopped refreshing the target; the watchdog zeroed it.
    Watchdog,
    /// The robot's measured speed did not follow the command; why, as far as the status tells.
    NotFollowing(String),
    /// The status output (stdout) went away: nobody can watch the drive any more.
    OutputGone(String),
}

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
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let limits = args.limits;
    // Signals first: a Ctrl-C while the link opens or the robot is awaited must end the command cleanly.
    let sender_slot: Arc<Mutex<Option<Stopper>>> = Arc::default();
    let suspended_early = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let signal = {
        let (on_signal, on_suspend) = (Arc::clone(&sender_slot), Arc::clone(&sender_slot));
        let early = Arc::clone(&suspended_early);
        signals::listen_suspendable(
            move |_| {
                if let Some(stopper) = on_signal.lock().as_ref() {
                    stopper.stop_now();
                }
            },
            move || match on_suspend.lock().as_ref() {
                Some(stopper) => {
                    stopper.suspend(SUSPEND_WAIT);
                }
                None => early.store(true, std::sync::atomic::Ordering::SeqCst),
            },
        )?
    };
    let session = live::open(global, true)?;
    let context = Context { signal, sender_slot, suspended_early };
    // Status and the report go to stdout, for scripts (`drive ... > run.txt`); diagnostics to stderr.
    execute_with(&session, args, limits, &mut std::io::stdout(), &context).map_err(|error| {
        // A broken pipe is a quiet success for output nobody reads any more (decode | head), not for the
        // status of a robot being driven: whoever watched it must learn from the exit status that it is gone.
        if exit::is_broken_pipe(&error) {
            Failure { code: FAILURE, message: format!("the status output went away ({error:#})") }.into()
        } else {
            error
        }
    })
}

/// What `run` sets up before the session: the signal flag and where the sender's stopper goes.
struct Context {
    signal: SignalFlag,
    sender_slot: Arc<Mutex<Option<Stopper>>>,
    suspended_early: Arc<std::sync::atomic::AtomicBool>,
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
    if let Some(status) = check_before_driving(session, args, out, context)? {
        return Ok(status);
    }

    let sender = MotionSender::start(session.tx.clone(), Codec::new(session.wire()), limits, WATCHDOG)?;
    *context.sender_slot.lock() = Some(sender.stopper());

    let mut drive = DriveLoop::new(session, args, target, &sender);
    let end = drive.run(out, signal);
    let DriveLoop { started, follow, style, .. } = drive;
    let stats = match end {
        End::TimeUp => sender.ramp_down_and_stop(&limits),
        _ => sender.stop(),
    };
    // A signal during the ramp down stopped it at once (the signal thread ends the sender): say so.
    let end = match (end, signal.caught()) {
        (End::TimeUp, Some(caught)) => End::Signal(caught),
        (end, _) => end,
    };
    context.sender_slot.lock().take();
    // Ends the overwritten line; a failure shows again when the report is written.
    if style == Style::Overwrite && !matches!(end, End::OutputGone(_)) {
        let _ = writeln!(out);
    }
    let elapsed = started.elapsed().as_secs_f64();
    let parts = report(&stats, &follow, session);
    let report = parts.join("; ");
    let result = outcome(&end, &stats, &follow, elapsed, &report, session);
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

/// Waits for the robot's first status and refuses to drive a robot that cannot (unless --ignore-faults).
/// `Some(exit status)` when a signal came first: nothing was sent.
fn check_before_driving(
    session: &Session,
    args: &Options,
    out: &mut impl Write,
    context: &Context,
) -> Result<Option<u8>> {
    let signal = &context.signal;
    let first = live::first_status_unless(session, || signal.received().is_some());
    if let Some(caught) = signal.caught() {
        crate::say!("tracerctl: {} before driving: nothing was sent", caught.name());
        return Ok(Some(caught.exit_status()));
    }
    let refusal = match first {
        Some((state, wire)) => {
            // The wire the status came on; the detector's counts only when the bus carries both versions.
            let protocol = match (wire, session.status().detector.verdict()) {
                (Wire::Serial, _) => "RS232".to_string(),
                (_, Verdict::Mixed) => session.status().detector.describe(),
                (Wire::CanV1, _) => "CAN V1".to_string(),
                (Wire::CanV2, _) => "CAN V2".to_string(),
            };
            if args.format == Format::Text {
                writeln!(out, "robot: {} (protocol {protocol})", live::describe(&state, wire))?;
            }
            state.why_not_drivable(wire)
        }
        // No feedback at all: nothing would show whether the robot moves, stops or is there at all, so
        // --ignore-faults (which overrides what the robot reports) has nothing to override.
        None => {
            return Err(Failure::not_done(format!(
                "not driving: {}",
                live::no_status_message(session, &session.status())
            ))
            .into())
        }
    };
    if let Some(reason) = refusal {
        if !args.ignore_faults {
            return Err(
                Failure::not_done(format!("not driving: {reason} (--ignore-faults to try anyway)")).into()
            );
        }
        crate::say!("tracerctl: warning: {reason}; driving anyway (--ignore-faults)");
    }
    if context.suspended_early.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(Failure {
            code: FAILURE,
            message: "suspended before driving started: drive ended (run it again to drive)".to_string(),
        }
        .into());
    }
    Ok(None)
}

/// The main loop's state: it refreshes the target, watches the sender and the robot, and prints the status.
struct DriveLoop<'a> {
    session: &'a Session,
    args: &'a Options,
    target: (f64, f64),
    sender: &'a MotionSender,
    started: Instant,
    last_status: Instant,
    last_mode_request: Instant,
    last_iteration: Instant,
    follow: Follow,
    suspend_seen: Option<Instant>,
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
            last_mode_request: Instant::now(),
            last_iteration: Instant::now(),
            follow: Follow::default(),
            suspend_seen: None,
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
        if let Some(caught) = signal.caught() {
            return Some(End::Signal(caught));
        }
        // After a gap in this loop (suspended with the rest of the process, or blocked on a slow
        // terminal), let the sender take its next tick first: it alone knows whether commands stopped.
        let since = self.last_iteration.elapsed();
        self.last_iteration = Instant::now();
        if since > GAP_LIMIT {
            std::thread::sleep(PERIOD * 2);
        }
        let stats = self.sender.stats();
        if let Some(end) = self.sender_held(&stats) {
            return Some(end);
        }
        if self.args.duration.is_some_and(|duration| self.started.elapsed() >= duration) {
            return Some(End::TimeUp);
        }
        self.sender.set_target(self.target.0, self.target.1);
        if crate::control::stop::panicked() {
            return Some(End::LinkLost("an internal error (a thread panicked)".to_string()));
        }
        let status = self.session.status();
        if let Some(end) = self.watch_robot(&status, &stats) {
            return Some(end);
        }
        self.print_status(out, &status)
    }

    /// The sender held the robot at zero (a gap in its clock, its watchdog, or SIGTSTP).
    fn sender_held(&mut self, stats: &SenderStats) -> Option<End> {
        match stats.hold {
            Some(Hold::Gap(gap)) => Some(End::Suspended(gap.max(stats.last_gap.unwrap_or_default()))),
            Some(Hold::Watchdog) => Some(End::Watchdog),
            // SIGTSTP sent zeros and stops the process; after SIGCONT the sender sees the gap. A SIGCONT so
            // quick that no gap shows still ends the drive: the hold is never lifted by drive.
            Some(Hold::Suspend) => {
                let since = *self.suspend_seen.get_or_insert_with(Instant::now);
                (since.elapsed() > GAP_LIMIT * 2).then_some(End::SuspendResumed)
            }
            _ => None,
        }
    }

    /// The link, the feedback, the E-stop, the mode and whether the robot follows the command.
    fn watch_robot(&mut self, status: &RobotStatus, stats: &SenderStats) -> Option<End> {
        if let Some(error) = status.link_error.clone() {
            return Some(End::LinkLost(error));
        }
        // Had feedback, and it stopped: do not keep driving blind. (On CAN, `last_frame` is when the robot
        // sent it, so a backlog read late does not count as fresh.)
        if status.last_frame.is_some_and(|at| at.elapsed() > FEEDBACK_LOST) {
            return Some(End::LinkLost(format!(
                "no frames from the robot for {} s",
                FEEDBACK_LOST.as_secs()
            )));
        }
        if let Some((state, wire)) = status.fresh_system(Duration::from_millis(200)) {
            if state.is_estop() && !self.args.ignore_faults {
                return Some(End::EStop);
            }
            // The robot stopped obeying by itself: end now rather than when the follow check notices.
            if state.is_exception() && !self.args.ignore_faults {
                return Some(End::Exception);
            }
            // Power-cycle or RC override put the robot in another mode: ask for command mode again.
            if wire == Wire::CanV2
                && state.mode(wire) != Some(ControlMode::Can)
                && self.last_mode_request.elapsed() >= MODE_RETRY
            {
                self.sender.request_mode_enable();
                self.last_mode_request = Instant::now();
            }
        }
        if self.follow.observe(status, stats.sent) && !self.args.ignore_faults {
            return Some(End::NotFollowing(robot_words(status)));
        }
        None
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

/// The exit status or the error for how the drive ended, with the report.
fn outcome(
    end: &End,
    stats: &SenderStats,
    follow: &Follow,
    elapsed: f64,
    report: &str,
    session: &Session,
) -> Result<u8> {
    match end {
        End::TimeUp => Ok(if stats.stop_confirmed() { SUCCESS } else { FAILURE }),
        End::Signal(caught) => Ok(caught.exit_status()),
        End::EStop => {
            Err(Failure::not_done(format!("stopped after {elapsed:.2} s: the E-stop was pressed; {report}"))
                .into())
        }
        End::Exception => Err(Failure::not_done(format!(
            "stopped after {elapsed:.2} s: {}; {report}",
            crate::protocol::message::EXCEPTION_REASON
        ))
        .into()),
        End::NotFollowing(robot) => Err(Failure {
            code: NOT_DONE,
            message: format!(
                "stopped after {elapsed:.2} s: the robot did not follow the command: sent {:+.3} m/s \
                 {:+.3} rad/s for {:.1} s, it reported {:+.3} m/s {:+.3} rad/s ({robot}); {report}",
                follow.commanded.linear(),
                follow.commanded.angular(),
                FOLLOW_WINDOW.as_secs_f64(),
                follow.measured.0,
                follow.measured.1,
            ),
        }
        .into()),
        End::Suspended(gap) => {
            Err(Failure { code: FAILURE, message: format!("{}; {report}", suspended_message(*gap)) }.into())
        }
        End::SuspendResumed => Err(Failure {
            code: FAILURE,
            message: format!(
                "suspended (SIGTSTP) after {elapsed:.2} s: zero frames were sent before stopping; drive ended \
                 (after a suspension it never resumes by itself); {report}"
            ),
        }
        .into()),
        End::Watchdog => Err(Failure {
            code: FAILURE,
            message: format!(
                "stopped after {elapsed:.2} s: drive's own loop stalled for more than {} ms and the watchdog \
                 commanded zero; drive ended (a stalled command is never resumed); {report}",
                WATCHDOG.as_millis()
            ),
        }
        .into()),
        End::LinkLost(error) => anyhow::bail!(
            "stopped after {elapsed:.2} s: the link {} failed ({error}); {report}",
            session.name
        ),
        // The stdout reader is gone: nothing more can be said there; the robot was stopped above.
        End::OutputGone(error) => {
            Err(Failure { code: FAILURE, message: format!("the status output went away ({error})") }.into())
        }
    }
}

/// `suspended for 0.80 s, longer than the robot's 500 ms command timeout: the robot stopped; drive ended`
fn suspended_message(gap: Duration) -> String {
    let seconds = gap.as_secs_f64();
    if gap >= COMMAND_TIMEOUT {
        format!(
            "suspended for {seconds:.2} s, longer than the robot's {} ms command timeout: the robot stopped; \
             drive ended",
            COMMAND_TIMEOUT.as_millis()
        )
    } else {
        format!(
            "suspended for {seconds:.2} s (no command for more than {} ms): the ramp was reset and only a \
             fresh command moves the robot again; drive ended",
            GAP_LIMIT.as_millis()
        )
    }
}

/// The end-of-run report, in parts: frames, what the robot measured, and whether the stop frames really left.
fn report(stats: &SenderStats, follow: &Follow, session: &Session) -> Vec<String> {
    let mut parts = vec![format!("{} motion frames sent", stats.frames)];
    let mut trouble = Vec::new();
    if stats.send_errors > 0 {
        trouble.push(format!("{} send errors", stats.send_errors));
    }
    if stats.queue_full > 0 {
        trouble.push(format!("{} not sent ({})", stats.queue_full, queue_full_meaning(session.kind)));
    }
    if stats.held_back > 0 {
        trouble.push(format!("{} held back while the link's output was not draining", stats.held_back));
    }
    if stats.discarded > 0 {
        trouble.push(format!("{} stale frames discarded before the stop frames", stats.discarded));
    }
    if stats.discarded_uncounted {
        trouble.push(UNCOUNTED_DISCARD.to_string());
    }
    if stats.watchdog_trips > 0 {
        trouble.push(format!("{} watchdog stops", stats.watchdog_trips));
    }
    if !trouble.is_empty() {
        parts[0] = format!("{} ({})", parts[0], trouble.join(", "));
    }
    parts.push(if follow.samples > 0 {
        format!("distance {:.2} m, peak measured {:+.3} m/s", follow.distance, follow.peak_linear)
    } else {
        "the robot reported no speed (no motion state frames)".to_string()
    });
    if stats.stop_confirmed() {
        parts.push(format!(
            "last command {:+.3} m/s {:+.3} rad/s",
            stats.sent.linear(),
            stats.sent.angular()
        ));
    } else if stats.stop_frames_queued > 0 {
        parts.push(format!(
            "the stop frames are still queued in the adapter ({} frames waiting: it is not sending, or the \
             peer does not read): the robot's own {} ms command timeout stops it",
            stats.stop_frames_queued,
            COMMAND_TIMEOUT.as_millis()
        ));
    } else {
        let why = session_error(session).unwrap_or_else(|| "nothing was accepted by the link".to_string());
        parts.push(format!(
            "the stop frames could not be sent ({why}): the robot's own {} ms command timeout stops it",
            COMMAND_TIMEOUT.as_millis()
        ));
    }
    parts
}

/// Why the link cannot take frames, if it said.
fn session_error(session: &Session) -> Option<String> {
    session.status().link_error
}

/// What the robot's status says, for a report.
fn robot_words(status: &RobotStatus) -> String {
    match status.fresh_system(Duration::from_millis(500)) {
        Some((state, wire)) => format!("robot: {}", live::describe(&state, wire)),
        None => "no recent status from the robot".to_string(),
    }
}

/// What the robot measured while driving: distance, peak speed, and whether it follows the command.
#[derive(Debug, Default)]
struct Follow {
    /// Motion-state samples seen, the time of the latest (to integrate the distance once per sample).
    samples: u64,
    last_sample: Option<Instant>,
    distance: f64,
    peak_linear: f64,
    /// Since when a moving command has shown no matching movement.
    lagging_since: Option<Instant>,
    /// The command and the measurement when it was judged.
    commanded: MotionCommand,
    measured: (f64, f64),
}

impl Follow {
    /// Takes the latest status; true when the robot has not followed a moving command for
    /// [`FOLLOW_WINDOW`].
    fn observe(&mut self, status: &RobotStatus, sent: MotionCommand) -> bool {
        let Some((at, motion)) = status.motion.filter(|(at, _)| at.elapsed() <= MOTION_FRESH) else {
            return false;
        };
        let measured = (motion.linear(), motion.angular());
        if self.last_sample != Some(at) {
            if let Some(previous) = self.last_sample {
                let dt = at.saturating_duration_since(previous).min(Duration::from_millis(100));
                self.distance += measured.0.abs() * dt.as_secs_f64();
            }
            self.last_sample = Some(at);
            self.samples += 1;
            if measured.0.abs() > self.peak_linear.abs() {
                self.peak_linear = measured.0;
            }
        }
        let follows = |commanded: f64, measured: f64| {
            commanded.abs() < MOVING_COMMAND
                || measured * commanded.signum() >= FOLLOW_SHARE * commanded.abs()
        };
        let commanding = sent.linear().abs() >= MOVING_COMMAND || sent.angular().abs() >= MOVING_COMMAND;
        if commanding && !(follows(sent.linear(), measured.0) && follows(sent.angular(), measured.1)) {
            let since = *self.lagging_since.get_or_insert_with(Instant::now);
            self.commanded = sent;
            self.measured = measured;
            return since.elapsed() >= FOLLOW_WINDOW;
        }
        self.lagging_since = None;
        false
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

impl End {
    /// The `end` of the JSON report.
    fn name(&self) -> &'static str {
        match self {
            End::TimeUp => "time_up",
            End::Signal(..) => "signal",
            End::EStop => "estop",
            End::Exception => "exception",
            End::LinkLost(_) => "link_lost",
            End::Suspended(_) | End::SuspendResumed => "suspended",
            End::Watchdog => "watchdog",
            End::NotFollowing(_) => "not_following",
            End::OutputGone(_) => "output_gone",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::MotionState;

    fn moving(linear_mm_s: i16) -> RobotStatus {
        RobotStatus {
            motion: Some((Instant::now(), MotionState { linear_mm_s, ..MotionState::default() })),
            ..RobotStatus::default()
        }
    }

    #[test]
    fn the_suspension_message_says_why_the_drive_ended() {
        assert_eq!(
            suspended_message(Duration::from_millis(800)),
            "suspended for 0.80 s, longer than the robot's 500 ms command timeout: the robot stopped; drive ended"
        );
        assert!(suspended_message(Duration::from_millis(250)).starts_with("suspended for 0.25 s (no command"));
    }

    #[test]
    fn a_robot_that_stays_still_is_not_following_after_the_window() {
        let mut follow = Follow::default();
        let command = MotionCommand { linear_mm_s: 300, angular_mrad_s: 0 };
        assert!(!follow.observe(&moving(0), command), "judged only after the window");
        follow.lagging_since = Some(Instant::now() - FOLLOW_WINDOW);
        assert!(follow.observe(&moving(0), command));
        assert_eq!(follow.measured, (0.0, 0.0));
        // Moving at a quarter of the command or more is following; a small command is never judged.
        let mut follow = Follow { lagging_since: Some(Instant::now() - FOLLOW_WINDOW), ..Follow::default() };
        assert!(!follow.observe(&moving(80), command));
        assert_eq!(follow.lagging_since, None);
        let slow = MotionCommand { linear_mm_s: 30, angular_mrad_s: 0 };
        assert!(!Follow { lagging_since: Some(Instant::now() - FOLLOW_WINDOW), ..Follow::default() }
            .observe(&moving(0), slow));
        // Backwards while asked forwards is not following.
        let mut follow = Follow { lagging_since: Some(Instant::now() - FOLLOW_WINDOW), ..Follow::default() };
        assert!(follow.observe(&moving(-300), command));
    }

    #[test]
    fn distance_and_peak_come_from_the_measured_speed() {
        let mut follow = Follow::default();
        let start = Instant::now() - Duration::from_millis(100);
        for step in 0..5u64 {
            let status = RobotStatus {
                motion: Some((
                    start + Duration::from_millis(20 * step),
                    MotionState { linear_mm_s: 500, ..MotionState::default() },
                )),
                ..RobotStatus::default()
            };
            follow.observe(&status, MotionCommand { linear_mm_s: 500, angular_mrad_s: 0 });
        }
        assert_eq!(follow.samples, 5);
        assert!((follow.distance - 0.04).abs() < 1e-9, "{}", follow.distance);
        assert_eq!(follow.peak_linear, 0.5);
    }
}
