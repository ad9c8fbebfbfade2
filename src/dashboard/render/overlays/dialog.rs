//! A box in the middle of the screen over the panels, and a question in it whose answer is never cut.

use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Block, Clear, Paragraph, Wrap};
use ratatui::Frame;

/// A box in the middle of `area`, at most `width` x `height`.
pub(super) fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let width = width.min(area.width);
    let height = height.min(area.height);
    Rect { x: area.x + (area.width - width) / 2, y: area.y + (area.height - height) / 2, width, height }
}

/// A question in a box in the middle of the screen, over what is there. The answer (the keys that
/// answer it) takes the box's last rows whole; the explanation gets what is left above it and is cut
/// first when the screen is small.
pub(super) fn dialog(
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_rows_counts_as_the_paragraph_wraps() {
        let rows = |text: &str, width| wrapped_rows(&Line::raw(text.to_string()), width);
        assert_eq!(rows("y arm   any other key keep watching", 40), 1);
        assert_eq!(rows("y arm   any other key keep watching", 20), 2);
        assert_eq!(rows("abcdefghij", 4), 3);
        assert_eq!(rows("", 10), 1);
    }
}
