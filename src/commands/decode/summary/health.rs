//! The "Response and health" section (issue 32), text and JSON: what `health::Analyzer` found in the log.
//! Every JSON key carries its unit (docs/json.md, section 6).

use std::fmt::Write as _;

use serde_json::{json, Value as Json};

use crate::health::{Axis, BatteryEstimate, Braking, Report, StepResponse};

/// Seconds of the log's clock, as the other sections print stamps (µs, exact).
fn seconds(us: i64) -> String {
    format!("{}.{:06}", us.div_euclid(1_000_000), us.rem_euclid(1_000_000))
}

fn seconds_json(us: i64) -> Json {
    seconds(us).parse::<f64>().map_or(Json::Null, Json::from)
}

fn unit(axis: Axis) -> &'static str {
    match axis {
        Axis::Linear => "m/s",
        Axis::Angular => "rad/s",
    }
}

fn optional(value: Option<f64>, decimals: usize, suffix: &str) -> String {
    value.map_or_else(|| "-".to_string(), |value| format!("{value:.decimals$}{suffix}"))
}

pub(super) fn text(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nResponse and health");
    if report.command_frames == 0 {
        let _ = writeln!(w, "  no motion commands in the log: nothing to measure the response against");
        return;
    }
    let _ = writeln!(w, "  steps: {}", report.steps.len() as u64 + report.steps_not_listed);
    for step in &report.steps {
        let _ = writeln!(
            w,
            "    {:<7} {:+.3} -> {:+.3} {} at {}: dead time {}, rise {}, overshoot {}",
            step.axis.as_str(),
            step.from,
            step.to,
            unit(step.axis),
            seconds(step.at_us),
            optional(step.dead_time_ms, 0, " ms"),
            optional(step.rise_time_ms, 0, " ms"),
            optional(step.overshoot_percent, 1, " %"),
        );
    }
    if report.steps_not_listed > 0 {
        let _ = writeln!(w, "    ... and {} more not listed", report.steps_not_listed);
    }
    let _ = writeln!(w, "  braking: {}", report.braking.len() as u64 + report.braking_not_listed);
    for braking in &report.braking {
        let (distance, deceleration) = match braking.axis {
            Axis::Linear => ("m", "m/s²"),
            Axis::Angular => ("rad", "rad/s²"),
        };
        let _ = writeln!(
            w,
            "    {:<7} from {:+.3} {} at {}: {:.0} ms, {:.3} {distance}, {:.2} {deceleration}",
            braking.axis.as_str(),
            braking.from_speed,
            unit(braking.axis),
            seconds(braking.at_us),
            braking.time_ms,
            braking.distance,
            braking.deceleration,
        );
    }
    if report.braking_not_listed > 0 {
        let _ = writeln!(w, "    ... and {} more not listed", report.braking_not_listed);
    }
    chassis_text(w, report);
}

/// Symmetry, geometry, command timeout and battery: one line each.
fn chassis_text(w: &mut String, report: &Report) {
    match &report.symmetry {
        Some(s) => {
            let _ = writeln!(
                w,
                "  symmetry: left/right gain ratio {:.4} (left {:.3} m, right {:.3} m), heading drift {:+.2} °/m",
                s.left_right_gain_ratio, s.left_m, s.right_m, s.heading_drift_deg_per_m
            );
        }
        None => {
            let _ = writeln!(w, "  symmetry: - (no held straight command)");
        }
    }
    let _ = writeln!(
        w,
        "  geometry: track width {}, odometer scale {}",
        optional(report.geometry.track_width_m, 3, " m"),
        optional(report.geometry.odometer_scale, 4, ""),
    );
    match &report.command_timeout {
        Some(timeout) => {
            let _ = writeln!(
                w,
                "  command timeout: {:.0} ms (commands ceased at {})",
                timeout.timeout_ms,
                seconds(timeout.last_command_us)
            );
        }
        None => {
            let _ = writeln!(w, "  command timeout: - (commands never ceased while moving)");
        }
    }
    match &report.battery {
        BatteryEstimate::Measured {
            internal_resistance_ohm,
            spread_ohm,
            open_circuit_voltage_v,
            load_steps,
        } => {
            let _ = writeln!(
                w,
                "  battery: internal resistance {internal_resistance_ohm:.3} Ω (spread {spread_ohm:.3} Ω, \
                 {load_steps} load steps), open-circuit voltage {open_circuit_voltage_v:.2} V"
            );
        }
        BatteryEstimate::NotMeasurable(why) => {
            let _ = writeln!(w, "  battery: not measurable: {why}");
        }
    }
}

fn step_json(step: &StepResponse) -> Json {
    json!({
        "axis": step.axis.as_str(), "unit": unit(step.axis), "at": seconds_json(step.at_us),
        "from": step.from, "to": step.to, "dead_time_ms": step.dead_time_ms.map(fixed),
        "rise_time_ms": step.rise_time_ms.map(fixed), "overshoot_percent": step.overshoot_percent.map(fixed),
    })
}

fn braking_json(braking: &Braking) -> Json {
    let mut object = json!({
        "axis": braking.axis.as_str(), "unit": unit(braking.axis), "at": seconds_json(braking.at_us),
        "from_speed": fixed(braking.from_speed), "time_ms": fixed(braking.time_ms),
    });
    let (distance, deceleration) = match braking.axis {
        Axis::Linear => ("distance_m", "deceleration_mps2"),
        Axis::Angular => ("distance_rad", "deceleration_radps2"),
    };
    object[distance] = json!(fixed(braking.distance));
    object[deceleration] = json!(fixed(braking.deceleration));
    object
}

pub(super) fn json(report: &Report) -> Json {
    let battery = match &report.battery {
        BatteryEstimate::Measured {
            internal_resistance_ohm,
            spread_ohm,
            open_circuit_voltage_v,
            load_steps,
        } => {
            json!({"internal_resistance_ohm": fixed(*internal_resistance_ohm), "spread_ohm": fixed(*spread_ohm),
                "open_circuit_voltage_v": fixed(*open_circuit_voltage_v), "load_steps": load_steps})
        }
        BatteryEstimate::NotMeasurable(why) => json!({ "not_measurable": why }),
    };
    json!({
        "command_frames": report.command_frames,
        "steps": report.steps.iter().map(step_json).collect::<Vec<_>>(),
        "steps_not_listed": report.steps_not_listed,
        "braking": report.braking.iter().map(braking_json).collect::<Vec<_>>(),
        "braking_not_listed": report.braking_not_listed,
        "symmetry": report.symmetry.as_ref().map(|s| json!({
            "left_right_gain_ratio": fixed(s.left_right_gain_ratio), "left_m": fixed(s.left_m),
            "right_m": fixed(s.right_m), "heading_drift_deg_per_m": fixed(s.heading_drift_deg_per_m)})),
        "geometry": {"track_width_m": report.geometry.track_width_m.map(fixed),
            "odometer_scale": report.geometry.odometer_scale.map(fixed)},
        "command_timeout": report.command_timeout.as_ref().map(|t| json!({
            "last_command_at": seconds_json(t.last_command_us), "command_timeout_ms": fixed(t.timeout_ms)})),
        "battery": battery,
    })
}

/// A figure to 6 decimals (as `commission` saves them): the analysis' float noise (an overshoot of
/// 1.85e-14 %) is not a measurement.
fn fixed(value: f64) -> f64 {
    let rounded = (value * 1e6).round() / 1e6;
    if rounded == 0.0 {
        0.0
    } else {
        rounded
    }
}
