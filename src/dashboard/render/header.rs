//! The header line: tool, arming, link, protocol, vehicle state, control mode and the age of the last
//! status, fitted to the width by leaving out whole parts.

use ratatui::style::{Modifier, Style};
use ratatui::text::{Line, Span};

use super::text::{age_text, middle_ellipsis};
use super::theme::{separator, Theme, Tone};
use crate::dashboard::app::{App, Arming, StatusAge};
use crate::protocol::message::{VEHICLE_ESTOP, VEHICLE_EXCEPTION, VEHICLE_NORMAL};
use crate::protocol::ControlMode;

/// A piece of the header, and when it gives way to a narrow terminal.
struct HeaderPart {
    spans: Vec<Span<'static>>,
    /// Dropped when the header does not fit, lowest first; `None`: always shown.
    drop: Option<u8>,
}

impl HeaderPart {
    fn new(span: Span<'static>, drop: Option<u8>) -> Self {
        Self { spans: vec![span], drop }
    }

    fn width(&self) -> usize {
        self.spans.iter().map(Span::width).sum()
    }
}

/// The link name's rank among the header's parts that give way (after the tool's name and the protocol).
const LINK_RANK: u8 = 2;
/// The fewest characters a long link name (a `--replay` path) keeps before it is left out altogether.
const MIN_LINK_NAME: usize = 12;

/// `tracerctl · ARMED · can0 · CAN V2 · NORMAL · mode can · status <0.1 s`, fitted to `width`: a long link
/// name (a replayed file's path) loses its middle first, then the tool's name, the protocol, the link and
/// the mode go; arming, the vehicle state and the status age always stay.
pub(super) fn header_line(app: &App, theme: Theme, width: u16) -> Line<'static> {
    let shown = &app.shown;
    let arming = match app.arming {
        Arming::Armed => Span::styled("ARMED", theme.alarm()),
        Arming::Watching => Span::styled("WATCHING", theme.ok().add_modifier(Modifier::BOLD)),
        Arming::WatchOnly => Span::styled("WATCH ONLY", theme.ok().add_modifier(Modifier::BOLD)),
    };
    let mut parts = vec![
        HeaderPart::new(Span::styled("tracerctl", theme.bold()), Some(0)),
        HeaderPart::new(arming, None),
        HeaderPart::new(Span::raw(shown.link_name.clone()), Some(LINK_RANK)),
        HeaderPart::new(Span::raw(shown.protocol.label()), Some(1)),
    ];
    match shown.system {
        Some(system) => {
            let (text, style) = match system.vehicle_state {
                VEHICLE_NORMAL => ("NORMAL".to_string(), theme.ok().add_modifier(Modifier::BOLD)),
                VEHICLE_ESTOP => ("E-STOP".to_string(), theme.alarm()),
                VEHICLE_EXCEPTION => ("EXCEPTION".to_string(), theme.alarm()),
                other => (format!("STATE 0x{other:02X}"), theme.alarm()),
            };
            parts.push(HeaderPart::new(Span::styled(text, style), None));
            let mode = format!("mode {}", ControlMode::describe(system.wire, system.control_mode));
            let style = if system.in_command_mode() { Style::new() } else { theme.warning() };
            parts.push(HeaderPart::new(Span::styled(mode, style), Some(3)));
        }
        None => parts.push(HeaderPart::new(Span::styled("state ?", theme.dim()), None)),
    }
    let age = match shown.status_age {
        _ if shown.link_ended => Span::styled(REPLAY_ENDED, theme.tone(Tone::Info)),
        StatusAge::Never => Span::styled("no status yet", theme.warning()),
        StatusAge::Fresh => Span::raw("status <0.1 s"),
        StatusAge::Stale { deciseconds } => {
            Span::styled(format!("NO STATUS FOR {}", age_text(deciseconds)), theme.alarm())
        }
    };
    parts.push(HeaderPart::new(age, None));
    fit_header(&mut parts, usize::from(width));
    let mut spans = Vec::new();
    for (index, part) in parts.into_iter().enumerate() {
        if index > 0 {
            spans.push(separator(theme));
        }
        spans.extend(part.spans);
    }
    Line::from(spans)
}

/// Shortens the link name (middle ellipsis), then drops parts by rank, until the header fits `width`.
fn fit_header(parts: &mut Vec<HeaderPart>, width: usize) {
    const SEPARATOR: usize = 3;
    let total = |parts: &[HeaderPart]| {
        parts.iter().map(HeaderPart::width).sum::<usize>() + SEPARATOR * parts.len().saturating_sub(1)
    };
    let shorten_link = |parts: &mut Vec<HeaderPart>, floor: usize| {
        if let Some(link) = parts.iter().position(|part| part.drop == Some(LINK_RANK)) {
            let others = total(parts) - parts[link].width();
            let room = width.saturating_sub(others).max(floor);
            if parts[link].width() > room {
                let name = parts[link].spans[0].content.to_string();
                parts[link].spans[0].content = middle_ellipsis(&name, room).into();
            }
        }
    };
    // A path keeps a readable part of its name before the tool's name goes, then shrinks further.
    shorten_link(parts, 2 * MIN_LINK_NAME);
    if total(parts) > width {
        parts.retain(|part| part.drop != Some(0));
    }
    shorten_link(parts, MIN_LINK_NAME);
    while total(parts) > width {
        let lowest =
            parts.iter().enumerate().filter_map(|(index, part)| part.drop.map(|rank| (rank, index))).min();
        let Some((_, index)) = lowest else { break };
        parts.remove(index);
    }
}

/// Said when the source ended on its own. Only a replay stays on screen after its end (the dashboard closes
/// when any other link ends), so this is always a replay.
pub(super) const REPLAY_ENDED: &str = "replay ended";
