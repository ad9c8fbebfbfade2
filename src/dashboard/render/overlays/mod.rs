//! What is drawn over the panels: the help, or a question that takes the next key (arm driving, clear the
//! faults). At most one at a time: a question hides the help.

mod confirm_arm;
mod confirm_clear;
mod dialog;
mod help;

use ratatui::Frame;

use super::theme::Theme;
use crate::dashboard::app::{App, Prompt};

/// The open question, else the help when it is open, over the whole `frame`.
pub(super) fn render_overlay(frame: &mut Frame, app: &App, theme: Theme) {
    let area = frame.area();
    match app.prompt {
        Prompt::ConfirmClear => confirm_clear::render_confirm(frame, area, app, theme),
        Prompt::ConfirmArm => confirm_arm::render_confirm_arm(frame, area, theme),
        Prompt::None if app.help => help::render_help(frame, area, app, theme),
        Prompt::None => {}
    }
}
