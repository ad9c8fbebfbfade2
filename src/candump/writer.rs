//! The `candump -L` log format writer.

use super::hex::HEX_UPPER;
use super::{Direction, Record, Timestamp, TimestampKind};
use crate::protocol::frame::ERR_FLAG;
use crate::protocol::{CanFrame, FrameKind};

/// Appends one log line, e.g. `(1700000000.002500) can0 211#00000103000000B1\n`.
///
/// Like candump: a 6-digit fraction (nanoseconds are truncated to microseconds), seconds zero-padded to
/// 10 digits for absolute stamps (`%010llu`) and to 3 for relative ones (`%03llu`). Without a timestamp
/// the `(...) ` prefix is left out (canplayer needs one; this parser does not). Never allocates beyond
/// growing `out`.
pub fn write_log_line(out: &mut Vec<u8>, ts: Option<Timestamp>, iface: &str, frame: &CanFrame) {
    if let Some(ts) = ts {
        let width = match ts.kind {
            TimestampKind::Absolute => 10,
            TimestampKind::Relative => 3,
        };
        out.push(b'(');
        write_padded(out, ts.secs, width);
        out.push(b'.');
        write_padded(out, u64::from(ts.nanos / 1_000), 6);
        out.extend_from_slice(b") ");
    }
    out.extend_from_slice(iface.as_bytes());
    out.push(b' ');
    write_frame(out, frame);
    out.push(b'\n');
}

/// Appends a log line for a parsed record, with the ` R`/` T` suffix of `candump -x` when it has a direction.
pub fn write_log_record(out: &mut Vec<u8>, record: &Record<'_>) {
    write_log_line(out, record.ts, record.iface, &record.frame);
    if let Some(dir) = record.dir {
        out.pop(); // the newline
        out.extend_from_slice(match dir {
            Direction::Rx => b" R\n",
            Direction::Tx => b" T\n",
        });
    }
}

/// Appends the frame in cansend syntax, byte for byte what `CanFrame`'s `Display` writes.
pub fn write_frame(out: &mut Vec<u8>, frame: &CanFrame) {
    match frame.kind() {
        FrameKind::Error => write_hex(out, frame.id() | ERR_FLAG, 8),
        _ if frame.is_extended() => write_hex(out, frame.id(), 8),
        _ => write_hex(out, frame.id(), 3),
    }
    out.push(b'#');
    match frame.kind() {
        FrameKind::Remote => {
            out.push(b'R');
            if !frame.is_empty() {
                // Remote lengths are 0..=8: one digit.
                out.push(b'0' + frame.len() as u8);
            }
        }
        FrameKind::Fd => {
            out.push(b'#');
            out.push(HEX_UPPER[usize::from(frame.fd_flags() & 0xF)]);
        }
        FrameKind::Data | FrameKind::Error => {}
    }
    for &byte in frame.data() {
        out.push(HEX_UPPER[usize::from(byte >> 4)]);
        out.push(HEX_UPPER[usize::from(byte & 0xF)]);
    }
    if let Some(dlc) = frame.raw_dlc() {
        out.push(b'_');
        out.push(HEX_UPPER[usize::from(dlc & 0xF)]);
    }
}

/// `digits` uppercase hex digits of `value`.
fn write_hex(out: &mut Vec<u8>, value: u32, digits: u32) {
    for shift in (0..digits).rev() {
        out.push(HEX_UPPER[((value >> (shift * 4)) & 0xF) as usize]);
    }
}

/// `value` in decimal, zero-padded to at least `width` digits (like `%0*llu`).
fn write_padded(out: &mut Vec<u8>, value: u64, width: usize) {
    let mut digits = [b'0'; 20];
    let mut at = digits.len();
    let mut rest = value;
    loop {
        at -= 1;
        digits[at] = b'0' + (rest % 10) as u8;
        rest /= 10;
        if rest == 0 {
            break;
        }
    }
    let len = digits.len() - at;
    out.resize(out.len() + width.saturating_sub(len), b'0');
    out.extend_from_slice(&digits[at..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(ts: Option<Timestamp>, frame: CanFrame) -> String {
        let mut out = Vec::new();
        write_log_line(&mut out, ts, "can0", &frame);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn writes_candump_log_lines() {
        let frame = CanFrame::new(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]).unwrap();
        let abs = Timestamp { secs: 1_700_000_000, nanos: 2_500_999, kind: TimestampKind::Absolute };
        assert_eq!(line(Some(abs), frame), "(1700000000.002500) can0 211#00000103000000B1\n");
        let rel = Timestamp { secs: 1, nanos: 123_456_000, kind: TimestampKind::Relative };
        assert_eq!(line(Some(rel), frame), "(001.123456) can0 211#00000103000000B1\n");
        let small_abs = Timestamp { secs: 0, nanos: 0, kind: TimestampKind::Absolute };
        assert_eq!(line(Some(small_abs), frame), "(0000000000.000000) can0 211#00000103000000B1\n");
        let long_rel = Timestamp { secs: 12_345, nanos: 0, kind: TimestampKind::Relative };
        assert_eq!(line(Some(long_rel), frame), "(12345.000000) can0 211#00000103000000B1\n");
        assert_eq!(line(None, frame), "can0 211#00000103000000B1\n");
    }

    #[test]
    fn frame_text_matches_display_for_every_kind() {
        let frames = [
            CanFrame::new(0x7FF, &[]).unwrap(),
            CanFrame::new_extended(0x123, &[0x11]).unwrap(),
            CanFrame::new_remote(0x123, false, 5).unwrap(),
            CanFrame::new_remote(0x1234_5678, true, 0).unwrap(),
            CanFrame::new_remote(0x123, false, 8).unwrap().with_raw_dlc(0xE).unwrap(),
            CanFrame::new_error(0x4, &[0, 8, 0, 0, 0, 0, 0x78, 0]).unwrap(),
            CanFrame::new_fd(0x151, false, 5, &[1, 2]).unwrap(),
            CanFrame::new_fd(0x1FFF_FFFF, true, 0xF, &[0xAB; 64]).unwrap(),
            CanFrame::new(0x123, &[0x11; 8]).unwrap().with_raw_dlc(9).unwrap(),
        ];
        for frame in frames {
            let mut out = Vec::new();
            write_frame(&mut out, &frame);
            assert_eq!(String::from_utf8(out).unwrap(), frame.to_string());
        }
    }

    #[test]
    fn records_keep_their_direction() {
        let frame = CanFrame::new(0x111, &[0; 8]).unwrap();
        let ts = Some(Timestamp { secs: 1_700_000_000, nanos: 0, kind: TimestampKind::Absolute });
        let mut out = Vec::new();
        write_log_record(&mut out, &Record { ts, iface: "can0", frame, dir: Some(Direction::Tx) });
        assert_eq!(out, b"(1700000000.000000) can0 111#0000000000000000 T\n");
    }
}
