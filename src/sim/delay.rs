//! Dead time: a delay line on the drive's target (v, w), one slot per 1 ms physics step.

use std::collections::VecDeque;

/// Gives back each target `len` steps after it went in; zeros before the first ones come out.
#[derive(Clone, Debug)]
pub(super) struct DelayLine {
    slots: VecDeque<(f64, f64)>,
    /// How many targets in `slots` are not (0, 0): the line is idle (nothing on the way) at 0.
    moving: usize,
}

impl DelayLine {
    /// A line `len` steps long (0: no delay).
    pub fn new(len: usize) -> Self {
        Self { slots: std::iter::repeat_n((0.0, 0.0), len).collect(), moving: 0 }
    }

    /// Puts in this step's target and takes out the one of `len` steps ago.
    pub fn pass(&mut self, target: (f64, f64)) -> (f64, f64) {
        let Some(oldest) = self.slots.pop_front() else { return target };
        self.moving -= usize::from(is_moving(oldest));
        self.moving += usize::from(is_moving(target));
        self.slots.push_back(target);
        oldest
    }

    /// Nothing but zero targets on the way.
    pub fn idle(&self) -> bool {
        self.moving == 0
    }

    /// Forgets what is on the way (an immediate stop: E-stop, power cut).
    pub fn clear(&mut self) {
        self.slots.iter_mut().for_each(|slot| *slot = (0.0, 0.0));
        self.moving = 0;
    }
}

fn is_moving(target: (f64, f64)) -> bool {
    target != (0.0, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_come_out_len_steps_later() {
        let mut line = DelayLine::new(3);
        assert!(line.idle());
        assert_eq!(line.pass((1.0, 0.5)), (0.0, 0.0));
        assert!(!line.idle());
        assert_eq!(line.pass((2.0, 0.0)), (0.0, 0.0));
        assert_eq!(line.pass((0.0, 0.0)), (0.0, 0.0));
        assert_eq!(line.pass((0.0, 0.0)), (1.0, 0.5));
        assert_eq!(line.pass((0.0, 0.0)), (2.0, 0.0));
        assert!(line.idle(), "only zeros left on the way");
        assert_eq!(line.pass((0.0, 0.0)), (0.0, 0.0));
        line.pass((3.0, 0.0));
        line.clear();
        assert!(line.idle());
        assert_eq!([line.pass((0.0, 0.0)), line.pass((0.0, 0.0)), line.pass((0.0, 0.0))], [(0.0, 0.0); 3]);
    }

    #[test]
    fn no_delay_passes_through() {
        let mut line = DelayLine::new(0);
        assert_eq!(line.pass((1.5, -0.2)), (1.5, -0.2));
        assert!(line.idle());
    }
}
