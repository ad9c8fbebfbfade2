//! `--sim-param NAME=VALUE`: the chassis parameters commissioning measures (dead time, lag, acceleration,
//! wheel gains, track width, odometer scale, command timeout, battery, noise), as one pure table with each
//! parameter's unit, default, allowed range (anything else is refused) and the narrower realistic range
//! property tests draw from. docs/sim.md, "Parameters you can set", is the same table with the semantics.

use std::fmt;
use std::str::FromStr;
use std::time::Duration;

use super::SimConfig;

/// How a parameter's value is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamKind {
    /// A duration: `120ms`, `0.12s`, or plain seconds (`0.12`); the table's numbers are milliseconds.
    Time,
    /// A decimal number in the table's unit.
    Number,
    /// A whole number from 0 to 2^64 - 1 (the noise seed).
    Whole,
}

/// One settable parameter. Ranges are inclusive, in `unit` (milliseconds for times).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimParam {
    /// The `--sim-param` name.
    pub name: &'static str,
    /// The `SimConfig` field it sets.
    pub field: &'static str,
    /// Unit of `default` and the ranges ("" for a ratio; noise is in units of each field's resolution).
    pub unit: &'static str,
    pub kind: ParamKind,
    /// The value of `SimConfig::default()`.
    pub default: f64,
    /// Values outside are refused (by `set_param`, and replaced by `SimConfig::sanitized`).
    pub allowed_min: f64,
    pub allowed_max: f64,
    /// A realistic robot: property tests draw parameter sets from here.
    pub test_min: f64,
    pub test_max: f64,
    /// What it does, one line of at most 60 characters (help text).
    pub meaning: &'static str,
    /// Where the default comes from.
    pub source: &'static str,
}

/// Every parameter, in the order help and docs list them.
pub const SIM_PARAMS: &[SimParam] = &[
    SimParam {
        name: "dead-time",
        field: "dead_time",
        unit: "ms",
        kind: ParamKind::Time,
        default: 0.0,
        allowed_min: 0.0,
        allowed_max: 2000.0,
        test_min: 0.0,
        test_max: 200.0,
        meaning: "delay from a target change to the drive acting on it",
        source: "assumption: today's model answers at once",
    },
    SimParam {
        name: "lag",
        field: "lag",
        unit: "ms",
        kind: ParamKind::Time,
        default: 0.0,
        allowed_min: 0.0,
        allowed_max: 2000.0,
        test_min: 0.0,
        test_max: 150.0,
        meaning: "first-order lag of actual speeds behind the ramp (0: none)",
        source: "assumption: none",
    },
    SimParam {
        name: "max-accel",
        field: "max_linear_accel",
        unit: "m/s2",
        kind: ParamKind::Number,
        default: 1.0,
        allowed_min: 0.05,
        allowed_max: 5.0,
        test_min: 0.5,
        test_max: 2.0,
        meaning: "linear accel. and braking limit; angular: 2 x this, rad/s2",
        source: "assumption",
    },
    SimParam {
        name: "left-gain",
        field: "left_gain",
        unit: "",
        kind: ParamKind::Number,
        default: 1.0,
        allowed_min: 0.5,
        allowed_max: 1.5,
        test_min: 0.9,
        test_max: 1.1,
        meaning: "left wheel's actual speed / its command (tyre wear, motor)",
        source: "a healthy robot",
    },
    SimParam {
        name: "right-gain",
        field: "right_gain",
        unit: "",
        kind: ParamKind::Number,
        default: 1.0,
        allowed_min: 0.5,
        allowed_max: 1.5,
        test_min: 0.9,
        test_max: 1.1,
        meaning: "right wheel's actual speed / its command",
        source: "a healthy robot",
    },
    SimParam {
        name: "track-width",
        field: "effective_track_m",
        unit: "m",
        kind: ParamKind::Number,
        default: crate::protocol::constants::TRACK_M,
        allowed_min: 0.2,
        allowed_max: 0.6,
        test_min: 0.33,
        test_max: 0.40,
        meaning: "effective track the body turns with (firmware: 0.36 m)",
        source: "manual 1.2: wheelbase 360 mm",
    },
    SimParam {
        name: "odometer-scale",
        field: "odometer_scale",
        unit: "",
        kind: ParamKind::Number,
        default: 1.0,
        allowed_min: 0.5,
        allowed_max: 1.5,
        test_min: 0.95,
        test_max: 1.05,
        meaning: "the odometers report this x the true wheel distance",
        source: "a calibrated robot",
    },
    SimParam {
        name: "command-timeout",
        field: "command_timeout",
        unit: "ms",
        kind: ParamKind::Time,
        default: 500.0,
        allowed_min: 20.0,
        allowed_max: 10_000.0,
        test_min: 200.0,
        test_max: 800.0,
        meaning: "target drops to 0 this long after the last command came",
        source: "manual: communication protection, 500 ms (notes §7)",
    },
    SimParam {
        name: "battery-ocv",
        field: "battery_start_v",
        unit: "V",
        kind: ParamKind::Number,
        default: 26.0,
        allowed_min: 18.0,
        allowed_max: 30.0,
        test_min: 23.5,
        test_max: 26.5,
        meaning: "open-circuit battery voltage at the start",
        source: "real V2 captures 25.9-26.3 V (notes §8); manual 1.2: 24 V pack",
    },
    SimParam {
        name: "battery-r",
        field: "battery_resistance_ohm",
        unit: "ohm",
        kind: ParamKind::Number,
        default: 0.08,
        allowed_min: 0.0,
        allowed_max: 2.0,
        test_min: 0.05,
        test_max: 0.5,
        meaning: "battery internal resistance: voltage sag = current x this",
        source: "assumption",
    },
    SimParam {
        name: "noise",
        field: "noise",
        unit: "x resolution",
        kind: ParamKind::Number,
        default: 0.0,
        allowed_min: 0.0,
        allowed_max: 10.0,
        test_min: 0.0,
        test_max: 2.0,
        meaning: "std dev of noise on reported values, in each field's quanta",
        source: "none: exact frames",
    },
    SimParam {
        name: "seed",
        field: "seed",
        unit: "",
        kind: ParamKind::Whole,
        default: 1.0,
        allowed_min: 0.0,
        allowed_max: u64::MAX as f64,
        test_min: 0.0,
        test_max: u64::MAX as f64,
        meaning: "noise generator seed: the same seed gives the same frames",
        source: "",
    },
];

impl SimParam {
    /// The parameter called `name` (case-insensitive, `_` for `-`).
    pub fn find(name: &str) -> Option<&'static SimParam> {
        let name = name.trim().to_ascii_lowercase().replace('_', "-");
        SIM_PARAMS.iter().find(|param| param.name == name)
    }

    /// Every name, comma-separated, for error messages.
    pub fn names() -> String {
        SIM_PARAMS.iter().map(|param| param.name).collect::<Vec<_>>().join(", ")
    }

    /// The allowed range in words, with the unit: "from 0 to 2000 ms", "from 0.5 to 1.5 (a ratio)".
    pub fn allowed_text(&self) -> String {
        match (self.kind, self.unit) {
            (ParamKind::Whole, _) => format!("a whole number from {} to 2^64 - 1", self.allowed_min as u64),
            (_, "") => format!("from {} to {} (a ratio)", self.allowed_min, self.allowed_max),
            (_, unit) => format!("from {} to {} {unit}", self.allowed_min, self.allowed_max),
        }
    }

    /// Parses `text` as this parameter's value, within the allowed range.
    pub fn parse(&'static self, text: &str) -> Result<SimParamSetting, SimParamError> {
        let bad = |reason: String| SimParamError::BadValue {
            name: self.name,
            value: text.to_string(),
            reason,
            allowed: self.allowed_text(),
        };
        let trimmed = text.trim();
        let value = match self.kind {
            ParamKind::Time => ParamValue::Time(parse_time(trimmed).map_err(bad)?),
            ParamKind::Number => match trimmed.parse::<f64>() {
                Ok(number) if number.is_finite() => ParamValue::Number(number),
                _ => return Err(bad("not a number".into())),
            },
            ParamKind::Whole => {
                ParamValue::Whole(trimmed.parse::<u64>().map_err(|_| bad("not a whole number".into()))?)
            }
        };
        if !self.allows(value.in_unit()) {
            return Err(SimParamError::OutOfRange {
                name: self.name,
                value: text.to_string(),
                allowed: self.allowed_text(),
            });
        }
        Ok(SimParamSetting { param: self, value })
    }

    fn allows(&self, value: f64) -> bool {
        value >= self.allowed_min && value <= self.allowed_max
    }

    /// This parameter's value in `config`, in the table's unit.
    pub fn get(&self, config: &SimConfig) -> f64 {
        self.value_of(config).in_unit()
    }

    fn value_of(&self, config: &SimConfig) -> ParamValue {
        match self.name {
            "dead-time" => ParamValue::Time(config.dead_time),
            "lag" => ParamValue::Time(config.lag),
            "max-accel" => ParamValue::Number(config.max_linear_accel),
            "left-gain" => ParamValue::Number(config.left_gain),
            "right-gain" => ParamValue::Number(config.right_gain),
            "track-width" => ParamValue::Number(config.effective_track_m),
            "odometer-scale" => ParamValue::Number(config.odometer_scale),
            "command-timeout" => ParamValue::Time(config.command_timeout),
            "battery-ocv" => ParamValue::Number(config.battery_start_v),
            "battery-r" => ParamValue::Number(config.battery_resistance_ohm),
            "noise" => ParamValue::Number(config.noise),
            _ => ParamValue::Whole(config.seed),
        }
    }
}

/// A parsed value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamValue {
    Time(Duration),
    Number(f64),
    Whole(u64),
}

impl ParamValue {
    /// In the table's unit (milliseconds for times).
    fn in_unit(self) -> f64 {
        match self {
            ParamValue::Time(duration) => duration.as_secs_f64() * 1000.0,
            ParamValue::Number(number) => number,
            ParamValue::Whole(number) => number as f64,
        }
    }
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::Time(duration) if duration.is_zero() => f.write_str("0ms"),
            ParamValue::Time(duration) => write!(f, "{}", humantime::format_duration(*duration)),
            ParamValue::Number(number) => write!(f, "{number}"),
            ParamValue::Whole(number) => write!(f, "{number}"),
        }
    }
}

/// One checked `NAME=VALUE` (the command line parses them before anything runs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimParamSetting {
    pub param: &'static SimParam,
    pub value: ParamValue,
}

impl SimParamSetting {
    /// Sets the parameter in `config` (the value was checked when parsed).
    pub fn apply(&self, config: &mut SimConfig) {
        match (self.param.name, self.value) {
            ("dead-time", ParamValue::Time(time)) => config.dead_time = time,
            ("lag", ParamValue::Time(time)) => config.lag = time,
            ("command-timeout", ParamValue::Time(time)) => config.command_timeout = time,
            ("max-accel", ParamValue::Number(accel)) => {
                config.max_linear_accel = accel;
                // Today's ratio of the defaults: 1 m/s2 and 2 rad/s2.
                config.max_angular_accel = 2.0 * accel;
            }
            ("left-gain", ParamValue::Number(gain)) => config.left_gain = gain,
            ("right-gain", ParamValue::Number(gain)) => config.right_gain = gain,
            ("track-width", ParamValue::Number(track)) => config.effective_track_m = track,
            ("odometer-scale", ParamValue::Number(scale)) => config.odometer_scale = scale,
            ("battery-ocv", ParamValue::Number(volts)) => {
                config.battery_start_v = volts;
                // The pack still discharges towards a lower voltage: keep "empty" 1 V below the start.
                if config.battery_empty_v > volts - EMPTY_BELOW_START_V {
                    config.battery_empty_v = volts - EMPTY_BELOW_START_V;
                }
            }
            ("battery-r", ParamValue::Number(ohm)) => config.battery_resistance_ohm = ohm,
            ("noise", ParamValue::Number(sigma)) => config.noise = sigma,
            ("seed", ParamValue::Whole(seed)) => config.seed = seed,
            // A setting is only made by `SimParam::parse`, whose kind matches its name.
            _ => {}
        }
    }
}

/// `battery-ocv` at or below `battery_empty_v` lowers "empty" to this far below the start.
pub const EMPTY_BELOW_START_V: f64 = 1.0;

impl fmt::Display for SimParamSetting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}={}", self.param.name, self.value)
    }
}

/// `NAME=VALUE`.
impl FromStr for SimParamSetting {
    type Err = SimParamError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let Some((name, value)) = text.split_once('=') else {
            return Err(SimParamError::NoValue { text: text.to_string() });
        };
        let param = SimParam::find(name).ok_or_else(|| SimParamError::Unknown { name: name.to_string() })?;
        param.parse(value)
    }
}

/// Why a `--sim-param` is refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SimParamError {
    #[error("'{text}' is not NAME=VALUE (e.g. dead-time=100ms); parameters: {}", SimParam::names())]
    NoValue { text: String },
    #[error("unknown simulator parameter \"{name}\"; parameters: {}", SimParam::names())]
    Unknown { name: String },
    #[error("{name}: '{value}' is {reason}; give {allowed}")]
    BadValue { name: &'static str, value: String, reason: String, allowed: String },
    #[error("{name}: '{value}' is out of range: give {allowed}")]
    OutOfRange { name: &'static str, value: String, allowed: String },
}

/// A duration: humantime (`120ms`, `0.12s`, `1m`) or plain seconds (`0.12`), as `--fault`'s TIME.
fn parse_time(text: &str) -> Result<Duration, String> {
    if text.is_empty() {
        return Err("empty".into());
    }
    if text.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
        let seconds: f64 = text.parse().map_err(|_| "not a duration such as 120ms or 0.12s".to_string())?;
        return Duration::try_from_secs_f64(seconds).map_err(|error| error.to_string());
    }
    humantime::parse_duration(text)
        .map_err(|error| format!("not a duration such as 120ms or 0.12s ({error})"))
}

impl SimConfig {
    /// Sets one `--sim-param` by name (`dead-time`, `lag`, `max-accel`, ...; see [`SIM_PARAMS`]). Times take
    /// `120ms`, `0.12s` or plain seconds. A value outside the allowed range is refused.
    pub fn set_param(&mut self, name: &str, value: &str) -> Result<(), SimParamError> {
        let param = SimParam::find(name).ok_or_else(|| SimParamError::Unknown { name: name.to_string() })?;
        param.parse(value)?.apply(self);
        Ok(())
    }

    /// The parameters that differ from `SimConfig::default()`, as `NAME=VALUE` (for `sim`'s startup text).
    pub fn non_default_params(&self) -> Vec<String> {
        let defaults = SimConfig::default();
        SIM_PARAMS
            .iter()
            .filter(|param| param.value_of(self) != param.value_of(&defaults))
            .map(|param| format!("{}={}", param.name, param.value_of(self)))
            .collect()
    }

    /// The first table parameter outside its allowed range, with that range in words.
    pub(super) fn param_out_of_range(&self) -> Option<(&'static SimParam, String)> {
        let value_in_range =
            |param: &&SimParam| param.kind == ParamKind::Whole || param.allows(param.get(self));
        SIM_PARAMS
            .iter()
            .find(|param| !value_in_range(param))
            .map(|param| (param, param.value_of(self).to_string()))
    }

    /// Each table parameter outside its allowed range back to its default.
    pub(super) fn reset_params_out_of_range(&mut self) {
        let defaults = SimConfig::default();
        for param in SIM_PARAMS {
            if param.kind != ParamKind::Whole && !param.allows(param.get(self)) {
                SimParamSetting { param, value: param.value_of(&defaults) }.apply(self);
            }
        }
    }
}

/// The parameters for `sim --help`: name, meaning, default and allowed range.
pub fn param_help() -> String {
    let width = SIM_PARAMS.iter().map(|param| param.name.len()).max().unwrap_or(0);
    let defaults = SimConfig::default();
    let mut text =
        String::from("Chassis parameters (--sim-param NAME=VALUE, repeatable; here or with --sim):\n");
    for param in SIM_PARAMS {
        text.push_str(&format!("  {:width$}  {}\n", param.name, param.meaning));
        let default = match (param.kind, param.unit) {
            (ParamKind::Number, unit) if !unit.is_empty() && unit != "x resolution" => {
                format!("{} {unit}", param.value_of(&defaults))
            }
            _ => param.value_of(&defaults).to_string(),
        };
        text.push_str(&format!("  {:width$}  default {default}; {}\n", "", param.allowed_text()));
    }
    text.push_str(
        "Times: 120ms, 0.12s or plain seconds; docs/sim.md has the model. For example:\n  \
         tracerctl --sim --sim-param dead-time=100ms --sim-param left-gain=0.95 doctor",
    );
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_matches_the_default_config_and_its_ranges_nest() {
        let defaults = SimConfig::default();
        for param in SIM_PARAMS {
            assert_eq!(param.get(&defaults), param.default, "{}", param.name);
            assert!(param.allowed_min <= param.test_min, "{}", param.name);
            assert!(param.test_min <= param.default && param.default <= param.test_max, "{}", param.name);
            assert!(param.test_max <= param.allowed_max, "{}", param.name);
            assert_eq!(SimParam::find(param.name), Some(param));
        }
        assert_eq!(SIM_PARAMS.len(), 12);
        assert_eq!(defaults.non_default_params(), Vec::<String>::new());
    }

    #[test]
    fn set_param_sets_the_fields_in_their_units() {
        let mut config = SimConfig::default();
        config.set_param("dead-time", "120ms").unwrap();
        assert_eq!(config.dead_time, Duration::from_millis(120));
        config.set_param("lag", "0.05s").unwrap();
        assert_eq!(config.lag, Duration::from_millis(50));
        config.set_param("command-timeout", "0.3").unwrap();
        assert_eq!(config.command_timeout, Duration::from_millis(300));
        config.set_param("max-accel", "1.5").unwrap();
        assert_eq!((config.max_linear_accel, config.max_angular_accel), (1.5, 3.0));
        config.set_param("Left_Gain", "0.95").unwrap();
        config.set_param("right-gain", "1.02").unwrap();
        assert_eq!((config.left_gain, config.right_gain), (0.95, 1.02));
        config.set_param("track-width", "0.38").unwrap();
        assert_eq!((config.effective_track_m, config.track_m), (0.38, 0.36));
        config.set_param("odometer-scale", "1.03").unwrap();
        assert_eq!(config.odometer_scale, 1.03);
        config.set_param("battery-r", "0.2").unwrap();
        assert_eq!(config.battery_resistance_ohm, 0.2);
        config.set_param("noise", "1.5").unwrap();
        config.set_param("seed", "18446744073709551615").unwrap();
        assert_eq!((config.noise, config.seed), (1.5, u64::MAX));
        config.set_param("battery-ocv", "24.5").unwrap();
        assert_eq!((config.battery_start_v, config.battery_empty_v), (24.5, 21.0));
        assert_eq!(config.validate(), Ok(()));
        assert_eq!(
            config.non_default_params(),
            [
                "dead-time=120ms",
                "lag=50ms",
                "max-accel=1.5",
                "left-gain=0.95",
                "right-gain=1.02",
                "track-width=0.38",
                "odometer-scale=1.03",
                "command-timeout=300ms",
                "battery-ocv=24.5",
                "battery-r=0.2",
                "noise=1.5",
                "seed=18446744073709551615"
            ]
        );
    }

    #[test]
    fn a_low_open_circuit_voltage_lowers_empty_below_it() {
        let mut config = SimConfig::default();
        config.set_param("battery-ocv", "20").unwrap();
        assert_eq!((config.battery_start_v, config.battery_empty_v), (20.0, 19.0));
        assert_eq!(config.validate(), Ok(()));
        assert_eq!(config.clone().sanitized(), config);
    }

    #[test]
    fn bad_names_values_and_ranges_are_refused_with_the_range_and_unit() {
        let mut config = SimConfig::default();
        let err = |config: &mut SimConfig, name: &str, value: &str| {
            config.set_param(name, value).unwrap_err().to_string()
        };
        let unknown = err(&mut config, "warp", "9");
        assert!(unknown
            .starts_with("unknown simulator parameter \"warp\"; parameters: dead-time, lag, max-accel"));
        assert_eq!(
            err(&mut config, "dead-time", "3s"),
            "dead-time: '3s' is out of range: give from 0 to 2000 ms"
        );
        assert_eq!(
            err(&mut config, "left-gain", "2"),
            "left-gain: '2' is out of range: give from 0.5 to 1.5 (a ratio)"
        );
        assert_eq!(
            err(&mut config, "noise", "-1"),
            "noise: '-1' is out of range: give from 0 to 10 x resolution"
        );
        assert_eq!(
            err(&mut config, "battery-r", "NaN"),
            "battery-r: 'NaN' is not a number; give from 0 to 2 ohm"
        );
        assert!(err(&mut config, "lag", "soon").starts_with("lag: 'soon' is not a duration such as 120ms"));
        assert!(err(&mut config, "seed", "-3")
            .starts_with("seed: '-3' is not a whole number; give a whole number"));
        assert_eq!(
            err(&mut config, "command-timeout", "10ms"),
            "command-timeout: '10ms' is out of range: give from 20 to 10000 ms"
        );
        assert_eq!(config, SimConfig::default(), "a refused value changes nothing");
        let no_value = "dead-time".parse::<SimParamSetting>().unwrap_err().to_string();
        assert!(no_value.starts_with("'dead-time' is not NAME=VALUE"), "{no_value}");
        let setting: SimParamSetting = "dead_time=0.1".parse().unwrap();
        assert_eq!(setting.to_string(), "dead-time=100ms");
    }

    #[test]
    fn validate_and_sanitized_cover_the_parameters() {
        let bad = SimConfig { left_gain: f64::NAN, ..SimConfig::default() };
        assert_eq!(bad.validate().unwrap_err().field, "left_gain");
        assert_eq!(bad.sanitized().left_gain, 1.0);
        let bad = SimConfig { dead_time: Duration::MAX, noise: f64::INFINITY, ..SimConfig::default() };
        let err = bad.validate().unwrap_err();
        assert_eq!(err.field, "noise");
        let fixed = bad.sanitized();
        assert_eq!((fixed.dead_time, fixed.noise), (Duration::ZERO, 0.0));
        let bad = SimConfig { dead_time: Duration::from_secs(5), ..SimConfig::default() };
        let err = bad.validate().unwrap_err();
        assert_eq!(err.to_string(), "simulator setting dead_time = 5s must be from 0 to 2000 ms");
        assert_eq!(bad.sanitized(), SimConfig::default());
        let bad = SimConfig { effective_track_m: 5.0, odometer_scale: 0.0, ..SimConfig::default() };
        assert_eq!(bad.sanitized(), SimConfig::default());
    }

    #[test]
    fn help_lists_every_parameter_with_its_default() {
        let help = param_help();
        for param in SIM_PARAMS {
            assert!(help.contains(&format!("  {}", param.name)), "{help}");
        }
        assert!(help.contains("default 500ms; from 20 to 10000 ms\n"), "{help}");
        assert!(help.lines().all(|line| !line.starts_with(' ') || line.chars().count() <= 80), "{help}");
    }
}
