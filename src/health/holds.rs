//! Held straight and spin commands, once the speed has settled: wheel odometers against the integrated
//! 0x221 motion, summed in the wire's integers (exact in any order, so chunks of a log add up exactly).
//! Symmetry and geometry are read from the sums.

use super::sample::{Motion, Odometer};
use super::series::within;
use super::steps::{level, threshold, value, SETTLED_US};
use super::{Axis, Geometry, Symmetry};

/// The speed has settled once it stays within this fraction of the settled level (or the noise).
const SETTLED_FRACTION: f64 = 0.05;

/// Sums over the settled parts of holds. Integrals are "doubled trapezoids": Σ (v_i + v_i+1) × Δt in
/// mm/s·µs (mrad/s·µs), so they stay integers.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct HoldSums {
    pub straight_holds: u64,
    /// |Δ left| and |Δ right| odometer, mm, over straight holds.
    pub left_mm: i64,
    pub right_mm: i64,
    /// |∫ linear| over the same odometer readings' span.
    pub odometer_travel: i128,
    /// Over the whole settled part: |∫ linear| and ∫ angular signed by the direction of travel.
    pub travel: i128,
    pub heading: i128,
    pub spins: u64,
    /// (Δ right - Δ left) signed by the turn, mm, and |∫ angular| over the same span.
    pub spin_difference_mm: i64,
    pub spin_turn: i128,
}

impl HoldSums {
    pub fn absorb(&mut self, later: &Self) {
        self.straight_holds += later.straight_holds;
        self.left_mm += later.left_mm;
        self.right_mm += later.right_mm;
        self.odometer_travel += later.odometer_travel;
        self.travel += later.travel;
        self.heading += later.heading;
        self.spins += later.spins;
        self.spin_difference_mm += later.spin_difference_mm;
        self.spin_turn += later.spin_turn;
    }

    /// A straight hold (angular command 0) from `t0` to `end`.
    pub fn straight(&mut self, motion: &[Motion], odometry: &[Odometer], t0: i64, end: i64) {
        let Some(from) = settled_from(motion, Axis::Linear, t0, end) else { return };
        let travel = integral(motion, Axis::Linear, from, end);
        if travel == 0 {
            return;
        }
        let direction = travel.signum();
        self.straight_holds += 1;
        self.travel += travel.abs();
        self.heading += direction * integral(motion, Axis::Angular, from, end);
        if let Some((first, last)) = span(odometry, from, end) {
            self.left_mm += (last.left - first.left).abs();
            self.right_mm += (last.right - first.right).abs();
            self.odometer_travel += integral(motion, Axis::Linear, first.t, last.t).abs();
        }
    }

    /// A spin (linear command 0) from `t0` to `end`.
    pub fn spin(&mut self, motion: &[Motion], odometry: &[Odometer], t0: i64, end: i64) {
        let Some(from) = settled_from(motion, Axis::Angular, t0, end) else { return };
        let Some((first, last)) = span(odometry, from, end) else { return };
        let turn = integral(motion, Axis::Angular, first.t, last.t);
        if turn == 0 {
            return;
        }
        self.spins += 1;
        let difference = (last.right - first.right) - (last.left - first.left);
        self.spin_difference_mm += difference * turn.signum() as i64;
        self.spin_turn += turn.abs();
    }

    pub fn symmetry(&self) -> Option<Symmetry> {
        if self.right_mm == 0 || self.travel == 0 {
            return None;
        }
        let heading_rad_per_m = self.heading as f64 / self.travel as f64;
        Some(Symmetry {
            left_right_gain_ratio: self.left_mm as f64 / self.right_mm as f64,
            left_m: self.left_mm as f64 / 1000.0,
            right_m: self.right_mm as f64 / 1000.0,
            heading_drift_deg_per_m: heading_rad_per_m.to_degrees(),
        })
    }

    pub fn geometry(&self) -> Geometry {
        // mm over mm/s·µs (doubled): × 2e6 / 1000 → m per m.
        let odometer_scale = (self.odometer_travel > 0)
            .then(|| (self.left_mm + self.right_mm) as f64 / 2.0 / (self.odometer_travel as f64 / 2e6));
        // mm over mrad/s·µs (doubled): the turn in rad is spin_turn / 2e9.
        let track_width_m = (self.spins > 0 && self.spin_turn > 0).then(|| {
            let track = self.spin_difference_mm as f64 / 1000.0 / (self.spin_turn as f64 / 2e9);
            track / odometer_scale.unwrap_or(1.0)
        });
        Geometry { track_width_m, odometer_scale }
    }
}

/// From when the speed of `axis` stays settled until `end`: the latest sample outside the band around the
/// level of the hold's end, plus one.
pub(super) fn settled_from(motion: &[Motion], axis: Axis, t0: i64, end: i64) -> Option<i64> {
    let (settled, sigma) = level(motion, axis, end - SETTLED_US, end)?;
    let band = (SETTLED_FRACTION * settled.abs()).max(threshold(sigma));
    let hold = &motion[within(motion, t0 + 1, end, |m| m.t)];
    let outside = hold.iter().rposition(|m| (value(m, axis) - settled).abs() > band);
    let first = outside.map_or(0, |index| index + 1);
    // At least a settled quarter of the hold, or nothing to measure.
    let from = hold.get(first)?.t;
    (end - from >= (end - t0) / 4).then_some(from)
}

/// The first and last odometer readings within `from..=to`, if two distinct ones.
fn span(odometry: &[Odometer], from: i64, to: i64) -> Option<(Odometer, Odometer)> {
    let readings = &odometry[within(odometry, from, to, |o| o.t)];
    let (first, last) = (*readings.first()?, *readings.last()?);
    (last.t > first.t).then_some((first, last))
}

/// The doubled trapezoid integral of `axis` (raw units × µs) over the samples within `from..=to`.
fn integral(motion: &[Motion], axis: Axis, from: i64, to: i64) -> i128 {
    let raw = |m: &Motion| i128::from(if axis == Axis::Linear { m.linear } else { m.angular });
    motion[within(motion, from, to, |m| m.t)]
        .windows(2)
        .map(|pair| (raw(&pair[0]) + raw(&pair[1])) * i128::from(pair[1].t - pair[0].t))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(linear: i32, angular: i32, until_ms: i64) -> Vec<Motion> {
        (0..=until_ms / 20).map(|n| Motion { t: n * 20_000, linear, angular }).collect()
    }

    fn odometry(left_per_step: i64, right_per_step: i64, until_ms: i64) -> Vec<Odometer> {
        (0..=until_ms / 20)
            .map(|n| Odometer { t: n * 20_000, left: n * left_per_step, right: n * right_per_step })
            .collect()
    }

    #[test]
    fn a_straight_hold_gives_the_gain_ratio_drift_and_odometer_scale() {
        let mut sums = HoldSums::default();
        // 5 m/s for 2 s with 10 mrad/s of turn; odometers 99 and 101 mm per 20 ms (scale 1.0).
        sums.straight(&motion(5000, 10, 2000), &odometry(99, 101, 2000), 0, 2_000_000);
        let symmetry = sums.symmetry().unwrap();
        assert!((symmetry.left_right_gain_ratio - 99.0 / 101.0).abs() < 1e-12);
        // 0.01 rad per 5 m.
        assert!((symmetry.heading_drift_deg_per_m - 0.002f64.to_degrees()).abs() < 1e-9, "{symmetry:?}");
        // Odometers 0.5 × (99 + 101) mm per 20 ms over 100 mm per 20 ms of 0x221.
        let scale = sums.geometry().odometer_scale.unwrap();
        assert!((scale - 1.0).abs() < 1e-12, "{scale}");
        // Backwards with the same turn: the heading drift per metre changes sign.
        let mut back = HoldSums::default();
        back.straight(&motion(-5000, 10, 2000), &odometry(-99, -101, 2000), 0, 2_000_000);
        assert!((back.symmetry().unwrap().heading_drift_deg_per_m + 0.002f64.to_degrees()).abs() < 1e-9);
    }

    #[test]
    fn a_spin_gives_the_track_width_corrected_by_the_odometer_scale() {
        let mut sums = HoldSums::default();
        // 0.5 rad/s: 10 mrad per 20 ms, and the wheels ∓2 mm per 20 ms: a 0.4 m track.
        sums.spin(&motion(0, 500, 3000), &odometry(-2, 2, 3000), 0, 3_000_000);
        assert!((sums.geometry().track_width_m.unwrap() - 0.4).abs() < 1e-12);
        // Odometers reading twice the 0x221 distance: the track is half of what they say.
        sums.left_mm = 2000;
        sums.right_mm = 2000;
        sums.odometer_travel = 2_000_000_000; // 1 m of 0x221, doubled
        assert!((sums.geometry().odometer_scale.unwrap() - 2.0).abs() < 1e-12);
        assert!((sums.geometry().track_width_m.unwrap() - 0.2).abs() < 1e-12);
    }

    #[test]
    fn the_rise_is_left_out_of_the_settled_part() {
        let mut samples = motion(300, 0, 2000);
        for (n, sample) in samples.iter_mut().take(15).enumerate() {
            sample.linear = 20 * n as i32;
        }
        // 0, 20, ..., 280 up to 280 ms, 300 from 300 ms: within 5 % (285) from 300 ms.
        assert_eq!(settled_from(&samples, Axis::Linear, 0, 2_000_000), Some(300_000));
    }
}
