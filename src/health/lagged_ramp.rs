//! The early response to a step as a *lagged ramp*: after a dead time `d` the drive ramps its target at an
//! acceleration `a` to the new level, and the actual speed follows that ramp through a first-order lag `τ`.
//! Fitted jointly to the samples (Levenberg-Marquardt), the model gives the dead time where a line through
//! the first moving samples cannot: a lag rounds the start of the response, so its first *measurable*
//! motion comes later than the drive's answer (up to 0.35 τ later with the lags of docs/sim.md).
//!
//! With `s` the time since the end of the dead time and `V` the change, the model is (Laplace, exact):
//! - `s ≤ 0`: 0;
//! - `0 < s ≤ s_r = V / a` (ramping): `a (s - τ (1 - e^(-s/τ)))`;
//! - `s > s_r` (the ramp at its end, the lag closing): `V - a τ (1 - e^(-s_r/τ)) e^(-(s - s_r)/τ)`.
//!
//! `τ = 0` is a plain ramp, `a → ∞` a plain lag; both are inside the family, so a robot that has only one
//! of them is fitted as well as one that has both.

/// At most this many samples are fitted (the fit runs on the stack: no allocation).
pub(super) const MAX_POINTS: usize = 96;
/// Levenberg-Marquardt iterations per start.
const ITERATIONS: usize = 40;
/// Below this time constant, s, the lag is taken as none (and the formulas' `e^(-s/τ)` as 0).
const NO_LAG_S: f64 = 1e-5;

/// The fitted parameters: seconds from the step's command, seconds, change per second².
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LaggedRamp {
    pub dead_s: f64,
    pub lag_s: f64,
    pub accel: f64,
}

/// The points to fit: (seconds since the command, the change so far in the step's direction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Points {
    items: [(f64, f64); MAX_POINTS],
    len: usize,
}

impl Default for Points {
    fn default() -> Self {
        Self { items: [(0.0, 0.0); MAX_POINTS], len: 0 }
    }
}

impl Points {
    /// Adds a point; false (and nothing added) when full.
    pub fn push(&mut self, s: f64, value: f64) -> bool {
        if self.len == MAX_POINTS {
            return false;
        }
        self.items[self.len] = (s, value);
        self.len += 1;
        true
    }

    pub fn as_slice(&self) -> &[(f64, f64)] {
        &self.items[..self.len]
    }
}

impl LaggedRamp {
    /// The model's value at `t` s after the command, for a change of `change` (> 0), and its derivatives
    /// by (dead time, lag, acceleration).
    fn value_and_gradient(&self, t: f64, change: f64) -> (f64, [f64; 3]) {
        let Self { dead_s, lag_s: tau, accel: a } = *self;
        let s = t - dead_s;
        if s <= 0.0 {
            return (0.0, [0.0; 3]);
        }
        let s_r = change / a;
        if tau < NO_LAG_S {
            // A plain ramp: the lag's derivative is its limit at 0 (while ramping, a τ of lag takes a τ off).
            return if s <= s_r { (a * s, [-a, -a, s]) } else { (change, [0.0; 3]) };
        }
        if s <= s_r {
            let e = (-s / tau).exp();
            let value = a * (s - tau * (1.0 - e));
            let d_dead = -a * (1.0 - e);
            let d_lag = -a * ((1.0 - e) - e * s / tau);
            let d_accel = s - tau * (1.0 - e);
            (value, [d_dead, d_lag, d_accel])
        } else {
            let e_r = (-s_r / tau).exp();
            let f = (-(s - s_r) / tau).exp();
            let k = a * tau * (1.0 - e_r) * f;
            let value = change - k;
            let d_dead = -a * (1.0 - e_r) * f;
            // ln k = ln a + ln τ + ln(1 - e_r) - (s - s_r)/τ, with s_r = V/a.
            let dln_lag = 1.0 / tau - e_r * s_r / (tau * tau * (1.0 - e_r)) + (s - s_r) / (tau * tau);
            let dln_accel = 1.0 / a - e_r * s_r / (a * tau * (1.0 - e_r)) - s_r / (a * tau);
            (value, [d_dead, -k * dln_lag, -k * dln_accel])
        }
    }

    /// The model's value at `t` s after the command, for a change of `change` (> 0).
    pub fn value(&self, t: f64, change: f64) -> f64 {
        self.value_and_gradient(t, change).0
    }

    fn squared_error(&self, points: &[(f64, f64)], change: f64) -> f64 {
        points.iter().map(|&(t, v)| (v - self.value(t, change)).powi(2)).sum()
    }

    /// Held within the physical: no negative lag, a positive acceleration, the dead time in `dead_range`.
    fn bounded(self, (earliest, latest): (f64, f64)) -> Self {
        Self {
            // `max`/`min`, not `clamp`: no panic on a reversed or NaN range whatever the samples.
            dead_s: self.dead_s.min(latest).max(earliest),
            lag_s: self.lag_s.clamp(0.0, 10.0),
            accel: self.accel.max(1e-6),
        }
    }
}

/// Where the fit starts: a plain ramp from the apparent onset (`apparent_s`, the line through the first moving
/// samples) at `accel`, and lags up to the longest of docs/sim.md's test range, each starting earlier as a
/// lag makes the apparent onset later. A lag seen from a start without one can sit in a local minimum.
pub(super) fn starts(apparent_s: f64, accel: f64) -> [LaggedRamp; 4] {
    [0.0, 0.03, 0.08, 0.15].map(|lag_s| LaggedRamp { dead_s: apparent_s - 0.4 * lag_s, lag_s, accel })
}

/// The best fit to `points` of a change of `change` (> 0) from the `starts`, the dead time kept within
/// `dead_range` (s), with its root-mean-square residual; `None` for fewer than 4 points.
pub(super) fn fit(
    points: &[(f64, f64)],
    change: f64,
    starts: &[LaggedRamp],
    dead_range: (f64, f64),
) -> Option<(LaggedRamp, f64)> {
    if points.len() < 4 || change <= 0.0 {
        return None;
    }
    let best = starts
        .iter()
        .map(|start| refine(points, change, start.bounded(dead_range), dead_range))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    Some((best.0, (best.1 / points.len() as f64).sqrt()))
}

/// The dead time alone, the lag and acceleration held at `shape`'s: the best `dead_s` within `dead_range`
/// for a change of `change` (> 0), and the root-mean-square residual; `None` for fewer than 4 points or an
/// empty range. With two parameters fewer the dead time is told apart where the joint fit cannot (a small
/// step's ramp ends before its lag lets the speed rise). A scan every millisecond, then a golden-section
/// search within a millisecond of the best.
pub(super) fn fit_dead_time(
    points: &[(f64, f64)],
    change: f64,
    shape: LaggedRamp,
    (earliest, latest): (f64, f64),
) -> Option<(f64, f64)> {
    // (a NaN bound is an empty range too)
    let ordered =
        matches!(earliest.partial_cmp(&latest), Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal));
    if points.len() < 4 || change <= 0.0 || !ordered || shape.accel <= 0.0 {
        return None;
    }
    let error = |dead_s: f64| LaggedRamp { dead_s, ..shape }.squared_error(points, change);
    const SCAN_S: f64 = 0.001;
    // At most 2000 evaluations: a range beyond 2 s is scanned more coarsely.
    let stride = SCAN_S.max((latest - earliest) / 2000.0);
    let mut best = (earliest, error(earliest));
    let mut dead_s = earliest;
    while dead_s < latest {
        dead_s = (dead_s + stride).min(latest);
        let candidate = error(dead_s);
        if candidate < best.1 {
            best = (dead_s, candidate);
        }
    }
    // Golden-section search: each step keeps one inner point and its error, so one evaluation a step.
    let (mut low, mut high) = ((best.0 - stride).max(earliest), (best.0 + stride).min(latest));
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (high - ratio * (high - low), low + ratio * (high - low));
    let (mut error_a, mut error_b) = (error(a), error(b));
    for _ in 0..30 {
        if error_a <= error_b {
            (high, b, error_b) = (b, a, error_a);
            a = high - ratio * (high - low);
            error_a = error(a);
        } else {
            (low, a, error_a) = (a, b, error_b);
            b = low + ratio * (high - low);
            error_b = error(b);
        }
    }
    let middle = (low + high) / 2.0;
    let error_middle = error(middle);
    let (dead_s, squared) = if error_middle < best.1 { (middle, error_middle) } else { best };
    Some((dead_s, (squared / points.len() as f64).sqrt()))
}

/// Levenberg-Marquardt from `start`: the parameters and their squared error.
fn refine(
    points: &[(f64, f64)],
    change: f64,
    start: LaggedRamp,
    dead_range: (f64, f64),
) -> (LaggedRamp, f64) {
    let mut current = start;
    let mut error = current.squared_error(points, change);
    let mut damping = 1e-3;
    for _ in 0..ITERATIONS {
        // The normal equations JᵀJ δ = Jᵀr, r = observed - model.
        let mut jtj = [[0.0; 3]; 3];
        let mut jtr = [0.0; 3];
        for &(t, v) in points {
            let (value, gradient) = current.value_and_gradient(t, change);
            let residual = v - value;
            for row in 0..3 {
                jtr[row] += gradient[row] * residual;
                for column in 0..3 {
                    jtj[row][column] += gradient[row] * gradient[column];
                }
            }
        }
        let mut improved = false;
        while damping < 1e9 {
            let mut damped = jtj;
            for (index, row) in damped.iter_mut().enumerate() {
                row[index] += damping * jtj[index][index].max(1e-12);
            }
            let Some(step) = solve(damped, jtr) else { break };
            let candidate = LaggedRamp {
                dead_s: current.dead_s + step[0],
                lag_s: current.lag_s + step[1],
                accel: current.accel + step[2],
            }
            .bounded(dead_range);
            let candidate_error = candidate.squared_error(points, change);
            if candidate_error < error {
                let gain = error - candidate_error;
                current = candidate;
                error = candidate_error;
                damping = (damping / 3.0).max(1e-9);
                improved = gain > 1e-12 * error.max(1e-18);
                break;
            }
            damping *= 4.0;
        }
        if !improved {
            break;
        }
    }
    (current, error)
}

/// `matrix x = rhs` by Cramer's rule; `None` when singular.
fn solve(matrix: [[f64; 3]; 3], rhs: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let whole = det(matrix);
    if !whole.is_normal() {
        return None;
    }
    let mut x = [0.0; 3];
    for (column, out) in x.iter_mut().enumerate() {
        let mut replaced = matrix;
        for row in 0..3 {
            replaced[row][column] = rhs[row];
        }
        *out = det(replaced) / whole;
    }
    x.iter().all(|value| value.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The model sampled every 20 ms from `from` s, rounded to `quantum`.
    fn sampled(truth: LaggedRamp, change: f64, from: f64, count: usize, quantum: f64) -> Vec<(f64, f64)> {
        (0..count)
            .map(|n| {
                let t = from + n as f64 * 0.02;
                (t, (truth.value(t, change) / quantum).round() * quantum)
            })
            .collect()
    }

    #[test]
    fn the_gradient_is_the_models_slope() {
        for truth in [
            LaggedRamp { dead_s: 0.05, lag_s: 0.08, accel: 1.0 },
            LaggedRamp { dead_s: 0.0, lag_s: 0.15, accel: 4.0 },
        ] {
            for t in [0.06, 0.1, 0.2, 0.3, 0.45, 0.8] {
                let (_, gradient) = truth.value_and_gradient(t, 0.3);
                let h = 1e-7;
                let moved = |index: usize| {
                    let mut plus = truth;
                    let mut minus = truth;
                    match index {
                        0 => (plus.dead_s += h, minus.dead_s -= h),
                        1 => (plus.lag_s += h, minus.lag_s -= h),
                        _ => (plus.accel += h, minus.accel -= h),
                    };
                    (plus.value(t, 0.3) - minus.value(t, 0.3)) / (2.0 * h)
                };
                for (index, &analytic) in gradient.iter().enumerate() {
                    let numeric = moved(index);
                    assert!(
                        (analytic - numeric).abs() < 1e-5,
                        "{truth:?} t {t} #{index}: {analytic} {numeric}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_lagged_ramp_is_fitted_to_the_millisecond_from_rounded_samples() {
        for (dead_s, lag_s, accel) in [(0.05, 0.1, 1.0), (0.12, 0.15, 0.5), (0.0, 0.04, 2.0), (0.2, 0.0, 1.0)]
        {
            let truth = LaggedRamp { dead_s, lag_s, accel };
            let points = sampled(truth, 0.3, -0.1, 40, 0.001);
            let (fitted, rms) = fit(&points, 0.3, &starts(dead_s + 0.3 * lag_s, 0.8), (0.0, 0.4)).unwrap();
            assert!((fitted.dead_s - dead_s).abs() < 0.004, "{truth:?}: {fitted:?}");
            assert!((fitted.lag_s - lag_s).abs() < 0.01, "{truth:?}: {fitted:?}");
            assert!(rms < 0.0006, "{rms}");
        }
    }

    #[test]
    fn with_the_lag_and_acceleration_known_the_dead_time_of_a_small_noisy_step_is_found() {
        // A 0.1 step whose ramp (at 3 per s²) ends in 33 ms, under a lag of 130 ms: the joint fit can trade
        // a later start for a faster ramp; with the shape held, the dead time is one parameter.
        let truth = LaggedRamp { dead_s: 0.06, lag_s: 0.13, accel: 3.0 };
        let mut noise = 0x2545_f491_4f6c_dd1d_u64;
        let points: Vec<(f64, f64)> = sampled(truth, 0.1, -0.06, 30, 0.001)
            .into_iter()
            .map(|(t, v)| {
                noise ^= noise << 13;
                noise ^= noise >> 7;
                noise ^= noise << 17;
                (t, v + ((noise % 5) as f64 - 2.0) * 0.001)
            })
            .collect();
        let (dead_s, rms) = fit_dead_time(&points, 0.1, truth, (0.0, 0.2)).unwrap();
        assert!((dead_s - 0.06).abs() < 0.005, "{dead_s}");
        assert!(rms < 0.002, "{rms}");
        // Exact samples: to the tenth of a millisecond.
        let exact = sampled(truth, 0.1, -0.06, 30, 1e-9);
        let (dead_s, _) = fit_dead_time(&exact, 0.1, truth, (0.0, 0.2)).unwrap();
        assert!((dead_s - 0.06).abs() < 1e-4, "{dead_s}");
    }

    #[test]
    fn the_dead_time_alone_needs_points_and_a_range() {
        let shape = LaggedRamp { dead_s: 0.0, lag_s: 0.05, accel: 1.0 };
        assert_eq!(fit_dead_time(&[(0.0, 0.0); 3], 0.1, shape, (0.0, 1.0)), None);
        assert_eq!(fit_dead_time(&[(0.0, 0.0); 8], 0.1, shape, (0.2, 0.1)), None);
        assert_eq!(fit_dead_time(&[(0.0, 0.0); 8], 0.1, shape, (f64::NAN, 0.1)), None);
        assert_eq!(fit_dead_time(&[(0.0, 0.0); 8], 0.0, shape, (0.0, 0.1)), None);
        let huge = fit_dead_time(&[(0.0, 0.0); 8], 0.1, shape, (0.0, 1e300)).unwrap();
        assert!(huge.0.is_finite());
    }

    #[test]
    fn a_reversed_dead_time_range_is_no_panic() {
        let points = sampled(LaggedRamp { dead_s: 0.05, lag_s: 0.02, accel: 1.0 }, 0.3, -0.06, 20, 0.001);
        let (fitted, _) = fit(&points, 0.3, &starts(0.05, 1.0), (0.0, -0.02)).unwrap();
        assert!(fitted.dead_s.is_finite());
    }

    #[test]
    fn too_few_points_or_no_change_fit_nothing() {
        let starts = [LaggedRamp { dead_s: 0.0, lag_s: 0.0, accel: 1.0 }];
        assert_eq!(fit(&[(0.0, 0.0); 3], 0.3, &starts, (0.0, 1.0)), None);
        assert_eq!(fit(&[(0.0, 0.0); 8], 0.0, &starts, (0.0, 1.0)), None);
    }
}
