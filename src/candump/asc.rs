//! Vector ASC text logs (CANalyzer/CANoe, python-can's ASCWriter, can-utils' `log2asc`).
//!
//! ```text
//! date Sam Sep 30 15:06:13.191 2017                  header lines: Comment
//! base hex  timestamps absolute
//! Begin Triggerblock ...
//!    0.000000 Start of measurement                    events that are not frames: Comment
//!    1.015991 1  Statistic: D 0 R 0 ...
//!    2.501000 1 ErrorFrame                            error frames: ErrorText
//!    3.098426 1  18EBFF00x       Rx d 8 01 A0 ...     classic frame (x: extended id)
//!    2.510001 2 100 Tx r                              remote frame
//!   30.005071 CANFD   2 Rx  300  Name  1 0 8  8 01 ... duration length flags ...   CAN FD (or classic, by flags)
//! ```
//!
//! Stamps are seconds since the start of the measurement; the `date` line (and a `Begin Triggerblock` line
//! that names a date) says when that was, in the recording machine's local time: the stamps are then on the
//! clock (absolute, the date converted with the local time zone, `TZ`, as python-can's
//! `ASCReader(relative_timestamp=False)` does), so a log lines up with candump logs of the same day; without
//! a date they stay relative. Channel `N` becomes the interface `canN`. `ErrorFrame`
//! lines are error frames, written as python-can writes them to candump logs: a bus error (`20000080#` and
//! eight zero bytes), the ASC line saying nothing more.

use super::hex::{decimal_time, decimal_u64, fields, hex_u32, hex_value};
use super::record::{Direction, Line, Record, Timestamp};
use super::timestamp::PosError;
use super::Reason;
use crate::protocol::frame::{CC_MAX_LEN, EFF_MAX, FD_LENGTHS, FD_MAX_LEN, SFF_MAX};
use crate::protocol::CanFrame;

/// CAN FD message flags (the 3rd column after the data): extended data length (an FD frame), remote frame.
const FLAG_EDL: u32 = 0x1000;
const FLAG_REMOTE: u32 = 0x10;
const FD_FDF: u8 = 0x4;
const FD_BRS: u8 = 0x1;
const FD_ESI: u8 = 0x2;

/// What the header said that changes how frames read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct AscState {
    /// `base dec`: identifiers and data bytes are decimal.
    decimal: bool,
    /// When the measurement started (the `date` line), in seconds and nanoseconds since the epoch.
    start: Option<(u64, u32)>,
}

/// The error class of an ASC error frame: a bus error, as python-can writes it (`CAN_ERR_BUSERROR`).
const BUS_ERROR: u32 = 0x80;

pub(crate) fn parse<'a>(
    text: &'a [u8],
    state: &mut AscState,
    iface: &'a mut Vec<u8>,
) -> Result<Line<'a>, PosError> {
    let text = text.strip_suffix(b"\r").unwrap_or(text);
    let mut fields = fields(text);
    let Some((start, first)) = fields.next() else {
        return Ok(Line::Blank);
    };
    let Some((secs, nanos)) = decimal_time(first, 1_000_000_000) else {
        return header_line(first, fields, state).ok_or((start, Reason::NotAsc));
    };
    let ts = Timestamp::since_start(secs, nanos, state.start);
    let (at, second) = fields.next().ok_or((text.len(), Reason::NotAsc))?;
    match second {
        b"CANFD" => {
            let (at, channel) = fields.next().ok_or((text.len(), Reason::NotAsc))?;
            let iface = channel_iface(iface, channel).ok_or((at, Reason::NotAsc))?;
            fd_frame(ts, iface, fields, text.len(), *state)
        }
        // "CAN 1 Status:chip status error active", "Start of measurement", and other non-frame events.
        b"CAN" | b"Start" | b"Trigger" | b"Log" | b"SV:" => Ok(Line::Comment),
        channel if channel.iter().all(u8::is_ascii_digit) => {
            let iface = channel_iface(iface, channel).ok_or((at, Reason::NotAsc))?;
            classic_frame(ts, iface, fields, text.len(), *state)
        }
        _ => Err((at, Reason::AscEvent)),
    }
}

/// The lines before and between the events. `None`: not ASC at all.
fn header_line<'f>(
    first: &[u8],
    mut fields: impl Iterator<Item = (usize, &'f [u8])>,
    state: &mut AscState,
) -> Option<Line<'static>> {
    let second = fields.next().map(|(_, field)| field);
    match first {
        b"base" => {
            state.decimal = second == Some(b"dec");
            Some(Line::Comment)
        }
        // `date Sat Sep 30 15:06:13.191 2017`: the weekday (in any language) is the second field.
        b"date" => {
            state.start = wall_clock(fields).or(state.start);
            Some(Line::Comment)
        }
        // `Begin Triggerblock Sat Sep 30 15:06:13.191 2017`: the block's stamps count from there.
        b"Begin" if second == Some(b"Triggerblock") => {
            let mut fields = fields.skip(1);
            state.start = wall_clock(&mut fields).or(state.start);
            Some(Line::Comment)
        }
        b"internal" | b"no" | b"Begin" | b"End" => Some(Line::Comment),
        _ if first.starts_with(b"//") => Some(Line::Comment),
        _ => None,
    }
}

/// `Sep 30 15:06:13.191 2017` or `Sep 30 03:06:13 pm 2017` (months in English or German, as CANoe writes
/// them), local time, as seconds and nanoseconds since the epoch.
fn wall_clock<'f>(mut fields: impl Iterator<Item = (usize, &'f [u8])>) -> Option<(u64, u32)> {
    const MONTHS: [&[u8]; 16] = [
        b"Jan",
        b"Feb",
        b"Mar",
        b"Apr",
        b"May",
        b"Jun",
        b"Jul",
        b"Aug",
        b"Sep",
        b"Oct",
        b"Nov",
        b"Dec",
        "M\u{e4}r".as_bytes(),
        b"Mai",
        b"Okt",
        b"Dez",
    ];
    const GERMAN: [u32; 4] = [3, 5, 10, 12];
    let mut next = || fields.next().map(|(_, field)| field);
    let month = next()?;
    let month = MONTHS.iter().position(|&name| name == month)?;
    let month = if month < 12 { month as u32 + 1 } else { GERMAN[month - 12] };
    let number = |field: &[u8]| {
        let (value, digits) = decimal_u64(field, 0);
        (digits == field.len() && digits > 0).then_some(value)
    };
    let day = number(next()?)?;
    let mut clock = next()?.split(|&b| b == b':');
    let (hour, minute) = (number(clock.next()?)?, number(clock.next()?)?);
    let (second, nanos) = decimal_time(clock.next()?, 1_000_000_000)?;
    let mut year = next()?;
    let hour = match year {
        b"am" | b"AM" => Some(hour % 12),
        b"pm" | b"PM" => Some(hour % 12 + 12),
        _ => None,
    }
    .map_or(Some(hour), |hour| {
        year = next()?;
        Some(hour)
    })?;
    let civil = [number(year)?, u64::from(month), day, hour, minute, second];
    Some((super::timestamp::local_to_epoch(civil)?, nanos))
}

/// `canN` for channel `N` (1 to 3 digits), written into the parser's buffer.
pub(crate) fn channel_iface<'a>(buf: &'a mut Vec<u8>, channel: &[u8]) -> Option<&'a str> {
    if channel.is_empty() || channel.len() > 3 || !channel.iter().all(u8::is_ascii_digit) {
        return None;
    }
    buf.clear();
    buf.extend_from_slice(b"can");
    buf.extend_from_slice(channel);
    std::str::from_utf8(buf).ok()
}

/// `ID[x]`: hex (or decimal with `base dec`); `x` marks an extended identifier.
fn identifier(token: &[u8], decimal: bool) -> Option<(u32, bool)> {
    let (digits, extended) = match token.strip_suffix(b"x").or_else(|| token.strip_suffix(b"X")) {
        Some(digits) => (digits, true),
        None => (token, false),
    };
    let id = match decimal {
        true => {
            let (value, count) = decimal_u64(digits, 0);
            (count == digits.len() && count > 0).then_some(u32::try_from(value).ok()?)?
        }
        false => (!digits.is_empty() && digits.len() <= 8).then(|| hex_u32(digits))??,
    };
    (id <= if extended { EFF_MAX } else { SFF_MAX }).then_some((id, extended))
}

fn byte(token: &[u8], decimal: bool) -> Option<u8> {
    match (decimal, token) {
        (false, [hi, lo]) => Some((hex_value(*hi)? << 4) | hex_value(*lo)?),
        (false, [lo]) => hex_value(*lo),
        (true, _) => {
            let (value, count) = decimal_u64(token, 0);
            (count == token.len() && count > 0).then_some(u8::try_from(value).ok()?)
        }
        _ => None,
    }
}

fn direction(token: &[u8]) -> Option<Direction> {
    match token {
        b"Rx" => Some(Direction::Rx),
        b"Tx" | b"TxRq" => Some(Direction::Tx),
        _ => None,
    }
}

/// `ID[x] Rx|Tx d DLC bytes... [Length = ...]` or `ID[x] Rx|Tx r [DLC]`, after the channel.
fn classic_frame<'a, 'f>(
    ts: Timestamp,
    iface: &'a str,
    mut fields: impl Iterator<Item = (usize, &'f [u8])>,
    end: usize,
    state: AscState,
) -> Result<Line<'a>, PosError> {
    let (at, id_token) = fields.next().ok_or((end, Reason::AscFrame))?;
    match id_token {
        b"ErrorFrame" => return error_frame(ts, iface, at),
        b"Statistic:" | b"J1939TP" | b"Status:" => return Ok(Line::Comment),
        _ => {}
    }
    let (id, extended) = identifier(id_token, state.decimal).ok_or((at, Reason::AscFrame))?;
    let (at, dir) = fields.next().ok_or((end, Reason::AscFrame))?;
    let dir = direction(dir).ok_or((at, Reason::AscFrame))?;
    let (at, kind) = fields.next().ok_or((end, Reason::AscFrame))?;
    let mut dlc = || {
        fields.next().and_then(|(_, f)| match f {
            [digit] => hex_value(*digit),
            _ => None,
        })
    };
    let frame = match kind {
        b"r" => CanFrame::new_remote(id, extended, dlc().unwrap_or(0).min(CC_MAX_LEN as u8)),
        b"d" => {
            let len = usize::from(dlc().ok_or((at, Reason::AscFrame))?).min(CC_MAX_LEN);
            let mut data = [0u8; CC_MAX_LEN];
            for slot in &mut data[..len] {
                let (at, token) = fields.next().ok_or((end, Reason::LengthMismatch))?;
                *slot = byte(token, state.decimal).ok_or((at, Reason::ConsoleByte))?;
            }
            match extended {
                true => CanFrame::new_extended(id, &data[..len]),
                false => CanFrame::new(id, &data[..len]),
            }
        }
        _ => return Err((at, Reason::AscFrame)),
    };
    let frame = frame.map_err(|e| (at, e.into()))?;
    Ok(Line::Frame(Record { ts: Some(ts), iface, frame, dir: Some(dir) }))
}

/// An `ErrorFrame` line (whatever follows it: ASC names no class).
fn error_frame(ts: Timestamp, iface: &str, at: usize) -> Result<Line<'_>, PosError> {
    let frame = CanFrame::new_error(BUS_ERROR, &[0; CC_MAX_LEN]).map_err(|e| (at, e.into()))?;
    Ok(Line::Frame(Record { ts: Some(ts), iface, frame, dir: None }))
}

/// `Rx|Tx ID[x] [name] BRS ESI DLC LEN bytes... [duration length flags ...]`, after `CANFD channel`.
fn fd_frame<'a, 'f>(
    ts: Timestamp,
    iface: &'a str,
    mut fields: impl Iterator<Item = (usize, &'f [u8])>,
    end: usize,
    state: AscState,
) -> Result<Line<'a>, PosError> {
    let (at, dir) = fields.next().ok_or((end, Reason::AscFrame))?;
    let dir = direction(dir).ok_or((at, Reason::AscFrame))?;
    let (at, id_token) = fields.next().ok_or((end, Reason::AscFrame))?;
    if id_token == b"ErrorFrame" {
        return error_frame(ts, iface, at);
    }
    let (id, extended) = identifier(id_token, state.decimal).ok_or((at, Reason::AscFrame))?;
    // An optional symbolic message name comes before the BRS column.
    let (mut at, mut brs) = fields.next().ok_or((end, Reason::AscFrame))?;
    if !matches!(brs, b"0" | b"1") {
        (at, brs) = fields.next().ok_or((end, Reason::AscFrame))?;
    }
    let (esi_at, esi) = fields.next().ok_or((end, Reason::AscFrame))?;
    let (brs, esi) = match (brs, esi) {
        (b"0" | b"1", b"0" | b"1") => (brs == b"1", esi == b"1"),
        (b"0" | b"1", _) => return Err((esi_at, Reason::AscFrame)),
        _ => return Err((at, Reason::AscFrame)),
    };
    let (dlc_at, dlc) = fields.next().ok_or((end, Reason::AscFrame))?;
    let dlc = match dlc {
        [digit] => hex_value(*digit).ok_or((dlc_at, Reason::AscFrame))?,
        _ => return Err((dlc_at, Reason::AscFrame)),
    };
    let (len_at, len) = fields.next().ok_or((end, Reason::AscFrame))?;
    let (len, digits) = decimal_u64(len, 0);
    if digits == 0 || len > FD_MAX_LEN as u64 {
        return Err((len_at, Reason::BadFdLength));
    }
    let len = len as usize;
    let mut data = [0u8; FD_MAX_LEN];
    for slot in &mut data[..len] {
        let (at, token) = fields.next().ok_or((end, Reason::LengthMismatch))?;
        *slot = byte(token, state.decimal).ok_or((at, Reason::ConsoleByte))?;
    }
    // duration, bit count, then the flags that say whether this was an FD frame at all.
    let flags = fields.nth(2).and_then(|(_, f)| (f.len() <= 8).then(|| hex_u32(f))?);
    let frame = match flags {
        Some(flags) if flags & FLAG_EDL == 0 && flags & FLAG_REMOTE != 0 => {
            CanFrame::new_remote(id, extended, usize::from(dlc).min(CC_MAX_LEN) as u8)
        }
        // More than 8 bytes can only be FD, whatever the flags say (python-can writes 0 there).
        Some(flags) if flags & FLAG_EDL == 0 && len <= CC_MAX_LEN => match extended {
            true => CanFrame::new_extended(id, &data[..len]),
            false => CanFrame::new(id, &data[..len]),
        },
        _ => {
            if FD_LENGTHS.get(usize::from(dlc)) != Some(&(len as u8)) && len > CC_MAX_LEN {
                return Err((len_at, Reason::BadFdLength));
            }
            let bits = FD_FDF | if brs { FD_BRS } else { 0 } | if esi { FD_ESI } else { 0 };
            CanFrame::new_fd(id, extended, bits, &data[..len])
        }
    };
    let frame = frame.map_err(|e| (len_at, e.into()))?;
    Ok(Line::Frame(Record { ts: Some(ts), iface, frame, dir: Some(dir) }))
}
