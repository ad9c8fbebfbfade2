//! The stop rules of a drive, shared by `drive` and `commission`: the checks before the first motion frame,
//! the checks every iteration of the loop that refreshes the sender's target (signals, the sender's holds,
//! the link, the feedback, the E-stop, the vehicle state, the mode, whether the robot follows), why a drive
//! ended in words and exit status, and the end-of-run report that says whether the stop frames left.
//!
//! `drive` is lenient where its options say so (`--ignore-faults`; it asks for command mode again when the
//! robot leaves it); `commission` is [`Strictness::Strict`]: a new fault bit, RC override, leaving command
//! mode or a serial peer that stops reading end it too, since a measurement under any of them is no
//! measurement.

use std::io::Write;
use std::time::{Duration, Instant};

use anyhow::Result;

use super::UNCOUNTED_DISCARD;
use crate::commands::live;
use crate::control::sender::{Hold, MotionSender, SenderStats, GAP_LIMIT, PERIOD};
use crate::exit::{Failure, FAILURE, NOT_DONE};
use crate::link::queue_full_meaning;
use crate::output::Format;
use crate::protocol::detect::Verdict;
use crate::protocol::faults::Severity;
use crate::protocol::message::{MotionCommand, COMMAND_TIMEOUT};
use crate::protocol::{ControlMode, Wire};
use crate::session::{RobotStatus, Session};
use crate::signals::{Caught, SignalFlag};

/// Re-enable command mode at most this often when the robot reports another mode.
const MODE_RETRY: Duration = Duration::from_millis(200);
/// The robot sends feedback every 20 ms; this long without any frame means the link is gone.
pub(crate) const FEEDBACK_LOST: Duration = Duration::from_secs(1);
/// A commanded speed at least this large (m/s or rad/s) should show in the robot's measured speed...
const MOVING_COMMAND: f64 = 0.05;
/// ... as at least this share of it ...
const FOLLOW_SHARE: f64 = 0.25;
/// ... within this long; otherwise the robot is not following and the drive ends.
pub(crate) const FOLLOW_WINDOW: Duration = Duration::from_millis(1500);
/// Motion feedback older than this is not a measurement of now.
const MOTION_FRESH: Duration = Duration::from_millis(200);
/// Watchdog of the loops that refresh the target (every 20 ms).
pub(crate) const WATCHDOG: Duration = Duration::from_millis(250);

/// Why a drive ended.
#[derive(Debug, PartialEq)]
pub(crate) enum End {
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
    /// Strict: a fault bit above info appeared (the fault list).
    Fault(String),
    /// Strict: the RC transmitter took over (SWB in the middle).
    RcOverride,
    /// Strict: the robot left command mode (the mode it reports now).
    ModeChanged(String),
    /// Strict: the link's output is not draining (a serial peer that stopped reading): motion held back.
    PeerStalled(u64),
    /// The operator pressed a key (its name, from the key table or the terminal's).
    Key(String),
}

impl End {
    /// The `end` of the JSON reports.
    pub(crate) fn name(&self) -> &'static str {
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
            End::Fault(_) => "fault",
            End::RcOverride => "rc_override",
            End::ModeChanged(_) => "mode_changed",
            End::PeerStalled(_) => "peer_stalled",
            End::Key(_) => "key",
        }
    }

    /// The exit status of a drive that ended so, short of finishing.
    pub(crate) fn exit_status(&self) -> u8 {
        match self {
            End::TimeUp => crate::exit::SUCCESS,
            End::Signal(caught) => caught.exit_status(),
            End::EStop
            | End::Exception
            | End::NotFollowing(_)
            | End::Fault(_)
            | End::RcOverride
            | End::ModeChanged(_)
            | End::Key(_) => NOT_DONE,
            End::LinkLost(_)
            | End::Suspended(_)
            | End::SuspendResumed
            | End::Watchdog
            | End::OutputGone(_)
            | End::PeerStalled(_) => FAILURE,
        }
    }

    /// Why it ended, in a sentence: `stopped after 2.31 s: the E-stop was pressed`.
    pub(crate) fn words(&self, elapsed: f64, follow: &Follow, link: &str) -> String {
        let stopped = format!("stopped after {elapsed:.2} s");
        match self {
            End::TimeUp => format!("{stopped} (time up)"),
            End::Signal(caught) => format!("{stopped} ({})", caught.name()),
            End::EStop => format!("{stopped}: the E-stop was pressed"),
            End::Exception => format!("{stopped}: {}", crate::protocol::message::EXCEPTION_REASON),
            End::NotFollowing(robot) => format!(
                "{stopped}: the robot did not follow the command: sent {:+.3} m/s {:+.3} rad/s for {:.1} s, it \
                 reported {:+.3} m/s {:+.3} rad/s ({robot})",
                follow.commanded.linear(),
                follow.commanded.angular(),
                FOLLOW_WINDOW.as_secs_f64(),
                follow.measured.0,
                follow.measured.1,
            ),
            End::Suspended(gap) => suspended_message(*gap),
            End::SuspendResumed => format!(
                "suspended (SIGTSTP) after {elapsed:.2} s: zero frames were sent before stopping; drive ended \
                 (after a suspension it never resumes by itself)"
            ),
            End::Watchdog => format!(
                "{stopped}: drive's own loop stalled for more than {} ms and the watchdog commanded zero; drive \
                 ended (a stalled command is never resumed)",
                WATCHDOG.as_millis()
            ),
            End::LinkLost(error) => format!("{stopped}: the link {link} failed ({error})"),
            End::OutputGone(error) => format!("the status output went away ({error})"),
            End::Fault(faults) => format!("{stopped}: a fault appeared ({faults})"),
            End::RcOverride => {
                format!("{stopped}: the RC transmitter took over (SWB in the middle overrides commands)")
            }
            End::ModeChanged(mode) => format!("{stopped}: the robot left command mode (now {mode})"),
            End::PeerStalled(held) => format!(
                "{stopped}: the link's output is not draining (the peer stopped reading): {held} motion frames \
                 held back"
            ),
            End::Key(key) => format!("{stopped}: the operator pressed a key ({key})"),
        }
    }
}

/// The exit status or the error for how the drive ended, with the report.
pub(crate) fn outcome(
    end: &End,
    stats: &SenderStats,
    follow: &Follow,
    elapsed: f64,
    report: &str,
    session: &Session,
) -> Result<u8> {
    match end {
        End::TimeUp => Ok(if stats.stop_confirmed() { crate::exit::SUCCESS } else { FAILURE }),
        End::Signal(caught) => Ok(caught.exit_status()),
        // The stdout reader is gone: nothing more can be said there; the robot was stopped.
        End::OutputGone(_) => {
            Err(Failure { code: FAILURE, message: end.words(elapsed, follow, &session.name) }.into())
        }
        _ => Err(Failure {
            code: end.exit_status(),
            message: format!("{}; {report}", end.words(elapsed, follow, &session.name)),
        }
        .into()),
    }
}

/// `suspended for 0.80 s, longer than the robot's 500 ms command timeout: the robot stopped; drive ended`
pub(crate) fn suspended_message(gap: Duration) -> String {
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
pub(crate) fn report(stats: &SenderStats, follow: &Follow, session: &Session) -> Vec<String> {
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
        let why =
            session.status().link_error.unwrap_or_else(|| "nothing was accepted by the link".to_string());
        parts.push(format!(
            "the stop frames could not be sent ({why}): the robot's own {} ms command timeout stops it",
            COMMAND_TIMEOUT.as_millis()
        ));
    }
    parts
}

/// What the robot's status says, for a report.
fn robot_words(status: &RobotStatus) -> String {
    match status.fresh_system(Duration::from_millis(500)) {
        Some((state, wire)) => format!("robot: {}", live::describe(&state, wire)),
        None => "no recent status from the robot".to_string(),
    }
}

/// Waits for the robot's first status and refuses to drive a robot that cannot (unless `ignore_faults`).
/// `Some(exit status)` when a signal came first: nothing was sent. In text, says what the robot is.
pub(crate) fn check_before_driving(
    session: &Session,
    format: Format,
    ignore_faults: bool,
    out: &mut impl Write,
    signal: &SignalFlag,
) -> Result<Option<u8>> {
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
            if format == Format::Text {
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
        if !ignore_faults {
            return Err(
                Failure::not_done(format!("not driving: {reason} (--ignore-faults to try anyway)")).into()
            );
        }
        crate::say!("tracerctl: warning: {reason}; driving anyway (--ignore-faults)");
    }
    Ok(None)
}

/// How much ends a drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Strictness {
    /// `drive`: the E-stop and the exception end it (unless `ignore_faults`); another mode is asked back.
    Lenient { ignore_faults: bool },
    /// `commission`: also a new fault bit above info, RC override, leaving command mode, a stalled peer.
    Strict,
}

/// The checks of one iteration of a drive loop, and what they keep between iterations.
pub(crate) struct Guard<'a> {
    sender: &'a MotionSender,
    strictness: Strictness,
    last_mode_request: Instant,
    last_iteration: Instant,
    suspend_seen: Option<Instant>,
    /// The fault bits already set when the drive began (strict: only new ones end it).
    faults_at_start: Option<u16>,
    /// Strict: the robot has been seen in command mode (leaving it afterwards ends the drive).
    command_mode_seen: bool,
    pub(crate) follow: Follow,
}

impl<'a> Guard<'a> {
    pub(crate) fn new(sender: &'a MotionSender, strictness: Strictness) -> Self {
        Self {
            sender,
            strictness,
            last_mode_request: Instant::now(),
            last_iteration: Instant::now(),
            suspend_seen: None,
            faults_at_start: None,
            command_mode_seen: false,
            follow: Follow::default(),
        }
    }

    fn ignore_faults(&self) -> bool {
        self.strictness == Strictness::Lenient { ignore_faults: true }
    }

    /// Before the target is refreshed: a signal, a gap in this loop, the sender's holds. The sender's
    /// statistics when the drive may go on.
    pub(crate) fn before_command(&mut self, signal: &SignalFlag) -> Result<SenderStats, End> {
        if let Some(caught) = signal.caught() {
            return Err(End::Signal(caught));
        }
        // After a gap in this loop (suspended with the rest of the process, or blocked on a slow
        // terminal), let the sender take its next tick first: it alone knows whether commands stopped.
        let since = self.last_iteration.elapsed();
        self.last_iteration = Instant::now();
        if since > GAP_LIMIT {
            std::thread::sleep(PERIOD * 2);
        }
        let stats = self.sender.stats();
        match self.sender_held(&stats) {
            Some(end) => Err(end),
            None => Ok(stats),
        }
    }

    /// The sender held the robot at zero (a gap in its clock, its watchdog, or SIGTSTP).
    fn sender_held(&mut self, stats: &SenderStats) -> Option<End> {
        match stats.hold {
            Some(Hold::Gap(gap)) => Some(End::Suspended(gap.max(stats.last_gap.unwrap_or_default()))),
            Some(Hold::Watchdog) => Some(End::Watchdog),
            // SIGTSTP sent zeros and stops the process; after SIGCONT the sender sees the gap. A SIGCONT so
            // quick that no gap shows still ends the drive: the hold is never lifted by the drive.
            Some(Hold::Suspend) => {
                let since = *self.suspend_seen.get_or_insert_with(Instant::now);
                (since.elapsed() > GAP_LIMIT * 2).then_some(End::SuspendResumed)
            }
            _ => None,
        }
    }

    /// After the target is refreshed: the link, the feedback, the robot's state and whether it follows
    /// `following` (what the robot should be doing now: the sent command, or zero while nothing is sent).
    pub(crate) fn after_command(
        &mut self,
        status: &RobotStatus,
        stats: &SenderStats,
        following: MotionCommand,
    ) -> Option<End> {
        if crate::control::stop::panicked() {
            return Some(End::LinkLost("an internal error (a thread panicked)".to_string()));
        }
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
        if self.strictness == Strictness::Strict && stats.held_back > 0 {
            return Some(End::PeerStalled(stats.held_back));
        }
        if let Some((state, wire)) = status.fresh_system(Duration::from_millis(200)) {
            if let Some(end) = self.watch_state(&state, wire) {
                return Some(end);
            }
        }
        if self.follow.observe(status, following) && !self.ignore_faults() {
            return Some(End::NotFollowing(robot_words(status)));
        }
        None
    }

    /// The E-stop, the vehicle state, the faults and the mode.
    fn watch_state(&mut self, state: &crate::protocol::message::SystemState, wire: Wire) -> Option<End> {
        if state.is_estop() && !self.ignore_faults() {
            return Some(End::EStop);
        }
        // The robot stopped obeying by itself: end now rather than when the follow check notices.
        if state.is_exception() && !self.ignore_faults() {
            return Some(End::Exception);
        }
        let mode = state.mode(wire);
        if self.strictness == Strictness::Strict {
            let at_start = *self.faults_at_start.get_or_insert(state.fault_code);
            let faults = state.faults(wire);
            let new_problem =
                faults.iter().any(|fault| fault.severity.is_problem()) && state.fault_code != at_start;
            if new_problem || faults.worst().is_some_and(Severity::blocks_driving) {
                return Some(End::Fault(live::fault_list(state, wire)));
            }
            // V1 and RS232 report RC and standby alike (0): before the robot has taken command mode, that is
            // the standby every robot boots in, not an override.
            if state.rc_has_control(wire) && (wire == Wire::CanV2 || self.command_mode_seen) {
                return Some(End::RcOverride);
            }
            // Standby until the sender's mode-enable frame is taken; leaving this link's command mode after
            // that ends it (another host taking the robot into its own link's mode too).
            let own = if wire == Wire::Serial { ControlMode::Serial } else { ControlMode::Can };
            let commanded = mode == Some(own);
            if commanded {
                self.command_mode_seen = true;
            } else if self.command_mode_seen {
                return Some(End::ModeChanged(ControlMode::describe(wire, state.control_mode)));
            }
        }
        // Power-cycle or RC override put the robot in another mode: ask for command mode again.
        if wire == Wire::CanV2
            && mode != Some(ControlMode::Can)
            && self.last_mode_request.elapsed() >= MODE_RETRY
        {
            self.sender.request_mode_enable();
            self.last_mode_request = Instant::now();
        }
        None
    }
}

/// What the robot measured while driving: distance, peak speed, and whether it follows the command.
#[derive(Debug, Default)]
pub(crate) struct Follow {
    /// Motion-state samples seen, the time of the latest (to integrate the distance once per sample).
    pub(crate) samples: u64,
    last_sample: Option<Instant>,
    pub(crate) distance: f64,
    pub(crate) peak_linear: f64,
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
    fn every_end_has_words_and_a_status() {
        let follow = Follow::default();
        let ends = [
            (End::EStop, "stopped after 1.50 s: the E-stop was pressed", NOT_DONE),
            (End::Key("Space".into()), "stopped after 1.50 s: the operator pressed a key (Space)", NOT_DONE),
            (End::RcOverride, "stopped after 1.50 s: the RC transmitter took over", NOT_DONE),
            (
                End::ModeChanged("standby".into()),
                "stopped after 1.50 s: the robot left command mode",
                NOT_DONE,
            ),
            (End::PeerStalled(3), "stopped after 1.50 s: the link's output is not draining", FAILURE),
            (End::LinkLost("gone".into()), "stopped after 1.50 s: the link can0 failed (gone)", FAILURE),
        ];
        for (end, words, status) in ends {
            assert!(end.words(1.5, &follow, "can0").starts_with(words), "{end:?}");
            assert_eq!(end.exit_status(), status, "{end:?}");
        }
        assert_eq!(End::Signal(Caught { signal: crate::signals::SIGTERM }).exit_status(), 143);
    }

    struct Accepting;
    impl crate::link::FrameTx for Accepting {
        fn send(&self, _frame: &crate::link::LinkFrame) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// What a strict guard makes of a sequence of reported (vehicle state, mode byte) on `wire`.
    fn strict_ends(wire: Wire, reports: &[u8]) -> Vec<Option<&'static str>> {
        let sender = MotionSender::start(
            std::sync::Arc::new(Accepting),
            crate::protocol::Codec::new(wire),
            crate::control::limits::Limits::default(),
            WATCHDOG,
        )
        .unwrap();
        let mut guard = Guard::new(&sender, Strictness::Strict);
        let ends = reports
            .iter()
            .map(|&control_mode| {
                let state = crate::protocol::message::SystemState { control_mode, ..Default::default() };
                guard.watch_state(&state, wire).map(|end| end.name())
            })
            .collect();
        sender.stop();
        ends
    }

    #[test]
    fn strict_mode_rules_read_each_wire_s_mode_byte() {
        // RS232: 0 at boot is standby (the robot takes serial mode with the first frame); 0 after serial
        // mode is RC (or standby: the wire cannot tell); 1 is another host's CAN mode.
        assert_eq!(
            strict_ends(Wire::Serial, &[0, 0, 2, 2, 0]),
            [None, None, None, None, Some("rc_override")]
        );
        assert_eq!(strict_ends(Wire::Serial, &[0, 2, 1]), [None, None, Some("mode_changed")]);
        // CAN V2: standby until 0x421 is taken; serial mode (an RS232 host) or standby afterwards is a change.
        assert_eq!(strict_ends(Wire::CanV2, &[0, 1, 2]), [None, None, Some("mode_changed")]);
        assert_eq!(strict_ends(Wire::CanV2, &[0, 1, 0]), [None, None, Some("mode_changed")]);
        assert_eq!(strict_ends(Wire::CanV2, &[1, 3]), [None, Some("rc_override")]);
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
