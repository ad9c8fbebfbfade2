//! `decode --summary` of a commissioning run's frames (both directions, as a candump -L log) gives the very
//! health figures the in-process `health::Analyzer` gives for the same frames: the real binary, one job and
//! several, for a few parameter sets drawn from the simulator's test ranges.

use std::time::Duration;

use serde_json::Value;
use tracerctl::candump::{write_log_line, Timestamp, TimestampKind};
use tracerctl::health::plan::{self, Action, PlanOptions};
use tracerctl::health::{Analyzer, BatteryEstimate, Report};
use tracerctl::protocol::can::encode_v2;
use tracerctl::protocol::message::{Message, MotionCommand, MODE_CAN};
use tracerctl::sim::{Chassis, ParamKind, SimConfig, SIM_PARAMS};

use crate::util::{stderr, tracerctl};

/// The log's clock starts here, s (an absolute candump stamp).
const START_S: u64 = 1_700_000_000;

/// A parameter set from the test ranges, drawn with a small fixed generator.
fn config(mut seed: u64) -> SimConfig {
    let mut config = SimConfig::default();
    for param in SIM_PARAMS {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
        let value = param.test_min + u * (param.test_max - param.test_min);
        let text = match param.kind {
            ParamKind::Time => format!("{}ms", value.round()),
            ParamKind::Number => value.to_string(),
            ParamKind::Whole => (seed >> 1).to_string(),
        };
        config.set_param(param.name, &text).unwrap();
    }
    config
}

/// The plan (timeout probe included) on the chassis at 50 Hz: the log's text and the in-process report
/// of the same frames at the same stamps.
fn run(config: SimConfig) -> (Vec<u8>, Report) {
    let mut chassis = Chassis::new(config);
    let mut analyzer = Analyzer::new();
    let mut log = Vec::new();
    let mut feedback = Vec::new();
    let mut emit = |now: Duration, message: &Message, analyzer: &mut Analyzer| {
        let micros = START_S * 1_000_000 + now.as_micros() as u64;
        let ts = Timestamp {
            secs: micros / 1_000_000,
            nanos: (micros % 1_000_000) as u32 * 1000,
            kind: TimestampKind::Absolute,
        };
        write_log_line(&mut log, Some(ts), "can0", &encode_v2(message).unwrap());
        analyzer.observe(micros as i64, message);
    };
    let mode = Message::ControlModeCommand(MODE_CAN);
    chassis.receive(Duration::ZERO, &mode);
    emit(Duration::ZERO, &mode, &mut analyzer);
    let mut now = Duration::ZERO;
    for step in plan::steps(&PlanOptions { include_timeout: true, ..PlanOptions::default() }) {
        let until = now + step.duration;
        while now < until {
            if let Action::Command { linear, angular } = step.action {
                let command = Message::MotionCommand(MotionCommand::from_si(linear, angular).unwrap());
                chassis.receive(now, &command);
                emit(now, &command, &mut analyzer);
            }
            feedback.clear();
            chassis.due_feedback(now, &mut feedback);
            for message in &feedback {
                emit(now, message, &mut analyzer);
            }
            now += Duration::from_millis(20);
        }
    }
    (log, analyzer.report())
}

/// The same figure: both absent, or equal to the 6 decimals the summary's JSON keeps.
fn same(json: &Value, figure: Option<f64>) -> bool {
    match (json.as_f64(), figure) {
        (None, None) => json.is_null(),
        (Some(a), Some(b)) => (a - b).abs() <= 0.5e-6 + 1e-12 * b.abs(),
        _ => false,
    }
}

fn assert_same(health: &Value, report: &Report) {
    let steps = health["steps"].as_array().unwrap();
    assert_eq!(steps.len(), report.steps.len(), "{health}");
    assert_eq!(report.steps.len(), 5);
    for (json, step) in steps.iter().zip(&report.steps) {
        assert!(same(&json["dead_time_ms"], step.dead_time_ms), "{json} {step:?}");
        assert!(same(&json["rise_time_ms"], step.rise_time_ms), "{json} {step:?}");
        assert!(same(&json["overshoot_percent"], step.overshoot_percent), "{json} {step:?}");
    }
    let braking = health["braking"].as_array().unwrap();
    assert_eq!(braking.len(), 4, "{health}");
    for (json, stop) in braking.iter().zip(&report.braking) {
        let deceleration = json.get("deceleration_mps2").or(json.get("deceleration_radps2")).unwrap();
        assert!(same(deceleration, Some(stop.deceleration)), "{json} {stop:?}");
        assert!(same(&json["time_ms"], Some(stop.time_ms)), "{json} {stop:?}");
    }
    let symmetry = report.symmetry.as_ref().unwrap();
    assert!(same(&health["symmetry"]["left_right_gain_ratio"], Some(symmetry.left_right_gain_ratio)));
    assert!(same(&health["symmetry"]["heading_drift_deg_per_m"], Some(symmetry.heading_drift_deg_per_m)));
    assert!(same(&health["geometry"]["track_width_m"], report.geometry.track_width_m));
    assert!(same(&health["geometry"]["odometer_scale"], report.geometry.odometer_scale));
    let timeout = report.command_timeout.as_ref().map(|t| t.timeout_ms);
    assert!(timeout.is_some());
    assert!(same(&health["command_timeout"]["command_timeout_ms"], timeout), "{health}");
    match &report.battery {
        BatteryEstimate::Measured { internal_resistance_ohm, load_steps, .. } => {
            assert!(same(&health["battery"]["internal_resistance_ohm"], Some(*internal_resistance_ohm)));
            assert_eq!(health["battery"]["load_steps"], *load_steps as u64);
        }
        BatteryEstimate::NotMeasurable(why) => assert_eq!(health["battery"]["not_measurable"], why.as_str()),
    }
    assert_eq!(health["command_frames"], report.command_frames);
}

#[test]
fn decode_summary_gives_the_live_analysis_figures() {
    let dir = tempfile::tempdir().unwrap();
    let mut measured = 0;
    for seed in [3, 17, 2026] {
        let mut config = config(seed);
        if seed == 2026 {
            // A small resistance: the sag is too small to measure, and the reason is compared.
            config.set_param("battery-r", "0.05").unwrap();
        }
        let (log, report) = run(config);
        let path = dir.path().join(format!("run-{seed}.log"));
        std::fs::write(&path, &log).unwrap();
        measured += usize::from(matches!(report.battery, BatteryEstimate::Measured { .. }));
        for jobs in ["1", "3"] {
            let output = tracerctl()
                .args(["decode", "--summary", "--format", "json", "-j", jobs])
                .arg(&path)
                .output()
                .unwrap();
            assert!(output.status.success(), "{}", stderr(&output));
            let summary: Value = serde_json::from_slice(&output.stdout).unwrap();
            assert_same(&summary["health"], &report);
        }
    }
    // The sets include a battery the analysis measures and one it does not, so both branches are compared.
    assert!((1..3).contains(&measured), "{measured}");
}
