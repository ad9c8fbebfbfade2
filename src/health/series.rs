//! The recent observations, one bounded queue per stream, in time order.

use std::collections::VecDeque;

use super::sample::{Command, Motion, Odometer, Reading, Sample};

/// Samples each queue holds at most (a minute and a half of 50 Hz feedback; the current queues hold
/// both motors); a full queue forces the analysis of what it holds.
const CAPACITY: usize = 4096;

#[derive(Clone, Debug, Default)]
pub(super) struct Series {
    pub commands: VecDeque<Command>,
    pub motion: VecDeque<Motion>,
    /// Per motor (motor 1, motor 2).
    pub currents: [VecDeque<Reading>; 2],
    pub odometry: VecDeque<Odometer>,
    pub voltage: VecDeque<Reading>,
}

/// The queues as slices, for the analysis.
#[derive(Clone, Copy, Debug)]
pub(super) struct View<'a> {
    pub commands: &'a [Command],
    pub motion: &'a [Motion],
    pub currents: [&'a [Reading]; 2],
    pub odometry: &'a [Odometer],
    pub voltage: &'a [Reading],
}

impl Series {
    /// Appends `sample` at `t`; true when its queue is now full.
    #[inline]
    pub fn push(&mut self, t: i64, sample: Sample) -> bool {
        match sample {
            Sample::Command { linear, angular } => push(&mut self.commands, Command { t, linear, angular }),
            Sample::Motion { linear, angular } => push(&mut self.motion, Motion { t, linear, angular }),
            Sample::Current { motor, deciamps } => {
                push(&mut self.currents[usize::from(motor & 1)], Reading { t, value: deciamps })
            }
            Sample::Odometry { left, right } => {
                push(&mut self.odometry, Odometer { t, left: left.into(), right: right.into() })
            }
            Sample::Voltage { decivolts } => push(&mut self.voltage, Reading { t, value: decivolts.into() }),
        }
    }

    /// Drops every sample before `t`.
    pub fn keep_from(&mut self, t: i64) {
        trim(&mut self.commands, t, |c| c.t);
        trim(&mut self.motion, t, |m| m.t);
        for current in &mut self.currents {
            trim(current, t, |r| r.t);
        }
        trim(&mut self.odometry, t, |o| o.t);
        trim(&mut self.voltage, t, |r| r.t);
    }

    /// Drops every sample (`keep_from(i64::MAX)` would keep those stamped `i64::MAX`).
    pub fn clear(&mut self) {
        self.commands.clear();
        self.motion.clear();
        for current in &mut self.currents {
            current.clear();
        }
        self.odometry.clear();
        self.voltage.clear();
    }

    /// The latest measured motion.
    pub fn last_motion(&self) -> Option<&Motion> {
        self.motion.back()
    }

    pub fn view(&mut self) -> View<'_> {
        self.commands.make_contiguous();
        self.motion.make_contiguous();
        for current in &mut self.currents {
            current.make_contiguous();
        }
        self.odometry.make_contiguous();
        self.voltage.make_contiguous();
        View {
            commands: self.commands.as_slices().0,
            motion: self.motion.as_slices().0,
            currents: [self.currents[0].as_slices().0, self.currents[1].as_slices().0],
            odometry: self.odometry.as_slices().0,
            voltage: self.voltage.as_slices().0,
        }
    }
}

#[inline]
fn push<T>(queue: &mut VecDeque<T>, item: T) -> bool {
    // The whole queue at once: memory stays flat and no push allocates after the first (a queue that
    // grew by doubling allocated more the longer the log, tests/no_alloc.rs).
    if queue.capacity() == 0 {
        queue.reserve_exact(CAPACITY);
    }
    queue.push_back(item);
    queue.len() >= CAPACITY
}

fn trim<T: Copy>(queue: &mut VecDeque<T>, t: i64, time: impl Fn(&T) -> i64) {
    // Times ascend: one binary search, then the front dropped at once (nothing to drop for `Copy` items).
    let old = queue.partition_point(|item| time(item) < t);
    queue.drain(..old);
}

/// The index range of `items` with times in `from..=to` (times ascending).
pub(super) fn within<T>(items: &[T], from: i64, to: i64, time: impl Fn(&T) -> i64) -> std::ops::Range<usize> {
    let start = items.partition_point(|item| time(item) < from);
    let end = items.partition_point(|item| time(item) <= to);
    start..end.max(start)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_go_to_their_queue_and_old_ones_are_dropped() {
        let mut series = Series::default();
        series.push(10, Sample::Command { linear: 1, angular: 0 });
        series.push(20, Sample::Motion { linear: 2, angular: 0 });
        series.push(30, Sample::Current { motor: 1, deciamps: 5 });
        series.push(40, Sample::Voltage { decivolts: 250 });
        series.push(50, Sample::Odometry { left: 1, right: 2 });
        assert_eq!(series.currents[1].len(), 1);
        series.keep_from(30);
        let view = series.view();
        assert!(view.commands.is_empty() && view.motion.is_empty());
        assert_eq!((view.currents[1].len(), view.voltage.len(), view.odometry.len()), (1, 1, 1));
        series.clear();
        assert!(series.voltage.is_empty() && series.odometry.is_empty());
    }

    #[test]
    fn clear_drops_samples_at_the_end_of_time_too() {
        let mut series = Series::default();
        series.push(i64::MAX, Sample::Command { linear: 1, angular: 0 });
        series.push(i64::MAX, Sample::Voltage { decivolts: 250 });
        series.clear();
        let view = series.view();
        assert!(view.commands.is_empty() && view.voltage.is_empty());
    }

    #[test]
    fn a_full_queue_says_so() {
        let mut series = Series::default();
        let full =
            (0..CAPACITY as i64).map(|t| series.push(t, Sample::Voltage { decivolts: 1 })).filter(|f| *f);
        assert_eq!(full.count(), 1);
    }

    #[test]
    fn within_finds_the_inclusive_time_range() {
        let times = [10i64, 20, 20, 30, 40];
        assert_eq!(within(&times, 20, 30, |t| *t), 1..4);
        assert_eq!(within(&times, 41, 50, |t| *t), 5..5);
        assert_eq!(within(&times, 30, 10, |t| *t), 3..3);
    }
}
