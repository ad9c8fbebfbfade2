//! Drawing the dashboard: a pure function of the [`App`] state.
//!
//! Layout, top to bottom: a header line (tool, link, protocol, vehicle state, control mode, age of the last
//! status), an alert line (the one thing to know now), Battery | Speeds | Odometry & lights, Faults (all the
//! room left), Motors | Link health, then the key-release mode, the keys, and the one-line message.
//! Below 100x30 the panels are abbreviated so that everything essential fits 80x24; below 60x20 a short
//! text view replaces the panels. Severity is always spelled (`[fault]`); colour only repeats it, and with
//! `color == false` no colour is used at all (bold only).

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Clear, Gauge, Paragraph, RenderDirection, Row, Sparkline, Table, Wrap};
use ratatui::Frame;

use super::app::{
    id_name, scale_percent, speed_text, App, Arming, BatteryZone, FaultLine, Prompt, Protocol, StatusAge,
    BATTERY_GAUGE_TOP_DV,
};
use super::keys;
use crate::protocol::catalog;
use crate::protocol::constants::{BATTERY_CUTOFF_DV, BATTERY_FAULT_DV, BATTERY_WARNING_DV};
use crate::protocol::message::{
    light_mode_name, MessageKind, MODE_CAN, MODE_SERIAL, VEHICLE_ESTOP, VEHICLE_EXCEPTION, VEHICLE_NORMAL,
};
use crate::protocol::{ControlMode, FlagTable, Flags, FrameId, Severity, Wire};

/// Below this the panels do not fit and a short text view is drawn instead.
const MIN_PANELS: (u16, u16) = (60, 20);
/// From this size on, the full panels; below, abbreviated ones.
const FULL: (u16, u16) = (100, 30);
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
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Tone {
    Ok,
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
        frame.render_widget(Paragraph::new(header_line(app, theme)), header);
        let (tone, text) = alert_text(app);
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
        let link_width = if compact { Constraint::Percentage(45) } else { Constraint::Length(44) };
        let [motors, link] = Layout::horizontal([Constraint::Fill(1), link_width]).areas(bottom);
        render_motors(frame, motors, app, theme, compact);
        render_link(frame, link, app, theme, compact);

        frame.render_widget(Paragraph::new(Line::styled(release_text(app), theme.dim())), release);
        frame.render_widget(Paragraph::new(keys_line(keys.width, theme, app.arming)), keys);
        frame.render_widget(Paragraph::new(message_line(app, theme)), message);
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
    let link_lines = 4 + ids.div_ceil(2).max(1);
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

/// `tracerctl · ARMED · can0 · CAN V2 · NORMAL · mode can · status <0.1 s`
fn header_line(app: &App, theme: Theme) -> Line<'static> {
    let shown = &app.shown;
    let arming = match app.arming {
        Arming::Armed => Span::styled("ARMED", theme.alarm()),
        Arming::Watching => Span::styled("WATCHING", theme.ok().add_modifier(Modifier::BOLD)),
        Arming::WatchOnly => Span::styled("WATCH ONLY", theme.ok().add_modifier(Modifier::BOLD)),
    };
    let mut spans = vec![
        Span::styled("tracerctl", theme.bold()),
        separator(theme),
        arming,
        separator(theme),
        Span::raw(shown.link_name.clone()),
        separator(theme),
        Span::raw(shown.protocol.label()),
        separator(theme),
    ];
    match shown.system {
        Some(system) => {
            let (text, style) = match system.vehicle_state {
                VEHICLE_NORMAL => ("NORMAL".to_string(), theme.ok().add_modifier(Modifier::BOLD)),
                VEHICLE_ESTOP => ("E-STOP".to_string(), theme.alarm()),
                VEHICLE_EXCEPTION => ("EXCEPTION".to_string(), theme.alarm()),
                other => (format!("STATE 0x{other:02X}"), theme.alarm()),
            };
            spans.push(Span::styled(text, style));
            spans.push(separator(theme));
            let mode = format!("mode {}", ControlMode::describe(system.wire, system.control_mode));
            let style = if in_command_mode(system.control_mode, system.wire) {
                Style::new()
            } else {
                theme.warning()
            };
            spans.push(Span::styled(mode, style));
        }
        None => spans.push(Span::styled("state ?", theme.dim())),
    }
    spans.push(separator(theme));
    spans.push(match shown.status_age {
        StatusAge::Never => Span::styled("no status yet", theme.warning()),
        StatusAge::Fresh => Span::raw("status <0.1 s"),
        StatusAge::Stale { deciseconds } => {
            Span::styled(format!("NO STATUS FOR {}", age_text(deciseconds)), theme.alarm())
        }
    });
    Line::from(spans)
}

fn in_command_mode(mode: u8, wire: Wire) -> bool {
    match wire {
        Wire::Serial => mode == MODE_SERIAL,
        Wire::CanV1 | Wire::CanV2 => mode == MODE_CAN,
    }
}

/// `3.0 s`, `42 s`.
fn age_text(deciseconds: u64) -> String {
    if deciseconds < 600 {
        format!("{}.{} s", deciseconds / 10, deciseconds % 10)
    } else {
        format!("{} s", deciseconds / 10)
    }
}

/// The one thing to know now, worst first.
fn alert_text(app: &App) -> (Tone, String) {
    let shown = &app.shown;
    if let Some(error) = &shown.link_error {
        return (Tone::Alarm, format!("[fault] LINK FAILED: {error}"));
    }
    let system = match (shown.status_age, shown.system) {
        (StatusAge::Stale { deciseconds }, _) => {
            return (
                Tone::Alarm,
                format!(
                    "[fault] STALE: no status for {}: every value on screen is old (robot off? cable? bus?)",
                    age_text(deciseconds)
                ),
            );
        }
        (StatusAge::Fresh, Some(system)) => system,
        _ if !shown.received_any => {
            return (
                Tone::Warning,
                format!(
                    "[warning] nothing received on {} yet: is the robot on, is this the right link?",
                    shown.link_name
                ),
            );
        }
        _ => {
            return (
                Tone::Warning,
                "[warning] frames arrive but no system status yet: is this a TRACER, is --protocol right?"
                    .to_string(),
            );
        }
    };
    let state = system.state();
    let faults = app.faults();
    let blocking: Vec<&FaultLine> =
        faults.iter().filter(|f| matches!(f.info.severity, Severity::Fault | Severity::Protection)).collect();
    if state.is_estop() {
        let reason = state.why_not_drivable(system.wire).unwrap_or_default();
        return (Tone::Alarm, format!("[fault] E-STOP: {reason}"));
    }
    if !blocking.is_empty() {
        let names: Vec<String> = blocking.iter().map(|f| fault_name(f)).collect();
        return (Tone::Alarm, format!("[fault] CANNOT DRIVE, see Faults: {}", names.join(", ")));
    }
    if let Some(reason) = state.why_not_drivable(system.wire) {
        return (Tone::Alarm, format!("[fault] CANNOT DRIVE: {reason}"));
    }
    if system.vehicle_state == VEHICLE_EXCEPTION {
        return (
            Tone::Alarm,
            "[fault] EXCEPTION: the robot reports a system exception (latched fault, battery cut-off or RC link lost)"
                .to_string(),
        );
    }
    if !in_command_mode(system.control_mode, system.wire) {
        let mode = ControlMode::describe(system.wire, system.control_mode);
        return (Tone::Warning, format!("[warning] not in command mode (mode {mode}): press m to enable it"));
    }
    let battery = BatteryZone::of(system.decivolts);
    if faults.iter().any(|f| f.info.severity > Severity::Info) || battery != BatteryZone::Ok {
        return (
            Tone::Warning,
            "[warning] ready to drive, with warnings: see Faults and Battery".to_string(),
        );
    }
    match app.arming {
        Arming::Armed => (Tone::Ok, "ready to drive: command mode, no faults".to_string()),
        Arming::Watching => {
            (Tone::Ok, "watching: nothing is sent; an arrow key or a asks to arm driving".to_string())
        }
        Arming::WatchOnly => (Tone::Ok, "watch only: nothing is sent to the robot".to_string()),
    }
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
    } else {
        format!("Speeds · scale {} %", scale_percent(teleop.scale))
    };
    let block = block(title, theme);
    let row = |label: &str, linear: String, angular: String| format!("{label:<6}{linear:>7} {angular:>7}");
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
    lines.push(Line::from(vec![
        Span::raw(if compact { "lights " } else { "lights  " }),
        lights_span(app, theme),
    ]));
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
    let title = if faults.is_empty() { "Faults".to_string() } else { format!("Faults ({})", faults.len()) };
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
    let shown_count = if fits_all { faults.len() } else { height.saturating_sub(1) };
    for (index, fault) in faults.iter().take(shown_count).enumerate() {
        let name = fault_name(fault);
        let body = format!("{name}: {}", fault.info.action);
        let wrapped = wrap(&body, body_width);
        // Keep one line for each fault still to come.
        let left_after = shown_count - index - 1;
        let room = height.saturating_sub(lines.len() + left_after);
        let rows: Vec<String> =
            if wrapped.len() <= room { wrapped } else { vec![truncate(&body, body_width)] };
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
    if !fits_all {
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
    let widths = if compact {
        [
            Constraint::Length(2),
            Constraint::Length(4),
            Constraint::Length(4),
            Constraint::Length(5),
            Constraint::Length(5),
            Constraint::Fill(1),
        ]
    } else {
        [
            Constraint::Length(2),
            Constraint::Length(4),
            Constraint::Length(7),
            Constraint::Length(5),
            Constraint::Length(5),
            Constraint::Fill(1),
        ]
    };
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
        let state = match motor.driver_state {
            None => dash(),
            Some(0) => Span::styled("ok", theme.ok()),
            Some(bits) => {
                let flags = Flags::new(FlagTable::DriverState, u16::from(bits));
                let names: Vec<&str> =
                    flags.iter().map(|info| info.name.strip_prefix("driver_").unwrap_or(info.name)).collect();
                let worst = flags.iter().map(|info| info.severity).max();
                Span::styled(
                    format!("0x{bits:02X} {}", names.join(",")),
                    worst.map_or_else(Style::new, |s| theme.severity(s)),
                )
            }
        };
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
    let mut first = vec![
        Span::raw(format!("rx {fps}/s ")),
        Span::styled(format!("err {}", c.error_frames), bad(c.error_frames)),
        Span::raw(" "),
        Span::styled(format!("drop {}", c.socket_drops), bad(c.socket_drops)),
        Span::raw(" "),
        Span::styled(format!("cksum {}", c.serial_bad_checksum), bad(c.serial_bad_checksum)),
    ];
    if c.send_errors > 0 || c.watchdog_trips > 0 {
        first.push(Span::styled(format!(" tx err {} wd {}", c.send_errors, c.watchdog_trips), theme.alarm()));
    }
    let mut lines = vec![Line::from(first), stale];
    let mut row: Vec<Span> = Vec::new();
    let mut used = 0usize;
    let width = usize::from(area.width.saturating_sub(2));
    for id in &shown.ids {
        let label = match id.id {
            FrameId::Standard(id) => format!("{id:03X}"),
            other => other.to_string(),
        };
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
    frame.render_widget(Paragraph::new(lines).block(block("Link · ID:fps", theme)), area);
}

/// The full link panel: the counters in words, then `0x211  system     50/s` in as many columns as fit.
fn render_link_full(frame: &mut Frame, area: Rect, app: &App, theme: Theme, stale: Line<'static>) {
    let shown = &app.shown;
    let c = &shown.counters;
    let fps = shown.total_fps.map_or_else(|| "-".to_string(), |fps| fps.to_string());
    let bad = |value: u64| bad_if_any(value, theme);
    let mut lines = vec![Line::from(vec![
        Span::raw(format!("rx {fps} fps · ")),
        Span::styled(format!("error frames {}", c.error_frames), bad(c.error_frames)),
        Span::raw(" · "),
        Span::styled(format!("dropped {}", c.socket_drops), bad(c.socket_drops)),
    ])];
    let mut checksum = vec![Span::styled(
        format!("serial checksum errors {}", c.serial_bad_checksum),
        bad(c.serial_bad_checksum),
    )];
    if c.serial_skipped_bytes > 0 {
        checksum.push(Span::raw(format!(" · skipped bytes {}", c.serial_skipped_bytes)));
    }
    lines.push(Line::from(checksum));
    lines.push(Line::from(vec![
        Span::styled(format!("tx send errors {}", c.send_errors), bad(c.send_errors)),
        Span::raw(" · "),
        Span::styled(format!("watchdog trips {}", c.watchdog_trips), bad(c.watchdog_trips)),
    ]));
    lines.push(stale);
    let room = usize::from(area.height.saturating_sub(2)).saturating_sub(lines.len());
    lines.extend(id_columns(app, theme, usize::from(area.width.saturating_sub(2)), room));
    frame.render_widget(Paragraph::new(lines).block(block("Link health", theme)), area);
}

/// `0x211  system     50/s` per ID, in as many columns as fit `width`, at most `room` rows (the last cell
/// then says how many more).
fn id_columns(app: &App, theme: Theme, width: usize, room: usize) -> Vec<Line<'static>> {
    const CELL: usize = 20;
    let shown = &app.shown;
    let columns = ((width + 2) / (CELL + 2)).max(1);
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
            let text = format!("{:<6}{:<9}{:>5}", id.id.to_string(), truncate(id_name(id.id), 8), rate);
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

/// The key summary from the key table, long or short to fit.
fn keys_line(width: u16, theme: Theme, arming: Arming) -> Line<'static> {
    let entries = keys::footer_entries(arming);
    let length = |keys: &[(&str, &str)]| -> usize {
        keys.iter().map(|(k, d)| k.chars().count() + 1 + d.len()).sum::<usize>()
            + 2 * keys.len().saturating_sub(1)
    };
    let long: Vec<(&str, &str)> = entries.iter().map(|entry| (entry.0, entry.1)).collect();
    let mut keys = if length(&long) <= usize::from(width) {
        long
    } else {
        entries.iter().map(|entry| (entry.0, entry.2)).collect()
    };
    // Still too wide: drop the least needed, so stopping, arming, help and quitting always show.
    let mut spare: Vec<(u8, &str)> =
        entries.iter().filter_map(|entry| entry.3.map(|rank| (rank, entry.0))).collect();
    spare.sort_unstable();
    for (_, least) in spare {
        if length(&keys) <= usize::from(width) {
            break;
        }
        keys.retain(|(key, _)| *key != least);
    }
    let mut spans = Vec::new();
    for (index, (key, description)) in keys.iter().enumerate() {
        if index > 0 {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(*key, theme.key()));
        spans.push(Span::raw(format!(" {description}")));
    }
    Line::from(spans)
}

/// The footer: a recording that loses frames (it stays: the exit status will say so too), then the message.
fn message_line(app: &App, theme: Theme) -> Line<'static> {
    let mut spans = Vec::new();
    if let Some(loss) = &app.recording_loss {
        spans.push(Span::styled(
            format!("[fault] RECORDING LOST {} frames: {}", loss.frames, loss.reason),
            theme.alarm(),
        ));
    }
    if let Some((text, _)) = &app.message {
        if !spans.is_empty() {
            spans.push(separator(theme));
        }
        spans.push(Span::styled("> ", theme.dim()));
        spans.push(Span::styled(text.clone(), theme.bold()));
    }
    Line::from(spans)
}

/// Under 60x20: the essentials as text.
fn render_small(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
    let (tone, alert) = alert_text(app);
    let mut lines = vec![header_line(app, theme), Line::styled(alert, theme.tone(tone))];
    if let Some(system) = app.shown.system {
        let faults = app.faults();
        let worst = faults.iter().map(|f| f.info.severity).max();
        lines.push(Line::raw(format!(
            "battery {} · faults {}{}",
            volts(system.decivolts),
            faults.len(),
            worst.map(|s| format!(" (worst {})", severity_tag(s))).unwrap_or_default()
        )));
    }
    lines.push(Line::raw(format!(
        "keys {}/{} · sent {}/{}",
        speed_text(app.teleop.requested.0),
        speed_text(app.teleop.requested.1),
        speed_text(f64::from(app.shown.sent.0) / 1000.0),
        speed_text(f64::from(app.shown.sent.1) / 1000.0)
    )));
    lines.push(Line::styled(release_text(app), theme.dim()));
    lines.push(keys_line(area.width, theme, app.arming));
    lines.push(Line::styled(
        format!("terminal {}x{}: 80x24 or larger shows the full dashboard", area.width, area.height),
        theme.warning(),
    ));
    lines.push(message_line(app, theme));
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}

/// A box in the middle of `area`, at most `width` x `height`.
fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let width = width.min(area.width);
    let height = height.min(area.height);
    Rect { x: area.x + (area.width - width) / 2, y: area.y + (area.height - height) / 2, width, height }
}

fn render_help(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
    let mut lines: Vec<Line> = keys::BINDINGS
        .iter()
        .map(|row| {
            let mut what = row.help.to_string();
            if row.keys.iter().any(|bind| bind.action == keys::Action::Faster) {
                what.push_str(&format!(" (now {} %)", scale_percent(app.teleop.scale)));
            }
            Line::from(vec![
                Span::styled(format!("{:<width$}", row.shown, width = keys::KEY_COLUMN), theme.key()),
                Span::raw(what),
            ])
        })
        .collect();
    lines.push(Line::raw(""));
    lines.push(Line::styled(release_text(app), theme.dim()));
    lines.push(Line::styled(
        "Opens WATCHING: nothing is sent until armed. Releasing a key brakes (--decel); an E-stop, a \
         latched fault or RC override sends zero until a fresh press. Every way out sends zero-velocity \
         frames first.",
        theme.dim(),
    ));
    let width = 70.min(area.width.saturating_sub(4)).max(20);
    let height = (lines.len() as u16 + 2).min(area.height);
    let popup = centered(area, width, height);
    frame.render_widget(Clear, popup);
    frame.render_widget(
        Paragraph::new(lines).wrap(Wrap { trim: false }).block(block("Keys · ? closes", theme)),
        popup,
    );
}

fn render_confirm_arm(frame: &mut Frame, area: Rect, theme: Theme) {
    let lines = vec![
        Line::raw("Arm driving? The dashboard then switches to command mode"),
        Line::raw("and sends motion commands at 50 Hz: it takes control from ROS"),
        Line::raw("or an RC transmitter. Until then nothing is sent."),
        Line::raw(""),
        Line::from(vec![
            Span::styled(keys::key_name(keys::Action::Yes), theme.key()),
            Span::raw(" arm   "),
            Span::styled("any other key", theme.key()),
            Span::raw(" keep watching"),
        ]),
    ];
    dialog(frame, area, lines, 64, block("Arm driving?", theme).border_style(theme.warning()));
}

/// A question in a box in the middle of the screen, over what is there.
fn dialog(frame: &mut Frame, area: Rect, lines: Vec<Line<'static>>, width: u16, block: Block<'static>) {
    let width = width.min(area.width.saturating_sub(4)).max(20);
    let height = (lines.len() as u16 + 2).min(area.height);
    let popup = centered(area, width, height);
    frame.render_widget(Clear, popup);
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }).block(block), popup);
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
    lines.push(Line::from(vec![
        Span::styled(keys::key_name(keys::Action::Yes), theme.key()),
        Span::raw(" send the clear   "),
        Span::styled(keys::key_name(keys::Action::Stop), theme.key()),
        Span::raw(" stop   "),
        Span::styled("any other key", theme.key()),
        Span::raw(" cancel"),
    ]));
    dialog(frame, area, lines, 62, block("Clear faults?", theme).border_style(theme.alarm()));
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
        Lights, MotionCommand, MotionState, MotorHighSpeed, MotorLowSpeed, Odometry, SystemState,
    };
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
            assert!(width < 20 || screen.contains("tracerctl"), "{width}x{height}:\n{screen}");
            app.toggle_help();
            let _ = self::screen(&app, width, height);
            app.toggle_help();
            app.ask_clear_confirmation();
            let _ = self::screen(&app, width, height);
            app.cancel_prompt();
        }
        let small = screen(&app, 50, 15);
        assert_contains(&small, &["80x24 or larger", "EXCEPTION"]);
    }

    #[test]
    fn wrap_keeps_words_and_splits_long_ones() {
        assert_eq!(wrap("check the cable and power", 10), ["check the", "cable and", "power"]);
        assert_eq!(wrap("abcdefghijkl xy", 5), ["abcde", "fghij", "kl xy"]);
        assert_eq!(wrap("", 5), [""]);
        assert_eq!(truncate("abcdef", 4), "abc…");
    }
}
