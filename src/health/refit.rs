//! The report's second look at every onset. A joint fit of dead time, lag and acceleration to one step's
//! samples can trade a later start for a faster ramp within the noise: a step below [`LARGE_STEP`] reaches
//! its level by a ramp of a period or two before a lag lets the speed rise, and a slow ramp (0.5 m/s²) rounds
//! its start by less than the noise. The larger steps of an axis tell the lag and the acceleration apart
//! together: the medians of the joint fits of its first [`SHAPE_STEPS`] steps of at least [`LARGE_STEP`] are
//! the axis's *shape*. With it held, every step's dead time (and the onset of the robot's own stop when
//! commands cease) is a fit of one parameter. It stands when it explains the samples within their noise
//! threshold, as the joint fit must; otherwise the first figure does.
//!
//! Done on the merged findings, when the report is made: every step of the run is known then, whichever
//! chunk of a log (`decode -jN`) held it. The analysis keeps it up to date as steps come ([`keep_up`]), so
//! that a live view, which asks for a report every second, finds it done: a result is reused only while the
//! shape it was fitted with is the report's, so the report is the same either way. Only the first
//! [`SHAPE_STEPS`] large steps of an axis move its shape, so each step is fitted at most that many times
//! more, however long the log.

use super::lagged_ramp::{fit_dead_time, LaggedRamp};
use super::steps::{Onset, OnsetFit};
use super::{Axis, CommandTimeout, StepResponse};

/// Steps of at least this (m/s, rad/s) give the shape.
pub(super) const LARGE_STEP: f64 = 0.2;
/// The shape is the medians of this many large steps of the axis, the first ones.
pub(super) const SHAPE_STEPS: usize = 9;

/// What the findings keep of a step's onset: the joint model of a large step (its lag and acceleration),
/// and the samples of every step.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct StepFit {
    pub model: Option<LaggedRamp>,
    /// On the heap: 1.5 KB of samples a step (at most `MAX_LISTED` steps are kept).
    pub onset: Option<Box<Refitted>>,
}

/// A step's samples, and its dead time (s) as last fitted with the shape beside it.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Refitted {
    pub fit: OnsetFit,
    pub fitted: Option<(LaggedRamp, Option<f64>)>,
}

impl StepFit {
    pub fn of(onset: Option<&Onset>, size: f64) -> Self {
        let fit = onset.and_then(|onset| onset.fit);
        Self {
            model: fit.and_then(|fit| fit.model).filter(|_| size.abs() >= LARGE_STEP),
            onset: fit.map(|fit| Box::new(Refitted { fit, fitted: None })),
        }
    }
}

impl Refitted {
    /// The dead time with `shape`: the one fitted before when it was fitted with this shape.
    fn dead_time(&self, shape: LaggedRamp) -> Option<f64> {
        match self.fitted {
            Some((used, dead_s)) if used == shape => dead_s,
            _ => dead_time(&self.fit, shape),
        }
    }
}

/// After a step was listed last in `steps` (and its fit in `fits`): fits the steps of its axis with the
/// shape as it now is, so the report finds them done. One of the first large steps may change the shape:
/// every step of the axis whose fit used another is fitted again; any other step: itself.
pub(super) fn keep_up(steps: &[StepResponse], fits: &mut [StepFit]) {
    let Some(axis) = steps.last().map(|step| step.axis) else { return };
    let Some(shape) = shape(steps, fits, axis) else { return };
    for (step, fit) in steps.iter().zip(fits.iter_mut()) {
        let Some(onset) = fit.onset.as_deref_mut().filter(|_| step.axis == axis) else { continue };
        if onset.fitted.is_none_or(|(used, _)| used != shape) {
            onset.fitted = Some((shape, dead_time(&onset.fit, shape)));
        }
    }
}

/// The command timeout as found, with what fitting it again needs.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TimeoutFound {
    pub figure: CommandTimeout,
    pub axis: Axis,
    /// The samples of the robot's own stop.
    pub stop: Option<Box<OnsetFit>>,
    /// The step whose dead time was taken off: its command frame, µs, and that dead time, µs.
    pub step_at: Option<i64>,
    pub dead_us: Option<f64>,
}

impl TimeoutFound {
    pub fn new(figure: CommandTimeout, axis: Axis, stop: &Onset, step: Option<(i64, f64)>) -> Self {
        let stop = stop.fit.map(Box::new);
        Self { figure, axis, stop, step_at: step.map(|(at, _)| at), dead_us: step.map(|(_, dead)| dead) }
    }
}

/// The middle value (the mean of the two middle ones for an even count); `None` for none.
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let count = values.len();
    match count {
        0 => None,
        _ if count % 2 == 1 => Some(values[count / 2]),
        _ => Some((values[count / 2 - 1] + values[count / 2]) / 2.0),
    }
}

/// The lag and acceleration of an axis: the medians of the joint fits of its first [`SHAPE_STEPS`] large
/// steps.
fn shape(steps: &[StepResponse], fits: &[StepFit], axis: Axis) -> Option<LaggedRamp> {
    let models = || {
        steps
            .iter()
            .zip(fits)
            .filter(|(step, _)| step.axis == axis)
            .filter_map(|(_, fit)| fit.model)
            .take(SHAPE_STEPS)
    };
    Some(LaggedRamp {
        dead_s: 0.0,
        lag_s: median(models().map(|model| model.lag_s).collect())?,
        accel: median(models().map(|model| model.accel).collect())?,
    })
}

/// The dead time of `fit` with `shape` held, s after its command; `None` when that does not explain the
/// samples within their noise threshold.
fn dead_time(fit: &OnsetFit, shape: LaggedRamp) -> Option<f64> {
    let (dead_s, rms) = fit_dead_time(fit.points.as_slice(), fit.change, shape, fit.dead_range)?;
    (rms <= fit.threshold).then_some(dead_s)
}

/// The steps with their dead times fitted again, and the command timeout with its stop's onset and its
/// step's dead time fitted again.
pub(super) fn refit(
    steps: &[StepResponse],
    fits: &[StepFit],
    timeout: Option<&TimeoutFound>,
) -> (Vec<StepResponse>, Option<CommandTimeout>) {
    let shapes = [Axis::Linear, Axis::Angular].map(|axis| shape(steps, fits, axis));
    let shape_of = |axis: Axis| shapes[usize::from(axis == Axis::Angular)];
    let mut refitted = steps.to_vec();
    for (step, fit) in refitted.iter_mut().zip(fits) {
        let (Some(onset), Some(shape)) = (&fit.onset, shape_of(step.axis)) else { continue };
        if let Some(dead_s) = onset.dead_time(shape) {
            step.dead_time_ms = Some(dead_s * 1000.0);
        }
    }
    let timeout = timeout.map(|found| {
        let mut figure = found.figure.clone();
        let shape = shape_of(found.axis);
        let stop = found
            .stop
            .as_deref()
            .zip(shape)
            .and_then(|(fit, shape)| dead_time(fit, shape).map(|dead_s| fit.t0 as f64 + dead_s * 1e6));
        if let Some(stop) = stop {
            let step =
                found.step_at.and_then(|at| refitted.iter().find(|s| s.at_us == at && s.axis == found.axis));
            let dead_us = step.and_then(|s| s.dead_time_ms).map(|ms| ms * 1000.0).or(found.dead_us);
            figure.timeout_ms = (stop - figure.last_command_us as f64 - dead_us.unwrap_or(0.0)) / 1000.0;
        }
        figure
    });
    (refitted, timeout)
}

#[cfg(test)]
mod tests {
    use super::super::lagged_ramp::Points;
    use super::*;

    fn step(axis: Axis, at_us: i64, size: f64, dead_ms: f64) -> StepResponse {
        StepResponse {
            axis,
            at_us,
            from: 0.0,
            to: size,
            dead_time_ms: Some(dead_ms),
            rise_time_ms: None,
            overshoot_percent: None,
        }
    }

    /// A step's samples every 20 ms from 60 ms before its command, from `truth`, as many as fit.
    fn samples(t0: i64, truth: LaggedRamp, change: f64) -> OnsetFit {
        let mut points = Points::default();
        for n in 0..96 {
            let s = -0.06 + n as f64 * 0.02;
            points.push(s, (truth.value(s, change) / 0.001).round() * 0.001);
        }
        OnsetFit { t0, points, change, dead_range: (0.0, 0.25), threshold: 0.002, model: None }
    }

    const TRUTH: LaggedRamp = LaggedRamp { dead_s: 0.05, lag_s: 0.12, accel: 3.0 };

    /// A step at `t0` from [`TRUTH`] of `change`, not yet fitted again; a large one with `model` as its
    /// joint fit.
    fn fitted_step(t0: i64, change: f64, model: Option<LaggedRamp>) -> StepFit {
        let fit = samples(t0, TRUTH, change);
        StepFit { model, onset: Some(Box::new(Refitted { fit, fitted: None })) }
    }

    /// A small (0.1) step at `t0` from [`TRUTH`], not yet fitted again.
    fn small_step(t0: i64) -> StepFit {
        fitted_step(t0, 0.1, None)
    }

    /// A large step's joint fit alone (no samples kept).
    fn model_only(model: LaggedRamp) -> StepFit {
        StepFit { model: Some(model), onset: None }
    }

    #[test]
    fn the_analysis_keeps_the_steps_fitted_and_the_report_reuses_it_while_the_shape_holds() {
        let mut steps = vec![step(Axis::Linear, 1_000_000, 0.1, 81.0)];
        let mut fits = vec![small_step(1_000_000)];
        // No large step yet: nothing to fit with.
        keep_up(&steps, &mut fits);
        assert_eq!(fits[0].onset.as_ref().unwrap().fitted, None);
        steps.push(step(Axis::Linear, 3_000_000, 0.3, 50.0));
        fits.push(model_only(TRUTH));
        keep_up(&steps, &mut fits);
        let (used, dead_s) = fits[0].onset.as_ref().unwrap().fitted.unwrap();
        assert_eq!(used, LaggedRamp { dead_s: 0.0, ..TRUTH });
        assert!((dead_s.unwrap() - 0.05).abs() < 0.001, "{dead_s:?}");
        // The report takes what was fitted with its shape (shown by planting another value) ...
        fits[0].onset.as_mut().unwrap().fitted = Some((used, Some(0.123)));
        assert_eq!(refit(&steps, &fits, None).0[0].dead_time_ms, Some(123.0));
        // ... and fits again when the shape has changed since (another large step moved the medians).
        steps.push(step(Axis::Linear, 5_000_000, -0.3, 50.0));
        fits.push(model_only(LaggedRamp { lag_s: 0.14, ..TRUTH }));
        let dead = refit(&steps, &fits, None).0[0].dead_time_ms.unwrap();
        assert!((dead - 123.0).abs() > 1.0 && (dead - 50.0).abs() < 10.0, "{dead}");
        keep_up(&steps, &mut fits);
        assert_eq!(refit(&steps, &fits, None).0[0].dead_time_ms, Some(dead));
    }

    #[test]
    fn a_small_step_takes_the_lag_and_acceleration_of_the_large_ones_of_its_axis() {
        let steps = [
            step(Axis::Linear, 1_000_000, 0.3, 50.0),
            step(Axis::Angular, 3_000_000, 0.5, 40.0),
            step(Axis::Linear, 5_000_000, 0.1, 81.0),
        ];
        let fits = [
            model_only(TRUTH),
            // The angular axis's shape is another: it must not be used for a linear step.
            model_only(LaggedRamp { dead_s: 0.04, lag_s: 0.0, accel: 20.0 }),
            small_step(5_000_000),
        ];
        let (refitted, _) = refit(&steps, &fits, None);
        let dead = refitted[2].dead_time_ms.unwrap();
        assert!((dead - 50.0).abs() < 1.0, "{dead}");
        assert_eq!(refitted[..2], steps[..2]);
    }

    /// Two large steps whose joint fits traded the lag for the dead time, each its own way (a slow ramp
    /// rounds its start by less than the noise): with the medians of the two held, both are timed again.
    #[test]
    fn a_large_step_is_fitted_again_with_the_shape_of_its_axis() {
        let steps = [step(Axis::Linear, 1_000_000, 0.3, 70.0), step(Axis::Linear, 5_000_000, -0.3, 30.0)];
        let fits = [
            fitted_step(1_000_000, 0.3, Some(LaggedRamp { dead_s: 0.07, lag_s: 0.10, ..TRUTH })),
            fitted_step(5_000_000, 0.3, Some(LaggedRamp { dead_s: 0.03, lag_s: 0.14, ..TRUTH })),
        ];
        let (refitted, _) = refit(&steps, &fits, None);
        for step in &refitted {
            let dead = step.dead_time_ms.unwrap();
            assert!((dead - 50.0).abs() < 1.0, "{dead}");
        }
    }

    #[test]
    fn only_the_first_large_steps_of_an_axis_make_its_shape() {
        let mut steps = Vec::new();
        let mut fits = Vec::new();
        for n in 0..SHAPE_STEPS as i64 {
            steps.push(step(Axis::Linear, n * 3_000_000, 0.3, 50.0));
            fits.push(fitted_step(n * 3_000_000, 0.3, Some(TRUTH)));
            keep_up(&steps, &mut fits);
        }
        let shape = LaggedRamp { dead_s: 0.0, ..TRUTH };
        assert!(fits.iter().all(|fit| fit.onset.as_ref().unwrap().fitted.unwrap().0 == shape));
        // Two more, far from the others: the shape stays (each is fitted with it, nothing else again).
        for n in 0..2 {
            let at = (SHAPE_STEPS as i64 + n) * 3_000_000;
            steps.push(step(Axis::Linear, at, 0.3, 50.0));
            fits.push(fitted_step(at, 0.3, Some(LaggedRamp { lag_s: 0.5, accel: 0.5, ..TRUTH })));
            keep_up(&steps, &mut fits);
        }
        assert!(fits.iter().all(|fit| fit.onset.as_ref().unwrap().fitted.unwrap().0 == shape));
        let (refitted, _) = refit(&steps, &fits, None);
        assert!(refitted.iter().all(|step| (step.dead_time_ms.unwrap() - 50.0).abs() < 1.0));
    }

    #[test]
    fn without_a_large_step_or_a_fit_that_explains_the_samples_the_first_figure_stands() {
        let small = step(Axis::Linear, 5_000_000, 0.1, 81.0);
        let fit = small_step(5_000_000);
        let (alone, _) = refit(std::slice::from_ref(&small), std::slice::from_ref(&fit), None);
        assert_eq!(alone[0].dead_time_ms, Some(81.0));
        // A shape far from the samples' (no lag, a slow ramp): the residual is beyond the threshold.
        let large = step(Axis::Linear, 1_000_000, 0.3, 50.0);
        let wrong = model_only(LaggedRamp { dead_s: 0.0, lag_s: 0.0, accel: 0.2 });
        let (refitted, _) = refit(&[large, small], &[wrong, fit], None);
        assert_eq!(refitted[1].dead_time_ms, Some(81.0));
    }

    #[test]
    fn the_timeout_takes_its_stop_and_its_step_fitted_again() {
        let steps = [step(Axis::Linear, 1_000_000, 0.3, 50.0), step(Axis::Linear, 5_000_000, 0.1, 81.0)];
        let fits = [model_only(TRUTH), small_step(5_000_000)];
        // Commands ceased at 6.5 s; the robot's own stop began 550 ms later (500 ms timeout + 50 ms dead).
        let stop = samples(6_500_000, LaggedRamp { dead_s: 0.55, ..TRUTH }, 0.1);
        let found = TimeoutFound {
            figure: CommandTimeout { last_command_us: 6_500_000, timeout_ms: 470.0 },
            axis: Axis::Linear,
            stop: Some(Box::new(OnsetFit { dead_range: (0.0, 0.8), ..stop })),
            step_at: Some(5_000_000),
            dead_us: Some(81_000.0),
        };
        let (_, timeout) = refit(&steps, &fits, Some(&found));
        let timeout = timeout.unwrap();
        assert!((timeout.timeout_ms - 500.0).abs() < 2.0, "{timeout:?}");
        assert_eq!(timeout.last_command_us, 6_500_000);
        // No shape: as found.
        let (_, as_found) = refit(&steps[1..], &fits[1..], Some(&found));
        assert_eq!(as_found.unwrap().timeout_ms, 470.0);
    }

    #[test]
    fn every_step_keeps_its_samples_and_only_a_large_one_its_model() {
        let fit = samples(0, TRUTH, 0.3);
        let onset = Onset { at: 50_000.0, fit: Some(OnsetFit { model: Some(TRUTH), ..fit }) };
        let large = StepFit::of(Some(&onset), -0.3);
        assert_eq!((large.model, large.onset.map(|kept| kept.fit.t0)), (Some(TRUTH), Some(0)));
        let small = StepFit::of(Some(&onset), 0.1);
        assert_eq!((small.model, small.onset.map(|kept| kept.fit.t0)), (None, Some(0)));
        assert_eq!(StepFit::of(None, 0.1), StepFit::default());
    }
}
