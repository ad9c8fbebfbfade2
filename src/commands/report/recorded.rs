//! What the report takes from a recorder's directory (layout in `src/blackbox/mod.rs`): the incidents,
//! newest first, and the ring segments covering the last minutes of the ring. Only regular files directly
//! in their folders are taken: a symbolic link could point anywhere (a home directory's keys), and the
//! bundle holds nothing from outside the recorder's directory.

use std::path::{Path, PathBuf};

use crate::candump::days_from_civil;

/// A file of the recorder's directory that may go into the bundle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DirFile {
    pub name: String,
    pub path: PathBuf,
    pub size: u64,
}

/// One incident directory: `YYYYMMDDTHHMMSSZ-CAUSE`, with its files (sorted by name).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Incident {
    pub name: String,
    pub files: Vec<DirFile>,
}

impl Incident {
    /// `2026-11-28 13:41:00 UTC` and the causes (`estop`, `fault+mark`), from the name.
    pub fn when_and_cause(&self) -> (String, String) {
        let (stamp, cause) = self.name.split_once('-').unwrap_or((&self.name, ""));
        let when = utc_name_seconds(stamp).map_or_else(|| stamp.to_string(), readable_utc);
        (when, cause.to_string())
    }
}

/// One ring segment, named by the UTC time of its first frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    pub file: DirFile,
    /// Seconds since the epoch, from the name; `None` for a name that is not a segment's.
    pub start: Option<i64>,
    /// When it was last written (seconds since the epoch), where the file system says.
    pub modified: Option<i64>,
}

/// What the recorder's directory holds.
#[derive(Clone, Debug, Default)]
pub struct Recorded {
    pub dir: PathBuf,
    pub status: Option<DirFile>,
    /// Newest first.
    pub incidents: Vec<Incident>,
    /// Oldest first, as named.
    pub ring: Vec<Segment>,
    /// What could not be read, in words.
    pub problems: Vec<String>,
}

/// Reads the recorder's directory `dir`.
pub fn scan(dir: &Path) -> Recorded {
    let mut recorded = Recorded { dir: dir.to_path_buf(), ..Recorded::default() };
    let (top, problem) = regular_files(dir);
    recorded.problems.extend(problem);
    recorded.status = top.into_iter().find(|file| file.name == "status.json");

    let incidents_dir = dir.join("incidents");
    if incidents_dir.is_dir() {
        let mut names: Vec<String> = match std::fs::read_dir(&incidents_dir) {
            Ok(entries) => entries
                .flatten()
                .filter(|entry| entry.file_type().is_ok_and(|kind| kind.is_dir()))
                .map(|entry| entry.file_name().to_string_lossy().into_owned())
                .collect(),
            Err(error) => {
                recorded.problems.push(format!("cannot read {}: {error}", incidents_dir.display()));
                Vec::new()
            }
        };
        // Names start with the UTC time: newest first is the reverse of name order.
        names.sort_unstable_by(|a, b| b.cmp(a));
        for name in names {
            let (files, problem) = regular_files(&incidents_dir.join(&name));
            recorded.problems.extend(problem);
            recorded.incidents.push(Incident { name, files });
        }
    }

    let (ring, problem) = regular_files(&dir.join("ring"));
    if dir.join("ring").is_dir() {
        recorded.problems.extend(problem);
    }
    recorded.ring = ring
        .into_iter()
        .map(|file| {
            let start = file.name.strip_suffix(".log.zst").and_then(utc_name_seconds);
            let modified = std::fs::metadata(&file.path)
                .and_then(|metadata| metadata.modified())
                .ok()
                .and_then(|time| time.duration_since(std::time::UNIX_EPOCH).ok())
                .and_then(|age| i64::try_from(age.as_secs()).ok());
            Segment { file, start, modified }
        })
        .collect();
    recorded
}

/// The regular files directly in `dir` (not links, not folders), sorted by name; why it could not be
/// read, if it could not.
fn regular_files(dir: &Path) -> (Vec<DirFile>, Option<String>) {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(error) => return (Vec::new(), Some(format!("cannot read {}: {error}", dir.display()))),
    };
    let mut files: Vec<DirFile> = entries
        .flatten()
        .filter_map(|entry| {
            let metadata = std::fs::symlink_metadata(entry.path()).ok()?;
            metadata.file_type().is_file().then(|| DirFile {
                name: entry.file_name().to_string_lossy().into_owned(),
                path: entry.path(),
                size: metadata.len(),
            })
        })
        .collect();
    files.sort_by(|a, b| a.name.cmp(&b.name));
    (files, None)
}

/// Seconds since the epoch of a compact UTC name, `YYYYMMDDTHHMMSS[.mmm]Z` (fractions ignored).
pub fn utc_name_seconds(name: &str) -> Option<i64> {
    let bytes = name.as_bytes();
    if bytes.len() < 16 || bytes[8] != b'T' || !name.ends_with('Z') {
        return None;
    }
    let number = |range: std::ops::Range<usize>| -> Option<i64> {
        let digits = name.get(range)?;
        digits.bytes().all(|b| b.is_ascii_digit()).then(|| digits.parse().ok())?
    };
    let fraction = &name[15..name.len() - 1];
    let fraction_ok = fraction.is_empty()
        || fraction.strip_prefix('.').is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()));
    let (year, month, day) = (number(0..4)?, number(4..6)?, number(6..8)?);
    let (hour, minute, second) = (number(9..11)?, number(11..13)?, number(13..15)?);
    let valid = fraction_ok
        && (1..=12).contains(&month)
        && (1..=31).contains(&day)
        && hour < 24
        && minute < 60
        && second < 61;
    valid.then(|| {
        days_from_civil(year, month as u32, day as u32) * 86_400 + hour * 3_600 + minute * 60 + second
    })
}

/// `2026-11-28 13:41:00 UTC`.
pub fn readable_utc(seconds: i64) -> String {
    let (days, rest) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let (year, month, day) = civil_from_days(days);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC", rest / 3_600, rest / 60 % 60, rest % 60)
}

/// `20261128T134100Z`, the recorder's compact form (file names).
pub fn compact_utc(seconds: i64) -> String {
    let (days, rest) = (seconds.div_euclid(86_400), seconds.rem_euclid(86_400));
    let (year, month, day) = civil_from_days(days);
    format!("{year:04}{month:02}{day:02}T{:02}{:02}{:02}Z", rest / 3_600, rest / 60 % 60, rest % 60)
}

/// The date of a day number (Howard Hinnant's `civil_from_days`, the inverse of `days_from_civil`).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let day_of_era = z.rem_euclid(146_097);
    let year_of_era = (day_of_era - day_of_era / 1_460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
    let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    let month_from_march = (5 * day_of_year + 2) / 153;
    let day = (day_of_year - (153 * month_from_march + 2) / 5 + 1) as u32;
    let month = if month_from_march < 10 { month_from_march + 3 } else { month_from_march - 9 } as u32;
    let year = year_of_era + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// Which segments (indices into `ring`, oldest first) cover the last `minutes` of the ring: the window
/// ends where the ring does (the newest segment's last write, or its start), so a recorder stopped
/// yesterday still gives its last minutes. A segment covers from its start to the next one's; the one
/// holding the window's start is included. Segments whose names give no time are not included.
pub fn ring_window(ring: &[Segment], minutes: u64) -> Vec<usize> {
    let timed: Vec<(usize, i64)> =
        ring.iter().enumerate().filter_map(|(i, s)| s.start.map(|t| (i, t))).collect();
    let Some(&(newest, newest_start)) = timed.last() else { return Vec::new() };
    // The newest segment was written up to its last change, at most one segment's length (the last gap
    // between starts, a minute for a lone one) after its start: a copied directory's new times do not
    // stretch it.
    let length = match timed.len() {
        1 => 60,
        n => newest_start - timed[n - 2].1,
    };
    let end = ring[newest].modified.unwrap_or(newest_start).clamp(newest_start, newest_start + length.max(0));
    let window_start = end - i64::try_from(minutes.saturating_mul(60)).unwrap_or(i64::MAX);
    // The first segment that starts after the window's start, less one: that one holds the start.
    let after = timed.iter().position(|&(_, start)| start > window_start).unwrap_or(timed.len());
    timed[after.saturating_sub(1)..].iter().map(|&(i, _)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(name: &str, modified: Option<i64>) -> Segment {
        let file = DirFile { name: name.to_string(), path: PathBuf::from(name), size: 1 };
        Segment { start: name.strip_suffix(".log.zst").and_then(utc_name_seconds), file, modified }
    }

    #[test]
    fn utc_names_round_trip() {
        let seconds = utc_name_seconds("20261128T134100Z").unwrap();
        assert_eq!(readable_utc(seconds), "2026-11-28 13:41:00 UTC");
        assert_eq!(compact_utc(seconds), "20261128T134100Z");
        assert_eq!(utc_name_seconds("20240229T000000.250Z"), Some(1_709_164_800));
        assert_eq!(compact_utc(0), "19700101T000000Z");
        for bad in [
            "20261328T000000Z",
            "20261128T246000Z",
            "20261128 134100Z",
            "20261128T134100",
            "2026",
            "20261128T134100.Z",
        ] {
            assert_eq!(utc_name_seconds(bad), None, "{bad}");
        }
    }

    #[test]
    fn the_window_takes_the_segment_holding_its_start_and_all_after() {
        // One-minute segments from 12:00 to 12:20, the newest written up to 12:20:30.
        let mut ring: Vec<Segment> =
            (0..=20).map(|minute| segment(&format!("20261128T12{minute:02}00.000Z.log.zst"), None)).collect();
        let end = utc_name_seconds("20261128T122030Z");
        ring.last_mut().unwrap().modified = end;
        // Ten minutes back from 12:20:30 is 12:10:30: the 12:10 segment holds it.
        let window = ring_window(&ring, 10);
        assert_eq!(window, (10..=20).collect::<Vec<_>>());
        assert_eq!(ring_window(&ring, 0), [20]);
        assert_eq!(ring_window(&ring, 1000), (0..=20).collect::<Vec<_>>());
        // A copy made a day later: a last change long after the segment's length ends at that length.
        ring.last_mut().unwrap().modified = end.map(|end| end + 86_400);
        assert_eq!(ring_window(&ring, 10), (11..=20).collect::<Vec<_>>());
    }

    #[test]
    fn segments_without_a_time_are_left_out_and_an_empty_ring_gives_nothing() {
        let ring = vec![segment("notes.txt", Some(5)), segment("20261128T120000Z.log.zst", None)];
        assert_eq!(ring_window(&ring, 10), [1]);
        assert!(ring_window(&[], 10).is_empty());
        assert!(ring_window(&ring[..1], 10).is_empty());
    }

    #[test]
    fn an_incident_name_gives_its_time_and_causes() {
        let incident = Incident { name: "20261128T134100Z-estop+mark".to_string(), files: Vec::new() };
        assert_eq!(
            incident.when_and_cause(),
            ("2026-11-28 13:41:00 UTC".to_string(), "estop+mark".to_string())
        );
        let odd = Incident { name: "manual".to_string(), files: Vec::new() };
        assert_eq!(odd.when_and_cause(), ("manual".to_string(), String::new()));
    }
}
