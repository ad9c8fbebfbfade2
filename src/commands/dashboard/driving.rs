//! Arming, holding and resuming: the dashboard's side of the stop rules, over the motion sender. What it
//! has to say goes out as a [`Message`]; the renderer words it.

use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;

use crate::control::{Limits, MotionSender, Stopper};
use crate::dashboard::app::Arming;
use crate::dashboard::message::Message;
use crate::protocol::{Codec, ControlMode};
use crate::session::{RobotStatus, Session};

/// Input or drawing that stalls longer than this makes the sender command zero.
const WATCHDOG: Duration = Duration::from_millis(250);
/// How long SIGTSTP / Ctrl-Z waits for the zero frame to leave before the process stops anyway.
pub(super) const SUSPEND_WAIT: Duration = Duration::from_millis(100);
/// After a halt, a gap or a block, the keyboard must be this quiet (no drive key) before a press counts as
/// fresh: auto-repeats of a key still held, or a backlog read after a suspension, are not fresh presses.
pub(super) const RELEASE_QUIET: Duration = Duration::from_millis(150);
/// A robot state older than this does not block driving (nor allow it: the sender's checks stay).
const BLOCK_STATUS_AGE: Duration = Duration::from_millis(500);
/// While the robot has not confirmed the command mode asked for, the request is repeated this often...
const MODE_RETRY: Duration = Duration::from_millis(200);
/// ... for this long; then the press is forgotten and a new one asks again.
const MODE_CONFIRM: Duration = Duration::from_secs(2);

/// What happened to the robot at the end.
pub(super) enum Stopped {
    NeverArmed,
    Confirmed,
    NotSent(String),
}

/// Arming, holding and resuming: the dashboard's side of the stop rules. The dashboard opens watching (no
/// sender, nothing sent); arming starts the sender (0x421, then 50 Hz motion); disarming stops it.
pub(super) struct Driving<'a> {
    pub(super) session: &'a Session,
    pub(super) limits: Limits,
    pub(super) sender: Option<MotionSender>,
    /// Where the signal thread finds the running sender's stopper.
    slot: Arc<Mutex<Option<Stopper>>>,
    /// Arming is not possible: --watch, or a replay.
    pub(super) watch_only: Option<&'static str>,
    was_armed: bool,
    /// After a halt, a gap or a blocking state: keys still held must be let go, and pressed again.
    pub(super) needs_release: bool,
    /// Why driving is blocked now (E-stop, latched fault, RC override), from the robot's status.
    blocked: Option<String>,
    /// Whether the robot's fresh status says it is in this link's command mode; `None`: no fresh status.
    in_command_mode: Option<bool>,
    /// A fresh press found the robot out of command mode (after an E-stop or RC override, say): command
    /// mode was asked for at the first instant, last at the second, and nothing drives until it is confirmed.
    mode_requested: Option<(Instant, Instant)>,
    seen_gaps: u64,
    seen_watchdog: u64,
    pub(super) last_requested: (f64, f64),
    /// The outcome of the last disarm (a stop that could not be sent is remembered for the exit message).
    pub(super) last_stop: Option<Stopped>,
}

impl<'a> Driving<'a> {
    pub(super) fn new(
        session: &'a Session,
        limits: Limits,
        slot: Arc<Mutex<Option<Stopper>>>,
        watch_only: Option<&'static str>,
    ) -> Self {
        Driving {
            session,
            limits,
            sender: None,
            slot,
            watch_only,
            was_armed: false,
            needs_release: false,
            blocked: None,
            in_command_mode: None,
            mode_requested: None,
            seen_gaps: 0,
            seen_watchdog: 0,
            last_requested: (0.0, 0.0),
            last_stop: None,
        }
    }

    pub(super) fn armed(&self) -> bool {
        self.sender.is_some()
    }

    pub(super) fn arm(&mut self) -> Result<Message> {
        if let Some(why) = self.watch_only {
            return Ok(Message::WatchOnlyCannotArm(why));
        }
        if self.armed() {
            return Ok(Message::AlreadyArmed);
        }
        let sender = MotionSender::start(
            self.session.tx.clone(),
            Codec::new(self.session.wire()),
            self.limits,
            WATCHDOG,
        )?;
        *self.slot.lock() = Some(sender.stopper());
        let stats = sender.stats();
        self.seen_gaps = stats.gaps;
        self.seen_watchdog = stats.watchdog_trips;
        self.sender = Some(sender);
        self.was_armed = true;
        self.last_requested = (0.0, 0.0);
        // Nothing moves until a key is pressed after arming (the key that asked does not drive).
        self.needs_release = true;
        Ok(Message::Armed)
    }

    /// Stops the sender: zero frames, then nothing more is sent.
    pub(super) fn disarm(&mut self) -> Stopped {
        self.slot.lock().take();
        self.mode_requested = None;
        match self.sender.take() {
            None if self.was_armed => self.last_stop.take().unwrap_or(Stopped::Confirmed),
            None => Stopped::NeverArmed,
            Some(sender) => {
                let error = sender.last_error();
                let stats = sender.stop();
                if stats.stop_confirmed() {
                    Stopped::Confirmed
                } else if stats.stop_frames_queued > 0 {
                    Stopped::NotSent(format!(
                        "{} frames still queued in the adapter, which is not sending",
                        stats.stop_frames_queued
                    ))
                } else {
                    Stopped::NotSent(error.unwrap_or_else(|| "the link took none".to_string()))
                }
            }
        }
    }

    /// Zero at once, and hold it until the keys are let go and pressed again.
    pub(super) fn halt(&mut self) {
        if let Some(sender) = &self.sender {
            sender.halt();
        }
        self.needs_release = true;
        // The press that asked for command mode is void: a new one asks again.
        self.mode_requested = None;
    }

    /// Takes what the robot reports: an E-stop, a latched fault or RC override blocks driving (zero at
    /// once, said on screen) until it clears and a key is pressed again. Returns a message when that changes.
    pub(super) fn observe(&mut self, status: &RobotStatus) -> Option<Message> {
        let fresh = status.fresh_system(BLOCK_STATUS_AGE);
        self.in_command_mode =
            fresh.map(|(state, wire)| state.mode(wire) == Some(ControlMode::command_mode_of(wire)));
        let blocked = fresh.and_then(|(state, wire)| state.why_not_drivable(wire));
        if blocked == self.blocked {
            return None;
        }
        self.mode_requested = None;
        let message = match (&self.blocked, &blocked) {
            (_, Some(reason)) if self.armed() => {
                self.halt();
                Message::BlockedZeroSent(reason.clone())
            }
            (_, Some(reason)) => Message::Blocked(reason.clone()),
            (Some(_), None) => Message::Unblocked,
            (None, None) => return None,
        };
        self.blocked = blocked;
        Some(message)
    }

    /// While command mode is awaited: confirmed, it drives; not yet, the request is repeated; too long,
    /// the press is forgotten. The message to show when that changes.
    pub(super) fn await_command_mode(&mut self) -> Option<Message> {
        let (asked, last) = self.mode_requested?;
        let sender = self.sender.as_ref()?;
        if self.in_command_mode == Some(true) {
            self.mode_requested = None;
            return Some(Message::CommandModeConfirmed);
        }
        if asked.elapsed() >= MODE_CONFIRM {
            self.mode_requested = None;
            self.needs_release = true;
            return Some(Message::CommandModeTimedOut(MODE_CONFIRM));
        }
        if last.elapsed() >= MODE_RETRY {
            sender.request_mode_enable();
            self.mode_requested = Some((asked, Instant::now()));
        }
        None
    }

    /// Checks the sender for a gap in its clock (the process was suspended) or a watchdog trip since the
    /// last look: every key counts as released, and input queued meanwhile is stale. True when one happened.
    pub(super) fn gap_since_last_look(&mut self) -> Option<Message> {
        let stats = self.sender.as_ref()?.stats();
        let gap = stats.gaps > self.seen_gaps;
        let watchdog = stats.watchdog_trips > self.seen_watchdog;
        self.seen_gaps = stats.gaps;
        self.seen_watchdog = stats.watchdog_trips;
        if gap || watchdog {
            self.mode_requested = None;
        }
        if gap {
            self.needs_release = true;
            return Some(Message::Suspended(stats.last_gap.unwrap_or_default()));
        }
        if watchdog {
            self.needs_release = true;
            return Some(Message::InputStalled(WATCHDOG));
        }
        None
    }

    /// The target for this tick. Keys held through a halt, a gap or a block must be let go first: the
    /// keyboard quiet for [`RELEASE_QUIET`] with nothing held. Then a fresh press ends the hold.
    /// A fresh press that finds the robot out of command mode asks for it first (the message says so); the
    /// keys drive once the robot confirms.
    pub(super) fn command(
        &mut self,
        requested: (f64, f64),
        anything_held: bool,
        fresh_press: bool,
        quiet: Duration,
    ) -> Option<Message> {
        let sender = self.sender.as_ref()?;
        if self.needs_release && !anything_held && self.blocked.is_none() && quiet >= RELEASE_QUIET {
            self.needs_release = false;
        }
        let gated = self.needs_release || self.blocked.is_some();
        let mut message = None;
        if fresh_press && !gated {
            if self.in_command_mode == Some(false) && self.mode_requested.is_none() {
                sender.request_mode_enable();
                self.mode_requested = Some((Instant::now(), Instant::now()));
                message = Some(Message::CommandModeAsked);
            }
            if sender.stats().hold.is_some() {
                sender.resume();
            }
        }
        let requested = if gated || self.mode_requested.is_some() { (0.0, 0.0) } else { requested };
        // A change (a press, a release, a deadline that expired) leaves at once rather than at the next tick.
        if requested != self.last_requested {
            sender.set_target_now(requested.0, requested.1);
        } else {
            sender.set_target(requested.0, requested.1);
        }
        self.last_requested = requested;
        message
    }

    /// What the header says: armed, watching, or watch-only.
    pub(super) fn arming(&self) -> Arming {
        match (self.armed(), self.watch_only.is_some()) {
            (true, _) => Arming::Armed,
            (false, true) => Arming::WatchOnly,
            (false, false) => Arming::Watching,
        }
    }

    pub(super) fn blocked_now(&self) -> bool {
        self.blocked.is_some()
    }

    #[cfg(unix)]
    pub(super) fn suspend(&self) {
        if let Some(stopper) = self.slot.lock().as_ref() {
            stopper.suspend(SUSPEND_WAIT);
        }
    }
}
