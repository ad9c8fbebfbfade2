//! `tracerctl dashboard`: the terminal loop tying the session, the teleop state machine, the motion sender
//! and the renderer together. Everything it draws comes from the pure `dashboard::{app, render}`; every key
//! goes through the pure `dashboard::keys` (the key table and its dispatcher) and `dashboard::teleop`.

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;
use ratatui::crossterm::event::{Event, KeyEvent};

use super::Global;
use crate::control::{Limits, MotionSender, Stopper, GAP_LIMIT};
use crate::dashboard::app::{App, Arming, ReleaseView, Snapshot, TeleopView};
use crate::dashboard::keys::{self, Context, Effect};
use crate::dashboard::lights::LIGHT_CYCLE;
use crate::dashboard::message::Message;
use crate::dashboard::render::render;
use crate::dashboard::teleop::{Key, KeyAction, ReleaseMode, Teleop};
use crate::dashboard::terminal::{spawn_input, Input, Screen};
use crate::exit::{Failure, DATA_ERROR, FAILURE, SUCCESS, USAGE};
use crate::link::LinkKind;
use crate::protocol::message::COMMAND_TIMEOUT;
use crate::protocol::{ClearTarget, Codec, ControlMode};
use crate::session::{RobotStatus, Session};
use crate::signals::{self, SignalFlag};

/// The loop's period: targets are refreshed this often (the sender's watchdog is ten times longer).
const LOOP: Duration = Duration::from_millis(20);
/// Input or drawing that stalls longer than this makes the sender command zero.
const WATCHDOG: Duration = Duration::from_millis(250);
/// At most 20 redraws a second (slow SSH links).
const MIN_REDRAW: Duration = Duration::from_millis(50);
const UPDATE_EVERY: Duration = Duration::from_millis(50);
/// How long SIGTSTP / Ctrl-Z waits for the zero frame to leave before the process stops anyway.
const SUSPEND_WAIT: Duration = Duration::from_millis(100);
/// After a halt, a gap or a block, the keyboard must be this quiet (no drive key) before a press counts as
/// fresh: auto-repeats of a key still held, or a backlog read after a suspension, are not fresh presses.
const RELEASE_QUIET: Duration = Duration::from_millis(150);
/// After a gap in the sender's clock, no drive key counts as a fresh press for this long: the keys the
/// terminal queued while the process was stopped arrive in this time, and are stale.
const GAP_SETTLE: Duration = Duration::from_millis(300);
/// A robot state older than this does not block driving (nor allow it: the sender's checks stay).
const BLOCK_STATUS_AGE: Duration = Duration::from_millis(500);
/// While the robot has not confirmed the command mode asked for, the request is repeated this often...
const MODE_RETRY: Duration = Duration::from_millis(200);
/// ... for this long; then the press is forgotten and a new one asks again.
const MODE_CONFIRM: Duration = Duration::from_secs(2);

/// Why the dashboard ended.
enum End {
    Quit,
    Signal(u8, &'static str),
    TerminalLost(String),
    LinkLost(String),
}

/// `tracerctl dashboard`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    pub limits: Limits,
    /// Never arm driving, never send anything.
    pub watch: bool,
    /// Write a candump log of the session to this file.
    pub record: Option<std::path::PathBuf>,
    /// Without key-release events: a repeating key counts as released after this, instead of the learned
    /// deadline.
    pub key_timeout: Option<Duration>,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    if !std::io::stdin().is_terminal() || !std::io::stdout().is_terminal() {
        return Err(Failure {
            code: USAGE,
            message: "the dashboard needs a terminal on standard input and output; for pipes and logs use \
                      `tracerctl monitor`"
                .to_string(),
        }
        .into());
    }
    let session =
        Session::open_recording(&global.link, global.protocol, global.sim_config(), args.record.as_deref())?;
    let color = global.color.enabled(true);

    let (end, stopped) = {
        let screen = Screen::enter()?;
        let result = drive_loop(screen, &session, args, color);
        // `screen` was dropped inside: the terminal is back before anything is printed.
        result?
    };
    let robot = match &stopped {
        Stopped::NeverArmed => "nothing was sent (never armed)".to_string(),
        Stopped::Confirmed => "the robot was stopped".to_string(),
        Stopped::NotSent(why) => format!(
            "the stop frames could not be sent ({why}): the robot's own {} ms command timeout stops it",
            COMMAND_TIMEOUT.as_millis()
        ),
    };
    let (status, message) = match end {
        End::Quit => (SUCCESS, format!("quit: {robot}")),
        End::Signal(status, name) => (status, format!("{name}: {robot}")),
        End::TerminalLost(why) => (FAILURE, format!("the terminal went away ({why}): {robot}")),
        End::LinkLost(why) => (FAILURE, format!("the link {} failed ({why}): {robot}", session.name)),
    };
    let mut status = match stopped {
        Stopped::NotSent(_) if status == SUCCESS => FAILURE,
        _ => status,
    };
    let _ = writeln!(std::io::stderr(), "tracerctl: {message}");
    // The robot is stopped: now the recording is written out, and what the screen could not list is said.
    let (name, replay) = (session.name.clone(), session.kind == LinkKind::Replay);
    let finished = session.finish();
    for note in &finished.notes {
        crate::say!("tracerctl: {note}");
    }
    if let Some(report) = &finished.report {
        crate::say!("tracerctl: {report}");
    }
    if let Some(loss) = &finished.recording {
        crate::say!("tracerctl: {loss}");
        if status == SUCCESS {
            status = FAILURE;
        }
    }
    if let Some(nothing) =
        replay.then(|| crate::link::replay::nothing_replayed(&name, &finished.rx)).flatten()
    {
        crate::say!("tracerctl: {nothing}");
        status = DATA_ERROR;
    }
    Ok(status)
}

/// What happened to the robot at the end.
enum Stopped {
    NeverArmed,
    Confirmed,
    NotSent(String),
}

/// Arming, holding and resuming: the dashboard's side of the stop rules. The dashboard opens watching (no
/// sender, nothing sent); arming starts the sender (0x421, then 50 Hz motion); disarming stops it.
struct Driving<'a> {
    session: &'a Session,
    limits: Limits,
    sender: Option<MotionSender>,
    /// Where the signal thread finds the running sender's stopper.
    slot: Arc<Mutex<Option<Stopper>>>,
    /// Arming is not possible: --watch, or a replay.
    watch_only: Option<&'static str>,
    was_armed: bool,
    /// After a halt, a gap or a blocking state: keys still held must be let go, and pressed again.
    needs_release: bool,
    /// Why driving is blocked now (E-stop, latched fault, RC override), from the robot's status.
    blocked: Option<String>,
    /// Whether the robot's fresh status says it is in this link's command mode; `None`: no fresh status.
    in_command_mode: Option<bool>,
    /// A fresh press found the robot out of command mode (after an E-stop or RC override, say): command
    /// mode was asked for at the first instant, last at the second, and nothing drives until it is confirmed.
    mode_requested: Option<(Instant, Instant)>,
    seen_gaps: u64,
    seen_watchdog: u64,
    last_requested: (f64, f64),
    /// The outcome of the last disarm (a stop that could not be sent is remembered for the exit message).
    last_stop: Option<Stopped>,
}

impl<'a> Driving<'a> {
    fn new(
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

    fn armed(&self) -> bool {
        self.sender.is_some()
    }

    fn arm(&mut self) -> Result<Message> {
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
    fn disarm(&mut self) -> Stopped {
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
    fn halt(&mut self) {
        if let Some(sender) = &self.sender {
            sender.halt();
        }
        self.needs_release = true;
        // The press that asked for command mode is void: a new one asks again.
        self.mode_requested = None;
    }

    /// Takes what the robot reports: an E-stop, a latched fault or RC override blocks driving (zero at
    /// once, said on screen) until it clears and a key is pressed again. Returns a message when that changes.
    fn observe(&mut self, status: &RobotStatus) -> Option<Message> {
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
    fn await_command_mode(&mut self) -> Option<Message> {
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
    fn gap_since_last_look(&mut self) -> Option<Message> {
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
    fn command(
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
    fn arming(&self) -> Arming {
        match (self.armed(), self.watch_only.is_some()) {
            (true, _) => Arming::Armed,
            (false, true) => Arming::WatchOnly,
            (false, false) => Arming::Watching,
        }
    }

    fn blocked_now(&self) -> bool {
        self.blocked.is_some()
    }

    #[cfg(unix)]
    fn suspend(&self) {
        if let Some(stopper) = self.slot.lock().as_ref() {
            stopper.suspend(SUSPEND_WAIT);
        }
    }
}

fn drive_loop(mut screen: Screen, session: &Session, args: &Options, color: bool) -> Result<(End, Stopped)> {
    let limits = args.limits;
    let watch_only = match (session.kind == LinkKind::Replay, args.watch) {
        (true, _) => Some("--replay is read-only"),
        (false, true) => Some("--watch"),
        (false, false) => None,
    };
    let mode = if screen.key_release { ReleaseMode::Events } else { ReleaseMode::Deadline };
    let teleop = Teleop::new(mode).with_key_timeout(args.key_timeout);
    let slot: Arc<Mutex<Option<Stopper>>> = Arc::default();
    let signal = listen_for_signals(&slot)?;
    let driving = Driving::new(session, limits, slot, watch_only);
    let done = Arc::new(AtomicBool::new(false));
    let input = spawn_input(Arc::clone(&done))?;
    let mut app = App::new(&session.name, limits, color);
    app.set_arming(driving.arming());
    let mut state = Loop::new(app, driving, teleop);
    let end = loop {
        if let Some(end) = state.tick(&mut screen, &input, &signal)? {
            break end;
        }
    };
    // Stop the robot first, then give the terminal back (Screen's drop), then stop the input thread.
    let stopped = state.driving.disarm();
    drop(screen);
    done.store(true, Ordering::SeqCst);
    Ok((end, stopped))
}

/// SIGINT, SIGTERM, SIGHUP stop the running sender at once; SIGTSTP sends zero first, then gives the
/// terminal back while stopped (the loop takes it again after SIGCONT).
fn listen_for_signals(slot: &Arc<Mutex<Option<Stopper>>>) -> Result<SignalFlag> {
    let (on_signal, on_suspend) = (Arc::clone(slot), Arc::clone(slot));
    signals::listen_suspendable(
        move |_| {
            if let Some(stopper) = on_signal.lock().as_ref() {
                stopper.stop_now();
            }
        },
        move || {
            if let Some(stopper) = on_suspend.lock().as_ref() {
                stopper.suspend(SUSPEND_WAIT);
            }
            // Give the terminal back while stopped; the loop takes it again after SIGCONT.
            crate::dashboard::terminal::restore();
        },
    )
}

/// The event loop's state: what is shown, the driving side, the keys held, and the clocks that tell a
/// fresh press from a key still held or a backlog.
struct Loop<'a> {
    app: App,
    driving: Driving<'a>,
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
}

impl<'a> Loop<'a> {
    fn new(app: App, driving: Driving<'a>, teleop: Teleop) -> Self {
        Loop {
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
    fn tick(
        &mut self,
        screen: &mut Screen,
        input: &Receiver<Input>,
        signal: &SignalFlag,
    ) -> Result<Option<End>> {
        if let (Some(status), name) = (signal.exit_status(), signal.name()) {
            return Ok(Some(End::Signal(status, name)));
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
    fn command(&mut self) {
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

/// Acts on a key that does not drive.
fn handle(
    app: &mut App,
    driving: &mut Driving,
    teleop: &mut Teleop,
    action: Effect,
    lights_step: &mut usize,
) {
    let now = Instant::now();
    match action {
        Effect::Quit | Effect::Suspend | Effect::None | Effect::Drive(..) => {}
        Effect::Stop => on_stop(app, driving, teleop, now),
        Effect::Faster => {
            teleop.faster();
        }
        Effect::Slower => {
            teleop.slower();
        }
        Effect::Help => {
            // Keys act on the help while it is open: none stays held under it.
            teleop.release_all();
            app.toggle_help();
        }
        Effect::Close => {
            app.cancel_prompt();
            app.hide_help();
        }
        Effect::AskArm => match driving.watch_only {
            Some(why) => app.set_message(Message::WatchOnly(why), now),
            None => app.ask_arm_confirmation(),
        },
        Effect::Arm => on_arm(app, driving, teleop, now),
        Effect::Disarm => on_disarm(app, driving, teleop, now),
        Effect::AskClear => {
            // The dialog owns the keyboard: nothing drives while it is open.
            teleop.release_all();
            app.ask_clear_confirmation();
        }
        Effect::Clear => {
            app.cancel_prompt();
            let frames = driving.session.codec().clear_faults(ClearTarget::All);
            let sent = frames.iter().map(|frame| driving.session.send(frame)).collect::<Result<Vec<_>>>();
            let message = match sent {
                Ok(_) => Message::ClearSent(driving.session.wire()),
                Err(error) => Message::ClearFailed(format!("{error:#}")),
            };
            app.set_message(message, now);
        }
        Effect::CommandMode => {
            if let Some(sender) = &driving.sender {
                sender.request_mode_enable();
                app.set_message(Message::CommandModeRequested, now);
            }
        }
        Effect::Lights => on_lights(app, driving, lights_step, now),
    }
}

/// Space: zero at once, held until a key is pressed again.
fn on_stop(app: &mut App, driving: &mut Driving, teleop: &mut Teleop, now: Instant) {
    teleop.release_all();
    driving.halt();
    if driving.armed() {
        app.set_message(Message::Stopped, now);
    }
}

/// y to "Arm driving?": the sender starts; the key that asked does not drive.
fn on_arm(app: &mut App, driving: &mut Driving, teleop: &mut Teleop, now: Instant) {
    app.cancel_prompt();
    teleop.release_all();
    let message = driving.arm().unwrap_or_else(|error| Message::ArmFailed(format!("{error:#}")));
    app.set_message(message, now);
}

/// a while armed: zero, then nothing is sent; a stop that could not be sent is kept for the exit message.
fn on_disarm(app: &mut App, driving: &mut Driving, teleop: &mut Teleop, now: Instant) {
    teleop.release_all();
    let message = match driving.disarm() {
        Stopped::NotSent(why) => {
            driving.last_stop = Some(Stopped::NotSent(why.clone()));
            Message::DisarmedStopNotSent(why)
        }
        _ => Message::Disarmed,
    };
    app.set_message(message, now);
}

/// l: the next light setting of [`LIGHT_CYCLE`].
fn on_lights(app: &mut App, driving: &Driving, lights_step: &mut usize, now: Instant) {
    let (lights, name) = LIGHT_CYCLE[*lights_step % LIGHT_CYCLE.len()];
    *lights_step += 1;
    let frame = driving.session.codec().lights(lights);
    let message = match driving.session.send(&frame) {
        Ok(()) => Message::Lights(name),
        Err(error) => Message::LightsFailed(format!("{error:#}")),
    };
    app.set_message(message, now);
}

/// How the keys are read now, for the footer: what the teleop has learned, in milliseconds.
fn release_view(teleop: &Teleop, watch_only: Option<&'static str>) -> ReleaseView {
    if let Some(why) = watch_only {
        return ReleaseView::DrivingOff(why);
    }
    match teleop.mode() {
        ReleaseMode::Events => ReleaseView::Events,
        ReleaseMode::Deadline => {
            let learned = |value: Duration| (!value.is_zero()).then_some(value.as_millis());
            let (delay, interval) = teleop.learned();
            ReleaseView::Deadline {
                delay_ms: learned(delay),
                interval_ms: learned(interval),
                timeout_ms: teleop.deadlines().1.as_millis(),
                from_flag: teleop.key_timeout().is_some(),
            }
        }
    }
}
