//! Drawing the dashboard: a pure function of the [`App`] state.
//!
//! Layout, top to bottom: a header line (tool, link, protocol, vehicle state, control mode, age of the last
//! status), an alert line (the one thing to know now), Battery | Speeds | Odometry & lights, Faults (all the
//! room left), Motors | Link health, then the key-release mode, the keys, and the one-line message.
//! Below 100x30 the panels are abbreviated so that every safety fact (arming, commanded and measured
//! speeds, faults, battery, how to quit) fits down to 60x20; below 60x20 a short text view replaces the
//! panels. What does not fit gives way whole (header parts, footer entries, words), never cut mid-word.
//! Severity is always spelled (`[fault]`); colour only repeats it, and with `color == false` no colour is
//! used at all (bold only).

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Gauge, Paragraph, RenderDirection, Row, Sparkline, Table, Wrap};
use ratatui::Frame;

use super::alert::Alert;
use super::app::{
    id_name, scale_percent, speed_text, App, Arming, BatteryZone, FaultLine, Prompt, Protocol, StatusAge,
    BATTERY_GAUGE_TOP_DV,
};
use super::keys;
use crate::protocol::catalog::{self, Direction};
use crate::protocol::constants::{BATTERY_CUTOFF_DV, BATTERY_FAULT_DV, BATTERY_WARNING_DV};
use crate::protocol::message::{
    light_mode_name, MessageKind, VEHICLE_ESTOP, VEHICLE_EXCEPTION, VEHICLE_NORMAL,
};
use crate::protocol::{ControlMode, FlagTable, Flags, Severity, Wire};

/// Below this the panels do not fit and a short text view is drawn instead.
const MIN_PANELS: (u16, u16) = (60, 20);
/// From this size on, the full panels; below, abbreviated ones.
const FULL: (u16, u16) = (100, 30);
/// Width of the full link panel: its two columns of identifiers.
const LINK_FULL_WIDTH: u16 = 44;
/// Width of the severity column of the faults list: `[protection]`.
const SEVERITY_COLUMN: usize = 12;

/// Styles; without colour, emphasis is bold only.
#[derive(Clone, Copy)]
struct Theme {
    color: bool,
}

impl Theme {
    fn paint(&self, color: Color) -> Style {
        if self.color {
            Style::new().fg(color)
        } else {
            Style::new()
        }
    }
    fn bold(&self) -> Style {
        Style::new().add_modifier(Modifier::BOLD)
    }
    fn alarm(&self) -> Style {
        self.paint(Color::Red).add_modifier(Modifier::BOLD)
    }
    fn warning(&self) -> Style {
        self.paint(Color::Yellow)
    }
    fn ok(&self) -> Style {
        self.paint(Color::Green)
    }
    fn dim(&self) -> Style {
        self.paint(Color::DarkGray)
    }
    fn key(&self) -> Style {
        self.paint(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    fn severity(&self, severity: Severity) -> Style {
        match severity {
            Severity::Protection | Severity::Fault => self.alarm(),
            Severity::Warning => self.warning(),
            Severity::Info => self.dim(),
            Severity::Unknown => self.paint(Color::Magenta),
        }
    }
    fn tone(&self, tone: Tone) -> Style {
        match tone {
            Tone::Ok => self.ok(),
            Tone::Warning => self.warning().add_modifier(Modifier::BOLD),
            Tone::Alarm => self.alarm(),
            Tone::Info => self.paint(Color::Cyan).add_modifier(Modifier::BOLD),
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Tone {
    Ok,
    /// Neither good nor bad news: a replay that ended.
    Info,
    Warning,
    Alarm,
}

/// Draws the whole dashboard.
pub fn render(frame: &mut Frame, app: &App) {
    let area = frame.area();
    let theme = Theme { color: app.color };
    if area.width < MIN_PANELS.0 || area.height < MIN_PANELS.1 {
        render_small(frame, area, app, theme);
    } else {
        let compact = area.width < FULL.0 || area.height < FULL.1;
        let top_height = if compact { 6 } else { 8 };
        let bottom_height = if compact { 6 } else { full_bottom_height(app, area) };
        let [header, alert, top, faults, bottom, release, keys, message] = Layout::vertical([
            Constraint::Length(1),
            Constraint::Length(1),
            Constraint::Length(top_height),
            Constraint::Min(3),
            Constraint::Length(bottom_height),
            Constraint::Length(1),
            Constraint::Length(1),
            Constraint::Length(1),
        ])
        .areas(area);
        frame.render_widget(Paragraph::new(header_line(app, theme, header.width)), header);
        let (tone, text) = alert_text(app, usize::from(alert.width));
        let text = fit_words(&text, usize::from(alert.width));
        frame.render_widget(Paragraph::new(Line::styled(text, theme.tone(tone))), alert);

        let [battery, speeds, odometry] = Layout::horizontal([
            Constraint::Percentage(33),
            Constraint::Percentage(34),
            Constraint::Percentage(33),
        ])
        .areas(top);
        render_battery(frame, battery, app, theme, compact);
        render_speeds(frame, speeds, app, theme, compact);
        render_odometry(frame, odometry, app, theme, compact);
        render_faults(frame, faults, app, theme);
        // Full: the link table's two columns of IDs take 44; the motors table the rest.
        let link_width =
            if compact { Constraint::Percentage(45) } else { Constraint::Length(LINK_FULL_WIDTH) };
        let [motors, link] = Layout::horizontal([Constraint::Fill(1), link_width]).areas(bottom);
        render_motors(frame, motors, app, theme, compact);
        render_link(frame, link, app, theme, compact);

        let release_line = fit_words(&release_text(app), usize::from(release.width));
        frame.render_widget(Paragraph::new(Line::styled(release_line, theme.dim())), release);
        frame.render_widget(Paragraph::new(keys_line(keys.width, theme, app.arming)), keys);
        let text = message_line(app, theme, Some(usize::from(message.width)));
        frame.render_widget(Paragraph::new(text), message);
    }
    if app.prompt == Prompt::ConfirmClear {
        render_confirm(frame, area, app, theme);
    } else if app.prompt == Prompt::ConfirmArm {
        render_confirm_arm(frame, area, theme);
    } else if app.help {
        render_help(frame, area, app, theme);
    }
}

/// Bottom row height of the full layout: the link table's rows, within what the screen leaves once the
/// faults have their lines (the faults come first).
fn full_bottom_height(app: &App, area: Rect) -> u16 {
    let ids = app.shown.ids.len() as u16;
    let inside = usize::from(LINK_FULL_WIDTH - 2);
    let missing = not_reported_lines(app.shown.protocol, inside, Theme { color: false }).len() as u16;
    let link_lines = 4 + ids.div_ceil(2).max(1) + missing;
    let wanted = (link_lines + 2).clamp(6, 15);
    let body_width = usize::from(area.width.saturating_sub(2)).saturating_sub(SEVERITY_COLUMN + 1).max(1);
    let fault_lines: usize = app
        .faults()
        .iter()
        .map(|fault| wrap(&format!("{}: {}", fault_name(fault), fault.info.action), body_width).len())
        .sum();
    let faults = (fault_lines.max(3) as u16).saturating_add(2);
    // header, alert, top, faults, footer.
    let room = area.height.saturating_sub(1 + 1 + 8 + 3).saturating_sub(faults);
    wanted.min(room).max(6)
}

fn block(title: impl Into<String>, theme: Theme) -> Block<'static> {
    Block::bordered().title(Span::styled(format!(" {} ", title.into()), theme.bold()))
}

fn separator(theme: Theme) -> Span<'static> {
    Span::styled(" · ", theme.dim())
}

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
fn header_line(app: &App, theme: Theme, width: u16) -> Line<'static> {
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

/// `/home/me/lo…/session.log`: the start and the end of `text` (a path's file name), in `width` characters.
fn middle_ellipsis(text: &str, width: usize) -> String {
    let count = text.chars().count();
    if count <= width {
        return text.to_string();
    }
    let keep = width.saturating_sub(1);
    // More of the end: a file's name says more than the start of its directory.
    let tail = (keep * 2).div_ceil(3);
    let head = keep - tail;
    let mut out: String = text.chars().take(head).collect();
    out.push('…');
    out.extend(text.chars().skip(count - tail));
    out
}

/// `text` within `width` characters, cut after a whole word with `…` when it is longer (a word longer than
/// the line is cut). Words end at a space or at a comma of a list (`overcurrent,overheat`).
fn fit_words(text: &str, width: usize) -> String {
    let chars: Vec<char> = text.chars().collect();
    if chars.len() <= width {
        return text.to_string();
    }
    let keep = width.saturating_sub(1);
    let separator = |c: char| c == ' ' || c == ',';
    // The longest start that ends where a word does: the next character separates.
    let end = (1..=keep).rev().find(|&end| separator(chars[end])).unwrap_or(keep);
    let mut out: String = chars[..end].iter().collect();
    out.truncate(out.trim_end_matches(separator).len());
    out.push('…');
    out
}

/// `3.0 s`, `42 s`.
fn age_text(deciseconds: u64) -> String {
    if deciseconds < 600 {
        format!("{}.{} s", deciseconds / 10, deciseconds % 10)
    } else {
        format!("{} s", deciseconds / 10)
    }
}

/// Said when the source ended on its own. Only a replay stays on screen after its end (the dashboard closes
/// when any other link ends), so this is always a replay.
const REPLAY_ENDED: &str = "replay ended";

/// The alert line: the words and the colour of the alert that wins ([`App::alert`]).
fn alert_text(app: &App, width: usize) -> (Tone, String) {
    match app.alert() {
        Alert::ReplayEnded => (
            Tone::Info,
            format!(
                "[info] {REPLAY_ENDED}: the log's last values stay on screen; {} quits",
                keys::key_name(keys::Action::Quit)
            ),
        ),
        Alert::LinkFailed(error) => (Tone::Alarm, format!("[fault] LINK FAILED: {error}")),
        Alert::Stale { deciseconds } => (
            Tone::Alarm,
            format!(
                "[fault] STALE: no status for {}: every value on screen is old (robot off? cable? bus?)",
                age_text(deciseconds)
            ),
        ),
        Alert::NothingReceived => (
            Tone::Warning,
            format!(
                "[warning] nothing received on {} yet: is the robot on, is this the right link?",
                app.shown.link_name
            ),
        ),
        Alert::NoSystemStatus => (
            Tone::Warning,
            "[warning] frames arrive but no system status yet: is this a TRACER, is --protocol right?"
                .to_string(),
        ),
        Alert::EStop { reason } => (Tone::Alarm, format!("[fault] E-STOP: {reason}")),
        Alert::BlockingFaults(faults) => {
            let names: Vec<String> = faults.iter().map(fault_name).collect();
            (Tone::Alarm, names_within("[fault] CANNOT DRIVE, see Faults: ", &names, width))
        }
        Alert::CannotDrive { reason } => (Tone::Alarm, format!("[fault] CANNOT DRIVE: {reason}")),
        Alert::NotInCommandMode { wire, mode } => (
            Tone::Warning,
            format!(
                "[warning] not in command mode (mode {}): press {} to enable it",
                ControlMode::describe(wire, mode),
                keys::key_name(keys::Action::CommandMode)
            ),
        ),
        Alert::Warnings => {
            (Tone::Warning, "[warning] ready to drive, with warnings: see Faults and Battery".to_string())
        }
        Alert::Ready(Arming::Armed) => (Tone::Ok, "ready to drive: command mode, no faults".to_string()),
        Alert::Ready(Arming::Watching) => {
            let arm = keys::key_name(keys::Action::Arm);
            (Tone::Ok, format!("watching: nothing is sent; an arrow key or {arm} asks to arm driving"))
        }
        Alert::Ready(Arming::WatchOnly) => (Tone::Ok, "watch only: nothing is sent to the robot".to_string()),
    }
}

/// `prefix` and as many whole `names` as fit `width`, then `+N`: `... driver_overheat_protection +1`.
fn names_within(prefix: &str, names: &[String], width: usize) -> String {
    let Some(first) = names.first() else { return prefix.to_string() };
    let mut text = format!("{prefix}{first}");
    for (index, name) in names.iter().enumerate().skip(1) {
        let next = format!("{text}, {name}");
        let after = names.len() - index - 1;
        let suffix = if after > 0 { format!(" +{after}").len() } else { 0 };
        if next.chars().count() + suffix > width {
            return format!("{text} +{}", names.len() - index);
        }
        text = next;
    }
    text
}

fn fault_name(fault: &FaultLine) -> String {
    match fault.motor {
        Some(motor) => format!("M{motor} {}", fault.info.name),
        None => fault.info.name.to_string(),
    }
}

fn severity_tag(severity: Severity) -> String {
    format!("[{}]", severity.as_str())
}

fn render_battery(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let block = block("Battery", theme);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let Some(system) = app.shown.system else {
        frame.render_widget(Paragraph::new(Line::styled("no status yet", theme.dim())), inner);
        return;
    };
    let decivolts = system.decivolts;
    let zone = BatteryZone::of(decivolts);
    let (zone_text, gauge_label) = match zone {
        BatteryZone::Ok => ("ok".to_string(), "OK"),
        BatteryZone::Warning => (format!("[warning] <= {}", volts(BATTERY_WARNING_DV)), "WARNING"),
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
            volts_bare(BATTERY_WARNING_DV),
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
        let text = match (recent.iter().min(), recent.iter().max()) {
            (Some(low), Some(high)) => {
                format!("last {} s: {}-{}", recent.len(), volts_bare(*low), volts(*high))
            }
            _ => "history: none yet".to_string(),
        };
        frame.render_widget(Paragraph::new(Line::styled(text, theme.dim())), caption);
    }
}

/// `25.9 V`
fn volts(decivolts: u16) -> String {
    format!("{} V", volts_bare(decivolts))
}

fn volts_bare(decivolts: u16) -> String {
    format!("{}.{}", decivolts / 10, decivolts % 10)
}

fn render_speeds(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
    let teleop = &app.teleop;
    // The scale is known once the glue has set the teleop view (it always sets the release mode).
    let title = if teleop.release_mode.is_empty() {
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
    let held: String = teleop
        .held
        .iter()
        .map(|key| match *key {
            "up" => "↑",
            "down" => "↓",
            "left" => "←",
            "right" => "→",
            other => other,
        })
        .collect();
    let mm = |value: i16| speed_text(f64::from(value) / 1000.0);
    let mut lines = vec![
        Line::styled(row("", "m/s".into(), "rad/s".into()), theme.dim()),
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

/// Why the odometry panel is empty: not yet, or never on a wire that does not report it (RS232, V1).
fn no_odometry_text(protocol: Protocol) -> String {
    let Some(wire) = protocol.wire() else { return "no odometry yet".to_string() };
    match catalog::identifier_of(MessageKind::Odometry, wire) {
        Some(id) => format!("no odometry ({id}) yet"),
        None => format!("{} reports no odometry", protocol.label()),
    }
}

fn render_odometry(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
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
            let name = match light_mode_name(mode) {
                Some("custom") => format!("custom {brightness} %"),
                Some(name) => name.to_string(),
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

fn render_faults(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
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

/// Word wrap to `width` columns (the texts are ASCII); words longer than a line are split.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut rows = Vec::new();
    let mut current = String::new();
    for word in text.split(' ') {
        let mut word = word.to_string();
        loop {
            let needed = if current.is_empty() { word.len() } else { current.len() + 1 + word.len() };
            if needed <= width {
                if !current.is_empty() {
                    current.push(' ');
                }
                current.push_str(&word);
                break;
            }
            if current.is_empty() {
                let rest = word.split_off(width.min(word.len()));
                rows.push(std::mem::replace(&mut word, rest));
                if word.is_empty() {
                    break;
                }
            } else {
                rows.push(std::mem::take(&mut current));
            }
        }
    }
    if !current.is_empty() || rows.is_empty() {
        rows.push(current);
    }
    rows
}

fn truncate(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let mut out: String = text.chars().take(width.saturating_sub(1)).collect();
    out.push('…');
    out
}

fn render_motors(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
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

fn render_link(frame: &mut Frame, area: Rect, app: &App, theme: Theme, compact: bool) {
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
    let feedback = shown.ids.iter().filter(|id| super::app::stale_after(id.id).is_some()).count();
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
fn not_reported(protocol: Protocol) -> Vec<&'static str> {
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
fn not_reported_lines(protocol: Protocol, width: usize, theme: Theme) -> Vec<Line<'static>> {
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

fn release_text(app: &App) -> String {
    if app.teleop.release_mode.is_empty() {
        "key release: -".to_string()
    } else {
        app.teleop.release_mode.clone()
    }
}

/// The key summary from the key table, long labels or short ones to fit. Still too wide, whole entries go,
/// never part of one: the spare ones first (lowest rank first), then the others from the end of the table,
/// then help; quitting stays.
fn keys_line(width: u16, theme: Theme, arming: Arming) -> Line<'static> {
    let width = usize::from(width);
    let entries = keys::footer_entries(arming);
    let length = |keys: &[(&str, &str)]| -> usize {
        keys.iter().map(|(k, d)| k.chars().count() + 1 + d.chars().count()).sum::<usize>()
            + 2 * keys.len().saturating_sub(1)
    };
    let long: Vec<(&str, &str)> = entries.iter().map(|entry| (entry.0, entry.1)).collect();
    let labelled: Vec<(&str, &str)> =
        if length(&long) <= width { long } else { entries.iter().map(|entry| (entry.0, entry.2)).collect() };
    let mut kept = vec![true; labelled.len()];
    let mut order: Vec<usize> = (0..entries.len()).collect();
    order.sort_by_key(|&index| footer_drop_rank(entries[index].0, entries[index].3, index));
    for index in order {
        let shown: Vec<(&str, &str)> =
            labelled.iter().zip(&kept).filter(|(_, keep)| **keep).map(|(entry, _)| *entry).collect();
        if length(&shown) <= width || footer_action(entries[index].0, keys::Action::Quit) {
            break;
        }
        kept[index] = false;
    }
    let mut spans = Vec::new();
    for (key, description) in labelled.iter().zip(&kept).filter(|(_, keep)| **keep).map(|(entry, _)| *entry) {
        if !spans.is_empty() {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(key, theme.key()));
        spans.push(Span::raw(format!(" {description}")));
    }
    Line::from(spans)
}

/// The order in which footer entries give way, lowest first: spare entries by rank, then the others from
/// the end of the table, then help, then quit.
fn footer_drop_rank(keys: &str, spare: Option<u8>, index: usize) -> (u8, usize) {
    match spare {
        Some(rank) => (0, usize::from(rank)),
        None if footer_action(keys, keys::Action::Quit) => (3, 0),
        None if footer_action(keys, keys::Action::Help) => (2, 0),
        None => (1, usize::MAX - index),
    }
}

/// Whether the footer entry shown as `keys` belongs to the row of the key table that does `action`.
fn footer_action(keys: &str, action: keys::Action) -> bool {
    keys::BINDINGS.iter().any(|row| {
        row.footer.is_some_and(|footer| footer.keys == keys)
            && row.keys.iter().any(|bind| bind.action == action)
    })
}

/// The footer: a recording that loses frames (it stays: the exit status will say so too), then the message.
/// Within `width` when given, the texts cut after whole words; `None` where the lines wrap.
fn message_line(app: &App, theme: Theme, width: Option<usize>) -> Line<'static> {
    let mut room = width.unwrap_or(usize::MAX);
    let fit = |text: String, room: &mut usize| {
        let text = if *room == usize::MAX { text } else { fit_words(&text, *room) };
        *room = room.saturating_sub(Span::raw(text.as_str()).width());
        text
    };
    let mut spans = Vec::new();
    if let Some(loss) = &app.recording_loss {
        let text = fit(format!("[fault] RECORDING LOST {} frames: {}", loss.frames, loss.reason), &mut room);
        spans.push(Span::styled(text, theme.alarm()));
    }
    if let Some((text, _)) = &app.message {
        if !spans.is_empty() {
            spans.push(separator(theme));
            room = room.saturating_sub(3);
        }
        spans.push(Span::styled("> ", theme.dim()));
        room = room.saturating_sub(2);
        if room > 0 {
            spans.push(Span::styled(fit(text.clone(), &mut room), theme.bold()));
        }
    }
    Line::from(spans)
}

/// Under 60x20: the essentials as text.
fn render_small(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
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

/// A box in the middle of `area`, at most `width` x `height`.
fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let width = width.min(area.width);
    let height = height.min(area.height);
    Rect { x: area.x + (area.width - width) / 2, y: area.y + (area.height - height) / 2, width, height }
}

/// The help overlay: every row of the key table, wrapped under its keys, then how releases and arming work.
/// On a short screen the closing notes go first, then each row keeps one line, then the rows in the middle
/// give way to a count: the row that quits always stays.
fn render_help(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
    let width = 70.min(area.width.saturating_sub(4)).max(20);
    let inner = usize::from(width.saturating_sub(2));
    let room = usize::from(area.height.saturating_sub(2));
    let text_width = inner.saturating_sub(keys::KEY_COLUMN).max(1);
    let rows: Vec<(&str, String, bool)> = keys::BINDINGS
        .iter()
        .map(|row| {
            let mut what = row.help.to_string();
            if row.keys.iter().any(|bind| bind.action == keys::Action::Faster) {
                what.push_str(&format!(" (now {} %)", scale_percent(app.teleop.scale)));
            }
            (row.shown, what, row.keys.iter().any(|bind| bind.action == keys::Action::Quit))
        })
        .collect();
    let row_lines = |shown: &str, what: &str, wrapped: bool| -> Vec<Line<'static>> {
        let texts = if wrapped { wrap(what, text_width) } else { vec![fit_words(what, text_width)] };
        texts
            .into_iter()
            .enumerate()
            .map(|(index, text)| {
                let keys = if index == 0 { shown } else { "" };
                Line::from(vec![
                    Span::styled(format!("{keys:<width$}", width = keys::KEY_COLUMN), theme.key()),
                    Span::raw(text),
                ])
            })
            .collect()
    };
    let mut lines: Vec<Line> =
        rows.iter().flat_map(|(shown, what, _)| row_lines(shown, what, true)).collect();
    let notes: Vec<Line> = [release_text(app), HELP_NOTE.to_string()]
        .iter()
        .flat_map(|text| wrap(text, inner))
        .map(|text| Line::styled(text, theme.dim()))
        .collect();
    if lines.len() + 1 + notes.len() <= room {
        lines.push(Line::raw(""));
        lines.extend(notes);
    } else if lines.len() > room {
        lines = rows.iter().flat_map(|(shown, what, _)| row_lines(shown, what, false)).collect();
        if lines.len() > room {
            // The first rows, a count of the others, and the way out.
            let keep = room.saturating_sub(2);
            let quit = rows.iter().position(|row| row.2).unwrap_or(rows.len().saturating_sub(1));
            let first: Vec<usize> = (0..rows.len()).filter(|&index| index != quit).take(keep).collect();
            let mut shown: Vec<Line> = first.iter().map(|&index| lines[index].clone()).collect();
            let more = rows.len() - first.len() - 1;
            shown.push(Line::styled(format!("... {more} more: a taller terminal shows them"), theme.dim()));
            shown.extend(lines.get(quit).cloned());
            lines = shown;
        }
    }
    let height = (lines.len() as u16 + 2).min(area.height);
    let popup = centered(area, width, height);
    frame.render_widget(Clear, popup);
    frame.render_widget(
        Paragraph::new(lines)
            .block(block(format!("Keys · {} closes", keys::key_name(keys::Action::Help)), theme)),
        popup,
    );
}

/// The help overlay's closing note.
const HELP_NOTE: &str =
    "Opens WATCHING: nothing is sent until armed. Releasing a key brakes (--decel); an E-stop, \
                         a latched fault or RC override sends zero until a fresh press. Every way out sends \
                         zero-velocity frames first.";

fn render_confirm_arm(frame: &mut Frame, area: Rect, theme: Theme) {
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

/// A question in a box in the middle of the screen, over what is there. The answer (the keys that
/// answer it) takes the box's last rows whole; the explanation gets what is left above it and is cut
/// first when the screen is small.
fn dialog(
    frame: &mut Frame,
    area: Rect,
    explanation: Vec<Line<'static>>,
    answer: Line<'static>,
    width: u16,
    block: Block<'static>,
) {
    let width = width.min(area.width.saturating_sub(4)).max(20).min(area.width);
    let inner = usize::from(width.saturating_sub(2)).max(1);
    let answer_rows = wrapped_rows(&answer, inner);
    let explanation_rows: u16 = explanation.iter().map(|line| wrapped_rows(line, inner)).sum();
    let height = (explanation_rows + answer_rows + 2).min(area.height);
    let popup = centered(area, width, height);
    frame.render_widget(Clear, popup);
    let inside = block.inner(popup);
    frame.render_widget(block, popup);
    let [text, keys] =
        Layout::vertical([Constraint::Fill(1), Constraint::Length(answer_rows.min(inside.height))])
            .areas(inside);
    frame.render_widget(Paragraph::new(explanation).wrap(Wrap { trim: false }), text);
    frame.render_widget(Paragraph::new(answer).wrap(Wrap { trim: false }), keys);
}

/// How many rows `line` takes wrapped at whole words to `width` (a word longer than the width is split).
fn wrapped_rows(line: &Line, width: usize) -> u16 {
    let text: String = line.spans.iter().map(|span| span.content.as_ref()).collect();
    let mut rows = 1u16;
    let mut used = 0usize;
    for word in text.split(' ') {
        let length = word.chars().count();
        let needed = if used == 0 { length } else { used + 1 + length };
        if needed <= width {
            used = needed;
        } else if used == 0 {
            rows += u16::try_from((length.max(1) - 1) / width).unwrap_or(u16::MAX);
            used = length % width;
        } else {
            rows =
                rows.saturating_add(1 + u16::try_from(length.saturating_sub(1) / width).unwrap_or(u16::MAX));
            used = if length > width { length % width } else { length };
        }
    }
    rows
}

fn render_confirm(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
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

#[cfg(test)]
mod tests {
    use std::time::{Duration, Instant};

    use ratatui::backend::TestBackend;
    use ratatui::buffer::Buffer;
    use ratatui::Terminal;

    use super::*;
    use crate::control::{Limits, SenderStats};
    use crate::dashboard::app::{Snapshot, TeleopView};
    use crate::protocol::detect::ProtocolDetector;
    use crate::protocol::message::{
        Lights, MotionCommand, MotionState, MotorDriverState, MotorHighSpeed, MotorLowSpeed, Odometry,
        SystemState,
    };
    use crate::protocol::FrameId;
    use crate::session::RobotStatus;

    /// The buffer as text, one line per row, trailing spaces trimmed.
    fn text(buffer: &Buffer) -> String {
        let area = buffer.area;
        let mut out = String::new();
        for y in area.top()..area.bottom() {
            let mut line = String::new();
            for x in area.left()..area.right() {
                line.push_str(buffer[(x, y)].symbol());
            }
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }

    fn draw(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
        let mut terminal = Terminal::new(TestBackend::new(width, height)).unwrap();
        terminal.draw(|frame| render(frame, app)).unwrap();
        terminal
    }

    fn screen(app: &App, width: u16, height: u16) -> String {
        text(draw(app, width, height).backend().buffer())
    }

    /// A V2 robot's status at `now`: 25.9 V, command mode, both motors at `rpm`.
    fn v2_status(now: Instant, linear_mm_s: i16, rpm: i16) -> RobotStatus {
        let system = SystemState {
            vehicle_state: 0,
            control_mode: 1,
            battery_decivolts: 259,
            fault_code: 0,
            count: 7,
        };
        let mut status = RobotStatus {
            system: Some((now, system, Wire::CanV2)),
            motion: Some((now, MotionState { linear_mm_s, angular_mrad_s: 0, count: 0 })),
            lights: Some((now, Lights { enable: 1, front_mode: 1, ..Lights::default() })),
            odometry: Some(Odometry::default()),
            detector: ProtocolDetector { v1_frames: 0, v2_frames: 1 },
            ..RobotStatus::default()
        };
        for motor in 0..2 {
            status.motor_high[motor] = Some(MotorHighSpeed {
                motor: motor as u8 + 1,
                rpm,
                current_deciamps: if rpm == 0 { 0 } else { 6 },
                pulse_count: 0,
            });
            status.motor_low[motor] = Some(MotorLowSpeed {
                motor: motor as u8 + 1,
                driver_decivolts: 259,
                driver_temperature: 27,
                motor_temperature: 27,
                driver_state: 0,
            });
        }
        status
    }

    /// Feeds `seconds` of 50 ms updates: V2 feedback at its rates (0x261/0x262 at 10 Hz), the wheels at
    /// `linear_mm_s`, the battery from `volts[second]`. `edit` changes the status before each update.
    fn run(
        app: &mut App,
        base: Instant,
        seconds: u64,
        linear_mm_s: i16,
        edit: &dyn Fn(&mut RobotStatus, u64),
    ) {
        let rpm = (f64::from(linear_mm_s) / 1000.0 / (std::f64::consts::PI * 0.15) * 60.0).round() as i16;
        let sent = MotionCommand { linear_mm_s, angular_mrad_s: 0 };
        for tick in 0..=seconds * 20 {
            let now = base + Duration::from_millis(50 * tick);
            let mut status = v2_status(now, linear_mm_s, rpm);
            let fast = tick * 5 / 2;
            let slow = tick / 2;
            status.id_counts = [0x211, 0x221, 0x231, 0x251, 0x252, 0x311]
                .iter()
                .map(|id| (FrameId::Standard(*id), fast))
                .chain([(FrameId::Standard(0x261), slow), (FrameId::Standard(0x262), slow)])
                .collect();
            status.id_counts.sort_unstable();
            status.frames = 6 * fast + 2 * slow;
            let travelled = (i64::from(linear_mm_s) * 50 * tick as i64 / 1000) as i32;
            status.odometry = Some(Odometry { left_mm: 120_000 + travelled, right_mm: 120_400 + travelled });
            edit(&mut status, tick);
            app.update(&Snapshot {
                status: &status,
                sender: SenderStats { sent, frames: tick, ..SenderStats::default() },
                link_name: "can0",
                now,
            });
        }
    }

    fn kitty(scale: f64, held: Vec<&'static str>, requested: (f64, f64)) -> TeleopView {
        TeleopView {
            release_mode: "key release: terminal events (kitty protocol)".to_string(),
            scale,
            held,
            requested,
        }
    }

    /// Driving straight at 0.3 m/s for 30 s on 25.9 V (26.0 V for the first 10 s), no faults.
    fn driving() -> App {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        run(&mut app, base, 30, 300, &|status, tick| {
            if tick < 200 {
                status.system.as_mut().unwrap().1.battery_decivolts = 260;
            }
        });
        app.set_teleop(kitty(0.6, vec!["up"], (0.3, 0.0)));
        app.set_arming(Arming::Armed);
        app
    }

    fn faulted() -> App {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        run(&mut app, base, 3, 0, &|status, _| {
            // CAN V1 system bits (latched driver over-temperature protection + its warning), with the
            // driver-state bytes of 0x261/0x262 as a V2 robot reports them.
            let system = &mut status.system.as_mut().unwrap();
            system.1.vehicle_state = 2;
            system.1.fault_code = 0x0040 | 0x0200;
            system.2 = Wire::CanV1;
            status.detector = ProtocolDetector { v1_frames: 1, v2_frames: 0 };
            status.motor_low[0].as_mut().unwrap().driver_state = 0x08 | 0x04;
            status.motor_low[0].as_mut().unwrap().driver_temperature = 68;
            status.motor_low[1].as_mut().unwrap().driver_state = 0x10;
        });
        app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
        app
    }

    fn assert_contains(screen: &str, needles: &[&str]) {
        for needle in needles {
            assert!(screen.contains(needle), "{needle:?} missing from:\n{screen}");
        }
    }

    /// No row wider than the terminal (the buffer guarantees it) and nothing drawn past the frame.
    fn rows(screen: &str) -> Vec<&str> {
        screen.lines().collect()
    }

    #[test]
    fn normal_driving_120x40() {
        let app = driving();
        let screen = screen(&app, 120, 40);
        assert_contains(
            &screen,
            &[
                "tracerctl · ARMED · can0 · CAN V2 · NORMAL · mode can · status <0.1 s",
                "ready to drive: command mode, no faults",
                "25.9 V  ok",
                "keys    +0.30   +0.00 ↑",
                "sent    +0.30   +0.00",
                "robot   +0.30   +0.00",
                "trip    9.00 m",
                "pose    x +9.00 y +0.00 m",
                "0x211 system    50/s",
                "0x261 driver 1  10/s",
                "stale: none",
                "key release: terminal events (kitty protocol)",
                "scale 60 %",
            ],
        );
        assert!(rows(&screen)[2..].iter().any(|row| row.contains("none")), "faults: none");
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn normal_driving_100x30() {
        let screen = screen(&driving(), 100, 30);
        assert_contains(
            &screen,
            &["NORMAL", "25.9 V  ok", "robot   +0.30", "Faults", "none", "0x311 odometry"],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn normal_driving_80x24_fits() {
        let screen = screen(&driving(), 80, 24);
        assert_contains(
            &screen,
            &[
                "NORMAL",
                "mode can",
                "25.9 V  ok",
                "keys    +0.30   +0.00 ↑",
                "robot   +0.30",
                "trip 9.00 m",
                "lights on",
                "none",
                "M1 +38",
                "stale: none",
                "211:50",
                "262:10",
                "key release: terminal events",
                "q quit",
            ],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn estop() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        run(&mut app, base, 2, 0, &|status, _| {
            let system = &mut status.system.as_mut().unwrap().1;
            system.vehicle_state = 1;
            system.control_mode = 0;
            for motor in status.motor_low.iter_mut() {
                motor.as_mut().unwrap().driver_state = 0x40;
            }
        });
        app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "E-STOP · mode standby",
                "[fault] E-STOP: the E-stop is pressed: release both E-stop buttons",
                "[info]",
                "M1 driver_disabled",
                "0x40 disabled",
            ],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn active_faults() {
        let app = faulted();
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "CAN V1 · EXCEPTION",
                "[fault] CANNOT DRIVE, see Faults: driver_overheat_protection",
                "[protection] driver_overheat_protection: stop, let the drivers cool",
                "[warning]",
                "driver_overheat_warning",
                "[fault]      M2 can_disconnected",
                "M1 driver_overcurrent",
                "0x0C overcurrent,overheat",
                "Faults (5)",
            ],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn active_faults_80x24_fits() {
        let screen = screen(&faulted(), 80, 24);
        assert_contains(
            &screen,
            &["EXCEPTION", "[protection] driver_overheat_protection", "[fault]", "[warning]"],
        );
        // Every fault still has its line, with its severity spelled.
        for name in [
            "driver_overheat_protection",
            "M2 can_disconnected",
            "driver_overheat_warning",
            "M1 driver_overcurrent",
            "M1 driver_overheat",
        ] {
            assert!(screen.contains(name), "{name} missing:\n{screen}");
        }
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn low_battery() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        run(&mut app, base, 20, 0, &|status, tick| {
            let system = &mut status.system.as_mut().unwrap().1;
            system.battery_decivolts = 223 - (tick / 200) as u16; // 22.3 V sagging to 22.1 V
            system.fault_code = 0x0200;
        });
        app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "22.1 V  [warning] <= 22.5 V",
                "WARNING",
                "[warning]    battery_undervoltage_warning: finish the task and charge soon",
                "last 21 s: 22.1-22.3 V",
            ],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn stale_link() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        // 5 s of traffic, then nothing for 3 s.
        run(&mut app, base, 5, 0, &|_, _| {});
        let mut status = v2_status(base + Duration::from_secs(5), 0, 0);
        status.odometry = Some(Odometry { left_mm: 120_000, right_mm: 120_400 });
        status.id_counts = [0x211, 0x221, 0x231, 0x251, 0x252, 0x311]
            .iter()
            .map(|id| (FrameId::Standard(*id), 250))
            .chain([(FrameId::Standard(0x261), 50), (FrameId::Standard(0x262), 50)])
            .collect();
        status.id_counts.sort_unstable();
        for tick in 1..=60 {
            let now = base + Duration::from_secs(5) + Duration::from_millis(50 * tick);
            app.update(&Snapshot { status: &status, sender: SenderStats::default(), link_name: "can0", now });
        }
        app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "NO STATUS FOR 3.0 s",
                "[fault] STALE: no status for 3.0 s: every value on screen is old",
                "STALE: all 8 feedback IDs, >= 3.0 s",
                "0x211 system   STALE",
            ],
        );
        insta::assert_snapshot!(screen);
    }

    // The snapshot has the ^Z row, which Windows (no job control) does not.
    #[cfg(unix)]
    #[test]
    fn help_overlay() {
        let mut app = driving();
        app.toggle_help();
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "Keys · ? closes",
                "drive forward / backward (linear speed)",
                "turn left / right (angular speed)",
                "held together: arcs (kitty protocol only)",
                "arcs ↖ ↗ ↙ ↘, also Home PgUp End PgDn",
                "Space  k  zero at once, no ramp",
                "speed scale up / down (now 60 %)",
                "cycle the lights",
                "clear faults (asks first)",
                "enable command mode",
                "q  ^C     stop the robot and quit",
            ],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn the_help_keeps_the_way_out_on_a_small_screen() {
        let mut app = driving();
        app.toggle_help();
        for (width, height) in [(60, 20), (80, 24), (60, 12)] {
            let screen = screen(&app, width, height);
            assert_contains(&screen, &["Keys · ? closes", "stop the robot and quit"]);
            if height < 20 {
                continue;
            }
            // The box's inside, as one text: every row's help is there whole (wrapped, never cut).
            let box_width = 70.min(width - 4);
            let left = usize::from((width - box_width) / 2) + 1;
            let inside: Vec<String> = screen
                .lines()
                .map(|line| line.chars().skip(left).take(usize::from(box_width) - 2).collect())
                .collect();
            let flat = inside.join(" ").split_whitespace().collect::<Vec<_>>().join(" ");
            for row in keys::BINDINGS {
                assert!(flat.contains(row.help), "{:?} at {width}x{height}:\n{screen}", row.help);
            }
        }
        assert_contains(
            &screen(&app, 60, 12),
            &["more: a taller terminal shows them", "q  ^C     stop the robot"],
        );
        assert_contains(&screen(&app, 80, 30), &["zero-velocity frames first."]);
    }

    #[test]
    fn clear_confirmation_prompt() {
        let mut app = faulted();
        app.ask_clear_confirmation();
        assert_eq!(app.prompt(), Prompt::ConfirmClear);
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "Clear faults?",
                "Send a fault clear to the robot (all latched faults)?",
                "[protection] driver_overheat_protection",
                "[fault] M2 can_disconnected",
                "y send the clear",
                "any other key cancel",
            ],
        );
        insta::assert_snapshot!(screen);
        app.cancel_prompt();
        assert!(!self::screen(&app, 100, 30).contains("Send a fault clear"));
    }

    #[test]
    fn recording_losses_stay_in_the_footer_beside_the_message() {
        let mut app = driving();
        let before = app.fingerprint();
        app.set_recording_loss(Some(crate::recorder::RecordLoss {
            frames: 1234,
            reason: "No space left on device (os error 28)".to_string(),
        }));
        assert_ne!(app.fingerprint(), before, "a loss redraws");
        app.set_message("lights: on".to_string(), Instant::now());
        let screen = screen(&app, 100, 30);
        let footer = rows(&screen).last().copied().unwrap_or_default().to_string();
        assert_eq!(
            footer.trim_end(),
            "[fault] RECORDING LOST 1234 frames: No space left on device (os error 28) · > lights: on"
        );
        assert!(screen_small(&app).contains("[fault] RECORDING LOST 1234 frames"));
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn message_and_nothing_received() {
        let base = Instant::now();
        let mut app = App::new("/dev/ttyUSB0", Limits::default(), false);
        app.update(&Snapshot {
            status: &RobotStatus::default(),
            sender: SenderStats::default(),
            link_name: "/dev/ttyUSB0",
            now: base,
        });
        app.set_message("lights: on".to_string(), base);
        let screen = screen(&app, 80, 24);
        assert_contains(
            &screen,
            &[
                "no status yet",
                "[warning] nothing received on /dev/ttyUSB0 yet",
                "> lights: on",
                "no frames yet",
            ],
        );
    }

    #[test]
    fn no_color_means_no_colour_and_color_repeats_the_words() {
        let mut app = faulted();
        let terminal = draw(&app, 100, 30);
        for cell in terminal.backend().buffer().content() {
            assert_eq!((cell.fg, cell.bg), (Color::Reset, Color::Reset), "{cell:?}");
        }
        app.color = true;
        let terminal = draw(&app, 100, 30);
        let buffer = terminal.backend().buffer();
        let screen = text(buffer);
        let row = screen.lines().position(|line| line.contains("[protection]")).unwrap();
        let column = screen.lines().nth(row).unwrap().find("[protection]").unwrap();
        // `find` counts bytes; the row is ASCII up to there apart from the border.
        let x = screen.lines().nth(row).unwrap()[..column].chars().count() as u16;
        assert_eq!(buffer[(x + 1, row as u16)].fg, Color::Red);
        assert!(buffer.content().iter().any(|cell| cell.fg == Color::Yellow), "warnings in yellow");
    }

    #[test]
    fn the_empty_odometry_panel_says_whether_odometry_can_come() {
        // Was "no odometry (0x311) yet" on every wire, for ever on RS232 and V1.
        assert_eq!(no_odometry_text(Protocol::CanV2), "no odometry (0x311) yet");
        assert_eq!(no_odometry_text(Protocol::Serial), "RS232 reports no odometry");
        assert_eq!(no_odometry_text(Protocol::CanV1), "CAN V1 reports no odometry");
        assert_eq!(no_odometry_text(Protocol::Unknown), "no odometry yet");
    }

    #[test]
    fn watching_arming_prompt_and_watch_only_are_shown() {
        let mut app = driving();
        app.set_arming(Arming::Watching);
        let shown = screen(&app, 100, 30);
        assert_contains(&shown, &["tracerctl · WATCHING · can0", "watching: nothing is sent", "a arm"]);
        app.ask_arm_confirmation();
        assert_eq!(app.prompt(), Prompt::ConfirmArm);
        let shown = screen(&app, 100, 30);
        assert_contains(&shown, &["Arm driving?", "y arm", "keep watching", "Until then nothing is sent."]);
        insta::assert_snapshot!(shown);
        let mut app = driving();
        app.set_arming(Arming::WatchOnly);
        let shown = screen(&app, 100, 30);
        assert_contains(&shown, &["WATCH ONLY", "watch only: nothing is sent to the robot"]);
        assert!(!shown.contains("a arm"), "no arming key when it cannot arm:\n{shown}");
        // The small layout keeps the state too.
        assert_contains(&screen_small(&app), &["WATCH ONLY"]);
    }

    #[test]
    fn the_keys_that_answer_a_prompt_are_never_cut() {
        // At 60x20 the arm box used to lose its last line, the only one that says how to answer.
        let mut arm = driving();
        arm.set_arming(Arming::Watching);
        arm.ask_arm_confirmation();
        let mut clear = driving();
        clear.ask_clear_confirmation();
        for width in (24..=121).step_by(3) {
            for height in (6..=40).step_by(2) {
                let shown = screen(&arm, width, height);
                assert_contains(&shown, &["y arm", "any other", "watching"]);
                let shown = screen(&clear, width, height);
                assert_contains(&shown, &["y send", "stop", "cancel"]);
            }
        }
        // Where there is room, the explanation is whole too.
        assert_contains(&screen(&arm, 100, 30), &["Until then nothing is sent."]);
    }

    #[test]
    fn wrapped_rows_counts_as_the_paragraph_wraps() {
        let rows = |text: &str, width| wrapped_rows(&Line::raw(text.to_string()), width);
        assert_eq!(rows("y arm   any other key keep watching", 40), 1);
        assert_eq!(rows("y arm   any other key keep watching", 20), 2);
        assert_eq!(rows("abcdefghij", 4), 3);
        assert_eq!(rows("", 10), 1);
    }

    fn screen_small(app: &App) -> String {
        screen(app, 50, 16)
    }

    #[test]
    fn every_size_draws_without_panicking() {
        let mut app = faulted();
        app.set_message("fault clear sent (0x441 all): watch the faults panel".to_string(), Instant::now());
        for (width, height) in [
            (1, 1),
            (20, 5),
            (59, 19),
            (60, 20),
            (79, 23),
            (80, 24),
            (99, 29),
            (100, 30),
            (120, 40),
            (250, 80),
        ] {
            let screen = screen(&app, width, height);
            // The header gives way from its least needed part: the arming state stays.
            assert!(width < 20 || screen.contains("WATCHING"), "{width}x{height}:\n{screen}");
            app.toggle_help();
            let _ = self::screen(&app, width, height);
            app.toggle_help();
            app.ask_clear_confirmation();
            let _ = self::screen(&app, width, height);
            app.cancel_prompt();
        }
        let small = screen(&app, 50, 15);
        assert_contains(&small, &["60x20 or larger shows the panels", "EXCEPTION"]);
    }

    /// Driving as [`driving`] does, with 2 [info] driver bits (standby-like) and one [warning] bit.
    fn driving_with_info_and_a_warning() -> App {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        run(&mut app, base, 3, 300, &|status, _| {
            status.system.as_mut().unwrap().1.fault_code = 0x0200;
            for motor in status.motor_low.iter_mut() {
                motor.as_mut().unwrap().driver_state = 0x40;
            }
        });
        app.set_teleop(kitty(0.6, vec![], (0.3, 0.0)));
        app.set_arming(Arming::Armed);
        app
    }

    /// The safety facts every size from the panels' minimum shows: arming, both speeds with units, the faults,
    /// the battery, how to quit.
    fn assert_safety_facts(screen: &str, size: (u16, u16)) {
        let (width, height) = size;
        let context = format!("{width}x{height}:\n{screen}");
        assert!(screen.contains("ARMED"), "arming state missing at {context}");
        assert!(screen.contains("m/s") && screen.contains("rad/s"), "speed units missing at {context}");
        // The speeds panel's row: what follows the label up to the panel's border.
        let row = |label: &str| {
            screen.lines().find_map(|line| {
                let after = line.split(&format!("│{label} ")).nth(1)?;
                Some(after.split('│').next().unwrap_or_default().split_whitespace().collect::<Vec<_>>())
            })
        };
        for label in ["sent", "robot"] {
            let values = row(label).unwrap_or_else(|| panic!("no {label} row at {context}"));
            assert_eq!(values, ["+0.30", "+0.00"], "{label} at {context}");
        }
        assert!(screen.contains("Faults (1)"), "the fault count (info not counted) at {context}");
        assert!(screen.contains("25.9 V"), "battery missing at {context}");
        let footer = screen.lines().rev().find(|line| line.contains("quit")).unwrap_or_default();
        assert!(footer.contains("q quit") && footer.contains("? help"), "keys at {context}");
        assert!(footer.trim_end().ends_with("q quit"), "the footer ends on a whole entry at {context}");
    }

    #[test]
    fn every_size_from_the_minimum_shows_the_safety_facts() {
        let app = driving_with_info_and_a_warning();
        let mut sizes = 0;
        for width in (MIN_PANELS.0..=120).step_by(3).chain([120]) {
            for height in (MIN_PANELS.1..=40).step_by(2).chain([40]) {
                assert_safety_facts(&screen(&app, width, height), (width, height));
                sizes += 1;
            }
        }
        assert!(sizes > 200, "{sizes} sizes");
    }

    #[test]
    fn safety_facts_60x20() {
        let screen = screen(&driving_with_info_and_a_warning(), 60, 20);
        assert_safety_facts(&screen, (60, 20));
        assert_contains(
            &screen,
            &["robot +0.30  +0.00", "ARMED · can0 · CAN V2 · NORMAL · mode can · status <0.1 s"],
        );
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn safety_facts_80x24() {
        let screen = screen(&driving_with_info_and_a_warning(), 80, 24);
        assert_safety_facts(&screen, (80, 24));
        assert_contains(&screen, &["robot   +0.30   +0.00", "[info]       M1 driver_disabled"]);
        insta::assert_snapshot!(screen);
    }

    #[test]
    fn safety_facts_100x30() {
        let screen = screen(&driving_with_info_and_a_warning(), 100, 30);
        assert_safety_facts(&screen, (100, 30));
        assert_contains(
            &screen,
            &["[warning]    battery_undervoltage_warning", "[info]       M2 driver_disabled"],
        );
        insta::assert_snapshot!(screen);
    }

    /// The footer's entries as drawn at `width`, split on the two spaces between entries.
    fn footer_at(width: u16, arming: Arming) -> Vec<String> {
        let line = keys_line(width, Theme { color: false }, arming);
        let text: String = line.spans.iter().map(|span| span.content.as_ref()).collect();
        assert!(Line::raw(text.clone()).width() <= usize::from(width).max(6), "{width}: {text:?}");
        text.split("  ").map(str::to_string).collect()
    }

    #[test]
    fn the_footer_drops_whole_entries_and_keeps_help_and_quit_last() {
        let every: Vec<String> = keys::footer_entries(Arming::Watching)
            .iter()
            .flat_map(|entry| [format!("{} {}", entry.0, entry.1), format!("{} {}", entry.0, entry.2)])
            .collect();
        for width in 6..=140 {
            let entries = footer_at(width, Arming::Watching);
            for entry in &entries {
                assert!(every.contains(entry), "{width}: {entry:?} is not a whole entry of the table");
            }
            assert_eq!(entries.last().map(String::as_str), Some("q quit"), "{width}: {entries:?}");
            if width >= 14 {
                assert!(entries.contains(&"? help".to_string()), "{width}: {entries:?}");
            }
        }
        assert_eq!(footer_at(14, Arming::Watching), ["? help", "q quit"]);
        assert_eq!(footer_at(13, Arming::Watching), ["q quit"]);
        assert_eq!(footer_at(6, Arming::Watching), ["q quit"]);
        // Whatever rows the table has: the spare entries go first, then the others from the end, in the
        // table's order otherwise.
        let kept: Vec<String> = keys::footer_entries(Arming::Watching)
            .iter()
            .filter(|entry| entry.3.is_none())
            .map(|entry| format!("{} {}", entry.0, entry.2))
            .collect();
        let width = kept.iter().map(|entry| entry.chars().count()).sum::<usize>() + 2 * (kept.len() - 1);
        assert_eq!(footer_at(width as u16, Arming::Watching), kept);
        let mut fewer = kept.clone();
        fewer.remove(kept.len() - 3);
        assert_eq!(footer_at(width as u16 - 1, Arming::Watching), fewer, "the last of the others goes first");
        assert_eq!(kept[..2], ["↑↓←→ drive", "Space stop"]);
    }

    #[test]
    fn a_long_replay_path_loses_its_middle_never_the_status() {
        let mut app = driving();
        let path = format!("/home/operator/{}/field-test-2026-11-24/session.log", "logs/".repeat(20));
        app.shown.link_name.clone_from(&path);
        for width in [60, 80, 100, 120] {
            let screen = screen(&app, width, 30);
            let header = screen.lines().next().unwrap_or_default();
            assert!(header.ends_with("NORMAL · mode can · status <0.1 s"), "{width}: {header}");
            assert!(header.contains("ARMED"), "{width}: {header}");
            if width >= 80 {
                assert!(header.contains("…") && header.contains("session.log"), "{width}: {header}");
            }
        }
        assert_eq!(middle_ellipsis("/home/operator/session.log", 12), "/ho…sion.log");
        assert_eq!(middle_ellipsis("can0", 12), "can0");
        assert_eq!(fit_words("press e to enable it", 15), "press e to…");
        assert_eq!(fit_words("press e to enable it", 20), "press e to enable it");
        let names = ["a_fault".to_string(), "M2 b_fault".to_string(), "c_fault".to_string()];
        assert_eq!(names_within("see: ", &names, 80), "see: a_fault, M2 b_fault, c_fault");
        assert_eq!(names_within("see: ", &names, 26), "see: a_fault +2");
        assert_eq!(names_within("see: ", &names, 27), "see: a_fault, M2 b_fault +1");
    }

    #[test]
    fn the_end_of_a_replay_is_info_and_keeps_the_last_values() {
        let base = Instant::now();
        let mut app = App::new("session.log", Limits::default(), false);
        run(&mut app, base, 3, 300, &|_, _| {});
        let end = base + Duration::from_secs(3);
        let mut status = v2_status(end, 300, 38);
        status.link_error = Some("end of the replayed log".to_string());
        status.link_ended = true;
        // Ten seconds after the end: nothing turns stale, the rates stay.
        for tick in 0..=200 {
            let now = end + Duration::from_millis(50 * tick);
            app.update(&Snapshot {
                status: &status,
                sender: SenderStats::default(),
                link_name: "session.log",
                now,
            });
        }
        app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "NORMAL · mode can · replay ended",
                "[info] replay ended: the log's last values stay on screen; q quits",
                "robot   +0.30   +0.00",
                "25.9 V",
                "stale: none",
                "0x211 system    50/s",
            ],
        );
        assert!(!screen.contains("[fault]") && !screen.contains("LINK FAILED"), "{screen}");
        // A link that fails is still a fault.
        status.link_ended = false;
        app.update(&Snapshot { status: &status, sender: SenderStats::default(), link_name: "x", now: end });
        assert!(self::screen(&app, 100, 30).contains("[fault] LINK FAILED: end of the replayed log"));
    }

    #[test]
    fn info_lines_are_listed_but_not_counted() {
        let screen = screen(&driving_with_info_and_a_warning(), 100, 30);
        assert_contains(
            &screen,
            &["Faults (1)", "[info]       M1 driver_disabled", "[info]       M2 driver_disabled"],
        );
        let app = driving_with_info_and_a_warning();
        assert_eq!((app.faults().len(), app.fault_count()), (3, 1));
        assert_contains(&screen_small(&app), &["faults 1 (worst [warning])"]);
    }

    /// An RS232 robot: the serial feedback identifiers of the catalog at 50/s, no odometry, no driver state.
    fn rs232() -> App {
        let base = Instant::now();
        let mut app = App::new("/dev/ttyUSB0", Limits::default(), false);
        let serial: Vec<FrameId> = catalog::CATALOG
            .iter()
            .filter(|entry| entry.wire == Wire::Serial && entry.direction == Direction::FromRobot)
            .map(|entry| entry.id)
            .collect();
        for tick in 0..=100u64 {
            let now = base + Duration::from_millis(50 * tick);
            let mut status = v2_status(now, 0, 0);
            let system = status.system.as_mut().unwrap();
            system.1.control_mode = ControlMode::Serial.code(Wire::Serial);
            system.2 = Wire::Serial;
            status.odometry = None;
            status.motor_low = [None, None];
            status.motor_high = [None, None];
            status.motor_driver = [1, 2].map(|motor| {
                Some(MotorDriverState {
                    motor,
                    current_deciamps: 3,
                    rpm: 0,
                    driver_temperature: 26,
                    count: 0,
                })
            });
            status.detector = ProtocolDetector::default();
            status.id_counts = serial.iter().map(|id| (*id, tick * 5 / 2)).collect();
            status.frames = serial.len() as u64 * tick * 5 / 2;
            app.update(&Snapshot {
                status: &status,
                sender: SenderStats::default(),
                link_name: "/dev/ttyUSB0",
                now,
            });
        }
        app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
        app
    }

    #[test]
    fn rs232_link_panel_lists_its_identifiers_and_what_it_does_not_report() {
        assert_eq!(
            not_reported(Protocol::Serial),
            ["odometry", "motor_low_speed", "rc_state", "version_response"]
        );
        assert_eq!(not_reported(Protocol::CanV1), not_reported(Protocol::Serial));
        assert!(not_reported(Protocol::CanV2).is_empty());
        let app = rs232();
        let screen = screen(&app, 100, 30);
        assert_contains(
            &screen,
            &[
                "RS232 · NORMAL · mode serial",
                "0xAA01 system   50/s  0xAA02 motion   50/s",
                "rx 250 fps · checksum errors 0",
                "skipped bytes 0",
                "RS232 does not report: odometry,",
                "motor_low_speed, rc_state,",
                "RS232 reports no odometry",
                "not on RS232",
            ],
        );
        assert!(!screen.contains("0xAA01system") && !screen.contains("error frames"), "{screen}");
        insta::assert_snapshot!(screen);
        let compact = self::screen(&app, 80, 24);
        assert_contains(&compact, &["rx 250/s cksum 0 skip 0", "AA01:50", "not on RS232"]);
        assert!(!compact.contains("err 0"), "{compact}");
    }

    #[test]
    fn wrap_keeps_words_and_splits_long_ones() {
        assert_eq!(wrap("check the cable and power", 10), ["check the", "cable and", "power"]);
        assert_eq!(wrap("abcdefghijkl xy", 5), ["abcde", "fghij", "kl xy"]);
        assert_eq!(wrap("", 5), [""]);
        assert_eq!(truncate("abcdef", 4), "abc…");
    }
}
