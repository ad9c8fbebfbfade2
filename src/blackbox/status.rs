//! `DIR/status.json`: what the running recorder says of itself, rewritten every few seconds (under another
//! name, then renamed: a reader never sees half of it). `record --status` reads it, and the lock says
//! whether its writer still runs.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::names;

/// How often the running recorder rewrites the file.
pub const EVERY: std::time::Duration = std::time::Duration::from_secs(5);

/// The file is padded with spaces to at least this many bytes.
const PADDED: usize = 4096;

pub fn path(dir: &Path) -> PathBuf {
    dir.join("status.json")
}

/// The recorder's counts and state.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Status {
    pub pid: u32,
    /// Microseconds since the epoch.
    pub started: u64,
    pub updated: u64,
    /// The link's name (`can0`, `/dev/ttyUSB0`, `sim`, a replayed file).
    pub link: String,
    /// `recording`, or why not (`waiting for can0: ...`).
    pub state: String,
    pub frames_recorded: u64,
    pub frames_lost: u64,
    /// Why frames were lost, each reason once, with its count.
    pub losses: Vec<(String, u64)>,
    pub incidents_made: u64,
    pub incidents_removed: u64,
    pub ring_segments_removed: u64,
    /// Times the link went away and came back.
    pub link_outages: u64,
}

impl Status {
    pub fn to_json(&self) -> Value {
        let losses: Vec<Value> =
            self.losses.iter().map(|(reason, frames)| json!({"reason": reason, "frames": frames})).collect();
        json!({
            "pid": self.pid,
            "started": names::rfc3339_millis(self.started),
            "updated": names::rfc3339_millis(self.updated),
            "link": self.link,
            "state": self.state,
            "frames_recorded": self.frames_recorded,
            "frames_lost": self.frames_lost,
            "losses": losses,
            "incidents_made": self.incidents_made,
            "incidents_removed": self.incidents_removed,
            "ring_segments_removed": self.ring_segments_removed,
            "link_outages": self.link_outages,
        })
    }

    /// Counts `frames` lost for `reason`.
    pub fn lose(&mut self, frames: u64, reason: &str) {
        if frames == 0 {
            return;
        }
        self.frames_lost += frames;
        match self.losses.iter_mut().find(|(known, _)| known == reason) {
            Some((_, count)) => *count += frames,
            None => self.losses.push((reason.to_string(), frames)),
        }
    }

    /// Writes `DIR/status.json` whole (a new file renamed over the old one). On a full disk, where no new
    /// file can be written, the old file's blocks are written over instead, padded with spaces to its
    /// length: the losses are then still told.
    pub fn write(&self, dir: &Path) -> io::Result<()> {
        let partial = dir.join(".status.json.partial");
        let mut text = serde_json::to_string_pretty(&self.to_json()).map_err(io::Error::other)?;
        text.push('\n');
        // Padded, so that the in-place write of a full disk has room for larger counts.
        text.push_str(&" ".repeat(PADDED.saturating_sub(text.len())));
        match fs::write(&partial, &text).and_then(|()| fs::rename(&partial, path(dir))) {
            Ok(()) => Ok(()),
            Err(error) => {
                let _ = fs::remove_file(&partial);
                overwrite(&path(dir), text).map_err(|_| error)
            }
        }
    }
}

/// Writes `text` over the file at `path` without growing it (so without new blocks); fails when it is
/// longer than the file.
fn overwrite(path: &Path, mut text: String) -> io::Result<()> {
    use std::io::{Seek, Write};
    let mut file = fs::OpenOptions::new().write(true).open(path)?;
    let length = file.metadata()?.len() as usize;
    if text.len() > length {
        return Err(io::Error::other("the status is longer than the file it would overwrite"));
    }
    text.push_str(&" ".repeat(length - text.len()));
    file.seek(io::SeekFrom::Start(0))?;
    file.write_all(text.as_bytes())
}

/// The last status a recorder wrote into `dir`, if any.
pub fn read(dir: &Path) -> io::Result<Option<Value>> {
    match fs::read_to_string(path(dir)) {
        Ok(text) => serde_json::from_str(&text).map(Some).map_err(|error| {
            io::Error::new(io::ErrorKind::InvalidData, format!("{}: {error}", path(dir).display()))
        }),
        Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(error) => Err(error),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_whole_and_read_back() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read(dir.path()).unwrap(), None);
        let mut status = Status {
            pid: 42,
            started: 1_700_000_000_000_000,
            updated: 1_700_000_005_000_000,
            link: "can0".into(),
            state: "recording".into(),
            frames_recorded: 2500,
            ..Status::default()
        };
        status.lose(3, "disk full");
        status.lose(2, "disk full");
        status.lose(0, "nothing");
        status.write(dir.path()).unwrap();
        let value = read(dir.path()).unwrap().unwrap();
        assert_eq!(value["started"], "2023-11-14T22:13:20.000Z");
        assert_eq!(value["frames_lost"], 5);
        assert_eq!(value["losses"], json!([{"reason": "disk full", "frames": 5}]));
        assert_eq!(value, status.to_json());
        // Written over in place, padded, when no new file can be made (here: the old file is longer).
        fs::write(path(dir.path()), " ".repeat(2000)).unwrap();
        overwrite(&path(dir.path()), serde_json::to_string(&status.to_json()).unwrap()).unwrap();
        assert_eq!(fs::metadata(path(dir.path())).unwrap().len(), 2000);
        assert_eq!(read(dir.path()).unwrap().unwrap(), status.to_json());
        assert!(overwrite(&path(dir.path()), "x".repeat(2001)).is_err());
        fs::write(path(dir.path()), "{").unwrap();
        assert!(read(dir.path()).unwrap_err().to_string().contains("status.json"));
    }
}
