//! `tracerctl dashboard`: the terminal loop tying the session, the teleop state machine, the motion sender
//! and the renderer together. Everything it draws comes from the pure `dashboard::{app, render}`; every key
//! goes through the pure `dashboard::teleop`.

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::cli::{Cli, DashboardArgs};
use crate::control::{Limits, MotionSender, Stopper, GAP_LIMIT};
use crate::dashboard::app::{App, Arming, Prompt, Snapshot, TeleopView};
use crate::dashboard::render::render;
use crate::dashboard::teleop::{Key, KeyAction, ReleaseMode, Teleop};
use crate::dashboard::terminal::{spawn_input, Input, Screen};
use crate::exit::{Failure, DATA_ERROR, FAILURE, SUCCESS, USAGE};
use crate::link::{ClearTarget, Codec, LinkChoice, LinkKind};
use crate::protocol::message::{Lights, COMMAND_TIMEOUT, LIGHT_BREATH, LIGHT_CUSTOM, LIGHT_OFF, LIGHT_ON};
use crate::protocol::Wire;
use crate::session::{RobotStatus, Session};
use crate::signals;

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

/// Why the dashboard ended.
enum End {
    Quit,
    Signal(u8, &'static str),
    TerminalLost(String),
    LinkLost(String),
}

pub fn run(cli: &Cli, args: &DashboardArgs) -> Result<u8> {
    if !std::io::stdin().is_terminal() || !std::io::stdout().is_terminal() {
        return Err(Failure {
            code: USAGE,
            message: "the dashboard needs a terminal on standard input and output; for pipes and logs use \
                      `tracerctl monitor`"
                .to_string(),
        }
        .into());
    }
    let limits = args.limits.limits()?;
    let choice = LinkChoice::from_args(&cli.link)?;
    let session = Session::open_recording(&choice, cli.protocol.into(), None, args.record.as_deref())?;
    let color = cli.color.enabled(true);

    let (end, stopped) = {
        let screen = Screen::enter()?;
        let result = drive_loop(screen, &session, limits, color, args.watch);
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
    seen_gaps: u64,
    seen_watchdog: u64,
    last_requested: (f64, f64),
    /// The outcome of the last disarm (a stop that could not be sent is remembered for the exit message).
    last_stop: Option<Stopped>,
}

impl<'a> Driving<'a> {
    fn armed(&self) -> bool {
        self.sender.is_some()
    }

    fn arm(&mut self) -> Result<String> {
        if let Some(why) = self.watch_only {
            return Ok(format!("watch-only ({why}): driving cannot be armed"));
        }
        if self.armed() {
            return Ok("already armed".to_string());
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
        Ok("ARMED: command mode requested; press an arrow key to drive, a to disarm".to_string())
    }

    /// Stops the sender: zero frames, then nothing more is sent.
    fn disarm(&mut self) -> Stopped {
        self.slot.lock().take();
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
    }

    /// Takes what the robot reports: an E-stop, a latched fault or RC override blocks driving (zero at
    /// once, said on screen) until it clears and a key is pressed again. Returns a message when that changes.
    fn observe(&mut self, status: &RobotStatus) -> Option<String> {
        let blocked =
            status.fresh_system(BLOCK_STATUS_AGE).and_then(|(state, wire)| state.why_not_drivable(wire));
        if blocked == self.blocked {
            return None;
        }
        let message = match (&self.blocked, &blocked) {
            (_, Some(reason)) if self.armed() => {
                self.halt();
                format!("zero sent: {reason}; press a key again once it is clear")
            }
            (_, Some(reason)) => format!("driving blocked: {reason}"),
            (Some(_), None) => "clear again: press a key to drive".to_string(),
            (None, None) => return None,
        };
        self.blocked = blocked;
        Some(message)
    }

    /// Checks the sender for a gap in its clock (the process was suspended) or a watchdog trip since the
    /// last look: every key counts as released, and input queued meanwhile is stale. True when one happened.
    fn gap_since_last_look(&mut self) -> Option<String> {
        let stats = self.sender.as_ref()?.stats();
        let gap = stats.gaps > self.seen_gaps;
        let watchdog = stats.watchdog_trips > self.seen_watchdog;
        self.seen_gaps = stats.gaps;
        self.seen_watchdog = stats.watchdog_trips;
        if gap {
            self.needs_release = true;
            let seconds = stats.last_gap.unwrap_or_default().as_secs_f64();
            return Some(format!(
                "suspended for {seconds:.2} s: zero sent, keys released; press again to drive"
            ));
        }
        if watchdog {
            self.needs_release = true;
            return Some(format!(
                "input stalled over {} ms: zero sent, keys released; press again to drive",
                WATCHDOG.as_millis()
            ));
        }
        None
    }

    /// The target for this tick. Keys held through a halt, a gap or a block must be let go first: the
    /// keyboard quiet for [`RELEASE_QUIET`] with nothing held. Then a fresh press ends the hold.
    fn command(&mut self, requested: (f64, f64), anything_held: bool, fresh_press: bool, quiet: Duration) {
        let Some(sender) = &self.sender else { return };
        if self.needs_release && !anything_held && self.blocked.is_none() && quiet >= RELEASE_QUIET {
            self.needs_release = false;
        }
        let gated = self.needs_release || self.blocked.is_some();
        if fresh_press && !gated && sender.stats().hold.is_some() {
            sender.resume();
        }
        let requested = if gated { (0.0, 0.0) } else { requested };
        // A change (a press, a release, a deadline that expired) leaves at once rather than at the next tick.
        if requested != self.last_requested {
            sender.set_target_now(requested.0, requested.1);
        } else {
            sender.set_target(requested.0, requested.1);
        }
        self.last_requested = requested;
    }

    fn blocked_now(&self) -> bool {
        self.blocked.is_some()
    }

    fn suspend(&self) {
        if let Some(stopper) = self.slot.lock().as_ref() {
            stopper.suspend(SUSPEND_WAIT);
        }
    }
}

fn drive_loop(
    mut screen: Screen,
    session: &Session,
    limits: Limits,
    color: bool,
    watch: bool,
) -> Result<(End, Stopped)> {
    let watch_only = match (session.kind == LinkKind::Replay, watch) {
        (true, _) => Some("--replay is read-only"),
        (false, true) => Some("--watch"),
        (false, false) => None,
    };
    let mode = if screen.key_release { ReleaseMode::Events } else { ReleaseMode::Deadline };
    let mut teleop = Teleop::new(mode);
    let slot: Arc<Mutex<Option<Stopper>>> = Arc::default();
    let signal = {
        let (on_signal, on_suspend) = (Arc::clone(&slot), Arc::clone(&slot));
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
        )?
    };
    let mut driving = Driving {
        session,
        limits,
        sender: None,
        slot,
        watch_only,
        was_armed: false,
        needs_release: false,
        blocked: None,
        seen_gaps: 0,
        seen_watchdog: 0,
        last_requested: (0.0, 0.0),
        last_stop: None,
    };
    let done = Arc::new(AtomicBool::new(false));
    let input = spawn_input(Arc::clone(&done))?;

    let mut app = App::new(&session.name, limits, color);
    app.set_arming(if watch_only.is_some() { Arming::WatchOnly } else { Arming::Watching });
    let epoch = Instant::now();
    let mut lights_step = 0usize;
    let mut last_update = Instant::now() - UPDATE_EVERY;
    let mut last_draw = Instant::now() - MIN_REDRAW;
    let mut drawn: Option<u64> = None;
    let mut next_tick = Instant::now();
    let mut last_loop = Instant::now();
    // After a gap, drive keys are not fresh until the terminal's backlog has surely been read.
    let mut settle_until = Instant::now();
    // No drive key yet: the keyboard has been quiet "forever".
    let mut last_drive_key = Instant::now().checked_sub(RELEASE_QUIET).unwrap_or_else(Instant::now);
    let end = 'run: loop {
        if let (Some(status), name) = (signal.exit_status(), signal.name()) {
            break End::Signal(status, name);
        }
        // After SIGTSTP or Ctrl-Z the terminal was given back: take it again (a cheap check of a flag).
        if screen.take_back()? {
            drawn = None;
        }
        if last_loop.elapsed() > GAP_LIMIT {
            // Let the sender take its tick first: it alone tells a suspension from a slow redraw, and the
            // input that piled up meanwhile must not be read as fresh presses before it has.
            if driving.armed() {
                std::thread::sleep(LOOP * 2);
            }
        }
        last_loop = Instant::now();
        // The sender's own clock jumped (the process was stopped, or the machine stalled; a slow redraw of
        // this loop alone does not count): what the terminal queued meanwhile is stale, every key counts as
        // released, and the quiet that makes a press fresh counts from here.
        if let Some(text) = driving.gap_since_last_look() {
            while input.try_recv().is_ok() {}
            teleop.release_all();
            last_drive_key = Instant::now();
            settle_until = Instant::now() + GAP_SETTLE;
            app.set_message(text, Instant::now());
        }
        // Wait for input until the next tick, so a key acts at once.
        let mut fresh_press = false;
        let wait = next_tick.saturating_duration_since(Instant::now());
        let mut first = match input.recv_timeout(wait) {
            Ok(input) => Some(input),
            Err(RecvTimeoutError::Timeout) => None,
            Err(RecvTimeoutError::Disconnected) => break End::TerminalLost("input closed".to_string()),
        };
        while let Some(item) = first.take().or_else(|| input.try_recv().ok()) {
            let now = epoch.elapsed();
            match item {
                Input::Closed(why) => break 'run End::TerminalLost(why),
                Input::Event(Event::Resize(..)) => drawn = None,
                Input::Event(Event::FocusLost) => teleop.release_all(),
                Input::Event(Event::Key(key)) => {
                    let was_held = !teleop.held(now).is_empty();
                    let overlay = app.prompt() != Prompt::None || app.help_shown();
                    if let Some((driving_key, action)) = driving_key(&key) {
                        if overlay || !driving.armed() {
                            // A dialog owns the keyboard; watching, a drive key asks to arm. Neither drives.
                            if action == KeyAction::Press {
                                handle(&mut app, &mut driving, &mut teleop, Action::AskArm, &mut lights_step);
                            }
                            continue;
                        }
                        // A press right after a quiet keyboard is fresh; check the quiet before this key.
                        let quiet = last_drive_key.elapsed();
                        last_drive_key = Instant::now();
                        teleop.key(now, driving_key, action);
                        let fresh = action == KeyAction::Press
                            && !was_held
                            && quiet >= RELEASE_QUIET
                            && Instant::now() >= settle_until;
                        if driving.needs_release && fresh && !driving.blocked_now() {
                            driving.needs_release = false;
                        }
                        fresh_press |= fresh;
                        continue;
                    }
                    if key.kind != KeyEventKind::Press {
                        continue;
                    }
                    let action = action_for(&key, app.prompt(), app.help_shown(), driving.armed());
                    match action {
                        Action::Quit => break 'run End::Quit,
                        Action::Suspend => {
                            // Ctrl-Z in raw mode is a key: do what the shell's Ctrl-Z would, safely.
                            driving.suspend();
                            crate::dashboard::terminal::restore();
                            let _ = signal_hook::low_level::raise(signal_hook::consts::SIGSTOP);
                        }
                        action => handle(&mut app, &mut driving, &mut teleop, action, &mut lights_step),
                    }
                }
                Input::Event(_) => {}
            }
        }

        // Look again before commanding: keys read just now may be a backlog from before a gap that the sender
        // has recorded meanwhile; they must not end its hold. (If the sender records the gap only after
        // this look, its gap overrides the resume asked for below: it checks for gaps after resumes.)
        if let Some(text) = driving.gap_since_last_look() {
            while input.try_recv().is_ok() {}
            teleop.release_all();
            last_drive_key = Instant::now();
            settle_until = Instant::now() + GAP_SETTLE;
            fresh_press = false;
            app.set_message(text, Instant::now());
        }
        let now = Instant::now();
        let request = teleop.request(epoch.elapsed());
        let requested = (request.0 * limits.max_linear, request.1 * limits.max_angular);
        let anything_held = !teleop.held(epoch.elapsed()).is_empty();
        driving.command(requested, anything_held, fresh_press, last_drive_key.elapsed());
        if now.duration_since(last_update) >= UPDATE_EVERY {
            let status = session.status();
            if let Some(error) = status.link_error.clone() {
                if session.kind != LinkKind::Replay {
                    break End::LinkLost(error);
                }
            }
            if let Some(text) = driving.observe(&status) {
                teleop.release_all();
                app.set_message(text, Instant::now());
            }
            let stats = driving.sender.as_ref().map(MotionSender::stats).unwrap_or_default();
            app.update(&Snapshot { status: &status, sender: stats, link_name: &session.name, now });
            app.set_recording_loss(session.recording_losses());
            app.set_arming(match (driving.armed(), watch_only.is_some()) {
                (true, _) => Arming::Armed,
                (false, true) => Arming::WatchOnly,
                (false, false) => Arming::Watching,
            });
            let held = teleop.held(epoch.elapsed()).into_iter().map(key_name).collect();
            let requested = if driving.armed() { driving.last_requested } else { (0.0, 0.0) };
            app.set_teleop(TeleopView {
                release_mode: release_mode_text(&teleop, watch_only),
                scale: teleop.scale(),
                held,
                requested,
            });
            last_update = now;
        }
        let fingerprint = app.fingerprint();
        if drawn != Some(fingerprint) && now.duration_since(last_draw) >= MIN_REDRAW {
            if let Err(error) = screen.terminal.draw(|frame| render(frame, &app)) {
                break End::TerminalLost(error.to_string());
            }
            drawn = Some(fingerprint);
            last_draw = now;
        }
        next_tick += LOOP;
        if next_tick < Instant::now() {
            next_tick = Instant::now() + LOOP;
        }
    };
    // Stop the robot first, then give the terminal back (Screen's drop), then stop the input thread.
    let stopped = driving.disarm();
    drop(screen);
    done.store(true, Ordering::SeqCst);
    Ok((end, stopped))
}

/// Acts on a key that does not drive.
fn handle(
    app: &mut App,
    driving: &mut Driving,
    teleop: &mut Teleop,
    action: Action,
    lights_step: &mut usize,
) {
    let now = Instant::now();
    match action {
        Action::Quit | Action::Suspend | Action::None => {}
        Action::Stop => {
            teleop.release_all();
            driving.halt();
            if driving.armed() {
                app.set_message("zero sent (Space): press a key again to drive".to_string(), now);
            }
        }
        Action::Faster => {
            teleop.faster();
        }
        Action::Slower => {
            teleop.slower();
        }
        Action::Help => app.toggle_help(),
        Action::Close => {
            app.cancel_prompt();
            app.hide_help();
        }
        Action::AskArm => match driving.watch_only {
            Some(why) => app.set_message(format!("watch-only ({why}): nothing is sent to the robot"), now),
            None => app.ask_arm_confirmation(),
        },
        Action::Arm => {
            app.cancel_prompt();
            teleop.release_all();
            let text = driving.arm().unwrap_or_else(|error| format!("cannot arm: {error:#}"));
            app.set_message(text, now);
        }
        Action::Disarm => {
            teleop.release_all();
            let text = match driving.disarm() {
                Stopped::NotSent(why) => {
                    let text = format!(
                        "disarmed, but the stop frames could not be sent ({why}): the robot's own {} ms \
                         command timeout stops it",
                        COMMAND_TIMEOUT.as_millis()
                    );
                    driving.last_stop = Some(Stopped::NotSent(why));
                    text
                }
                _ => "disarmed: zero sent; WATCHING (nothing is sent)".to_string(),
            };
            app.set_message(text, now);
        }
        Action::AskClear => app.ask_clear_confirmation(),
        Action::Clear => {
            app.cancel_prompt();
            let frames = driving.session.codec().clear_faults(ClearTarget::All);
            let sent = frames.iter().map(|frame| driving.session.send(frame)).collect::<Result<Vec<_>>>();
            let text = match sent {
                Ok(_) => {
                    format!("fault clear sent ({}): watch the faults panel", clear_words(driving.session))
                }
                Err(error) => format!("cannot send the fault clear: {error:#}"),
            };
            app.set_message(text, now);
        }
        Action::CommandMode => {
            if let Some(sender) = &driving.sender {
                sender.request_mode_enable();
                app.set_message("command mode requested".to_string(), now);
            }
        }
        Action::Lights => {
            let (lights, name) = LIGHT_CYCLE[*lights_step % LIGHT_CYCLE.len()];
            *lights_step += 1;
            let frame = driving.session.codec().lights(lights);
            let text = match driving.session.send(&frame) {
                Ok(()) => format!("lights: {name}"),
                Err(error) => format!("cannot set the lights: {error:#}"),
            };
            app.set_message(text, now);
        }
    }
}

/// What a fault clear sends on this link, in words.
fn clear_words(session: &Session) -> &'static str {
    match session.wire() {
        Wire::CanV2 => "0x441 all",
        Wire::CanV1 => "V1 clear codes in 0x130",
        Wire::Serial => "RS232 clear codes",
    }
}

fn release_mode_text(teleop: &Teleop, watch_only: Option<&str>) -> String {
    if let Some(why) = watch_only {
        return format!("driving off: {why}");
    }
    match teleop.mode() {
        ReleaseMode::Events => "key release: terminal events (kitty protocol)".to_string(),
        ReleaseMode::Deadline => {
            let learned = |value: Duration| {
                if value.is_zero() {
                    "not learned yet".to_string()
                } else {
                    format!("{} ms", value.as_millis())
                }
            };
            let (delay, interval) = teleop.learned();
            format!(
                "key release: auto-repeat timeout (repeat delay {}, interval {})",
                learned(delay),
                learned(interval)
            )
        }
    }
}

/// The light settings `l` cycles through.
const LIGHT_CYCLE: [(Lights, &str); 5] = [
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_ON,
            front_brightness: 0,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "on",
    ),
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_BREATH,
            front_brightness: 0,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "breathing",
    ),
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_CUSTOM,
            front_brightness: 30,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "custom 30 %",
    ),
    (
        Lights {
            enable: 1,
            front_mode: LIGHT_OFF,
            front_brightness: 0,
            rear_mode: 0,
            rear_brightness: 0,
            count: 0,
        },
        "off",
    ),
    (
        Lights { enable: 0, front_mode: 0, front_brightness: 0, rear_mode: 0, rear_brightness: 0, count: 0 },
        "released to the firmware",
    ),
];

fn key_name(key: Key) -> &'static str {
    match key {
        Key::Up => "up",
        Key::Down => "down",
        Key::Left => "left",
        Key::Right => "right",
    }
}

/// Arrow keys, with what kind of event this is. Legacy terminals report every byte as a Press.
fn driving_key(key: &KeyEvent) -> Option<(Key, KeyAction)> {
    let driving = match key.code {
        KeyCode::Up => Key::Up,
        KeyCode::Down => Key::Down,
        KeyCode::Left => Key::Left,
        KeyCode::Right => Key::Right,
        _ => return None,
    };
    let action = match key.kind {
        KeyEventKind::Press => KeyAction::Press,
        KeyEventKind::Repeat => KeyAction::Repeat,
        KeyEventKind::Release => KeyAction::Release,
    };
    Some((driving, action))
}

#[derive(Debug, PartialEq, Eq)]
enum Action {
    Quit,
    Suspend,
    Stop,
    Faster,
    Slower,
    Help,
    /// Close the prompt or overlay on screen (Esc, or any key a dialog does not take).
    Close,
    AskArm,
    Arm,
    Disarm,
    AskClear,
    Clear,
    CommandMode,
    Lights,
    None,
}

/// What a (non-arrow) key press does, given what is on screen and whether driving is armed. A prompt or the
/// help owns the keyboard: its keys act on it, others close it; Esc closes and never quits. q, Ctrl-C and
/// Space work everywhere.
fn action_for(key: &KeyEvent, prompt: Prompt, help: bool, armed: bool) -> Action {
    let ctrl = key.modifiers.contains(KeyModifiers::CONTROL);
    match key.code {
        KeyCode::Char('c') if ctrl => return Action::Quit,
        KeyCode::Char('z') if ctrl => return Action::Suspend,
        KeyCode::Char(' ') => return Action::Stop,
        _ => {}
    }
    match prompt {
        Prompt::ConfirmClear => {
            return match key.code {
                KeyCode::Char('y') | KeyCode::Char('Y') => Action::Clear,
                _ => Action::Close,
            }
        }
        Prompt::ConfirmArm => {
            return match key.code {
                KeyCode::Char('y') | KeyCode::Char('Y') => Action::Arm,
                _ => Action::Close,
            }
        }
        Prompt::None => {}
    }
    if help {
        return match key.code {
            KeyCode::Char('q') => Action::Quit,
            _ => Action::Close,
        };
    }
    // Watching: every key that would send something asks to arm first.
    let sends = |action: Action| if armed { action } else { Action::AskArm };
    match key.code {
        KeyCode::Char('q') => Action::Quit,
        KeyCode::Esc => Action::Close,
        KeyCode::Char('+') | KeyCode::Char('=') => Action::Faster,
        KeyCode::Char('-') | KeyCode::Char('_') => Action::Slower,
        KeyCode::Char('?') => Action::Help,
        KeyCode::Char('a') if armed => Action::Disarm,
        KeyCode::Char('a') => Action::AskArm,
        KeyCode::Char('c') => sends(Action::AskClear),
        KeyCode::Char('m') => sends(Action::CommandMode),
        KeyCode::Char('l') => sends(Action::Lights),
        _ => Action::None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn press(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    #[test]
    fn keys_map_to_actions_and_the_prompt_takes_precedence() {
        let armed = |code| action_for(&press(code), Prompt::None, false, true);
        assert_eq!(armed(KeyCode::Char('q')), Action::Quit);
        assert_eq!(armed(KeyCode::Esc), Action::Close, "Esc never quits");
        let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
        assert_eq!(
            action_for(&ctrl_c, Prompt::ConfirmClear, false, true),
            Action::Quit,
            "Ctrl-C always quits"
        );
        let ctrl_z = KeyEvent::new(KeyCode::Char('z'), KeyModifiers::CONTROL);
        assert_eq!(action_for(&ctrl_z, Prompt::None, false, true), Action::Suspend);
        assert_eq!(armed(KeyCode::Char('c')), Action::AskClear);
        assert_eq!(armed(KeyCode::Char('a')), Action::Disarm);
        assert_eq!(action_for(&press(KeyCode::Char('y')), Prompt::ConfirmClear, false, true), Action::Clear);
        assert_eq!(action_for(&press(KeyCode::Char('q')), Prompt::ConfirmClear, false, true), Action::Close);
        assert_eq!(action_for(&press(KeyCode::Esc), Prompt::ConfirmClear, false, true), Action::Close);
        assert_eq!(action_for(&press(KeyCode::Char(' ')), Prompt::ConfirmClear, false, true), Action::Stop);
        assert_eq!(
            action_for(&press(KeyCode::Esc), Prompt::None, true, true),
            Action::Close,
            "Esc closes help"
        );
        assert_eq!(action_for(&press(KeyCode::Char('l')), Prompt::None, true, true), Action::Close);
        assert_eq!(driving_key(&press(KeyCode::Up)), Some((Key::Up, KeyAction::Press)));
        assert_eq!(driving_key(&press(KeyCode::Char('w'))), None);
    }

    #[test]
    fn watching_every_key_that_sends_asks_to_arm_first() {
        let watching = |code| action_for(&press(code), Prompt::None, false, false);
        for code in [KeyCode::Char('a'), KeyCode::Char('c'), KeyCode::Char('m'), KeyCode::Char('l')] {
            assert_eq!(watching(code), Action::AskArm, "{code:?}");
        }
        assert_eq!(watching(KeyCode::Char('+')), Action::Faster, "the scale sends nothing");
        assert_eq!(action_for(&press(KeyCode::Char('y')), Prompt::ConfirmArm, false, false), Action::Arm);
        assert_eq!(action_for(&press(KeyCode::Char('n')), Prompt::ConfirmArm, false, false), Action::Close);
        assert_eq!(action_for(&press(KeyCode::Char(' ')), Prompt::None, false, false), Action::Stop);
    }
}
