//! `--compare OLD.json`: each figure of this run beside the same figure (same name, same step) of an earlier
//! record, with the change, flagged when it drifted by more than half its warning margin (tyre wear shows
//! in the gain ratio, an ageing battery in its internal resistance) or its verdict got worse. Pure.

use std::fmt::Write as _;

use serde_json::Value;

use super::verdict::Thresholds;

/// How far a figure may move between two runs before it is flagged, in its own unit.
fn drift_limit(name: &str, t: &Thresholds) -> Option<f64> {
    Some(match name {
        "dead_time_ms" => t.dead_time_ms.warn / 2.0,
        "rise_time_ms" => t.rise_time_ms.warn / 2.0,
        "overshoot_percent" => t.overshoot_percent.warn / 2.0,
        "left_right_gain_ratio" => t.gain_ratio.warn / 2.0,
        "heading_drift_deg_per_m" => t.heading_drift_deg_per_m.warn / 2.0,
        "track_width_m" => t.track_width_percent.warn / 2.0 / 100.0 * crate::protocol::constants::TRACK_M,
        "odometer_scale" => t.odometer_scale_percent.warn / 2.0 / 100.0,
        "command_timeout_ms" => t.command_timeout_ms.warn / 2.0,
        "internal_resistance_ohm" => t.internal_resistance_ohm.warn / 2.0,
        _ => return None,
    })
}

fn rank(verdict: &str) -> u8 {
    match verdict {
        "pass" => 1,
        "warn" => 2,
        "fail" => 3,
        _ => 0,
    }
}

/// One figure in both runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Change {
    pub name: String,
    pub step: String,
    pub old: Option<f64>,
    pub new: Option<f64>,
    pub drifted: bool,
}

/// Why an earlier record cannot be compared with.
pub fn check_old(old: &Value) -> Result<(), String> {
    if old["type"] != "commission" || !old["figures"].is_array() {
        return Err("not a commission record (tracerctl commission --format json or --save)".to_string());
    }
    Ok(())
}

/// The figures of `new` against `old`, in `new`'s order (figures only `old` has come last).
pub fn changes(old: &Value, new: &Value, thresholds: &Thresholds) -> Vec<Change> {
    let figures = |record: &Value| record["figures"].as_array().cloned().unwrap_or_default();
    let key = |figure: &Value| {
        (figure["name"].as_str().unwrap_or("").to_string(), figure["step"].as_str().unwrap_or("").to_string())
    };
    let (old_figures, new_figures) = (figures(old), figures(new));
    let mut changes = Vec::new();
    for figure in &new_figures {
        let (name, step) = key(figure);
        let before = old_figures.iter().find(|other| key(other) == (name.clone(), step.clone()));
        let (old_value, new_value) = (before.and_then(|b| b["value"].as_f64()), figure["value"].as_f64());
        let worse = before.is_some_and(|b| {
            rank(figure["verdict"].as_str().unwrap_or("")) > rank(b["verdict"].as_str().unwrap_or("")).max(1)
        });
        let moved = match (old_value, new_value, drift_limit(&name, thresholds)) {
            (Some(old), Some(new), Some(limit)) => (new - old).abs() > limit,
            _ => false,
        };
        changes.push(Change { name, step, old: old_value, new: new_value, drifted: moved || worse });
    }
    for figure in &old_figures {
        let (name, step) = key(figure);
        if !changes.iter().any(|change| change.name == name && change.step == step) {
            changes.push(Change { name, step, old: figure["value"].as_f64(), new: None, drifted: false });
        }
    }
    changes
}

/// The comparison for people.
pub fn text(old_label: &str, changes: &[Change]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "compared with {old_label}:");
    let _ = writeln!(out, "{:<24} {:<26} {:>10} {:>10} {:>10}", "step", "figure", "old", "new", "change");
    let show = |value: Option<f64>| value.map_or_else(|| "-".to_string(), |value| format!("{value:.3}"));
    for change in changes {
        let delta = match (change.old, change.new) {
            (Some(old), Some(new)) => format!("{:+.3}", new - old),
            _ => "-".to_string(),
        };
        let flag = if change.drifted { "  DRIFTED" } else { "" };
        let _ = writeln!(
            out,
            "{:<24} {:<26} {:>10} {:>10} {:>10}{flag}",
            change.step,
            change.name,
            show(change.old),
            show(change.new),
            delta
        );
    }
    let drifted = changes.iter().filter(|change| change.drifted).count();
    let _ =
        writeln!(out, "{drifted} figures drifted beyond half their warning margin (or got a worse verdict)");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn record(ratio: f64, verdict: &str, resistance: f64) -> Value {
        json!({"type": "commission", "figures": [
            {"name": "left_right_gain_ratio", "step": "whole drive", "value": ratio, "verdict": verdict},
            {"name": "internal_resistance_ohm", "step": "battery", "value": resistance, "verdict": "pass"},
            {"name": "dead_time_ms", "step": "forward", "value": 40.0, "verdict": "pass"},
        ]})
    }

    #[test]
    fn tyre_wear_and_an_ageing_battery_show_as_drift() {
        let old = record(1.000, "pass", 0.08);
        let new = record(1.015, "pass", 0.22);
        let changes = changes(&old, &new, &Thresholds::default());
        assert_eq!(changes.len(), 3);
        // 0.015 is beyond half of the 0.02 warning margin; 0.14 Ω beyond half of 0.25 Ω.
        assert!(changes[0].drifted && changes[1].drifted && !changes[2].drifted, "{changes:?}");
        let text = text("old.json", &changes);
        assert!(text.contains("whole drive              left_right_gain_ratio           1.000      1.015     +0.015  DRIFTED"), "{text}");
        assert!(text.contains("2 figures drifted"), "{text}");
        // A worse verdict is a drift even when the value moved little.
        let changes = super::changes(
            &record(1.019, "pass", 0.08),
            &record(1.021, "warn", 0.08),
            &Thresholds::default(),
        );
        assert!(changes[0].drifted);
        assert_eq!(
            check_old(&json!({"type": "drive"})).unwrap_err(),
            "not a commission record (tracerctl commission --format json or --save)"
        );
    }
}
