//! Text, JSON and CSV renderings of decoded frames, shared by `decode` and `monitor`.
//!
//! Every writer appends to a caller-owned `Vec<u8>` (flushed in large blocks by the caller), so a line costs
//! no allocation.

pub mod console;
pub mod csv;
pub mod filter;
pub mod json;
pub mod mcap;
pub mod number;
pub mod palette;
pub mod queue;
pub mod short_text;
pub mod stamp;
pub mod text;

use crate::candump::{Direction, Timestamp};
use crate::protocol::error_frame::ErrorFrame;
use crate::protocol::serial::SerialFrame;
use crate::protocol::{CanFrame, DecodeError, Decoded, FrameKind};

/// Where a frame came from on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameRef<'a> {
    Can(&'a CanFrame),
    Serial(&'a SerialFrame),
}

/// One frame with its context and what it decoded to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event<'a> {
    pub ts: Option<Timestamp>,
    pub iface: &'a str,
    pub dir: Option<Direction>,
    pub frame: FrameRef<'a>,
    /// `Ok(None)`: not a TRACER message (shown raw); `Err`: a TRACER ID whose content is invalid.
    pub decoded: Result<Option<Decoded>, DecodeError>,
}

/// What kind of line an event becomes, before any field is printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Message(Decoded),
    Invalid(DecodeError),
    ErrorFrame(ErrorFrame),
    Remote,
    Raw,
}

impl Shape {
    /// The `msg` name of an event of this shape.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Message(decoded) => decoded.message.name(),
            Shape::Invalid(_) => filter::FrameShape::Invalid.name(),
            Shape::ErrorFrame(_) => filter::FrameShape::ErrorFrame.name(),
            Shape::Remote => filter::FrameShape::RemoteRequest.name(),
            Shape::Raw => filter::FrameShape::Raw.name(),
        }
    }
}

impl Shape {
    /// The shape of a frame with what the protocol made of it (as [`Event::shape`]).
    pub fn of(frame: FrameRef<'_>, decoded: &Result<Option<Decoded>, DecodeError>) -> Self {
        match *decoded {
            Ok(Some(decoded)) => Shape::Message(decoded),
            Err(error) => Shape::Invalid(error),
            Ok(None) => match frame {
                FrameRef::Can(frame) => match frame.kind() {
                    FrameKind::Error => Shape::ErrorFrame(ErrorFrame::from_frame(frame).expect("error kind")),
                    FrameKind::Remote => Shape::Remote,
                    _ => Shape::Raw,
                },
                FrameRef::Serial(_) => Shape::Raw,
            },
        }
    }
}

impl Event<'_> {
    pub fn shape(&self) -> Shape {
        Shape::of(self.frame, &self.decoded)
    }

    /// The `msg` name of the line.
    pub fn msg_name(&self) -> &'static str {
        self.shape().name()
    }

    /// `can-v2`, `can-v1`, `serial`, or `None` for frames that are not TRACER messages.
    pub fn wire_name(&self) -> Option<&'static str> {
        match (self.decoded, self.frame) {
            (Ok(Some(decoded)), _) => Some(decoded.wire.as_str()),
            (_, FrameRef::Serial(_)) => Some("serial"),
            _ => None,
        }
    }

    /// The identifier as printed: `0x211`, `0x00000123` (extended), `0x20000004` (error), `0xAA01` (serial).
    pub fn push_id(&self, out: &mut Vec<u8>) {
        match self.frame {
            FrameRef::Can(frame) if frame.kind() == FrameKind::Error => {
                number::push_can_id(out, frame.id() | crate::protocol::frame::ERR_FLAG, true)
            }
            FrameRef::Can(frame) => number::push_can_id(out, frame.id(), frame.is_extended()),
            FrameRef::Serial(frame) => number::push_hex_value(out, u32::from(frame.id()), 4),
        }
    }

    /// The raw bytes as hex: the CAN payload, or the whole 13-byte serial frame.
    pub fn push_data(&self, out: &mut Vec<u8>) {
        match self.frame {
            FrameRef::Can(frame) => number::push_hex(out, frame.data()),
            FrameRef::Serial(frame) => number::push_hex(out, &frame.to_bytes()),
        }
    }
}

/// `s` for any count but one: `1 time`, `2 times`.
pub fn plural(count: impl Into<u64>) -> &'static str {
    if count.into() == 1 {
        ""
    } else {
        "s"
    }
}

/// When to colour output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorChoice {
    #[default]
    Auto,
    Always,
    Never,
}

impl ColorChoice {
    /// Whether to colour a stream that is (or is not) a terminal. NO_COLOR (set and not empty) changes only
    /// the `auto` default: an explicit `--color always` wins, as in ripgrep and as no-color.org asks.
    pub fn enabled(self, is_terminal: bool) -> bool {
        self.enabled_with(is_terminal, std::env::var_os("NO_COLOR").is_some_and(|value| !value.is_empty()))
    }

    fn enabled_with(self, is_terminal: bool, no_color: bool) -> bool {
        match self {
            ColorChoice::Always => true,
            ColorChoice::Never => false,
            ColorChoice::Auto => is_terminal && !no_color,
        }
    }
}

/// Output format of `decode` and `monitor`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// One readable line per frame.
    Text,
    /// One JSON object per line (schema in docs/json.md).
    Json,
    /// Comma-separated values with a fixed header (for spreadsheets).
    Csv,
}

/// Renders events in one format.
#[derive(Clone, Copy, Debug)]
pub struct EventWriter {
    pub format: Format,
    /// ANSI colour in text output (by default only on a terminal and not with NO_COLOR).
    pub color: bool,
}

impl EventWriter {
    pub fn new(format: Format, color: bool) -> Self {
        Self { format, color }
    }

    /// Written once before the first event (the CSV header).
    pub fn header(&self, out: &mut Vec<u8>) {
        if self.format == Format::Csv {
            csv::header(out);
        }
    }

    pub fn write(&self, out: &mut Vec<u8>, event: &Event) {
        match self.format {
            Format::Text => text::write(out, event, self.color),
            Format::Json => json::write(out, event),
            Format::Csv => csv::write(out, event),
        }
    }
}

/// Writes a value's `Display` text through `escape` (one byte at a time) without allocating.
pub fn push_display(out: &mut Vec<u8>, value: &impl std::fmt::Display, escape: fn(&mut Vec<u8>, u8)) {
    struct Escaping<'a> {
        out: &'a mut Vec<u8>,
        escape: fn(&mut Vec<u8>, u8),
    }
    impl std::fmt::Write for Escaping<'_> {
        fn write_str(&mut self, text: &str) -> std::fmt::Result {
            for byte in text.bytes() {
                (self.escape)(self.out, byte);
            }
            Ok(())
        }
    }
    let _ = std::fmt::write(&mut Escaping { out, escape }, format_args!("{value}"));
}

fn direction_name(dir: Direction) -> &'static str {
    match dir {
        Direction::Rx => "rx",
        Direction::Tx => "tx",
    }
}

/// A writer's output for `decoded` on `can0` (tests): the frame its codec writes, or stand-in bytes for a
/// message no codec writes (an old-firmware frame); the writer takes the fields from `decoded`.
#[cfg(test)]
pub(crate) fn written(write: fn(&mut Vec<u8>, &Event), decoded: Decoded) -> String {
    let frame = crate::protocol::can::encode(&decoded).or_else(|_| CanFrame::new(0x123, &[0; 8])).unwrap();
    let event = Event {
        ts: None,
        iface: "can0",
        dir: None,
        frame: FrameRef::Can(&frame),
        decoded: Ok(Some(decoded)),
    };
    let mut out = Vec::new();
    write(&mut out, &event);
    String::from_utf8(out).unwrap()
}

#[cfg(test)]
mod color_tests {
    use super::ColorChoice;

    #[test]
    fn no_color_changes_only_the_auto_default() {
        // (choice, is a terminal, NO_COLOR set) -> colour
        for (choice, terminal, no_color, expected) in [
            (ColorChoice::Auto, true, false, true),
            (ColorChoice::Auto, true, true, false),
            (ColorChoice::Auto, false, false, false),
            (ColorChoice::Always, false, true, true),
            (ColorChoice::Always, true, true, true),
            (ColorChoice::Never, true, false, false),
        ] {
            assert_eq!(choice.enabled_with(terminal, no_color), expected, "{choice:?} {terminal} {no_color}");
        }
    }
}
