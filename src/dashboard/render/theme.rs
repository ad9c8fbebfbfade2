//! Styles: what colour and emphasis each kind of text gets. Colour only repeats what the words say; without
//! colour, emphasis is bold only.

use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Span;
use ratatui::widgets::Block;

use crate::protocol::Severity;

/// Styles; without colour, emphasis is bold only.
#[derive(Clone, Copy)]
pub(super) struct Theme {
    pub(super) color: bool,
}

impl Theme {
    pub(super) fn paint(&self, color: Color) -> Style {
        if self.color {
            Style::new().fg(color)
        } else {
            Style::new()
        }
    }
    pub(super) fn bold(&self) -> Style {
        Style::new().add_modifier(Modifier::BOLD)
    }
    pub(super) fn alarm(&self) -> Style {
        self.paint(Color::Red).add_modifier(Modifier::BOLD)
    }
    pub(super) fn warning(&self) -> Style {
        self.paint(Color::Yellow)
    }
    pub(super) fn ok(&self) -> Style {
        self.paint(Color::Green)
    }
    pub(super) fn dim(&self) -> Style {
        self.paint(Color::DarkGray)
    }
    pub(super) fn key(&self) -> Style {
        self.paint(Color::Cyan).add_modifier(Modifier::BOLD)
    }
    pub(super) fn severity(&self, severity: Severity) -> Style {
        match severity {
            Severity::Protection | Severity::Fault => self.alarm(),
            Severity::Warning => self.warning(),
            Severity::Info => self.dim(),
            Severity::Unknown => self.paint(Color::Magenta),
        }
    }
    pub(super) fn tone(&self, tone: Tone) -> Style {
        match tone {
            Tone::Ok => self.ok(),
            Tone::Warning => self.warning().add_modifier(Modifier::BOLD),
            Tone::Alarm => self.alarm(),
            Tone::Info => self.paint(Color::Cyan).add_modifier(Modifier::BOLD),
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Tone {
    Ok,
    /// Neither good nor bad news: a replay that ended.
    Info,
    Warning,
    Alarm,
}

pub(super) fn block(title: impl Into<String>, theme: Theme) -> Block<'static> {
    Block::bordered().title(Span::styled(format!(" {} ", title.into()), theme.bold()))
}

pub(super) fn separator(theme: Theme) -> Span<'static> {
    Span::styled(" · ", theme.dim())
}
