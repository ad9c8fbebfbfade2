//! An output that is also an input is refused before anything is created or truncated, as `sort -o`, `cp`
//! and `cat` refuse it: `decode -o cap.log cap.log` would empty the log before reading it, and so would
//! `--replay rp.log monitor --log rp.log`. "The same file" is the same file on disk, however it is spelled
//! (`./cap.log`, a hard link, a symbolic link): on Unix the device and inode, on Windows the volume and file
//! index.

use std::path::Path;

use super::usage;

/// A file a command reads or writes: the option that named it (`-o`, `--replay`, `the input`) and its path.
/// An input path `-` is standard input.
#[derive(Clone, Copy, Debug)]
pub struct Named<'a> {
    pub option: &'a str,
    pub path: &'a Path,
}

impl Named<'_> {
    fn describe(&self) -> String {
        match self.path.as_os_str() == "-" {
            true => "standard input".to_string(),
            false => format!("{} {}", self.option, self.path.display()),
        }
    }
}

/// A usage error (exit status 2) naming both when an output that exists as a regular file is one of the
/// inputs. Inputs that are not files (a frame given on the command line, a missing file) are passed over:
/// they are never truncated.
pub fn refuse_overwriting(inputs: &[Named], outputs: &[Named]) -> anyhow::Result<()> {
    for output in outputs {
        let Some(written) = identity::of_regular_file(output.path) else { continue };
        for input in inputs {
            let read = match input.path.as_os_str() == "-" {
                true => identity::of_standard_input(),
                false => identity::of_path(input.path),
            };
            if read.as_ref() == Some(&written) {
                return Err(usage(format!(
                    "{} is the same file as {}: writing it would destroy the input before it is read; \
                     write to another file",
                    output.describe(),
                    input.describe()
                )));
            }
        }
    }
    Ok(())
}

#[cfg(unix)]
mod identity {
    use std::fs::{File, Metadata};
    use std::os::fd::AsFd;
    use std::os::unix::fs::MetadataExt;
    use std::path::Path;

    /// The device and inode: one file, whatever the path.
    pub type Identity = (u64, u64);

    fn of(metadata: &Metadata) -> Identity {
        (metadata.dev(), metadata.ino())
    }

    pub fn of_path(path: &Path) -> Option<Identity> {
        std::fs::metadata(path).ok().map(|metadata| of(&metadata))
    }

    /// Only a regular file is emptied by being opened for writing (`/dev/null`, a terminal or a pipe is not).
    pub fn of_regular_file(path: &Path) -> Option<Identity> {
        std::fs::metadata(path).ok().filter(Metadata::is_file).map(|metadata| of(&metadata))
    }

    /// What standard input is (`tracerctl decode -o cap.log - < cap.log`), through a duplicate of it.
    pub fn of_standard_input() -> Option<Identity> {
        let duplicate = std::io::stdin().as_fd().try_clone_to_owned().ok()?;
        File::from(duplicate).metadata().ok().map(|metadata| of(&metadata))
    }
}

#[cfg(windows)]
mod identity {
    use std::path::Path;

    /// The volume serial number and file index (same-file's handle): one file whatever the path, hard
    /// links included, which a canonical path does not see (a hard link under another name was emptied).
    pub type Identity = same_file::Handle;

    pub fn of_path(path: &Path) -> Option<Identity> {
        same_file::Handle::from_path(path).ok()
    }

    pub fn of_regular_file(path: &Path) -> Option<Identity> {
        std::fs::metadata(path).ok().filter(std::fs::Metadata::is_file)?;
        of_path(path)
    }

    /// What standard input is, when it is a file (`tracerctl decode -o cap.log - < cap.log`).
    pub fn of_standard_input() -> Option<Identity> {
        same_file::Handle::stdin().ok()
    }
}

#[cfg(not(any(unix, windows)))]
mod identity {
    use std::path::Path;

    pub type Identity = ();

    pub fn of_path(_: &Path) -> Option<Identity> {
        None
    }

    pub fn of_regular_file(_: &Path) -> Option<Identity> {
        None
    }

    pub fn of_standard_input() -> Option<Identity> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named<'a>(option: &'a str, path: &'a Path) -> Named<'a> {
        Named { option, path }
    }

    #[test]
    fn the_same_file_by_any_name_is_refused_naming_both() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("cap.log");
        std::fs::write(&log, "(1.000000) can0 211#00\n").unwrap();
        let hard = dir.path().join("hard.log");
        std::fs::hard_link(&log, &hard).unwrap();
        let dotted = dir.path().join(".").join("cap.log");
        for output in [&log, &hard, &dotted] {
            let error = refuse_overwriting(&[named("the input", &log)], &[named("-o", output)]).unwrap_err();
            let failure = error.downcast_ref::<crate::exit::Failure>().unwrap();
            assert_eq!(failure.code, crate::exit::USAGE);
            assert_eq!(
                failure.message,
                format!(
                    "-o {} is the same file as the input {}: writing it would destroy the input before it is \
                     read; write to another file",
                    output.display(),
                    log.display()
                )
            );
        }
    }

    #[test]
    fn other_files_missing_files_and_frames_pass() {
        let dir = tempfile::tempdir().unwrap();
        let (log, other) = (dir.path().join("cap.log"), dir.path().join("out.log"));
        std::fs::write(&log, "x\n").unwrap();
        std::fs::write(&other, "y\n").unwrap();
        let missing = dir.path().join("missing.log");
        let frame = Path::new("211#00000103000000B1");
        let inputs = [named("the input", &log), named("the input", frame), named("the input", &missing)];
        for output in [&other, &missing] {
            refuse_overwriting(&inputs, &[named("-o", output)]).unwrap();
        }
        // Not a regular file: writing to it empties nothing.
        #[cfg(unix)]
        refuse_overwriting(
            &[named("the input", Path::new("/dev/null"))],
            &[named("-o", Path::new("/dev/null"))],
        )
        .unwrap();
    }
}
