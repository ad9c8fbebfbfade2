//! drive's periodic status: one record per update, drawn as a line that fits the terminal, a full line for
//! a pipe or a log, or a JSON object (docs/json.md).
//!
//! On a narrow terminal the line loses detail in a fixed order: the speeds stay (ever more compact), then
//! the faults, the battery and the control mode, in that order of importance, so a wrapped line never
//! pushes the status up the screen.

use std::time::Duration;

use serde_json::{json, Value};

use crate::protocol::faults::Severity;
use crate::protocol::message::{vehicle_state_name, SystemState};
use crate::protocol::{ControlMode, Wire};

/// What one status update says.
#[derive(Clone, Debug, PartialEq)]
pub struct Status {
    pub elapsed: Duration,
    /// (m/s, rad/s) asked for, after the caps.
    pub target: (f64, f64),
    /// (m/s, rad/s) in the latest motion frame sent (ramped).
    pub sent: (f64, f64),
    /// (m/s, rad/s) the robot reports, if it has.
    pub measured: Option<(f64, f64)>,
    /// The robot's recent system state; `None` when there is none.
    pub robot: Option<Robot>,
    pub send_error: Option<String>,
}

/// The robot's system state in the words of the status.
#[derive(Clone, Debug, PartialEq)]
pub struct Robot {
    /// `normal`, `estop`, ... (as decode's `vehicle_state`).
    pub vehicle_state: String,
    /// `can`, `standby`, ... (as decode's `control_mode`).
    pub control_mode: String,
    pub battery_voltage: f64,
    /// Every set fault or status bit, named, with its severity.
    pub faults: Vec<(&'static str, Severity)>,
}

impl Robot {
    pub fn new(state: &SystemState, wire: Wire) -> Self {
        Self {
            vehicle_state: vehicle_state_name(state.vehicle_state)
                .map_or_else(|| format!("unknown_0x{:02X}", state.vehicle_state), str::to_string),
            control_mode: ControlMode::describe(wire, state.control_mode),
            battery_voltage: state.battery_voltage(),
            faults: state.faults(wire).iter().map(|info| (info.name, info.severity)).collect(),
        }
    }
}

/// How much of the speeds a line shows.
#[derive(Clone, Copy)]
enum Speeds {
    /// `  1.25 s  target +0.300 m/s +0.000 rad/s  sent +0.300 +0.000  measured +0.298 m/s +0.000 rad/s`
    Full,
    /// `1.2 s  sent +0.300 +0.000  measured +0.298 +0.000`
    Short,
    /// `sent +0.30 +0.00 meas +0.30 +0.00`
    Tiny,
}

/// How much of the faults (with the vehicle state) a line shows.
#[derive(Clone, Copy, PartialEq)]
enum Faults {
    /// `normal, faults: none`, `estop, faults: motor_overheat [fault]`
    List,
    /// `normal, 0 faults`, `normal, 2 faults [fault]`
    Count,
    /// `ok`, `fault`, or the vehicle state when it is not normal (`estop`): a word, so 40 columns keep it
    Word,
    Hidden,
}

/// What a line keeps besides the speeds: (faults, battery, mode, send error), most complete first. The
/// first that fits (with the speeds as full as still fits) is drawn.
const LAYOUTS: [(Faults, bool, bool, bool); 9] = [
    (Faults::List, true, true, true),
    (Faults::List, true, true, false),
    (Faults::List, true, false, false),
    (Faults::Count, true, true, false),
    (Faults::Count, true, false, false),
    (Faults::List, false, false, false),
    (Faults::Count, false, false, false),
    (Faults::Word, false, false, false),
    (Faults::Hidden, false, false, false),
];

/// The status as one line of at most `width` characters, dropping the least important parts first.
pub fn fit(status: &Status, width: usize) -> String {
    for (faults, battery, mode, error) in LAYOUTS {
        for speeds in [Speeds::Full, Speeds::Short, Speeds::Tiny] {
            let line = compose(status, speeds, faults, battery, mode, error);
            if line.chars().count() <= width {
                return line;
            }
        }
    }
    compose(status, Speeds::Tiny, Faults::Hidden, false, false, false).chars().take(width).collect()
}

/// The status as one line with everything (for a pipe or a log).
pub fn full(status: &Status) -> String {
    compose(status, Speeds::Full, Faults::List, true, true, true)
}

fn compose(
    status: &Status,
    speeds: Speeds,
    faults: Faults,
    battery: bool,
    mode: bool,
    error: bool,
) -> String {
    let mut parts = vec![speed_text(status, speeds)];
    match &status.robot {
        Some(robot) => {
            parts.extend(fault_text(robot, faults));
            if battery {
                parts.push(format!("{:.1} V", robot.battery_voltage));
            }
            if mode {
                parts.push(format!("mode {}", robot.control_mode));
            }
        }
        None if faults != Faults::Hidden => parts.push("no status".to_string()),
        None => {}
    }
    if let (true, Some(message)) = (error, &status.send_error) {
        parts.push(format!("send error: {message}"));
    }
    parts.join("  ")
}

fn speed_text(status: &Status, speeds: Speeds) -> String {
    let (target, sent) = (status.target, status.sent);
    match speeds {
        Speeds::Full => {
            let measured = status.measured.map_or_else(
                || "-".to_string(),
                |(linear, angular)| format!("{linear:+.3} m/s {angular:+.3} rad/s"),
            );
            format!(
                "{:6.2} s  target {:+.3} m/s {:+.3} rad/s  sent {:+.3} {:+.3}  measured {measured}",
                status.elapsed.as_secs_f64(),
                target.0,
                target.1,
                sent.0,
                sent.1
            )
        }
        Speeds::Short => {
            let measured = status
                .measured
                .map_or_else(|| "-".to_string(), |(linear, angular)| format!("{linear:+.3} {angular:+.3}"));
            format!(
                "{:.1} s  sent {:+.3} {:+.3}  measured {measured}",
                status.elapsed.as_secs_f64(),
                sent.0,
                sent.1
            )
        }
        Speeds::Tiny => {
            let measured = status
                .measured
                .map_or_else(|| "-".to_string(), |(linear, angular)| format!("{linear:+.2} {angular:+.2}"));
            format!("sent {:+.2} {:+.2} meas {measured}", sent.0, sent.1)
        }
    }
}

fn fault_text(robot: &Robot, faults: Faults) -> Option<String> {
    let state = &robot.vehicle_state;
    let count = robot.faults.len();
    let worst = robot.faults.iter().map(|(_, severity)| *severity).max();
    let plural = if count == 1 { "" } else { "s" };
    match (faults, worst) {
        (Faults::List, None) => Some(format!("{state}, faults: none")),
        (Faults::List, Some(_)) => {
            let list: Vec<String> =
                robot.faults.iter().map(|(name, severity)| format!("{name} [{severity}]")).collect();
            Some(format!("{state}, faults: {}", list.join(", ")))
        }
        (Faults::Count, None) => Some(format!("{state}, 0 faults")),
        (Faults::Count, Some(worst)) => Some(format!("{state}, {count} fault{plural} [{worst}]")),
        (Faults::Word, None) if state == "normal" => Some("ok".to_string()),
        (Faults::Word, None) => Some(state.clone()),
        (Faults::Word, Some(_)) if state == "normal" => Some("fault".to_string()),
        (Faults::Word, Some(_)) => Some(state.clone()),
        (Faults::Hidden, _) => None,
    }
}

/// A (m/s, rad/s) pair as JSON, with decode's field names.
pub fn velocity_json((linear, angular): (f64, f64)) -> Value {
    json!({ "linear_velocity": round(linear, 3), "angular_velocity": round(angular, 3) })
}

/// Rounded to `decimals`, so JSON shows 0.3, not 0.30000000000000004.
pub fn round(value: f64, decimals: i32) -> f64 {
    let scale = 10f64.powi(decimals);
    (value * scale).round() / scale
}

/// The status as one JSON object (docs/json.md, "drive").
pub fn json(status: &Status) -> Value {
    let robot = status.robot.as_ref().map(|robot| {
        json!({
            "vehicle_state": robot.vehicle_state,
            "control_mode": robot.control_mode,
            "battery_voltage": round(robot.battery_voltage, 1),
            "faults": robot.faults.iter().map(|(name, _)| *name).collect::<Vec<_>>(),
        })
    });
    json!({
        "type": "status",
        "elapsed": round(status.elapsed.as_secs_f64(), 3),
        "target": velocity_json(status.target),
        "sent": velocity_json(status.sent),
        "measured": status.measured.map(velocity_json),
        "robot": robot,
        "send_error": status.send_error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(faults: Vec<(&'static str, Severity)>) -> Status {
        Status {
            elapsed: Duration::from_millis(1250),
            target: (0.3, 0.0),
            sent: (0.3, -0.1),
            measured: Some((0.298, -0.1)),
            robot: Some(Robot {
                vehicle_state: "normal".to_string(),
                control_mode: "can".to_string(),
                battery_voltage: 25.9,
                faults,
            }),
            send_error: None,
        }
    }

    const WIDTHS: [usize; 5] = [40, 60, 80, 100, 140];

    /// Whatever the width, a part is shown only if every more important part is.
    fn assert_priorities(line: &str, width: usize) {
        assert!(line.chars().count() <= width, "{width}: {line:?} is {} long", line.chars().count());
        assert!(line.contains("sent +0.30"), "{width}: the speeds always stay: {line:?}");
        let shows_faults = line.contains("fault") || line.contains("  ok");
        let shows_battery = line.contains(" V");
        let shows_mode = line.contains("mode can");
        assert!(!shows_battery || shows_faults, "{width}: battery without faults: {line:?}");
        assert!(!shows_mode || shows_battery, "{width}: mode without battery: {line:?}");
    }

    #[test]
    fn the_line_fits_every_width_and_drops_the_least_important_first() {
        let healthy = status(Vec::new());
        let expected = [
            (40, "sent +0.30 -0.10 meas +0.30 -0.10  ok"),
            (60, "sent +0.30 -0.10 meas +0.30 -0.10  normal, 0 faults  25.9 V"),
            (80, "sent +0.30 -0.10 meas +0.30 -0.10  normal, faults: none  25.9 V  mode can"),
            (100, "1.2 s  sent +0.300 -0.100  measured +0.298 -0.100  normal, faults: none  25.9 V  mode can"),
            (
                140,
                "  1.25 s  target +0.300 m/s +0.000 rad/s  sent +0.300 -0.100  measured +0.298 m/s -0.100 rad/s  \
                 normal, faults: none  25.9 V  mode can",
            ),
        ];
        for (width, line) in expected {
            assert_eq!(fit(&healthy, width), line, "at {width} columns");
            assert_priorities(line, width);
        }
        assert_eq!(full(&healthy), expected[4].1);
    }

    #[test]
    fn faults_outrank_battery_and_mode_on_narrow_lines() {
        let faulty = status(vec![
            ("motor_driver_overheat_protection", Severity::Protection),
            ("battery_undervoltage_warning", Severity::Warning),
        ]);
        for width in WIDTHS {
            assert_priorities(&fit(&faulty, width), width);
        }
        assert_eq!(fit(&faulty, 40), "sent +0.30 -0.10 meas +0.30 -0.10  fault");
        assert_eq!(
            fit(&faulty, 80),
            "sent +0.30 -0.10 meas +0.30 -0.10  normal, 2 faults [protection]  25.9 V"
        );
        // A list too long to keep the battery beside it is counted instead; a pipe gets every name.
        assert_eq!(
            fit(&faulty, 140),
            "1.2 s  sent +0.300 -0.100  measured +0.298 -0.100  normal, 2 faults [protection]  25.9 V  mode can"
        );
        assert!(full(&faulty).contains(
            "normal, faults: motor_driver_overheat_protection [protection], battery_undervoltage_warning \
             [warning]  25.9 V  mode can"
        ));

        let estop = Status {
            robot: Some(Robot { vehicle_state: "estop".to_string(), ..status(Vec::new()).robot.unwrap() }),
            ..status(Vec::new())
        };
        assert_eq!(fit(&estop, 40), "sent +0.30 -0.10 meas +0.30 -0.10  estop");
    }

    #[test]
    fn no_status_a_send_error_and_tiny_widths_still_fit() {
        let silent = Status { robot: None, measured: None, ..status(Vec::new()) };
        assert_eq!(fit(&silent, 40), "sent +0.30 -0.10 meas -  no status");
        let failing = Status {
            send_error: Some("No buffer space available (os error 105)".into()),
            ..status(Vec::new())
        };
        for width in WIDTHS {
            assert_priorities(&fit(&failing, width), width);
        }
        assert!(full(&failing).ends_with("mode can  send error: No buffer space available (os error 105)"));
        // Below the speeds' own 33 characters, they are cut at the width.
        for width in 0..40 {
            let length = fit(&failing, width).chars().count();
            assert!(length <= width && (width >= 33 || length == width), "width {width}: {length}");
        }
    }

    #[test]
    fn json_has_the_documented_fields() {
        let value = json(&status(vec![("battery_undervoltage_warning", Severity::Warning)]));
        assert_eq!(
            value.to_string(),
            r#"{"elapsed":1.25,"measured":{"angular_velocity":-0.1,"linear_velocity":0.298},"robot":{"battery_voltage":25.9,"control_mode":"can","faults":["battery_undervoltage_warning"],"vehicle_state":"normal"},"send_error":null,"sent":{"angular_velocity":-0.1,"linear_velocity":0.3},"target":{"angular_velocity":0.0,"linear_velocity":0.3},"type":"status"}"#
        );
    }
}
