//! The configuration file and its per-robot profiles, used by every command.
//!
//! # Files
//!
//! `/etc/tracerctl/config.toml` (the site's), then `$XDG_CONFIG_HOME/tracerctl/config.toml` (the user's;
//! `~/.config/tracerctl/config.toml` when the variable is unset); on Windows
//! `%APPDATA%\tracerctl\config.toml` only. A later file's values beat an earlier one's. A missing file is
//! no error; an unreadable one is (exit 1), naming it. `TRACERCTL_CONFIG=FILE` reads that file only (it
//! must exist: for tests and for the service); `TRACERCTL_CONFIG=` (empty) reads none, which is what the
//! test suite sets (`.cargo/config.toml`), so that no one's own file changes a test.
//!
//! # Layout
//!
//! Top-level tables hold the defaults; `[profiles.NAME]` tables override them for one robot, chosen with
//! `--profile NAME` or `TRACERCTL_PROFILE`. Keys are the long flags' names with `_` for `-`:
//!
//! ```toml
//! [link]
//! iface = "can0"            # or serial = "/dev/ttyUSB0" (and baud = 115200): one link per table
//! protocol = "v2"           # auto, v1, v2
//!
//! [drive]                   # drive and dashboard: caps and ramps; the dashboard's key timeout
//! max_linear = 0.5          # m/s (at most 1.5 is used, as with the flag)
//! max_angular = 0.5         # rad/s
//! accel = 0.5               # m/s²; angular_accel, decel, angular_decel likewise
//! key_timeout = "300ms"
//!
//! [battery]
//! warning_volts = 23.0      # the low-battery threshold, 18 to 30 V (default: the manual's alarm voltage)
//!
//! [record]                  # tracerctl record
//! dir = "/var/lib/tracerctl/can0"
//! segment = "1m"
//! max_total = "1GiB"
//! max_age = "7d"
//! before = "60s"
//! after = "30s"
//! max_incidents = 100
//! triggers = ["battery_voltage<23.0"]
//! default_triggers = true   # false: as --no-default-triggers
//!
//! [commission]              # tracerctl commission's thresholds (docs/commission.md)
//! dead_time_warn_ms = 150   # each figure: NAME_warn_UNIT and NAME_fail_UNIT, positive numbers
//! gain_ratio_fail = 0.05
//!
//! [profiles.tracer-07]
//! link.iface = "can1"
//! drive.max_linear = 0.8
//! ```
//!
//! # Precedence
//!
//! Command-line flag > environment variable (`TRACERCTL_IFACE`) > profile > file > built-in default. A value
//! from a file is checked by the flag's own parser (same ranges, same words) and the error names
//! `FILE:LINE:COLUMN` instead of the flag; caps are clamped to the protocol's limits as the flags' are, so a
//! file can never make the robot move where a flag could not. A link chosen on the command line (`--sim`,
//! `--replay`, `--serial`, `--iface`) or by `TRACERCTL_IFACE` replaces the file's; within the files, the
//! highest layer that names a link (`link.iface` or `link.serial`) chooses it. A list (`record.triggers`)
//! is replaced as a whole, never merged. An unknown key, table or profile, a value of the wrong kind or out
//! of range is a usage error (exit 2), with the nearest known key when one is close.
//!
//! `tracerctl config show` prints every effective value with its source (`flag`, `env VAR`,
//! `profile NAME (FILE:LINE)`, `file FILE:LINE`, `default`); `tracerctl config path` the files looked for.
//!
//! The files: [`keys`] (every key: its kind and the arguments it gives a default to), [`value`] (values
//! and where they were written), [`file`] (one file parsed), [`profile`] (the layers resolved),
//! [`paths`] (where to look), [`show`] (the reports). The command line (`src/cli.rs`) applies the
//! settings to its arguments and runs the flags' parsers on them.

pub mod file;
pub mod keys;
pub mod paths;
pub mod profile;
pub mod show;
pub mod value;

use std::io::Read;
use std::path::{Path, PathBuf};

pub use file::{ParsedFile, Setting};
pub use keys::{Key, Kind, Target, Use, KEYS};
pub use paths::{Lookup, CONFIG_ENV, PROFILE_ENV};
pub use profile::Effective;
pub use show::{FileState, Report, Row, Source};
pub use value::{Location, Value};

/// A configuration file that cannot be used: its text (`FILE:LINE:COLUMN: reason`, or the file and why it
/// cannot be read).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct ConfigError {
    pub message: String,
    /// The file could not be read (an I/O error, exit 1); otherwise what it says is wrong (exit 2).
    pub unreadable: bool,
}

impl ConfigError {
    pub fn content(message: impl Into<String>) -> Self {
        Self { message: message.into(), unreadable: false }
    }

    pub fn unreadable(message: impl Into<String>) -> Self {
        Self { message: message.into(), unreadable: true }
    }

    /// A mistake in what the files say (or in the profile asked for): a usage error.
    pub fn is_usage(&self) -> bool {
        !self.unreadable
    }
}

/// The files read and the settings in effect.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Loaded {
    /// Each file looked for and whether it exists.
    pub files: Vec<FileState>,
    /// Why only these files, when `TRACERCTL_CONFIG` chose them.
    pub note: Option<String>,
    pub parsed: Vec<ParsedFile>,
    pub profile: Option<String>,
    pub effective: Vec<Effective>,
}

impl Loaded {
    /// Every setting of every file, in every profile (each is checked, whichever is used).
    pub fn all_settings(&self) -> impl Iterator<Item = &Setting> {
        self.parsed.iter().flat_map(ParsedFile::all_settings)
    }

    /// The setting in effect for a key, and the profile it came from.
    pub fn effective(&self, key: &Key) -> Option<&Effective> {
        self.effective.iter().find(|effective| effective.setting.key == key)
    }
}

/// A configuration file is a few lines: more than this is not one (`TRACERCTL_CONFIG=/dev/zero`).
const MAX_FILE_BYTES: u64 = 1 << 20;

/// The files this process's environment asks for.
pub fn lookup() -> Lookup {
    paths::lookup(|name| std::env::var_os(name))
}

/// The note `config path` and `config show` give for a lookup.
pub fn lookup_note(lookup: &Lookup) -> Option<String> {
    match lookup {
        Lookup::Standard(_) => None,
        Lookup::Only(_) => Some(format!("{CONFIG_ENV} names the only file read")),
        Lookup::Nothing => Some(format!("{CONFIG_ENV} is empty: no file is read")),
    }
}

/// Each file of `lookup` and whether it exists (for `config path`, which reads none).
pub fn file_states(lookup: &Lookup) -> Vec<FileState> {
    let state =
        |(path, _): (PathBuf, bool)| FileState { exists: path.exists(), path: path.display().to_string() };
    lookup.files().into_iter().map(state).collect()
}

/// Reads the files of `lookup` and resolves `profile`.
pub fn load(lookup: &Lookup, profile: Option<&str>) -> Result<Loaded, ConfigError> {
    let mut loaded =
        Loaded { note: lookup_note(lookup), profile: profile.map(str::to_string), ..Loaded::default() };
    for (path, required) in lookup.files() {
        let text = read(&path, required)?;
        loaded.files.push(FileState { path: path.display().to_string(), exists: text.is_some() });
        if let Some(text) = text {
            loaded.parsed.push(file::parse(&path.display().to_string(), &text)?);
        }
    }
    loaded.effective = profile::resolve(&loaded.parsed, profile)?;
    Ok(loaded)
}

/// A file's text; `None` when it does not exist and need not.
fn read(path: &Path, required: bool) -> Result<Option<String>, ConfigError> {
    let name = path.display();
    let file = match std::fs::File::open(path) {
        Ok(file) => file,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound && !required => return Ok(None),
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => {
            return Err(ConfigError::unreadable(format!("{name} ({CONFIG_ENV}): no such file")))
        }
        Err(error) => return Err(ConfigError::unreadable(format!("cannot read {name}: {error}"))),
    };
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|error| ConfigError::unreadable(format!("cannot read {name}: {error}")))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ConfigError::content(format!(
            "{name}: larger than 1 MiB; a configuration file is a few lines"
        )));
    }
    match String::from_utf8(bytes) {
        Ok(text) => Ok(Some(text)),
        Err(error) => {
            let valid = &error.as_bytes()[..error.utf8_error().valid_up_to()];
            let text = String::from_utf8_lossy(valid);
            let at = Location::of_offset(&name.to_string(), &text, text.len());
            Err(ConfigError::content(format!("{at}: not UTF-8 text")))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_file(text: &[u8]) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("config.toml");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn missing_standard_files_are_fine_and_a_missing_override_is_not() {
        let dir = tempfile::tempdir().unwrap();
        let absent = dir.path().join("absent.toml");
        let loaded = load(&Lookup::Standard(vec![absent.clone()]), None).unwrap();
        assert_eq!(loaded.files, [FileState { path: absent.display().to_string(), exists: false }]);
        assert_eq!(loaded.effective, []);
        let error = load(&Lookup::Only(absent.clone()), None).unwrap_err();
        assert!(error.unreadable && error.message.ends_with("(TRACERCTL_CONFIG): no such file"), "{error}");
        assert_eq!(load(&Lookup::Nothing, None).unwrap().files, []);
        assert_eq!(lookup_note(&Lookup::Nothing).unwrap(), "TRACERCTL_CONFIG is empty: no file is read");
    }

    #[test]
    fn the_files_are_read_in_order_and_the_profile_resolved() {
        let (_a, site) = temp_file(b"[drive]\nmax_linear = 0.4\n[profiles.r1]\ndrive.accel = 0.2\n");
        let (_b, user) = temp_file(b"[drive]\nmax_linear = 0.6\n");
        let loaded = load(&Lookup::Standard(vec![site.clone(), user.clone()]), Some("r1")).unwrap();
        let max_linear = loaded.effective(Key::find("drive.max_linear").unwrap()).unwrap();
        assert_eq!(max_linear.setting.value, Value::Number(0.6));
        assert_eq!(max_linear.setting.at.file, user.display().to_string());
        let accel = loaded.effective(Key::find("drive.accel").unwrap()).unwrap();
        assert_eq!(accel.profile.as_deref(), Some("r1"));
        assert_eq!(loaded.all_settings().count(), 3);
        assert!(file_states(&Lookup::Only(site)).iter().all(|state| state.exists));
    }

    #[test]
    fn unreadable_huge_and_binary_files_are_errors_naming_them() {
        let (_dir, path) = temp_file(&[b'#'; 2 << 20]);
        assert!(load(&Lookup::Only(path), None).unwrap_err().message.contains("larger than 1 MiB"));
        let (_dir, path) = temp_file(b"[drive]\n\xff = 1\n");
        let error = load(&Lookup::Only(path.clone()), None).unwrap_err();
        assert_eq!(error.message, format!("{}:2:1: not UTF-8 text", path.display()));
        let dir = tempfile::tempdir().unwrap();
        let error = load(&Lookup::Standard(vec![dir.path().to_path_buf()]), None).unwrap_err();
        assert!(error.unreadable && error.message.starts_with("cannot read "), "{error}");
    }
}
