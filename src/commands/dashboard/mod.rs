//! `tracerctl dashboard`: the terminal glue tying the session, the teleop state machine, the motion sender
//! and the renderer together. Everything it draws comes from the pure `dashboard::{app, render}`; every key
//! goes through the pure `dashboard::keys` (the key table and its dispatcher) and `dashboard::teleop`.
//!
//! Here: the command (a terminal, the session, what is said once the screen is gone) and the wiring of
//! the loop. [`event_loop`] runs the loop (input, the command each tick, the view), [`driving`] owns arming
//! and the stop rules, [`actions`] acts on the keys that do not drive.

mod actions;
mod driving;
mod event_loop;
mod health_feed;

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use anyhow::Result;
use parking_lot::Mutex;

use self::driving::{Driving, Stopped, SUSPEND_WAIT};
use self::event_loop::{End, Loop};
use self::health_feed::{health_tap, LatestHealth};
use super::Global;
use crate::control::{Limits, Stopper};
use crate::dashboard::app::App;
use crate::dashboard::teleop::{ReleaseMode, Teleop};
use crate::dashboard::terminal::{spawn_input, Screen};
use crate::exit::{Failure, DATA_ERROR, FAILURE, SUCCESS, USAGE};
use crate::link::LinkKind;
use crate::protocol::message::COMMAND_TIMEOUT;
use crate::session::{Journaling, Session};
use crate::signals::{self, SignalFlag};

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
    /// The battery's warning voltage: the manual's, or the configuration's `battery.warning_volts`.
    pub battery_warning_volts: f64,
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
    // The live analysis sees exactly the frames `--record` writes (the session's tap).
    let (tap, health) = health_tap(global.protocol)?;
    let journal =
        Journaling { record: args.record.as_deref().map(|path| (path, "dashboard")), tap: Some(tap) };
    let session = Session::open_journaled(&global.link, global.protocol, global.sim_config(), journal)?;
    let color = global.color.enabled(true);

    let (end, stopped) = {
        let screen = Screen::enter()?;
        let result = drive_loop(screen, &session, args, color, health);
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
        End::Signal(caught) => (caught.exit_status(), format!("{}: {robot}", caught.name())),
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

fn drive_loop(
    mut screen: Screen,
    session: &Session,
    args: &Options,
    color: bool,
    health: LatestHealth,
) -> Result<(End, Stopped)> {
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
    app.set_battery_warning(args.battery_warning_volts);
    app.set_arming(driving.arming());
    let mut state = Loop::new(app, driving, teleop, health);
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
