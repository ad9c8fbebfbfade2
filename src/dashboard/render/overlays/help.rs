//! The help overlay: the key table, each row's help wrapped under its keys, then how releases and arming
//! work.

use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph};
use ratatui::Frame;

use super::dialog::centered;
use crate::dashboard::app::{scale_percent, App};
use crate::dashboard::keys;
use crate::dashboard::render::footer::release_text;
use crate::dashboard::render::text::{fit_words, wrap};
use crate::dashboard::render::theme::{block, Theme};

/// The help overlay: every row of the key table, wrapped under its keys, then how releases and arming work.
/// On a short screen the closing notes go first, then each row keeps one line, then the rows in the middle
/// give way to a count: the row that quits always stays.
pub(super) fn render_help(frame: &mut Frame, area: Rect, app: &App, theme: Theme) {
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
