//! What the keys that do not drive do: stop, arm and disarm, the help and the prompts, a fault clear,
//! command mode, the lights; and how the keys are read, for the footer.

use std::time::{Duration, Instant};

use anyhow::Result;

use super::driving::{Driving, Stopped};
use crate::dashboard::app::{App, ReleaseView};
use crate::dashboard::keys::Effect;
use crate::dashboard::lights::LIGHT_CYCLE;
use crate::dashboard::message::Message;
use crate::dashboard::teleop::{ReleaseMode, Teleop};
use crate::protocol::ClearTarget;

/// Acts on a key that does not drive.
pub(super) fn handle(
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
pub(super) fn release_view(teleop: &Teleop, watch_only: Option<&'static str>) -> ReleaseView {
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
