//! The dashboard's event loop: each tick takes signals, the terminal, gaps in the sender's clock and the
//! input, commands the sender from the keys held, folds the robot's status into the view and redraws it.

use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use anyhow::Result;
use ratatui::crossterm::event::{Event, KeyEvent};

use super::actions::{handle, release_view};
use super::driving::{Driving, RELEASE_QUIET};
use super::health_feed::LatestHealth;
use crate::control::{MotionSender, GAP_LIMIT};
use crate::dashboard::app::{App, Snapshot, TeleopView};
use crate::dashboard::keys::{self, Context, Effect};
use crate::dashboard::render::render;
use crate::dashboard::teleop::{Key, KeyAction, Teleop};
use crate::dashboard::terminal::{Input, Screen};
use crate::link::LinkKind;
use crate::signals::{Caught, SignalFlag};

/// The loop's period: targets are refreshed this often (the sender's watchdog is ten times longer).
const LOOP: Duration = Duration::from_millis(20);
/// At most 20 redraws a second (slow SSH links).
const MIN_REDRAW: Duration = Duration::from_millis(50);
const UPDATE_EVERY: Duration = Duration::from_millis(50);
/// After a gap in the sender's clock, no drive key counts as a fresh press for this long: the keys the
/// terminal queued while the process was stopped arrive in this time, and are stale.
const GAP_SETTLE: Duration = Duration::from_millis(300);

/// Why the dashboard ended.
pub(super) enum End {
    Quit,
    Signal(Caught),
    TerminalLost(String),
    LinkLost(String),
}

/// The event loop's state: what is shown, the driving side, the keys held, and the clocks that tell a
/// fresh press from a key still held or a backlog.
pub(super) struct Loop<'a> {
    app: App,
    pub(super) driving: Driving<'a>,
    teleop: Teleop,
    lights_step: usize,
    epoch: Instant,
    last_update: Instant,
    last_draw: Instant,
    drawn: Option<u64>,
    next_tick: Instant,
    last_loop: Instant,
    /// After a gap, drive keys are not fresh until the terminal's backlog has surely been read.
    settle_until: Instant,
    /// The last drive key; the keyboard's quiet counts from it.
    last_drive_key: Instant,
    /// A fresh press of a drive key in this tick's input.
    fresh_press: bool,
    /// The drive key that closed a dialog, and its last byte: it does not drive until let go (its auto-repeats
    /// look like presses on a terminal without releases).
    swallowed: Option<(Key, Instant)>,
    /// What the key that asked "Arm driving?" was for (a fault clear, the lights): done once armed.
    after_arm: Option<Effect>,
    /// The live analysis' latest view, made on the session's analysis thread (`health_feed.rs`).
    health: LatestHealth,
}

impl<'a> Loop<'a> {
    pub(super) fn new(app: App, driving: Driving<'a>, teleop: Teleop, health: LatestHealth) -> Self {
        Loop {
            health,
            app,
            driving,
            teleop,
            lights_step: 0,
            epoch: Instant::now(),
            last_update: Instant::now() - UPDATE_EVERY,
            last_draw: Instant::now() - MIN_REDRAW,
            drawn: None,
            next_tick: Instant::now(),
            last_loop: Instant::now(),
            settle_until: Instant::now(),
            // No drive key yet: the keyboard has been quiet "forever".
            last_drive_key: Instant::now().checked_sub(RELEASE_QUIET).unwrap_or_else(Instant::now),
            fresh_press: false,
            swallowed: None,
            after_arm: None,
        }
    }

    /// One turn: signals, the terminal, gaps, input, the command, the view. `Some` ends the dashboard.
    pub(super) fn tick(
        &mut self,
        screen: &mut Screen,
        input: &Receiver<Input>,
        signal: &SignalFlag,
    ) -> Result<Option<End>> {
        if let Some(caught) = signal.caught() {
            return Ok(Some(End::Signal(caught)));
        }
        // After SIGTSTP or Ctrl-Z the terminal was given back: take it again (a cheap check of a flag).
        if screen.take_back()? {
            self.drawn = None;
        }
        if self.last_loop.elapsed() > GAP_LIMIT {
            // Let the sender take its tick first: it alone tells a suspension from a slow redraw, and the
            // input that piled up meanwhile must not be read as fresh presses before it has.
            if self.driving.armed() {
                std::thread::sleep(LOOP * 2);
            }
        }
        self.last_loop = Instant::now();
        // The sender's own clock jumped (the process was stopped, or the machine stalled; a slow redraw of
        // this loop alone does not count): what the terminal queued meanwhile is stale, every key counts as
        // released, and the quiet that makes a press fresh counts from here.
        self.on_gap(input);
        if let Some(end) = self.read_input(input) {
            return Ok(Some(end));
        }
        // Look again before commanding: keys read just now may be a backlog from before a gap that the sender
        // has recorded meanwhile; they must not end its hold. (If the sender records the gap only after
        // this look, its gap overrides the resume asked for below: it checks for gaps after resumes.)
        self.on_gap(input);
        let now = Instant::now();
        self.command();
        if now.duration_since(self.last_update) >= UPDATE_EVERY {
            if let Some(end) = self.refresh(now) {
                return Ok(Some(end));
            }
        }
        if let Some(end) = self.draw(screen, now) {
            return Ok(Some(end));
        }
        self.next_tick += LOOP;
        if self.next_tick < Instant::now() {
            self.next_tick = Instant::now() + LOOP;
        }
        Ok(None)
    }

    /// After a gap in the sender's clock or a watchdog trip: drop the queued input, release every key, and
    /// let no drive key count as fresh until the backlog has been read.
    fn on_gap(&mut self, input: &Receiver<Input>) {
        if let Some(message) = self.driving.gap_since_last_look() {
            while input.try_recv().is_ok() {}
            self.teleop.release_all();
            self.last_drive_key = Instant::now();
            self.settle_until = Instant::now() + GAP_SETTLE;
            self.fresh_press = false;
            self.app.set_message(message, Instant::now());
        }
    }

    /// Waits for input until the next tick, so a key acts at once, then takes everything queued.
    fn read_input(&mut self, input: &Receiver<Input>) -> Option<End> {
        self.fresh_press = false;
        // Wake up for a key's deadline too: a release is commanded when it expires, not up to a tick later.
        let now = self.epoch.elapsed();
        let expiry = self.teleop.next_expiry(now).map(|at| Instant::now() + (at - now));
        let wake = expiry.map_or(self.next_tick, |at| at.min(self.next_tick));
        let wait = wake.saturating_duration_since(Instant::now());
        let mut first = match input.recv_timeout(wait) {
            Ok(input) => Some(input),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => {
                return Some(End::TerminalLost("input closed".to_string()))
            }
        };
        while let Some(item) = first.take().or_else(|| input.try_recv().ok()) {
            if let Some(end) = self.on_input(item) {
                return Some(end);
            }
        }
        None
    }

    fn on_input(&mut self, item: Input) -> Option<End> {
        match item {
            Input::Closed(why) => return Some(End::TerminalLost(why)),
            Input::Event(Event::Resize(..)) => self.drawn = None,
            Input::Event(Event::FocusLost) => self.teleop.release_all(),
            Input::Event(Event::Key(key)) => return self.on_key(&key),
            Input::Event(_) => {}
        }
        None
    }

    /// A key, through the key table's dispatcher.
    fn on_key(&mut self, key: &KeyEvent) -> Option<End> {
        let now = self.epoch.elapsed();
        let context =
            Context { prompt: self.app.prompt(), help: self.app.help_shown(), armed: self.driving.armed() };
        let effect = keys::dispatch(key, context);
        if let (Effect::Close, Some((_, bind))) = (effect, keys::lookup(key)) {
            if let keys::Action::Drive(closing) = bind.action {
                self.swallowed = Some((closing, Instant::now()));
            }
        }
        match effect {
            Effect::Quit => return Some(End::Quit),
            Effect::Suspend => self.on_suspend(),
            Effect::Drive(key, action) => self.on_arrow(now, key, action),
            effect => {
                self.remember_after_arm(key, effect);
                handle(&mut self.app, &mut self.driving, &mut self.teleop, effect, &mut self.lights_step);
                if effect == Effect::Arm && self.driving.armed() {
                    // Armed at the request of a clear or the lights key: go on to what it asked for (the
                    // clear still asks first). A drive key never drives this way: it must be pressed again.
                    if let Some(then) = self.after_arm.take() {
                        handle(
                            &mut self.app,
                            &mut self.driving,
                            &mut self.teleop,
                            then,
                            &mut self.lights_step,
                        );
                    }
                }
            }
        }
        None
    }

    /// Keeps what a key that asks to arm was for, until the prompt is answered or closed.
    fn remember_after_arm(&mut self, key: &KeyEvent, effect: Effect) {
        match effect {
            Effect::AskArm => {
                self.after_arm = match keys::lookup(key).map(|(_, bind)| bind.action) {
                    Some(keys::Action::ClearFaults) => Some(Effect::AskClear),
                    Some(keys::Action::Lights) => Some(Effect::Lights),
                    _ => None,
                }
            }
            // A key's release or repeat (kitty protocol) does nothing, and keeps what was asked.
            Effect::Arm | Effect::None => {}
            _ => self.after_arm = None,
        }
    }

    /// An arrow while armed with nothing on top: the teleop takes it. A press after a quiet keyboard, and
    /// not while a gap's backlog settles, is fresh: it may end a hold.
    fn on_arrow(&mut self, now: Duration, key: Key, action: KeyAction) {
        if let Some((closing, last)) = self.swallowed {
            // Bytes of the key that closed a dialog, each within a first deadline of the one before: still held.
            if closing == key && action != KeyAction::Release && last.elapsed() <= self.teleop.deadlines().0 {
                self.swallowed = Some((closing, Instant::now()));
                return;
            }
            self.swallowed = None;
        }
        let was_held = !self.teleop.held(now).is_empty();
        // A press right after a quiet keyboard is fresh; check the quiet before this key.
        let quiet = self.last_drive_key.elapsed();
        self.last_drive_key = Instant::now();
        self.teleop.key(now, key, action);
        let fresh = action == KeyAction::Press
            && !was_held
            && quiet >= RELEASE_QUIET
            && Instant::now() >= self.settle_until;
        if self.driving.needs_release && fresh && !self.driving.blocked_now() {
            self.driving.needs_release = false;
        }
        self.fresh_press |= fresh;
    }

    /// Ctrl-Z in raw mode is a key: do what the shell's Ctrl-Z would, safely (zero first).
    #[cfg(unix)]
    fn on_suspend(&self) {
        self.driving.suspend();
        crate::dashboard::terminal::restore();
        let _ = signal_hook::low_level::raise(signal_hook::consts::SIGSTOP);
    }

    /// Windows consoles have no job control: Ctrl-Z is not a key the dashboard acts on.
    #[cfg(not(unix))]
    fn on_suspend(&self) {}

    /// This tick's target from the keys held, through the driving side's holds and blocks.
    pub(super) fn command(&mut self) {
        let limits = self.driving.limits;
        let request = self.teleop.request(self.epoch.elapsed());
        let requested = (request.0 * limits.max_linear, request.1 * limits.max_angular);
        let anything_held = !self.teleop.held(self.epoch.elapsed()).is_empty();
        let quiet = self.last_drive_key.elapsed();
        if let Some(message) = self.driving.command(requested, anything_held, self.fresh_press, quiet) {
            self.app.set_message(message, Instant::now());
        }
    }

    /// Takes the robot's status and the sender's stats into the view; a lost live link ends the dashboard.
    fn refresh(&mut self, now: Instant) -> Option<End> {
        let session = self.driving.session;
        let status = session.status();
        if let Some(error) = status.link_error.clone() {
            if session.kind != LinkKind::Replay {
                return Some(End::LinkLost(error));
            }
        }
        if let Some(message) = self.driving.observe(&status) {
            self.teleop.release_all();
            self.app.set_message(message, Instant::now());
        }
        // Not a block: the key held since the fresh press drives on once the robot confirms.
        if let Some(message) = self.driving.await_command_mode() {
            self.app.set_message(message, Instant::now());
        }
        let stats = self.driving.sender.as_ref().map(MotionSender::stats).unwrap_or_default();
        self.app.update(&Snapshot { status: &status, sender: stats, link_name: &session.name, now });
        self.app.set_recording_loss(session.recording_losses());
        if let Some(view) = self.health.lock().take() {
            self.app.set_health(view);
        }
        self.app.set_arming(self.driving.arming());
        let held = self.teleop.held(self.epoch.elapsed());
        let requested = if self.driving.armed() { self.driving.last_requested } else { (0.0, 0.0) };
        self.app.set_teleop(TeleopView {
            release_mode: release_view(&self.teleop, self.driving.watch_only),
            scale: self.teleop.scale(),
            held,
            requested,
        });
        self.last_update = now;
        None
    }

    /// Redraws when something changed, at most every [`MIN_REDRAW`]; a terminal that fails ends it.
    fn draw(&mut self, screen: &mut Screen, now: Instant) -> Option<End> {
        let fingerprint = self.app.fingerprint();
        if self.drawn != Some(fingerprint) && now.duration_since(self.last_draw) >= MIN_REDRAW {
            if let Err(error) = screen.terminal.draw(|frame| render(frame, &self.app)) {
                return Some(End::TerminalLost(error.to_string()));
            }
            self.drawn = Some(fingerprint);
            self.last_draw = now;
        }
        None
    }
}
