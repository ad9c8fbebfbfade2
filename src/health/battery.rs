//! The battery's internal resistance and open-circuit voltage from the reported voltage against the summed
//! motor current around load steps (command steps and stops: the accelerations), by least squares.

use super::fit::mean_and_sigma;
use super::sample::Reading;
use super::series::{within, View};
use super::BatteryEstimate;

/// A load step's window: from before the command step to after the acceleration, µs.
const BEFORE_US: i64 = 300_000;
const AFTER_US: i64 = 700_000;
/// A voltage reading is paired with each motor's current reading nearest in time, within this, µs.
const PAIRING_US: i64 = 15_000;
/// A load step needs this many pairs ...
const MIN_PAIRS: i64 = 5;
/// ... and a current change of at least 1 A (in 0.1 A).
const MIN_CURRENT_RANGE_DA: i32 = 10;
/// Below a 0.5 V swing (in 0.1 V) the 0.1 V resolution leaves the estimate a guess: not measured.
pub(super) const MIN_VOLTAGE_RANGE_DV: i32 = 5;
/// Nor when the slope's standard error is above this fraction of it (noise, not load, moved the voltage):
/// three standard errors stay within the 15 % tolerance.
const MAX_RELATIVE_ERROR: f64 = 0.04;

/// One load step's pairs, summed in 0.1 A and 0.1 V (exact).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct LoadStep {
    pub pairs: i64,
    pub sum_i: i64,
    pub sum_v: i64,
    pub sum_ii: i128,
    pub sum_iv: i128,
    pub sum_vv: i128,
    pub current_range: i32,
    pub voltage_range: i32,
}

impl LoadStep {
    /// (centred Σ I², centred Σ I·V), in 0.1 A and 0.1 V.
    fn centred(&self) -> (f64, f64) {
        let n = self.pairs as f64;
        let (si, sv) = (self.sum_i as f64, self.sum_v as f64);
        (self.sum_ii as f64 - si * si / n, self.sum_iv as f64 - si * sv / n)
    }

    /// Centred Σ V², in 0.1 V.
    fn centred_vv(&self) -> f64 {
        let sv = self.sum_v as f64;
        self.sum_vv as f64 - sv * sv / self.pairs as f64
    }
}

/// The pairs around the command step at `t0`.
pub(super) fn load_step(view: &View, t0: i64) -> Option<LoadStep> {
    let mut step = LoadStep::default();
    let (mut i_range, mut v_range) = ((i32::MAX, i32::MIN), (i32::MAX, i32::MIN));
    for voltage in &view.voltage[within(view.voltage, t0 - BEFORE_US, t0 + AFTER_US, |r| r.t)] {
        let (Some(first), Some(second)) =
            (nearest(view.currents[0], voltage.t), nearest(view.currents[1], voltage.t))
        else {
            continue;
        };
        let (current, volts) = (i64::from(first + second), i64::from(voltage.value));
        step.pairs += 1;
        step.sum_i += current;
        step.sum_v += volts;
        step.sum_ii += i128::from(current * current);
        step.sum_iv += i128::from(current * volts);
        step.sum_vv += i128::from(volts * volts);
        i_range = (i_range.0.min(first + second), i_range.1.max(first + second));
        v_range = (v_range.0.min(voltage.value), v_range.1.max(voltage.value));
    }
    if step.pairs == 0 {
        return None;
    }
    step.current_range = i_range.1.saturating_sub(i_range.0);
    step.voltage_range = v_range.1.saturating_sub(v_range.0);
    (step.pairs >= MIN_PAIRS && step.current_range >= MIN_CURRENT_RANGE_DA).then_some(step)
}

/// The reading nearest `t` within [`PAIRING_US`].
fn nearest(readings: &[Reading], t: i64) -> Option<i32> {
    let range = within(readings, t - PAIRING_US, t + PAIRING_US, |r| r.t);
    readings[range].iter().min_by_key(|r| (r.t - t).abs()).map(|r| r.value)
}

/// The estimate from the load steps found (in order), or why there is none.
pub(super) fn estimate(steps: &[LoadStep], current_frames: u64, voltage_frames: u64) -> BatteryEstimate {
    let not = |why: String| BatteryEstimate::NotMeasurable(why);
    if current_frames == 0 {
        return not("no current frames".into());
    }
    if voltage_frames == 0 {
        return not("no battery voltage frames".into());
    }
    if steps.is_empty() {
        return not("no load steps (a command step with a motor current change of 1 A or more)".into());
    }
    let swing = steps.iter().map(|s| s.voltage_range).max().unwrap_or(0);
    let current = steps.iter().map(|s| s.current_range).max().unwrap_or(0);
    if swing < MIN_VOLTAGE_RANGE_DV {
        return not(format!(
            "the voltage moved by at most {:.1} V at {} load steps (motor current changes up to {:.1} A): \
             below {:.1} V, too little for the 0.1 V resolution",
            f64::from(swing) / 10.0,
            steps.len(),
            f64::from(current) / 10.0,
            f64::from(MIN_VOLTAGE_RANGE_DV) / 10.0
        ));
    }
    let (sxx, sxy) = steps.iter().map(LoadStep::centred).fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    // V = OCV - R·I: 0.1 V per 0.1 A is ohms.
    let resistance = -sxy / sxx;
    if resistance.is_nan() || resistance <= 0.0 {
        return not(format!("the voltage did not drop under load at {} load steps", steps.len()));
    }
    // The residual variance around the per-step lines (one mean per step and the common slope).
    let pairs: i64 = steps.iter().map(|s| s.pairs).sum();
    let freedom = (pairs - steps.len() as i64 - 1).max(1) as f64;
    let residual = (steps.iter().map(LoadStep::centred_vv).sum::<f64>() - sxy * sxy / sxx).max(0.0) / freedom;
    let standard_error = (residual / sxx).sqrt();
    if standard_error > MAX_RELATIVE_ERROR * resistance {
        return not(format!(
            "{resistance:.3} Ω ± {standard_error:.3} Ω at {} load steps: the voltage noise is too large for \
             the load's sag (a standard error above {:.0} %)",
            steps.len(),
            MAX_RELATIVE_ERROR * 100.0
        ));
    }
    let per_step = steps.iter().map(|s| s.centred()).filter(|(x, _)| *x > 0.0).map(|(x, y)| -y / x);
    let spread = mean_and_sigma(per_step).map_or(0.0, |(_, sigma)| sigma);
    let open_circuit =
        steps.iter().map(|s| (s.sum_v as f64 + resistance * s.sum_i as f64) / s.pairs as f64).sum::<f64>()
            / steps.len() as f64;
    BatteryEstimate::Measured {
        internal_resistance_ohm: resistance,
        spread_ohm: spread,
        open_circuit_voltage_v: open_circuit / 10.0,
        load_steps: steps.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::health::sample::{Command, Motion, Odometer};

    fn view<'a>(currents: [&'a [Reading]; 2], voltage: &'a [Reading]) -> View<'a> {
        const NO_COMMANDS: &[Command] = &[];
        const NO_MOTION: &[Motion] = &[];
        const NO_ODOMETRY: &[Odometer] = &[];
        View { commands: NO_COMMANDS, motion: NO_MOTION, currents, odometry: NO_ODOMETRY, voltage }
    }

    fn readings(values: &[i32]) -> Vec<Reading> {
        values.iter().enumerate().map(|(n, &value)| Reading { t: n as i64 * 20_000, value }).collect()
    }

    #[test]
    fn resistance_and_open_circuit_voltage_of_exact_readings() {
        // 25.0 V at rest; 5 A then 10 A per motor: 0.1 Ω drops 1 V and 2 V.
        let current = readings(&[0, 0, 0, 0, 0, 50, 50, 50, 100, 100, 100, 0, 0]);
        let voltage = readings(&[250, 250, 250, 250, 250, 240, 240, 240, 230, 230, 230, 250, 250]);
        let step = load_step(&view([&current, &current], &voltage), 100_000).unwrap();
        assert_eq!((step.pairs, step.current_range, step.voltage_range), (13, 200, 20));
        let BatteryEstimate::Measured {
            internal_resistance_ohm,
            spread_ohm,
            open_circuit_voltage_v,
            load_steps,
        } = estimate(&[step.clone(), step], 100, 100)
        else {
            panic!("not measured")
        };
        assert!((internal_resistance_ohm - 0.1).abs() < 1e-12);
        assert!(spread_ohm.abs() < 1e-12);
        assert!((open_circuit_voltage_v - 25.0).abs() < 1e-12);
        assert_eq!(load_steps, 2);
    }

    #[test]
    fn no_estimate_without_current_voltage_steps_or_swing() {
        let step = LoadStep { pairs: 10, current_range: 40, voltage_range: 3, ..LoadStep::default() };
        assert_eq!(estimate(&[], 0, 10), BatteryEstimate::NotMeasurable("no current frames".into()));
        assert_eq!(estimate(&[], 10, 0), BatteryEstimate::NotMeasurable("no battery voltage frames".into()));
        assert!(
            matches!(estimate(&[], 10, 10), BatteryEstimate::NotMeasurable(why) if why.starts_with("no load steps"))
        );
        let BatteryEstimate::NotMeasurable(why) = estimate(&[step], 10, 10) else { panic!() };
        assert_eq!(
            why,
            "the voltage moved by at most 0.3 V at 1 load steps (motor current changes up to 4.0 A): below 0.5 V, \
             too little for the 0.1 V resolution"
        );
    }

    #[test]
    fn pairs_need_both_motors_near_in_time_and_a_current_change() {
        let current = readings(&[0, 0, 0, 0, 0, 0]);
        let voltage = readings(&[250; 6]);
        assert_eq!(load_step(&view([&current, &current], &voltage), 0), None);
        assert_eq!(load_step(&view([&current, &[]], &voltage), 0), None);
    }
}
