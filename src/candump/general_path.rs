//! The general path of the candump dialect: every line shape candump and its relatives write, with every
//! option (`-t a/A/d/z`, `-x`, `-a`, `-8`, `-e`, `-S`, `-i`), log lines the fast path (`fast_path.rs`) did
//! not take, console lines, drop counts and the Pengutronix canutils lines.

use memchr::memchr;

use super::cansend::{classify_id, data_frame, parse_frame_text, FrameText, IdForm};
use super::hex::{decimal_u64, hex_pair, hex_u32, hex_value, is_hex, skip_spaces, token_end};
use super::record::{Direction, Line, Record, Timestamp, TimestampKind, IFACE_MAX_LEN, RELATIVE_LIMIT_SECS};
use super::timestamp::{parse_date_time, parse_numeric, DeltaSum, PosError};
use super::Reason;
use crate::protocol::frame::{CC_MAX_LEN, EFF_MAX, FD_LENGTHS, FD_MAX_LEN, SFF_MAX};
use crate::protocol::CanFrame;

/// CAN FD flag bits as candump writes them.
const FD_BRS: u8 = 0x1;
const FD_ESI: u8 = 0x2;
const FD_FDF: u8 = 0x4;

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
pub(super) fn parse_general<'a>(text: &'a [u8], deltas: Option<&mut DeltaSum>) -> Result<Line<'a>, PosError> {
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
        Some(sum) if !stamp.dated && stamp.secs < RELATIVE_LIMIT_SECS => sum.add(stamp.secs, stamp.nanos),
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

/// A Pengutronix canutils candump line: `<0x18eeff01> [8] 05 a0 be 1c 00 a0 a0 c0 ` (`<0x123>` for
/// standard identifiers), with `remote request` for remote frames.
pub(super) fn parse_angle_frame(text: &[u8], start: usize) -> Result<CanFrame, PosError> {
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
