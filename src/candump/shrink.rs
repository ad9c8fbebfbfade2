//! A file that shrinks while it is read (another program truncates it, a log rotated in place): every reader
//! of `decode` says so the same way, counts only the whole lines read before the cut, and fails (exit 1).
//! Without this, the reading thread ended at the new end as at a normal one (the cut line's start decoded as
//! a line), while a mapped window read zeros where pages had vanished.

use std::fs::File;
use std::io::{self, Read};

/// Why a file found shorter than when it was opened could not be read to its end.
#[derive(Debug, thiserror::Error)]
#[error("it shrank while being read ({size} bytes, now {now})")]
pub struct Shrank {
    pub size: u64,
    pub now: u64,
}

/// The read error of a file found shorter than when it was opened.
pub fn shrank(size: u64, now: u64) -> io::Error {
    io::Error::other(Shrank { size, now })
}

/// A file read from its start that fails, where it ends, when it is shorter than when it was opened.
pub struct WatchedFile {
    file: File,
    /// The size when opened (`None`: not a regular file, whose end is its own).
    size: Option<u64>,
    read: u64,
}

impl WatchedFile {
    pub fn new(file: File) -> Self {
        let size = file.metadata().ok().filter(|metadata| metadata.is_file()).map(|metadata| metadata.len());
        Self { file, size, read: 0 }
    }
}

impl Read for WatchedFile {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let read = self.file.read(buf)?;
        self.read += read as u64;
        match self.size {
            Some(size) if read == 0 && !buf.is_empty() && self.read < size => {
                let now = self.file.metadata().map_or(self.read, |metadata| metadata.len());
                Err(shrank(size, now))
            }
            _ => Ok(read),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// A file holding `text`, watched from its start, and a handle to change it by.
    fn watched(text: &[u8]) -> (WatchedFile, File) {
        let mut file = tempfile::tempfile().unwrap();
        file.write_all(text).unwrap();
        let handle = file.try_clone().unwrap();
        std::io::Seek::rewind(&mut file).unwrap();
        (WatchedFile::new(file), handle)
    }

    #[test]
    fn a_file_cut_short_while_read_fails_at_its_new_end() {
        let (mut watched, handle) = watched(b"one\ntwo\nthree\n");
        let mut start = [0u8; 4];
        watched.read_exact(&mut start).unwrap();
        handle.set_len(6).unwrap();
        let mut rest = Vec::new();
        let error = watched.read_to_end(&mut rest).unwrap_err();
        assert_eq!(rest, b"tw");
        assert_eq!(error.to_string(), "it shrank while being read (14 bytes, now 6)");
    }

    #[cfg(unix)]
    #[test]
    fn a_whole_file_and_a_grown_one_end_as_usual() {
        let (mut watched, handle) = watched(b"one\n");
        // Written at its end without moving the shared offset.
        std::os::unix::fs::FileExt::write_all_at(&handle, b"two\n", 4).unwrap();
        let mut all = Vec::new();
        watched.read_to_end(&mut all).unwrap();
        assert_eq!(all, b"one\ntwo\n");
    }
}
