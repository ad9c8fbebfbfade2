//! The battery's internal resistance and open-circuit voltage from the reported voltage against the summed
//! motor current around load steps (command steps and stops: the accelerations).
//!
//! Not by least squares of voltage on current: the currents are noisy too, and noise in the regressor
//! flattens the slope by var(noise) / var(current) (errors in variables: 3.5 % on average at noise 1.5-2
//! quanta, more at small load steps; one set of the random test measured 17 % low). The slope is an
//! instrumental-variable estimate instead: each pair's instrument is the sum of the currents read just
//! before and just after the paired ones, which follows the load as closely but carries none of the
//! paired readings' noise.

use super::fit::mean_and_sigma;
use super::sample::Reading;
use super::series::{within, View};
use super::BatteryEstimate;

/// A load step's window: from before the command step to after the acceleration, µs.
const BEFORE_US: i64 = 300_000;
const AFTER_US: i64 = 700_000;
/// A voltage reading is paired with each motor's current reading nearest in time, within this, µs ...
const PAIRING_US: i64 = 15_000;
/// ... whose neighbours (the instrument) are read within this of it, µs (two and a half 50 Hz periods) ...
const NEIGHBOUR_US: i64 = 50_000;
/// ... and both read 0 (at rest: exact) or their mean is at least this, in 0.1 A. A current is never
/// reported negative, so a small one reads high under noise: those pairs are left out, chosen by the
/// instrument, which is independent of their own noise. (Pairs near 0 A made the slope 1.5 % steep on
/// average at noise 1.5-2 quanta, more at small accelerations; 0.3 A leaves 0.5 % and keeps most pairs:
/// both neighbours at 0.5 A or more dropped half of a 0.6 A cruise and raised the standard errors.)
const MIN_LOADED_DA: i32 = 3;
/// A load step needs this many pairs ...
const MIN_PAIRS: i64 = 5;
/// ... and a current change of at least 1 A (in 0.1 A).
const MIN_CURRENT_RANGE_DA: i32 = 10;
/// Below a 0.5 V swing (in 0.1 V) the 0.1 V resolution leaves the estimate a guess: not measured.
pub(super) const MIN_VOLTAGE_RANGE_DV: i32 = 5;
/// Nor when the slope's standard error is above this fraction of it (noise, not load, moved the voltage):
/// four standard errors stay within the 15 % tolerance. (At 4 %, 1 set in 20 000 of the random test's
/// ranges measured 15.1 % off on a wire, 3.9 standard errors; at 3 %, 71 in 20 000 went unmeasured with a
/// true sag of 10 noise σ, which the tests hold measurable.)
const MAX_RELATIVE_ERROR: f64 = 0.035;

/// One load step's pairs, summed in 0.1 A and 0.1 V (exact): current I, voltage V and instrument Z.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct LoadStep {
    pub pairs: i64,
    pub sum_i: i64,
    pub sum_v: i64,
    pub sum_z: i64,
    pub sum_ii: i128,
    pub sum_iv: i128,
    pub sum_vv: i128,
    pub sum_zi: i128,
    pub sum_zv: i128,
    pub sum_zz: i128,
    pub current_range: i32,
    pub voltage_range: i32,
}

/// Centred sums of products (Σ (x - x̄)(y - ȳ)) of one load step, in 0.1 A and 0.1 V.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Centred {
    zi: f64,
    zv: f64,
    zz: f64,
    ii: f64,
    iv: f64,
    vv: f64,
}

impl std::ops::Add for Centred {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self {
            zi: self.zi + other.zi,
            zv: self.zv + other.zv,
            zz: self.zz + other.zz,
            ii: self.ii + other.ii,
            iv: self.iv + other.iv,
            vv: self.vv + other.vv,
        }
    }
}

impl std::iter::Sum for Centred {
    fn sum<I: Iterator<Item = Self>>(steps: I) -> Self {
        steps.fold(Self::default(), |sum, step| sum + step)
    }
}

impl Centred {
    /// The slope of V against I (ohms, negated: the voltage drops), instrumented by Z.
    fn resistance(&self) -> f64 {
        -self.zv / self.zi
    }

    /// Σ of the squared residuals around the per-step lines of slope -`resistance`.
    fn residual(&self, resistance: f64) -> f64 {
        (self.vv + 2.0 * resistance * self.iv + resistance * resistance * self.ii).max(0.0)
    }
}

impl LoadStep {
    fn centred(&self) -> Centred {
        let n = self.pairs as f64;
        let (si, sv, sz) = (self.sum_i as f64, self.sum_v as f64, self.sum_z as f64);
        let centred = |sum: i128, a: f64, b: f64| sum as f64 - a * b / n;
        Centred {
            zi: centred(self.sum_zi, sz, si),
            zv: centred(self.sum_zv, sz, sv),
            zz: centred(self.sum_zz, sz, sz),
            ii: centred(self.sum_ii, si, si),
            iv: centred(self.sum_iv, si, sv),
            vv: centred(self.sum_vv, sv, sv),
        }
    }
}

/// The pairs around the command step at `t0`.
pub(super) fn load_step(view: &View, t0: i64) -> Option<LoadStep> {
    let mut step = LoadStep::default();
    let (mut i_range, mut v_range) = ((i32::MAX, i32::MIN), (i32::MAX, i32::MIN));
    for voltage in &view.voltage[within(view.voltage, t0 - BEFORE_US, t0 + AFTER_US, |r| r.t)] {
        let (Some((first, first_around)), Some((second, second_around))) =
            (nearest(view.currents[0], voltage.t), nearest(view.currents[1], voltage.t))
        else {
            continue;
        };
        let (current, volts) = (i64::from(first + second), i64::from(voltage.value));
        let instrument = first_around + second_around;
        step.pairs += 1;
        step.sum_i += current;
        step.sum_v += volts;
        step.sum_z += instrument;
        step.sum_ii += i128::from(current * current);
        step.sum_iv += i128::from(current * volts);
        step.sum_vv += i128::from(volts * volts);
        step.sum_zi += i128::from(instrument * current);
        step.sum_zv += i128::from(instrument * volts);
        step.sum_zz += i128::from(instrument * instrument);
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

/// The reading nearest `t` within [`PAIRING_US`], and the sum of the readings just before and after it
/// (the instrument), when both are within [`NEIGHBOUR_US`] of it and at rest or loaded ([`MIN_LOADED_DA`]).
fn nearest(readings: &[Reading], t: i64) -> Option<(i32, i64)> {
    let range = within(readings, t - PAIRING_US, t + PAIRING_US, |r| r.t);
    let index = range.min_by_key(|&n| (readings[n].t - t).abs())?;
    let (before, reading, after) =
        (readings.get(index.checked_sub(1)?)?, &readings[index], readings.get(index + 1)?);
    let near = |other: &Reading| (other.t - reading.t).abs() <= NEIGHBOUR_US;
    let at_rest = before.value == 0 && after.value == 0;
    let loaded = before.value + after.value >= 2 * MIN_LOADED_DA;
    (near(before) && near(after) && (at_rest || loaded))
        .then(|| (reading.value, i64::from(before.value) + i64::from(after.value)))
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
    let all = steps.iter().map(LoadStep::centred).sum::<Centred>();
    // V = OCV - R·I: 0.1 V per 0.1 A is ohms.
    let resistance = all.resistance();
    if resistance.is_nan() || resistance <= 0.0 || all.zi <= 0.0 {
        return not(format!("the voltage did not drop under load at {} load steps", steps.len()));
    }
    // The residual variance around the per-step lines (one mean per step and the common slope), and the
    // instrumental-variable estimate's standard error.
    let pairs: i64 = steps.iter().map(|s| s.pairs).sum();
    let freedom = (pairs - steps.len() as i64 - 1).max(1) as f64;
    let residual = all.residual(resistance) / freedom;
    let standard_error = (residual * all.zz).sqrt() / all.zi;
    if standard_error.is_nan() || standard_error > MAX_RELATIVE_ERROR * resistance {
        return not(format!(
            "{resistance:.3} Ω ± {standard_error:.3} Ω at {} load steps: the voltage noise is too large for \
             the load's sag (a standard error above {:.1} %)",
            steps.len(),
            MAX_RELATIVE_ERROR * 100.0
        ));
    }
    let per_step =
        steps.iter().map(LoadStep::centred).filter(|step| step.zi > 0.0).map(|step| step.resistance());
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
        // The first and last readings have no neighbour on one side: no instrument, no pair.
        assert_eq!((step.pairs, step.current_range, step.voltage_range), (11, 200, 20));
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
    fn noise_in_the_currents_does_not_flatten_the_slope() {
        // 0.5 Ω; each motor's true current ramps from rest up to 1 A and back (0.1 A units), the voltage
        // is exact (25.0 V less 0.5 Ω × the sum: whole 0.1 V quanta), the reported currents are off by a
        // pseudo-random -3..=3 (0.1 A), never below 0, exact at rest.
        let truth: Vec<i32> = (0..60).map(|n: i32| (n - 10).clamp(0, 10).min(60 - n)).collect();
        let voltage = readings(&truth.iter().map(|t| 250 - t).collect::<Vec<_>>());
        let mut state = 12_345_u64;
        let mut read = || {
            let values = truth.iter().map(|&t| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                if t == 0 {
                    0
                } else {
                    (t + (state >> 33) as i32 % 7 - 3).max(0)
                }
            });
            readings(&values.collect::<Vec<_>>())
        };
        let steps: Vec<LoadStep> =
            (0..8).map(|_| load_step(&view([&read(), &read()], &voltage), 300_000).unwrap()).collect();
        let all = steps.iter().map(LoadStep::centred).sum::<Centred>();
        let (least_squares, instrumented) = (-all.iv / all.ii, all.resistance());
        assert!((instrumented / 0.5 - 1.0).abs() < 0.03, "instrumented {instrumented}");
        assert!(least_squares / 0.5 - 1.0 < -0.05, "least squares {least_squares}");
    }

    #[test]
    fn a_small_current_near_zero_is_left_out_an_exact_zero_kept() {
        // Neighbours 0 and 0: at rest, kept; 1 and 2 (0.15 A on average, below 0.3 A): left out; 3 and 4
        // (0.35 A): kept.
        let current = readings(&[0, 0, 0, 1, 7, 2, 3, 9, 4, 40, 40]);
        let voltage = readings(&[250; 11]);
        let step = load_step(&view([&current, &current], &voltage), 100_000).unwrap();
        // The readings with both neighbours: 1 (0 and 0: rest) kept, 2 (0 and 1) left out, 3 (0 and 7)
        // kept, 4 (1 and 2) left out, 5 to 9 kept.
        assert_eq!(step.pairs, 7);
    }

    #[test]
    fn pairs_need_both_motors_near_in_time_and_a_current_change() {
        let current = readings(&[0, 0, 0, 0, 0, 0]);
        let voltage = readings(&[250; 6]);
        assert_eq!(load_step(&view([&current, &current], &voltage), 0), None);
        assert_eq!(load_step(&view([&current, &[]], &voltage), 0), None);
    }
}
