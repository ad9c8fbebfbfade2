//! The commissioning record: what was asked, what was measured and judged, how the drive ended. Written as
//! text for people or as one JSON object (`--format json`, `--save DIR`, the input of `--compare`). Pure.

use std::fmt::Write as _;

use serde_json::{json, Value};

use super::verdict::{worst, Band, Figure, Thresholds, Verdict};
use crate::health::plan::{Action, Step};

/// The record's format version (`"version"` in JSON).
pub const VERSION: u32 = 1;

/// The operator's bounds and what the plan needs.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameters {
    pub max_linear: f64,
    pub max_angular: f64,
    pub include_timeout: bool,
    pub duration_s: f64,
    pub free_space_m: f64,
}

/// How the run ended short of its last step.
#[derive(Clone, Debug, PartialEq)]
pub struct Abort {
    /// `estop`, `key`, `signal`, ... (drive's `end` names).
    pub reason: &'static str,
    pub message: String,
}

/// Everything a run produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub link: String,
    /// RFC 3339, UTC, to the second.
    pub started_utc: String,
    pub parameters: Parameters,
    pub thresholds: Thresholds,
    pub plan: Vec<Step>,
    /// Steps begun.
    pub begun: usize,
    pub figures: Vec<Figure>,
    pub abort: Option<Abort>,
    /// The sender's report: frames, and whether the stop frames left.
    pub stop: Vec<String>,
    pub stop_confirmed: bool,
    pub exit_status: u8,
    pub recording: Option<String>,
}

impl Record {
    /// `pass`, `warn`, `fail`, or `aborted`.
    pub fn verdict(&self) -> &'static str {
        if self.abort.is_some() {
            return "aborted";
        }
        match worst(&self.figures) {
            Verdict::Fail => "fail",
            Verdict::Warn => "warn",
            _ => "pass",
        }
    }
}

/// `forward 0.300 m/s`, `spin left 0.500 rad/s`, `nothing sent`.
pub fn action_words(action: Action) -> String {
    match action {
        Action::Command { linear, angular } if linear == 0.0 && angular == 0.0 => "zero".to_string(),
        Action::Command { linear, angular: 0.0 } => format!("{linear:+.3} m/s"),
        Action::Command { linear: 0.0, angular } => format!("{angular:+.3} rad/s"),
        Action::Command { linear, angular } => format!("{linear:+.3} m/s {angular:+.3} rad/s"),
        Action::Silence => "nothing sent".to_string(),
    }
}

/// The plan as `--dry-run` and the confirmation show it.
pub fn plan_text(link: Option<&str>, parameters: &Parameters, plan: &[Step]) -> String {
    let mut out = String::new();
    let on = link.map_or_else(String::new, |link| format!(" on {link}"));
    let _ = writeln!(out, "tracerctl commission{on}: a bounded test drive of {} steps", plan.len());
    let mut at = 0.0;
    for (number, step) in plan.iter().enumerate() {
        let _ = writeln!(
            out,
            "  {:>2}. {:<24} {:>6.1} s  (from {at:>5.1} s)  {}",
            number + 1,
            step.name,
            step.duration.as_secs_f64(),
            action_words(step.action)
        );
        at += step.duration.as_secs_f64();
    }
    let _ = writeln!(
        out,
        "bounds: at most {:.3} m/s and {:.3} rad/s, sent as steps (no ramp) on the 50 Hz sender",
        parameters.max_linear, parameters.max_angular
    );
    let _ = writeln!(out, "duration: {:.1} s", parameters.duration_s);
    let _ = writeln!(
        out,
        "free space: {} m clear ahead and behind; it ends near where it started (it also spins in place)",
        parameters.free_space_m
    );
    if parameters.include_timeout {
        let _ = writeln!(
            out,
            "command timeout probe: nothing is sent for a while; the robot's own timeout must stop it"
        );
    }
    out
}

/// The report for people.
pub fn text(record: &Record) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "commission report: {}, {} ({} of {} steps run)",
        record.link,
        record.started_utc,
        record.begun,
        record.plan.len()
    );
    let _ = writeln!(out, "{:<24} {:<22} {:>12}  {:<5} limits", "step", "figure", "value", "");
    for figure in &record.figures {
        let value = figure.value.map_or_else(
            || "-".to_string(),
            |value| format!("{} {}", number(value, figure.unit), figure.unit),
        );
        let _ = writeln!(
            out,
            "{:<24} {:<22} {:>12}  {:<5} {}",
            figure.step,
            figure.label,
            value.trim_end(),
            figure.verdict.label(),
            figure.note
        );
    }
    if record.figures.is_empty() {
        let _ = writeln!(out, "(nothing measured)");
    }
    let _ = writeln!(out, "stop: {}", record.stop.join("; "));
    if let Some(path) = &record.recording {
        let _ = writeln!(out, "recording: {path} (tracerctl decode --summary {path})");
    }
    let counts = |verdict| record.figures.iter().filter(|figure| figure.verdict == verdict).count();
    let result = match &record.abort {
        Some(abort) => format!(
            "ABORTED ({}): {}; the figures above are what was measured before",
            abort.reason, abort.message
        ),
        None => format!(
            "{}: {} pass, {} warn, {} fail, {} not measured",
            record.verdict().to_ascii_uppercase(),
            counts(Verdict::Pass),
            counts(Verdict::Warn),
            counts(Verdict::Fail),
            counts(Verdict::NotMeasured)
        ),
    };
    let _ = writeln!(out, "result: {result} (exit status {})", record.exit_status);
    out
}

/// A figure's value, to 3 significant decimals at most; times in whole milliseconds (the feedback comes
/// every 20 ms: a fraction of one is noise), percentages to a tenth.
fn number(value: f64, unit: &str) -> String {
    let digits = if value.abs() >= 100.0 || unit == "ms" {
        0
    } else if value.abs() >= 10.0 || unit == "%" {
        1
    } else {
        3
    };
    format!("{value:.digits$}")
}

fn round(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}

fn band_json(band: Band) -> Value {
    json!({ "warn": band.warn, "fail": band.fail })
}

/// The record as one JSON object (docs/commission.md, "JSON").
pub fn json(record: &Record) -> Value {
    let t = &record.thresholds;
    json!({
        "type": "commission",
        "version": VERSION,
        "link": record.link,
        "started": record.started_utc,
        "parameters": {
            "max_linear_mps": record.parameters.max_linear,
            "max_angular_radps": record.parameters.max_angular,
            "include_timeout": record.parameters.include_timeout,
            "duration_s": round(record.parameters.duration_s),
            "free_space_m": record.parameters.free_space_m,
        },
        "thresholds": {
            "dead_time_ms": band_json(t.dead_time_ms),
            "rise_time_ms": band_json(t.rise_time_ms),
            "overshoot_percent": band_json(t.overshoot_percent),
            "left_right_gain_ratio_off": band_json(t.gain_ratio),
            "heading_drift_deg_per_m": band_json(t.heading_drift_deg_per_m),
            "track_width_percent": band_json(t.track_width_percent),
            "odometer_scale_percent": band_json(t.odometer_scale_percent),
            "command_timeout_ms": band_json(t.command_timeout_ms),
            "internal_resistance_ohm": band_json(t.internal_resistance_ohm),
        },
        "steps": record.plan.iter().enumerate().map(|(number, step)| json!({
            "name": step.name,
            "action": action_words(step.action),
            "duration_s": step.duration.as_secs_f64(),
            "run": number < record.begun,
        })).collect::<Vec<_>>(),
        "figures": record.figures.iter().map(|figure| json!({
            "name": figure.name,
            "step": figure.step,
            "value": figure.value.map(round),
            "verdict": figure.verdict.as_str(),
            "note": figure.note,
        })).collect::<Vec<_>>(),
        "verdict": record.verdict(),
        "abort": record.abort.as_ref().map(|abort| json!({ "reason": abort.reason, "message": abort.message })),
        "stop": record.stop.join("; "),
        "stop_confirmed": record.stop_confirmed,
        "recording": record.recording,
        "exit_status": record.exit_status,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::health::plan::{steps, PlanOptions, FREE_SPACE_M};

    fn record() -> Record {
        let plan = steps(&PlanOptions::default());
        Record {
            link: "sim".into(),
            started_utc: "2025-01-02T03:04:05Z".into(),
            parameters: Parameters {
                max_linear: 0.3,
                max_angular: 0.5,
                include_timeout: false,
                duration_s: 21.7,
                free_space_m: FREE_SPACE_M,
            },
            thresholds: Thresholds::default(),
            begun: 3,
            plan,
            figures: vec![Figure {
                name: "dead_time_ms",
                step: "forward".into(),
                label: "dead time",
                value: Some(40.0),
                unit: "ms",
                verdict: Verdict::Pass,
                note: "warn > 150 ms, fail > 300 ms".into(),
            }],
            abort: Some(Abort {
                reason: "estop",
                message: "stopped after 5.00 s: the E-stop was pressed".into(),
            }),
            stop: vec!["250 motion frames sent".into()],
            stop_confirmed: true,
            exit_status: 4,
            recording: None,
        }
    }

    #[test]
    fn the_plan_names_every_step_the_bounds_and_the_free_space() {
        let record = record();
        let text = plan_text(Some("sim"), &record.parameters, &record.plan);
        assert!(text.contains(" 2. forward"), "{text}");
        assert!(text.contains("+0.300 m/s"), "{text}");
        assert!(text.contains("at most 0.300 m/s and 0.500 rad/s"), "{text}");
        assert!(text.contains("duration: 21.7 s"), "{text}");
        assert!(text.contains("1.5 m clear ahead and behind; it ends near where it started"), "{text}");
    }

    #[test]
    fn an_aborted_record_keeps_its_figures_and_says_why() {
        let record = record();
        let text = text(&record);
        assert!(text.contains("forward                  dead time"), "{text}");
        assert!(text.contains("40 ms  PASS"), "{text}");
        assert!(
            text.contains("result: ABORTED (estop): stopped after 5.00 s: the E-stop was pressed"),
            "{text}"
        );
        let value = json(&record);
        assert_eq!(value["verdict"], "aborted");
        assert_eq!(value["abort"]["reason"], "estop");
        assert_eq!(value["figures"][0]["name"], "dead_time_ms");
        assert_eq!(value["figures"][0]["value"], 40.0);
        assert_eq!(value["steps"][2]["run"], true);
        assert_eq!(value["steps"][3]["run"], false);
        assert_eq!(value["parameters"]["max_linear_mps"], 0.3);
    }
}
