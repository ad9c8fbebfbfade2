//! The colours of the text output, named once: what each one means, as an `anstyle` style, and the escape
//! it is written as. The dashboard has its own (ratatui) theme.
//!
//! anstyle writes a bold colour as two sequences (`ESC[1m ESC[36m`); the output has always written one
//! (`ESC[1;36m`), which [`Sgr::of`] builds from the same style at compile time, so the line writers copy a
//! constant and the bytes stay as they were.

use anstyle::{AnsiColor, Color, Effects, Style};

/// A message name in `decode` and `monitor` lines.
pub const MESSAGE: Sgr = Sgr::of(Style::new().bold().fg_color(Some(Color::Ansi(AnsiColor::Cyan))));
/// A frame that failed to decode, and fault flags.
pub const FAULT: Sgr = Sgr::of(fg(AnsiColor::Red));
/// Warning flags, and a doctor check that warns.
pub const WARNING: Sgr = Sgr::of(fg(AnsiColor::Yellow));
/// A doctor check that passed.
pub const PASS: Sgr = Sgr::of(fg(AnsiColor::Green));
/// A doctor check that was skipped.
pub const SKIPPED: Sgr = Sgr::of(Style::new().dimmed());
/// A doctor check that failed.
pub const FAILED: Sgr = Sgr::of(Style::new().bold().fg_color(Some(Color::Ansi(AnsiColor::Red))));
/// Back to the terminal's own colours (anstyle's `Reset`).
pub const RESET: Sgr = Sgr::reset();

/// Erases the rest of the line, after a carriage return: `drive`'s status line that overwrites itself.
pub const CLEAR_LINE: &str = "\x1b[K";

const fn fg(color: AnsiColor) -> Style {
    Style::new().fg_color(Some(Color::Ansi(color)))
}

/// One SGR escape sequence (`ESC[…m`), its codes joined by `;`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sgr {
    bytes: [u8; Sgr::CAPACITY],
    len: usize,
}

impl Sgr {
    /// Room for `ESC[1;2;97m`: the effects and the 16 colours the palette uses.
    const CAPACITY: usize = 16;

    /// The escape for `style`: bold and dimmed, then a foreground colour of the 16 basic ones. Anything
    /// else (backgrounds, 256 and RGB colours) fails the build: the palette does not use it.
    pub const fn of(style: Style) -> Self {
        assert!(style.get_bg_color().is_none() && style.get_underline_color().is_none());
        let effects = style.get_effects();
        assert!(Effects::BOLD.insert(Effects::DIMMED).contains(effects), "only bold and dimmed are written");
        let mut sgr = Self::start();
        if effects.contains(Effects::BOLD) {
            sgr = sgr.code(1);
        }
        if effects.contains(Effects::DIMMED) {
            sgr = sgr.code(2);
        }
        match style.get_fg_color() {
            Some(Color::Ansi(color)) => {
                let index = color as u8;
                sgr = sgr.code(if index < 8 { 30 + index } else { 90 + index - 8 });
            }
            None => {}
            Some(_) => panic!("only the 16 basic colours are written"),
        }
        sgr.push(b'm')
    }

    /// `ESC[0m`.
    pub const fn reset() -> Self {
        Self::start().code(0).push(b'm')
    }

    const fn start() -> Self {
        Self { bytes: [0; Self::CAPACITY], len: 0 }.push(0x1b).push(b'[')
    }

    const fn push(mut self, byte: u8) -> Self {
        self.bytes[self.len] = byte;
        self.len += 1;
        self
    }

    /// Appends a code, after a `;` unless it is the first.
    const fn code(mut self, code: u8) -> Self {
        if self.len > 2 {
            self = self.push(b';');
        }
        if code >= 10 {
            self = self.push(b'0' + code / 10);
        }
        self.push(b'0' + code % 10)
    }

    pub const fn as_bytes(&self) -> &[u8] {
        self.bytes.split_at(self.len).0
    }

    pub const fn as_str(&self) -> &str {
        match std::str::from_utf8(self.as_bytes()) {
            Ok(text) => text,
            Err(_) => panic!("an escape is ASCII"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// anstyle's own rendering with its sequences merged into one: `ESC[1m ESC[36m` is `ESC[1;36m`.
    fn anstyle_merged(style: Style) -> String {
        let rendered = style.render().to_string();
        let codes: Vec<&str> = rendered
            .split('\x1b')
            .filter(|part| !part.is_empty())
            .map(|part| &part[1..part.len() - 1])
            .collect();
        format!("\x1b[{}m", codes.join(";"))
    }

    #[test]
    fn the_escapes_are_the_ones_the_output_always_wrote() {
        let written: Vec<&str> =
            [MESSAGE, FAULT, WARNING, PASS, SKIPPED, FAILED, RESET].iter().map(Sgr::as_str).collect();
        assert_eq!(
            written,
            ["\x1b[1;36m", "\x1b[31m", "\x1b[33m", "\x1b[32m", "\x1b[2m", "\x1b[1;31m", "\x1b[0m"]
        );
        assert_eq!(MESSAGE.as_bytes(), b"\x1b[1;36m");
    }

    #[test]
    fn each_escape_says_what_anstyle_says() {
        let red = Color::Ansi(AnsiColor::Red);
        for style in [
            Style::new().bold().fg_color(Some(Color::Ansi(AnsiColor::Cyan))),
            fg(AnsiColor::Red),
            fg(AnsiColor::Yellow),
            fg(AnsiColor::Green),
            fg(AnsiColor::BrightWhite),
            Style::new().dimmed(),
            Style::new().bold().dimmed().fg_color(Some(red)),
        ] {
            assert_eq!(Sgr::of(style).as_str(), anstyle_merged(style), "{style:?}");
        }
        assert_eq!(RESET.as_str(), anstyle::Reset.render().to_string());
    }
}
