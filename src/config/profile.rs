//! The effective settings of the files read, with a profile or without: each key's value from the highest
//! layer that has it. The layers, lowest first: each file's top-level tables in the order the files are
//! read (`/etc` first, the user's file last), then the chosen profile's tables in each file in the same
//! order; so a profile beats every file's defaults, and a later file beats an earlier one. Pure.

use super::file::{ParsedFile, Setting};
use super::ConfigError;

/// A setting in effect, and the profile it came from (`None`: a file's top-level tables).
#[derive(Clone, Debug, PartialEq)]
pub struct Effective {
    pub setting: Setting,
    pub profile: Option<String>,
}

/// Every profile defined in `files`, each once, in the order first met.
pub fn profile_names(files: &[ParsedFile]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for profile in files.iter().flat_map(|file| &file.profiles) {
        if !names.contains(&profile.name) {
            names.push(profile.name.clone());
        }
    }
    names
}

/// The settings in effect with `profile` (a name no file defines is an error listing those that exist).
pub fn resolve(files: &[ParsedFile], profile: Option<&str>) -> Result<Vec<Effective>, ConfigError> {
    if let Some(name) = profile {
        let names = profile_names(files);
        if !names.iter().any(|known| known == name) {
            return Err(unknown_profile(name, files, &names));
        }
    }
    let bases = files.iter().map(|file| (None, &file.base));
    let profiles = files.iter().flat_map(|file| {
        let chosen = file.profiles.iter().filter(|candidate| Some(candidate.name.as_str()) == profile);
        chosen.map(|chosen| (Some(chosen.name.as_str()), &chosen.settings))
    });
    // (layer, effective), one per key; a higher layer replaces a lower one's.
    let mut effective: Vec<(usize, Effective)> = Vec::new();
    for (layer, (profile, settings)) in bases.chain(profiles).enumerate() {
        for setting in settings {
            let value = Effective { setting: setting.clone(), profile: profile.map(str::to_string) };
            match effective.iter_mut().find(|(_, known)| known.setting.key == setting.key) {
                Some(known) => *known = (layer, value),
                None => effective.push((layer, value)),
            }
        }
    }
    drop_the_lower_link(&mut effective);
    Ok(effective.into_iter().map(|(_, effective)| effective).collect())
}

/// A layer's `link.iface` and another's `link.serial`: the higher layer chose the link (a profile with a
/// serial port on a site whose file names a CAN interface), so the other is not in effect.
fn drop_the_lower_link(effective: &mut Vec<(usize, Effective)>) {
    let layer_of = |name: &str, effective: &[(usize, Effective)]| {
        effective
            .iter()
            .find(|(_, known)| known.setting.key.table == "link" && known.setting.key.name == name)
            .map(|(layer, _)| *layer)
    };
    if let (Some(iface), Some(serial)) = (layer_of("iface", effective), layer_of("serial", effective)) {
        let lower = if iface < serial { "iface" } else { "serial" };
        effective
            .retain(|(_, known)| !(known.setting.key.table == "link" && known.setting.key.name == lower));
    }
}

fn unknown_profile(name: &str, files: &[ParsedFile], names: &[String]) -> ConfigError {
    let read: Vec<&str> = files.iter().map(|file| file.name.as_str()).collect();
    let message = if read.is_empty() {
        format!("unknown profile '{name}': no configuration file was read (tracerctl config path lists where they are looked for)")
    } else if names.is_empty() {
        format!("unknown profile '{name}': {} defines no profile ([profiles.NAME])", read.join(", "))
    } else {
        format!("unknown profile '{name}'; the profiles are: {} (in {})", names.join(", "), read.join(", "))
    };
    ConfigError::content(message)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::file::parse;
    use crate::config::value::Value;

    const SITE: &str = r#"
[link]
iface = "can0"
[drive]
max_linear = 0.5
accel = 0.4
[profiles.tracer-07]
drive.max_linear = 0.8
link.iface = "can1"
[profiles.bench]
link.serial = "/dev/ttyUSB0"
"#;

    const USER: &str = r#"
[drive]
accel = 0.3
max_angular = 0.6
[profiles.tracer-07]
drive.max_angular = 0.7
[profiles.lab]
drive.max_linear = 0.2
"#;

    fn files() -> Vec<ParsedFile> {
        vec![parse("/etc/c.toml", SITE).unwrap(), parse("/home/c.toml", USER).unwrap()]
    }

    fn value(effective: &[Effective], dotted: &str) -> Option<(Value, String, Option<String>)> {
        let found = effective.iter().find(|known| known.setting.key.dotted() == dotted)?;
        Some((found.setting.value.clone(), found.setting.at.file_line(), found.profile.clone()))
    }

    fn number(effective: &[Effective], dotted: &str) -> f64 {
        match value(effective, dotted) {
            Some((Value::Number(number), ..)) => number,
            other => panic!("{dotted}: {other:?}"),
        }
    }

    #[test]
    fn a_later_file_beats_an_earlier_one_and_a_profile_beats_both() {
        let files = files();
        let plain = resolve(&files, None).unwrap();
        assert_eq!(number(&plain, "drive.max_linear"), 0.5);
        assert_eq!(value(&plain, "drive.accel"), Some((Value::Number(0.3), "/home/c.toml:3".into(), None)));
        assert_eq!(number(&plain, "drive.max_angular"), 0.6);
        assert_eq!(value(&plain, "link.iface").unwrap().0, Value::Text("can0".into()));

        let tracer = resolve(&files, Some("tracer-07")).unwrap();
        assert_eq!(
            value(&tracer, "drive.max_linear"),
            Some((Value::Number(0.8), "/etc/c.toml:8".into(), Some("tracer-07".into())))
        );
        // The user's profile beats the site's file and the user's own defaults.
        assert_eq!(number(&tracer, "drive.max_angular"), 0.7);
        // What the profile leaves out comes from the files, the later first.
        assert_eq!(number(&tracer, "drive.accel"), 0.3);
        assert_eq!(value(&tracer, "link.iface").unwrap().0, Value::Text("can1".into()));
        // A profile defined in one file only.
        assert_eq!(number(&resolve(&files, Some("lab")).unwrap(), "drive.max_linear"), 0.2);
    }

    #[test]
    fn the_higher_layer_chooses_the_link() {
        let bench = resolve(&files(), Some("bench")).unwrap();
        assert_eq!(value(&bench, "link.serial").unwrap().0, Value::Text("/dev/ttyUSB0".into()));
        assert_eq!(value(&bench, "link.iface"), None, "the profile's serial port replaces the file's CAN");
        let lower = [
            parse("a", "[link]\nserial = \"/dev/ttyS0\"").unwrap(),
            parse("b", "[link]\niface = \"can2\"").unwrap(),
        ];
        let effective = resolve(&lower, None).unwrap();
        assert_eq!(value(&effective, "link.serial"), None);
        assert_eq!(value(&effective, "link.iface").unwrap().0, Value::Text("can2".into()));
    }

    #[test]
    fn an_unknown_profile_lists_the_profiles_there_are() {
        let error = resolve(&files(), Some("tracer-08")).unwrap_err();
        assert_eq!(
            error.message,
            "unknown profile 'tracer-08'; the profiles are: tracer-07, bench, lab (in /etc/c.toml, /home/c.toml)"
        );
        assert!(error.is_usage());
        let none = resolve(&[parse("a.toml", "[drive]\naccel = 1").unwrap()], Some("x")).unwrap_err();
        assert_eq!(none.message, "unknown profile 'x': a.toml defines no profile ([profiles.NAME])");
        assert!(resolve(&[], Some("x")).unwrap_err().message.contains("no configuration file was read"));
        assert_eq!(resolve(&[], None).unwrap(), []);
        assert_eq!(profile_names(&files()), ["tracer-07", "bench", "lab"]);
    }
}
