//! The analysis against the truth: random chassis parameter sets drawn from the test ranges of
//! `sim::SIM_PARAMS` (docs/sim.md), the commissioning plan (timeout probe included) driven through the
//! pure `Chassis` at 50 Hz on both wires, the report compared with the parameters it should recover within
//! the tolerances of docs/commission.md ("Tolerances"). The ignored `precision_table` prints the
//! "Precision on the simulator" table of docs/commission.md.

use std::time::Duration;

use proptest::prelude::*;

use super::plan::PlanOptions;
use super::sim_tests::{analyse, drive_traced};
use super::{Axis, BatteryEstimate, Report};
use crate::protocol::message::Message;
use crate::sim::{Chassis, ParamKind, SimConfig, SimWire, SIM_PARAMS};

/// The simulator's idle (electronics) current, A: the open-circuit voltage the analysis gives is the
/// voltage at zero *motor* current, so it includes this sag.
const IDLE_CURRENT_A: f64 = 1.0;
/// Within this of the battery measurement window (docs/commission.md, "Battery"), µs.
const LOAD_WINDOW_US: (i64, i64) = (300_000, 700_000);
/// The 15 % tolerance of the internal resistance is asserted from this up (docs/commission.md), Ω.
const MIN_ASSERTED_OHM: f64 = 0.1;
/// A true voltage swing of at least this at some load step must be measured: the documented 0.5 V plus one
/// 0.1 V quantum the rounding may take off the reported swing ...
const MEASURABLE_SWING_V: f64 = 0.6;
/// ... and at least this many standard deviations of the voltage noise (else the standard error may pass
/// 5 %: "not measurable").
const MEASURABLE_SWING_SIGMAS: f64 = 10.0;

/// How close a figure must come to the truth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Tolerance {
    /// Absolute, in the metric's unit.
    Abs(f64),
    /// Relative to the truth.
    Rel(f64),
    /// Reported in the precision table only.
    Reported,
}

/// One 20 ms period, for every step: the onset is the joint fit of dead time, lag and acceleration
/// (`lagged_ramp`), not the first measurable motion, then fitted again with the lag and acceleration of the
/// larger steps of its axis (`refit`).
pub(crate) fn dead_time_tolerance(_config: &SimConfig, _change: f64) -> Tolerance {
    Tolerance::Abs(20.0)
}

/// The issue's 25 ms: the stop's onset is fitted as the step's is (again with the larger steps' lag and
/// acceleration, as is the probe's dead time it takes off).
pub(crate) fn timeout_tolerance(_config: &SimConfig) -> Tolerance {
    Tolerance::Abs(25.0)
}

/// One figure of a report against its truth.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Check {
    pub metric: &'static str,
    pub unit: &'static str,
    /// `None`: the report has no figure where the truth says there should be one.
    pub measured: Option<f64>,
    pub truth: f64,
    pub tolerance: Tolerance,
}

impl Check {
    pub fn error(&self) -> Option<(f64, f64)> {
        self.measured.map(|m| ((m - self.truth).abs(), (m - self.truth).abs() / self.truth.abs()))
    }

    pub fn holds(&self) -> bool {
        match (self.error(), self.tolerance) {
            (None, _) => false,
            (Some(_), Tolerance::Reported) => true,
            (Some((abs, _)), Tolerance::Abs(limit)) => abs <= limit,
            (Some((_, rel)), Tolerance::Rel(limit)) => rel <= limit,
        }
    }
}

/// A parameter set: each table parameter's value from a unit draw `u` in [0, 1) over its test range.
pub(crate) fn config(wire: SimWire, draws: &[f64]) -> (SimConfig, Vec<String>) {
    let mut config = SimConfig { wire, ..SimConfig::default() };
    let mut settings = Vec::new();
    for (param, &u) in SIM_PARAMS.iter().zip(draws) {
        let value = param.test_min + u * (param.test_max - param.test_min);
        let text = match param.kind {
            ParamKind::Time => format!("{}ms", value.round()),
            ParamKind::Number => format!("{value}"),
            ParamKind::Whole => format!("{}", (u * u64::MAX as f64) as u64),
        };
        config.set_param(param.name, &text).unwrap();
        settings.push(format!("{}={text}", param.name));
    }
    (config, settings)
}

/// The model's exact state every millisecond: (µs, linear m/s, angular rad/s, battery V).
type Trace = Vec<(i64, f64, f64, f64)>;

fn true_value(point: &(i64, f64, f64, f64), axis: Axis) -> f64 {
    if axis == Axis::Linear {
        point.1
    } else {
        point.2
    }
}

/// The trace point at or before `t`.
fn at(trace: &Trace, t: i64) -> &(i64, f64, f64, f64) {
    &trace[trace.partition_point(|p| p.0 <= t).saturating_sub(1)]
}

/// The first time after `t0` at which the true `axis` speed reaches `level` going `direction`,
/// interpolated between milliseconds.
fn true_crossing(trace: &Trace, axis: Axis, t0: i64, level: f64, direction: f64) -> Option<f64> {
    let start = trace.partition_point(|p| p.0 < t0);
    let points = trace[start..].iter().map(|p| (p.0, true_value(p, axis)));
    super::fit::crossing(points, level, direction)
}

/// The times of the command frames, and of those that change the command's value, µs, in order.
fn commands(log: &[(i64, Message)]) -> (Vec<i64>, Vec<i64>) {
    let mut last = None;
    let (mut all, mut changes) = (Vec::new(), Vec::new());
    for (t, message) in log {
        if let Some(super::sample::Sample::Command { linear, angular }) = super::sample::Sample::of(message) {
            all.push(*t);
            if last != Some((linear, angular)) {
                changes.push(*t);
                last = Some((linear, angular));
            }
        }
    }
    (all, changes)
}

/// The run of one parameter set on its wire: the report and every figure against its truth.
pub(crate) fn run(config: SimConfig) -> (Report, Vec<Check>) {
    let (report, checks, _) = run_logged(config);
    (report, checks)
}

/// [`run`], with the log.
fn run_logged(config: SimConfig) -> (Report, Vec<Check>, Vec<(i64, Message)>) {
    let options = PlanOptions { include_timeout: true, ..PlanOptions::default() };
    let mut trace = Trace::new();
    let record = |now: Duration, chassis: &Chassis| {
        let state = chassis.state();
        trace.push((now.as_micros() as i64, state.linear, state.angular, state.battery_voltage));
    };
    let log = drive_traced(config.clone(), &options, record);
    let report = analyse(&log);
    let checks = checks(&config, &report, &log, &trace);
    (report, checks, log)
}

fn checks(config: &SimConfig, report: &Report, log: &[(i64, Message)], trace: &Trace) -> Vec<Check> {
    let (all, changes) = commands(log);
    // The last command frame of the hold that starts at `t0` (commands may cease before the next change).
    let hold_end = |t0: i64| {
        let next = changes.iter().copied().find(|&t| t > t0).unwrap_or(i64::MAX);
        all[all.partition_point(|&t| t < next) - 1]
    };
    let ms = |d: Duration| d.as_secs_f64() * 1000.0;
    // The plan: forward, back, spin left, spin right, the timeout probe; a stop after each of the first four.
    let mut checks = vec![
        Check {
            metric: "steps found",
            unit: "",
            measured: Some(report.steps.iter().filter(|s| s.dead_time_ms.is_some()).count() as f64),
            truth: 5.0,
            tolerance: Tolerance::Abs(0.0),
        },
        Check {
            metric: "stops found",
            unit: "",
            measured: Some(report.braking.len() as f64),
            truth: 4.0,
            tolerance: Tolerance::Abs(0.0),
        },
    ];
    for step in &report.steps {
        let end = hold_end(step.at_us);
        let settled = true_value(at(trace, end), step.axis);
        let before = true_value(at(trace, step.at_us), step.axis);
        let change = settled - before;
        let direction = change.signum();
        let t10 = true_crossing(trace, step.axis, step.at_us, before + 0.1 * change, direction).unwrap();
        let t90 = true_crossing(trace, step.axis, step.at_us, before + 0.9 * change, direction).unwrap();
        checks.push(Check {
            metric: if ms(config.lag) <= 40.0 { "dead time, lag <= 40 ms" } else { "dead time, lag > 40 ms" },
            unit: "ms",
            measured: step.dead_time_ms,
            truth: ms(config.dead_time),
            tolerance: dead_time_tolerance(config, step.to - step.from),
        });
        checks.push(Check {
            metric: "rise time",
            unit: "ms",
            measured: step.rise_time_ms,
            truth: (t90 - t10) / 1000.0,
            tolerance: Tolerance::Reported,
        });
    }
    for braking in &report.braking {
        let v0 = true_value(at(trace, braking.at_us), braking.axis);
        let t90 = true_crossing(trace, braking.axis, braking.at_us, 0.9 * v0, -v0.signum()).unwrap();
        let t10 = true_crossing(trace, braking.axis, braking.at_us, 0.1 * v0, -v0.signum()).unwrap();
        checks.push(Check {
            metric: if braking.axis == Axis::Linear { "deceleration linear" } else { "deceleration angular" },
            unit: if braking.axis == Axis::Linear { "m/s²" } else { "rad/s²" },
            measured: Some(braking.deceleration),
            truth: 0.8 * v0.abs() / ((t10 - t90) / 1e6),
            tolerance: Tolerance::Rel(0.10),
        });
    }
    chassis_checks(config, report, &mut checks);
    battery_checks(config, report, &changes, trace, &mut checks);
    checks
}

/// Symmetry, geometry and the command timeout: what the wire carries.
fn chassis_checks(config: &SimConfig, report: &Report, checks: &mut Vec<Check>) {
    let (left, right) = (config.left_gain, config.right_gain);
    if config.wire == SimWire::CanV2 {
        checks.push(Check {
            metric: "left/right gain ratio",
            unit: "",
            measured: report.symmetry.as_ref().map(|s| s.left_right_gain_ratio),
            truth: left / right,
            tolerance: Tolerance::Rel(0.01),
        });
        checks.push(Check {
            metric: "track width",
            unit: "m",
            measured: report.geometry.track_width_m,
            truth: config.effective_track_m,
            tolerance: Tolerance::Rel(0.02),
        });
        checks.push(Check {
            metric: "odometer scale",
            unit: "",
            measured: report.geometry.odometer_scale,
            truth: config.odometer_scale,
            tolerance: Tolerance::Rel(0.01),
        });
        // Straight: w = (r - l) / track, v = (r + l) / 2, per metre w / v.
        let drift = (2.0 * (right - left) / (config.effective_track_m * (left + right))).to_degrees();
        checks.push(Check {
            metric: "heading drift",
            unit: "°/m",
            measured: report.symmetry.as_ref().map(|s| s.heading_drift_deg_per_m),
            truth: drift,
            tolerance: Tolerance::Reported,
        });
    }
    checks.push(Check {
        metric: "command timeout",
        unit: "ms",
        measured: report.command_timeout.as_ref().map(|t| t.timeout_ms),
        truth: config.command_timeout.as_secs_f64() * 1000.0,
        tolerance: timeout_tolerance(config),
    });
}

/// The largest true voltage swing within a load step's window.
fn true_swing(changes: &[i64], trace: &Trace) -> f64 {
    let swing = |t0: i64| {
        let window = trace.iter().filter(|p| (t0 - LOAD_WINDOW_US.0..=t0 + LOAD_WINDOW_US.1).contains(&p.0));
        let (low, high) = window.fold((f64::MAX, f64::MIN), |(low, high), p| (low.min(p.3), high.max(p.3)));
        high - low
    };
    changes.iter().map(|&t0| swing(t0)).fold(0.0, f64::max)
}

fn battery_checks(
    config: &SimConfig,
    report: &Report,
    changes: &[i64],
    trace: &Trace,
    checks: &mut Vec<Check>,
) {
    let resistance = config.battery_resistance_ohm;
    match &report.battery {
        BatteryEstimate::Measured { internal_resistance_ohm, open_circuit_voltage_v, .. } => {
            checks.push(Check {
                metric: "internal resistance",
                unit: "Ω",
                measured: Some(*internal_resistance_ohm),
                truth: resistance,
                // Below 0.1 Ω the sag at a step is a few 0.1 V quanta: the rounding biases the slope.
                tolerance: if resistance >= MIN_ASSERTED_OHM {
                    Tolerance::Rel(0.15)
                } else {
                    Tolerance::Reported
                },
            });
            checks.push(Check {
                metric: "open-circuit voltage",
                unit: "V",
                measured: Some(*open_circuit_voltage_v),
                truth: config.battery_start_v - IDLE_CURRENT_A * resistance,
                tolerance: Tolerance::Reported,
            });
        }
        BatteryEstimate::NotMeasurable(_)
            if true_swing(changes, trace)
                >= MEASURABLE_SWING_V.max(MEASURABLE_SWING_SIGMAS * config.noise * 0.1) =>
        {
            checks.push(Check {
                metric: "internal resistance",
                unit: "Ω",
                measured: None,
                truth: resistance,
                tolerance: Tolerance::Rel(0.15),
            });
        }
        BatteryEstimate::NotMeasurable(_) => {}
    }
}

/// Every check of one set on both wires; the failures in words.
fn failures(draws: &[f64]) -> Vec<String> {
    let mut failed = Vec::new();
    for wire in [SimWire::CanV2, SimWire::Serial] {
        let (config, settings) = config(wire, draws);
        let (report, checks, log) = run_logged(config);
        for check in checks.iter().filter(|check| !check.holds()) {
            failed.push(format!("{wire:?} {}: {check:?}\n  report: {report:?}", settings.join(" ")));
        }
        // Noise, lag and creeping stops included, the chunks of `decode -j N` still merge exactly.
        let cuts = [(draws[0] * log.len() as f64) as usize, (draws[1] * log.len() as f64) as usize];
        let cuts = [cuts[0].min(cuts[1]), cuts[0].max(cuts[1])];
        if super::sim_tests::merged(&log, &cuts).is_some_and(|merged| merged != report) {
            failed.push(format!("{wire:?} {}: cut at {cuts:?}, the merge differs", settings.join(" ")));
        }
    }
    failed
}

fn draws() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(0.0..1.0f64, SIM_PARAMS.len())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Any realistic chassis is measured within the documented tolerances, on CAN and on RS232.
    #[test]
    fn random_chassis_are_measured_within_the_tolerances(draws in draws()) {
        let failed = failures(&draws);
        prop_assert!(failed.is_empty(), "{}", failed.join("\n"));
    }
}

/// The corner the joint fit alone missed, as the property test above shrank it: the timeout probe's 0.1 m/s
/// under noise of 1.9 quanta and a lag of 128 ms. Before `refit`, its dead time was 98.4 ms against a true
/// 71 (27.4 ms off, beyond one period).
#[test]
fn the_probe_under_noise_and_a_long_lag_is_timed_within_one_period() {
    let settings = [
        ("dead-time", "71ms"),
        ("lag", "128ms"),
        ("max-accel", "0.5"),
        ("left-gain", "0.9"),
        ("right-gain", "0.9"),
        ("track-width", "0.33"),
        ("odometer-scale", "0.95"),
        ("command-timeout", "200ms"),
        ("battery-ocv", "23.5"),
        ("battery-r", "0.05"),
        ("noise", "1.8867203774643584"),
        ("seed", "197187518578264192"),
    ];
    for wire in [SimWire::CanV2, SimWire::Serial] {
        let mut config = SimConfig { wire, ..SimConfig::default() };
        for (name, value) in settings {
            config.set_param(name, value).unwrap();
        }
        let (report, checks) = run(config);
        let probe = report.steps.iter().find(|step| (step.to - step.from).abs() < 0.2).expect("the probe");
        let dead = probe.dead_time_ms.expect("the probe's dead time");
        assert!((dead - 71.0).abs() <= 20.0, "{wire:?}: the probe's dead time {dead} ms, truth 71 ms");
        let failed: Vec<&Check> = checks.iter().filter(|check| !check.holds()).collect();
        assert!(failed.is_empty(), "{wire:?}: {failed:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 100, ..ProptestConfig::default() })]

    #[test]
    #[ignore = "100 cases, about a minute in a debug build: run with --ignored"]
    fn random_chassis_are_measured_within_the_tolerances_100(draws in draws()) {
        let failed = failures(&draws);
        prop_assert!(failed.is_empty(), "{}", failed.join("\n"));
    }
}

/// The set a CI run's random test found (issue 32): 0.339 Ω measured 0.280 Ω on RS232 (-17.4 %) by least
/// squares, the noise in the currents (1.79 quanta) flattening the slope of a small load (max-accel 0.56).
#[test]
fn noisy_currents_at_a_small_load_do_not_flatten_the_resistance() {
    holds_everywhere(&[
        0.4010553547208743,
        0.20045391307112995,
        0.03681261854265106,
        0.0,
        0.470171582805929,
        0.0,
        0.0,
        0.0,
        0.0,
        0.641537924687727,
        0.8970808250930961,
        0.9105747351219414,
    ]);
}

/// A set a 12 000-set scan found: on RS232 the settled 0.1 m/s timeout probe (noise 1.84 quanta, lag 147 ms)
/// had a last-300 ms trend of 4.2 standard errors, so it was judged still moving and got no rise time.
#[test]
fn a_settled_noisy_probe_keeps_its_rise_time() {
    holds_everywhere(&[
        0.015974235788112235,
        0.9770476784116321,
        0.4503161764304174,
        0.44619763024031905,
        0.23934992582484882,
        0.8214685756391397,
        0.3271507663613981,
        0.5495767842507038,
        0.7182660746979077,
        0.42464083152532456,
        0.9224552486878973,
        0.9518246602580855,
    ]);
}

/// Sets a 20 000-set scan found with the joint fit's dead times: at max-accel 0.51-0.55 m/s² (the slowest
/// ramp of the test range) a ramp rounds its start by less than the noise, so one step's fit traded the lag
/// for the dead time: 20.5 ms late (RS232, dead-time 170 ms, lag 25 ms, noise 1.59) and 20.5 ms early
/// (CAN V2, dead-time 108 ms, lag 2 ms, noise 1.94). The large steps are now fitted again with the medians
/// of their axis (`refit.rs`).
#[test]
fn a_slow_ramp_under_noise_is_timed_within_one_period() {
    holds_everywhere(&[
        0.8488747289041151,
        0.1671854420772915,
        0.008958953550504882,
        0.2082963689736461,
        0.8595546975743524,
        0.26818285287597066,
        0.6765115909781421,
        0.23281571728008685,
        0.9569806843120058,
        0.08148169582518211,
        0.7957556934867634,
        0.3924022511786643,
    ]);
    holds_everywhere(&[
        0.5400945943819899,
        0.011100686525763327,
        0.03452335293628704,
        0.4378534057348387,
        0.24125850606208327,
        0.2232288632831658,
        0.7550238069857078,
        0.208471999309535,
        0.44249542065475206,
        0.4554618133135035,
        0.9711847681518451,
        0.3353577911113362,
    ]);
}

/// The same scan: on CAN V2 (dead-time 196 ms, lag 142 ms, max-accel 0.54) the robot's own stop from the
/// probe began 991 ms after the last command and had not reached 95 % of its change when the silence
/// ended, so it had no fit and its apparent onset stood: a timeout 35 ms long. A response cut short now
/// keeps its samples, fitted again with the axis's shape (`steps.rs`, `refit.rs`).
#[test]
fn a_stop_the_silence_cuts_short_is_timed_within_the_tolerance() {
    holds_everywhere(&[
        0.978350785402738,
        0.9434020393279082,
        0.027603584876609057,
        0.2594053725325751,
        0.40861180846686457,
        0.8161458020348192,
        0.5300172409665255,
        0.9909773896582911,
        0.9684981533140298,
        0.7199349127544021,
        0.6711120051727705,
        0.31052736480547094,
    ]);
}

/// A set of a scan of 10 000 more: the settled RS232 probe (noise 1.89 quanta) had a trend of 6.07 standard
/// errors, no rise time; the limit is now 8 (`SETTLED_ERRORS`).
#[test]
fn a_probe_with_a_trend_of_six_errors_is_settled() {
    holds_everywhere(&[
        0.2324096755313332,
        0.15308807693466012,
        0.6319468319585144,
        0.7276261188611655,
        0.23713437193697903,
        0.6849491073891881,
        0.11288936568938232,
        0.3947260078891739,
        0.8599884137452892,
        0.3847246335079003,
        0.9433553937430271,
        0.09775489060722785,
    ]);
}

/// Every check of the set `draws` holds, on both wires.
fn holds_everywhere(draws: &[f64]) {
    let failed = failures(draws);
    assert!(failed.is_empty(), "{failed:#?}");
}

/// A fixed, reproducible stream of unit draws (splitmix64).
fn unit_draws(seed: &mut u64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|_| {
            *seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = *seed;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            (z ^ (z >> 31)) as f64 / 2f64.powi(64)
        })
        .collect()
}

/// Per metric: each set's worst (absolute, relative) error, the unit, the sets without a figure, the checks
/// outside their tolerance.
type MetricErrors = (Vec<(f64, f64)>, &'static str, usize, usize);

/// Sets in the precision table (docs/commission.md, "Precision on the simulator").
const TABLE_SETS: usize = 100;
const TABLE_SEED: u64 = 32;

/// `cargo test --release --lib health::precision_tests::precision_table -- --ignored --nocapture`
#[test]
#[ignore = "prints the precision table of docs/commission.md: run with --ignored --nocapture"]
fn precision_table() {
    use std::collections::BTreeMap;
    use std::fmt::Write as _;
    let mut table = String::new();
    // The same sets on both wires.
    for wire in [SimWire::CanV2, SimWire::Serial] {
        // Per metric: each set's worst (absolute, relative) error, the unit, the sets without a figure.
        let mut errors: BTreeMap<&str, MetricErrors> = BTreeMap::new();
        let mut failed = 0;
        let mut table_seed = TABLE_SEED;
        for _ in 0..TABLE_SETS {
            let (config, _) = config(wire, &unit_draws(&mut table_seed, SIM_PARAMS.len()));
            let (_, checks) = run(config);
            let mut worst: BTreeMap<&str, (f64, f64)> = BTreeMap::new();
            for check in &checks {
                let entry = errors.entry(check.metric).or_insert((Vec::new(), check.unit, 0, 0));
                failed += usize::from(!check.holds());
                entry.3 += usize::from(!check.holds());
                match check.error() {
                    Some((abs, rel)) => {
                        let w = worst.entry(check.metric).or_insert((0.0, 0.0));
                        *w = (w.0.max(abs), w.1.max(rel));
                    }
                    None => entry.2 += 1,
                }
            }
            for (metric, error) in worst {
                errors.get_mut(metric).unwrap().0.push(error);
            }
        }
        let _ = writeln!(table, "\n{wire:?}: {TABLE_SETS} sets, {failed} checks outside their tolerance");
        let _ = writeln!(
            table,
            "| metric | sets measured | median error | worst error | median rel. | worst rel. | outside |"
        );
        let _ = writeln!(table, "|---|---|---|---|---|---|---|");
        for (metric, (mut sets, unit, missing, outside)) in errors {
            let n = sets.len();
            if n == 0 {
                let _ = writeln!(table, "| {metric} | 0 ({missing} missing) | | | | | {outside} |");
                continue;
            }
            sets.sort_by(|a, b| a.0.total_cmp(&b.0));
            let median_abs = sets[n / 2].0;
            let worst_abs = sets[n - 1].0;
            sets.sort_by(|a, b| a.1.total_cmp(&b.1));
            let (median_rel, worst_rel) = (sets[n / 2].1, sets[n - 1].1);
            let _ = writeln!(
            table,
                "| {metric} | {n}{} | {median_abs:.4} {unit} | {worst_abs:.4} {unit} | {:.2} % | {:.2} % | {outside} |",
                if missing > 0 { format!(" ({missing} missing)") } else { String::new() },
                median_rel * 100.0,
                worst_rel * 100.0,
            );
        }
    }
    let _ = std::io::Write::write_all(&mut std::io::stdout().lock(), table.as_bytes());
}
