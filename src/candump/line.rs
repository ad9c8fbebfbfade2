//! One line of candump text, in either the log format or the console format, detected per line.

use memchr::memchr;

use super::asc::{self, AscState};
use super::cansend::{classify_id, data_frame, parse_frame_text, FrameText, IdForm};
use super::hex::{
    decimal_u64, hex_bytes_8, hex_pair, hex_u32, hex_value, is_hex, same_bytes, skip_spaces, token_end,
};
use super::line_limit::LineLimit;
use super::open::{LogFormat, TextFormat};
use super::timestamp::{
    parse_date_time, parse_numeric, parse_numeric_cached, DeltaSum, PosError, SecondsCache,
};
use super::trc::{self, TrcState};
use super::{LineError, Reason, Timestamp, TimestampKind};
use crate::protocol::frame::{FrameKind, CC_MAX_LEN, EFF_MAX, FD_LENGTHS, FD_MAX_LEN, SFF_MAX};
use crate::protocol::CanFrame;

/// Longest interface name (IFNAMSIZ - 1).
const IFACE_MAX_LEN: usize = 15;
/// CAN FD flag bits as candump writes them.
const FD_BRS: u8 = 0x1;
const FD_ESI: u8 = 0x2;
const FD_FDF: u8 = 0x4;

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

/// A common log line read where it stands ([`LineParser::parse_log_line_at`]): the frame stays in the
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
    format: TextFormat,
    after_error_frame: bool,
    /// The interface of ASC/trc frames (`canN`) or of Pengutronix lines, borrowed by the records.
    iface: Vec<u8>,
    asc: AscState,
    trc: TrcState,
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
        let trc = match format.text {
            TextFormat::PeakTrc { version } => TrcState::for_version(version),
            _ => TrcState::default(),
        };
        Self { format: format.text, trc, ..Self::default() }
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
        match self.format {
            TextFormat::Candump => {}
            TextFormat::VectorAsc => {
                return asc::parse(line, &mut self.asc, &mut self.iface).map_err(to_error)
            }
            TextFormat::PeakTrc { .. } => {
                return trc::parse(line, &mut self.trc, &mut self.iface).map_err(to_error)
            }
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

/// A Pengutronix canutils candump line: `<0x18eeff01> [8] 05 a0 be 1c 00 a0 a0 c0 ` (`<0x123>` for
/// standard identifiers), with `remote request` for remote frames.
fn parse_angle_frame(text: &[u8], start: usize) -> Result<CanFrame, PosError> {
    let text = trim_end(text);
    let id_start = start + 3;
    let close = memchr(b'>', &text[id_start..]).map(|i| id_start + i).ok_or((start, Reason::NotCandump))?;
    let digits = &text[id_start..close];
    if digits.is_empty() || digits.len() > 8 {
        return Err((id_start, Reason::IdLength));
    }
    let id = hex_u32(digits).ok_or((id_start, Reason::NotHex))?;
    let extended = digits.len() > 3 || id > SFF_MAX;
    if id > EFF_MAX {
        return Err((id_start, Reason::IdTooLarge));
    }
    let len_start = skip_spaces(text, close + 1);
    if len_start == close + 1 {
        return Err((len_start, Reason::ExpectedSpace));
    }
    let len = match parse_length_field(text, len_start)? {
        (Length::Classic { len, raw_dlc: None }, after) => (len, after),
        _ => return Err((len_start, Reason::BadLength)),
    };
    let (len, after) = len;
    let body = skip_spaces(text, after);
    if matches!(&text[body..], b"remote request" | b"rtr") {
        return CanFrame::new_remote(id, extended, len as u8).map_err(|e| (len_start, e.into()));
    }
    let mut data = [0u8; CC_MAX_LEN];
    let mut pos = after;
    for slot in &mut data[..len] {
        let start = skip_spaces(text, pos);
        let end = token_end(text, start);
        *slot = match &text[start..end] {
            [] => return Err((start, Reason::LengthMismatch)),
            [hi, lo] if start > pos => hex_pair(*hi, *lo).ok_or((start, Reason::ConsoleByte))?,
            _ => return Err((start, Reason::ConsoleByte)),
        };
        pos = end;
    }
    if pos < text.len() {
        return Err((skip_spaces(text, pos), Reason::LengthMismatch));
    }
    let frame =
        if extended { CanFrame::new_extended(id, &data[..len]) } else { CanFrame::new(id, &data[..len]) };
    frame.map_err(|e| (len_start, e.into()))
}

/// The fast path for the common log line `(1700000000.002500) can0 211#00000103000000B1[ R]`: standard
/// or extended data frames of 0-8 bytes without separators. Returns `None` for anything else (including
/// errors), leaving the line to the general path, which must give the same result for lines accepted here.
#[inline]
fn parse_log_fast<'a>(
    line: &[u8],
    last_iface: &'a mut String,
    last_seconds: &mut SecondsCache,
) -> Option<Record<'a>> {
    // A line holds no `\n`, so the line ends where the text does.
    let mut frame = CanFrame::default();
    let head = parse_log_line_into(line, last_iface, last_seconds, &mut frame)?;
    Some(Record { ts: head.ts, iface: head.iface, frame, dir: head.dir })
}

/// What [`parse_log_line_into`] read besides the frame.
struct LogHead<'a> {
    ts: Option<Timestamp>,
    iface: &'a str,
    dir: Option<Direction>,
    /// The line's length without its `\n`.
    length: usize,
}

/// [`parse_log_fast`] on the line at the start of `line`, which may go on past the line's `\n`: the line is
/// found by parsing it, so a buffer of lines needs no search for each line's end. Writes the frame into
/// `frame` (left as it was when the line is not taken) and returns the rest.
#[inline(always)]
fn parse_log_line_into<'a>(
    line: &[u8],
    last_iface: &'a mut String,
    last_seconds: &mut SecondsCache,
    frame: &mut CanFrame,
) -> Option<LogHead<'a>> {
    if line.first() != Some(&b'(') {
        return None;
    }
    let (secs, nanos, after_ts) = parse_numeric_cached(line, 1, last_seconds).ok()?;
    if line.get(after_ts) != Some(&b' ') {
        return None;
    }
    let iface_start = skip_spaces(line, after_ts + 1);
    // The last line's interface (1..=15 printable bytes, checked then) followed by a space: the scan
    // below would stop at that space, so the name is that one.
    let last_end = iface_start + last_iface.len();
    let (pos, iface) = match line.get(iface_start..last_end) {
        Some(name)
            if !last_iface.is_empty()
                && same_bytes(name, last_iface.as_bytes())
                && line.get(last_end) == Some(&b' ') =>
        {
            (last_end, last_iface.as_str())
        }
        _ => {
            let mut pos = iface_start;
            while let Some(0x21..=0x7E) = line.get(pos) {
                pos += 1;
            }
            if pos == iface_start || pos - iface_start > IFACE_MAX_LEN || line.get(pos) != Some(&b' ') {
                return None;
            }
            (pos, same_iface(last_iface, &line[iface_start..pos])?)
        }
    };
    let id_start = pos + 1;
    let (id, extended, mut pos) = if line.get(id_start + 3) == Some(&b'#') {
        let id = hex3(line.get(id_start..id_start + 3)?)?;
        (id, false, id_start + 4)
    } else if line.get(id_start + 8) == Some(&b'#') {
        let digits = line.get(id_start..id_start + 8)?;
        let id = digits.iter().try_fold(0u32, |acc, &b| Some((acc << 4) | u32::from(hex_value(b)?)))?;
        (id, true, id_start + 9)
    } else {
        return None;
    };
    if id > if extended { EFF_MAX } else { SFF_MAX } {
        return None; // error frames and out-of-range ids: the general path decides
    }
    let mut data = [0u8; CC_MAX_LEN];
    let mut len = 0;
    // A full 8-byte payload (most frames) in one step; anything else byte by byte below.
    if let Some(digits) = line.get(pos..pos + 2 * CC_MAX_LEN) {
        if matches!(line.get(pos + 2 * CC_MAX_LEN), None | Some(b' ' | b'\r' | b'\n')) {
            data = hex_bytes_8(digits.try_into().ok()?)?;
            len = CC_MAX_LEN;
            pos += 2 * CC_MAX_LEN;
        }
    }
    while let Some(&hi) = line.get(pos) {
        if matches!(hi, b' ' | b'\r' | b'\n') {
            break;
        }
        if len == CC_MAX_LEN {
            return None;
        }
        data[len] = hex_pair(hi, *line.get(pos + 1)?)?;
        len += 1;
        pos += 2;
    }
    let (dir, length) = log_line_end(line, pos)?;
    frame.set_classic_data(id, extended, data, len).ok()?;
    Some(LogHead { ts: Some(Timestamp::from_numeric(secs, nanos)), iface, dir, length })
}

/// The end of a fast-path line after its data at `pos`: an optional direction and an optional `\r`, then the
/// text's end or a `\n`. Returns the direction and the line's length without the `\n`.
#[inline(always)]
fn log_line_end(line: &[u8], pos: usize) -> Option<(Option<Direction>, usize)> {
    let (dir, rest) = match line.get(pos..)? {
        [b' ', b'R', rest @ ..] => (Some(Direction::Rx), rest),
        [b' ', b'T', rest @ ..] => (Some(Direction::Tx), rest),
        rest => (None, rest),
    };
    let after = line.len() - rest.len();
    match rest {
        [] | [b'\n', ..] => Some((dir, after)),
        [b'\r'] | [b'\r', b'\n', ..] => Some((dir, after + 1)),
        _ => None,
    }
}

/// The interface `name` as text, through `last` (the previous line's): equal names (the usual case) need no
/// UTF-8 check; a new one is checked and kept. `None` if it is not UTF-8.
#[inline(always)]
fn same_iface<'a>(last: &'a mut String, name: &[u8]) -> Option<&'a str> {
    if !same_bytes(last.as_bytes(), name) {
        let name = std::str::from_utf8(name).ok()?;
        last.clear();
        last.push_str(name);
    }
    Some(last.as_str())
}

#[inline(always)]
fn hex3(digits: &[u8]) -> Option<u32> {
    match digits {
        [a, b, c] => {
            let (a, b, c) = (hex_value(*a)?, hex_value(*b)?, hex_value(*c)?);
            Some((u32::from(a) << 8) | (u32::from(b) << 4) | u32::from(c))
        }
        _ => None,
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

/// A parsed `(...)` stamp before it is classified.
#[derive(Clone, Copy)]
struct RawStamp {
    secs: u64,
    nanos: u32,
    /// `-t A` wall-clock form: always absolute.
    dated: bool,
}

impl RawStamp {
    fn classify(self) -> Timestamp {
        match self.dated {
            true => Timestamp { secs: self.secs, nanos: self.nanos, kind: TimestampKind::Absolute },
            false => Timestamp::from_numeric(self.secs, self.nanos),
        }
    }
}

/// Every line shape: comments, drop counts, log lines (any variant), console lines.
fn parse_general<'a>(text: &'a [u8], deltas: Option<&mut DeltaSum>) -> Result<Line<'a>, PosError> {
    if text.first() == Some(&b'\t') {
        return Ok(Line::ErrorText);
    }
    let text = trim_end(text);
    let start = skip_spaces(text, 0);
    let Some(&first) = text.get(start) else {
        return Ok(Line::Blank);
    };
    match first {
        b'#' | b';' => return Ok(Line::Comment),
        b'D' if text[start..].starts_with(b"DROPCOUNT:") => return parse_dropcount(text, start),
        _ => {}
    }

    let (stamp, iface_start) = if first == b'(' { parse_stamp(text, start)? } else { (None, start) };

    let iface_end = token_end(text, iface_start);
    let next = skip_spaces(text, iface_end);
    if next == text.len() {
        // A single field: not enough for any candump line.
        let field = &text[iface_start..iface_end];
        return Err(match stamp {
            // A bare `211#00...` (cansend syntax) lacks only the interface name.
            _ if memchr(b'#', field).is_some() => (iface_start, Reason::MissingInterface),
            None => (start, Reason::NotCandump),
            Some(_) => (next, Reason::MissingFrame),
        });
    }
    let next_end = token_end(text, next);
    let field = &text[next..next_end];

    // Log format: the field after the interface is the frame.
    if memchr(b'#', field).is_some() {
        let iface = check_iface(text, iface_start, iface_end)?;
        return log_frame(text, stamp, iface, next, next_end);
    }

    // Console format: [RX|TX flag flag] id [len] bytes...
    let (dir, fd_bits, id_start) = console_prefix(text, start, next, next_end)?;
    let iface = check_iface(text, iface_start, iface_end)?;
    let ts = stamp.map(|stamp| match deltas {
        Some(sum) if !stamp.dated && stamp.secs < super::RELATIVE_LIMIT_SECS => {
            sum.add(stamp.secs, stamp.nanos)
        }
        _ => stamp.classify(),
    });
    Ok(match parse_console_frame(text, id_start, fd_bits)? {
        FrameText::Can(frame) => Line::Frame(Record { ts, iface, frame, dir }),
        FrameText::Xl => Line::CanXl,
    })
}

/// The `(...)` timestamp at `start` (seconds, or a date and time with `-ta`); returns it and where the
/// interface starts.
#[inline]
fn parse_stamp(text: &[u8], start: usize) -> Result<(Option<RawStamp>, usize), PosError> {
    let open = start + 1;
    let dated = matches!(text.get(open..open + 5), Some([a, b, c, d, b'-'])
        if [a, b, c, d].iter().all(|x| x.is_ascii_digit()));
    let (secs, nanos, end) = match dated {
        true => parse_date_time(text, open)?,
        false => parse_numeric(text, open)?,
    };
    match text.get(end) {
        Some(b' ') => {}
        Some(_) => return Err((end, Reason::ExpectedSpace)),
        None => return Err((end, Reason::MissingInterface)),
    }
    Ok((Some(RawStamp { secs, nanos, dated }), skip_spaces(text, end)))
}

/// The rest of a log-format line: the frame field at `next..next_end` and an optional `R`/`T` direction.
#[inline]
fn log_frame<'a>(
    text: &'a [u8],
    stamp: Option<RawStamp>,
    iface: &'a str,
    next: usize,
    next_end: usize,
) -> Result<Line<'a>, PosError> {
    let frame = parse_frame_text(&text[next..next_end]).map_err(|(pos, reason)| (next + pos, reason))?;
    let dir = match &text[skip_spaces(text, next_end)..] {
        [] => None,
        b"R" => Some(Direction::Rx),
        b"T" => Some(Direction::Tx),
        _ => return Err((skip_spaces(text, next_end), Reason::TrailingGarbage)),
    };
    Ok(match frame {
        FrameText::Can(frame) => Line::Frame(Record { ts: stamp.map(RawStamp::classify), iface, frame, dir }),
        FrameText::Xl => Line::CanXl,
    })
}

/// The start of a console frame after the interface (the field at `next..next_end`): `RX`/`TX` with the
/// `-x` columns, or directly the identifier before a `[len]`/`{F}`. Returns the direction, the FD flag bits
/// and where the identifier starts.
#[inline]
fn console_prefix(
    text: &[u8],
    start: usize,
    next: usize,
    next_end: usize,
) -> Result<(Option<Direction>, u8, usize), PosError> {
    let field = &text[next..next_end];
    if let b"RX" | b"TX" = field {
        let (fd_bits, id_start) = parse_message_info(text, next_end)?;
        let dir = if field == b"RX" { Direction::Rx } else { Direction::Tx };
        return Ok((Some(dir), fd_bits, id_start));
    }
    let len_field = skip_spaces(text, next_end);
    if !matches!(text.get(len_field), Some(b'[' | b'{')) {
        // Neither shape: a hex field is most likely a log frame that lost its '#'.
        return Err(match field.iter().all(|&b| is_hex(b)) {
            true => (next_end, Reason::MissingHash),
            false => (start, Reason::NotCandump),
        });
    }
    Ok((None, 0, next))
}

fn trim_end(text: &[u8]) -> &[u8] {
    let mut end = text.len();
    while end > 0 && matches!(text[end - 1], b' ' | b'\r' | b'\n') {
        end -= 1;
    }
    &text[..end]
}

/// Validates an interface name: 1..=15 printable ASCII characters.
fn check_iface(text: &[u8], start: usize, end: usize) -> Result<&str, PosError> {
    let name = &text[start..end];
    if let Some(bad) = name.iter().position(|b| !(0x21..=0x7E).contains(b)) {
        return Err((start + bad, Reason::BadInterface));
    }
    if name.len() > IFACE_MAX_LEN {
        return Err((start, Reason::InterfaceTooLong));
    }
    std::str::from_utf8(name).map_err(|_| (start, Reason::BadInterface))
}

/// The `-x` columns after `RX`/`TX`: `- -`, `B -`, `- E`, `B E` (and CAN XL's `S`/`R`). Returns the FD flag
/// bits they stand for and where the identifier starts.
fn parse_message_info(text: &[u8], after_dir: usize) -> Result<(u8, usize), PosError> {
    let mut bits = 0;
    let mut pos = after_dir;
    for (allowed, flag) in [(b"-BS", FD_BRS), (b"-ER", FD_ESI)] {
        let start = skip_spaces(text, pos);
        let end = token_end(text, start);
        match text.get(start..end) {
            Some(&[column]) if start > pos && allowed.contains(&column) => {
                if matches!(column, b'B' | b'E') {
                    bits |= flag;
                }
            }
            _ => return Err((start, Reason::BadMessageInfo)),
        }
        pos = end;
    }
    Ok((bits, skip_spaces(text, pos)))
}

/// The console frame: `151   [8]  00 01 ...`, `12345678  [64]  ...`, `151   [0]  remote request`,
/// `151   {F}  ...`, `20000004   [8]  ...   ERRORFRAME`, `123 [0003] (...) ...` (CAN XL).
fn parse_console_frame(text: &[u8], id_start: usize, fd_bits: u8) -> Result<FrameText, PosError> {
    let id_end = token_end(text, id_start);
    let id_digits = &text[id_start..id_end];
    if let Some(bad) = id_digits.iter().position(|&b| !is_hex(b)) {
        return Err((id_start + bad, Reason::NotHex));
    }
    let (id, form) = match id_digits.len() {
        3 | 8 => classify_id(id_digits).map_err(|(_, reason)| (id_start, reason))?,
        _ => return Err((id_start, Reason::IdLength)),
    };
    let len_start = skip_spaces(text, id_end);
    let (length, after) = parse_length_field(text, len_start)?;

    let (len, raw_dlc, fd) = match length {
        Length::Xl => return Ok(FrameText::Xl),
        Length::Classic { len, raw_dlc } => (len, raw_dlc, false),
        Length::Fd(len) => (len, None, true),
    };
    let body = skip_spaces(text, after);
    if !fd && text[body..].starts_with(b"remote request") {
        return remote_request(text, body, (id, form), len, raw_dlc, len_start);
    }

    let mut data = [0u8; FD_MAX_LEN];
    let mut pos = after;
    let view = match other_byte_view(text, after, &mut data[..len])? {
        Some(end) => {
            pos = end;
            0
        }
        None => len,
    };
    for slot in data.iter_mut().take(view) {
        (*slot, pos) = console_byte(text, pos)?;
    }
    check_console_tail(text, pos, form)?;

    let frame = if fd {
        if form == IdForm::Error {
            return Err((len_start, Reason::ErrorFrameNotData));
        }
        // Without -x the two-digit length is the only FD marker: report FDF, as candump -L >= 2025.01 does.
        CanFrame::new_fd(id, form.is_extended(), FD_FDF | fd_bits, &data[..len])
            .map_err(|e| (len_start, e.into()))?
    } else {
        data_frame(id, form, &data[..len]).map_err(|reason| (len_start, reason))?
    };
    with_raw_dlc(frame, raw_dlc, len_start)
}

/// `151   [0]  remote request`: a remote frame (never an error frame), nothing after it.
#[inline]
fn remote_request(
    text: &[u8],
    body: usize,
    (id, form): (u32, IdForm),
    len: usize,
    raw_dlc: Option<u8>,
    len_start: usize,
) -> Result<FrameText, PosError> {
    if form == IdForm::Error {
        return Err((body, Reason::ErrorFrameNotData));
    }
    let end = body + b"remote request".len();
    if end < text.len() {
        return Err((skip_spaces(text, end), Reason::TrailingGarbage));
    }
    let frame = CanFrame::new_remote(id, form.is_extended(), len as u8).map_err(|e| (len_start, e.into()))?;
    with_raw_dlc(frame, raw_dlc, len_start)
}

/// One data byte of a console frame at `pos`, and where it ends. candump's own layout, " HH", first;
/// anything else goes through the tolerant scan.
#[inline]
fn console_byte(text: &[u8], pos: usize) -> Result<(u8, usize), PosError> {
    if let Some(&[b' ', hi, lo]) = text.get(pos..pos + 3) {
        if let Some(byte) = hex_pair(hi, lo) {
            if matches!(text.get(pos + 3), None | Some(b' ')) {
                return Ok((byte, pos + 3));
            }
        }
    }
    let start = skip_spaces(text, pos);
    let end = token_end(text, start);
    let column = &text[start..end];
    if column.is_empty() {
        return Err((start, Reason::LengthMismatch));
    }
    if start == pos {
        return Err((start, Reason::ExpectedSpace));
    }
    let byte = match column {
        [hi, lo] => hex_pair(*hi, *lo),
        _ => None,
    };
    let Some(byte) = byte else {
        return Err(match column {
            // The ASCII column or the error tag came early: fewer bytes than the length says.
            [b'\'', ..] | b"ERRORFRAME" => (start, Reason::LengthMismatch),
            _ => (start, Reason::ConsoleByte),
        });
    };
    Ok((byte, end))
}

/// candump's `-S` (bytes in reverse order, joined by backticks: ``B1`00`03``) and `-i` (each byte as 8
/// binary digits) views. Fills `out` and returns where the bytes end, or `None` for the ordinary view.
fn other_byte_view(text: &[u8], after: usize, out: &mut [u8]) -> Result<Option<usize>, PosError> {
    let start = skip_spaces(text, after);
    let len = out.len();
    if start == after || len == 0 {
        return Ok(None);
    }
    if len >= 2 && text.get(start + 2) == Some(&b'`') {
        let mut pos = start;
        for index in (0..len).rev() {
            if index + 1 < len {
                if text.get(pos) != Some(&b'`') {
                    return Err((pos, Reason::LengthMismatch));
                }
                pos += 1;
            }
            let pair = text.get(pos..pos + 2).ok_or((pos, Reason::LengthMismatch))?;
            out[index] = hex_pair(pair[0], pair[1]).ok_or((pos, Reason::ConsoleByte))?;
            pos += 2;
        }
        return Ok(Some(pos));
    }
    let is_bits = |at: usize| {
        text.get(at..at + 8).is_some_and(|bits| bits.iter().all(|b| matches!(b, b'0' | b'1')))
            && matches!(text.get(at + 8), None | Some(b' '))
    };
    if !is_bits(start) {
        return Ok(None);
    }
    let mut pos = start;
    for (index, slot) in out.iter_mut().enumerate() {
        if index > 0 {
            if text.get(pos) != Some(&b' ') || !is_bits(pos + 1) {
                return Err((pos, Reason::LengthMismatch));
            }
            pos += 1;
        }
        *slot = text[pos..pos + 8].iter().fold(0u8, |acc, &bit| (acc << 1) | (bit - b'0'));
        pos += 8;
    }
    Ok(Some(pos))
}

fn with_raw_dlc(frame: CanFrame, raw_dlc: Option<u8>, pos: usize) -> Result<FrameText, PosError> {
    match raw_dlc {
        Some(dlc) => frame.with_raw_dlc(dlc).map(FrameText::Can).map_err(|e| (pos, e.into())),
        None => Ok(FrameText::Can(frame)),
    }
}

/// What follows the data bytes: nothing, the `-a` ASCII column `'...'`, or `ERRORFRAME` on error frames.
fn check_console_tail(text: &[u8], pos: usize, form: IdForm) -> Result<(), PosError> {
    let start = skip_spaces(text, pos);
    let tail = &text[start..];
    // -a's ASCII column: '...' (or `...` with -S).
    let quoted = |quote: u8| tail.len() >= 2 && tail.first() == Some(&quote) && tail.last() == Some(&quote);
    let ascii = quoted(b'\'') || quoted(b'`');
    let error_tag = tail == b"ERRORFRAME" && form == IdForm::Error;
    if tail.is_empty() || (start > pos && (ascii || error_tag)) {
        return Ok(());
    }
    let looks_like_byte =
        matches!(tail, [a, b, ..] if is_hex(*a) && is_hex(*b)) && token_end(text, start) == start + 2;
    Err(match looks_like_byte {
        true => (start, Reason::LengthMismatch),
        false => (start, Reason::TrailingGarbage),
    })
}

/// A console length field.
enum Length {
    /// `[0]`..`[8]`, or `{0}`..`{F}` with `-8` (length min(dlc, 8), raw DLC when 9..F).
    Classic { len: usize, raw_dlc: Option<u8> },
    /// `[00]`..`[64]`: a CAN FD frame.
    Fd(usize),
    /// `[0000]`: a CAN XL frame.
    Xl,
}

/// Parses the length field at `pos`; returns it and the index just past its closing bracket.
fn parse_length_field(text: &[u8], pos: usize) -> Result<(Length, usize), PosError> {
    match text.get(pos) {
        Some(b'[') => {
            let (value, digits) = decimal_u64(text, pos + 1);
            let close = pos + 1 + digits;
            if text.get(close) != Some(&b']') {
                return Err((pos, Reason::BadLength));
            }
            let length = match (digits, value) {
                (1, len @ 0..=8) => Length::Classic { len: len as usize, raw_dlc: None },
                (2, len) if len <= 64 && FD_LENGTHS.contains(&(len as u8)) => Length::Fd(len as usize),
                (2, _) => return Err((pos, Reason::BadFdLength)),
                (4, _) => Length::Xl,
                _ => return Err((pos, Reason::BadLength)),
            };
            Ok((length, close + 1))
        }
        Some(b'{') => {
            let dlc = text.get(pos + 1).and_then(|&b| hex_value(b));
            match (dlc, text.get(pos + 2)) {
                (Some(dlc), Some(b'}')) => {
                    let len = usize::from(dlc).min(CC_MAX_LEN);
                    Ok((Length::Classic { len, raw_dlc: (dlc > 8).then_some(dlc) }, pos + 3))
                }
                _ => Err((pos, Reason::BadLength)),
            }
        }
        _ => Err((pos, Reason::BadLength)),
    }
}

/// `DROPCOUNT: dropped N CAN frame[s] on 'can0' socket (total drops M)`.
fn parse_dropcount(text: &[u8], start: usize) -> Result<Line<'static>, PosError> {
    const PREFIX: &[u8] = b"DROPCOUNT: dropped ";
    if !text[start..].starts_with(PREFIX) {
        return Err((start, Reason::BadDropCount));
    }
    let mut pos = start + PREFIX.len();
    // candump prints the u32 count with %d, so counts of 2^31 and more appear negative.
    let negative = text.get(pos) == Some(&b'-');
    pos += usize::from(negative);
    let (count, digits) = decimal_u64(text, pos);
    if digits == 0 || !text[pos + digits..].starts_with(b" CAN frame") {
        return Err((pos, Reason::BadDropCount));
    }
    let dropped = match negative {
        false => count,
        true if (1..=1 << 31).contains(&count) => (1u64 << 32) - count,
        true => return Err((pos, Reason::BadDropCount)),
    };
    Ok(Line::DropCount { dropped })
}

/// What one line leaves for the next: the interface a Pengutronix header named, whether an error frame came
/// last, and what ASC (`base dec`) and trc (`;$FILEVERSION=`, `;$COLUMNS=`) headers said about the lines
/// after them. A log decoded in chunks starts each chunk from a guess of it and checks the guess.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CarriedState {
    pub iface: Vec<u8>,
    pub after_error_frame: bool,
    pub(crate) asc: AscState,
    pub(crate) trc: TrcState,
}

impl LineParser {
    /// The state the last line left (`-t d` sums are not included).
    pub fn carried(&self) -> CarriedState {
        // ASC and trc lines write their `canN` anew each time: only a Pengutronix header's name carries over.
        let iface = match self.format {
            TextFormat::Candump => self.iface.clone(),
            TextFormat::VectorAsc | TextFormat::PeakTrc { .. } => Vec::new(),
        };
        CarriedState { iface, after_error_frame: self.after_error_frame, asc: self.asc, trc: self.trc }
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
        if self.format != TextFormat::Candump {
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
        self.asc = state.asc;
        self.trc = state.trc;
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
