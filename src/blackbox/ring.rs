//! The ring of segments under `DIR/ring/`: listed by name (time order), trimmed oldest first to its size
//! and age bounds, and read back between two times for an incident.

use std::fs;
use std::io::{self, BufRead, BufReader};
use std::path::{Path, PathBuf};

use super::names;

/// A closed or open segment file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SegmentFile {
    pub path: PathBuf,
    /// Its first frame's time (from the name), microseconds.
    pub start: u64,
    pub bytes: u64,
}

/// The ring's bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bounds {
    /// Bytes of all segments together.
    pub max_total: u64,
    /// Microseconds: a segment whose last frame is older than this is removed.
    pub max_age: u64,
}

/// What a trim removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Removed {
    pub segments: u64,
    pub bytes: u64,
}

impl Removed {
    pub fn add(&mut self, other: Removed) {
        self.segments += other.segments;
        self.bytes += other.bytes;
    }
}

/// What reading a time range back found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReadBack {
    pub lines: u64,
    /// Segments that could not be read to their end (name: reason); their whole frames were read.
    pub damaged: Vec<String>,
}

pub struct Ring {
    dir: PathBuf,
}

impl Ring {
    /// The ring in `dir` (created if missing).
    pub fn open(dir: &Path) -> io::Result<Self> {
        fs::create_dir_all(dir)?;
        Ok(Self { dir: dir.to_path_buf() })
    }

    /// The ring in `dir`, only to read (nothing created).
    pub fn at(dir: &Path) -> Self {
        Self { dir: dir.to_path_buf() }
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Every segment, oldest first. A missing ring directory has none.
    pub fn segments(&self) -> io::Result<Vec<SegmentFile>> {
        let entries = match fs::read_dir(&self.dir) {
            Ok(entries) => entries,
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(error) => return Err(error),
        };
        let mut segments = Vec::new();
        for entry in entries {
            let entry = entry?;
            let name = entry.file_name();
            let Some(start) = name.to_str().and_then(names::segment_start) else { continue };
            // A segment removed between the listing and here is simply not there.
            let Ok(metadata) = entry.metadata() else { continue };
            if metadata.is_file() {
                segments.push(SegmentFile { path: entry.path(), start, bytes: metadata.len() });
            }
        }
        segments.sort_by(|a, b| (a.start, &a.path).cmp(&(b.start, &b.path)));
        Ok(segments)
    }

    /// Removes the oldest segments until the ring is within `bounds` at time `now`. The newest segment
    /// (the one being written) is never removed.
    pub fn trim(&self, bounds: Bounds, now: u64) -> io::Result<Removed> {
        let segments = self.segments()?;
        let mut total: u64 = segments.iter().map(|s| s.bytes).sum();
        let mut removed = Removed::default();
        for (index, segment) in segments.iter().enumerate() {
            let Some(next) = segments.get(index + 1) else { break };
            // A segment ends where the next one starts.
            let too_old = now.saturating_sub(next.start) > bounds.max_age;
            if total <= bounds.max_total && !too_old {
                break;
            }
            remove(&segment.path)?;
            total -= segment.bytes;
            removed.add(Removed { segments: 1, bytes: segment.bytes });
        }
        Ok(removed)
    }

    /// Removes the oldest segment but the newest (room for a full disk); `None` when only that one is left.
    pub fn remove_oldest(&self) -> io::Result<Option<Removed>> {
        let segments = self.segments()?;
        if segments.len() < 2 {
            return Ok(None);
        }
        remove(&segments[0].path)?;
        Ok(Some(Removed { segments: 1, bytes: segments[0].bytes }))
    }

    /// Every line stamped in `[start, end]`, in order, to `out` (each with its `\n`). A segment that
    /// cannot be read to its end (cut by a crash) gives its whole frames and is named in `damaged`.
    pub fn read_between(&self, start: u64, end: u64, mut out: impl FnMut(&[u8])) -> io::Result<ReadBack> {
        let segments = self.segments()?;
        let mut back = ReadBack::default();
        for (index, segment) in segments.iter().enumerate() {
            let next_start = segments.get(index + 1).map_or(u64::MAX, |next| next.start);
            if next_start < start || segment.start > end {
                continue;
            }
            if let Err(error) = read_segment(&segment.path, start, end, &mut out, &mut back.lines) {
                let name = segment.path.file_name().map(|n| n.to_string_lossy().into_owned());
                back.damaged.push(format!("{}: {error}", name.unwrap_or_default()));
            }
        }
        Ok(back)
    }
}

fn remove(path: &Path) -> io::Result<()> {
    match fs::remove_file(path) {
        Err(error) if error.kind() != io::ErrorKind::NotFound => Err(error),
        _ => Ok(()),
    }
}

fn read_segment(
    path: &Path,
    start: u64,
    end: u64,
    out: &mut impl FnMut(&[u8]),
    lines: &mut u64,
) -> io::Result<()> {
    let file = fs::File::open(path)?;
    let mut reader = BufReader::new(zstd::stream::read::Decoder::new(file)?);
    let mut line = Vec::with_capacity(128);
    loop {
        line.clear();
        let read = reader.read_until(b'\n', &mut line)?;
        if read == 0 {
            return Ok(());
        }
        if line.last() != Some(&b'\n') {
            // Only a damaged file ends inside a line: each frame holds whole lines.
            return Err(io::Error::new(io::ErrorKind::UnexpectedEof, "ends inside a line"));
        }
        match names::line_time(&line) {
            Some(time) if time > end => return Ok(()),
            Some(time) if time >= start => {
                out(&line);
                *lines += 1;
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::segment::Segment;
    use super::*;

    const S: u64 = 1_000_000;
    const T0: u64 = 1_700_000_000 * S;

    fn line(us: u64, id: &str) -> String {
        format!("({}.{:06}) can0 {id}#00\n", us / S, us % S)
    }

    /// Segments at T0, T0+60 s, T0+120 s, each with a line a second for 60 s.
    fn three_segments(dir: &Path) -> Ring {
        let ring = Ring::open(dir).unwrap();
        for minute in 0..3 {
            let start = T0 + minute * 60 * S;
            let mut segment = Segment::create(dir, start).unwrap();
            for second in 0..60 {
                segment.append(line(start + second * S, "211").as_bytes(), 1).unwrap();
            }
        }
        ring
    }

    #[test]
    fn segments_are_listed_oldest_first_and_other_files_ignored() {
        let dir = tempfile::tempdir().unwrap();
        let ring = three_segments(dir.path());
        fs::write(dir.path().join("notes.txt"), "x").unwrap();
        let starts: Vec<u64> = ring.segments().unwrap().iter().map(|s| s.start).collect();
        assert_eq!(starts, [T0, T0 + 60 * S, T0 + 120 * S]);
        assert!(Ring::at(&dir.path().join("missing")).segments().unwrap().is_empty());
    }

    #[test]
    fn trim_by_size_and_age_keeps_the_newest() {
        let dir = tempfile::tempdir().unwrap();
        let ring = three_segments(dir.path());
        let sizes: Vec<u64> = ring.segments().unwrap().iter().map(|s| s.bytes).collect();
        let loose = Bounds { max_total: u64::MAX, max_age: u64::MAX };
        assert_eq!(ring.trim(loose, T0 + 180 * S).unwrap(), Removed::default());
        // Size: room for the two newest.
        let bounds = Bounds { max_total: sizes[1] + sizes[2], max_age: u64::MAX };
        assert_eq!(ring.trim(bounds, T0).unwrap(), Removed { segments: 1, bytes: sizes[0] });
        // Age: the middle one ended at T0+120 s; at T0+181 s it is 61 s old.
        let bounds = Bounds { max_total: u64::MAX, max_age: 60 * S };
        assert_eq!(ring.trim(bounds, T0 + 180 * S).unwrap(), Removed::default());
        assert_eq!(ring.trim(bounds, T0 + 181 * S).unwrap().segments, 1);
        // Never the newest, however small the bound.
        let bounds = Bounds { max_total: 0, max_age: 0 };
        assert_eq!(ring.trim(bounds, u64::MAX).unwrap(), Removed::default());
        assert_eq!(ring.segments().unwrap().len(), 1);
        assert_eq!(ring.remove_oldest().unwrap(), None);
    }

    #[test]
    fn read_between_gives_exactly_the_lines_in_range_across_segments() {
        let dir = tempfile::tempdir().unwrap();
        let ring = three_segments(dir.path());
        let mut text = Vec::new();
        let back = ring.read_between(T0 + 58 * S, T0 + 61 * S, |line| text.extend_from_slice(line)).unwrap();
        let expected: String = (58..=61).map(|s| line(T0 + s * S, "211")).collect();
        assert_eq!(String::from_utf8(text).unwrap(), expected);
        assert_eq!(back, ReadBack { lines: 4, damaged: Vec::new() });
    }

    #[test]
    fn a_segment_cut_by_a_crash_gives_its_whole_frames() {
        let dir = tempfile::tempdir().unwrap();
        let ring = Ring::open(dir.path()).unwrap();
        let mut segment = Segment::create(dir.path(), T0).unwrap();
        segment.append(line(T0, "211").as_bytes(), 1).unwrap();
        let whole = segment.bytes;
        segment.append(line(T0 + S, "221").as_bytes(), 1).unwrap();
        let path = segment.path().to_path_buf();
        drop(segment);
        let file = fs::OpenOptions::new().write(true).open(&path).unwrap();
        file.set_len(whole + 5).unwrap();
        let mut text = Vec::new();
        let back = ring.read_between(0, u64::MAX, |line| text.extend_from_slice(line)).unwrap();
        assert_eq!(String::from_utf8(text).unwrap(), line(T0, "211"));
        assert_eq!(back.lines, 1);
        assert_eq!(back.damaged.len(), 1, "{back:?}");
    }
}
