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
//!
//! One file per panel, the layout here: [`header`], [`alert`], [`battery`], [`motion`] (Speeds),
//! [`odometry`] (Odometry & lights), [`faults`], [`motors`], [`link`], [`footer`] (the key-release mode, the
//! keys, the message), [`small`] (the text view) and the [`overlays`] (help and the two questions), with
//! [`theme`] (styles) and [`text`] (fitting words to a width). Each is a pure function of the app state.

mod alert;
mod battery;
mod faults;
mod footer;
mod header;
mod link;
mod message;
mod motion;
mod motors;
mod odometry;
mod overlays;
mod small;
mod text;
mod theme;

#[cfg(test)]
mod tests;

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::Paragraph;
use ratatui::Frame;

use self::alert::alert_text;
use self::battery::render_battery;
use self::faults::{fault_name, render_faults, SEVERITY_COLUMN};
use self::footer::{keys_line, message_line, release_text};
use self::header::header_line;
use self::link::{not_reported_lines, render_link, LINK_FULL_WIDTH};
use self::motion::render_speeds;
use self::motors::render_motors;
use self::odometry::render_odometry;
use self::overlays::render_overlay;
use self::small::{render_small, MIN_PANELS};
use self::text::{fit_words, wrap};
use self::theme::Theme;
use super::app::App;

/// From this size on, the full panels; below, abbreviated ones.
const FULL: (u16, u16) = (100, 30);

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
    render_overlay(frame, app, theme);
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
