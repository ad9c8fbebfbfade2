//! `tracerctl config show` and `config path`: every effective value with its source, as text or JSON. Pure:
//! the rows in, the text out.

use std::fmt;

use serde::Serialize;

use super::keys::{Key, Kind};
use super::value::Location;

/// Where an effective value came from, highest precedence first.
#[derive(Clone, Debug, PartialEq)]
pub enum Source {
    /// The command line (`--iface`).
    Flag(String),
    /// An environment variable.
    Env(String),
    Profile {
        name: String,
        at: Location,
    },
    File {
        at: Location,
    },
    /// Built in.
    Default,
}

impl fmt::Display for Source {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Source::Flag(flag) => write!(f, "flag {flag}"),
            Source::Env(variable) => write!(f, "env {variable}"),
            Source::Profile { name, at } => write!(f, "profile {name} ({})", at.file_line()),
            Source::File { at } => write!(f, "file {}", at.file_line()),
            Source::Default => f.write_str("default"),
        }
    }
}

/// One key's effective value: the texts a flag takes (none: no value), and its source.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub key: &'static Key,
    pub values: Vec<String>,
    pub source: Source,
}

/// A file looked for.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct FileState {
    pub path: String,
    pub exists: bool,
}

/// Everything `config show` says.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub files: Vec<FileState>,
    /// Why only these files (`TRACERCTL_CONFIG`), if so.
    pub note: Option<String>,
    /// The profile and where it was chosen (`--profile`, `env TRACERCTL_PROFILE`).
    pub profile: Option<(String, String)>,
    pub rows: Vec<Row>,
}

/// The lines of `config path`: each file looked for, `exists` or `missing`, then the note.
pub fn paths_text(files: &[FileState], note: Option<&str>) -> String {
    let mut out = String::new();
    for file in files {
        out.push_str(&format!("{:<8}{}\n", if file.exists { "exists" } else { "missing" }, file.path));
    }
    if let Some(note) = note {
        out.push_str(&format!("({note})\n"));
    }
    out
}

/// `config show` as text: the files and the profile, then one aligned line per key.
pub fn text(report: &Report) -> String {
    let mut out = paths_text(&report.files, report.note.as_deref());
    match &report.profile {
        Some((name, from)) => out.push_str(&format!("profile {name} ({from})\n")),
        None => out.push_str("no profile\n"),
    }
    out.push('\n');
    let shown: Vec<(String, String, String)> = report
        .rows
        .iter()
        .map(|row| {
            let source = match (&row.source, row.values.is_empty()) {
                (Source::Default, true) if !row.key.fallback.unset().is_empty() => {
                    format!("default ({})", row.key.fallback.unset())
                }
                (source, _) => source.to_string(),
            };
            (row.key.dotted(), value_text(row), source)
        })
        .collect();
    let key_width = shown.iter().map(|(key, ..)| key.chars().count()).max().unwrap_or(0);
    let value_width = shown.iter().map(|(_, value, _)| value.chars().count()).max().unwrap_or(0);
    for (key, value, source) in shown {
        out.push_str(&format!("{key:<key_width$}  {value:<value_width$}  {source}\n"));
    }
    out
}

fn value_text(row: &Row) -> String {
    match (row.key.kind, row.values.as_slice()) {
        (_, []) if row.key.kind != Kind::TextList => "-".to_string(),
        (Kind::TextList, values) => {
            let quoted: Vec<String> = values.iter().map(|value| format!("{value:?}")).collect();
            format!("[{}]", quoted.join(", "))
        }
        (_, values) => values.join(" "),
    }
}

#[derive(Serialize)]
struct JsonReport<'a> {
    files: &'a [FileState],
    #[serde(skip_serializing_if = "Option::is_none")]
    note: Option<&'a str>,
    profile: Option<JsonProfile<'a>>,
    values: Vec<JsonRow>,
}

#[derive(Serialize)]
struct JsonProfile<'a> {
    name: &'a str,
    from: &'a str,
}

#[derive(Serialize)]
struct JsonRow {
    key: String,
    value: serde_json::Value,
    source: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    flag: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    variable: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    profile: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    file: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    line: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    column: Option<usize>,
}

/// `config show -f json`: one object (docs/json.md), values typed by their key (numbers, booleans, arrays;
/// durations and sizes as written; `null` for none).
pub fn json(report: &Report) -> String {
    let values = report.rows.iter().map(json_row).collect();
    let profile = report.profile.as_ref().map(|(name, from)| JsonProfile { name, from });
    let document = JsonReport { files: &report.files, note: report.note.as_deref(), profile, values };
    let mut text = serde_json::to_string(&document).unwrap_or_default();
    text.push('\n');
    text
}

fn json_row(row: &Row) -> JsonRow {
    let mut json = JsonRow {
        key: row.key.dotted(),
        value: typed(row.key.kind, &row.values),
        source: "default",
        flag: None,
        variable: None,
        profile: None,
        file: None,
        line: None,
        column: None,
    };
    let mut place = |at: &Location| {
        json.file = Some(at.file.clone());
        json.line = Some(at.line);
        json.column = Some(at.column);
    };
    match &row.source {
        Source::Flag(flag) => (json.source, json.flag) = ("flag", Some(flag.clone())),
        Source::Env(variable) => (json.source, json.variable) = ("env", Some(variable.clone())),
        Source::Profile { name, at } => {
            place(at);
            (json.source, json.profile) = ("profile", Some(name.clone()));
        }
        Source::File { at } => {
            place(at);
            json.source = "file";
        }
        Source::Default => {}
    }
    json
}

fn typed(kind: Kind, values: &[String]) -> serde_json::Value {
    use serde_json::Value;
    match (kind, values) {
        (Kind::TextList, values) => Value::Array(values.iter().cloned().map(Value::String).collect()),
        (_, []) => Value::Null,
        (Kind::Number, [value]) => value
            .parse::<f64>()
            .ok()
            .and_then(serde_json::Number::from_f64)
            .map_or(Value::Null, Value::Number),
        (Kind::Count, [value]) => {
            value.parse::<u64>().map_or_else(|_| Value::String(value.clone()), Value::from)
        }
        (Kind::Bool, [value]) => {
            value.parse::<bool>().map_or_else(|_| Value::String(value.clone()), Value::Bool)
        }
        (_, values) => Value::String(values.join(" ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(dotted: &str) -> &'static Key {
        Key::find(dotted).unwrap()
    }

    fn at(line: usize) -> Location {
        Location { file: "/etc/tracerctl/config.toml".into(), line, column: 14 }
    }

    fn report() -> Report {
        Report {
            files: vec![
                FileState { path: "/etc/tracerctl/config.toml".into(), exists: true },
                FileState { path: "/home/op/.config/tracerctl/config.toml".into(), exists: false },
            ],
            note: None,
            profile: Some(("tracer-07".into(), "--profile".into())),
            rows: vec![
                Row {
                    key: key("link.iface"),
                    values: vec!["can3".into()],
                    source: Source::Flag("--iface".into()),
                },
                Row {
                    key: key("link.protocol"),
                    values: vec!["v2".into()],
                    source: Source::File { at: at(3) },
                },
                Row {
                    key: key("drive.max_linear"),
                    values: vec!["0.8".into()],
                    source: Source::Profile { name: "tracer-07".into(), at: at(9) },
                },
                Row { key: key("drive.key_timeout"), values: vec![], source: Source::Default },
                Row { key: key("record.max_incidents"), values: vec!["100".into()], source: Source::Default },
                Row {
                    key: key("record.triggers"),
                    values: vec!["battery_voltage<23.0".into()],
                    source: Source::Env("X".into()),
                },
                Row {
                    key: key("record.default_triggers"),
                    values: vec!["true".into()],
                    source: Source::Default,
                },
            ],
        }
    }

    #[test]
    fn text_has_one_aligned_line_per_key_with_its_source() {
        let text = text(&report());
        let expected = "\
exists  /etc/tracerctl/config.toml
missing /home/op/.config/tracerctl/config.toml
profile tracer-07 (--profile)

link.iface               can3                      flag --iface
link.protocol            v2                        file /etc/tracerctl/config.toml:3
drive.max_linear         0.8                       profile tracer-07 (/etc/tracerctl/config.toml:9)
drive.key_timeout        -                         default (learned from the key stream)
record.max_incidents     100                       default
record.triggers          [\"battery_voltage<23.0\"]  env X
record.default_triggers  true                      default
";
        assert_eq!(text, expected);
    }

    #[test]
    fn json_types_the_values_and_names_the_place() {
        let json: serde_json::Value = serde_json::from_str(&json(&report())).unwrap();
        assert_eq!(json["profile"], serde_json::json!({"name": "tracer-07", "from": "--profile"}));
        assert_eq!(
            json["files"][1],
            serde_json::json!({"path": "/home/op/.config/tracerctl/config.toml", "exists": false})
        );
        let values = json["values"].as_array().unwrap();
        assert_eq!(
            values[0],
            serde_json::json!({"key": "link.iface", "value": "can3", "source": "flag", "flag": "--iface"})
        );
        assert_eq!(
            values[2],
            serde_json::json!({"key": "drive.max_linear", "value": 0.8, "source": "profile", "profile": "tracer-07",
                "file": "/etc/tracerctl/config.toml", "line": 9, "column": 14})
        );
        assert_eq!(values[1]["source"], "file");
        assert_eq!(values[3]["value"], serde_json::Value::Null);
        assert_eq!(values[4]["value"], 100);
        assert_eq!(values[5]["value"], serde_json::json!(["battery_voltage<23.0"]));
        assert_eq!(values[5]["variable"], "X");
        assert_eq!(values[6]["value"], true);
        assert!(json.get("note").is_none());
    }

    #[test]
    fn paths_say_which_exist() {
        let files = [FileState { path: "/tmp/t.toml".into(), exists: true }];
        assert_eq!(paths_text(&files, Some("TRACERCTL_CONFIG")), "exists  /tmp/t.toml\n(TRACERCTL_CONFIG)\n");
        assert_eq!(paths_text(&[], None), "");
    }
}
