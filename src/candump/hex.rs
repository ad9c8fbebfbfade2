//! Byte-level helpers shared by the parsers: a hex lookup table and small scanners.

/// Marks a byte that is not a hex digit in [`HEX_VALUE`].
pub(crate) const NOT_HEX: u8 = 0xFF;

/// Value of every byte as a hex digit (either case), or [`NOT_HEX`]. A table beats branching on ranges
/// in the hot loop.
pub(crate) static HEX_VALUE: [u8; 256] = {
    let mut table = [NOT_HEX; 256];
    let mut i = 0;
    while i < 10 {
        table[b'0' as usize + i] = i as u8;
        i += 1;
    }
    let mut i = 0;
    while i < 6 {
        table[b'A' as usize + i] = 10 + i as u8;
        table[b'a' as usize + i] = 10 + i as u8;
        i += 1;
    }
    table
};

/// Uppercase hex digits, as candump writes them.
pub(crate) const HEX_UPPER: &[u8; 16] = b"0123456789ABCDEF";

#[inline]
pub(crate) fn hex_value(byte: u8) -> Option<u8> {
    let value = HEX_VALUE[byte as usize];
    (value != NOT_HEX).then_some(value)
}

#[inline]
pub(crate) fn is_hex(byte: u8) -> bool {
    HEX_VALUE[byte as usize] != NOT_HEX
}

/// Decodes two hex digits into a byte.
#[inline]
pub(crate) fn hex_pair(hi: u8, lo: u8) -> Option<u8> {
    let (hi, lo) = (HEX_VALUE[hi as usize], HEX_VALUE[lo as usize]);
    // Both lookups are < 16 unless one is NOT_HEX, so one test covers both.
    ((hi | lo) & 0xF0 == 0).then_some((hi << 4) | lo)
}

/// Decodes 16 hex digits into 8 bytes (a full classic payload), all sixteen at once in an SSE2 register
/// (x86-64 always has SSE2): one validity test, no table (measured: table lookups took 110 instructions a
/// line, two SWAR words 50, this 20).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) fn hex_bytes_8(digits: &[u8; 16]) -> Option<[u8; 8]> {
    use std::arch::x86_64::{
        _mm_add_epi8, _mm_and_si128, _mm_cmpgt_epi8, _mm_cmplt_epi8, _mm_cvtsi128_si64, _mm_movemask_epi8,
        _mm_or_si128, _mm_packus_epi16, _mm_set1_epi16, _mm_set1_epi8, _mm_set_epi64x, _mm_setzero_si128,
        _mm_slli_epi16, _mm_srli_epi16,
    };
    let (first, second) = digits.split_at(8);
    let word = |half: &[u8]| half.try_into().map(i64::from_le_bytes);
    let (first, second) = (word(first).ok()?, word(second).ok()?);
    // SAFETY: these intrinsics only compute on registers (no memory access) and need SSE2, which every
    // x86-64 processor has (it is in the target's baseline features).
    let packed = unsafe {
        let text = _mm_set_epi64x(second, first);
        // Signed byte compares: bytes from 0x80 up are negative, so below every bound and in no range.
        let between = |bytes, lo: u8, hi: u8| {
            let above = _mm_cmpgt_epi8(bytes, _mm_set1_epi8((lo - 1) as i8));
            _mm_and_si128(above, _mm_cmplt_epi8(bytes, _mm_set1_epi8((hi + 1) as i8)))
        };
        let decimal = between(text, b'0', b'9');
        // Setting 0x20 folds `A-F` onto `a-f` and moves nothing else into that range.
        let letter = between(_mm_or_si128(text, _mm_set1_epi8(0x20)), b'a', b'f');
        if _mm_movemask_epi8(_mm_or_si128(decimal, letter)) != 0xFFFF {
            return None;
        }
        let values =
            _mm_add_epi8(_mm_and_si128(text, _mm_set1_epi8(0x0F)), _mm_and_si128(letter, _mm_set1_epi8(9)));
        // Each 16-bit lane holds a byte's first digit low and its second high: the byte is
        // first << 4 | second, then the lanes are packed to bytes (all below 0x100: nothing saturates).
        let first_digits = _mm_slli_epi16(_mm_and_si128(values, _mm_set1_epi16(0x00FF)), 4);
        let bytes = _mm_or_si128(first_digits, _mm_srli_epi16(values, 8));
        _mm_cvtsi128_si64(_mm_packus_epi16(bytes, _mm_setzero_si128()))
    };
    Some(packed.to_le_bytes())
}

/// [`hex_bytes_8`] without SSE2: SWAR, eight digits at a time in a u64, with one validity test for each
/// eight. Built (and tested) everywhere; used where the target is not x86-64.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
pub(crate) fn hex_bytes_8(digits: &[u8; 16]) -> Option<[u8; 8]> {
    hex_bytes_8_swar(digits)
}

#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline(always)]
fn hex_bytes_8_swar(digits: &[u8; 16]) -> Option<[u8; 8]> {
    let (first, second) = digits.split_at(8);
    let first = hex_word(u64::from_le_bytes(first.try_into().ok()?))?;
    let second = hex_word(u64::from_le_bytes(second.try_into().ok()?))?;
    Some((first | (second << 32)).to_le_bytes())
}

/// Eight ASCII hex digits, the first in the lowest byte, as four bytes in the low 32 bits (the first byte
/// lowest); `None` unless every byte is `0-9`, `A-F` or `a-f` (exactly what [`HEX_VALUE`] accepts).
#[inline(always)]
fn hex_word(digits: u64) -> Option<u64> {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    if digits & HIGH != 0 {
        return None;
    }
    // For bytes below 0x80: the high bit of each byte of the result says whether it lies in lo..=hi
    // (b + 0x80 - lo reaches 0x80 when b >= lo; b + 0x7F - hi does when b > hi; no carry between bytes).
    let in_range = |word: u64, lo: u8, hi: u8| {
        (word + ONES * u64::from(0x80 - lo)) & !(word + ONES * u64::from(0x7F - hi)) & HIGH
    };
    let decimal = in_range(digits, b'0', b'9');
    // Setting 0x20 folds `A-F` onto `a-f` and moves nothing else into that range.
    let letter = in_range(digits | (ONES * 0x20), b'a', b'f');
    if decimal | letter != HIGH {
        return None;
    }
    let values = (digits & (ONES * 0x0F)) + (letter >> 7) * 9;
    // Each 16-bit lane: its first digit (the high nibble) and second digit into its low byte.
    const LOW_BYTES: u64 = 0x00FF_00FF_00FF_00FF;
    let pairs = ((values & LOW_BYTES) << 4) | ((values >> 8) & LOW_BYTES);
    // The four low bytes of the lanes, gathered into the low 32 bits.
    let pairs = (pairs | (pairs >> 8)) & 0x0000_FFFF_0000_FFFF;
    Some((pairs | (pairs >> 16)) & 0xFFFF_FFFF)
}

/// Whether two byte strings are equal; names of up to 16 bytes (interface names) are compared as two
/// overlapping words each, inline, instead of through a `memcmp` call (measured: one call per line).
#[inline(always)]
pub fn same_bytes(a: &[u8], b: &[u8]) -> bool {
    let len = a.len();
    if len != b.len() {
        return false;
    }
    match len {
        0 => true,
        // Positions 0, len / 2 and len - 1 cover every byte of 1 to 3.
        1..=3 => a.first() == b.first() && a.get(len / 2) == b.get(len / 2) && a.last() == b.last(),
        4..=8 => word::<4>(a, 0) == word::<4>(b, 0) && word::<4>(a, len - 4) == word::<4>(b, len - 4),
        9..=16 => word::<8>(a, 0) == word::<8>(b, 0) && word::<8>(a, len - 8) == word::<8>(b, len - 8),
        _ => a == b,
    }
}

/// The `N` bytes of `bytes` at `at`, as one array (compared as a word).
#[inline(always)]
fn word<const N: usize>(bytes: &[u8], at: usize) -> Option<[u8; N]> {
    bytes.get(at..at + N)?.try_into().ok()
}

/// Value of an all-hex slice of at most 8 digits; `None` if any byte is not hex.
#[inline]
pub(crate) fn hex_u32(digits: &[u8]) -> Option<u32> {
    let mut value = 0u32;
    for &byte in digits {
        value = (value << 4) | u32::from(hex_value(byte)?);
    }
    Some(value)
}

/// Index of the first byte at or after `pos` that is not a space.
#[inline]
pub(crate) fn skip_spaces(text: &[u8], mut pos: usize) -> usize {
    while text.get(pos) == Some(&b' ') {
        pos += 1;
    }
    pos
}

/// Index of the first space at or after `pos`, or `text.len()`.
#[inline]
pub(crate) fn token_end(text: &[u8], mut pos: usize) -> usize {
    while let Some(&byte) = text.get(pos) {
        if byte == b' ' {
            break;
        }
        pos += 1;
    }
    pos
}

/// Parses up to 19 decimal digits starting at `pos` (19 digits always fit in a u64).
/// Returns the value and the number of digits consumed (which may be 0); more digits are left alone.
#[inline(always)]
pub(crate) fn decimal_u64(text: &[u8], pos: usize) -> (u64, usize) {
    let mut value = 0u64;
    let mut count = 0;
    for &byte in text.get(pos..).unwrap_or_default().iter().take(19) {
        let digit = byte.wrapping_sub(b'0');
        if digit > 9 {
            break;
        }
        value = value * 10 + u64::from(digit);
        count += 1;
    }
    (value, count)
}

/// Whitespace-separated fields (spaces and TABs) with their start index, for the column formats (ASC, trc).
pub(crate) fn fields(text: &[u8]) -> impl Iterator<Item = (usize, &[u8])> {
    let mut pos = 0;
    std::iter::from_fn(move || {
        while matches!(text.get(pos), Some(b' ' | b'\t')) {
            pos += 1;
        }
        let start = pos;
        while matches!(text.get(pos), Some(byte) if !matches!(byte, b' ' | b'\t')) {
            pos += 1;
        }
        (pos > start).then(|| (start, &text[start..pos]))
    })
}

/// `secs[.frac]` in units of `unit_nanos` nanoseconds (1_000_000_000 for seconds, 1_000_000 for ms) as
/// whole seconds and nanoseconds; `None` unless digits, an optional dot and digits (at most 9 after it).
pub(crate) fn decimal_time(text: &[u8], unit_nanos: u64) -> Option<(u64, u32)> {
    let (int, frac) = match memchr::memchr(b'.', text) {
        Some(dot) => (&text[..dot], &text[dot + 1..]),
        None => (text, &b""[..]),
    };
    let (whole, int_digits) = decimal_u64(int, 0);
    let (fraction, frac_digits) = decimal_u64(frac, 0);
    if int_digits == 0 || int_digits != int.len() || frac_digits != frac.len() || frac_digits > 9 {
        return None;
    }
    // fraction / 10^digits units, in nanoseconds (exact: unit_nanos is a power of ten >= 10^digits or
    // the remainder is dropped below a nanosecond).
    let frac_nanos = u128::from(fraction) * u128::from(unit_nanos) / 10u128.pow(frac_digits as u32);
    let total = u128::from(whole) * u128::from(unit_nanos) + frac_nanos;
    let secs = u64::try_from(total / 1_000_000_000).ok()?;
    Some((secs, (total % 1_000_000_000) as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_table_accepts_both_cases_and_nothing_else() {
        for byte in 0..=255u8 {
            let expected = (byte as char).to_digit(16).map(|d| d as u8);
            assert_eq!(hex_value(byte), expected, "byte {byte:#x}");
        }
        assert_eq!(hex_pair(b'a', b'F'), Some(0xAF));
        assert_eq!(hex_pair(b'g', b'0'), None);
        assert_eq!(hex_pair(b'0', b' '), None);
        assert_eq!(hex_u32(b"1FFFFFFF"), Some(0x1FFF_FFFF));
        assert_eq!(hex_u32(b"12x"), None);
        assert_eq!(hex_bytes_8(b"00B1fF0123456789"), Some([0x00, 0xB1, 0xFF, 0x01, 0x23, 0x45, 0x67, 0x89]));
        for at in 0..16 {
            let mut digits = *b"0123456789ABCDEF";
            digits[at] = b'g';
            assert_eq!(hex_bytes_8(&digits), None);
        }
    }

    /// The word-at-a-time decoding against the table, for every byte value at every position.
    #[test]
    fn hex_bytes_8_agrees_with_the_table_for_every_byte() {
        let by_table = |digits: &[u8; 16]| -> Option<[u8; 8]> {
            let mut bytes = [0u8; 8];
            for (byte, pair) in bytes.iter_mut().zip(digits.chunks_exact(2)) {
                *byte = hex_pair(pair[0], pair[1])?;
            }
            Some(bytes)
        };
        for base in [*b"0123456789ABCDEF", *b"fedcba9876543210", *b"0000000000000000", *b"FfFfaAbB09afAF90"] {
            assert_eq!(hex_bytes_8(&base), by_table(&base));
            for at in 0..16 {
                for byte in 0..=255u8 {
                    let mut digits = base;
                    digits[at] = byte;
                    assert_eq!(hex_bytes_8(&digits), by_table(&digits), "{:?}", digits);
                    assert_eq!(hex_bytes_8_swar(&digits), by_table(&digits), "{:?}", digits);
                }
            }
        }
        // Two bad bytes at once, anywhere: the validity test is one for all sixteen.
        for at in 0..16 {
            for other in 0..16 {
                for byte in [b'/', b':', b'@', b'G', b'`', b'g', 0x80, 0xB0, 0xC1, 0xFF] {
                    let mut digits = *b"0123456789abcdef";
                    digits[at] = byte;
                    digits[other] = b'F';
                    assert_eq!(hex_bytes_8(&digits), by_table(&digits), "{:?}", digits);
                    assert_eq!(hex_bytes_8_swar(&digits), by_table(&digits), "{:?}", digits);
                }
            }
        }
        assert_eq!(hex_bytes_8(b"fedcba9876543210"), Some([0xFE, 0xDC, 0xBA, 0x98, 0x76, 0x54, 0x32, 0x10]));
        assert_eq!(hex_bytes_8(b"0000000000000000"), Some([0; 8]));
        assert_eq!(hex_bytes_8(b"FFFFFFFFFFFFFFFF"), Some([0xFF; 8]));
    }

    #[test]
    fn same_bytes_compares_every_byte_of_every_length() {
        for len in 0..=24usize {
            let name: Vec<u8> = (0..len).map(|i| b'a' + i as u8).collect();
            assert!(same_bytes(&name, &name.clone()), "length {len}");
            for at in 0..len {
                let mut other = name.clone();
                other[at] ^= 0x01;
                assert!(!same_bytes(&name, &other), "length {len}, byte {at}");
            }
            assert!(!same_bytes(&name, &name[..len.saturating_sub(1)]) || len == 0);
        }
        assert!(same_bytes(b"can0", b"can0"));
        assert!(!same_bytes(b"can0", b"can1"));
        assert!(!same_bytes(b"vcan0", b"can0"));
    }

    #[test]
    fn decimal_stops_at_19_digits_and_non_digits() {
        assert_eq!(decimal_u64(b"0012x", 0), (12, 4));
        assert_eq!(decimal_u64(b"x", 0), (0, 0));
        assert_eq!(decimal_u64(b"99999999999999999999", 0), (9_999_999_999_999_999_999, 19));
        assert_eq!(decimal_u64(b"12", 5), (0, 0));
    }
}
