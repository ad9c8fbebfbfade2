//! Allocation-free number formatting into a byte buffer (the hot path of text, JSON and CSV output).

use std::cell::Cell;

use super::short_text::push_short;
use crate::candump::Timestamp;

const HEX: &[u8; 16] = b"0123456789ABCDEF";

pub fn push_int<T: itoa::Integer + TryInto<u8> + Copy>(out: &mut Vec<u8>, value: T) {
    // Counts, switches and idle readings are mostly one digit: no call to format and copy them.
    if let Ok(digit @ 0..=9) = value.try_into() {
        return out.push(b'0' + digit);
    }
    let mut buffer = itoa::Buffer::new();
    push_short(out, buffer.format(value).as_bytes());
}

/// "00" to "99": two digits per division by 100.
const DIGIT_PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// Room for a sign, 20 integer digits, a dot and up to 19 fraction digits.
const NUMBER_BUFFER: usize = 64;
/// Where the integer part ends (and the dot goes) in a number buffer.
const POINT: usize = 21;

/// Writes `value` in decimal so that it ends just before `end`; returns where it starts.
#[inline(always)]
fn digits_ending_at(buf: &mut [u8; NUMBER_BUFFER], end: usize, mut value: u64) -> usize {
    let mut start = end;
    while value >= 100 {
        let pair = (value % 100) as usize * 2;
        value /= 100;
        start -= 2;
        buf[start..start + 2].copy_from_slice(&DIGIT_PAIRS[pair..pair + 2]);
    }
    if value >= 10 {
        let pair = value as usize * 2;
        start -= 2;
        buf[start..start + 2].copy_from_slice(&DIGIT_PAIRS[pair..pair + 2]);
    } else {
        start -= 1;
        buf[start] = b'0' + value as u8;
    }
    start
}

/// Appends `buf[start..end]` (fixed-size moves, no `memcpy` call: [`push_short`]).
#[inline(always)]
fn push_digits(out: &mut Vec<u8>, buf: &[u8; NUMBER_BUFFER], start: usize, end: usize) {
    push_short(out, &buf[start..end]);
}

/// A number buffer: all `'0'`, so digits written right-aligned are zero-padded for free (no `memset`).
const ZEROS: [u8; NUMBER_BUFFER] = [b'0'; NUMBER_BUFFER];

/// `raw / 10^scale` as a JSON or CSV float: plain decimal, trailing fractional zeros trimmed down to one, so
/// the number always has its decimal point: (259, 1) -> "25.9", (150, 3) -> "0.15", (2000, 3) -> "2.0",
/// (0, 3) -> "0.0". A reader that types a column from its first rows (DuckDB's `read_json_auto`, Spark)
/// then makes a speed column DOUBLE even when the log starts with the robot standing still.
pub fn push_decimal(out: &mut Vec<u8>, raw: i64, scale: u8) {
    push_decimal_as::<true>(out, raw, scale);
}

/// `raw / 10^scale` for people (text output): trailing fractional zeros and a bare point trimmed,
/// (2000, 3) -> "2", (-5, 3) -> "-0.005".
pub fn push_decimal_trimmed(out: &mut Vec<u8>, raw: i64, scale: u8) {
    push_decimal_as::<false>(out, raw, scale);
}

/// Written into a stack buffer and appended once: the per-byte pushes and the two `itoa` calls it used
/// to make cost more than the digits (measured with callgrind on the JSON path).
#[inline(always)]
fn push_decimal_as<const POINT_KEPT: bool>(out: &mut Vec<u8>, raw: i64, scale: u8) {
    // A divisor known when compiling is a multiplication; a division by a variable one is not (and
    // `pow` is a loop). The protocol's scales are 1, 3 and 5.
    match scale {
        1 => push_scaled::<1, POINT_KEPT>(out, raw),
        2 => push_scaled::<2, POINT_KEPT>(out, raw),
        3 => push_scaled::<3, POINT_KEPT>(out, raw),
        4 => push_scaled::<4, POINT_KEPT>(out, raw),
        5 => push_scaled::<5, POINT_KEPT>(out, raw),
        6 => push_scaled::<6, POINT_KEPT>(out, raw),
        _ => push_decimal_general(out, raw, scale, POINT_KEPT),
    }
}

/// [`push_decimal_as`] with the scale as a constant.
#[inline(always)]
fn push_scaled<const SCALE: u32, const POINT_KEPT: bool>(out: &mut Vec<u8>, raw: i64) {
    let divisor = 10u64.pow(SCALE);
    let magnitude = raw.unsigned_abs();
    let mut buf = ZEROS;
    let mut start = digits_ending_at(&mut buf, POINT, magnitude / divisor);
    if raw < 0 {
        start -= 1;
        buf[start] = b'-';
    }
    let mut fraction = magnitude % divisor;
    let mut end = POINT;
    if fraction != 0 {
        let mut digits = SCALE as usize;
        while fraction % 10 == 0 {
            fraction /= 10;
            digits -= 1;
        }
        buf[POINT] = b'.';
        end = POINT + 1 + digits;
        digits_ending_at(&mut buf, end, fraction);
    } else if POINT_KEPT {
        // The buffer is all '0': the point is the only byte to write.
        buf[POINT] = b'.';
        end = POINT + 2;
    }
    push_digits(out, &buf, start, end);
}

/// [`push_decimal_as`] for any scale, with `itoa`.
#[cold]
fn push_decimal_general(out: &mut Vec<u8>, raw: i64, scale: u8, point_kept: bool) {
    let divisor = 10u128.pow(u32::from(scale));
    let magnitude = u128::from(raw.unsigned_abs());
    if raw < 0 {
        out.push(b'-');
    }
    push_int(out, magnitude / divisor);
    let mut fraction = magnitude % divisor;
    if fraction == 0 {
        if point_kept {
            out.extend_from_slice(b".0");
        }
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
    push_short(out, text);
}

/// The two upper-case hex digits of every byte value.
static HEX_PAIRS: [[u8; 2]; 256] = {
    let mut table = [[0u8; 2]; 256];
    let mut byte = 0;
    while byte < 256 {
        table[byte] = [HEX[byte >> 4], HEX[byte & 0xF]];
        byte += 1;
    }
    table
};

/// Upper-case hex of each byte, no separators (built on the stack, appended in one copy).
pub fn push_hex(out: &mut Vec<u8>, bytes: &[u8]) {
    // A full classic payload (most frames): a copy of constant length, inlined instead of a `memcpy` call.
    if let Ok(&[a, b, c, d, e, f, g, h]) = <&[u8; 8]>::try_from(bytes) {
        let digits = [hex8(u32::from_be_bytes([a, b, c, d])), hex8(u32::from_be_bytes([e, f, g, h]))];
        return out.extend_from_slice(digits.as_flattened());
    }
    for chunk in bytes.chunks(32) {
        let mut buf = [[0u8; 2]; 32];
        for (pair, &byte) in buf.iter_mut().zip(chunk) {
            *pair = HEX_PAIRS[usize::from(byte)];
        }
        out.extend_from_slice(buf[..chunk.len()].as_flattened());
    }
}

/// The eight upper-case hex digits of `value`, the most significant first, worked out side by side in one
/// u64: each nibble moved into a byte of its own, then `0`-`9` or `A`-`F` added to every byte at once.
#[inline(always)]
fn hex8(value: u32) -> [u8; 8] {
    const BYTES: u64 = 0x0101_0101_0101_0101;
    let mut nibbles = u64::from(value);
    nibbles = (nibbles | (nibbles << 16)) & 0x0000_FFFF_0000_FFFF;
    nibbles = (nibbles | (nibbles << 8)) & 0x00FF_00FF_00FF_00FF;
    nibbles = (nibbles | (nibbles << 4)) & (BYTES * 0x0F);
    // 1 in each byte whose nibble is 10 or more (adding 6 carries it into bit 4): those bytes get 7 more,
    // the gap between '9' + 1 and 'A'.
    let letters = ((nibbles + BYTES * 6) >> 4) & BYTES;
    (nibbles + BYTES * u64::from(b'0') + letters * 7).to_be_bytes()
}

/// `0x` and `digits` upper-case hex digits.
pub fn push_hex_value(out: &mut Vec<u8>, value: u32, digits: u8) {
    let digits = usize::from(digits);
    if !(1..=8).contains(&digits) {
        return push_hex_value_general(out, value, digits);
    }
    // The wanted digits moved to the top, so they come first; the block is appended whole and trimmed.
    let [a, b, c, d, e, f, g, h] = hex8(value << (4 * (8 - digits)));
    let len = out.len();
    out.extend_from_slice(&[b'0', b'x', a, b, c, d, e, f, g, h]);
    out.truncate(len + 2 + digits);
}

/// More than 8 digits (never asked for today): leading zeros beyond the u32.
#[cold]
fn push_hex_value_general(out: &mut Vec<u8>, value: u32, digits: usize) {
    out.extend_from_slice(b"0x");
    for shift in (0..digits).rev() {
        let nibble = u64::from(value).checked_shr(4 * shift as u32).unwrap_or(0) & 0xF;
        out.push(HEX[nibble as usize]);
    }
}

/// The digits of the seconds a thread wrote last, as they stand before [`POINT`] in a number buffer.
#[derive(Clone, Copy)]
struct SecondsDigits {
    secs: u64,
    start: usize,
    digits: [u8; POINT],
}

thread_local! {
    static LAST_SECONDS: Cell<Option<SecondsDigits>> = const { Cell::new(None) };
}

/// Writes `secs` to end at [`POINT`] and returns where it starts. Frames of a log mostly share their
/// second with the frame before, so the digits are worked out once per second of log and copied after.
#[inline(always)]
fn seconds_digits(buf: &mut [u8; NUMBER_BUFFER], secs: u64) -> usize {
    LAST_SECONDS.with(|last| match last.get() {
        Some(seconds) if seconds.secs == secs => {
            buf[..POINT].copy_from_slice(&seconds.digits);
            seconds.start
        }
        _ => {
            let start = digits_ending_at(buf, POINT, secs);
            if let Ok(digits) = buf[..POINT].try_into() {
                last.set(Some(SecondsDigits { secs, start, digits }));
            }
            start
        }
    })
}

/// Seconds with 6 fractional digits, or 9 when the stamp has sub-microsecond precision.
pub fn push_timestamp(out: &mut Vec<u8>, ts: &Timestamp) {
    let mut buf = ZEROS;
    let start = seconds_digits(&mut buf, ts.secs);
    buf[POINT] = b'.';
    let (value, digits) = if ts.nanos % 1000 == 0 { (ts.nanos / 1000, 6) } else { (ts.nanos, 9) };
    // `nanos` < 10^9 by the type's invariant; `min` keeps a broken value from overrunning the digits.
    let value = u64::from(value).min(10u64.pow(digits as u32) - 1);
    digits_ending_at(&mut buf, POINT + 1 + digits, value);
    push_digits(out, &buf, start, POINT + 1 + digits);
}

/// The stamp in whole nanoseconds, as `push_int(ts.as_nanos())` writes it: the seconds' digits followed by
/// nine of nanoseconds, so no 19-digit (or u128) number is formatted.
pub fn push_nanos(out: &mut Vec<u8>, ts: &Timestamp) {
    if ts.secs == 0 {
        return push_int(out, ts.nanos);
    }
    let mut buf = ZEROS;
    let start = seconds_digits(&mut buf, ts.secs);
    // `nanos` < 10^9 by the type's invariant; `min` keeps a broken value inside its nine digits.
    digits_ending_at(&mut buf, POINT + 9, u64::from(ts.nanos.min(999_999_999)));
    push_digits(out, &buf, start, POINT + 9);
}

/// [`push_timestamp`], `between`, then [`push_nanos`] of the same stamp (JSON's `ts` and `ts_ns`), with the
/// digits worked out once: nine digits of nanoseconds after the seconds are the whole-nanosecond number,
/// and their first six (or all nine) are the stamp's decimals.
pub fn push_timestamp_and_nanos(out: &mut Vec<u8>, ts: &Timestamp, between: &[u8]) {
    if ts.secs == 0 {
        push_timestamp(out, ts);
        push_short(out, between);
        return push_nanos(out, ts);
    }
    let mut buf = ZEROS;
    let start = seconds_digits(&mut buf, ts.secs);
    // `nanos` < 10^9 by the type's invariant; `min` keeps a broken value inside its nine digits.
    let nanos = ts.nanos.min(999_999_999);
    digits_ending_at(&mut buf, POINT + 9, u64::from(nanos));
    let decimals = if ts.nanos % 1000 == 0 { 6 } else { 9 };
    push_digits(out, &buf, start, POINT);
    out.push(b'.');
    push_digits(out, &buf, POINT, POINT + decimals);
    push_short(out, between);
    push_digits(out, &buf, start, POINT + 9);
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
        push_decimal_trimmed(&mut out, raw, scale);
        String::from_utf8(out).unwrap()
    }

    fn float(raw: i64, scale: u8) -> String {
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
        assert_eq!(decimal(i64::MAX, 19), "0.9223372036854775807");
        assert_eq!(decimal(i64::MIN, 19), "-0.9223372036854775808");
        assert_eq!(decimal(-12345, 20), "-0.00000000000000012345");
        assert_eq!(decimal(-1, 1), "-0.1");
        assert_eq!(decimal(99, 2), "0.99");
        assert_eq!(decimal(1_000_001, 6), "1.000001");
    }

    #[test]
    fn floats_always_have_a_decimal_point() {
        assert_eq!(float(0, 3), "0.0");
        assert_eq!(float(0, 1), "0.0");
        assert_eq!(float(2000, 3), "2.0");
        assert_eq!(float(-2000, 3), "-2.0");
        assert_eq!(float(150, 3), "0.15");
        assert_eq!(float(259, 1), "25.9");
        assert_eq!(float(-5, 3), "-0.005");
        assert_eq!(float(42, 0), "42.0");
        assert_eq!(float(0, 9), "0.0");
        assert_eq!(float(-3_000_000_000, 9), "-3.0");
        assert_eq!(float(i64::MIN, 3), "-9223372036854775.808");
        assert_eq!(float(0, 20), "0.0");
    }

    #[test]
    fn decimals_match_the_general_route() {
        for raw in [0, 1, -1, 7, 10, 99, 100, 101, 259, -5, 1200, 65535, -32768, i64::MAX, i64::MIN] {
            for scale in 0..=19 {
                for point_kept in [false, true] {
                    let mut general = Vec::new();
                    push_decimal_general(&mut general, raw, scale, point_kept);
                    let fast = if point_kept { float(raw, scale) } else { decimal(raw, scale) };
                    assert_eq!(fast.as_bytes(), general, "{raw} {scale} {point_kept}");
                }
            }
        }
    }

    #[test]
    fn timestamps_have_6_or_9_digits() {
        let stamp = |secs, nanos| {
            let mut out = Vec::new();
            push_timestamp(&mut out, &Timestamp::from_numeric(secs, nanos));
            String::from_utf8(out).unwrap()
        };
        assert_eq!(stamp(1_700_000_000, 2_500_000), "1700000000.002500");
        assert_eq!(stamp(0, 0), "0.000000");
        assert_eq!(stamp(5, 1), "5.000000001");
        assert_eq!(stamp(u64::MAX, 999_999_999), "18446744073709551615.999999999");
        assert_eq!(stamp(12, 120_000_000), "12.120000");
        // The seconds' digits are kept from one stamp to the next: a change of second, and back.
        assert_eq!(stamp(1_700_000_000, 0), "1700000000.000000");
        assert_eq!(stamp(1_700_000_001, 0), "1700000001.000000");
        assert_eq!(stamp(99, 0), "99.000000");
        assert_eq!(stamp(1_700_000_000, 1), "1700000000.000000001");
    }

    #[test]
    fn stamp_and_nanos_together_equal_each_alone() {
        let mut seconds: Vec<u64> = (0..20).map(|power| 10u64.pow(power)).collect();
        seconds.extend([0, 9, 99, 1_700_000_000, 1_700_000_123, u64::MAX]);
        for secs in seconds {
            for nanos in [0, 1, 999, 1000, 2_500_000, 120_000_000, 999_999_000, 999_999_999, 1_000_000_000] {
                let ts = Timestamp::from_numeric(secs, nanos);
                let mut apart = Vec::new();
                push_timestamp(&mut apart, &ts);
                apart.extend_from_slice(b",\"ts_ns\":");
                push_nanos(&mut apart, &ts);
                let mut together = Vec::new();
                push_timestamp_and_nanos(&mut together, &ts, b",\"ts_ns\":");
                assert_eq!(
                    String::from_utf8(together).unwrap(),
                    String::from_utf8(apart).unwrap(),
                    "{secs} {nanos}"
                );
            }
        }
    }

    #[test]
    fn hex_digits_side_by_side_equal_formatting() {
        let values =
            (0..=0xFFFFu32).chain((0..=0xFFFF).map(|low| low << 16 | 0xA5C3)).chain([u32::MAX, 0x8000_0000]);
        for value in values {
            assert_eq!(hex8(value), format!("{value:08X}").as_bytes(), "{value:#x}");
        }
        for digits in 0..=10u8 {
            for value in [0, 1, 0xF, 0x211, 0xAA01, 0x1234_5678, u32::MAX] {
                let mut out = b"x".to_vec();
                push_hex_value(&mut out, value, digits);
                // The digits asked for (the value cut to them, as a fixed-width column would) or more.
                let full = format!("{value:0width$X}", width = usize::from(digits));
                let expected = if digits == 0 {
                    String::new()
                } else {
                    full[full.len() - usize::from(digits)..].to_string()
                };
                assert_eq!(String::from_utf8(out).unwrap(), format!("x0x{expected}"), "{value:#x} {digits}");
            }
        }
    }

    #[test]
    fn nanos_print_as_the_whole_number() {
        for (secs, nanos) in
            [(0, 0), (0, 2_500_000), (1, 0), (1_700_000_000, 2_500_000), (u64::MAX, 999_999_999)]
        {
            let ts = Timestamp::from_numeric(secs, nanos);
            let mut out = Vec::new();
            push_nanos(&mut out, &ts);
            assert_eq!(out, ts.as_nanos().to_string().as_bytes(), "{secs} {nanos}");
        }
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
        out.clear();
        push_hex_value(&mut out, 0xA, 2);
        push_hex_value(&mut out, 0xAA01, 4);
        push_hex_value(&mut out, 0x1234, 10);
        assert_eq!(out, b"0x0A0xAA010x0000001234");
        out.clear();
        push_hex(&mut out, &[0x5A; 64]);
        assert_eq!(out, "5A".repeat(64).as_bytes());
        out.clear();
        // The eight-byte payload's own path.
        push_hex(&mut out, &[0x00, 0x01, 0x7F, 0x80, 0xA5, 0xC3, 0xFE, 0xFF]);
        assert_eq!(out, b"00017F80A5C3FEFF");
    }
}
