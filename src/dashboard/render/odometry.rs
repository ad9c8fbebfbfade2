//! The Odometry & lights panel: the wheel odometers, the trip, the dead-reckoned pose and the lights.

use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use super::text::fit_words;
use super::theme::{block, Theme};
use crate::dashboard::app::{App, Protocol};
use crate::protocol::catalog;
use crate::protocol::message::MessageKind;
use crate::protocol::LightMode;

/// Why the odometry panel is empty: not yet, or never on a wire that does not report it (RS232, V1).
fn no_odometry_text(protocol: Protocol) -> String {
    let Some(wire) = protocol.wire() else { return "no odometry yet".to_string() };
    match catalog::identifier_of(MessageKind::Odometry, wire) {
        Some(id) => format!("no odometry ({id}) yet"),
        None => format!("{} reports no odometry", protocol.label()),
    }
}

pub(super) fn render_odometry(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let shown = &app.shown;
    let metres = |mm: i32| format!("{:.2}", f64::from(mm) / 1000.0);
    let cm = |cm: i64| format!("{:+.2}", cm as f64 / 100.0);
    let trip = format!("{:.2} m", shown.trip_cm as f64 / 100.0);
    let mut lines = Vec::new();
    match (shown.odometer_mm, shown.pose) {
        (Some((left, right)), Some(pose)) => {
            let heading = pose.heading_decideg as f64 / 10.0;
            if compact {
                lines.push(Line::raw(format!("L {}  R {} m", metres(left), metres(right))));
                lines.push(Line::raw(format!("trip {trip}")));
                lines.push(Line::raw(format!("x{} y{} θ{heading:+.0}°", cm(pose.x_cm), cm(pose.y_cm))));
            } else {
                lines.push(Line::raw(format!("left    {} m", metres(left))));
                lines.push(Line::raw(format!("right   {} m", metres(right))));
                lines.push(Line::raw(format!("trip    {trip}")));
                lines.push(Line::raw(format!("pose    x {} y {} m", cm(pose.x_cm), cm(pose.y_cm))));
                lines.push(Line::raw(format!("heading {heading:+.1}°")));
            }
        }
        _ => {
            lines.push(Line::styled(no_odometry_text(shown.protocol), theme.dim()));
            lines.push(Line::styled("pose: -", theme.dim()));
            if !compact {
                lines.push(Line::raw(""));
                lines.push(Line::raw(""));
                lines.push(Line::raw(""));
            } else {
                lines.push(Line::raw(""));
            }
        }
    }
    let label = if compact { "lights " } else { "lights  " };
    let mut lights = lights_span(app, theme);
    let room = usize::from(area.width.saturating_sub(2)).saturating_sub(label.len());
    lights.content = fit_words(&lights.content, room).into();
    lines.push(Line::from(vec![Span::raw(label), lights]));
    frame.render_widget(Paragraph::new(lines).block(block("Odometry & lights", theme)), area);
}

fn lights_span(app: &App, theme: Theme) -> Span<'static> {
    match app.shown.lights {
        None => Span::styled("?", theme.dim()),
        Some((enable, mode, brightness)) => {
            let name = match LightMode::from_code(mode) {
                Some(LightMode::Custom) => format!("custom {brightness} %"),
                Some(mode) => mode.name().to_string(),
                None => format!("mode 0x{mode:02X}"),
            };
            if enable == 0 {
                Span::raw(format!("firmware: {name}"))
            } else {
                Span::raw(name)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_empty_odometry_panel_says_whether_odometry_can_come() {
        // Was "no odometry (0x311) yet" on every wire, for ever on RS232 and V1.
        assert_eq!(no_odometry_text(Protocol::CanV2), "no odometry (0x311) yet");
        assert_eq!(no_odometry_text(Protocol::Serial), "RS232 reports no odometry");
        assert_eq!(no_odometry_text(Protocol::CanV1), "CAN V1 reports no odometry");
        assert_eq!(no_odometry_text(Protocol::Unknown), "no odometry yet");
    }
}
