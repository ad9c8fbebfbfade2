//! Allocation-free number formatting into a byte buffer (the hot path of text, JSON and CSV output).

use crate::candump::Timestamp;

const HEX: &[u8; 16] = b"0123456789ABCDEF";

pub fn push_int(out: &mut Vec<u8>, value: impl itoa::Integer) {
    let mut buffer = itoa::Buffer::new();
    out.extend_from_slice(buffer.format(value).as_bytes());
}

/// `raw / 10^scale` in plain decimal, trailing fractional zeros trimmed: (259, 1) -> "25.9", (150, 3) -> "0.15",
/// (-5, 3) -> "-0.005", (2000, 3) -> "2".
pub fn push_decimal(out: &mut Vec<u8>, raw: i64, scale: u8) {
    if scale == 0 {
        return push_int(out, raw);
    }
    let divisor = 10u64.pow(u32::from(scale));
    let magnitude = raw.unsigned_abs();
    if raw < 0 {
        out.push(b'-');
    }
    push_int(out, magnitude / divisor);
    let mut fraction = magnitude % divisor;
    if fraction == 0 {
        return;
    }
    let mut digits = scale;
    while fraction % 10 == 0 {
        fraction /= 10;
        digits -= 1;
    }
    out.push(b'.');
    let mut buffer = itoa::Buffer::new();
    let text = buffer.format(fraction).as_bytes();
    out.extend(std::iter::repeat_n(b'0', usize::from(digits) - text.len()));
    out.extend_from_slice(text);
}

/// Upper-case hex of each byte, no separators.
pub fn push_hex(out: &mut Vec<u8>, bytes: &[u8]) {
    for byte in bytes {
        out.push(HEX[usize::from(byte >> 4)]);
        out.push(HEX[usize::from(byte & 0xF)]);
    }
}

/// `0x` and `digits` upper-case hex digits.
pub fn push_hex_value(out: &mut Vec<u8>, value: u32, digits: u8) {
    out.extend_from_slice(b"0x");
    for shift in (0..digits).rev() {
        out.push(HEX[((value >> (4 * u32::from(shift))) & 0xF) as usize]);
    }
}

/// Seconds with 6 fractional digits, or 9 when the stamp has sub-microsecond precision.
pub fn push_timestamp(out: &mut Vec<u8>, ts: &Timestamp) {
    push_int(out, ts.secs);
    out.push(b'.');
    let (value, digits) = if ts.nanos % 1000 == 0 { (ts.nanos / 1000, 6) } else { (ts.nanos, 9) };
    let mut buffer = itoa::Buffer::new();
    let text = buffer.format(value).as_bytes();
    out.extend(std::iter::repeat_n(b'0', digits - text.len()));
    out.extend_from_slice(text);
}

/// A CAN identifier as `0x` + 3 hex digits (standard) or 8 (extended and error frames).
pub fn push_can_id(out: &mut Vec<u8>, id: u32, wide: bool) {
    push_hex_value(out, id, if wide { 8 } else { 3 });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decimal(raw: i64, scale: u8) -> String {
        let mut out = Vec::new();
        push_decimal(&mut out, raw, scale);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn decimals_are_exact_and_trimmed() {
        assert_eq!(decimal(259, 1), "25.9");
        assert_eq!(decimal(150, 3), "0.15");
        assert_eq!(decimal(-5, 3), "-0.005");
        assert_eq!(decimal(2000, 3), "2");
        assert_eq!(decimal(0, 3), "0");
        assert_eq!(decimal(7853, 5), "0.07853");
        assert_eq!(decimal(-78530, 5), "-0.7853");
        assert_eq!(decimal(i64::MIN, 3), "-9223372036854775.808");
        assert_eq!(decimal(42, 0), "42");
    }

    #[test]
    fn hex_and_ids() {
        let mut out = Vec::new();
        push_can_id(&mut out, 0x211, false);
        out.push(b' ');
        push_can_id(&mut out, 0x123, true);
        out.push(b' ');
        push_hex(&mut out, &[0x00, 0xB1, 0x0F]);
        assert_eq!(out, b"0x211 0x00000123 00B10F");
    }
}
