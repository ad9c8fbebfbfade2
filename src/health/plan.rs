//! The commissioning drive as data: a fixed sequence of held commands, scaled to the caps the operator
//! gave. Pure, so `commission`, its `--dry-run` and the simulator's tests all run the very same steps.

use std::time::Duration;

/// Straight steps drive at most this far from where they start, m: forward, then back the same way.
pub const STRAIGHT_DISTANCE_M: f64 = 1.0;
/// What the operator must keep free ahead of (and behind) the robot: the straight distance plus the
/// braking and the slack of a robot that does not stop where it is told, m.
pub const FREE_SPACE_M: f64 = 1.5;
/// The fastest straight step, m/s: over `STRAIGHT_DISTANCE_M` it is held for 1.67 s, long enough for the
/// robot to settle and for the analysis to take it as a step (it needs 1 s held); faster would need more
/// room than `FREE_SPACE_M`. `commission` caps `--max-linear` here.
pub const MAX_LINEAR: f64 = 0.6;
/// The command-timeout probe's speed, m/s (slow: the robot stops on its own).
pub const TIMEOUT_PROBE_LINEAR: f64 = 0.1;

/// What the host does during a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    /// Send this command (m/s, rad/s) every period.
    Command { linear: f64, angular: f64 },
    /// Send nothing: the robot's own command timeout must stop it.
    Silence,
}

/// One step of the drive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// A name for the report and the plot ("forward", "brake after forward", ...).
    pub name: &'static str,
    pub action: Action,
    pub duration: Duration,
}

/// The operator's bounds and choices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanOptions {
    /// m/s, above 0.
    pub max_linear: f64,
    /// rad/s, above 0.
    pub max_angular: f64,
    /// The opt-in command-timeout probe (`--include timeout`).
    pub include_timeout: bool,
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self { max_linear: 0.3, max_angular: 0.5, include_timeout: false }
    }
}

const SETTLE: Duration = Duration::from_secs(1);
const BRAKE: Duration = Duration::from_secs(2);
const SPIN: Duration = Duration::from_secs(3);
const LONGEST_STRAIGHT: Duration = Duration::from_secs(4);
const TIMEOUT_PROBE: Duration = Duration::from_secs(2);
const TIMEOUT_SILENCE: Duration = Duration::from_millis(1500);

/// The steps, in order.
pub fn steps(options: &PlanOptions) -> Vec<Step> {
    let (v, w) = (options.max_linear.min(MAX_LINEAR), options.max_angular);
    let straight = Duration::from_secs_f64((STRAIGHT_DISTANCE_M / v).min(LONGEST_STRAIGHT.as_secs_f64()));
    let command = |linear, angular| Action::Command { linear, angular };
    let stop = command(0.0, 0.0);
    let mut steps = vec![
        Step { name: "settle", action: stop, duration: SETTLE },
        Step { name: "forward", action: command(v, 0.0), duration: straight },
        Step { name: "brake after forward", action: stop, duration: BRAKE },
        Step { name: "back", action: command(-v, 0.0), duration: straight },
        Step { name: "brake after back", action: stop, duration: BRAKE },
        Step { name: "spin left", action: command(0.0, w), duration: SPIN },
        Step { name: "brake after spin left", action: stop, duration: BRAKE },
        Step { name: "spin right", action: command(0.0, -w), duration: SPIN },
        Step { name: "brake after spin right", action: stop, duration: BRAKE },
    ];
    if options.include_timeout {
        steps.extend([
            Step {
                name: "timeout probe",
                action: command(TIMEOUT_PROBE_LINEAR, 0.0),
                duration: TIMEOUT_PROBE,
            },
            Step { name: "commands cease", action: Action::Silence, duration: TIMEOUT_SILENCE },
            Step { name: "stop", action: stop, duration: SETTLE },
        ]);
    }
    steps
}

/// How long the whole drive takes.
pub fn duration(steps: &[Step]) -> Duration {
    steps.iter().map(|step| step.duration).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_drive_stays_within_the_free_space_and_comes_back() {
        let steps = steps(&PlanOptions::default());
        let mut position = 0.0_f64;
        let mut furthest = 0.0_f64;
        for step in &steps {
            if let Action::Command { linear, .. } = step.action {
                position += linear * step.duration.as_secs_f64();
                furthest = furthest.max(position.abs());
            }
        }
        assert!((furthest - STRAIGHT_DISTANCE_M).abs() < 1e-9, "{furthest}");
        assert!(position.abs() < 1e-9, "{position}");
        assert!(furthest < FREE_SPACE_M);
        assert!((duration(&steps).as_secs_f64() - (1.0 + 2.0 / 0.3 + 4.0 * 2.0 + 6.0)).abs() < 1e-6);
    }

    #[test]
    fn the_timeout_probe_is_opt_in_and_ends_with_a_stop_command() {
        assert!(!steps(&PlanOptions::default()).iter().any(|step| step.action == Action::Silence));
        let with = steps(&PlanOptions { include_timeout: true, ..PlanOptions::default() });
        assert_eq!(with.iter().filter(|step| step.action == Action::Silence).count(), 1);
        assert_eq!(with.last().unwrap().action, Action::Command { linear: 0.0, angular: 0.0 });
    }

    #[test]
    fn every_straight_is_held_long_enough_to_be_analysed_as_a_step() {
        // A straight of 1 s at 1 m/s was shorter than the analysis' 1 s hold by a period: never a step.
        for tenths in 1..=20 {
            let max_linear = f64::from(tenths) / 10.0;
            let steps = steps(&PlanOptions { max_linear, ..PlanOptions::default() });
            let held = steps[1].duration.as_micros() as i64;
            assert!(held >= super::super::segment::HOLD_US * 3 / 2, "{max_linear} m/s held {held} µs");
            let Action::Command { linear, .. } = steps[1].action else { panic!() };
            assert!(
                linear <= MAX_LINEAR
                    && linear * steps[1].duration.as_secs_f64() <= STRAIGHT_DISTANCE_M + 1e-9
            );
        }
    }

    #[test]
    fn slow_caps_shorten_nothing_but_keep_the_distance_bounded() {
        let steps = steps(&PlanOptions { max_linear: 0.1, ..PlanOptions::default() });
        assert_eq!(steps[1].duration, LONGEST_STRAIGHT);
    }
}
