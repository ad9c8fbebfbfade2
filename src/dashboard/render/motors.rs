//! The Motors panel: each motor's speed, current, temperatures and driver state.

use ratatui::layout::{Constraint, Rect};
use ratatui::style::Style;
use ratatui::text::Span;
use ratatui::widgets::{Row, Table};
use ratatui::Frame;

use super::link::not_reported;
use super::text::fit_words;
use super::theme::{block, Theme};
use crate::dashboard::app::{App, Protocol};
use crate::protocol::message::MessageKind;
use crate::protocol::{FlagTable, Flags};

pub(super) fn render_motors(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let header = if compact {
        ["", "RPM", "A", "drv°C", "mot°C", "state"]
    } else {
        ["", "RPM", "current", "drv°C", "mot°C", "driver state"]
    };
    let fixed: [u16; 5] = if compact { [2, 4, 4, 5, 5] } else { [2, 4, 7, 5, 5] };
    let widths = fixed.map(Constraint::Length).into_iter().chain([Constraint::Fill(1)]);
    // What the state column has: the panel less its border, the fixed columns and one space between each.
    let state_width = usize::from(area.width.saturating_sub(2 + fixed.iter().sum::<u16>() + 5));
    let dash = || Span::styled("-", theme.dim());
    let rows = app.shown.motors.iter().enumerate().map(|(index, motor)| {
        let rpm = motor.rpm.map_or_else(dash, |rpm| Span::raw(format!("{rpm:+}")));
        let current = motor.current_deciamps.map_or_else(dash, |da| {
            let amps = format!("{:.1}", f64::from(da) / 10.0);
            Span::raw(if compact { amps } else { format!("{amps} A") })
        });
        let temperature = |value: Option<i16>| value.map_or_else(dash, |t| Span::raw(t.to_string()));
        let driver = temperature(motor.driver_temperature);
        let motor_temperature = match motor.motor_temperature {
            Some(-40) => Span::styled("n/a", theme.dim()),
            other => temperature(other.map(i16::from)),
        };
        let state = driver_state_span(motor.driver_state, app.shown.protocol, theme, state_width);
        Row::new(vec![
            Span::styled(format!("M{}", index + 1), theme.bold()),
            rpm,
            current,
            driver,
            motor_temperature,
            state,
        ])
    });
    let table = Table::new(rows, widths)
        .header(Row::new(header.map(|h| Span::styled(h, theme.dim()))))
        .block(block("Motors", theme));
    frame.render_widget(table, area);
}

/// `0x0C overcurrent,overheat`, within `width` (whole words); `not on RS232` where the wire has no driver
/// state (it comes in low-speed frames, which RS232 and V1 lack).
fn driver_state_span(state: Option<u8>, protocol: Protocol, theme: Theme, width: usize) -> Span<'static> {
    let (text, style) = match state {
        None if not_reported(protocol).contains(&MessageKind::MotorLowSpeed.name()) => {
            (format!("not on {}", protocol.label()), theme.dim())
        }
        None => ("-".to_string(), theme.dim()),
        Some(0) => ("ok".to_string(), theme.ok()),
        Some(bits) => {
            let flags = Flags::new(FlagTable::DriverState, u16::from(bits));
            let names: Vec<&str> =
                flags.iter().map(|info| info.name.strip_prefix("driver_").unwrap_or(info.name)).collect();
            let worst = flags.iter().map(|info| info.severity).max();
            (
                format!("0x{bits:02X} {}", names.join(",")),
                worst.map_or_else(Style::new, |s| theme.severity(s)),
            )
        }
    };
    Span::styled(fit_words(&text, width), style)
}
