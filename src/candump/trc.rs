//! PEAK trace files (`.trc`: PCAN-View, PCAN-Explorer, PEAK-Converter, python-can's TRCWriter), versions
//! 1.0 to 2.1.
//!
//! ```text
//! ;$FILEVERSION=2.1                           header and comment lines start with ';': Comment
//! ;$COLUMNS=N,O,T,B,I,d,R,L,D                 2.1 names its columns; older versions have fixed ones
//!       1      2501.000 DT 2      00C8 Tx -  8    09 08 07 06 05 04 03 02
//!      12)     48937.6  Rx         0704  1  RTR            (1.1)
//! ```
//!
//! Columns: N message number, O time offset (ms), T type, B bus, I identifier (4 hex digits: standard,
//! 8: extended), d direction, R reserved, L DLC, l data length, D data. Types: `DT` data, `FD`/`FB`/`FE`/`BI`
//! CAN FD (with BRS/ESI), `RR` remote request; `ST` status, `EC` error counter, `ER` error frame and 1.x's
//! `Warng`/`Error` are error text; `EV` events are comments. Stamps are milliseconds since the start of the
//! trace; `;$STARTTIME=` (days since 1899-12-30, taken as UTC, as python-can's TRCReader takes it) says
//! when that was, and the stamps are then on the clock, so a trace lines up with other logs of the same day
//! (without it they stay relative). Bus `N` becomes the interface `canN` (`can1` for versions without a bus
//! column).

use super::asc::channel_iface;
use super::hex::{decimal_time, decimal_u64, fields, hex_pair, hex_u32};
use super::record::{Direction, Line, Record, Timestamp};
use super::timestamp::PosError;
use super::Reason;
use crate::protocol::frame::{CC_MAX_LEN, EFF_MAX, FD_LENGTHS, FD_MAX_LEN, SFF_MAX};
use crate::protocol::CanFrame;

const FD_FDF: u8 = 0x4;
const FD_BRS: u8 = 0x1;
const FD_ESI: u8 = 0x2;
const MAX_COLUMNS: usize = 12;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Column {
    Number,
    Offset,
    Type,
    Bus,
    Id,
    Direction,
    Reserved,
    Dlc,
    Length,
    Data,
}

/// The column layout of the trace being read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TrcState {
    columns: [Column; MAX_COLUMNS],
    count: usize,
    /// When the trace started (`;$STARTTIME=`), in seconds and nanoseconds since the epoch.
    start: Option<(u64, u32)>,
}

impl Default for TrcState {
    fn default() -> Self {
        Self::for_version(10)
    }
}

impl TrcState {
    /// The fixed layout of each version (2.1's default, before its `;$COLUMNS=` line).
    pub(crate) fn for_version(version: u8) -> Self {
        use Column::*;
        let layout: &[Column] = match version {
            11 => &[Number, Offset, Type, Id, Dlc, Data],
            12 => &[Number, Offset, Bus, Type, Id, Dlc, Data],
            13 => &[Number, Offset, Bus, Type, Id, Reserved, Dlc, Data],
            20 => &[Number, Offset, Type, Id, Direction, Length, Data],
            21 => &[Number, Offset, Type, Bus, Id, Direction, Reserved, Dlc, Data],
            _ => &[Number, Offset, Id, Dlc, Data],
        };
        let mut state = Self { columns: [Data; MAX_COLUMNS], count: layout.len(), start: None };
        state.columns[..layout.len()].copy_from_slice(layout);
        state
    }

    /// `;$FILEVERSION=x.y` and `;$COLUMNS=...` lines change the layout; anything unknown keeps it.
    fn header(&mut self, line: &[u8]) {
        if let Some(version) = line.strip_prefix(b";$FILEVERSION=") {
            let version = match version.trim_ascii() {
                b"1.1" => 11,
                b"1.2" => 12,
                b"1.3" => 13,
                b"2.0" => 20,
                b"2.1" => 21,
                _ => return,
            };
            *self = Self { start: self.start, ..Self::for_version(version) };
        } else if let Some(days) = line.strip_prefix(b";$STARTTIME=") {
            self.start = start_time(days.trim_ascii()).or(self.start);
        } else if let Some(names) = line.strip_prefix(b";$COLUMNS=") {
            let mut state = Self { columns: [Column::Data; MAX_COLUMNS], count: 0, start: self.start };
            for name in names.trim_ascii().split(|&b| b == b',') {
                let column = match name {
                    b"N" => Column::Number,
                    b"O" => Column::Offset,
                    b"T" => Column::Type,
                    b"B" => Column::Bus,
                    b"I" => Column::Id,
                    b"d" => Column::Direction,
                    b"R" => Column::Reserved,
                    b"L" => Column::Dlc,
                    b"l" => Column::Length,
                    b"D" => Column::Data,
                    _ => return,
                };
                if state.count == MAX_COLUMNS {
                    return;
                }
                state.columns[state.count] = column;
                state.count += 1;
            }
            // Data must come last: everything after it is data bytes.
            if state.count > 0 && state.columns[state.count - 1] == Column::Data {
                *self = state;
            }
        }
    }
}

/// `;$STARTTIME=` days since 1899-12-30 (an OLE date: `45623.208912037`) as seconds and nanoseconds since
/// the epoch, to the microsecond as python-can reads it; `None` before 1970 or unreadable.
pub(super) fn start_time(days: &[u8]) -> Option<(u64, u32)> {
    const EPOCH_DAYS: i64 = 25_569; // 1899-12-30 to 1970-01-01
    let days: f64 = std::str::from_utf8(days).ok()?.parse().ok()?;
    if !days.is_finite() || days.abs() > 1e9 {
        return None;
    }
    // Whole days and the fraction apart, the fraction rounded half to even: Python's timedelta(days=...).
    let whole = days.trunc();
    let fraction = ((days - whole) * 86_400e6).round_ties_even() as i64;
    let micros = (whole as i64 - EPOCH_DAYS) * 86_400_000_000 + fraction;
    let micros = u64::try_from(micros).ok()?;
    Some((micros / 1_000_000, (micros % 1_000_000) as u32 * 1000))
}

/// What the type column says the line is.
enum Kind {
    Classic,
    Fd(u8),
    Remote,
}

pub(crate) fn parse<'a>(
    text: &'a [u8],
    state: &mut TrcState,
    iface: &'a mut Vec<u8>,
) -> Result<Line<'a>, PosError> {
    let text = text.strip_suffix(b"\r").unwrap_or(text);
    let trimmed = text.trim_ascii_start();
    if trimmed.is_empty() {
        return Ok(Line::Blank);
    }
    if trimmed.starts_with(b";") {
        state.header(trimmed);
        return Ok(Line::Comment);
    }
    let mut fields = fields(text);
    let end = text.len();
    let mut ts = None;
    let mut bus: &[u8] = b"1";
    let mut id = None;
    let mut dir = None;
    let mut kind = Kind::Classic;
    let mut dlc = None;
    let mut length = None;
    let mut rtr_text = false;
    let mut data = [0u8; FD_MAX_LEN];
    let mut data_len = 0;
    for &column in &state.columns[..state.count] {
        if column == Column::Data {
            (data_len, rtr_text) = data_bytes(fields.by_ref(), &mut data)?;
            break;
        }
        let (at, token) = fields.next().ok_or((end, Reason::TrcFrame))?;
        match column {
            Column::Number => {}
            Column::Offset => {
                let (secs, nanos) = decimal_time(token, 1_000_000).ok_or((at, Reason::TrcFrame))?;
                ts = Some(Timestamp::since_start(secs, nanos, state.start));
            }
            Column::Type => match type_column(token) {
                Type::Frame(frame_kind, frame_dir) => {
                    kind = frame_kind;
                    dir = dir.or(frame_dir);
                }
                Type::Status => return Ok(Line::ErrorText),
                Type::Event => return Ok(Line::Comment),
                Type::Unknown => return Err((at, Reason::TrcFrame)),
            },
            Column::Bus => {
                if token != b"-" {
                    bus = token;
                }
            }
            Column::Id => id = Some(identifier(token, at)?),
            Column::Direction => {
                dir = match token {
                    b"Rx" => Some(Direction::Rx),
                    b"Tx" => Some(Direction::Tx),
                    _ => return Err((at, Reason::TrcFrame)),
                }
            }
            Column::Reserved => {}
            Column::Dlc => dlc = Some(length_column(token, at)?),
            Column::Length => length = Some(length_column(token, at)?),
            Column::Data => {}
        }
    }
    let (id, extended, id_at) = id.ok_or((0, Reason::TrcFrame))?;
    let iface = channel_iface(iface, bus).ok_or((0, Reason::TrcFrame))?;
    if rtr_text {
        kind = Kind::Remote;
    }
    let frame = frame_of(kind, (id, extended, id_at), length, dlc, &data[..data_len])?;
    Ok(Line::Frame(Record { ts, iface, frame, dir }))
}

/// The frame the columns describe. The length the line declares is a data length, or a DLC (0-15, FD
/// lengths above 8); positions (for errors) come with each value.
#[inline]
fn frame_of(
    kind: Kind,
    (id, extended, id_at): (u32, bool, usize),
    length: Option<(usize, usize)>,
    dlc: Option<(usize, usize)>,
    data: &[u8],
) -> Result<CanFrame, PosError> {
    let fd = matches!(kind, Kind::Fd(_));
    let (declared, len_at) = match (length, dlc) {
        (Some(length), _) => length,
        (None, Some((dlc, at))) if fd => {
            (*FD_LENGTHS.get(dlc).ok_or((at, Reason::BadFdLength))? as usize, at)
        }
        (None, Some((dlc, at))) => (dlc.min(CC_MAX_LEN), at),
        (None, None) => (data.len(), id_at),
    };
    let frame = match kind {
        Kind::Remote => CanFrame::new_remote(id, extended, declared.min(CC_MAX_LEN) as u8),
        _ if declared != data.len() => return Err((len_at, Reason::LengthMismatch)),
        Kind::Fd(bits) => CanFrame::new_fd(id, extended, bits, data),
        Kind::Classic if extended => CanFrame::new_extended(id, data),
        Kind::Classic => CanFrame::new(id, data),
    };
    frame.map_err(|e| (len_at, e.into()))
}

/// A DLC or length column: a decimal number up to 64, with its position.
#[inline]
fn length_column(token: &[u8], at: usize) -> Result<(usize, usize), PosError> {
    let (value, digits) = decimal_u64(token, 0);
    if digits != token.len() || digits == 0 || value > 64 {
        return Err((at, Reason::BadLength));
    }
    Ok((value as usize, at))
}

/// What a type column (`DT`, `Rx`, `FD`, `RR`, `ST`, ...) makes of the line.
enum Type {
    /// A frame of this kind, with the direction 1.x versions put in this column.
    Frame(Kind, Option<Direction>),
    /// A status or error line (`ST`, `EC`, `ER`, `Warng`, `Error`).
    Status,
    /// An event (`EV`).
    Event,
    Unknown,
}

#[inline]
fn type_column(token: &[u8]) -> Type {
    match token {
        b"DT" => Type::Frame(Kind::Classic, None),
        b"Rx" => Type::Frame(Kind::Classic, Some(Direction::Rx)),
        b"Tx" => Type::Frame(Kind::Classic, Some(Direction::Tx)),
        b"FD" => Type::Frame(Kind::Fd(FD_FDF), None),
        b"FB" => Type::Frame(Kind::Fd(FD_FDF | FD_BRS), None),
        b"FE" => Type::Frame(Kind::Fd(FD_FDF | FD_ESI), None),
        b"BI" => Type::Frame(Kind::Fd(FD_FDF | FD_BRS | FD_ESI), None),
        b"RR" => Type::Frame(Kind::Remote, None),
        b"ST" | b"EC" | b"ER" | b"Warng" | b"Error" => Type::Status,
        b"EV" => Type::Event,
        _ => Type::Unknown,
    }
}

/// The identifier column: hex, 8 digits at most; extended when written with more than 4 digits or above the
/// standard range.
#[inline]
fn identifier(token: &[u8], at: usize) -> Result<(u32, bool, usize), PosError> {
    let value = (token.len() <= 8).then(|| hex_u32(token)).flatten().ok_or((at, Reason::NotHex))?;
    let extended = token.len() > 4 || value > SFF_MAX;
    if value > EFF_MAX {
        return Err((at, Reason::IdTooLarge));
    }
    Ok((value, extended, at))
}

/// The data bytes, the last column: two hex digits each. `RTR` in place of the data marks a 1.x remote
/// frame. Returns the number of bytes and whether the line said `RTR`.
#[inline]
fn data_bytes<'t>(
    fields: impl Iterator<Item = (usize, &'t [u8])>,
    data: &mut [u8; FD_MAX_LEN],
) -> Result<(usize, bool), PosError> {
    let mut data_len = 0;
    let mut rtr_text = false;
    for (at, token) in fields {
        if token == b"RTR" && data_len == 0 {
            rtr_text = true; // 1.x remote frames
            continue;
        }
        let byte = match token {
            [hi, lo] if !rtr_text => hex_pair(*hi, *lo),
            _ => None,
        };
        let slot = data.get_mut(data_len).ok_or((at, Reason::FdTooManyBytes))?;
        *slot = byte.ok_or((at, Reason::TrailingGarbage))?;
        data_len += 1;
    }
    Ok((data_len, rtr_text))
}
