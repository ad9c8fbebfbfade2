//! The alert line: the one thing to know now, in words and a colour. Which alert wins is the app state's
//! decision ([`App::alert`]); this only says it.

use super::faults::fault_name;
use super::header::REPLAY_ENDED;
use super::text::{age_text, names_within};
use super::theme::Tone;
use crate::dashboard::alert::Alert;
use crate::dashboard::app::{App, Arming};
use crate::dashboard::keys;
use crate::protocol::ControlMode;

/// The alert line: the words and the colour of the alert that wins ([`App::alert`]).
pub(super) fn alert_text(app: &App, width: usize) -> (Tone, String) {
    match app.alert() {
        Alert::ReplayEnded => (
            Tone::Info,
            format!(
                "[info] {REPLAY_ENDED}: the log's last values stay on screen; {} quits",
                keys::key_name(keys::Action::Quit)
            ),
        ),
        Alert::LinkFailed(error) => (Tone::Alarm, format!("[fault] LINK FAILED: {error}")),
        Alert::Stale { deciseconds } => (
            Tone::Alarm,
            format!(
                "[fault] STALE: no status for {}: every value on screen is old (robot off? cable? bus?)",
                age_text(deciseconds)
            ),
        ),
        Alert::NothingReceived => (
            Tone::Warning,
            format!(
                "[warning] nothing received on {} yet: is the robot on, is this the right link?",
                app.shown.link_name
            ),
        ),
        Alert::NoSystemStatus => (
            Tone::Warning,
            "[warning] frames arrive but no system status yet: is this a TRACER, is --protocol right?"
                .to_string(),
        ),
        Alert::EStop { reason } => (Tone::Alarm, format!("[fault] E-STOP: {reason}")),
        Alert::BlockingFaults(faults) => {
            let names: Vec<String> = faults.iter().map(fault_name).collect();
            (Tone::Alarm, names_within("[fault] CANNOT DRIVE, see Faults: ", &names, width))
        }
        Alert::CannotDrive { reason } => (Tone::Alarm, format!("[fault] CANNOT DRIVE: {reason}")),
        Alert::NotInCommandMode { wire, mode } => (
            Tone::Warning,
            format!(
                "[warning] not in command mode (mode {}): press {} to enable it",
                ControlMode::describe(wire, mode),
                keys::key_name(keys::Action::CommandMode)
            ),
        ),
        Alert::Warnings => {
            (Tone::Warning, "[warning] ready to drive, with warnings: see Faults and Battery".to_string())
        }
        Alert::Ready(Arming::Armed) => (Tone::Ok, "ready to drive: command mode, no faults".to_string()),
        Alert::Ready(Arming::Watching) => {
            let arm = keys::key_name(keys::Action::Arm);
            (Tone::Ok, format!("watching: nothing is sent; an arrow key or {arm} asks to arm driving"))
        }
        Alert::Ready(Arming::WatchOnly) => (Tone::Ok, "watch only: nothing is sent to the robot".to_string()),
    }
}
