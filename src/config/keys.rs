//! Every key the configuration file knows: its table and name, the TOML values it takes, and the command-line
//! arguments it gives a default to. The one list: the parser, the suggestions for a misspelt key, `config
//! show` and the command line's defaults are all read from [`KEYS`].

use crate::protocol::constants::{volts, BATTERY_WARNING_DV};

/// What a key's value is in TOML (the range, when there is a flag, is the flag's own check).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A TOML string.
    Text,
    /// A TOML number, integer or float (m/s, rad/s, volts).
    Number,
    /// A TOML integer that is not negative.
    Count,
    /// A duration: a string such as `"300ms"`, `"1m30s"`, `"7d"`, or a number of seconds.
    Duration,
    /// A size: a string such as `"1GiB"`, `"500MB"`, `"64k"`, or a number of bytes.
    Size,
    /// `true` or `false`.
    Bool,
    /// An array of strings.
    TextList,
}

impl Kind {
    /// What a value of this kind looks like, for an error.
    pub fn expected(self) -> &'static str {
        match self {
            Kind::Text => "a string",
            Kind::Number => "a number",
            Kind::Count => "a whole number (0 or more)",
            Kind::Duration => "a duration such as \"300ms\" or \"7d\" (or a number of seconds)",
            Kind::Size => "a size such as \"1GiB\" or \"500MB\" (or a number of bytes)",
            Kind::Bool => "true or false",
            Kind::TextList => "an array of strings",
        }
    }
}

/// How a key reaches the command: as the default of command-line arguments, or read by the command line's
/// own code (the link: a configured interface must not conflict with `--sim` as a flag would).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// Becomes the default of each target argument (a flag or its environment variable still wins).
    Default,
    /// Checked by each target argument's parser, applied by the command line's own code.
    Read,
    /// No argument: read by the commands from the settings.
    Setting,
}

/// One command-line argument a key gives its value to: the subcommand (`""` for a global option) and the
/// argument's id (clap's, the field name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Target {
    pub subcommand: &'static str,
    pub arg: &'static str,
    /// A `false` in the file is the flag given (`default_triggers = false` is `--no-default-triggers`).
    pub inverted: bool,
}

const fn target(subcommand: &'static str, arg: &'static str) -> Target {
    Target { subcommand, arg, inverted: false }
}

/// A key of the configuration file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    /// The table (`link`, `drive`, `battery`, `record`, `commission`).
    pub table: &'static str,
    /// The key within it.
    pub name: &'static str,
    pub kind: Kind,
    pub targets: &'static [Target],
    pub usage: Use,
    /// An environment variable read for it by the command line's own code (clap's own `env` is seen from
    /// the arguments).
    pub env: Option<&'static str>,
    /// The built-in value when no target argument has a default.
    pub fallback: Fallback,
}

/// A key's built-in value when its arguments have no default (`config show` says it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fallback {
    /// This text.
    Text(&'static str),
    /// No value; what happens then.
    None(&'static str),
    /// The manual's low-battery alarm voltage (`protocol::constants`).
    BatteryWarning,
}

impl Fallback {
    /// The value, if there is one.
    pub fn value(self) -> Option<String> {
        match self {
            Fallback::Text(text) => Some(text.to_string()),
            Fallback::None(_) => None,
            Fallback::BatteryWarning => Some(volts(BATTERY_WARNING_DV).to_string()),
        }
    }

    /// What happens without a value (empty: nothing to say).
    pub fn unset(self) -> &'static str {
        match self {
            Fallback::None(what) => what,
            _ => "",
        }
    }
}

impl Key {
    /// `table.name`, as `config show` and the errors say it.
    pub fn dotted(&self) -> String {
        format!("{}.{}", self.table, self.name)
    }

    /// The key spelt `table.name`, if there is one.
    pub fn find(dotted: &str) -> Option<&'static Key> {
        let (table, name) = dotted.split_once('.')?;
        KEYS.iter().find(|key| key.table == table && key.name == name)
    }
}

/// The tables, in the order of [`KEYS`].
pub const TABLES: &[&str] = &["link", "drive", "battery", "record", "commission"];

/// `record`'s keys give their values to `tracerctl record`'s arguments of the same ids.
const fn record(name: &'static str, kind: Kind, targets: &'static [Target], fallback: Fallback) -> Key {
    Key { table: "record", name, kind, targets, usage: Use::Default, env: None, fallback }
}

/// Caps and ramps: the same arguments in `drive` and `dashboard`.
const fn motion(name: &'static str, targets: &'static [Target]) -> Key {
    Key {
        table: "drive",
        name,
        kind: Kind::Number,
        targets,
        usage: Use::Default,
        env: None,
        fallback: Fallback::None(""),
    }
}

/// `commission`'s thresholds (docs/commission.md): read by the command from the settings; the fallback
/// is the built-in limit (a test checks it against the command's own).
const fn commission(name: &'static str, fallback: &'static str) -> Key {
    Key {
        table: "commission",
        name,
        kind: Kind::Number,
        targets: &[],
        usage: Use::Setting,
        env: None,
        fallback: Fallback::Text(fallback),
    }
}

/// The RS232 rate of the TRACER, as the command line's `--baud` default.
pub const DEFAULT_BAUD: &str = "115200";

pub const KEYS: &[Key] = &[
    Key {
        table: "link",
        name: "iface",
        kind: Kind::Text,
        targets: &[target("", "iface")],
        usage: Use::Read,
        env: Some("TRACERCTL_IFACE"),
        fallback: Fallback::Text("can0"),
    },
    Key {
        table: "link",
        name: "serial",
        kind: Kind::Text,
        targets: &[target("", "serial")],
        usage: Use::Read,
        env: None,
        fallback: Fallback::None("none: the link is CAN"),
    },
    Key {
        table: "link",
        name: "baud",
        kind: Kind::Count,
        targets: &[target("", "baud")],
        usage: Use::Read,
        env: None,
        fallback: Fallback::Text(DEFAULT_BAUD),
    },
    Key {
        table: "link",
        name: "protocol",
        kind: Kind::Text,
        targets: &[target("", "protocol")],
        usage: Use::Default,
        env: None,
        fallback: Fallback::Text("auto"),
    },
    motion("max_linear", &[target("drive", "max_linear"), target("dashboard", "max_linear")]),
    motion("max_angular", &[target("drive", "max_angular"), target("dashboard", "max_angular")]),
    motion("accel", &[target("drive", "accel"), target("dashboard", "accel")]),
    motion("angular_accel", &[target("drive", "angular_accel"), target("dashboard", "angular_accel")]),
    motion("decel", &[target("drive", "decel"), target("dashboard", "decel")]),
    motion("angular_decel", &[target("drive", "angular_decel"), target("dashboard", "angular_decel")]),
    Key {
        table: "drive",
        name: "key_timeout",
        kind: Kind::Duration,
        targets: &[target("dashboard", "key_timeout")],
        usage: Use::Default,
        env: None,
        fallback: Fallback::None("learned from the key stream"),
    },
    Key {
        table: "battery",
        name: "warning_volts",
        kind: Kind::Number,
        targets: &[],
        usage: Use::Setting,
        env: None,
        fallback: Fallback::BatteryWarning,
    },
    record("dir", Kind::Text, &[target("record", "dir")], Fallback::None("")),
    record("segment", Kind::Duration, &[target("record", "segment")], Fallback::Text("1m")),
    record("max_total", Kind::Size, &[target("record", "max_total")], Fallback::Text("1GiB")),
    record("max_age", Kind::Duration, &[target("record", "max_age")], Fallback::Text("7d")),
    record("before", Kind::Duration, &[target("record", "before")], Fallback::Text("60s")),
    record("after", Kind::Duration, &[target("record", "after")], Fallback::Text("30s")),
    record("max_incidents", Kind::Count, &[target("record", "max_incidents")], Fallback::Text("100")),
    record("triggers", Kind::TextList, &[target("record", "trigger")], Fallback::None("")),
    record(
        "default_triggers",
        Kind::Bool,
        &[Target { subcommand: "record", arg: "no_default_triggers", inverted: true }],
        Fallback::Text("true"),
    ),
    commission("dead_time_warn_ms", "150"),
    commission("dead_time_fail_ms", "300"),
    commission("rise_time_warn_ms", "500"),
    commission("rise_time_fail_ms", "1000"),
    commission("overshoot_warn_percent", "10"),
    commission("overshoot_fail_percent", "25"),
    commission("gain_ratio_warn", "0.02"),
    commission("gain_ratio_fail", "0.05"),
    commission("heading_drift_warn_deg_per_m", "2"),
    commission("heading_drift_fail_deg_per_m", "5"),
    commission("track_width_warn_percent", "5"),
    commission("track_width_fail_percent", "10"),
    commission("odometer_scale_warn_percent", "2"),
    commission("odometer_scale_fail_percent", "5"),
    commission("command_timeout_warn_ms", "100"),
    commission("command_timeout_fail_ms", "1000"),
    commission("internal_resistance_warn_ohm", "0.25"),
    commission("internal_resistance_fail_ohm", "0.5"),
];

/// `battery.warning_volts`: the pack from empty to full, as `sim --battery` takes it.
pub const BATTERY_VOLTS: (f64, f64) = (18.0, 30.0);

/// The known key nearest to an unknown one (`table.name`, or a bare name at the top level), if one is close
/// enough to be what was meant.
pub fn nearest(table: Option<&str>, name: &str) -> Option<String> {
    let wanted = table.map_or_else(|| name.to_string(), |table| format!("{table}.{name}"));
    let mut best: Option<(usize, String)> = None;
    for key in KEYS {
        let dotted = key.dotted();
        // The same name in another table (`[drive] iface`) is one step away; so is a bare top-level name.
        let distance = if key.name == name {
            usize::from(table != Some(key.table))
        } else {
            strsim::damerau_levenshtein(&wanted, &dotted)
        };
        if best.as_ref().is_none_or(|(shortest, _)| distance < *shortest) {
            best = Some((distance, dotted));
        }
    }
    // Close: at most a third of the name's letters (at least one) differ.
    let allowed = (name.chars().count() / 3).max(1);
    best.filter(|(distance, _)| *distance <= allowed).map(|(_, dotted)| dotted)
}

/// The table nearest to an unknown one.
pub fn nearest_table(name: &str) -> Option<&'static str> {
    let allowed = (name.chars().count() / 3).max(1);
    let candidates = TABLES.iter().chain(&["profiles"]);
    candidates
        .map(|table| (strsim::damerau_levenshtein(name, table), *table))
        .min()
        .filter(|(d, _)| *d <= allowed)
        .map(|(_, table)| table)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_key_is_in_a_known_table_once() {
        for (at, key) in KEYS.iter().enumerate() {
            assert!(TABLES.contains(&key.table), "{key:?}");
            assert!(!KEYS[..at].iter().any(|other| other.dotted() == key.dotted()), "{key:?} twice");
            assert_eq!(Key::find(&key.dotted()), Some(key));
            assert_eq!(key.targets.is_empty(), key.usage == Use::Setting, "{key:?}");
        }
        assert_eq!(Key::find("drive.iface"), None);
        // The battery threshold's default is the manual's alarm voltage.
        let warning = Key::find("battery.warning_volts").unwrap().fallback.value();
        assert_eq!(warning, Some(volts(BATTERY_WARNING_DV).to_string()));
    }

    #[test]
    fn a_misspelt_key_gets_the_nearest_one() {
        assert_eq!(nearest(Some("drive"), "max_linaer").as_deref(), Some("drive.max_linear"));
        assert_eq!(nearest(Some("drive"), "iface").as_deref(), Some("link.iface"));
        assert_eq!(nearest(None, "iface").as_deref(), Some("link.iface"));
        assert_eq!(nearest(Some("record"), "trigger").as_deref(), Some("record.triggers"));
        assert_eq!(nearest(Some("record"), "max_incident").as_deref(), Some("record.max_incidents"));
        assert_eq!(nearest(Some("drive"), "colour"), None);
        assert_eq!(nearest_table("dirve"), Some("drive"));
        assert_eq!(nearest_table("profile"), Some("profiles"));
        assert_eq!(nearest_table("colours"), None);
    }
}
