//! Manual marks: `tracerctl record --mark NOTE` drops a file into `DIR/marks/`; the running recorder takes
//! it within a second and treats it as a trigger at the time the mark was made.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::names;

/// Marks are files with this ending (written under another name first, then renamed: never read half).
const SUFFIX: &str = ".mark";
/// The longest note kept, in bytes.
pub const MAX_NOTE: usize = 1024;

pub fn dir(recorder: &Path) -> PathBuf {
    recorder.join("marks")
}

/// Leaves a mark made at `now` with `note` for the recorder in `recorder`; returns its file.
pub fn write(recorder: &Path, now: u64, note: &str) -> io::Result<PathBuf> {
    let marks = dir(recorder);
    fs::create_dir_all(&marks)?;
    let name = format!("{}-{}", names::stamp_millis(now), std::process::id());
    let partial = marks.join(format!(".{name}.partial"));
    let path = marks.join(format!("{name}{SUFFIX}"));
    fs::write(&partial, truncate(note, MAX_NOTE))?;
    fs::rename(&partial, &path)?;
    Ok(path)
}

/// The marks left since the last call, oldest first, removed from the directory: (time, note).
pub fn take(recorder: &Path) -> io::Result<Vec<(u64, String)>> {
    let entries = match fs::read_dir(dir(recorder)) {
        Ok(entries) => entries,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(error) => return Err(error),
    };
    let mut marks = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(stem) = name.strip_suffix(SUFFIX) else { continue };
        let time = stem.split_once('-').and_then(|(stamp, _)| names::parse_stamp(stamp));
        let note = fs::read(entry.path()).map(|bytes| String::from_utf8_lossy(&bytes).into_owned());
        // Taken once: a mark that cannot be removed would fire every second.
        fs::remove_file(entry.path())?;
        if let (Some(time), Ok(note)) = (time, note) {
            marks.push((time, truncate(&note, MAX_NOTE).to_string()));
        }
    }
    marks.sort();
    Ok(marks)
}

fn truncate(text: &str, max: usize) -> &str {
    if text.len() <= max {
        return text;
    }
    let mut end = max;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    &text[..end]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mark_is_taken_once_with_its_time_and_note() {
        let dir = tempfile::tempdir().unwrap();
        assert!(take(dir.path()).unwrap().is_empty());
        write(dir.path(), 1_700_000_001_500_000, "the robot stopped by the lift").unwrap();
        write(dir.path(), 1_700_000_000_000_000, "").unwrap();
        fs::write(super::dir(dir.path()).join(".x.partial"), "half").unwrap();
        let marks = take(dir.path()).unwrap();
        assert_eq!(
            marks,
            [
                (1_700_000_000_000_000, String::new()),
                (1_700_000_001_500_000, "the robot stopped by the lift".to_string())
            ]
        );
        assert!(take(dir.path()).unwrap().is_empty());
    }

    #[test]
    fn long_notes_are_cut_at_a_character() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), 1_700_000_000_000_000, &"é".repeat(1000)).unwrap();
        let marks = take(dir.path()).unwrap();
        assert_eq!(marks[0].1.len(), MAX_NOTE);
    }
}
