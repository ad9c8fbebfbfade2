//! Step responses: dead time, 10-90 % rise time and overshoot of the measured speed after a command step,
//! and the helpers the other measurements share (levels, noise-aware thresholds, motion onsets).

use super::fit::{crossing, mean_and_sigma, Line};
use super::lagged_ramp::{self, LaggedRamp, Points};
use super::sample::Motion;
use super::series::within;
use super::{Axis, StepResponse};

/// The resolution of 0x221 and the RS232 motion state: 1 mm/s, 1 mrad/s.
pub(super) const QUANTUM: f64 = 0.001;
/// The level before a step (and its noise) is measured over this long before the command frame, µs.
pub(super) const BEFORE_US: i64 = 300_000;
/// The level a step settles at is measured over this long before the command changes again, µs.
pub(super) const SETTLED_US: i64 = 300_000;
/// A trend within this many of its standard errors is noise. The error is estimated from the same 15
/// samples, so the ratio follows Student's t with 13 degrees of freedom: beyond 4 once in 660, 6 once in
/// 22 500, 8 once in 450 000 (settled 0.1 m/s probes at noise 1.8-1.9 quanta were judged still moving, so
/// no rise time: 4.2 errors in 12 000 sets, 6.07 in 20 000).
const SETTLED_ERRORS: f64 = 8.0;
/// An onset is found from at most this many samples ...
const ONSET_POINTS: usize = 3;
/// ... all within this fraction of the change (the early, nearly straight part of any response).
const ONSET_FRACTION: f64 = 0.6;
/// Motion starts at the first of this many samples in a row beyond the noise threshold: a single noisy
/// sample beyond 3 σ (one in 370) is not motion.
const PERSISTENT: usize = 3;
/// The lagged-ramp fit takes the samples from this long before the command (the level the model starts at) ...
const FIT_BEFORE_US: i64 = 60_000;
/// ... until the response reaches this fraction of the change, and this many samples more (the lag's tail).
const FIT_ARRIVED: f64 = 0.95;
const FIT_TAIL: usize = 3;

/// The measured value of `axis`, m/s or rad/s.
#[inline]
pub(super) fn value(sample: &Motion, axis: Axis) -> f64 {
    f64::from(match axis {
        Axis::Linear => sample.linear,
        Axis::Angular => sample.angular,
    }) / 1000.0
}

/// The samples of `axis` with times in `from..=to`, as (µs, value).
pub(super) fn points(
    motion: &[Motion],
    axis: Axis,
    from: i64,
    to: i64,
) -> impl Iterator<Item = (i64, f64)> + Clone + '_ {
    motion[within(motion, from, to, |m| m.t)].iter().map(move |m| (m.t, value(m, axis)))
}

/// Mean and noise (standard deviation) of `axis` over `from..=to`.
pub(super) fn level(motion: &[Motion], axis: Axis, from: i64, to: i64) -> Option<(f64, f64)> {
    mean_and_sigma(points(motion, axis, from, to).map(|(_, v)| v))
}

/// A change is motion once it exceeds two quanta and three standard deviations of the noise.
pub(super) fn threshold(sigma: f64) -> f64 {
    (2.0 * QUANTUM).max(3.0 * sigma)
}

/// The samples a response's onset was fitted to and what the joint fit made of them: kept so that the report
/// can fit its dead time again with the lag and acceleration of the larger steps of its axis (`refit.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct OnsetFit {
    /// µs of the log's clock the points' seconds count from (the command frame).
    pub t0: i64,
    pub points: Points,
    /// The size of the change (> 0), in the points' direction.
    pub change: f64,
    /// Where the dead time may lie, s after `t0`.
    pub dead_range: (f64, f64),
    pub threshold: f64,
    /// The joint fit, when it explained the samples within `threshold` (then the onset is its dead time).
    pub model: Option<LaggedRamp>,
}

/// Where a response started, µs, and the fit behind it when there was one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Onset {
    pub at: f64,
    pub fit: Option<OnsetFit>,
}

/// When the measured value started to leave `level` in `direction` after `t0` (until `end`), µs: the first
/// sample beyond the noise `threshold`, then a line through the first few moving samples extrapolated back
/// to `level` (so the 20 ms feedback period does not round the answer up), kept between `t0` and that
/// first sample.
pub(super) fn onset(
    motion: &[Motion],
    axis: Axis,
    (t0, end): (i64, i64),
    level: f64,
    (direction, change, threshold): (f64, f64, f64),
) -> Option<Onset> {
    let range = within(motion, t0 + 1, end, |m| m.t);
    let after = &motion[range.clone()];
    let beyond = |m: &Motion| direction * (value(m, axis) - level) > threshold;
    // Motion, not a noise spike: this sample and the next ones (as many as there are) beyond the threshold.
    let first = (0..after.len()).find(|&i| after[i..after.len().min(i + PERSISTENT)].iter().all(beyond))?;
    let moving = after[first..]
        .iter()
        .take(ONSET_POINTS)
        .take_while(|m| direction * (value(m, axis) - level) <= ONSET_FRACTION * change.abs())
        .count()
        .max(1);
    // One moving sample alone: the line goes through the sample before it.
    let from = if moving == 1 { (range.start + first).saturating_sub(1) } else { range.start + first };
    let fitted = motion[from..range.start + first + moving].iter().map(|m| (m.t, value(m, axis)));
    let at_first = after[first].t as f64;
    let apparent = Line::fit(fitted)
        .filter(|line| line.slope * direction > 0.0)
        .and_then(|line| line.time_at(level))
        .map_or(at_first, |t| t.clamp(t0 as f64, at_first));
    let fit = fitted_onset(motion, axis, t0, after, (level, direction, change.abs(), threshold), apparent);
    let at = fit.and_then(|fit| fit.model).map_or(apparent, |model| t0 as f64 + model.dead_s * 1e6);
    Some(Onset { at, fit })
}

/// A joint fit of dead time, lag and acceleration ([`lagged_ramp`]) to the samples from [`FIT_BEFORE_US`]
/// before `t0` until the response has nearly arrived; its model stands when it explains them within the
/// noise threshold (the residual of a fit that fits is the noise, σ, and the threshold is 3 σ measured on a
/// few samples), else (a shape it does not describe) the apparent onset does. `None`: too few samples, or
/// the response never half-way; no model when it never arrived. `after`: the samples after `t0`;
/// `apparent`: the line's onset, µs.
fn fitted_onset(
    motion: &[Motion],
    axis: Axis,
    t0: i64,
    after: &[Motion],
    (level, direction, change, threshold): (f64, f64, f64, f64),
    apparent: f64,
) -> Option<OnsetFit> {
    let seconds = |t: i64| (t - t0) as f64 / 1e6;
    let mut points = Points::default();
    let before = within(motion, t0 - FIT_BEFORE_US, t0, |m| m.t);
    let mut arrived_at = None;
    // The dead time ends before the response is half-way: the fit's bound (not the first sample beyond the
    // threshold: noise above a threshold measured on a few samples can pass it early).
    let mut half_way = None;
    let mut steepest = 0.0f64;
    let mut previous: Option<(f64, f64)> = None;
    for (index, m) in motion[before].iter().chain(after).enumerate() {
        let (s, y) = (seconds(m.t), direction * (value(m, axis) - level));
        if !points.push(s, y) || arrived_at.is_some_and(|arrived| index >= arrived + FIT_TAIL) {
            break;
        }
        if let Some((ps, py)) = previous.filter(|&(ps, _)| s > ps) {
            steepest = steepest.max((y - py) / (s - ps));
        }
        previous = Some((s, y));
        if half_way.is_none() && s > 0.0 && y >= 0.5 * change {
            half_way = Some(s);
        }
        if arrived_at.is_none() && y >= FIT_ARRIVED * change {
            arrived_at = Some(index);
        }
    }
    let dead_range = (0.0, half_way?);
    if points.as_slice().len() < 4 {
        return None;
    }
    // Only a response that arrived is fitted jointly (its end tells the lag and the acceleration apart); one
    // cut short (a robot's own stop at the end of the silence) keeps its samples for `refit.rs`.
    let model = arrived_at.and_then(|_| {
        let starts = lagged_ramp::starts((apparent - t0 as f64) / 1e6, steepest.max(change));
        let (model, rms) = lagged_ramp::fit(points.as_slice(), change, &starts, dead_range)?;
        (rms <= threshold).then_some(model)
    });
    Some(OnsetFit { t0, points, change, dead_range, threshold, model })
}

/// The response to a step of `axis` from `from` to `to` (commanded) at `t0`, held until `end`; its onset too
/// (the dead time in µs is `at - t0`: the command timeout takes it off).
pub(super) fn respond(
    motion: &[Motion],
    axis: Axis,
    (t0, end): (i64, i64),
    (from, to): (f64, f64),
) -> (StepResponse, Option<Onset>) {
    let mut response = StepResponse {
        axis,
        at_us: t0,
        from,
        to,
        dead_time_ms: None,
        rise_time_ms: None,
        overshoot_percent: None,
    };
    let (Some((before, sigma)), Some((settled, _))) =
        (level(motion, axis, t0 - BEFORE_US, t0), level(motion, axis, end - SETTLED_US, end))
    else {
        return (response, None);
    };
    let change = settled - before;
    let threshold = threshold(sigma);
    // The robot did not answer (RC override, E-stop, a wheel blocked): nothing to time.
    if change.abs() <= 2.0 * threshold {
        return (response, None);
    }
    let direction = change.signum();
    let dead = onset(motion, axis, (t0, end), before, (direction, change, threshold));
    response.dead_time_ms = dead.map(|onset| (onset.at - t0 as f64) / 1000.0);
    // Rise and overshoot are judged against where the response settled: a step cut short while still
    // changing (the robot had not reached the command yet) has neither, never a guess.
    if !settled_within(motion, axis, end, change) {
        return (response, dead);
    }
    // From the last sample before the command, so a first moving sample past 10 % is interpolated.
    let before_step = motion.partition_point(|m| m.t <= t0).saturating_sub(1);
    let after = points(motion, axis, motion[before_step].t, end);
    let t10 = crossing(after.clone(), before + 0.1 * change, direction);
    let t90 = crossing(after.clone(), before + 0.9 * change, direction);
    if let (Some(t10), Some(t90)) = (t10, t90) {
        response.rise_time_ms = Some((t90 - t10) / 1000.0);
    }
    let peak = points(motion, axis, t0 + 1, end).map(|(_, v)| direction * (v - settled)).fold(0.0, f64::max);
    response.overshoot_percent = Some(peak / change.abs() * 100.0);
    (response, dead)
}

/// Whether the response had settled by `end`: over the last [`SETTLED_US`], the trend of the samples (a
/// least-squares line) changes the value by at most 5 % of the `change`, or by no more than
/// [`SETTLED_ERRORS`] standard errors of that trend (noise alone tilts the line of a small step's few
/// samples that much).
fn settled_within(motion: &[Motion], axis: Axis, end: i64, change: f64) -> bool {
    let window = points(motion, axis, end - SETTLED_US, end);
    Line::fit(window.clone()).is_none_or(|line| {
        let trend = (line.slope * SETTLED_US as f64).abs();
        let noise = SETTLED_ERRORS * line.slope_error(window) * SETTLED_US as f64;
        trend <= (0.05 * change.abs()).max(noise)
    })
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Motion samples every 20 ms from `t0`, linear speeds in mm/s.
    pub fn linear(t0: i64, speeds: &[i32]) -> Vec<Motion> {
        speeds
            .iter()
            .enumerate()
            .map(|(n, &v)| Motion { t: t0 + n as i64 * 20_000, linear: v, angular: 0 })
            .collect()
    }

    #[test]
    fn a_step_cut_short_while_still_rising_has_a_dead_time_but_no_rise_nor_overshoot() {
        // At rest for 1 s, then a command of 1 m/s at 1 s answered by a 1 m/s² ramp that the next command
        // cuts at 0.98 m/s: before, its 300 ms "settled" level was the ramp's middle, overshoot 16 %.
        let speeds: Vec<i32> = (0..100).map(|n| if n <= 50 { 0 } else { (n - 50) * 20 }).collect();
        let motion = linear(0, &speeds);
        let (response, dead) = respond(&motion, Axis::Linear, (1_000_000, 1_980_000), (0.0, 1.0));
        assert!(dead.is_some() && response.dead_time_ms.unwrap() < 20.0, "{response:?}");
        assert_eq!((response.rise_time_ms, response.overshoot_percent), (None, None));
    }

    /// A ramp at 1 m/s² (20 mm/s per 20 ms) to 300 mm/s starting `dead_ms` after the command at 1 s.
    fn ramp(dead_ms: i64) -> Vec<Motion> {
        (0..150)
            .map(|n| {
                let t = n * 20_000;
                let moving = (t - 1_000_000 - dead_ms * 1000).max(0);
                Motion { t, linear: ((moving / 1000) as i32).min(300), angular: 0 }
            })
            .collect()
    }

    #[test]
    fn a_ramp_gives_its_dead_time_to_the_millisecond_and_its_rise() {
        for dead_ms in [0, 7, 30, 45, 100] {
            let (response, dead) = respond(&ramp(dead_ms), Axis::Linear, (1_000_000, 2_900_000), (0.0, 0.3));
            let measured = response.dead_time_ms.unwrap();
            assert!((measured - dead_ms as f64).abs() < 0.5, "{dead_ms}: {measured}");
            assert!(((dead.unwrap().at - 1_000_000.0) / 1000.0 - measured).abs() < 1e-9);
            // 10 % to 90 % of 300 mm/s at 1 m/s²: 240 ms.
            assert!((response.rise_time_ms.unwrap() - 240.0).abs() < 1e-6, "{response:?}");
            assert!(response.overshoot_percent.unwrap() < 1e-9);
        }
    }

    #[test]
    fn overshoot_is_measured_against_the_settled_speed() {
        let mut speeds = vec![0; 10];
        speeds.extend([0, 100, 200, 330, 310, 300]);
        speeds.extend([300; 60]);
        let motion = linear(0, &speeds);
        let (response, _) = respond(&motion, Axis::Linear, (200_000, motion.last().unwrap().t), (0.0, 0.3));
        assert!((response.overshoot_percent.unwrap() - 10.0).abs() < 1e-9);
        // 10 % (30 mm/s) at 206 ms, 90 % (270 mm/s) at 250.77 ms: interpolated.
        let rise = response.rise_time_ms.unwrap();
        assert!((rise - (240.0 + 70.0 / 130.0 * 20.0 - 206.0)).abs() < 1e-6, "{rise}");
    }

    #[test]
    fn a_robot_that_does_not_move_has_no_figures() {
        let motion = linear(0, &[0; 100]);
        let (response, dead) = respond(&motion, Axis::Linear, (500_000, 1_900_000), (0.0, 0.3));
        assert_eq!((response.dead_time_ms, response.rise_time_ms, dead), (None, None, None));
        assert_eq!(response.to, 0.3);
    }

    #[test]
    fn noise_before_the_step_raises_the_threshold() {
        // ±3 mm/s of noise at rest: a 4 mm/s sample is not yet motion.
        let mut speeds: Vec<i32> = (0..20).map(|n| if n % 2 == 0 { 3 } else { -3 }).collect();
        speeds.extend([4, 24, 44, 64, 84]);
        speeds.extend([100; 50]);
        let motion = linear(0, &speeds);
        let (response, _) = respond(&motion, Axis::Linear, (380_000, motion.last().unwrap().t), (0.0, 0.1));
        // The line through 24 and 44 mm/s at 420 and 440 ms (64 is past 60 % of the step) meets the rest
        // level (0) at 396 ms.
        let dead = response.dead_time_ms.unwrap();
        assert!((dead - 16.0).abs() < 1e-6, "{dead}");
    }
}
