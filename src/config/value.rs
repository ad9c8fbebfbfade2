//! A value of the configuration file: taken from TOML by its key's [`Kind`], checked for what the kind
//! says (a duration that parses, a size, a count that is not negative), and given to the command line as
//! the texts a flag would have had. Ranges are the flags' own checks, run by the command line.

use std::fmt;

use toml::de::DeValue;

use super::keys::Kind;

/// Where a value was written: `FILE:LINE:COLUMN`, both counted from 1, the column in characters.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    pub file: String,
    pub line: usize,
    pub column: usize,
}

impl Location {
    /// The line and column of byte `offset` of `text` (clamped to the text, and to a character boundary).
    pub fn of_offset(file: &str, text: &str, offset: usize) -> Self {
        let mut offset = offset.min(text.len());
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &text[..offset];
        let line_start = before.rfind('\n').map_or(0, |at| at + 1);
        Self {
            file: file.to_string(),
            line: before.matches('\n').count() + 1,
            column: before[line_start..].chars().count() + 1,
        }
    }

    /// `FILE:LINE`, as `config show` names a source.
    pub fn file_line(&self) -> String {
        format!("{}:{}", self.file, self.line)
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// A checked value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A string as written: a name, a path, a duration or a size.
    Text(String),
    /// A number (a duration given as seconds too).
    Number(f64),
    /// A whole number (a size given as bytes too).
    Count(u64),
    Bool(bool),
    List(Vec<String>),
}

impl Value {
    /// The texts a flag would have been given (one per value; a list gives each). An inverted target takes
    /// the opposite of a boolean.
    pub fn arg_texts(&self, inverted: bool) -> Vec<String> {
        match self {
            Value::Text(text) => vec![text.clone()],
            Value::Number(number) => vec![number.to_string()],
            Value::Count(count) => vec![count.to_string()],
            Value::Bool(flag) => vec![(flag ^ inverted).to_string()],
            Value::List(items) => items.clone(),
        }
    }
}

/// Takes a TOML value as a value of `kind`; the error says what was expected and what was found.
pub fn from_toml(kind: Kind, value: &DeValue<'_>) -> Result<Value, String> {
    let wrong = || format!("expected {}, found {}", kind.expected(), type_name(value));
    match (kind, value) {
        (Kind::Text, DeValue::String(text)) => non_empty(text).map(Value::Text),
        (Kind::Number, DeValue::Integer(_) | DeValue::Float(_)) => number(value).map(Value::Number),
        (Kind::Count, DeValue::Integer(_)) => count(value).map(Value::Count),
        (Kind::Duration, DeValue::String(text)) => {
            duration(text)?;
            Ok(Value::Text(text.to_string()))
        }
        (Kind::Duration, DeValue::Integer(_) | DeValue::Float(_)) => match number(value)? {
            seconds if seconds >= 0.0 => Ok(Value::Number(seconds)),
            seconds => Err(format!("{seconds} is not a duration: durations are not negative")),
        },
        (Kind::Size, DeValue::String(text)) => {
            parse_size(text)?;
            Ok(Value::Text(text.to_string()))
        }
        (Kind::Size, DeValue::Integer(_)) => count(value).map(Value::Count),
        (Kind::Bool, DeValue::Boolean(flag)) => Ok(Value::Bool(*flag)),
        (Kind::TextList, DeValue::String(text)) => Ok(Value::List(vec![non_empty(text)?])),
        (Kind::TextList, DeValue::Array(items)) => {
            let texts = items.iter().map(|item| match item.get_ref() {
                DeValue::String(text) => non_empty(text),
                other => Err(format!("expected strings in the array, found {}", type_name(other))),
            });
            texts.collect::<Result<_, _>>().map(Value::List)
        }
        _ => Err(wrong()),
    }
}

fn type_name(value: &DeValue<'_>) -> &'static str {
    match value {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a date-time",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

fn non_empty(text: &str) -> Result<String, String> {
    if text.trim().is_empty() {
        Err("must not be empty".to_string())
    } else {
        Ok(text.to_string())
    }
}

/// A TOML integer or float as `f64` (NaN and infinities are numbers here; the ranges refuse them).
fn number(value: &DeValue<'_>) -> Result<f64, String> {
    match value {
        DeValue::Integer(integer) => i64::from_str_radix(integer.as_str(), integer.radix())
            .map(|integer| integer as f64)
            .map_err(|_| format!("{integer} is too large")),
        DeValue::Float(float) => float.as_str().parse().map_err(|_| format!("{float} is not a number")),
        _ => Err("expected a number".to_string()),
    }
}

fn count(value: &DeValue<'_>) -> Result<u64, String> {
    let DeValue::Integer(integer) = value else { return Err("expected a whole number".to_string()) };
    if integer.as_str().starts_with('-') {
        return Err(format!("{integer} is negative: give 0 or more"));
    }
    u64::from_str_radix(integer.as_str().trim_start_matches('+'), integer.radix())
        .map_err(|_| format!("{integer} is too large"))
}

/// The range check of a key no option checks (`Use::Setting`); the others are their options' parsers'.
pub fn check_setting(key: &super::keys::Key, value: &Value) -> Result<(), String> {
    match (key.table, key.name, value) {
        ("battery", "warning_volts", Value::Number(volts))
            if !(*volts >= super::keys::BATTERY_VOLTS.0 && *volts <= super::keys::BATTERY_VOLTS.1) =>
        {
            Err(format!(
                "{volts} is not a voltage from {} to {}",
                super::keys::BATTERY_VOLTS.0,
                super::keys::BATTERY_VOLTS.1
            ))
        }
        // `commission`'s thresholds: a limit is a positive number.
        ("commission", _, Value::Number(limit)) if !(limit.is_finite() && *limit > 0.0) => {
            Err(format!("{limit} is not a positive number"))
        }
        _ => Ok(()),
    }
}

/// Checks a duration's spelling as the flags take it (`300ms`, `1m30s`, `7d`, or seconds); its range is the
/// flag's check.
pub fn duration(text: &str) -> Result<std::time::Duration, String> {
    match text.trim().parse::<f64>() {
        Ok(seconds) if seconds >= 0.0 && seconds.is_finite() && seconds < 1e15 => {
            Ok(std::time::Duration::from_secs_f64(seconds))
        }
        Ok(_) => Err(format!("'{text}' is not a duration: give one such as 300ms, 1m30s or 7d")),
        Err(_) => humantime::parse_duration(text.trim())
            .map_err(|error| format!("'{text}' is not a duration such as 300ms, 1m30s or 7d ({error})")),
    }
}

/// A size in bytes: a number with an optional unit, `k`/`KB` (1000), `KiB` (1024) and so on up to `T`/`TB`,
/// `TiB`, case-insensitive (`1GiB`, `500MB`, `1.5G`, `4096`). Fractions of a byte are dropped.
pub fn parse_size(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let number_end = trimmed.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(trimmed.len());
    let (number, unit) = trimmed.split_at(number_end);
    let bad = || format!("'{text}' is not a size such as 1GiB, 500MB or 4096 (bytes)");
    let number: f64 = number.parse().map_err(|_| bad())?;
    let unit = unit.trim().to_ascii_lowercase();
    let factor: f64 = match unit.as_str() {
        "" | "b" => 1.0,
        "k" | "kb" => 1e3,
        "m" | "mb" => 1e6,
        "g" | "gb" => 1e9,
        "t" | "tb" => 1e12,
        "kib" => 1024.0,
        "mib" => 1024.0 * 1024.0,
        "gib" => 1024.0 * 1024.0 * 1024.0,
        "tib" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
        _ => return Err(bad()),
    };
    let bytes = number * factor;
    // 2^63 bytes is far beyond any disk; it keeps the conversion exact and the sum of sizes from overflowing.
    if bytes.is_finite() && bytes < 9.2e18 {
        Ok(bytes as u64)
    } else {
        Err(format!("'{text}' is too large"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(kind: Kind, toml: &str) -> Result<Value, String> {
        let parsed = DeValue::parse(toml).expect("valid TOML value");
        from_toml(kind, parsed.get_ref())
    }

    #[test]
    fn values_of_each_kind() {
        assert_eq!(value(Kind::Text, "\"can1\""), Ok(Value::Text("can1".into())));
        assert_eq!(value(Kind::Number, "0.8"), Ok(Value::Number(0.8)));
        assert_eq!(value(Kind::Number, "1"), Ok(Value::Number(1.0)));
        assert_eq!(value(Kind::Number, "1_000.5"), Ok(Value::Number(1000.5)));
        assert_eq!(value(Kind::Count, "0x10"), Ok(Value::Count(16)));
        assert_eq!(value(Kind::Count, "115200"), Ok(Value::Count(115_200)));
        assert_eq!(value(Kind::Duration, "\"300ms\""), Ok(Value::Text("300ms".into())));
        assert_eq!(value(Kind::Duration, "2.5"), Ok(Value::Number(2.5)));
        assert_eq!(value(Kind::Size, "\"1GiB\""), Ok(Value::Text("1GiB".into())));
        assert_eq!(value(Kind::Size, "4096"), Ok(Value::Count(4096)));
        assert_eq!(value(Kind::Bool, "false"), Ok(Value::Bool(false)));
        let list = Value::List(vec!["battery_voltage<23.0".into(), "id=0x441".into()]);
        assert_eq!(value(Kind::TextList, "[\"battery_voltage<23.0\", \"id=0x441\"]"), Ok(list));
        assert_eq!(value(Kind::TextList, "\"id=0x441\""), Ok(Value::List(vec!["id=0x441".into()])));
        assert_eq!(Value::Bool(false).arg_texts(true), ["true"]);
        assert_eq!(Value::Number(0.8).arg_texts(false), ["0.8"]);
    }

    #[test]
    fn wrong_values_say_what_was_expected() {
        assert_eq!(value(Kind::Number, "\"fast\""), Err("expected a number, found a string".into()));
        assert_eq!(value(Kind::Text, "3"), Err("expected a string, found an integer".into()));
        assert_eq!(value(Kind::Text, "\" \""), Err("must not be empty".into()));
        assert_eq!(value(Kind::Count, "-1"), Err("-1 is negative: give 0 or more".into()));
        assert_eq!(
            value(Kind::Count, "1.5"),
            Err("expected a whole number (0 or more), found a float".into())
        );
        assert_eq!(
            value(Kind::Count, "99999999999999999999").unwrap_err(),
            "99999999999999999999 is too large"
        );
        assert!(value(Kind::Duration, "\"soon\"").unwrap_err().contains("'soon' is not a duration"));
        assert!(value(Kind::Duration, "-2").unwrap_err().contains("not negative"));
        assert!(value(Kind::Size, "\"1 parsec\"").unwrap_err().contains("is not a size"));
        assert_eq!(value(Kind::Bool, "\"yes\""), Err("expected true or false, found a string".into()));
        assert!(value(Kind::TextList, "[1]").unwrap_err().contains("expected strings in the array"));
        assert!(value(Kind::Text, "1979-05-27").unwrap_err().contains("found a date-time"));
        assert_eq!(value(Kind::Number, "nan").map(|v| v.arg_texts(false)), Ok(vec!["NaN".to_string()]));
    }

    #[test]
    fn sizes() {
        assert_eq!(parse_size("1GiB"), Ok(1 << 30));
        assert_eq!(parse_size("500MB"), Ok(500_000_000));
        assert_eq!(parse_size("64k"), Ok(64_000));
        assert_eq!(parse_size("1.5 gib"), Ok(1_610_612_736));
        assert_eq!(parse_size("4096"), Ok(4096));
        assert_eq!(parse_size("2TiB"), Ok(2 << 40));
        for bad in ["", "GiB", "1..5G", "-1G", "1 GB extra", "1e3"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
        assert!(parse_size("99999999999TiB").unwrap_err().contains("too large"));
    }

    #[test]
    fn locations_count_lines_and_characters_from_one() {
        let text = "a = 1\n[drive]\n# é\nmax = \"x\"\n";
        assert_eq!(Location::of_offset("f", text, 0).to_string(), "f:1:1");
        assert_eq!(Location::of_offset("f", text, 6).to_string(), "f:2:1");
        let after_e = text.find('é').unwrap() + 'é'.len_utf8();
        assert_eq!(Location::of_offset("f", text, after_e).to_string(), "f:3:4");
        // Inside a character, or past the end: never a panic.
        assert_eq!(Location::of_offset("f", text, after_e - 1).to_string(), "f:3:3");
        assert_eq!(Location::of_offset("f", text, 999).line, 5);
        assert_eq!(Location::of_offset("f", text, 6).file_line(), "f:2");
    }
}
