//! Reading timestamps as candump writes them: `(1700000000.002500)`, `(000.123456)`,
//! `(2020-12-19 12:04:45.485261)`, and the running sum of `-t d` deltas. The [`Timestamp`] type itself is
//! in `record.rs`, with the records that carry it.

use super::hex::decimal_u64;
use super::record::{Timestamp, TimestampKind};
use super::Reason;

/// `[year, month, day, hour, minute, second]` of the local time zone (`TZ`) as seconds since the epoch;
/// `None` for a date mktime cannot place or one before 1970.
pub(crate) fn local_to_epoch([year, month, day, hour, minute, second]: [u64; 6]) -> Option<u64> {
    let field = |value: u64| libc::c_int::try_from(value).ok();
    // SAFETY: a zeroed tm is a valid value; mktime reads and normalises the struct we own and the process's
    // time zone, which nothing here changes.
    let epoch = unsafe {
        let mut tm: libc::tm = std::mem::zeroed();
        tm.tm_year = field(year)?.checked_sub(1900)?;
        tm.tm_mon = field(month)?.checked_sub(1)?;
        (tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec) =
            (field(day)?, field(hour)?, field(minute)?, field(second)?);
        tm.tm_isdst = -1;
        mktime(&mut tm)
    };
    u64::try_from(epoch).ok()
}

#[cfg(unix)]
use libc::mktime;

#[cfg(windows)]
extern "C" {
    // The C runtime's 64-bit mktime (libc declares no mktime for Windows).
    #[link_name = "_mktime64"]
    fn mktime(tm: *mut libc::tm) -> i64;
}

/// Scales a fraction of `digits` decimal digits to nanoseconds.
const NANO_SCALE: [u32; 10] = [0, 100_000_000, 10_000_000, 1_000_000, 100_000, 10_000, 1_000, 100, 10, 1];

/// Error position (0-based index into the text) and reason.
pub(crate) type PosError = (usize, Reason);

/// Parses `secs.frac)` starting at `pos` (just after the `(`). Returns seconds, nanoseconds and the index
/// just past the `)`. Accepts 1..=19 seconds digits and 1..=9 fraction digits.
#[inline]
pub(crate) fn parse_numeric(text: &[u8], pos: usize) -> Result<(u64, u32, usize), PosError> {
    parse_numeric_cached(text, pos, &mut SecondsCache::default())
}

/// [`parse_numeric`] through `cache`, which remembers the seconds of the last candump-layout stamp.
#[inline(always)]
pub(crate) fn parse_numeric_cached(
    text: &[u8],
    pos: usize,
    cache: &mut SecondsCache,
) -> Result<(u64, u32, usize), PosError> {
    match parse_candump_stamp(text, pos, cache) {
        Some(parsed) => Ok(parsed),
        None => parse_numeric_any(text, pos),
    }
}

/// The ten seconds digits of the last candump-layout stamp and their value. A log's lines mostly share
/// their second with the line before, so a stamp with the same ten bytes skips their digit check and
/// conversion (callgrind: 5 % of `decode --summary`'s instructions). Holds nothing until a stamp's
/// seconds were checked as digits: no byte pattern can match an empty cache.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SecondsCache {
    checked: bool,
    /// The first eight seconds bytes as one word, the last two as another.
    head: u64,
    rest: u16,
    value: u64,
}

/// candump's own layout, `1700000000.002500)` (10 seconds digits, 6 fraction digits), in one pass of
/// integer arithmetic: 8 digits at a time in a u64 (measured: a third of the summary's instructions went
/// to the digit-by-digit scan), the seconds through `cache`. `None` for any other layout, which the general
/// scan reads.
#[inline(always)]
fn parse_candump_stamp(text: &[u8], pos: usize, cache: &mut SecondsCache) -> Option<(u64, u32, usize)> {
    let stamp: &[u8; 18] = text.get(pos..pos + 18)?.try_into().ok()?;
    let (seconds, tail) = stamp.split_at(10);
    // `.ffffff)` as one word: the dot in the lowest byte, the parenthesis in the highest.
    let tail = u64::from_le_bytes(tail.try_into().ok()?);
    if tail & 0xFF != u64::from(b'.') || tail >> 56 != u64::from(b')') {
        return None;
    }
    let (head_bytes, rest_bytes) = seconds.split_at(8);
    let head = u64::from_le_bytes(head_bytes.try_into().ok()?);
    let rest = u16::from_le_bytes(rest_bytes.try_into().ok()?);
    let secs = if cache.checked && cache.head == head && cache.rest == rest {
        cache.value
    } else {
        let [s0, s1, ..] = *stamp;
        if !s0.is_ascii_digit() || !s1.is_ascii_digit() {
            return None;
        }
        let low = eight_digits(seconds.get(2..10)?.try_into().ok()?)?;
        let value = u64::from(s0 - b'0') * 1_000_000_000 + u64::from(s1 - b'0') * 100_000_000 + low;
        *cache = SecondsCache { checked: true, head, rest, value };
        value
    };
    // The six fraction digits moved up two bytes, with two zeros before them: their value in microseconds.
    let fraction = eight_digits((((tail >> 8) << 16) | 0x3030).to_le_bytes())?;
    Some((secs, fraction as u32 * NANO_SCALE[6], pos + 18))
}

/// The value of 8 ASCII decimal digits (the first is the most significant), or `None` if any byte is not
/// a digit. SWAR: all eight bytes are checked and combined in a few operations on one u64.
#[inline(always)]
pub(crate) fn eight_digits(bytes: [u8; 8]) -> Option<u64> {
    let digits = u64::from_le_bytes(bytes).wrapping_sub(0x3030_3030_3030_3030);
    // A byte below '0' wraps to 0xD0.. and one above '9' reaches 0x10 once 6 is added: either sets a high
    // nibble. The lowest bad byte always shows (no borrow or carry reaches it), which is all that matters.
    if (digits | digits.wrapping_add(0x0606_0606_0606_0606)) & 0xF0F0_F0F0_F0F0_F0F0 != 0 {
        return None;
    }
    // Pairs, then quadruples, then all eight (little-endian: the first digit is the lowest byte).
    let pairs = digits.wrapping_mul(10).wrapping_add(digits >> 8) & 0x00FF_00FF_00FF_00FF;
    let quads = pairs.wrapping_mul(100).wrapping_add(pairs >> 16) & 0x0000_FFFF_0000_FFFF;
    Some(quads.wrapping_mul(10_000).wrapping_add(quads >> 32) & 0xFFFF_FFFF)
}

/// [`parse_numeric`] for every layout, with the error positions.
#[inline(never)]
fn parse_numeric_any(text: &[u8], pos: usize) -> Result<(u64, u32, usize), PosError> {
    let (secs, secs_digits) = decimal_u64(text, pos);
    let mut at = pos + secs_digits;
    match text.get(at) {
        Some(b'.') if secs_digits > 0 => {}
        Some(byte) if byte.is_ascii_digit() => return Err((pos, Reason::TimestampTooLarge)),
        _ => return Err(bad_char(text, pos, at, Reason::BadTimestamp)),
    }
    at += 1;
    let frac_start = at;
    let (frac, frac_digits) = decimal_u64(text, frac_start);
    at += frac_digits;
    if frac_digits == 0 || frac_digits > 9 {
        return Err(bad_char(text, pos, frac_start, Reason::TimestampFraction));
    }
    if text.get(at) != Some(&b')') {
        return Err(bad_char(text, pos, at, Reason::BadTimestamp));
    }
    // frac < 10^9 and the scale makes it nanoseconds, so the product fits in u32.
    let nanos = frac as u32 * NANO_SCALE[frac_digits];
    Ok((secs, nanos, at + 1))
}

/// Parses the `-t A` form `YYYY-MM-DD HH:MM:SS.frac)` starting at `pos` (just after the `(`), treating the
/// wall-clock time as UTC (candump printed local time and did not say which zone).
pub(crate) fn parse_date_time(text: &[u8], pos: usize) -> Result<(u64, u32, usize), PosError> {
    // Fixed-width fields and the separator expected after each.
    const FIELDS: [(usize, u8); 6] = [(4, b'-'), (2, b'-'), (2, b' '), (2, b':'), (2, b':'), (2, b'.')];
    let mut values = [0u64; 6];
    let mut at = pos;
    for (value, &(width, separator)) in values.iter_mut().zip(FIELDS.iter()) {
        let (number, digits) = decimal_u64(text, at);
        if digits != width || text.get(at + width) != Some(&separator) {
            return Err(bad_char(text, pos, at, Reason::BadDateTime));
        }
        *value = number;
        at += width + 1;
    }
    let (frac, frac_digits) = decimal_u64(text, at);
    if frac_digits == 0 || frac_digits > 9 {
        return Err(bad_char(text, pos, at, Reason::TimestampFraction));
    }
    at += frac_digits;
    if text.get(at) != Some(&b')') {
        return Err(bad_char(text, pos, at, Reason::BadTimestamp));
    }
    let [year, month, day, hour, minute, second] = values;
    let valid = year >= 1970
        && (1..=12).contains(&month)
        && day >= 1
        && day <= days_in_month(year, month)
        && hour < 24
        && minute < 60
        && second < 60;
    if !valid {
        return Err((pos, Reason::BadDateTime));
    }
    let days = days_from_civil(year as i64, month as u32, day as u32);
    // `valid` guarantees days >= 0 and the year has at most 4 digits, so no overflow.
    let secs = days as u64 * 86_400 + hour * 3_600 + minute * 60 + second;
    Ok((secs, frac as u32 * NANO_SCALE[frac_digits], at + 1))
}

/// The reason for a bad character, unless the real problem is a missing `)`.
fn bad_char(text: &[u8], open: usize, at: usize, reason: Reason) -> PosError {
    let rest = text.get(open..).unwrap_or_default();
    if memchr::memchr(b')', rest).is_none() {
        (open.saturating_sub(1), Reason::UnterminatedTimestamp)
    } else {
        (at, reason)
    }
}

fn is_leap(year: u64) -> bool {
    year % 4 == 0 && (year % 100 != 0 || year % 400 == 0)
}

fn days_in_month(year: u64, month: u64) -> u64 {
    match month {
        2 if is_leap(year) => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// Days since 1970-01-01 of a proleptic Gregorian date (Howard Hinnant's `days_from_civil`).
pub(crate) fn days_from_civil(year: i64, month: u32, day: u32) -> i64 {
    let year = if month <= 2 { year - 1 } else { year };
    let era = if year >= 0 { year } else { year - 399 } / 400;
    let year_of_era = year - era * 400; // [0, 399]
    let month_from_march = if month > 2 { month - 3 } else { month + 9 }; // [0, 11]
    let day_of_year = (153 * i64::from(month_from_march) + 2) / 5 + i64::from(day) - 1; // [0, 365]
    let day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year; // [0, 146096]
    era * 146_097 + day_of_era - 719_468
}

/// Running sum of `-t d` deltas. Saturating addition of non-negative values is associative, so sums of
/// consecutive runs of lines (a parallel decode's chunks) add up to exactly the sum of all of them.
#[derive(Clone, Copy, Debug, Default)]
pub struct DeltaSum {
    secs: u64,
    nanos: u32,
    /// How many deltas were added (tells a summed stamp from a log line's own).
    added: u64,
}

impl DeltaSum {
    /// How many deltas were added.
    pub fn added(&self) -> u64 {
        self.added
    }

    /// The sum as a relative timestamp.
    pub fn total(&self) -> Timestamp {
        Timestamp { secs: self.secs, nanos: self.nanos, kind: TimestampKind::Relative }
    }

    /// Adds one delta and returns the sum as a relative timestamp (saturating, never panicking).
    pub fn add(&mut self, secs: u64, nanos: u32) -> Timestamp {
        self.added = self.added.wrapping_add(1);
        let mut total_nanos = self.nanos + nanos; // both < 10^9: no overflow
        let mut carry = 0;
        if total_nanos >= 1_000_000_000 {
            total_nanos -= 1_000_000_000;
            carry = 1;
        }
        self.secs = self.secs.saturating_add(secs).saturating_add(carry);
        self.nanos = total_nanos;
        Timestamp { secs: self.secs, nanos: self.nanos, kind: TimestampKind::Relative }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numeric_stamps_scale_any_fraction_width() {
        assert_eq!(parse_numeric(b"(1700000000.002500)", 1), Ok((1_700_000_000, 2_500_000, 19)));
        assert_eq!(parse_numeric(b"(0.5)", 1), Ok((0, 500_000_000, 5)));
        assert_eq!(parse_numeric(b"(1614188635.1000000)", 1), Ok((1_614_188_635, 100_000_000, 20)));
        assert_eq!(parse_numeric(b"(1.123456789)", 1), Ok((1, 123_456_789, 13)));
    }

    #[test]
    fn eight_digits_reads_digits_and_rejects_anything_else() {
        assert_eq!(eight_digits(*b"01234567"), Some(1_234_567));
        assert_eq!(eight_digits(*b"99999999"), Some(99_999_999));
        assert_eq!(eight_digits(*b"00000000"), Some(0));
        for bad in 0..=255u8 {
            if bad.is_ascii_digit() {
                continue;
            }
            for at in 0..8 {
                let mut bytes = *b"98765432";
                bytes[at] = bad;
                assert_eq!(eight_digits(bytes), None, "{bad:#x} at {at}");
            }
        }
    }

    #[test]
    fn the_candump_layout_parses_as_the_general_scan_does() {
        // Every layout near candump's: the fast path must agree with the digit-by-digit scan.
        for text in [
            &b"(1700000000.002500) "[..],
            b"(0000000000.000000)",
            b"(9999999999.999999)",
            b"(1700000000.00250)",
            b"(1700000000.0025000)",
            b"(170000000.002500)",
            b"(17000000000.002500)",
            b"(1700000000x002500)",
            b"(1700000000.00250x)",
            b"(170000000a.002500)",
            b"(1700000000.002500]",
            b"(1700/00000.002500)",
            b"(1700000000.002:00)",
        ] {
            assert_eq!(parse_numeric(text, 1), parse_numeric_any(text, 1), "{}", text.escape_ascii());
        }
        assert_eq!(
            parse_candump_stamp(b"(1614188635.123456)", 1, &mut SecondsCache::default()),
            Some((1_614_188_635, 123_456_000, 19))
        );
        assert_eq!(parse_candump_stamp(b"(1614188635.12345)", 1, &mut SecondsCache::default()), None);
    }

    /// The seconds cache gives what a fresh parse gives: after a cached stamp, every byte value at every
    /// position (a changed seconds byte is read afresh, a non-digit rejected); an empty cache takes no
    /// bytes unchecked, not even ten NULs (the words it starts with).
    #[test]
    fn the_seconds_cache_reuses_only_checked_identical_seconds() {
        let fresh = |text: &[u8]| parse_candump_stamp(text, 1, &mut SecondsCache::default());
        let mut nuls = *b"(0000000000.002500)";
        nuls[1..11].fill(0);
        let mut empty = SecondsCache::default();
        assert_eq!(parse_candump_stamp(&nuls, 1, &mut empty), None);
        assert_eq!(parse_numeric_cached(&nuls, 1, &mut empty), parse_numeric_any(&nuls, 1));

        let mut cache = SecondsCache::default();
        assert_eq!(
            parse_candump_stamp(b"(1700000000.002500)", 1, &mut cache),
            Some((1_700_000_000, 2_500_000, 19))
        );
        assert_eq!(
            parse_candump_stamp(b"(1700000000.999999)", 1, &mut cache),
            Some((1_700_000_000, 999_999_000, 19))
        );
        let warm = cache;
        for at in 1..19 {
            for byte in 0..=255u8 {
                let mut text = *b"(1700000000.002500) ";
                text[at] = byte;
                let mut cache = warm;
                assert_eq!(
                    parse_candump_stamp(&text, 1, &mut cache),
                    fresh(&text),
                    "{}",
                    text.escape_ascii()
                );
                // And the stamp after it, back on the cached second.
                assert_eq!(
                    parse_candump_stamp(b"(1700000000.000001)", 1, &mut cache),
                    Some((1_700_000_000, 1_000, 19)),
                    "after {}",
                    text.escape_ascii()
                );
            }
        }
        // A new second replaces the cached one.
        assert_eq!(parse_candump_stamp(b"(1700000001.000000)", 1, &mut cache), Some((1_700_000_001, 0, 19)));
        assert_eq!(parse_candump_stamp(b"(1700000001.5000000)", 1, &mut cache), None);
        assert_eq!(
            parse_numeric_cached(b"(1700000001.5000000)", 1, &mut cache),
            Ok((1_700_000_001, 500_000_000, 20))
        );
        assert_eq!(
            parse_candump_stamp(b"(1700000001.000002)", 1, &mut cache),
            Some((1_700_000_001, 2_000, 19))
        );
    }

    /// The word-at-a-time stamp (seconds in two digits and a word, the fraction in a word with the dot and
    /// the parenthesis) against the digit-by-digit scan: every byte value at every position.
    #[test]
    fn the_candump_layout_agrees_with_the_scan_for_every_byte() {
        for base in [*b"(1700000000.002500) ", *b"(9876543210.987654) ", *b"(0123456789.012345) "] {
            for at in 1..19 {
                for byte in 0..=255u8 {
                    let mut text = base;
                    text[at] = byte;
                    let fast = parse_candump_stamp(&text, 1, &mut SecondsCache::default());
                    if let Some(parsed) = fast {
                        assert_eq!(Ok(parsed), parse_numeric_any(&text, 1), "{}", text.escape_ascii());
                    } else {
                        assert!(!byte.is_ascii_digit() || at == 11 || at == 18, "{}", text.escape_ascii());
                    }
                    assert_eq!(
                        parse_numeric(&text, 1),
                        parse_numeric_any(&text, 1),
                        "{}",
                        text.escape_ascii()
                    );
                }
            }
        }
        assert_eq!(
            parse_candump_stamp(b"(9876543210.987654)", 1, &mut SecondsCache::default()),
            Some((9_876_543_210, 987_654_000, 19))
        );
    }

    #[test]
    fn numeric_stamp_errors_point_at_the_problem() {
        assert_eq!(parse_numeric(b"(1.1234567890)", 1), Err((3, Reason::TimestampFraction)));
        assert_eq!(parse_numeric(b"(1.)", 1), Err((3, Reason::TimestampFraction)));
        assert_eq!(parse_numeric(b"(1.5", 1), Err((0, Reason::UnterminatedTimestamp)));
        assert_eq!(parse_numeric(b"(.5)", 1), Err((1, Reason::BadTimestamp)));
        assert_eq!(parse_numeric(b"(17)", 1), Err((3, Reason::BadTimestamp)));
        assert_eq!(parse_numeric(b"(1.5x)", 1), Err((4, Reason::BadTimestamp)));
        assert_eq!(parse_numeric(b"(12345678901234567890.1)", 1), Err((1, Reason::TimestampTooLarge)));
    }

    #[test]
    fn date_time_is_converted_as_utc() {
        // 2020-12-19 12:04:45 UTC = 1608379485 (date -u -d '2020-12-19 12:04:45' +%s).
        let text = b"(2020-12-19 12:04:45.485261)";
        assert_eq!(parse_date_time(text, 1), Ok((1_608_379_485, 485_261_000, text.len())));
        assert_eq!(parse_date_time(b"(1970-01-01 00:00:00.0)", 1), Ok((0, 0, 23)));
        // Leap day and the last second of a year.
        assert_eq!(parse_date_time(b"(2024-02-29 00:00:00.0)", 1).map(|r| r.0), Ok(1_709_164_800));
        assert_eq!(parse_date_time(b"(2023-12-31 23:59:59.9)", 1).map(|r| r.0), Ok(1_704_067_199));
    }

    #[test]
    fn impossible_dates_are_rejected() {
        for text in [
            &b"(2023-02-29 00:00:00.0)"[..],
            b"(2023-13-01 00:00:00.0)",
            b"(2023-00-01 00:00:00.0)",
            b"(2023-04-31 00:00:00.0)",
            b"(2023-01-01 24:00:00.0)",
            b"(2023-01-01 00:60:00.0)",
            b"(1969-12-31 23:59:59.0)",
        ] {
            assert_eq!(parse_date_time(text, 1), Err((1, Reason::BadDateTime)), "{}", text.escape_ascii());
        }
        assert_eq!(parse_date_time(b"(2023-1-01 00:00:00.0)", 1), Err((6, Reason::BadDateTime)));
        assert_eq!(parse_date_time(b"(2023-01-01 00:00:00.)", 1), Err((21, Reason::TimestampFraction)));
        assert_eq!(parse_date_time(b"(2023-01-01 00:00:00.5", 1), Err((0, Reason::UnterminatedTimestamp)));
    }

    #[test]
    fn days_from_civil_matches_known_dates() {
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
        assert_eq!(days_from_civil(1969, 12, 31), -1);
        assert_eq!(days_from_civil(2023, 11, 14), 19_675);
    }

    #[test]
    fn classification_and_conversions() {
        let ts = Timestamp::from_numeric(1_700_000_000, 2_500_000);
        assert_eq!(ts.kind, TimestampKind::Absolute);
        assert_eq!(ts.as_nanos(), 1_700_000_000_002_500_000);
        assert!((ts.as_secs_f64() - 1_700_000_000.002_5).abs() < 1e-6);
        assert_eq!(Timestamp::from_numeric(99_999_999, 0).kind, TimestampKind::Relative);
        assert_eq!(Timestamp::from_numeric(100_000_000, 0).kind, TimestampKind::Absolute);
    }

    #[test]
    fn delta_sum_carries_nanoseconds() {
        let mut sum = DeltaSum::default();
        assert_eq!(sum.add(0, 600_000_000).as_nanos(), 600_000_000);
        let ts = sum.add(1, 600_000_000);
        assert_eq!((ts.secs, ts.nanos, ts.kind), (2, 200_000_000, TimestampKind::Relative));
        let ts = sum.add(u64::MAX, 0);
        assert_eq!(ts.secs, u64::MAX);
    }
}
