//! Below the panels' minimum size: the essentials as wrapped text.

use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Paragraph, Wrap};
use ratatui::Frame;

use super::alert::alert_text;
use super::battery::volts;
use super::faults::severity_tag;
use super::footer::{keys_line, message_line, release_text};
use super::header::header_line;
use super::theme::Theme;
use crate::dashboard::app::{speed_text, App};

/// Below this the panels do not fit and a short text view is drawn instead.
pub(super) const MIN_PANELS: (u16, u16) = (60, 20);

/// Under 60x20: the essentials as text.
pub(super) fn render_small(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
    let (tone, alert) = alert_text(app, usize::MAX);
    let mut lines = vec![header_line(app, theme, area.width), Line::styled(alert, theme.tone(tone))];
    if let Some(system) = app.shown.system {
        let worst = app.faults().iter().map(|f| f.info.severity).filter(|s| s.is_problem()).max();
        lines.push(Line::raw(format!(
            "battery {} · faults {}{}",
            volts(system.decivolts),
            app.fault_count(),
            worst.map(|s| format!(" (worst {})", severity_tag(s))).unwrap_or_default()
        )));
    }
    let mm = |value: i16| speed_text(f64::from(value) / 1000.0);
    let measured =
        app.shown.measured.map_or_else(|| "-".to_string(), |(l, a)| format!("{} {}", mm(l), mm(a)));
    lines.push(Line::raw(format!(
        "m/s rad/s: keys {} {} · sent {} {} · robot {measured}",
        speed_text(app.teleop.requested.0),
        speed_text(app.teleop.requested.1),
        mm(app.shown.sent.0),
        mm(app.shown.sent.1),
    )));
    lines.push(Line::styled(release_text(app), theme.dim()));
    lines.push(keys_line(area.width, theme, app.arming));
    lines.push(Line::styled(
        format!(
            "terminal {}x{}: {}x{} or larger shows the panels",
            area.width, area.height, MIN_PANELS.0, MIN_PANELS.1
        ),
        theme.warning(),
    ));
    lines.push(message_line(app, theme, None));
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}
