//! The fast path of the candump dialect: the common log line `(1700000000.002500) can0 211#00000103000000B1`
//! (standard or extended data frames of 0-8 bytes, an optional direction), read in one pass. Any other line,
//! or an error, is left to the general path (`general_path.rs`), which gives the same result for every line
//! taken here (a property test checks it).

use super::hex::{hex_bytes_8, hex_pair, hex_value, same_bytes, skip_spaces};
use super::record::{Direction, Record, Timestamp, IFACE_MAX_LEN};
use super::timestamp::{parse_numeric_cached, SecondsCache};
use crate::protocol::frame::{CC_MAX_LEN, EFF_MAX, SFF_MAX};
use crate::protocol::CanFrame;

/// The fast path for the common log line `(1700000000.002500) can0 211#00000103000000B1[ R]`: standard
/// or extended data frames of 0-8 bytes without separators. Returns `None` for anything else (including
/// errors), leaving the line to the general path, which must give the same result for lines accepted here.
#[inline]
pub(super) fn parse_log_fast<'a>(
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
pub(super) struct LogHead<'a> {
    pub(super) ts: Option<Timestamp>,
    pub(super) iface: &'a str,
    pub(super) dir: Option<Direction>,
    /// The line's length without its `\n`.
    pub(super) length: usize,
}

/// [`parse_log_fast`] on the line at the start of `line`, which may go on past the line's `\n`: the line is
/// found by parsing it, so a buffer of lines needs no search for each line's end. Writes the frame into
/// `frame` (left as it was when the line is not taken) and returns the rest.
#[inline(always)]
pub(super) fn parse_log_line_into<'a>(
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
