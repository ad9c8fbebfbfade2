//! Why a line or a frame was rejected: a closed, `Copy` set of reasons with fixed texts, so callers can
//! count them in summary tables without allocating.

use std::fmt;

use crate::protocol::FrameError;

macro_rules! reasons {
    ($($(#[$doc:meta])* $variant:ident => $code:literal, $text:literal;)+) => {
        /// Why a candump line or a cansend frame was rejected.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum Reason {
            $($(#[$doc])* $variant,)+
        }

        impl Reason {
            /// Every reason, in declaration order (for summary tables).
            pub const ALL: &'static [Reason] = &[$(Reason::$variant,)+];

            /// Human-readable explanation, e.g. "odd number of hex digits in data".
            pub fn as_str(&self) -> &'static str {
                match self {
                    $(Reason::$variant => $text,)+
                }
            }

            /// Stable kebab-case identifier, e.g. `odd-hex-digits` (for JSON and CSV output).
            pub fn code(&self) -> &'static str {
                match self {
                    $(Reason::$variant => $code,)+
                }
            }
        }
    };
}

reasons! {
    /// The line has none of the shapes candump writes.
    NotCandump => "not-candump", "not a candump line";
    /// `(` without a closing `)`.
    UnterminatedTimestamp => "unterminated-timestamp", "unterminated timestamp: missing ')'";
    /// Something other than `digits.digits` inside the parentheses.
    BadTimestamp => "bad-timestamp", "timestamp must be decimal seconds, '.', and a decimal fraction";
    /// No fraction digits, or more than 9.
    TimestampFraction => "timestamp-fraction", "timestamp fraction must have 1 to 9 digits";
    /// More than 19 digits of seconds.
    TimestampTooLarge => "timestamp-too-large", "timestamp seconds do not fit in 64 bits";
    /// A `-t A` date/time that is malformed or not a real calendar time.
    BadDateTime => "bad-date-time", "invalid date/time: expected YYYY-MM-DD HH:MM:SS.ffffff from 1970 on";
    /// Two fields run into each other.
    ExpectedSpace => "expected-space", "expected a space";
    /// The frame follows the timestamp directly.
    MissingInterface => "missing-interface", "missing interface name";
    /// Interface names have at most 15 characters (IFNAMSIZ - 1).
    InterfaceTooLong => "interface-too-long", "interface name longer than 15 characters";
    /// Interface names are printable ASCII without spaces.
    BadInterface => "bad-interface", "interface name must be printable ASCII";
    /// Nothing after the interface name.
    MissingFrame => "missing-frame", "missing frame after the interface name";
    /// An identifier not followed by `#`.
    MissingHash => "missing-hash", "missing '#' after the identifier";
    /// A character that should be a hex digit is not.
    NotHex => "not-hex", "expected a hex digit";
    /// Identifiers have exactly 3 (standard) or 8 (extended or error) digits.
    IdLength => "id-length", "identifier must have 3 or 8 hex digits";
    /// A 3-digit identifier above 0x7FF (cansend accepts up to FFF; the bus cannot carry it).
    SffIdTooLarge => "sff-id-too-large", "3-digit identifier above 0x7FF";
    /// An 8-digit identifier with bit 30 or 31 set (SocketCAN's RTR/EFF flags smuggled into the id).
    IdTooLarge => "id-too-large", "8-digit identifier above 0x3FFFFFFF (bits 30 and 31 must be clear)";
    /// Data hex digits that do not pair up into bytes.
    OddHexDigits => "odd-hex-digits", "odd number of hex digits in data";
    /// `.` inside a byte or doubled.
    BadSeparator => "bad-separator", "'.' may only separate whole bytes, one at a time";
    /// A classic frame with a 9th byte.
    TooManyBytes => "too-many-bytes", "more than 8 data bytes";
    /// A CAN FD frame with a 65th byte.
    FdTooManyBytes => "fd-too-many-bytes", "more than 64 data bytes in a CAN FD frame";
    /// A CAN FD payload length that no DLC encodes.
    BadFdLength => "bad-fd-length", "CAN FD length must be 0-8, 12, 16, 20, 24, 32, 48 or 64";
    /// `##` not followed by the flags nibble.
    BadFdFlags => "bad-fd-flags", "CAN FD frame needs a flags nibble (0-F) after '##'";
    /// `R` followed by something other than a length 0-8.
    BadRemoteLength => "bad-remote-length", "remote request length must be a single digit 0-8";
    /// `_X` anywhere but after exactly 8 bytes of a classic frame, or X outside 9..F.
    BadRawDlc => "bad-raw-dlc", "raw DLC suffix must be '_' and one digit 9-F after exactly 8 data bytes";
    /// An error-frame identifier (bit 29) on a remote request or a CAN FD frame.
    ErrorFrameNotData => "error-frame-not-data", "an error frame cannot be a remote request or a CAN FD frame";
    /// A console `-x` column other than `RX|TX` and two flag columns.
    BadMessageInfo => "bad-message-info", "expected RX or TX and two flag columns such as '- -' or 'B E'";
    /// A console length field other than `[N]`, `[NN]`, `[NNNN]` or `{X}`.
    BadLength => "bad-length", "length must be [0-8], a two-digit CAN FD length [NN] or a raw DLC {0-F}";
    /// The console length disagrees with the bytes that follow it.
    LengthMismatch => "length-mismatch", "length in brackets does not match the number of data bytes";
    /// A console data column that is not two hex digits.
    ConsoleByte => "console-byte", "expected a two-digit hex data byte";
    /// A CAN XL line that does not follow `VCIDPRIO#flags:sdt:af#data`.
    BadXlFrame => "bad-xl-frame", "malformed CAN XL frame (expected VVPPP#FF:SS:AAAAAAAA#data, at most 2048 bytes)";
    /// A CAN XL frame where a classic or FD frame is required.
    XlUnsupported => "xl-unsupported", "CAN XL frames are not supported here";
    /// Text after a complete frame that candump never writes.
    TrailingGarbage => "trailing-garbage", "unexpected text after the frame";
    /// cansend syntax has no whitespace.
    UnexpectedWhitespace => "unexpected-whitespace", "whitespace is not allowed in a frame";
    /// cansend text that is empty.
    EmptyFrame => "empty-frame", "empty frame";
    /// A `DROPCOUNT:` line in an unknown layout.
    BadDropCount => "bad-dropcount", "malformed DROPCOUNT line";
    /// A TAB-started line that is not a frame and does not follow an error frame (`-e` continuation text
    /// only ever follows an `ERRORFRAME` line).
    StrayErrorText => "stray-error-text", "TAB-indented text that does not follow an error frame";
    /// A Vector ASC line that is neither a header, a comment, an event nor a frame.
    NotAsc => "not-asc", "not a Vector ASC line";
    /// A Vector ASC event that tracerctl does not read (LIN, FlexRay, system variables, ...).
    AscEvent => "asc-event", "Vector ASC event that is not a CAN frame";
    /// A Vector ASC CAN line whose columns do not read.
    AscFrame => "asc-frame", "malformed Vector ASC CAN frame line";
    /// A PEAK trc line whose columns do not match the trace's layout.
    TrcFrame => "trc-frame", "malformed PEAK trc frame line (columns do not match the file version)";
    /// Reported by callers for [`RawLine::TooLong`](super::RawLine::TooLong); the parser never sees such lines.
    LineTooLong => "line-too-long", "line too long";
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::error::Error for Reason {}

impl From<FrameError> for Reason {
    /// The frame constructors re-check what the parsers already checked; this maps their verdicts onto
    /// the same reasons so no input can make a parser panic.
    fn from(err: FrameError) -> Self {
        match err {
            FrameError::StandardIdTooLarge { .. } => Reason::SffIdTooLarge,
            FrameError::ExtendedIdTooLarge { .. } => Reason::IdTooLarge,
            FrameError::TooLong { .. } => Reason::TooManyBytes,
            FrameError::BadFdLength { .. } => Reason::BadFdLength,
            FrameError::BadRawDlc { .. } => Reason::BadRawDlc,
        }
    }
}

/// Why a line was rejected. `column` is a 1-based byte column into the line (after ANSI colour codes are
/// removed, for coloured console lines).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {column}: {reason}")]
pub struct LineError {
    pub column: usize,
    pub reason: Reason,
}

/// Why a cansend-syntax frame was rejected. `column` is 1-based.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {column}: {reason}")]
pub struct FrameSyntaxError {
    pub column: usize,
    pub reason: Reason,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn every_reason_has_a_distinct_text_and_code() {
        let texts: HashSet<_> = Reason::ALL.iter().map(Reason::as_str).collect();
        let codes: HashSet<_> = Reason::ALL.iter().map(Reason::code).collect();
        assert_eq!(texts.len(), Reason::ALL.len());
        assert_eq!(codes.len(), Reason::ALL.len());
        assert!(Reason::ALL.iter().all(|r| r.to_string() == r.as_str()));
    }

    #[test]
    fn errors_display_column_and_reason() {
        let err = LineError { column: 7, reason: Reason::OddHexDigits };
        assert_eq!(err.to_string(), "column 7: odd number of hex digits in data");
        let err = FrameSyntaxError { column: 1, reason: Reason::IdLength };
        assert_eq!(err.to_string(), "column 1: identifier must have 3 or 8 hex digits");
    }
}
