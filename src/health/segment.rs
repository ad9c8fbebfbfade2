//! One stretch of a run between rests, analysed at once: its command frames are cut into runs of one
//! value, and each run is judged: a step, a stop, a straight or spin hold, commands ceasing, a load step.

use super::battery::{load_step, LoadStep};
use super::braking::brake;
use super::fit::median;
use super::holds::HoldSums;
use super::refit::{keep_up, StepFit, TimeoutFound};
use super::sample::Command;
use super::series::View;
use super::steps::respond;
use super::timeout::timeout;
use super::{Axis, Braking, StepResponse};

/// A command value must be held this long to be a step (its response has to settle), µs.
pub(super) const HOLD_US: i64 = 1_000_000;
/// Smaller command changes are not steps: m/s (linear), rad/s (angular).
const MIN_STEP: f64 = 0.05;
/// Commands may have ceased after a gap of more than this many command periods ...
const SILENT_PERIODS: i64 = 3;
/// ... and never less than this, µs. They have when the robot stopped by itself in the gap, or ...
const MIN_SILENCE_US: i64 = 60_000;
/// ... whatever it did, after a gap this long (the documented command timeout), µs. A sender starved of the
/// CPU leaves gaps of a few hundred ms that the robot drives through: the run goes on.
const CEASED_US: i64 = 500_000;
/// At most this many steps and stops are listed; the rest are counted.
pub(super) const MAX_LISTED: usize = 1000;

/// A list that keeps its first [`MAX_LISTED`] items and counts the rest.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Capped<T> {
    pub items: Vec<T>,
    pub not_listed: u64,
}

impl<T> Default for Capped<T> {
    fn default() -> Self {
        Self { items: Vec::new(), not_listed: 0 }
    }
}

impl<T: Clone> Capped<T> {
    pub fn push(&mut self, item: T) {
        if self.items.len() < MAX_LISTED {
            self.items.push(item);
        } else {
            self.not_listed += 1;
        }
    }

    /// `later`'s items after these, as if pushed one by one.
    pub fn absorb(&mut self, later: &Self) {
        for item in &later.items {
            self.push(item.clone());
        }
        self.not_listed += later.not_listed;
    }
}

/// Everything found so far, and the frames counted.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Found {
    pub steps: Capped<StepResponse>,
    /// Each listed step's onset fit, in the same order (`refit.rs`).
    pub step_fits: Capped<StepFit>,
    pub braking: Capped<Braking>,
    pub holds: HoldSums,
    pub timeout: Option<TimeoutFound>,
    pub load_steps: Capped<LoadStep>,
    pub command_frames: u64,
    pub current_frames: u64,
    pub voltage_frames: u64,
}

impl Found {
    pub fn absorb(&mut self, later: &Self) {
        self.steps.absorb(&later.steps);
        self.step_fits.absorb(&later.step_fits);
        self.braking.absorb(&later.braking);
        self.holds.absorb(&later.holds);
        if self.timeout.is_none() {
            self.timeout.clone_from(&later.timeout);
        }
        self.load_steps.absorb(&later.load_steps);
        self.command_frames += later.command_frames;
        self.current_frames += later.current_frames;
        self.voltage_frames += later.voltage_frames;
    }
}

/// A run of command frames of one value, without a cease inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Run {
    first: usize,
    last: usize,
    /// Commands ceased after its last frame.
    silence_after: bool,
}

/// Analyses the runs that start after `from` (the stretch's start; earlier frames are context only), with
/// the data until `end`.
pub(super) fn analyse(view: &View, from: i64, end: i64, found: &mut Found) {
    let commands = view.commands;
    if commands.is_empty() {
        return;
    }
    let silence = silence_gap(commands);
    let ceased = |previous: &Command, next: &Command| {
        let gap = next.t - previous.t;
        gap > CEASED_US || (gap > silence && stopped_by_itself(view, previous, next.t))
    };
    let runs = runs(commands, ceased);
    for (index, run) in runs.iter().enumerate() {
        let value = commands[run.first];
        let (t0, last) = (value.t, commands[run.last].t);
        let next = runs.get(index + 1).map_or(end, |next| commands[next.first].t);
        let previous = index.checked_sub(1).map(|p| runs[p]).filter(|p| !p.silence_after);
        let mut dead = None;
        if let (Some(previous), true) = (previous, t0 > from) {
            let before = commands[previous.first];
            dead = change(view, (&before, &value), (t0, last, next), found).map(|at| (t0, at - t0 as f64));
        }
        if run.silence_after && last > from && !value.is_zero() && found.timeout.is_none() {
            let axis = if value.linear != 0 { Axis::Linear } else { Axis::Angular };
            if let Some((figure, stop)) = timeout(view.motion, axis, (last, next), dead.map(|(_, us)| us)) {
                found.timeout = Some(TimeoutFound::new(figure, axis, &stop, dead));
            }
        }
    }
}

/// A change of command from `before` to `value` at `t0`, held until `last` (the next change at `next`):
/// a stop, a step and a hold, each measured when it qualifies. The step's onset, µs.
fn change(
    view: &View,
    (before, value): (&Command, &Command),
    (t0, last, next): (i64, i64, i64),
    found: &mut Found,
) -> Option<f64> {
    let (linear, angular) = (value.linear_si(), value.angular_si());
    let (d_linear, d_angular) = (linear - before.linear_si(), angular - before.angular_si());
    if d_linear.abs() < MIN_STEP && d_angular.abs() < MIN_STEP {
        return None;
    }
    if let Some(load) = load_step(view, t0) {
        found.load_steps.push(load);
    }
    if value.is_zero() {
        let axis = if before.linear != 0 { Axis::Linear } else { Axis::Angular };
        if let Some(braking) = brake(view.motion, axis, t0, next) {
            found.braking.push(braking);
        }
        return None;
    }
    if last - t0 < HOLD_US {
        return None;
    }
    let mut dead = None;
    let axis = match (d_linear.abs() >= MIN_STEP, d_angular.abs() >= MIN_STEP) {
        (true, false) if d_angular == 0.0 => Some((Axis::Linear, before.linear_si(), linear)),
        (false, true) if d_linear == 0.0 => Some((Axis::Angular, before.angular_si(), angular)),
        _ => None,
    };
    if let Some((axis, from, to)) = axis {
        let (response, onset) = respond(view.motion, axis, (t0, last), (from, to));
        found.steps.push(response);
        found.step_fits.push(StepFit::of(onset.as_ref(), to - from));
        keep_up(&found.steps.items, &mut found.step_fits.items);
        dead = onset.map(|onset| onset.at);
    }
    match (value.linear != 0, value.angular != 0) {
        (true, false) => found.holds.straight(view.motion, view.odometry, t0, last),
        (false, true) => found.holds.spin(view.motion, view.odometry, t0, last),
        _ => {}
    }
    dead
}

/// The robot, told `command`, stopped by itself before `next` (the command timeout).
fn stopped_by_itself(view: &View, command: &Command, next: i64) -> bool {
    let axis = match (command.linear != 0, command.angular != 0) {
        (true, _) => Axis::Linear,
        (false, true) => Axis::Angular,
        (false, false) => return false,
    };
    timeout(view.motion, axis, (command.t, next), None).is_some()
}

/// The gap between command frames beyond which commands may have ceased: [`SILENT_PERIODS`] median periods.
fn silence_gap(commands: &[Command]) -> i64 {
    let gaps: Vec<i64> = commands.windows(2).map(|pair| pair[1].t - pair[0].t).collect();
    let period = median(gaps).unwrap_or(0);
    (SILENT_PERIODS * period).max(MIN_SILENCE_US)
}

/// The runs of one value; `ceased` tells whether commands ceased between two frames.
fn runs(commands: &[Command], ceased: impl Fn(&Command, &Command) -> bool) -> Vec<Run> {
    let mut runs = Vec::new();
    let mut first = 0;
    for index in 1..=commands.len() {
        let ends = match commands.get(index) {
            None => Some(false),
            Some(next) => {
                let previous = &commands[index - 1];
                if ceased(previous, next) {
                    Some(true)
                } else if !next.same_value(previous) {
                    Some(false)
                } else {
                    None
                }
            }
        };
        if let Some(silence_after) = ends {
            runs.push(Run { first, last: index - 1, silence_after });
            first = index;
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn command(t_ms: i64, linear: i32) -> Command {
        Command { t: t_ms * 1000, linear, angular: 0 }
    }

    #[test]
    fn runs_end_at_a_change_and_at_a_silence() {
        let commands = [
            command(0, 0),
            command(20, 0),
            command(40, 100),
            command(60, 100),
            command(200, 100),
            command(220, 0),
        ];
        let silence = silence_gap(&commands);
        assert_eq!(silence, 60_000);
        let runs = runs(&commands, |previous, next| next.t - previous.t > silence);
        assert_eq!(
            runs,
            [
                Run { first: 0, last: 1, silence_after: false },
                Run { first: 2, last: 3, silence_after: true },
                Run { first: 4, last: 4, silence_after: false },
                Run { first: 5, last: 5, silence_after: false },
            ]
        );
    }

    #[test]
    fn capped_lists_keep_the_first_and_count_the_rest_across_merges() {
        let mut first = Capped::default();
        let mut later = Capped::default();
        for n in 0..MAX_LISTED - 1 {
            first.push(n);
        }
        for n in 0..3 {
            later.push(n + 5000);
        }
        first.absorb(&later);
        assert_eq!((first.items.len(), first.not_listed, first.items[MAX_LISTED - 1]), (MAX_LISTED, 2, 5000));
    }
}
