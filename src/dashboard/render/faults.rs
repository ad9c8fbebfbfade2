//! The Faults panel: every set fault and status bit, worst first, its severity spelled, wrapped while the
//! room allows.

use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use super::text::{fit_words, wrap};
use super::theme::{block, Theme};
use crate::dashboard::app::{App, FaultLine};
use crate::protocol::Severity;

/// Width of the severity column of the faults list: `[protection]`.
pub(super) const SEVERITY_COLUMN: usize = 12;

pub(super) fn fault_name(fault: &FaultLine) -> String {
    match fault.motor {
        Some(motor) => format!("M{motor} {}", fault.info.name),
        None => fault.info.name.to_string(),
    }
}

pub(super) fn severity_tag(severity: Severity) -> String {
    format!("[{}]", severity.as_str())
}

pub(super) fn render_faults(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
    let faults = app.faults();
    // Counted as doctor counts: info lines (states) are listed, not counted.
    let title = match app.fault_count() {
        0 => "Faults".to_string(),
        count => format!("Faults ({count})"),
    };
    let block = block(title, theme);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    if app.shown.system.is_none() {
        frame.render_widget(Paragraph::new(Line::styled("no status yet", theme.dim())), inner);
        return;
    }
    if faults.is_empty() {
        frame.render_widget(Paragraph::new(Line::styled("none", theme.ok())), inner);
        return;
    }
    let lines = fault_lines(&faults, usize::from(inner.width), usize::from(inner.height), theme);
    frame.render_widget(Paragraph::new(lines), inner);
}

/// The faults, worst first: wrapped while the room allows, else one line each, else the first ones and a
/// count of the rest.
fn fault_lines(faults: &[FaultLine], width: usize, height: usize, theme: Theme) -> Vec<Line<'static>> {
    let body_width = width.saturating_sub(SEVERITY_COLUMN + 1).max(1);
    let mut lines = Vec::new();
    let fits_all = faults.len() <= height;
    // One line of room shows the worst fault itself (the title has the count), more keep one for the rest.
    let shown_count = match (fits_all, height) {
        (true, _) => faults.len(),
        (false, 0 | 1) => height,
        (false, _) => height - 1,
    };
    for (index, fault) in faults.iter().take(shown_count).enumerate() {
        let name = fault_name(fault);
        let body = format!("{name}: {}", fault.info.action);
        let wrapped = wrap(&body, body_width);
        // Keep one line for each fault still to come.
        let left_after = shown_count - index - 1;
        let room = height.saturating_sub(lines.len() + left_after);
        let rows: Vec<String> =
            if wrapped.len() <= room { wrapped } else { vec![fit_words(&body, body_width)] };
        let style = theme.severity(fault.info.severity);
        for (row, text) in rows.into_iter().enumerate() {
            let mut spans = Vec::new();
            if row == 0 {
                spans.push(Span::styled(
                    format!("{:<width$} ", severity_tag(fault.info.severity), width = SEVERITY_COLUMN),
                    style,
                ));
                let cut = name.len().min(text.len());
                let (head, tail) = text.split_at(cut);
                spans.push(Span::styled(head.to_string(), theme.bold()));
                spans.push(Span::raw(tail.to_string()));
            } else {
                spans.push(Span::raw(" ".repeat(SEVERITY_COLUMN + 1)));
                spans.push(Span::raw(text));
            }
            lines.push(Line::from(spans));
        }
    }
    if !fits_all && shown_count < height {
        let more = faults.len() - shown_count;
        let worst = faults[shown_count..].iter().map(|f| f.info.severity).max();
        let text = format!(
            "... {more} more (worst {}): a taller terminal shows them",
            worst.map(severity_tag).unwrap_or_default()
        );
        lines.push(Line::styled(text, theme.bold()));
    }
    lines
}
