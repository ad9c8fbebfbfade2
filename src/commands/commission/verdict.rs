//! The figures of a commissioning run and their verdicts: the analysis' [`Report`] turned into named
//! figures with units (`dead_time_ms`, `left_right_gain_ratio`, ...), each judged PASS / WARN / FAIL against
//! [`Thresholds`] (docs/commission.md, overridable in the configuration file's `[commission]` table). Pure.

use crate::health::plan::{Action, Step};
use crate::health::{Axis, BatteryEstimate, Report};
use crate::protocol::constants::TRACK_M;
use crate::protocol::message::COMMAND_TIMEOUT;

/// What a figure says about the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Verdict {
    /// Measured; nothing to judge it against (a distance, the open-circuit voltage).
    Info,
    /// Not measured (the run was cut short, or the robot reports nothing to measure it from).
    NotMeasured,
    Pass,
    Warn,
    Fail,
}

impl Verdict {
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Info => "info",
            Verdict::NotMeasured => "not_measured",
            Verdict::Pass => "pass",
            Verdict::Warn => "warn",
            Verdict::Fail => "fail",
        }
    }

    /// As the text report shows it.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Info => "INFO",
            Verdict::NotMeasured => "n/a",
            Verdict::Pass => "PASS",
            Verdict::Warn => "WARN",
            Verdict::Fail => "FAIL",
        }
    }
}

/// A warning and a failing limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    pub warn: f64,
    pub fail: f64,
}

/// The limits every figure is judged by (docs/commission.md, "Thresholds").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thresholds {
    /// Above: ms.
    pub dead_time_ms: Band,
    /// Above: ms.
    pub rise_time_ms: Band,
    /// Above: % of the step.
    pub overshoot_percent: Band,
    /// Left over right further from 1 than this.
    pub gain_ratio: Band,
    /// Heading drift beyond this, degrees per metre either way.
    pub heading_drift_deg_per_m: Band,
    /// Track width further than this from [`TRACK_M`], %.
    pub track_width_percent: Band,
    /// Odometer scale further than this from 1, %.
    pub odometer_scale_percent: Band,
    /// `warn`: further than this from the documented 500 ms; `fail`: the robot not stopped by itself this
    /// long after the last command, ms.
    pub command_timeout_ms: Band,
    /// Above: Ω.
    pub internal_resistance_ohm: Band,
}

impl Default for Thresholds {
    fn default() -> Self {
        let band = |warn, fail| Band { warn, fail };
        Self {
            dead_time_ms: band(150.0, 300.0),
            rise_time_ms: band(500.0, 1000.0),
            overshoot_percent: band(10.0, 25.0),
            gain_ratio: band(0.02, 0.05),
            heading_drift_deg_per_m: band(2.0, 5.0),
            track_width_percent: band(5.0, 10.0),
            odometer_scale_percent: band(2.0, 5.0),
            command_timeout_ms: band(100.0, 1000.0),
            internal_resistance_ohm: band(0.25, 0.5),
        }
    }
}

impl Thresholds {
    /// Sets the limit a `[commission]` key names (`dead_time_warn_ms`, `gain_ratio_fail`, ...); false for a
    /// name that is not one.
    pub fn set(&mut self, key: &str, value: f64) -> bool {
        let (prefix, warn) = match (key.find("_warn"), key.find("_fail")) {
            (Some(at), None) => (&key[..at], true),
            (None, Some(at)) => (&key[..at], false),
            _ => return false,
        };
        let band = match prefix {
            "dead_time" => &mut self.dead_time_ms,
            "rise_time" => &mut self.rise_time_ms,
            "overshoot" => &mut self.overshoot_percent,
            "gain_ratio" => &mut self.gain_ratio,
            "heading_drift" => &mut self.heading_drift_deg_per_m,
            "track_width" => &mut self.track_width_percent,
            "odometer_scale" => &mut self.odometer_scale_percent,
            "command_timeout" => &mut self.command_timeout_ms,
            "internal_resistance" => &mut self.internal_resistance_ohm,
            _ => return false,
        };
        if warn {
            band.warn = value;
        } else {
            band.fail = value;
        }
        true
    }
}

/// One measured figure of the run.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// The JSON name, with its unit (`dead_time_ms`).
    pub name: &'static str,
    /// The step it was measured in (`forward`), or what it covers (`whole drive`, `battery`).
    pub step: String,
    /// In words, for the text report (`dead time`).
    pub label: &'static str,
    pub value: Option<f64>,
    /// As the text report shows it (`ms`, `m/s²`).
    pub unit: &'static str,
    pub verdict: Verdict,
    /// The limits it was judged by, or why it was not measured.
    pub note: String,
}

impl Figure {
    fn new(
        name: &'static str,
        step: &str,
        label: &'static str,
        value: Option<f64>,
        unit: &'static str,
    ) -> Self {
        Self { name, step: step.to_string(), label, value, unit, verdict: Verdict::Info, note: String::new() }
    }

    /// Judged by its distance from `nominal` (`value - nominal`, absolute, in the band's units after
    /// `scale`), or by the value itself when `nominal` is `None`.
    fn judged(mut self, band: Band, nominal: Option<f64>, scale: f64, limits: String) -> Self {
        self.note = limits;
        self.verdict = match self.value {
            None => Verdict::NotMeasured,
            Some(value) => {
                let off = nominal.map_or(value, |nominal| ((value - nominal) * scale).abs());
                if off > band.fail {
                    Verdict::Fail
                } else if off > band.warn {
                    Verdict::Warn
                } else {
                    Verdict::Pass
                }
            }
        };
        self
    }

    fn not_measured(mut self, why: impl Into<String>) -> Self {
        self.verdict = Verdict::NotMeasured;
        self.note = why.into();
        self
    }
}

/// Where each step of the run began (µs of the recording's clock), to name the step a figure comes from.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepTimes {
    pub starts: Vec<(String, i64)>,
}

impl StepTimes {
    /// The step running at `at_us` (a command sent at a step's start is stamped just after it).
    pub fn at(&self, at_us: i64) -> String {
        self.starts
            .iter()
            .rev()
            .find(|(_, start)| *start <= at_us + 1000)
            .map_or_else(|| "before the drive".to_string(), |(name, _)| name.clone())
    }
}

/// What the run measured, beside the analysis: the robot's own stop when commands ceased (watched live).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Observed {
    /// The timeout probe ran (`--include timeout`).
    pub timeout_probe: bool,
    /// During the silence, the robot was still moving this long after the last command, ms (`None`: it
    /// stopped, or the probe did not get that far).
    pub still_moving_after_ms: Option<f64>,
}

/// The figures of a report, judged.
pub fn figures(
    report: &Report,
    steps: &StepTimes,
    thresholds: &Thresholds,
    observed: Observed,
) -> Vec<Figure> {
    let mut figures = Vec::new();
    response_figures(report, steps, thresholds, &mut figures);
    braking_figures(report, steps, &mut figures);
    symmetry_figures(report, thresholds, &mut figures);
    timeout_figures(report, thresholds, observed, &mut figures);
    battery_figures(report, thresholds, &mut figures);
    figures
}

fn above(band: Band, unit: &str) -> String {
    format!("warn > {} {unit}, fail > {} {unit}", band.warn, band.fail)
}

fn response_figures(report: &Report, steps: &StepTimes, t: &Thresholds, figures: &mut Vec<Figure>) {
    for step in &report.steps {
        let name = steps.at(step.at_us);
        figures.push(Figure::new("dead_time_ms", &name, "dead time", step.dead_time_ms, "ms").judged(
            t.dead_time_ms,
            None,
            1.0,
            above(t.dead_time_ms, "ms"),
        ));
        figures.push(
            Figure::new("rise_time_ms", &name, "rise time 10-90 %", step.rise_time_ms, "ms").judged(
                t.rise_time_ms,
                None,
                1.0,
                above(t.rise_time_ms, "ms"),
            ),
        );
        figures.push(
            Figure::new("overshoot_percent", &name, "overshoot", step.overshoot_percent, "%").judged(
                t.overshoot_percent,
                None,
                1.0,
                above(t.overshoot_percent, "%"),
            ),
        );
    }
}

/// Braking warns only below this share of the acceleration: both are estimates (the deceleration within
/// 10 % on the simulator, docs/commission.md), and equal figures read a hair apart must not warn.
const BRAKING_MARGIN: f64 = 0.9;

/// Mean acceleration of the step before `at_us` on `axis` (10 % to 90 % of it over the rise time).
fn acceleration_before(report: &Report, axis: Axis, at_us: i64) -> Option<f64> {
    let step = report.steps.iter().rev().find(|step| step.axis == axis && step.at_us < at_us)?;
    let rise = step.rise_time_ms? / 1000.0;
    (rise > 0.0).then(|| 0.8 * (step.to - step.from).abs() / rise)
}

fn braking_figures(report: &Report, steps: &StepTimes, figures: &mut Vec<Figure>) {
    for braking in &report.braking {
        let name = steps.at(braking.at_us);
        let (decel_name, distance_name, unit, distance_unit) = match braking.axis {
            Axis::Linear => ("deceleration_mps2", "braking_distance_m", "m/s²", "m"),
            Axis::Angular => ("angular_deceleration_radps2", "braking_angle_rad", "rad/s²", "rad"),
        };
        figures.push(Figure::new("braking_time_ms", &name, "braking time", Some(braking.time_ms), "ms"));
        figures.push(Figure::new(
            distance_name,
            &name,
            "braking distance",
            Some(braking.distance),
            distance_unit,
        ));
        let mut decel = Figure::new(decel_name, &name, "deceleration", Some(braking.deceleration), unit);
        // Braking must be at least as strong as speeding up (the stop rules' own rule for the sender).
        if let Some(accel) = acceleration_before(report, braking.axis, braking.at_us) {
            let floor = BRAKING_MARGIN * accel;
            decel.verdict = if braking.deceleration < floor { Verdict::Warn } else { Verdict::Pass };
            decel.note = format!("warn below 90 % of the acceleration ({accel:.2} {unit})");
        }
        figures.push(decel);
    }
}

fn symmetry_figures(report: &Report, t: &Thresholds, figures: &mut Vec<Figure>) {
    const WHOLE: &str = "whole drive";
    let symmetry = report.symmetry.as_ref();
    let ratio = Figure::new(
        "left_right_gain_ratio",
        WHOLE,
        "left/right gain ratio",
        symmetry.map(|s| s.left_right_gain_ratio),
        "",
    );
    figures.push(ratio.judged(
        t.gain_ratio,
        Some(1.0),
        1.0,
        format!(
            "warn outside {}-{}, fail outside {}-{}",
            1.0 - t.gain_ratio.warn,
            1.0 + t.gain_ratio.warn,
            1.0 - t.gain_ratio.fail,
            1.0 + t.gain_ratio.fail
        ),
    ));
    let drift = Figure::new(
        "heading_drift_deg_per_m",
        WHOLE,
        "heading drift",
        symmetry.map(|s| s.heading_drift_deg_per_m),
        "°/m",
    );
    let band = t.heading_drift_deg_per_m;
    figures.push(drift.judged(
        band,
        Some(0.0),
        1.0,
        format!("warn beyond ±{} °/m, fail beyond ±{} °/m", band.warn, band.fail),
    ));
    let band = t.track_width_percent;
    figures.push(
        Figure::new("track_width_m", WHOLE, "track width", report.geometry.track_width_m, "m").judged(
            band,
            Some(TRACK_M),
            100.0 / TRACK_M,
            format!("nominal {TRACK_M} m: warn beyond {} %, fail beyond {} %", band.warn, band.fail),
        ),
    );
    let band = t.odometer_scale_percent;
    figures.push(
        Figure::new("odometer_scale", WHOLE, "odometer scale", report.geometry.odometer_scale, "").judged(
            band,
            Some(1.0),
            100.0,
            format!("warn beyond {} %, fail beyond {} %", band.warn, band.fail),
        ),
    );
}

fn timeout_figures(report: &Report, t: &Thresholds, observed: Observed, figures: &mut Vec<Figure>) {
    if !observed.timeout_probe {
        return;
    }
    let nominal = COMMAND_TIMEOUT.as_secs_f64() * 1000.0;
    let band = t.command_timeout_ms;
    let figure = Figure::new(
        "command_timeout_ms",
        "commands cease",
        "command timeout",
        report.command_timeout.as_ref().map(|timeout| timeout.timeout_ms),
        "ms",
    );
    let limits = format!(
        "documented {nominal} ms: warn beyond ±{} ms, fail if not stopped within {} ms",
        band.warn, band.fail
    );
    let mut figure = match figure.value {
        // Warn only by the distance from 500 ms; failing is not stopping at all (below).
        Some(_) => {
            figure.judged(Band { warn: band.warn, fail: f64::INFINITY }, Some(nominal), 1.0, limits.clone())
        }
        None => figure.not_measured("not found in the feedback"),
    };
    if let Some(moving) = observed.still_moving_after_ms {
        figure.verdict = Verdict::Fail;
        figure.note = format!("the robot still moved {moving:.0} ms after the last command ({limits})");
    } else if figure.value.is_some_and(|value| value > band.fail) {
        figure.verdict = Verdict::Fail;
    }
    figures.push(figure);
}

fn battery_figures(report: &Report, t: &Thresholds, figures: &mut Vec<Figure>) {
    let resistance = Figure::new("internal_resistance_ohm", "battery", "internal resistance", None, "Ω");
    let voltage = Figure::new("open_circuit_voltage_v", "battery", "open-circuit voltage", None, "V");
    match &report.battery {
        BatteryEstimate::Measured {
            internal_resistance_ohm,
            spread_ohm,
            open_circuit_voltage_v,
            load_steps,
        } => {
            let band = t.internal_resistance_ohm;
            let mut resistance = Figure { value: Some(*internal_resistance_ohm), ..resistance }.judged(
                band,
                None,
                1.0,
                above(band, "Ω"),
            );
            resistance.note = format!("±{spread_ohm:.3} Ω over {load_steps} load steps; {}", resistance.note);
            figures.push(resistance);
            figures.push(Figure { value: Some(*open_circuit_voltage_v), ..voltage });
        }
        BatteryEstimate::NotMeasurable(why) => {
            figures.push(resistance.not_measured(format!("not measurable: {why}")));
            figures.push(voltage.not_measured(format!("not measurable: {why}")));
        }
    }
}

/// What a step that ran to its end must have given, when the analysis did not find it: a WARN with no
/// value, so a run that measured nothing never passes quietly. A held single-axis command of 1 s or more
/// gives a step response; a zero after a moving step, a braking.
pub fn missing(plan: &[Step], steps: &StepTimes, completed: usize, report: &Report) -> Vec<Figure> {
    const WHY: &str = "not found: the recording holds no response to this step (docs/troubleshooting.md, \
                       \"commission: not found\")";
    let within = |at_us: i64, (from, to): (i64, i64)| from <= at_us + 1000 && at_us + 1000 < to;
    let mut figures = Vec::new();
    for (index, step) in plan.iter().enumerate().take(completed.min(steps.starts.len())) {
        let span = (steps.starts[index].1, steps.starts.get(index + 1).map_or(i64::MAX, |next| next.1));
        let Action::Command { linear, angular } = step.action else { continue };
        let previous_moving = index
            .checked_sub(1)
            .is_some_and(|p| matches!(plan[p].action, Action::Command { linear, angular } if linear != 0.0 || angular != 0.0));
        let expected = match (linear != 0.0, angular != 0.0) {
            (true, false) | (false, true) if step.duration.as_secs_f64() >= 1.0 => {
                let found = report.steps.iter().any(|response| within(response.at_us, span));
                (!found).then(|| Figure::new("dead_time_ms", step.name, "dead time", None, "ms"))
            }
            (false, false) if previous_moving => {
                let found = report.braking.iter().any(|braking| within(braking.at_us, span));
                let (name, unit) = match plan[index - 1].action {
                    Action::Command { linear: 0.0, .. } => ("angular_deceleration_radps2", "rad/s²"),
                    _ => ("deceleration_mps2", "m/s²"),
                };
                (!found).then(|| Figure::new(name, step.name, "deceleration", None, unit))
            }
            _ => None,
        };
        if let Some(mut figure) = expected {
            figure.verdict = Verdict::Warn;
            figure.note = WHY.to_string();
            figures.push(figure);
        }
    }
    figures
}

/// The worst verdict of the figures (`Info` when none was judged).
pub fn worst(figures: &[Figure]) -> Verdict {
    figures.iter().map(|figure| figure.verdict).max().unwrap_or(Verdict::Info)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::health::plan::{self, PlanOptions};
    use crate::health::{Braking, Geometry, StepResponse, Symmetry};

    #[test]
    fn a_step_that_ran_and_gave_nothing_warns_so_nothing_measured_never_passes() {
        let plan = plan::steps(&PlanOptions::default());
        // The report has the forward step (1.0 s) and its braking (5.0 s) only.
        let starts_ms = [0, 990, 4_990, 7_000, 10_000, 12_000, 15_000, 17_000, 20_000];
        let steps = StepTimes {
            starts: plan.iter().zip(starts_ms).map(|(step, ms)| (step.name.to_string(), ms * 1000)).collect(),
        };
        let named = |figures: Vec<Figure>| -> Vec<(String, &'static str, Verdict, Option<f64>)> {
            figures.into_iter().map(|f| (f.step, f.name, f.verdict, f.value)).collect()
        };
        let warn = |step: &str, name| (step.to_string(), name, Verdict::Warn, None);
        assert_eq!(
            named(missing(&plan, &steps, plan.len(), &report())),
            [
                warn("back", "dead_time_ms"),
                warn("brake after back", "deceleration_mps2"),
                warn("spin left", "dead_time_ms"),
                warn("brake after spin left", "angular_deceleration_radps2"),
                warn("spin right", "dead_time_ms"),
                warn("brake after spin right", "angular_deceleration_radps2"),
            ]
        );
        // Cut short during "back": the steps before it gave what they must.
        assert_eq!(named(missing(&plan, &steps, 3, &report())), []);
        let figure = &missing(&plan, &steps, 4, &report())[0];
        assert!(figure.note.starts_with("not found: the recording holds no response"), "{figure:?}");
        assert_eq!(worst(std::slice::from_ref(figure)), Verdict::Warn);
    }

    fn report() -> Report {
        Report {
            steps: vec![StepResponse {
                axis: Axis::Linear,
                at_us: 1_000_000,
                from: 0.0,
                to: 0.3,
                dead_time_ms: Some(40.0),
                rise_time_ms: Some(400.0),
                overshoot_percent: Some(0.0),
            }],
            braking: vec![Braking {
                axis: Axis::Linear,
                at_us: 5_000_000,
                from_speed: 0.3,
                time_ms: 500.0,
                distance: 0.07,
                deceleration: 0.5,
            }],
            symmetry: Some(Symmetry {
                left_right_gain_ratio: 1.03,
                left_m: 1.03,
                right_m: 1.0,
                heading_drift_deg_per_m: -0.5,
            }),
            geometry: Geometry { track_width_m: Some(0.40), odometer_scale: Some(1.001) },
            command_timeout: None,
            battery: BatteryEstimate::NotMeasurable("no current frames".into()),
            steps_not_listed: 0,
            braking_not_listed: 0,
            command_frames: 500,
        }
    }

    fn steps() -> StepTimes {
        StepTimes {
            starts: vec![("settle".into(), 0), ("forward".into(), 1_000_100), ("brake".into(), 5_000_000)],
        }
    }

    fn find<'a>(figures: &'a [Figure], name: &str) -> &'a Figure {
        figures.iter().find(|figure| figure.name == name).unwrap()
    }

    #[test]
    fn each_figure_is_judged_against_its_band() {
        let figures = figures(&report(), &steps(), &Thresholds::default(), Observed::default());
        let dead = find(&figures, "dead_time_ms");
        assert_eq!((dead.step.as_str(), dead.value, dead.verdict), ("forward", Some(40.0), Verdict::Pass));
        assert_eq!(
            find(&figures, "left_right_gain_ratio").verdict,
            Verdict::Warn,
            "1.03 is outside 0.98-1.02"
        );
        assert_eq!(find(&figures, "heading_drift_deg_per_m").verdict, Verdict::Pass);
        // 0.40 m is 11 % over 0.36 m.
        assert_eq!(find(&figures, "track_width_m").verdict, Verdict::Fail);
        assert_eq!(find(&figures, "odometer_scale").verdict, Verdict::Pass);
        // 0.3 m/s in 0.4 s (10-90 %) is 0.6 m/s²: braking at 0.5 m/s² is weaker.
        let decel = find(&figures, "deceleration_mps2");
        assert_eq!((decel.step.as_str(), decel.verdict), ("brake", Verdict::Warn));
        assert_eq!(find(&figures, "internal_resistance_ohm").verdict, Verdict::NotMeasured);
        assert!(find(&figures, "open_circuit_voltage_v").note.contains("no current frames"));
        assert!(!figures.iter().any(|figure| figure.name == "command_timeout_ms"), "not asked for");
        assert_eq!(worst(&figures), Verdict::Fail);
    }

    #[test]
    fn braking_as_strong_as_the_acceleration_read_a_hair_apart_passes() {
        // The simulator's own run: 1.000 m/s² both ways, the braking estimate 0.9999 (a WARN before).
        let mut report = report();
        report.braking[0].deceleration = 0.6 * 0.9999;
        let figures = figures(&report, &steps(), &Thresholds::default(), Observed::default());
        assert_eq!(find(&figures, "deceleration_mps2").verdict, Verdict::Pass);
        report.braking[0].deceleration = 0.6 * 0.89;
        let figures = super::figures(&report, &steps(), &Thresholds::default(), Observed::default());
        assert_eq!(find(&figures, "deceleration_mps2").verdict, Verdict::Warn);
    }

    #[test]
    fn a_robot_that_does_not_stop_by_itself_fails_the_timeout() {
        let observed = Observed { timeout_probe: true, still_moving_after_ms: Some(1200.0) };
        let figures = figures(&report(), &steps(), &Thresholds::default(), observed);
        let timeout = find(&figures, "command_timeout_ms");
        assert_eq!(timeout.verdict, Verdict::Fail);
        assert!(timeout.note.starts_with("the robot still moved 1200 ms"), "{}", timeout.note);
        let mut report = report();
        report.command_timeout =
            Some(crate::health::CommandTimeout { last_command_us: 0, timeout_ms: 650.0 });
        let observed = Observed { timeout_probe: true, still_moving_after_ms: None };
        let figures = super::figures(&report, &steps(), &Thresholds::default(), observed);
        assert_eq!(find(&figures, "command_timeout_ms").verdict, Verdict::Warn, "150 ms from 500");
    }

    #[test]
    fn the_configuration_keys_set_every_limit_and_their_fallbacks_are_the_defaults() {
        let keys: Vec<_> = crate::config::KEYS.iter().filter(|key| key.table == "commission").collect();
        assert_eq!(keys.len(), 18, "a warning and a failing limit per figure");
        let mut configured = Thresholds::default();
        for key in &keys {
            let fallback: f64 = key.fallback.value().unwrap().parse().unwrap();
            assert!(configured.set(key.name, fallback), "{}", key.name);
        }
        assert_eq!(configured, Thresholds::default(), "the keys' fallbacks are the built-in limits");
        assert!(configured.set("gain_ratio_warn", 0.01));
        assert_eq!(configured.gain_ratio.warn, 0.01);
        assert!(!configured.set("colour_warn", 1.0));
    }

    #[test]
    fn a_measured_battery_is_judged_by_its_resistance() {
        let mut report = report();
        report.battery = BatteryEstimate::Measured {
            internal_resistance_ohm: 0.3,
            spread_ohm: 0.02,
            open_circuit_voltage_v: 26.1,
            load_steps: 4,
        };
        let figures = figures(&report, &steps(), &Thresholds::default(), Observed::default());
        assert_eq!(find(&figures, "internal_resistance_ohm").verdict, Verdict::Warn);
        assert_eq!(find(&figures, "open_circuit_voltage_v").value, Some(26.1));
    }
}
