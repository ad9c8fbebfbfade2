//! The commissioning drive itself: each step of the plan held for its duration on the sender's own 50 Hz
//! clock, under drive's guard ([`Strictness::Strict`]) and the operator's keyboard, the step start times
//! taken on the recording's clock so each figure is named by its step. Nothing here judges the figures.

use std::time::{Duration, Instant};

use super::keys::{self, Keyboard, Press};
use super::verdict::{Observed, StepTimes};
use crate::commands::drive::{End, Follow, Guard, Strictness, REFRESH};
use crate::control::sender::MotionSender;
use crate::health::plan::{Action, Step};
use crate::protocol::message::{MotionCommand, COMMAND_TIMEOUT};
use crate::session::Session;
use crate::signals::SignalFlag;

/// Measured linear speed below this is standing still, m/s (the protocol's resolution is 1 mm/s).
const STANDSTILL: f64 = 0.01;
/// A moving step starts only when the robot was heard from within this long (it sends a frame every few ms):
/// otherwise the drive holds zero until it is, or until the guard's silence limit ends the drive. Without
/// this, a link that fell silent during a rest had the next step drive blind until that limit.
const FRESH_FEEDBACK: Duration = Duration::from_millis(100);

/// Until when a step is held.
#[derive(Clone, Copy, Debug)]
enum Until {
    /// Its end.
    Time(Instant),
    /// The robot's next frame.
    FreshFeedback,
}

/// How the drive went.
pub struct Driven {
    /// Why it ended early; `None` when every step ran.
    pub end: Option<End>,
    pub steps: StepTimes,
    /// Steps begun (the last one possibly cut short).
    pub begun: usize,
    pub observed: Observed,
    pub follow: Follow,
    pub started: Instant,
}

/// What the drive runs with.
pub struct Drive<'a> {
    pub session: &'a Session,
    pub sender: &'a MotionSender,
    pub signal: &'a SignalFlag,
    pub keyboard: Option<&'a Keyboard>,
    /// The robot must have stopped by itself this long after the last command of the timeout probe.
    pub timeout_fail: Duration,
    /// Progress lines on stderr.
    pub progress: bool,
}

impl Drive<'_> {
    /// Runs the steps; returns how far it got and why it stopped.
    pub fn run(&self, plan: &[Step]) -> Driven {
        let mut guard = Guard::new(self.sender, Strictness::Strict);
        let started = Instant::now();
        let mut driven = Driven {
            end: None,
            steps: StepTimes::default(),
            begun: 0,
            observed: Observed {
                timeout_probe: plan.iter().any(|step| step.action == Action::Silence),
                still_moving_after_ms: None,
            },
            follow: Follow::default(),
            started,
        };
        let mut silent = false;
        for (number, step) in plan.iter().enumerate() {
            driven.begun = number + 1;
            if let Some(end) = self.await_feedback(&mut guard, step, &mut driven.observed) {
                driven.end = Some(end);
                break;
            }
            driven.steps.starts.push((step.name.to_string(), crate::link::now_timestamp().as_micros_i64()));
            if self.progress {
                keys::say_line(&format!(
                    "step {}/{}: {} ({:.1} s)",
                    number + 1,
                    plan.len(),
                    step.name,
                    step.duration.as_secs_f64()
                ));
            }
            let last_command = self.sender.stats().sent_at;
            match step.action {
                Action::Command { linear, angular } => {
                    if silent {
                        // After the silence: only fresh commands, from rest.
                        self.sender.resume();
                        silent = false;
                    }
                    self.sender.set_target_now(linear, angular);
                }
                Action::Silence => {
                    self.sender.silence();
                    silent = true;
                }
            }
            let step_end = Until::Time(Instant::now() + step.duration);
            if let Some(end) = self.hold(&mut guard, step, step_end, last_command, &mut driven.observed) {
                driven.end = Some(end);
                break;
            }
        }
        driven.follow = guard.follow;
        driven
    }

    /// Before a moving step: zero held until the robot's feedback is fresh ([`FRESH_FEEDBACK`]); `Some`
    /// when the drive must end meanwhile (the guard's silence limit, a key, a signal...).
    fn await_feedback(&self, guard: &mut Guard<'_>, step: &Step, observed: &mut Observed) -> Option<End> {
        let moving =
            matches!(step.action, Action::Command { linear, angular } if linear != 0.0 || angular != 0.0);
        if !moving || fresh(&self.session.status()) {
            return None;
        }
        let rest = Step {
            name: step.name,
            duration: Duration::ZERO,
            action: Action::Command { linear: 0.0, angular: 0.0 },
        };
        self.hold(guard, &rest, Until::FreshFeedback, None, observed)
    }

    /// Holds one step until `until`; `Some` when the drive must end.
    fn hold(
        &self,
        guard: &mut Guard<'_>,
        step: &Step,
        until: Until,
        last_command: Option<Instant>,
        observed: &mut Observed,
    ) -> Option<End> {
        loop {
            let stats = match guard.before_command(self.signal) {
                Ok(stats) => stats,
                Err(end) => return Some(end),
            };
            if let Some(press) = self.keyboard.and_then(Keyboard::pressed) {
                return Some(match press {
                    Press::Interrupt(caught) => End::Signal(caught),
                    Press::Yes => {
                        End::Key(crate::dashboard::keys::key_name(crate::dashboard::keys::Action::Yes).into())
                    }
                    Press::Other(name) => End::Key(name),
                    Press::Closed(why) => End::Key(format!("the terminal went away: {why}")),
                });
            }
            let over = match until {
                Until::Time(end) => Instant::now() >= end,
                Until::FreshFeedback => fresh(&self.session.status()),
            };
            if over {
                return None;
            }
            let following = match step.action {
                Action::Command { linear, angular } => {
                    self.sender.set_target(linear, angular);
                    stats.sent
                }
                Action::Silence => MotionCommand::STOP,
            };
            let status = self.session.status();
            if let Some(end) = guard.after_command(&status, &stats, following) {
                return Some(end);
            }
            if step.action == Action::Silence {
                watch_own_stop(&status, last_command, self.timeout_fail, observed);
            }
            // Woken by every frame the robot sends (about every 3 ms), so an E-stop, a fault or a mode
            // change in a status frame ends the step within the period it came in, not a period later;
            // keys are looked at on each wake too. At most REFRESH keeps the sender's watchdog fed.
            self.session.wait_for_change(REFRESH);
        }
    }
}

/// The robot was heard from within [`FRESH_FEEDBACK`].
fn fresh(status: &crate::session::RobotStatus) -> bool {
    status.last_frame.is_some_and(|at| at.elapsed() <= FRESH_FEEDBACK)
}

/// During the silence: the robot still moving `timeout_fail` after the last command has not stopped by
/// itself (its command timeout is documented as 500 ms).
fn watch_own_stop(
    status: &crate::session::RobotStatus,
    last_command: Option<Instant>,
    timeout_fail: Duration,
    observed: &mut Observed,
) {
    let Some(last) = last_command else { return };
    let Some((at, motion)) = status.motion else { return };
    let since = at.saturating_duration_since(last);
    if since >= timeout_fail.max(COMMAND_TIMEOUT) && motion.linear().abs() > STANDSTILL {
        observed.still_moving_after_ms.get_or_insert(since.as_secs_f64() * 1000.0);
    }
}
