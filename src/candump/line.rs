//! The line parser: one line of a log at a time, in the log's dialect. candump text (log and console lines,
//! detected per line) is read by `fast_path.rs` and `general_path.rs`, Vector ASC by `asc.rs`, PEAK trc by
//! `trc.rs`; what every dialect makes of a line is in `record.rs`.

use memchr::memchr;

use super::asc::{self, AscState};
use super::fast_path::{parse_log_fast, parse_log_line_into};
use super::general_path::{parse_angle_frame, parse_general};
use super::hex::{skip_spaces, token_end};
use super::line_limit::LineLimit;
use super::open::{LogFormat, TextFormat};
use super::record::{Line, LogRecord, Record, IFACE_MAX_LEN};
use super::timestamp::{DeltaSum, PosError, SecondsCache};
use super::trc::{self, TrcState};
use super::{LineError, Reason};
use crate::protocol::frame::FrameKind;
use crate::protocol::CanFrame;

/// The text format being read, with what its headers said so far about the lines after them: candump (its
/// own state, the same for log and console lines, is the parser's), Vector ASC (`base dec`, `date`) or
/// PEAK trc (`;$FILEVERSION=`, `;$COLUMNS=`, `;$STARTTIME=`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Dialect {
    #[default]
    Candump,
    Asc(AscState),
    Trc(TrcState),
}

impl Dialect {
    fn of(format: TextFormat) -> Self {
        match format {
            TextFormat::Candump => Dialect::Candump,
            TextFormat::VectorAsc => Dialect::Asc(AscState::default()),
            TextFormat::PeakTrc { version } => Dialect::Trc(TrcState::for_version(version)),
        }
    }
}

/// Parses candump text one line at a time (or, built with [`LineParser::for_format`], Vector ASC or PEAK
/// trc lines).
///
/// Every candump line is classified on its own, so log and console lines may be mixed. The parser is
/// stateful only for: the reusable scratch buffer that coloured (`-c`) lines are copied into without
/// their ANSI codes, the running sum of `-t d` deltas, whether the previous line was an error frame (TAB
/// lines after one are its `-e` text), and the interface named by a Pengutronix `interface = ...` header.
///
/// `-t d` and `-t z` print the same `(000.123456)` layout, so the parser cannot tell them apart: by default
/// small stamps are taken as `-t z` (since the start). Call [`LineParser::with_delta_timestamps`] for
/// `-t d` captures; then relative stamps of console lines are summed (the first delta starts the sum).
/// Log lines never hold deltas (`candump -l` writes only `-t a` or `-t z` stamps). A console line whose
/// frame is rejected still adds its delta, since that time did pass.
#[derive(Debug, Default)]
pub struct LineParser {
    scratch: Vec<u8>,
    deltas: bool,
    delta_sum: DeltaSum,
    dialect: Dialect,
    after_error_frame: bool,
    /// The interface of ASC/trc frames (`canN`) or of Pengutronix lines, borrowed by the records.
    iface: Vec<u8>,
    /// The interface name of the last log line, validated once: the next lines (nearly always the same
    /// interface) are compared with it instead of being checked as UTF-8 again.
    last_iface: String,
    /// The seconds of the last log line's stamp, checked then: the next lines' equal seconds are not again.
    last_seconds: SecondsCache,
    /// The frame of the last line [`LineParser::parse_log_line_at`] read, rewritten in place.
    log_frame: CanFrame,
}

/// Lines of the Pengutronix-era canutils candump (`<0x18eeff01> [8] 05 a0 ...`) name no interface: this one
/// is used unless an `interface = can0, ...` header named it.
const UNNAMED_IFACE: &str = "-";

impl LineParser {
    pub fn new() -> Self {
        Self::default()
    }

    /// A parser for the format [`open_log`](super::open_log) recognised.
    pub fn for_format(format: LogFormat) -> Self {
        Self { dialect: Dialect::of(format.text), ..Self::default() }
    }

    /// Treats relative console stamps as `-t d` deltas and reports their running sum.
    pub fn with_delta_timestamps(mut self) -> Self {
        self.deltas = true;
        self
    }

    /// Forgets the running `-t d` sum (for a new file).
    pub fn reset(&mut self) {
        self.delta_sum = DeltaSum::default();
    }

    /// Parses one line. `line` has no trailing `\n`; a trailing `\r` is accepted.
    ///
    /// The result may borrow from `line` or from the parser's scratch buffer (coloured lines), hence the
    /// shared lifetime. Error columns are 1-based byte columns; for coloured lines they count the text
    /// without its colour codes.
    pub fn parse<'a>(&'a mut self, line: &'a [u8]) -> Result<Line<'a>, LineError> {
        let to_error = |(pos, reason): PosError| LineError { column: pos + 1, reason };
        match &mut self.dialect {
            Dialect::Candump => {}
            Dialect::Asc(state) => return asc::parse(line, state, &mut self.iface).map_err(to_error),
            Dialect::Trc(state) => return trc::parse(line, state, &mut self.iface).map_err(to_error),
        }
        if let Some(record) = parse_log_fast(line, &mut self.last_iface, &mut self.last_seconds) {
            self.after_error_frame = false;
            return Ok(Line::Frame(record));
        }
        let text: &'a [u8] = if memchr(0x1B, line).is_some() {
            strip_ansi(line, &mut self.scratch);
            &self.scratch
        } else {
            line
        };
        let after_error_frame = std::mem::replace(&mut self.after_error_frame, false);
        let deltas = self.deltas.then_some(&mut self.delta_sum);
        if text.first() == Some(&b'\t') {
            // candump -e continues an error frame's line with TAB-indented text; anything else that
            // starts with a TAB is read as what it is.
            let indent = text.iter().take_while(|b| matches!(b, b'\t' | b' ')).count();
            return match parse_general(&text[indent..], deltas) {
                Ok(Line::Frame(record)) => {
                    self.after_error_frame = record.frame.kind() == FrameKind::Error;
                    Ok(Line::Frame(record))
                }
                _ if after_error_frame => {
                    self.after_error_frame = true;
                    Ok(Line::ErrorText)
                }
                Ok(other) => Ok(other),
                Err((_, Reason::NotCandump)) => Err(LineError { column: 1, reason: Reason::StrayErrorText }),
                Err((pos, reason)) => Err(LineError { column: indent + pos + 1, reason }),
            };
        }
        let start = skip_spaces(text, 0);
        if text[start..].starts_with(b"<0x") {
            let frame = parse_angle_frame(text, start).map_err(to_error)?;
            let iface = match self.iface.is_empty() {
                true => UNNAMED_IFACE,
                false => std::str::from_utf8(&self.iface).unwrap_or(UNNAMED_IFACE),
            };
            return Ok(Line::Frame(Record { ts: None, iface, frame, dir: None }));
        }
        if let Some(rest) = text[start..].strip_prefix(b"interface = ") {
            // The Pengutronix candump header: "interface = can0, family = 29, type = 3, proto = 1".
            let name = &rest[..token_end(rest, 0)];
            let name = name.strip_suffix(b",").unwrap_or(name);
            if (1..=IFACE_MAX_LEN).contains(&name.len()) && name.iter().all(|b| (0x21..=0x7E).contains(b)) {
                self.iface.clear();
                self.iface.extend_from_slice(name);
                return Ok(Line::Comment);
            }
        }
        let line = parse_general(text, deltas).map_err(to_error)?;
        if let Line::Frame(record) = &line {
            self.after_error_frame = record.frame.kind() == FrameKind::Error;
        }
        Ok(line)
    }
}

/// Copies `line` into `out` without ANSI escape sequences (`ESC [ params final`; a lone ESC is dropped).
fn strip_ansi(line: &[u8], out: &mut Vec<u8>) {
    out.clear();
    let mut rest = line;
    while let Some(esc) = memchr(0x1B, rest) {
        out.extend_from_slice(&rest[..esc]);
        rest = &rest[esc + 1..];
        if rest.first() == Some(&b'[') {
            let mut end = 1;
            while let Some(0x20..=0x3F) = rest.get(end) {
                end += 1;
            }
            if let Some(0x40..=0x7E) = rest.get(end) {
                end += 1;
            }
            rest = rest.get(end..).unwrap_or_default();
        }
    }
    out.extend_from_slice(rest);
}

/// What one line leaves for the next: the interface a Pengutronix header named, whether an error frame came
/// last, and what ASC (`base dec`) and trc (`;$FILEVERSION=`, `;$COLUMNS=`) headers said about the lines
/// after them (the dialect). A log decoded in chunks starts each chunk from a guess of it and checks the guess.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CarriedState {
    pub iface: Vec<u8>,
    pub after_error_frame: bool,
    pub(crate) dialect: Dialect,
}

impl LineParser {
    /// The state the last line left (`-t d` sums are not included).
    pub fn carried(&self) -> CarriedState {
        // ASC and trc lines write their `canN` anew each time: only a Pengutronix header's name carries over.
        let iface = match self.dialect {
            Dialect::Candump => self.iface.clone(),
            Dialect::Asc(_) | Dialect::Trc(_) => Vec::new(),
        };
        CarriedState { iface, after_error_frame: self.after_error_frame, dialect: self.dialect }
    }

    /// Whether relative console stamps are summed as `-t d` deltas ([`Self::with_delta_timestamps`]).
    pub fn sums_deltas(&self) -> bool {
        self.deltas
    }

    /// The running `-t d` sum (of this parser's lines only).
    pub fn delta_sum(&self) -> DeltaSum {
        self.delta_sum
    }

    /// The common candump log line at the start of `text` (a buffer of whole lines), parsed where it stands:
    /// the record and the line's length without its `\n`, as [`LineParser::parse`] reads that line. `None`
    /// for any other line (and for every line of ASC or trc files, and a line over the [`LineLimit`]): find
    /// its end and call `parse` (or reject it as too long).
    // Always inlined into decode's line loop: out of line it cost 6.6 M instructions on 200,000 lines.
    #[inline(always)]
    pub fn parse_log_line_at(&mut self, text: &[u8]) -> Option<(LogRecord<'_>, usize)> {
        if !matches!(self.dialect, Dialect::Candump) {
            return None;
        }
        let head =
            parse_log_line_into(text, &mut self.last_iface, &mut self.last_seconds, &mut self.log_frame)?;
        // Spaces after the stamp can make a line of this shape any length; past the limit every reader
        // rejects the line whole, unparsed (and it leaves the parser's state as it was).
        if LineLimit::DEFAULT.is_over(head.length) {
            return None;
        }
        self.after_error_frame = false;
        let record = LogRecord { ts: head.ts, iface: head.iface, frame: &self.log_frame, dir: head.dir };
        Some((record, head.length))
    }

    /// Continues as if the lines that left `state` had just been parsed.
    pub fn carry_on_from(&mut self, state: &CarriedState) {
        self.iface.clone_from(&state.iface);
        self.after_error_frame = state.after_error_frame;
        // The parser keeps its format; a state of another one (a default state) starts this one's headers anew.
        self.dialect = match (self.dialect, state.dialect) {
            (Dialect::Candump, _) => Dialect::Candump,
            (Dialect::Asc(_), Dialect::Asc(asc)) => Dialect::Asc(asc),
            (Dialect::Asc(_), _) => Dialect::Asc(AscState::default()),
            (Dialect::Trc(_), Dialect::Trc(trc)) => Dialect::Trc(trc),
            (Dialect::Trc(_), _) => Dialect::Trc(TrcState::default()),
        };
    }
}

#[cfg(test)]
pub(crate) fn parse_log_fast_for_tests<'a>(line: &'a [u8]) -> Option<Record<'a>> {
    // Leaked: a test helper, so the record may outlive the cache it borrows.
    let cache = Box::leak(Box::new(String::new()));
    parse_log_fast(line, cache, &mut SecondsCache::default())
}

#[cfg(test)]
pub(crate) fn parse_general_for_tests(line: &[u8]) -> Option<Record<'_>> {
    match parse_general(line, None) {
        Ok(Line::Frame(record)) => Some(record),
        _ => None,
    }
}
