//! What a line of a log holds, in every format: the frame record with its timestamp, interface and
//! direction, or what else the line is. A leaf: the parsers of each format and the writer share these
//! types, and they read nothing else of this module.

use crate::protocol::CanFrame;

/// Whether this host received or sent the frame (`-x`: log ` R`/` T`, console `RX`/`TX`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Rx,
    Tx,
}

/// One frame line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Record<'a> {
    pub ts: Option<Timestamp>,
    pub iface: &'a str,
    pub frame: CanFrame,
    pub dir: Option<Direction>,
}

/// A common log line read where it stands ([`LineParser::parse_log_line_at`](super::LineParser::parse_log_line_at)): the frame stays in the
/// parser and is lent, not copied out with the rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LogRecord<'a> {
    pub ts: Option<Timestamp>,
    pub iface: &'a str,
    pub frame: &'a CanFrame,
    pub dir: Option<Direction>,
}

impl<'a> LogRecord<'a> {
    /// The record with its own copy of the frame.
    pub fn to_record(&self) -> Record<'a> {
        Record { ts: self.ts, iface: self.iface, frame: *self.frame, dir: self.dir }
    }
}

/// What a line holds.
#[derive(Debug, PartialEq, Eq)]
pub enum Line<'a> {
    Frame(Record<'a>),
    /// Empty or only spaces.
    Blank,
    /// Starts with `#` or `;` (after optional spaces).
    Comment,
    /// `DROPCOUNT: dropped N CAN frame[s] on 'can0' socket (total drops M)`.
    DropCount {
        dropped: u64,
    },
    /// A TAB-started continuation line following an error frame (`-e`), or the error / status lines of
    /// other formats (ASC `ErrorFrame`, trc `ER`/`ST`/`EC`).
    ErrorText,
    /// A syntactically valid CAN XL frame (not decoded; the caller counts it).
    CanXl,
}

/// Longest interface name (IFNAMSIZ - 1).
pub(crate) const IFACE_MAX_LEN: usize = 15;

/// Seconds values below this (before 1973-03-03) are taken as relative stamps (`-t z`, `-t d`,
/// python-can's `(0.000000)`): no real capture is that old.
pub const RELATIVE_LIMIT_SECS: u64 = 100_000_000;

/// A timestamp exactly as the log had it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timestamp {
    pub secs: u64,
    /// 0..1_000_000_000.
    pub nanos: u32,
    pub kind: TimestampKind,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimestampKind {
    /// Seconds since the epoch (log default, console `-t a`; `-t A` converted treating the wall-clock as UTC).
    Absolute,
    /// Since the start of the capture (`-t z`, or the running sum of `-t d` deltas).
    Relative,
}

impl Timestamp {
    /// A stamp `secs.nanos` after the start of a recording: on the clock when the file says when it started
    /// (ASC's `date`, trc's `$STARTTIME`), else relative.
    pub(crate) fn since_start(secs: u64, nanos: u32, start: Option<(u64, u32)>) -> Self {
        let Some((start_secs, start_nanos)) = start else {
            return Self { secs, nanos, kind: TimestampKind::Relative };
        };
        let nanos = nanos + start_nanos;
        let secs = secs.saturating_add(start_secs).saturating_add(u64::from(nanos / 1_000_000_000));
        Self { secs, nanos: nanos % 1_000_000_000, kind: TimestampKind::Absolute }
    }

    pub fn as_secs_f64(&self) -> f64 {
        self.secs as f64 + f64::from(self.nanos) * 1e-9
    }

    pub fn as_nanos(&self) -> u128 {
        u128::from(self.secs) * 1_000_000_000 + u128::from(self.nanos)
    }

    /// Whole microseconds, as a candump line carries them; `u64::MAX` beyond (year 586,000).
    pub fn as_micros(&self) -> u64 {
        u64::try_from(self.as_nanos() / 1000).unwrap_or(u64::MAX)
    }

    /// [`Self::as_micros`] as the signed time of an analysis, `i64::MAX` beyond (year 294,000).
    pub fn as_micros_i64(&self) -> i64 {
        i64::try_from(self.as_micros()).unwrap_or(i64::MAX)
    }

    /// Classifies a numeric stamp by its value (see [`RELATIVE_LIMIT_SECS`]).
    pub(crate) fn from_numeric(secs: u64, nanos: u32) -> Self {
        let kind = if secs < RELATIVE_LIMIT_SECS { TimestampKind::Relative } else { TimestampKind::Absolute };
        Self { secs, nanos, kind }
    }
}
