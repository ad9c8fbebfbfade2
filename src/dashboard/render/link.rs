//! The Link panel: the link's counters, the feedback identifiers that went stale, each identifier's rate,
//! and what this wire does not report. Full: counters in words and a table of identifiers; compact:
//! `211:50` flowing over the lines.

use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use super::text::{age_text, truncate, wrap};
use super::theme::{block, Theme};
use crate::dashboard::app::{id_name, stale_after, App, Protocol};
use crate::protocol::catalog::{self, Direction};
use crate::protocol::message::MessageKind;
use crate::protocol::Wire;

/// Width of the full link panel: its two columns of identifiers.
pub(super) const LINK_FULL_WIDTH: u16 = 44;

pub(super) fn render_link(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let stale = stale_line(app, theme);
    if compact {
        render_link_compact(frame, area, app, theme, stale);
    } else {
        render_link_full(frame, area, app, theme, stale);
    }
}

/// Which feedback IDs stopped arriving: none, all of them, or a list with their ages.
fn stale_line(app: &App, theme: Theme) -> Line<'static> {
    let shown = &app.shown;
    let stale: Vec<_> = shown.ids.iter().filter(|id| id.stale_deciseconds.is_some()).collect();
    let feedback = shown.ids.iter().filter(|id| stale_after(id.id).is_some()).count();
    if stale.is_empty() {
        Line::from(vec![Span::raw("stale: "), Span::styled("none", theme.ok())])
    } else if stale.len() == feedback && stale.len() > 2 {
        let newest = stale.iter().filter_map(|id| id.stale_deciseconds).min().unwrap_or(0);
        Line::styled(
            format!("STALE: all {} feedback IDs, >= {}", stale.len(), age_text(newest)),
            theme.alarm(),
        )
    } else {
        let list: Vec<String> = stale
            .iter()
            .map(|id| format!("{} {}", id.id, age_text(id.stale_deciseconds.unwrap_or(0))))
            .collect();
        Line::styled(format!("STALE: {}", list.join(", ")), theme.alarm())
    }
}

/// An alarm style for a counter that is not zero.
fn bad_if_any(value: u64, theme: Theme) -> Style {
    if value > 0 {
        theme.alarm()
    } else {
        Style::new()
    }
}

/// The small link panel: the counters on one line, then `211:50 221:50 ...` flowing over the lines left.
fn render_link_compact(frame: &mut Frame, area: Rect, app: &App, theme: Theme, stale: Line<'static>) {
    let shown = &app.shown;
    let c = &shown.counters;
    let fps = shown.total_fps.map_or_else(|| "-".to_string(), |fps| fps.to_string());
    let bad = |value: u64| bad_if_any(value, theme);
    let mut counters = vec![Span::raw(format!("rx {fps}/s"))];
    // A serial port has no error frames nor socket drops.
    if shown.protocol != Protocol::Serial {
        counters.push(Span::styled(format!("err {}", c.error_frames), bad(c.error_frames)));
        counters.push(Span::styled(format!("drop {}", c.socket_drops), bad(c.socket_drops)));
    }
    counters.push(Span::styled(format!("cksum {}", c.serial_bad_checksum), bad(c.serial_bad_checksum)));
    if shown.protocol == Protocol::Serial {
        counters.push(Span::raw(format!("skip {}", c.serial_skipped_bytes)));
    }
    if c.send_errors > 0 || c.watchdog_trips > 0 {
        counters
            .push(Span::styled(format!("tx err {} wd {}", c.send_errors, c.watchdog_trips), theme.alarm()));
    }
    let width = usize::from(area.width.saturating_sub(2));
    // Whole counters only: one that does not fit is left out, never cut.
    let mut first = Vec::new();
    let mut used = 0usize;
    for counter in counters {
        let needed = counter.width() + usize::from(used > 0);
        if used + needed > width {
            continue;
        }
        if used > 0 {
            first.push(Span::raw(" "));
        }
        used += needed;
        first.push(counter);
    }
    let mut lines = vec![Line::from(first), stale];
    let mut row: Vec<Span> = Vec::new();
    let mut used = 0usize;
    for id in &shown.ids {
        let label = id.id.to_string().trim_start_matches("0x").to_string();
        let text = format!("{label}:{}", id.fps.map_or_else(|| "-".to_string(), |f| f.to_string()));
        let needed = text.len() + usize::from(used > 0);
        if used + needed > width && used > 0 {
            lines.push(Line::from(std::mem::take(&mut row)));
            used = 0;
        }
        if used > 0 {
            row.push(Span::raw(" "));
            used += 1;
        }
        used += text.len();
        let style = if id.stale_deciseconds.is_some() { theme.alarm() } else { Style::new() };
        row.push(Span::styled(text, style));
    }
    if !row.is_empty() {
        lines.push(Line::from(row));
    }
    if shown.ids.is_empty() {
        lines.push(Line::styled("no frames yet", theme.dim()));
    }
    let room = usize::from(area.height.saturating_sub(2)).saturating_sub(lines.len());
    lines.extend(not_reported_lines(shown.protocol, width, theme).into_iter().take(room));
    frame.render_widget(Paragraph::new(lines).block(block("Link · ID:fps", theme)), area);
}

/// The full link panel: the counters in words, then `0x211  system     50/s` in as many columns as fit.
fn render_link_full(frame: &mut Frame, area: Rect, app: &App, theme: Theme, stale: Line<'static>) {
    let shown = &app.shown;
    let c = &shown.counters;
    let fps = shown.total_fps.map_or_else(|| "-".to_string(), |fps| fps.to_string());
    let bad = |value: u64| bad_if_any(value, theme);
    let mut lines = Vec::new();
    // What the link can count: error frames and drops on CAN, checksums and skipped bytes on RS232.
    if shown.protocol == Protocol::Serial {
        lines.push(Line::from(vec![
            Span::raw(format!("rx {fps} fps · ")),
            Span::styled(format!("checksum errors {}", c.serial_bad_checksum), bad(c.serial_bad_checksum)),
        ]));
        lines.push(Line::raw(format!("skipped bytes {}", c.serial_skipped_bytes)));
    } else {
        lines.push(Line::from(vec![
            Span::raw(format!("rx {fps} fps · ")),
            Span::styled(format!("error frames {}", c.error_frames), bad(c.error_frames)),
            Span::raw(" · "),
            Span::styled(format!("dropped {}", c.socket_drops), bad(c.socket_drops)),
        ]));
        let mut checksum = vec![Span::styled(
            format!("serial checksum errors {}", c.serial_bad_checksum),
            bad(c.serial_bad_checksum),
        )];
        if c.serial_skipped_bytes > 0 {
            checksum.push(Span::raw(format!(" · skipped bytes {}", c.serial_skipped_bytes)));
        }
        lines.push(Line::from(checksum));
    }
    lines.push(Line::from(vec![
        Span::styled(format!("tx send errors {}", c.send_errors), bad(c.send_errors)),
        Span::raw(" · "),
        Span::styled(format!("watchdog trips {}", c.watchdog_trips), bad(c.watchdog_trips)),
    ]));
    lines.push(stale);
    let width = usize::from(area.width.saturating_sub(2));
    let room = usize::from(area.height.saturating_sub(2)).saturating_sub(lines.len());
    lines.extend(id_columns(app, theme, width, room));
    // Then, in the room left (the panel's height counts them), what this wire does not report.
    let room = usize::from(area.height.saturating_sub(2)).saturating_sub(lines.len());
    lines.extend(not_reported_lines(shown.protocol, width, theme).into_iter().take(room));
    frame.render_widget(Paragraph::new(lines).block(block("Link health", theme)), area);
}

/// What the robot reports on CAN V2 and not on this protocol's wire, by message name (RS232: odometry,
/// motor_low_speed, rc_state, version_response): the catalog's robot frames compared, wire by wire.
pub(super) fn not_reported(protocol: Protocol) -> Vec<&'static str> {
    let Some(wire) = protocol.wire() else { return Vec::new() };
    let sends = |kind: MessageKind, wire: Wire| {
        catalog::CATALOG
            .iter()
            .any(|entry| entry.kind == kind && entry.wire == wire && entry.direction == Direction::FromRobot)
    };
    let mut missing = Vec::new();
    for entry in
        catalog::CATALOG.iter().filter(|e| e.wire == Wire::CanV2 && e.direction == Direction::FromRobot)
    {
        if !sends(entry.kind, wire) && !missing.contains(&entry.kind.name()) {
            missing.push(entry.kind.name());
        }
    }
    missing
}

/// `RS232 does not report: odometry, ...`, wrapped to `width`; nothing on CAN V2.
pub(super) fn not_reported_lines(protocol: Protocol, width: usize, theme: Theme) -> Vec<Line<'static>> {
    let missing = not_reported(protocol);
    if missing.is_empty() {
        return Vec::new();
    }
    let text = format!("{} does not report: {}", protocol.label(), missing.join(", "));
    wrap(&text, width).into_iter().map(|row| Line::styled(row, theme.dim())).collect()
}

/// `0x211  system     50/s` per ID, in as many columns as fit `width`, at most `room` rows (the last cell
/// then says how many more).
fn id_columns(app: &App, theme: Theme, width: usize, room: usize) -> Vec<Line<'static>> {
    const NAME: usize = 8;
    const RATE: usize = 5;
    let shown = &app.shown;
    // As wide as the identifiers shown (0x211: 5, 0xAA01: 6) and their names, with a space after each.
    let id_width = shown.ids.iter().map(|id| id.id.to_string().len()).max().unwrap_or(5) + 1;
    let name_width =
        shown.ids.iter().map(|id| id_name(id.id).chars().count().min(NAME)).max().unwrap_or(0) + 1;
    let cell = id_width + name_width + RATE;
    let columns = ((width + 2) / (cell + 2)).max(1);
    let capacity = room * columns;
    let overflow = shown.ids.len() > capacity;
    let listed = if overflow { capacity.saturating_sub(1) } else { shown.ids.len() };
    let mut cells: Vec<Span> = shown.ids[..listed]
        .iter()
        .map(|id| {
            let rate = match (id.stale_deciseconds, id.fps) {
                (Some(_), _) => "STALE".to_string(),
                (None, Some(fps)) => format!("{fps}/s"),
                (None, None) => "-".to_string(),
            };
            let text = format!(
                "{:<id_width$}{:<name_width$}{rate:>RATE$}",
                id.id.to_string(),
                truncate(id_name(id.id), NAME)
            );
            let style = if id.stale_deciseconds.is_some() { theme.alarm() } else { Style::new() };
            Span::styled(text, style)
        })
        .collect();
    if overflow {
        cells.push(Span::styled(format!("... {} more IDs", shown.ids.len() - listed), theme.dim()));
    }
    let mut lines = Vec::new();
    if shown.ids.is_empty() {
        lines.push(Line::styled("no frames yet", theme.dim()));
    }
    for chunk in cells.chunks(columns) {
        let mut row = Vec::new();
        for (index, cell) in chunk.iter().enumerate() {
            if index > 0 {
                row.push(Span::raw("  "));
            }
            row.push(cell.clone());
        }
        lines.push(Line::from(row));
    }
    lines
}
