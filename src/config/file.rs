//! One configuration file: its TOML parsed with the spans of keys and values, each key looked up in
//! [`KEYS`](super::keys::KEYS) and each value checked for its kind, into settings that know where they were
//! written. Pure: the text and the file's name in, settings or the first error (`FILE:LINE:COLUMN: reason`)
//! out.

use std::ops::Range;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::keys::{nearest, nearest_table, Key, KEYS, TABLES};
use super::value::{from_toml, Location, Value};
use super::ConfigError;

/// One value of one key, where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    pub key: &'static Key,
    pub value: Value,
    pub at: Location,
}

/// A `[profiles.NAME]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    pub name: String,
    pub at: Location,
    pub settings: Vec<Setting>,
}

/// A file's settings: the top-level tables (the defaults) and its profiles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParsedFile {
    pub name: String,
    pub base: Vec<Setting>,
    pub profiles: Vec<Profile>,
}

impl ParsedFile {
    /// Every setting, the defaults' and every profile's (each is checked, whichever profile is used).
    pub fn all_settings(&self) -> impl Iterator<Item = &Setting> {
        self.base.iter().chain(self.profiles.iter().flat_map(|profile| &profile.settings))
    }
}

/// Parses the text of the file called `name` (named so in errors and in `config show`).
pub fn parse(name: &str, text: &str) -> Result<ParsedFile, ConfigError> {
    let at = |span: Range<usize>| Location::of_offset(name, text, span.start);
    let document = DeTable::parse(text).map_err(|error| {
        let place = at(error.span().unwrap_or(0..0));
        ConfigError::content(format!("{place}: {}", error.message().trim_end()))
    })?;
    let mut file = ParsedFile { name: name.to_string(), ..ParsedFile::default() };
    for (key, value) in in_source_order(document.get_ref()) {
        let table = key.get_ref().as_ref();
        if table == "profiles" {
            let profiles =
                as_table(value, || "[profiles] holds one table per profile: [profiles.NAME]".into())
                    .map_err(|reason| ConfigError::content(format!("{}: {reason}", at(value.span()))))?;
            for (name, body) in in_source_order(profiles) {
                let profile = profile(name.get_ref(), body, &at)?;
                file.profiles.push(Profile {
                    name: name.get_ref().to_string(),
                    at: at(name.span()),
                    settings: profile,
                });
            }
        } else if TABLES.contains(&table) {
            tables(&mut file.base, key, value, &at)?;
        } else {
            return Err(unknown_table(None, key.get_ref(), value, at(key.span())));
        }
    }
    Ok(file)
}

/// The entries of a table in the order they were written (the parser's map is sorted by name), so that the
/// first mistake in the file is the one reported.
fn in_source_order<'a, 'i>(
    table: &'a DeTable<'i>,
) -> Vec<(&'a Spanned<std::borrow::Cow<'i, str>>, &'a Spanned<DeValue<'i>>)> {
    let mut entries: Vec<_> = table.iter().collect();
    entries.sort_by_key(|(key, _)| key.span().start);
    entries
}

fn as_table<'a, 'i>(
    value: &'a Spanned<DeValue<'i>>,
    reason: impl FnOnce() -> String,
) -> Result<&'a DeTable<'i>, String> {
    match value.get_ref() {
        DeValue::Table(table) => Ok(table),
        _ => Err(reason()),
    }
}

/// One profile's tables (`[profiles.NAME.drive]`, or dotted keys `drive.max_linear = 0.8` in
/// `[profiles.NAME]`).
fn profile(
    name: &str,
    body: &Spanned<DeValue<'_>>,
    at: &impl Fn(Range<usize>) -> Location,
) -> Result<Vec<Setting>, ConfigError> {
    let body = as_table(body, || {
        format!("profiles.{name} must be a table: [profiles.{name}] with keys such as link.iface = \"can1\"")
    })
    .map_err(|reason| ConfigError::content(format!("{}: {reason}", at(body.span()))))?;
    let mut settings = Vec::new();
    for (key, value) in in_source_order(body) {
        if TABLES.contains(&key.get_ref().as_ref()) {
            tables(&mut settings, key, value, at)?;
        } else {
            return Err(unknown_table(Some(name), key.get_ref(), value, at(key.span())));
        }
    }
    Ok(settings)
}

/// The keys of one known table, checked, into `settings`.
fn tables(
    settings: &mut Vec<Setting>,
    table_key: &Spanned<std::borrow::Cow<'_, str>>,
    value: &Spanned<DeValue<'_>>,
    at: &impl Fn(Range<usize>) -> Location,
) -> Result<(), ConfigError> {
    let table = table_key.get_ref().as_ref();
    let entries = as_table(value, || format!("{table} must be a table: [{table}] with its keys below it"))
        .map_err(|reason| ConfigError::content(format!("{}: {reason}", at(table_key.span()))))?;
    for (name, value) in in_source_order(entries) {
        let name_text = name.get_ref().as_ref();
        let Some(key) = KEYS.iter().find(|key| key.table == table && key.name == name_text) else {
            return Err(ConfigError::content(format!(
                "{}: {}",
                at(name.span()),
                unknown_key(table, name_text)
            )));
        };
        let checked = from_toml(key.kind, value.get_ref())
            .and_then(|checked| super::value::check_setting(key, &checked).map(|()| checked))
            .map_err(|reason| {
                ConfigError::content(format!("{}: {}: {reason}", at(value.span()), key.dotted()))
            })?;
        let setting = Setting { key, value: checked, at: at(value.span()) };
        refuse_two_links(settings, &setting)?;
        settings.push(setting);
    }
    Ok(())
}

/// `link.iface` and `link.serial` in one table: two links, and no way to tell which was meant.
fn refuse_two_links(settings: &[Setting], setting: &Setting) -> Result<(), ConfigError> {
    let is_link = |key: &Key| key.table == "link" && matches!(key.name, "iface" | "serial");
    if !is_link(setting.key) {
        return Ok(());
    }
    match settings.iter().find(|other| is_link(other.key) && other.key != setting.key) {
        Some(other) => Err(ConfigError::content(format!(
            "{}: {} and {} (at {}) name two links: keep one",
            setting.at,
            setting.key.dotted(),
            other.key.dotted(),
            other.at
        ))),
        None => Ok(()),
    }
}

fn unknown_key(table: &str, name: &str) -> String {
    match nearest(Some(table), name) {
        Some(known) => format!("unknown key {table}.{name} (did you mean {known}?)"),
        None => {
            let known: Vec<_> = KEYS.iter().filter(|key| key.table == table).map(|key| key.name).collect();
            format!("unknown key {table}.{name}; [{table}] takes {}", known.join(", "))
        }
    }
}

/// A top-level name (or a profile's) that is not a table: a misspelt table, or a key without its table.
fn unknown_table(
    profile: Option<&str>,
    name: &str,
    value: &Spanned<DeValue<'_>>,
    at: Location,
) -> ConfigError {
    let prefix = profile.map_or_else(String::new, |profile| format!("profiles.{profile}."));
    let tables = "the tables are link, drive, battery, record, commission and profiles";
    let reason = match value.get_ref() {
        DeValue::Table(_) => {
            match nearest_table(name).filter(|table| profile.is_none() || *table != "profiles") {
                Some(table) => format!("unknown table [{prefix}{name}] (did you mean [{prefix}{table}]?)"),
                None => format!("unknown table [{prefix}{name}]; {tables}"),
            }
        }
        _ => match nearest(None, name) {
            Some(known) => format!("unknown key {prefix}{name} (did you mean {prefix}{known}?)"),
            None => format!("unknown key {prefix}{name}: keys go in a table; {tables}"),
        },
    };
    ConfigError::content(format!("{at}: {reason}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r#"
[link]
iface = "can0"
protocol = "v2"

[drive]
max_linear = 0.6
key_timeout = "300ms"

[battery]
warning_volts = 23

[record]
dir = "/var/lib/tracerctl/can0"
segment = "1m"
max_total = "1GiB"
max_age = "7d"
before = "60s"
after = "30s"
max_incidents = 100
triggers = ["battery_voltage<23.0"]
default_triggers = false

[profiles.tracer-07]
link.iface = "can1"
drive.max_linear = 0.8

[profiles.bench.link]
serial = "/dev/ttyUSB0"
baud = 9600
"#;

    fn setting<'a>(settings: &'a [Setting], dotted: &str) -> &'a Setting {
        settings.iter().find(|setting| setting.key.dotted() == dotted).unwrap_or_else(|| panic!("{dotted}"))
    }

    fn error(text: &str) -> String {
        parse("c.toml", text).expect_err("an error").message
    }

    #[test]
    fn the_example_parses_with_where_each_value_was_written() {
        let file = parse("/etc/tracerctl/config.toml", EXAMPLE).unwrap();
        assert_eq!(file.base.len(), 14);
        let iface = setting(&file.base, "link.iface");
        assert_eq!(iface.value, Value::Text("can0".into()));
        assert_eq!(iface.at.to_string(), "/etc/tracerctl/config.toml:3:9");
        assert_eq!(setting(&file.base, "drive.max_linear").value, Value::Number(0.6));
        assert_eq!(setting(&file.base, "battery.warning_volts").value, Value::Number(23.0));
        assert_eq!(setting(&file.base, "record.max_incidents").value, Value::Count(100));
        assert_eq!(setting(&file.base, "record.max_total").value, Value::Text("1GiB".into()));
        assert_eq!(
            setting(&file.base, "record.triggers").value,
            Value::List(vec!["battery_voltage<23.0".into()])
        );
        assert_eq!(setting(&file.base, "record.default_triggers").value, Value::Bool(false));
        // Written in source order.
        assert_eq!(file.base[0].key.dotted(), "link.iface");
        assert_eq!(file.base[13].key.dotted(), "record.default_triggers");
        let names: Vec<_> = file.profiles.iter().map(|profile| profile.name.as_str()).collect();
        assert_eq!(names, ["tracer-07", "bench"]);
        let tracer = &file.profiles[0];
        assert_eq!(tracer.at.to_string(), "/etc/tracerctl/config.toml:24:11");
        assert_eq!(setting(&tracer.settings, "link.iface").at.line, 25);
        assert_eq!(setting(&tracer.settings, "drive.max_linear").value, Value::Number(0.8));
        assert_eq!(setting(&file.profiles[1].settings, "link.baud").value, Value::Count(9600));
        assert_eq!(file.all_settings().count(), 18);
    }

    #[test]
    fn an_empty_file_has_no_settings() {
        assert_eq!(parse("c.toml", "").unwrap().base, []);
        assert_eq!(parse("c.toml", "# nothing yet\n").unwrap().profiles, []);
    }

    #[test]
    fn unknown_keys_and_tables_name_the_place_and_the_nearest_key() {
        assert_eq!(
            error("[drive]\nmax_linear = 0.5\nmax_linaer = 0.8\n"),
            "c.toml:3:1: unknown key drive.max_linaer (did you mean drive.max_linear?)"
        );
        assert_eq!(
            error("[drive]\niface = \"can1\""),
            "c.toml:2:1: unknown key drive.iface (did you mean link.iface?)"
        );
        assert_eq!(error("iface = \"can1\""), "c.toml:1:1: unknown key iface (did you mean link.iface?)");
        assert_eq!(
            error("[dirve]\nmax_linear = 1"),
            "c.toml:1:2: unknown table [dirve] (did you mean [drive]?)"
        );
        assert_eq!(
            error("[colour]\nx = 1"),
            "c.toml:1:2: unknown table [colour]; the tables are link, drive, battery, record, commission and profiles"
        );
        assert!(error("[drive]\nspeed_of_light = 1").starts_with(
            "c.toml:2:1: unknown key drive.speed_of_light; [drive] takes max_linear, max_angular, accel"
        ));
        assert_eq!(
            error("[profiles.a]\ndrive.max_lineer = 1"),
            "c.toml:2:7: unknown key drive.max_lineer (did you mean drive.max_linear?)"
        );
        assert_eq!(
            error("[profiles.a.drve]\nmax_linear = 1"),
            "c.toml:1:13: unknown table [profiles.a.drve] (did you mean [profiles.a.drive]?)"
        );
        assert_eq!(
            error("[profiles.a]\niface = \"can1\""),
            "c.toml:2:1: unknown key profiles.a.iface (did you mean profiles.a.link.iface?)"
        );
    }

    #[test]
    fn bad_values_and_shapes_name_the_place() {
        assert_eq!(
            error("[drive]\nmax_linear = \"fast\""),
            "c.toml:2:14: drive.max_linear: expected a number, found a string"
        );
        assert!(error("[record]\nmax_age = \"a week\"")
            .starts_with("c.toml:2:11: record.max_age: 'a week' is not a duration"));
        assert!(error("[record]\nmax_total = \"lots\"")
            .starts_with("c.toml:2:13: record.max_total: 'lots' is not a size"));
        assert_eq!(error("[link]\nbaud = -1"), "c.toml:2:8: link.baud: -1 is negative: give 0 or more");
        assert_eq!(
            error("[battery]\nwarning_volts = 12"),
            "c.toml:2:17: battery.warning_volts: 12 is not a voltage from 18 to 30"
        );
        assert!(error("[battery]\nwarning_volts = nan").ends_with("NaN is not a voltage from 18 to 30"));
        assert_eq!(error("drive = 3"), "c.toml:1:1: drive must be a table: [drive] with its keys below it");
        assert_eq!(
            error("profiles = 3"),
            "c.toml:1:12: [profiles] holds one table per profile: [profiles.NAME]"
        );
        assert!(error("[profiles]\nx = 3").starts_with("c.toml:2:5: profiles.x must be a table"));
        assert_eq!(
            error("[link]\niface = \"can0\"\nserial = \"/dev/ttyUSB0\""),
            "c.toml:3:10: link.serial and link.iface (at c.toml:2:9) name two links: keep one"
        );
    }

    #[test]
    fn toml_syntax_errors_name_the_place() {
        assert!(
            error("[drive]\nmax_linear = = 1").starts_with("c.toml:2:"),
            "{}",
            error("[drive]\nmax_linear = = 1")
        );
        assert!(error("[drive\n").starts_with("c.toml:1:"));
        // A key twice is TOML's own error.
        let twice = error("[drive]\nmax_linear = 1\nmax_linear = 2\n");
        assert!(twice.starts_with("c.toml:3:1: "), "{twice}");
        // Not a panic, whatever the bytes.
        for text in [
            "\u{0}",
            "[[drive]]\n",
            "a.b.c.d.e = 1",
            "[profiles.x.y.z]\nq = 1",
            "=",
            "\"",
            "[link]\nbaud = 1e400",
        ] {
            let _ = parse("c.toml", text);
        }
    }
}
