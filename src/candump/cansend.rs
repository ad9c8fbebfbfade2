//! The `ID#DATA` frame syntax shared by candump logs and cansend, parsed strictly.
//!
//! Strict where cansend is sloppy (candump-formats.md §3): a 9th data byte, trailing junk, `R9`/`RX`,
//! an invalid `_X`, whitespace, odd digits and 1/2/4-7/9+-digit identifiers are errors, and 3-digit
//! identifiers above 0x7FF are rejected. Accepted like cansend: either hex case, one optional `.` before
//! any byte and a trailing `.`, `R`/`r`, `R5`, `R8_E`, `_E` after 8 bytes, `123##<flags><data>` CAN FD
//! (flags 0-F, lengths from `FD_LENGTHS`), 8-digit identifiers (extended; bit 29 set makes an error frame).

use super::hex::{hex_pair, hex_u32, hex_value, is_hex};
use super::timestamp::PosError;
use super::{FrameSyntaxError, Reason};
use crate::protocol::frame::{CC_MAX_LEN, EFF_MAX, ERR_FLAG, FD_LENGTHS, FD_MAX_LEN, SFF_MAX};
use crate::protocol::CanFrame;

/// Largest CAN XL payload.
const XL_MAX_LEN: usize = 2048;

/// A syntactically valid frame text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FrameText {
    Can(CanFrame),
    /// A CAN XL frame: checked, not decoded.
    Xl,
}

/// Parses one frame in cansend syntax, e.g. `211#00000103000000B1`, `123#R`, `123##1DEAD`.
///
/// Used for frames given on the command line. See the module docs for what is accepted.
pub fn parse_cansend(text: &[u8]) -> Result<CanFrame, FrameSyntaxError> {
    let error = |(pos, reason): PosError| FrameSyntaxError { column: pos + 1, reason };
    if let Some(pos) = text.iter().position(u8::is_ascii_whitespace) {
        return Err(error((pos, Reason::UnexpectedWhitespace)));
    }
    match parse_frame_text(text).map_err(error)? {
        FrameText::Can(frame) => Ok(frame),
        FrameText::Xl => Err(error((0, Reason::XlUnsupported))),
    }
}

/// How the identifier was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum IdForm {
    Standard,
    Extended,
    /// 8 digits with bit 29 set; the value has the flag removed.
    Error,
}

impl IdForm {
    /// Error frames are extended too (their id is 29 bits of error class).
    pub(crate) fn is_extended(self) -> bool {
        self != IdForm::Standard
    }
}

/// Parses a whole frame token (no surrounding whitespace). Error positions are 0-based indices into `text`.
pub(crate) fn parse_frame_text(text: &[u8]) -> Result<FrameText, PosError> {
    if text.is_empty() {
        return Err((0, Reason::EmptyFrame));
    }
    let digits = text.iter().position(|&b| !is_hex(b)).unwrap_or(text.len());
    match text.get(digits) {
        None => return Err((digits, Reason::MissingHash)),
        Some(b'#') => {}
        Some(_) => return Err((digits, Reason::NotHex)),
    }
    let body = digits + 1;
    let (id, form) = match digits {
        3 | 8 => classify_id(&text[..digits])?,
        5 if looks_like_xl_header(text, body) => return check_xl(text, body).map(|()| FrameText::Xl),
        _ => return Err((0, Reason::IdLength)),
    };
    match text.get(body) {
        Some(b'R' | b'r') => parse_remote(text, body, id, form),
        Some(b'#') => parse_fd(text, body, id, form),
        _ => parse_classic(text, body, id, form),
    }
}

/// Value and form of a 3- or 8-digit identifier, rejecting values the bus cannot carry.
pub(crate) fn classify_id(digits: &[u8]) -> Result<(u32, IdForm), PosError> {
    let value = hex_u32(digits).ok_or((0, Reason::NotHex))?;
    if digits.len() == 3 {
        return if value > SFF_MAX { Err((0, Reason::SffIdTooLarge)) } else { Ok((value, IdForm::Standard)) };
    }
    if value > (EFF_MAX | ERR_FLAG) {
        Err((0, Reason::IdTooLarge))
    } else if value & ERR_FLAG != 0 {
        Ok((value & !ERR_FLAG, IdForm::Error))
    } else {
        Ok((value, IdForm::Extended))
    }
}

/// Builds a classic data or error frame.
pub(crate) fn data_frame(id: u32, form: IdForm, data: &[u8]) -> Result<CanFrame, Reason> {
    let frame = match form {
        IdForm::Standard => CanFrame::new(id, data),
        IdForm::Extended => CanFrame::new_extended(id, data),
        IdForm::Error => CanFrame::new_error(id, data),
    };
    frame.map_err(Reason::from)
}

/// `R`, `R5`, `R8_E` (starting at the `R`).
fn parse_remote(text: &[u8], at: usize, id: u32, form: IdForm) -> Result<FrameText, PosError> {
    if form == IdForm::Error {
        return Err((at, Reason::ErrorFrameNotData));
    }
    let mut pos = at + 1;
    let mut len = 0u8;
    match text.get(pos) {
        Some(&digit @ b'0'..=b'8') => {
            len = digit - b'0';
            pos += 1;
        }
        Some(b'_') | None => {}
        Some(_) => return Err((pos, Reason::BadRemoteLength)),
    }
    let mut frame = CanFrame::new_remote(id, form.is_extended(), len).map_err(|e| (at, e.into()))?;
    if text.get(pos) == Some(&b'_') {
        let dlc = raw_dlc(text, pos, usize::from(len))?;
        frame = frame.with_raw_dlc(dlc).map_err(|e| (pos, e.into()))?;
        pos += 2;
    }
    match pos < text.len() {
        true => Err((pos, Reason::TrailingGarbage)),
        false => Ok(FrameText::Can(frame)),
    }
}

/// `##<flags><data>` (starting at the second `#`).
fn parse_fd(text: &[u8], at: usize, id: u32, form: IdForm) -> Result<FrameText, PosError> {
    if form == IdForm::Error {
        return Err((at, Reason::ErrorFrameNotData));
    }
    let flags_pos = at + 1;
    let flags = text.get(flags_pos).and_then(|&b| hex_value(b)).ok_or((flags_pos, Reason::BadFdFlags))?;
    let data_pos = flags_pos + 1;
    let mut data = [0u8; FD_MAX_LEN];
    let (len, end) = scan_bytes(text, data_pos, FD_MAX_LEN, Reason::FdTooManyBytes, |i, b| data[i] = b)?;
    if end < text.len() {
        // Only '_' stops the scan early; FD frames have no raw DLC.
        return Err((end, Reason::BadRawDlc));
    }
    if !FD_LENGTHS.contains(&(len as u8)) {
        return Err((data_pos, Reason::BadFdLength));
    }
    let frame =
        CanFrame::new_fd(id, form.is_extended(), flags, &data[..len]).map_err(|e| (data_pos, e.into()))?;
    Ok(FrameText::Can(frame))
}

/// Classic data (or error) frame body, with the optional `_X` raw DLC.
fn parse_classic(text: &[u8], at: usize, id: u32, form: IdForm) -> Result<FrameText, PosError> {
    let mut data = [0u8; CC_MAX_LEN];
    let (len, end) = scan_bytes(text, at, CC_MAX_LEN, Reason::TooManyBytes, |i, b| data[i] = b)?;
    let mut frame = data_frame(id, form, &data[..len]).map_err(|r| (at, r))?;
    if end < text.len() {
        // The scan stopped at '_'.
        if form == IdForm::Error {
            return Err((end, Reason::BadRawDlc));
        }
        let dlc = raw_dlc(text, end, len)?;
        frame = frame.with_raw_dlc(dlc).map_err(|e| (end, e.into()))?;
        if end + 2 < text.len() {
            return Err((end + 2, Reason::TrailingGarbage));
        }
    }
    Ok(FrameText::Can(frame))
}

/// The digit of a `_X` suffix at `pos`, valid only after 8 bytes and only 9..=F.
fn raw_dlc(text: &[u8], pos: usize, len: usize) -> Result<u8, PosError> {
    match text.get(pos + 1).and_then(|&b| hex_value(b)) {
        Some(dlc @ 9..=15) if len == CC_MAX_LEN => Ok(dlc),
        _ => Err((pos, Reason::BadRawDlc)),
    }
}

/// Scans hex byte pairs with cansend's optional `.` separators from `pos`, handing each byte to `sink`.
/// Stops at the end of the text or at `_`. Returns the byte count and where it stopped.
#[inline]
pub(crate) fn scan_bytes(
    text: &[u8],
    mut pos: usize,
    max: usize,
    too_many: Reason,
    mut sink: impl FnMut(usize, u8),
) -> Result<(usize, usize), PosError> {
    let mut count = 0;
    let mut after_dot = false;
    while let Some(&hi) = text.get(pos) {
        match hi {
            b'.' if after_dot => return Err((pos, Reason::BadSeparator)),
            b'.' => {
                after_dot = true;
                pos += 1;
                continue;
            }
            b'_' => break,
            // A full frame followed by something that is not another byte is junk, not a bad digit.
            _ if count == max && !is_hex(hi) => return Err((pos, Reason::TrailingGarbage)),
            _ => {}
        }
        let Some(&lo) = text.get(pos + 1) else {
            return Err(match is_hex(hi) {
                true => (pos, Reason::OddHexDigits),
                false => (pos, Reason::NotHex),
            });
        };
        let Some(byte) = hex_pair(hi, lo) else {
            return Err(match (is_hex(hi), lo) {
                (false, _) => (pos, Reason::NotHex),
                (true, b'.') => (pos + 1, Reason::BadSeparator),
                (true, b'_') => (pos, Reason::OddHexDigits),
                (true, _) => (pos + 1, Reason::NotHex),
            });
        };
        if count == max {
            return Err((pos, too_many));
        }
        sink(count, byte);
        count += 1;
        pos += 2;
        after_dot = false;
    }
    Ok((count, pos))
}

/// True if `text[at..]` starts like the `flags:` part of a CAN XL frame, so a 5-digit id is VCID+PRIO.
fn looks_like_xl_header(text: &[u8], at: usize) -> bool {
    matches!(text.get(at..at + 3), Some([a, b, b':']) if is_hex(*a) && is_hex(*b))
}

/// Checks `FF:SS:AAAAAAAA#data` starting at `at` (after `VVPPP#`).
fn check_xl(text: &[u8], at: usize) -> Result<(), PosError> {
    // (width of the hex field, byte that must follow it)
    const HEADER: [(usize, u8); 3] = [(2, b':'), (2, b':'), (8, b'#')];
    let mut pos = at;
    for (width, separator) in HEADER {
        let field = text.get(pos..pos + width).ok_or((pos, Reason::BadXlFrame))?;
        if let Some(bad) = field.iter().position(|&b| !is_hex(b)) {
            return Err((pos + bad, Reason::BadXlFrame));
        }
        if text.get(pos + width) != Some(&separator) {
            return Err((pos + width, Reason::BadXlFrame));
        }
        pos += width + 1;
    }
    let (_, end) = scan_bytes(text, pos, XL_MAX_LEN, Reason::BadXlFrame, |_, _| {})?;
    match end < text.len() {
        true => Err((end, Reason::BadXlFrame)),
        false => Ok(()),
    }
}
