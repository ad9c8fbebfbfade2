//! "Arm driving?": asked before the dashboard sends anything.

use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::Frame;

use super::dialog::dialog;
use crate::dashboard::keys;
use crate::dashboard::render::theme::{block, Theme};

pub(super) fn render_confirm_arm(frame: &mut Frame, area: Rect, theme: Theme) {
    let explanation = vec![
        Line::raw("Arm driving? The dashboard then switches to command mode"),
        Line::raw("and sends motion commands at 50 Hz: it takes control from ROS"),
        Line::raw("or an RC transmitter. Until then nothing is sent."),
        Line::raw(""),
    ];
    let answer = Line::from(vec![
        Span::styled(keys::key_name(keys::Action::Yes), theme.key()),
        Span::raw(" arm   "),
        Span::styled("any other key", theme.key()),
        Span::raw(" keep watching"),
    ]);
    dialog(frame, area, explanation, answer, 64, block("Arm driving?", theme).border_style(theme.warning()));
}
