//! One recorder per directory: the running recorder holds `DIR/recorder.lock` (an advisory lock the
//! system drops when the process ends, however it ends), which also tells `record --status` it runs.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

const NAME: &str = "recorder.lock";

/// The lock, held while this lives.
pub struct DirLock {
    _file: File,
}

/// What trying the lock found.
pub enum Acquired {
    Held(DirLock),
    /// Another process holds it (its process id, as it wrote it).
    Busy(Option<u32>),
}

impl DirLock {
    /// Takes the lock of `dir` and writes this process's id into it.
    pub fn acquire(dir: &Path) -> io::Result<Acquired> {
        let path = dir.join(NAME);
        let mut file = OpenOptions::new().read(true).write(true).create(true).truncate(false).open(&path)?;
        if !try_lock(&file, true)? {
            return Ok(Acquired::Busy(
                std::fs::read_to_string(&path).ok().and_then(|t| t.trim().parse().ok()),
            ));
        }
        file.set_len(0)?;
        write!(file, "{}", std::process::id())?;
        Ok(Acquired::Held(DirLock { _file: file }))
    }

    /// The id of the process recording into `dir`, if one is.
    pub fn holder(dir: &Path) -> Option<u32> {
        let path = dir.join(NAME);
        let file = File::open(&path).ok()?;
        if try_lock(&file, false).ok()? {
            return None;
        }
        std::fs::read_to_string(&path).ok()?.trim().parse().ok()
    }
}

#[cfg(unix)]
fn try_lock(file: &File, exclusive: bool) -> io::Result<bool> {
    use std::os::fd::AsRawFd;
    let kind = if exclusive { libc::LOCK_EX } else { libc::LOCK_SH };
    // SAFETY: flock on a descriptor this File owns and keeps open for the call.
    let result = unsafe { libc::flock(file.as_raw_fd(), kind | libc::LOCK_NB) };
    if result == 0 {
        if !exclusive {
            // SAFETY: as above; releases the shared lock just taken to look.
            unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_UN) };
        }
        return Ok(true);
    }
    let error = io::Error::last_os_error();
    if error.kind() == io::ErrorKind::WouldBlock {
        return Ok(false);
    }
    Err(error)
}

/// Elsewhere (the recorder runs on the robot's Linux computer) no lock: every try succeeds.
#[cfg(not(unix))]
fn try_lock(_file: &File, _exclusive: bool) -> io::Result<bool> {
    Ok(true)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn one_holder_at_a_time_and_its_pid_is_seen() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(DirLock::holder(dir.path()), None);
        let Acquired::Held(lock) = DirLock::acquire(dir.path()).unwrap() else { panic!("free") };
        // flock locks belong to the open file: a second open in this process is refused as another would be.
        assert!(
            matches!(DirLock::acquire(dir.path()).unwrap(), Acquired::Busy(Some(pid)) if pid == std::process::id())
        );
        assert_eq!(DirLock::holder(dir.path()), Some(std::process::id()));
        drop(lock);
        assert_eq!(DirLock::holder(dir.path()), None);
        assert!(matches!(DirLock::acquire(dir.path()).unwrap(), Acquired::Held(_)));
    }
}
