//! The Speeds panel: what the keys ask for, what was sent and what the robot reports, in m/s and rad/s,
//! with the caps and ramps when there is room.

use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use super::theme::{block, Theme};
use crate::dashboard::app::{scale_percent, speed_text, App, ReleaseView};
use crate::dashboard::teleop::Key;

pub(super) fn render_speeds(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let teleop = &app.teleop;
    // The scale is known once the glue has set the teleop view (it always sets the release mode).
    let title = if teleop.release_mode == ReleaseView::Unset {
        "Speeds".to_string()
    } else if area.width >= 23 {
        format!("Speeds · scale {} %", scale_percent(teleop.scale))
    } else {
        format!("Speeds · {} %", scale_percent(teleop.scale))
    };
    let block = block(title, theme);
    // Narrower columns in a narrow panel (60 columns: 18 inside), so that rad/s stays on screen.
    let (label_width, value_width) = if area.width >= 23 { (6, 7) } else { (5, 6) };
    let row = |label: &str, linear: String, angular: String| {
        format!("{label:<label_width$}{linear:>value_width$} {angular:>value_width$}")
    };
    let held: String = teleop.held.iter().map(Key::to_string).collect();
    let mm = |value: i16| speed_text(f64::from(value) / 1000.0);
    let mut lines = vec![
        // The live analysis' dead time, once a step gave one, beside the units (the panel's rows are full).
        Line::styled(
            match app.shown.health.dead_time_text() {
                Some(dead_time) => format!("{}  {dead_time}", row("", "m/s".into(), "rad/s".into())),
                None => row("", "m/s".into(), "rad/s".into()),
            },
            theme.dim(),
        ),
        Line::from(vec![
            Span::raw(row("keys", speed_text(teleop.requested.0), speed_text(teleop.requested.1))),
            Span::styled(if held.is_empty() { String::new() } else { format!(" {held}") }, theme.bold()),
        ]),
        Line::raw(row("sent", mm(app.shown.sent.0), mm(app.shown.sent.1))),
        match app.shown.measured {
            Some((linear, angular)) => Line::raw(row("robot", mm(linear), mm(angular))),
            None => Line::styled(row("robot", "-".into(), "-".into()), theme.dim()),
        },
    ];
    if !compact {
        let limits = &app.limits;
        lines.push(Line::styled(
            format!("caps  {:.2} m/s · {:.2} rad/s", limits.max_linear, limits.max_angular),
            theme.dim(),
        ));
        lines.push(Line::styled(
            format!("ramps {:.2} m/s² · {:.2} rad/s²", limits.linear_accel, limits.angular_accel),
            theme.dim(),
        ));
    }
    frame.render_widget(Paragraph::new(lines).block(block), area);
}
