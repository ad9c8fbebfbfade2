//! `tracerctl dashboard`: the terminal loop tying the session, the teleop state machine, the motion sender
//! and the renderer together. Everything it draws comes from the pure `dashboard::{app, render}`; every key
//! goes through the pure `dashboard::teleop`.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use crate::cli::{Cli, DashboardArgs};
use crate::control::{Limits, MotionSender};
use crate::dashboard::app::{App, Prompt, Snapshot, TeleopView};
use crate::dashboard::render::render;
use crate::dashboard::teleop::{Key, KeyAction, ReleaseMode, Teleop};
use crate::dashboard::terminal::{spawn_input, Input, Screen};
use crate::exit::{Failure, FAILURE, SUCCESS, USAGE};
use crate::link::{ClearTarget, Codec, LinkChoice, LinkKind};
use crate::protocol::message::{Lights, LIGHT_BREATH, LIGHT_CUSTOM, LIGHT_OFF, LIGHT_ON};
use crate::session::Session;
use crate::signals;

/// The loop's period: targets are refreshed this often (the sender's watchdog is ten times longer).
const LOOP: Duration = Duration::from_millis(20);
/// Input or drawing that stalls longer than this makes the sender command zero.
const WATCHDOG: Duration = Duration::from_millis(250);
/// At most 20 redraws a second (slow SSH links).
const MIN_REDRAW: Duration = Duration::from_millis(50);
const UPDATE_EVERY: Duration = Duration::from_millis(50);

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

    let end = {
        let screen = Screen::enter()?;
        let result = drive_loop(screen, &session, limits, color);
        // `screen` was dropped inside: the terminal is back before anything is printed.
        result?
    };
    let (status, message) = match end {
        End::Quit => (SUCCESS, "quit: the robot was stopped".to_string()),
        End::Signal(status, name) => (status, format!("{name}: the robot was stopped")),
        End::TerminalLost(why) => (FAILURE, format!("the terminal went away ({why}): the robot was stopped")),
        End::LinkLost(why) => {
            (FAILURE, format!("the link {} failed ({why}): the robot was stopped", session.name))
        }
    };
    eprintln!("tracerctl: {message}");
    Ok(status)
}

fn drive_loop(mut screen: Screen, session: &Session, limits: Limits, color: bool) -> Result<End> {
    let can_drive = session.kind != LinkKind::Replay;
    let mode = if screen.key_release { ReleaseMode::Events } else { ReleaseMode::Deadline };
    let mut teleop = Teleop::new(mode);
    let sender = if can_drive {
        Some(MotionSender::start(session.tx.clone(), Codec::new(session.wire()), limits, WATCHDOG)?)
    } else {
        None
    };
    let stopper = sender.as_ref().map(MotionSender::stopper);
    let signal = signals::listen(move |_| {
        if let Some(stopper) = &stopper {
            stopper.stop_now();
        }
    })?;
    let done = Arc::new(AtomicBool::new(false));
    let input = spawn_input(Arc::clone(&done))?;

    let mut app = App::new(&session.name, limits, color);
    let epoch = Instant::now();
    let mut lights_step = 0usize;
    let mut last_update = Instant::now() - UPDATE_EVERY;
    let mut last_draw = Instant::now() - MIN_REDRAW;
    let mut drawn: Option<u64> = None;
    let mut next_tick = Instant::now();
    let end = 'run: loop {
        if let (Some(status), name) = (signal.exit_status(), signal.name()) {
            break End::Signal(status, name);
        }
        // Wait for input until the next tick, so a key acts at once.
        let mut kick = false;
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
                    if let Some((driving, action)) = driving_key(&key) {
                        teleop.key(now, driving, action);
                        kick |= action == KeyAction::Press;
                        continue;
                    }
                    if key.kind != KeyEventKind::Press {
                        continue;
                    }
                    match action_for(&key, app.prompt()) {
                        Action::Quit => break 'run End::Quit,
                        Action::Stop => {
                            teleop.release_all();
                            kick = true;
                        }
                        Action::Faster => {
                            teleop.faster();
                        }
                        Action::Slower => {
                            teleop.slower();
                        }
                        Action::Help => app.toggle_help(),
                        Action::AskClear => app.ask_clear_confirmation(),
                        Action::CancelPrompt => app.cancel_prompt(),
                        Action::Clear => {
                            app.cancel_prompt();
                            let frames = session.codec().clear_faults(ClearTarget::All);
                            let sent =
                                frames.iter().map(|frame| session.send(frame)).collect::<Result<Vec<_>>>();
                            let text = match sent {
                                Ok(_) => "fault clear sent (0x441 all): watch the faults panel".to_string(),
                                Err(error) => format!("cannot send the fault clear: {error:#}"),
                            };
                            app.set_message(text, Instant::now());
                        }
                        Action::CommandMode => {
                            if let Some(sender) = &sender {
                                sender.request_mode_enable();
                                app.set_message("command mode requested".to_string(), Instant::now());
                            }
                        }
                        Action::Lights => {
                            let (lights, name) = LIGHT_CYCLE[lights_step % LIGHT_CYCLE.len()];
                            lights_step += 1;
                            let frame = session.codec().lights(lights);
                            let text = match session.send(&frame) {
                                Ok(()) => format!("lights: {name}"),
                                Err(error) => format!("cannot set the lights: {error:#}"),
                            };
                            app.set_message(text, Instant::now());
                        }
                        Action::None => {}
                    }
                }
                Input::Event(_) => {}
            }
        }

        let now = Instant::now();
        let request = teleop.request(epoch.elapsed());
        let requested = (request.0 * limits.max_linear, request.1 * limits.max_angular);
        if let Some(sender) = &sender {
            if kick {
                sender.set_target_now(requested.0, requested.1);
            } else {
                sender.set_target(requested.0, requested.1);
            }
        }
        if now.duration_since(last_update) >= UPDATE_EVERY {
            let status = session.status();
            if let Some(error) = status.link_error.clone() {
                if session.kind != LinkKind::Replay {
                    break End::LinkLost(error);
                }
            }
            let stats = sender.as_ref().map(MotionSender::stats).unwrap_or_default();
            app.update(&Snapshot { status: &status, sender: stats, link_name: &session.name, now });
            let held = teleop.held(epoch.elapsed()).into_iter().map(key_name).collect();
            let release_mode = match (can_drive, teleop.mode()) {
                (false, _) => "driving off: --replay is read-only".to_string(),
                (true, ReleaseMode::Events) => "key release: terminal events (kitty protocol)".to_string(),
                (true, ReleaseMode::Deadline) => {
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
            };
            app.set_teleop(TeleopView { release_mode, scale: teleop.scale(), held, requested });
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
    if let Some(sender) = sender {
        sender.stop();
    }
    drop(screen);
    done.store(true, Ordering::SeqCst);
    Ok(end)
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
    Stop,
    Faster,
    Slower,
    Help,
    AskClear,
    Clear,
    CancelPrompt,
    CommandMode,
    Lights,
    None,
}

/// What a (non-arrow) key press does, given the prompt on screen.
fn action_for(key: &KeyEvent, prompt: Prompt) -> Action {
    let ctrl_c = key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL);
    if ctrl_c {
        return Action::Quit;
    }
    if prompt == Prompt::ConfirmClear {
        return match key.code {
            KeyCode::Char('y') | KeyCode::Char('Y') => Action::Clear,
            KeyCode::Char(' ') => Action::Stop,
            _ => Action::CancelPrompt,
        };
    }
    match key.code {
        KeyCode::Char('q') | KeyCode::Esc => Action::Quit,
        KeyCode::Char(' ') => Action::Stop,
        KeyCode::Char('+') | KeyCode::Char('=') => Action::Faster,
        KeyCode::Char('-') | KeyCode::Char('_') => Action::Slower,
        KeyCode::Char('?') => Action::Help,
        KeyCode::Char('c') => Action::AskClear,
        KeyCode::Char('m') => Action::CommandMode,
        KeyCode::Char('l') => Action::Lights,
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
        assert_eq!(action_for(&press(KeyCode::Char('q')), Prompt::None), Action::Quit);
        assert_eq!(action_for(&press(KeyCode::Esc), Prompt::None), Action::Quit);
        let ctrl_c = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
        assert_eq!(action_for(&ctrl_c, Prompt::ConfirmClear), Action::Quit, "Ctrl-C always quits");
        assert_eq!(action_for(&press(KeyCode::Char('c')), Prompt::None), Action::AskClear);
        assert_eq!(action_for(&press(KeyCode::Char('y')), Prompt::ConfirmClear), Action::Clear);
        assert_eq!(action_for(&press(KeyCode::Char('q')), Prompt::ConfirmClear), Action::CancelPrompt);
        assert_eq!(action_for(&press(KeyCode::Char(' ')), Prompt::ConfirmClear), Action::Stop);
        assert_eq!(driving_key(&press(KeyCode::Up)), Some((Key::Up, KeyAction::Press)));
        assert_eq!(driving_key(&press(KeyCode::Char('w'))), None);
    }
}
