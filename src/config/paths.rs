//! Where the configuration files are looked for. Pure: the environment is a function argument, so each
//! system's rule is tested anywhere.

use std::ffi::OsString;
use std::path::PathBuf;

/// Reads only this file (it must exist); empty: no file at all (the test suite's hermetic setting).
pub const CONFIG_ENV: &str = "TRACERCTL_CONFIG";
/// The profile when `--profile` is not given.
pub const PROFILE_ENV: &str = "TRACERCTL_PROFILE";

/// The files to read, lowest precedence first.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Lookup {
    /// The system's file and the user's; each may be missing.
    Standard(Vec<PathBuf>),
    /// `TRACERCTL_CONFIG=FILE`: that file only, which must exist.
    Only(PathBuf),
    /// `TRACERCTL_CONFIG=` (empty): no file.
    #[default]
    Nothing,
}

impl Lookup {
    /// The files of this lookup, each with whether it must exist.
    pub fn files(&self) -> Vec<(PathBuf, bool)> {
        match self {
            Lookup::Standard(paths) => paths.iter().map(|path| (path.clone(), false)).collect(),
            Lookup::Only(path) => vec![(path.clone(), true)],
            Lookup::Nothing => Vec::new(),
        }
    }
}

/// The lookup the environment `var` asks for, on this system.
pub fn lookup(var: impl Fn(&str) -> Option<OsString>) -> Lookup {
    match var(CONFIG_ENV) {
        Some(path) if path.is_empty() => Lookup::Nothing,
        Some(path) => Lookup::Only(PathBuf::from(path)),
        None => Lookup::Standard(standard(cfg!(windows), var)),
    }
}

/// `/etc/tracerctl/config.toml`, then `$XDG_CONFIG_HOME/tracerctl/config.toml` (`~/.config` when the
/// variable is unset, empty or relative, as the XDG base directory specification says); on Windows
/// `%APPDATA%\tracerctl\config.toml` only.
pub fn standard(windows: bool, var: impl Fn(&str) -> Option<OsString>) -> Vec<PathBuf> {
    let set = |name: &str| var(name).filter(|value| !value.is_empty()).map(PathBuf::from);
    if windows {
        return set("APPDATA").map(|dir| dir.join("tracerctl").join("config.toml")).into_iter().collect();
    }
    let user_dir = set("XDG_CONFIG_HOME")
        .filter(|dir| dir.is_absolute())
        .or_else(|| set("HOME").map(|home| home.join(".config")));
    let mut files = vec![PathBuf::from("/etc/tracerctl/config.toml")];
    files.extend(user_dir.map(|dir| dir.join("tracerctl").join("config.toml")));
    files
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<OsString> + 'a {
        move |name| pairs.iter().find(|(key, _)| *key == name).map(|(_, value)| OsString::from(value))
    }

    /// The Linux layout (its paths are Unix paths: `/cfg` is not absolute on Windows).
    #[cfg(unix)]
    #[test]
    fn the_system_file_then_the_users() {
        let home = [("HOME", "/home/op")];
        assert_eq!(
            standard(false, env(&home)),
            [
                PathBuf::from("/etc/tracerctl/config.toml"),
                PathBuf::from("/home/op/.config/tracerctl/config.toml")
            ]
        );
        let xdg = [("HOME", "/home/op"), ("XDG_CONFIG_HOME", "/cfg")];
        assert_eq!(standard(false, env(&xdg))[1], PathBuf::from("/cfg/tracerctl/config.toml"));
        // A relative or empty XDG_CONFIG_HOME is ignored; no HOME: the system file only.
        let relative = [("HOME", "/home/op"), ("XDG_CONFIG_HOME", "cfg")];
        assert_eq!(
            standard(false, env(&relative))[1],
            PathBuf::from("/home/op/.config/tracerctl/config.toml")
        );
        assert_eq!(
            standard(false, env(&[("XDG_CONFIG_HOME", "")])),
            [PathBuf::from("/etc/tracerctl/config.toml")]
        );
    }

    #[test]
    fn on_windows_the_users_file_only() {
        let windows = [("APPDATA", r"C:\Users\op\AppData\Roaming"), ("HOME", "/home/op")];
        assert_eq!(
            standard(true, env(&windows)),
            [PathBuf::from(r"C:\Users\op\AppData\Roaming").join("tracerctl").join("config.toml")]
        );
        assert_eq!(standard(true, env(&[])), Vec::<PathBuf>::new());
    }

    #[test]
    fn the_override_reads_one_file_or_none() {
        let only = [(CONFIG_ENV, "/tmp/t.toml"), ("HOME", "/home/op")];
        assert_eq!(lookup(env(&only)), Lookup::Only("/tmp/t.toml".into()));
        assert_eq!(lookup(env(&only)).files(), [(PathBuf::from("/tmp/t.toml"), true)]);
        assert_eq!(lookup(env(&[(CONFIG_ENV, "")])), Lookup::Nothing);
        assert_eq!(lookup(env(&[(CONFIG_ENV, "")])).files(), []);
        assert!(matches!(lookup(env(&[("HOME", "/h")])), Lookup::Standard(_)));
    }
}
