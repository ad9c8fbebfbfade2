//! `decode DIR`: a directory of the black-box recorder (its layout in `src/blackbox/mod.rs`) given as an
//! input stands for the logs it holds. An incident directory (`DIR/incidents/TIME-CAUSE/`) is its
//! `frames.log`; the ring (`DIR/ring/`), or the recorder's `DIR` itself, is its `*.log.zst` segments in
//! name order (which is time order), as if each had been given as an argument: each is named in messages
//! and numbers its own lines. Directories are listed before any output is created, so an output written
//! into one is never read back as an input.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

pub(super) use crate::blackbox::names::SEGMENT_SUFFIX;
/// An incident's frames, a candump -L log.
const INCIDENT_LOG: &str = "frames.log";
/// The recorder's ring, under its directory.
const RING: &str = "ring";
/// The recorder's incidents, under its directory.
const INCIDENTS: &str = "incidents";

/// One input as decode reads it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Input {
    /// As given (a file, `-`, a frame), or the path of a log found in a directory given.
    pub name: String,
    /// Found in a directory: the recorder may remove it (the ring rotates) before it is read.
    pub listed: bool,
}

/// The inputs with every directory replaced by the logs it holds, in order.
pub(super) fn expand(inputs: &[String]) -> Result<Vec<Input>> {
    let mut expanded = Vec::with_capacity(inputs.len());
    for name in inputs {
        let path = Path::new(name);
        if name != "-" && path.is_dir() {
            let logs = logs_in(path)?;
            expanded.extend(logs.iter().map(|log| Input { name: log.display().to_string(), listed: true }));
        } else {
            expanded.push(Input { name: name.clone(), listed: false });
        }
    }
    Ok(expanded)
}

/// An incident's `frames.log`, or the segments of the ring (`dir/ring`, else `dir` itself), by name.
fn logs_in(dir: &Path) -> Result<Vec<PathBuf>> {
    let incident = dir.join(INCIDENT_LOG);
    if incident.is_file() {
        return Ok(vec![incident]);
    }
    let ring = dir.join(RING);
    let segments = if ring.is_dir() { segments_in(&ring)? } else { Vec::new() };
    if !segments.is_empty() {
        return Ok(segments);
    }
    let segments = segments_in(dir)?;
    if !segments.is_empty() {
        return Ok(segments);
    }
    let shown = dir.display();
    let incidents = dir.join(INCIDENTS);
    let latest = latest_incident(dir).or_else(|| latest_incident(&incidents));
    let hint = match latest {
        Some(latest) => format!(" (it holds incidents: give one, such as the latest, {})", latest.display()),
        None => String::new(),
    };
    bail!(
        "{shown} is a directory with no {INCIDENT_LOG} and no *{SEGMENT_SUFFIX} segments{hint}: give a log \
         file, an incident directory (DIR/{INCIDENTS}/TIME-CAUSE) or a recorder's ring (DIR/{RING})"
    )
}

/// The last by name (the latest: names start with the time) of the subdirectories of `dir` holding a
/// `frames.log`.
fn latest_incident(dir: &Path) -> Option<PathBuf> {
    let entries = fs::read_dir(dir).ok()?;
    let incidents =
        entries.filter_map(|entry| Some(entry.ok()?.path())).filter(|path| path.join(INCIDENT_LOG).is_file());
    incidents.max()
}

/// The `*.log.zst` files of `dir`, sorted by name; hidden files (a `.` first) are left out.
fn segments_in(dir: &Path) -> Result<Vec<PathBuf>> {
    let list = |error: io::Error| anyhow::Error::new(error).context(format!("cannot list {}", dir.display()));
    let mut segments = Vec::new();
    for entry in fs::read_dir(dir).map_err(list)? {
        let entry = entry.map_err(list)?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if name.starts_with('.') || !name.ends_with(SEGMENT_SUFFIX) {
            continue;
        }
        // A segment removed since the listing is simply not there; a directory so named is no segment.
        let is_file = entry.metadata().is_ok_and(|metadata| metadata.is_file());
        if is_file {
            segments.push(name.to_string());
        }
    }
    segments.sort_unstable();
    Ok(segments.into_iter().map(|name| dir.join(name)).collect())
}

/// A listed log that is gone when its turn comes: said, not an error.
pub(super) fn vanished(name: &str) -> String {
    format!("{name}: removed before it was read (the recorder's ring rotated)")
}

/// Whether `path` can be opened now, with the reason if not (for [`super::Decoder`]).
pub(super) fn still_there(path: &Path) -> Result<bool> {
    match fs::symlink_metadata(path) {
        Ok(_) => Ok(true),
        Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(false),
        Err(error) => Err(error).with_context(|| format!("cannot open {}", path.display())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(path: &Path) {
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, b"(1.000000) can0 211#00\n").unwrap();
    }

    fn names(inputs: &[Input]) -> Vec<String> {
        inputs.iter().map(|input| input.name.clone()).collect()
    }

    #[test]
    fn a_ring_is_its_segments_in_name_order_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let ring = dir.path().join("ring");
        for name in
            ["20261128T134600.000Z.log.zst", "20261128T134500.123Z.log.zst", "20261128T134500.999Z.log.zst"]
        {
            touch(&ring.join(name));
        }
        touch(&ring.join(".20261128T134700.000Z.log.zst"));
        touch(&ring.join("notes.txt"));
        touch(&ring.join("20261128T134400.000Z.log"));
        fs::create_dir(ring.join("sub.log.zst")).unwrap();
        let expected: Vec<String> =
            ["20261128T134500.123Z.log.zst", "20261128T134500.999Z.log.zst", "20261128T134600.000Z.log.zst"]
                .iter()
                .map(|name| ring.join(name).display().to_string())
                .collect();
        let given = ring.display().to_string();
        let inputs = expand(&[given]).unwrap();
        assert_eq!(names(&inputs), expected);
        assert!(inputs.iter().all(|input| input.listed));
        // The recorder's directory itself reads as its ring.
        assert_eq!(names(&expand(&[dir.path().display().to_string()]).unwrap()), expected);
    }

    #[test]
    fn an_incident_is_its_frames_log_and_other_inputs_stay_as_given() {
        let dir = tempfile::tempdir().unwrap();
        let incident = dir.path().join("incidents/20261128T134512Z-estop");
        touch(&incident.join("frames.log"));
        touch(&incident.join("summary.txt"));
        let given =
            ["-".to_string(), incident.display().to_string(), "211#00".to_string(), "x.log".to_string()];
        let inputs = expand(&given).unwrap();
        let frames = incident.join("frames.log").display().to_string();
        assert_eq!(names(&inputs), ["-", frames.as_str(), "211#00", "x.log"]);
        assert_eq!(inputs.iter().map(|input| input.listed).collect::<Vec<_>>(), [false, true, false, false]);
    }

    #[test]
    fn a_directory_with_no_log_is_an_error_that_says_what_it_looked_for() {
        let dir = tempfile::tempdir().unwrap();
        fs::create_dir(dir.path().join("ring")).unwrap();
        let incidents = dir.path().join("incidents");
        for name in ["20261128T134512Z-estop", "20261128T150000Z-fault", "20261128T140000Z-mark"] {
            touch(&incidents.join(name).join("frames.log"));
        }
        fs::create_dir(incidents.join("20261128T160000Z-empty")).unwrap();
        let latest = incidents.join("20261128T150000Z-fault");
        for given in [dir.path(), incidents.as_path()] {
            let error = expand(&[given.display().to_string()]).unwrap_err().to_string();
            assert_eq!(
                error,
                format!(
                    "{} is a directory with no frames.log and no *.log.zst segments (it holds incidents: give one, \
                     such as the latest, {}): give a log file, an incident directory (DIR/incidents/TIME-CAUSE) or \
                     a recorder's ring (DIR/ring)",
                    given.display(),
                    latest.display()
                )
            );
        }
        let plain = tempfile::tempdir().unwrap();
        let error = expand(&[plain.path().display().to_string()]).unwrap_err().to_string();
        assert!(
            error.ends_with(
                "no *.log.zst segments: give a log file, an incident directory \
                 (DIR/incidents/TIME-CAUSE) or a recorder's ring (DIR/ring)"
            ),
            "{error}"
        );
    }
}
