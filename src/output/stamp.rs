//! The time column of `monitor`'s text lines in candump's `-t` modes: absolute seconds (`a`, today's
//! column), the delta from the previous line (`d`), seconds since the first line (`z`) and the local date and
//! time (`A`). Written into the line buffer without allocating.

use super::number::{push_int, push_timestamp};
use crate::candump::Timestamp;

const NANOS: i128 = 1_000_000_000;

/// Which time candump's `-t` shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TimeMode {
    /// Seconds since the epoch as received, 6 or 9 decimals (`-t a`; what `decode` prints too).
    #[default]
    Absolute,
    /// Seconds since the previous line (`-t d`): `000.020000`; the first line is 0.
    Delta,
    /// Seconds since the first line (`-t z`): `001.250000`.
    Zero,
    /// Local date and time (`-t A`): `2023-11-14 22:13:20.000250`.
    Date,
}

/// Writes stamps in one mode, remembering the first and the previous stamp shown.
#[derive(Clone, Debug)]
pub struct Clock {
    mode: TimeMode,
    first: Option<Timestamp>,
    previous: Option<Timestamp>,
    /// Nine decimals from the first stamp with sub-microsecond precision on, so the column stays aligned
    /// (a nanosecond stamp that happens to be a whole microsecond would otherwise print six).
    nine_digits: bool,
}

impl Clock {
    pub fn new(mode: TimeMode) -> Self {
        #[cfg(unix)]
        if mode == TimeMode::Date {
            // The local time zone (TZ, /etc/localtime) is read once, before the first line.
            // SAFETY: tzset only reads the environment and the zone files into libc's own state.
            unsafe { tzset() };
        }
        Self { mode, first: None, previous: None, nine_digits: false }
    }

    pub fn mode(&self) -> TimeMode {
        self.mode
    }

    /// The time column for a line stamped `ts` (`-` without a stamp).
    pub fn push(&mut self, out: &mut Vec<u8>, ts: Option<&Timestamp>) {
        let Some(ts) = ts else {
            out.push(b'-');
            return;
        };
        self.nine_digits |= ts.nanos % 1000 != 0;
        match self.mode {
            TimeMode::Absolute => push_timestamp(out, ts),
            TimeMode::Delta => {
                let since = self.previous.unwrap_or(*ts);
                push_span(out, nanos(ts) - nanos(&since), self.nine_digits);
            }
            TimeMode::Zero => {
                let first = *self.first.get_or_insert(*ts);
                push_span(out, nanos(ts) - nanos(&first), self.nine_digits);
            }
            TimeMode::Date => {
                if !push_local_date(out, ts, self.nine_digits) {
                    // Beyond what the C library converts (year 2^31): the seconds, still true.
                    push_timestamp(out, ts);
                }
            }
        }
        self.previous = Some(*ts);
    }
}

fn nanos(ts: &Timestamp) -> i128 {
    // At most (2^64 - 1) * 10^9 + 10^9: far inside i128.
    i128::from(ts.secs) * NANOS + i128::from(ts.nanos)
}

/// `SSS.ffffff` as candump's `%03llu.%06llu`, 9 decimals when asked; a stamp earlier than the one it is
/// measured from keeps its minus sign (candump would show 0, hiding that the source went backwards).
fn push_span(out: &mut Vec<u8>, span: i128, nine_digits: bool) {
    if span < 0 {
        out.push(b'-');
    }
    let span = span.unsigned_abs();
    let secs = span / NANOS as u128;
    if secs < 100 {
        out.extend(std::iter::repeat_n(b'0', if secs < 10 { 2 } else { 1 }));
    }
    push_int(out, secs);
    push_fraction(out, (span % NANOS as u128) as u32, nine_digits);
}

/// `.ffffff` (microseconds, truncated as candump does) or `.fffffffff`.
fn push_fraction(out: &mut Vec<u8>, nanos: u32, nine_digits: bool) {
    out.push(b'.');
    let (value, digits) = if nine_digits { (nanos, 9) } else { (nanos / 1000, 6) };
    let mut buffer = itoa::Buffer::new();
    let text = buffer.format(value).as_bytes();
    out.extend(std::iter::repeat_n(b'0', digits - text.len()));
    out.extend_from_slice(text);
}

/// `YYYY-MM-DD HH:MM:SS.ffffff` in the local time zone; false when the C library cannot convert the stamp.
fn push_local_date(out: &mut Vec<u8>, ts: &Timestamp, nine_digits: bool) -> bool {
    let Some(tm) = local_fields(ts.secs) else { return false };
    push_padded(out, i64::from(tm.tm_year) + 1900, 4);
    out.push(b'-');
    push_padded(out, i64::from(tm.tm_mon) + 1, 2);
    out.push(b'-');
    push_padded(out, i64::from(tm.tm_mday), 2);
    out.push(b' ');
    push_padded(out, i64::from(tm.tm_hour), 2);
    out.push(b':');
    push_padded(out, i64::from(tm.tm_min), 2);
    out.push(b':');
    push_padded(out, i64::from(tm.tm_sec), 2);
    push_fraction(out, ts.nanos, nine_digits);
    true
}

/// The local calendar fields of `secs` since the epoch (POSIX's thread-safe `localtime_r`).
#[cfg(unix)]
fn local_fields(secs: u64) -> Option<libc::tm> {
    // libc marks time_t deprecated on musl (its width changed in musl 1.2); it is the type localtime_r takes.
    #[allow(deprecated)]
    let secs = libc::time_t::try_from(secs).ok()?;
    // SAFETY: an all-zero `tm` is a valid value (integers and a null zone name pointer).
    let mut tm: libc::tm = unsafe { std::mem::zeroed() };
    // SAFETY: both pointers are to live locals; localtime_r is the thread-safe form and writes only `tm`.
    let converted = !unsafe { libc::localtime_r(&secs, &mut tm) }.is_null();
    converted.then_some(tm)
}

/// The local calendar fields of `secs` since the epoch (the C runtime's thread-safe `localtime_s`).
#[cfg(windows)]
fn local_fields(secs: u64) -> Option<libc::tm> {
    let secs = libc::time_t::try_from(secs).ok()?;
    // SAFETY: an all-zero `tm` is a valid value (integers only on Windows).
    let mut tm: libc::tm = unsafe { std::mem::zeroed() };
    // SAFETY: both pointers are to live locals; localtime_s writes only `tm`.
    let converted = unsafe { libc::localtime_s(&mut tm, &secs) } == 0;
    converted.then_some(tm)
}

/// A non-negative number with leading zeros to `width` digits (years before 1000 included).
fn push_padded(out: &mut Vec<u8>, value: i64, width: usize) {
    let mut buffer = itoa::Buffer::new();
    let text = buffer.format(value).as_bytes();
    out.extend(std::iter::repeat_n(b'0', width.saturating_sub(text.len())));
    out.extend_from_slice(text);
}

#[cfg(unix)]
extern "C" {
    // POSIX; the libc crate does not declare it on every target.
    fn tzset();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::TimestampKind;

    fn stamp(secs: u64, nanos: u32) -> Timestamp {
        Timestamp { secs, nanos, kind: TimestampKind::Absolute }
    }

    fn column(clock: &mut Clock, ts: Timestamp) -> String {
        let mut out = Vec::new();
        clock.push(&mut out, Some(&ts));
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn delta_and_zero_are_candump_columns() {
        let mut delta = Clock::new(TimeMode::Delta);
        let mut zero = Clock::new(TimeMode::Zero);
        let stamps =
            [stamp(1_700_000_000, 0), stamp(1_700_000_000, 20_000_000), stamp(1_700_000_123, 500_000)];
        let deltas: Vec<String> = stamps.iter().map(|ts| column(&mut delta, *ts)).collect();
        let zeros: Vec<String> = stamps.iter().map(|ts| column(&mut zero, *ts)).collect();
        assert_eq!(deltas, ["000.000000", "000.020000", "122.980500"]);
        assert_eq!(zeros, ["000.000000", "000.020000", "123.000500"]);
        // Backwards: the minus sign stays; beyond 999 s the seconds grow.
        assert_eq!(column(&mut delta, stamp(1_700_000_123, 0)), "-000.000500");
        assert_eq!(column(&mut zero, stamp(1_700_001_234, 0)), "1234.000000");
    }

    #[test]
    fn nine_decimals_once_a_stamp_has_nanoseconds() {
        let mut zero = Clock::new(TimeMode::Zero);
        assert_eq!(column(&mut zero, stamp(10, 1)), "000.000000000");
        assert_eq!(column(&mut zero, stamp(11, 1)), "001.000000000");
        let mut absolute = Clock::new(TimeMode::Absolute);
        assert_eq!(column(&mut absolute, stamp(1_700_000_000, 250_000)), "1700000000.000250");
        let mut out = Vec::new();
        absolute.push(&mut out, None);
        assert_eq!(out, b"-");
    }

    #[cfg(unix)]
    #[test]
    fn dates_are_local_and_out_of_range_ones_stay_seconds() {
        // TZ is not set by the tests: the shape is checked, the value in tests/integration/monitor_modes.rs.
        let mut date = Clock::new(TimeMode::Date);
        let text = column(&mut date, stamp(1_700_000_000, 250_000));
        let bytes = text.as_bytes();
        assert_eq!(bytes.len(), 26, "{text}");
        for (at, separator) in [(4, b'-'), (7, b'-'), (10, b' '), (13, b':'), (16, b':'), (19, b'.')] {
            assert_eq!(bytes[at], separator, "{text}");
        }
        assert!(text.ends_with(".000250"), "{text}");
        assert_eq!(column(&mut date, stamp(u64::MAX, 0)), "18446744073709551615.000000");
    }
}
