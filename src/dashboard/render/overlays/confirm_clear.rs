//! "Clear faults?": asked before a fault clear is sent, with the latched faults it would clear.

use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::Frame;

use super::dialog::dialog;
use crate::dashboard::app::App;
use crate::dashboard::keys;
use crate::dashboard::render::faults::{fault_name, severity_tag};
use crate::dashboard::render::theme::{block, Theme};
use crate::protocol::Severity;

pub(super) fn render_confirm(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
    let latched: Vec<String> = app
        .faults()
        .iter()
        .filter(|f| matches!(f.info.severity, Severity::Fault | Severity::Protection))
        .map(|f| format!("{} {}", severity_tag(f.info.severity), fault_name(f)))
        .collect();
    let mut lines = vec![
        Line::raw("Send a fault clear to the robot (all latched faults)?"),
        Line::styled("Battery bits and the E-stop do not clear this way.", theme.dim()),
        Line::raw(""),
    ];
    if latched.is_empty() {
        lines.push(Line::styled("No fault or protection is set now.", theme.dim()));
    } else {
        lines.push(Line::raw("Set now:"));
        for fault in latched.iter().take(4) {
            lines.push(Line::styled(format!("  {fault}"), theme.alarm()));
        }
        if latched.len() > 4 {
            lines.push(Line::raw(format!("  ... {} more", latched.len() - 4)));
        }
    }
    lines.push(Line::raw(""));
    let answer = Line::from(vec![
        Span::styled(keys::key_name(keys::Action::Yes), theme.key()),
        Span::raw(" send the clear   "),
        Span::styled(keys::key_name(keys::Action::Stop), theme.key()),
        Span::raw(" stop   "),
        Span::styled("any other key", theme.key()),
        Span::raw(" cancel"),
    ]);
    dialog(frame, area, lines, answer, 62, block("Clear faults?", theme).border_style(theme.alarm()));
}
