//! The Battery panel: the voltage and its zone against the manual's thresholds, a gauge, and the recent
//! history as a sparkline.

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Gauge, Paragraph, RenderDirection, Sparkline};
use ratatui::Frame;

use super::theme::{block, Theme};
use crate::dashboard::app::{App, BatteryZone, BATTERY_GAUGE_TOP_DV};
use crate::protocol::constants::{BATTERY_CUTOFF_DV, BATTERY_FAULT_DV};

pub(super) fn render_battery(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let block = block("Battery", theme);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let Some(system) = app.shown.system else {
        frame.render_widget(Paragraph::new(Line::styled("no status yet", theme.dim())), inner);
        return;
    };
    let decivolts = system.decivolts;
    let zone = BatteryZone::of(decivolts, app.battery_warning_dv);
    let (zone_text, gauge_label) = match zone {
        BatteryZone::Ok => ("ok".to_string(), "OK"),
        BatteryZone::Warning => (format!("[warning] <= {}", volts(app.battery_warning_dv)), "WARNING"),
        BatteryZone::Fault => (format!("[fault] <= {}", volts(BATTERY_FAULT_DV)), "FAULT"),
        BatteryZone::CutOff => (format!("[fault] cut-off <= {}", volts(BATTERY_CUTOFF_DV)), "CUT-OFF"),
    };
    let zone_style = match zone.severity() {
        Some(severity) => theme.severity(severity),
        None => theme.ok(),
    };
    let mut rows = vec![Constraint::Length(1), Constraint::Length(1)];
    if !compact {
        rows.push(Constraint::Length(1));
    }
    rows.push(Constraint::Min(1));
    if !compact {
        rows.push(Constraint::Length(1));
    }
    let parts = Layout::vertical(rows).split(inner);
    let value = Line::from(vec![
        Span::styled(volts(decivolts), theme.bold()),
        Span::raw("  "),
        Span::styled(zone_text, zone_style),
    ]);
    frame.render_widget(Paragraph::new(value), parts[0]);
    let span = f64::from(BATTERY_GAUGE_TOP_DV - BATTERY_CUTOFF_DV);
    let ratio = (f64::from(decivolts.saturating_sub(BATTERY_CUTOFF_DV)) / span).clamp(0.0, 1.0);
    let gauge_style = match zone {
        BatteryZone::Ok => theme.ok(),
        BatteryZone::Warning => theme.warning(),
        BatteryZone::Fault | BatteryZone::CutOff => theme.paint(Color::Red),
    };
    frame.render_widget(
        Gauge::default().ratio(ratio).label(Span::styled(gauge_label, theme.bold())).gauge_style(gauge_style),
        parts[1],
    );
    let history = &app.shown.battery_history;
    let (spark_area, caption) = if compact { (parts[2], None) } else { (parts[3], Some(parts[4])) };
    if !compact {
        let scale = format!(
            "warn {} fault {} cut {}",
            volts_bare(app.battery_warning_dv),
            volts_bare(BATTERY_FAULT_DV),
            volts_bare(BATTERY_CUTOFF_DV)
        );
        frame.render_widget(Paragraph::new(Line::styled(scale, theme.dim())), parts[2]);
    }
    // Newest on the right. Scaled to the samples shown, over at least 1 V, so a sag of 0.1 V shows.
    let recent: Vec<u16> = history.iter().rev().take(usize::from(spark_area.width)).copied().collect();
    let top = recent.iter().copied().max().unwrap_or(0);
    let floor = recent.iter().copied().min().unwrap_or(0).saturating_sub(1).min(top.saturating_sub(10));
    let data: Vec<u64> = recent.iter().map(|dv| u64::from(dv - floor)).collect();
    frame.render_widget(
        Sparkline::default()
            .data(&data)
            .max(u64::from(top - floor).max(1))
            .direction(RenderDirection::RightToLeft)
            .style(theme.dim()),
        spark_area,
    );
    if let Some(caption) = caption {
        // Once a drive has given one, the battery's internal resistance (the live analysis) says more
        // about its age than the range of the sparkline.
        let text = match (app.shown.health.battery_text(), recent.iter().min(), recent.iter().max()) {
            (Some(estimate), _, _) => estimate,
            (None, Some(low), Some(high)) => {
                format!("last {} s: {}-{}", recent.len(), volts_bare(*low), volts(*high))
            }
            (None, _, _) => "history: none yet".to_string(),
        };
        frame.render_widget(Paragraph::new(Line::styled(text, theme.dim())), caption);
    }
}

/// `25.9 V`
pub(super) fn volts(decivolts: u16) -> String {
    format!("{} V", volts_bare(decivolts))
}

fn volts_bare(decivolts: u16) -> String {
    format!("{}.{}", decivolts / 10, decivolts % 10)
}
