//! File names of the recorder directory, and the time of a recorded line: pure text functions.
//!
//! Times are microseconds since the epoch (UTC), the resolution of a candump -L line. Names sort in time
//! order and hold no `:` (Windows copies of a directory keep them).

use std::time::{Duration, UNIX_EPOCH};

use crate::candump::{Timestamp, TimestampKind};

/// A segment's file name ends so: candump -L text in zstd frames.
pub const SEGMENT_SUFFIX: &str = ".log.zst";

/// `20261128T134500.123Z`: the compact UTC time of `us` with milliseconds.
pub fn stamp_millis(us: u64) -> String {
    compact(&humantime::format_rfc3339_millis(UNIX_EPOCH + Duration::from_micros(us)).to_string())
}

/// `20261128T134500Z`: the compact UTC time of `us` in whole seconds.
pub fn stamp_seconds(us: u64) -> String {
    compact(&humantime::format_rfc3339_seconds(UNIX_EPOCH + Duration::from_micros(us)).to_string())
}

/// `2026-11-28T13:45:00.123Z`: the time for people and JSON.
pub fn rfc3339_millis(us: u64) -> String {
    humantime::format_rfc3339_millis(UNIX_EPOCH + Duration::from_micros(us)).to_string()
}

fn compact(rfc3339: &str) -> String {
    rfc3339.chars().filter(|c| *c != '-' && *c != ':').collect()
}

/// The time a compact stamp names (`20261128T134500.123Z` or `20261128T134500Z`), in microseconds.
pub fn parse_stamp(stamp: &str) -> Option<u64> {
    let bytes = stamp.as_bytes();
    if bytes.len() < 16 || bytes[8] != b'T' || !stamp.is_ascii() {
        return None;
    }
    let text = format!(
        "{}-{}-{}T{}:{}:{}",
        &stamp[0..4],
        &stamp[4..6],
        &stamp[6..8],
        &stamp[9..11],
        &stamp[11..13],
        &stamp[13..]
    );
    let time = humantime::parse_rfc3339(&text).ok()?;
    u64::try_from(time.duration_since(UNIX_EPOCH).ok()?.as_micros()).ok()
}

/// A frame's stamp in the recorder's microseconds.
pub fn micros(ts: &Timestamp) -> u64 {
    ts.as_micros()
}

/// The stamp of a time in microseconds.
pub fn timestamp(us: u64) -> Timestamp {
    Timestamp { secs: us / 1_000_000, nanos: (us % 1_000_000) as u32 * 1000, kind: TimestampKind::Absolute }
}

/// A segment's file name for a segment whose first frame is at `us`.
pub fn segment_name(us: u64) -> String {
    format!("{}{SEGMENT_SUFFIX}", stamp_millis(us))
}

/// The start of the segment a file name names, if it is one.
pub fn segment_start(name: &str) -> Option<u64> {
    parse_stamp(name.strip_suffix(SEGMENT_SUFFIX)?)
}

/// An incident directory's name: its trigger's time and first cause (`20261128T134512Z-estop`).
pub fn incident_name(us: u64, slug: &str) -> String {
    format!("{}-{slug}", stamp_seconds(us))
}

/// The trigger time an incident directory's name gives.
pub fn incident_time(name: &str) -> Option<u64> {
    parse_stamp(name.split_once('-')?.0)
}

/// The time of a line the recorder wrote: `(1700000000.002500) can0 ...` (CAN) or
/// `5AA5... # (1700000000.002500123) /dev/ttyUSB0` (RS232, nanoseconds: truncated to microseconds).
pub fn line_time(line: &[u8]) -> Option<u64> {
    let open = if line.first() == Some(&b'(') { 0 } else { memchr::memmem::find(line, b" # (")? + 3 };
    let rest = &line[open + 1..];
    let close = memchr::memchr(b')', rest)?;
    let (secs, micros) = split_stamp(&rest[..close])?;
    secs.checked_mul(1_000_000)?.checked_add(micros)
}

fn split_stamp(text: &[u8]) -> Option<(u64, u64)> {
    let dot = memchr::memchr(b'.', text)?;
    let (secs, fraction) = (&text[..dot], &text[dot + 1..]);
    // candump -L has microseconds; an RS232 line's comment has the link's nanoseconds.
    let micros = match fraction.len() {
        6 => digits(fraction)?,
        9 => digits(fraction)? / 1000,
        _ => return None,
    };
    Some((digits(secs)?, micros))
}

fn digits(text: &[u8]) -> Option<u64> {
    if text.is_empty() || text.len() > 19 {
        return None;
    }
    text.iter()
        .try_fold(0u64, |value, &byte| byte.is_ascii_digit().then(|| value * 10 + u64::from(byte - b'0')))
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: u64 = 1_795_873_500_123_456; // 2026-11-28T13:45:00.123456Z

    #[test]
    fn stamps_are_compact_utc_and_read_back() {
        assert_eq!(stamp_millis(T), "20261128T134500.123Z");
        assert_eq!(stamp_seconds(T), "20261128T134500Z");
        assert_eq!(rfc3339_millis(T), "2026-11-28T13:45:00.123Z");
        assert_eq!(parse_stamp("20261128T134500.123Z"), Some(T - 456));
        assert_eq!(parse_stamp("20261128T134500Z"), Some(T - 123_456));
        assert_eq!(parse_stamp("20261328T134500Z"), None);
        assert_eq!(parse_stamp("2026112"), None);
        assert_eq!(parse_stamp("20261128X134500Z"), None);
        assert_eq!(parse_stamp("2026112éT134500Z"), None);
    }

    #[test]
    fn stamps_to_microseconds_and_back() {
        let ts = Timestamp { secs: 1_700_000_000, nanos: 2_500_999, kind: TimestampKind::Absolute };
        assert_eq!(micros(&ts), 1_700_000_000_002_500);
        assert_eq!(timestamp(1_700_000_000_002_500), Timestamp { nanos: 2_500_000, ..ts });
    }

    #[test]
    fn segment_and_incident_names() {
        assert_eq!(segment_name(T), "20261128T134500.123Z.log.zst");
        assert_eq!(segment_start("20261128T134500.123Z.log.zst"), Some(T - 456));
        assert_eq!(segment_start("20261128T134500.123Z.log"), None);
        assert_eq!(segment_start("notes.txt"), None);
        assert_eq!(incident_name(T, "estop"), "20261128T134500Z-estop");
        assert_eq!(incident_time("20261128T134500Z-link-silence"), Some(T - 123_456));
        assert_eq!(incident_time("garbage"), None);
        // Names sort as times do.
        assert!(segment_name(T) < segment_name(T + 1_000));
    }

    #[test]
    fn line_times_of_can_and_serial_lines() {
        assert_eq!(line_time(b"(1700000000.002500) can0 211#00000103000000B1"), Some(1_700_000_000_002_500));
        assert_eq!(
            line_time(b"5AA50A55010200000000000061 # (1700000000.002500) /dev/ttyUSB0"),
            Some(1_700_000_000_002_500)
        );
        assert_eq!(
            line_time(b"5AA50A55010200000000000061 # (1700000000.002500999) /dev/pts/0"),
            Some(1_700_000_000_002_500)
        );
        assert_eq!(line_time(b"(1700000000.0025) can0 211#00"), None);
        assert_eq!(line_time(b"can0 211#00"), None);
        assert_eq!(line_time(b"(x) can0"), None);
        assert_eq!(line_time(b"(99999999999999999999.000000) can0"), None);
        assert_eq!(line_time(b""), None);
    }
}
