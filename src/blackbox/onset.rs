//! When a trigger fires: on the onset of its condition (false -> true), and again only after the condition
//! has been false for the re-arm time. Two shapes: [`Onset`] for a condition that lasts (an E-stop held, a
//! fault bit set), [`Pulse`] for one that is an instant (a frame seen, a mode changed). Times are
//! nanoseconds on the frames' clock. Pure.

/// A lasting condition, fed at each observation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Onset {
    active: bool,
    /// Fired at least once: from then on an onset fires only once re-armed.
    fired: bool,
    /// When the condition last became false.
    false_since: u64,
}

impl Onset {
    /// Feeds the condition observed at `now`; true when this observation is an onset that fires. The first
    /// observation counts from false, so a condition already true then fires.
    #[inline]
    pub fn update(&mut self, now: u64, condition: bool, rearm: u64) -> bool {
        if condition == self.active {
            return false;
        }
        self.active = condition;
        if !condition {
            self.false_since = now;
            return false;
        }
        let fires = !self.fired || rearmed(self.false_since, now, rearm);
        self.fired |= fires;
        fires
    }

    pub fn is_active(&self) -> bool {
        self.active
    }
}

/// An instantaneous condition: it fires when it happens unless it already happened within the re-arm time
/// (each happening restarts that time, so a steady stream fires once).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Pulse {
    last: Option<u64>,
}

impl Pulse {
    /// The condition happened at `now`; true when that fires.
    #[inline]
    pub fn hit(&mut self, now: u64, rearm: u64) -> bool {
        let fires = self.last.is_none_or(|last| rearmed(last, now, rearm));
        self.last = Some(now);
        fires
    }

    pub fn last(&self) -> Option<u64> {
        self.last
    }
}

/// False (or quiet) since `since`, now `now`: re-armed after `rearm`. A clock that went back cannot say how
/// long it was: then re-armed, so an event is reported twice rather than lost.
#[inline]
fn rearmed(since: u64, now: u64, rearm: u64) -> bool {
    now < since || now - since >= rearm
}

#[cfg(test)]
mod tests {
    use super::*;

    const REARM: u64 = 1_000;

    #[test]
    fn an_onset_fires_once_then_rearms_after_the_condition_was_false_long_enough() {
        let mut onset = Onset::default();
        assert!(onset.update(0, true, REARM), "true at the first observation fires");
        assert!(!onset.update(10, true, REARM));
        assert!(!onset.update(20, false, REARM));
        // False for 980 < 1000: not re-armed; and going false again restarts the count.
        assert!(!onset.update(1_000, true, REARM));
        assert!(!onset.update(1_100, false, REARM));
        assert!(!onset.update(2_099, true, REARM));
        assert!(!onset.update(2_100, false, REARM));
        assert!(onset.update(3_100, true, REARM), "false for exactly the re-arm time");
        assert!(onset.is_active());
    }

    #[test]
    fn false_at_first_is_not_an_onset_and_a_clock_going_back_rearms() {
        let mut onset = Onset::default();
        assert!(!onset.update(5, false, REARM));
        assert!(onset.update(6, true, REARM));
        assert!(!onset.update(500, false, REARM));
        assert!(onset.update(100, true, REARM), "time went back: re-armed, not lost");
    }

    #[test]
    fn a_pulse_fires_once_per_quiet_period() {
        let mut pulse = Pulse::default();
        assert!(pulse.hit(0, REARM));
        for t in (100..5_000).step_by(100) {
            assert!(!pulse.hit(t, REARM), "{t}: a steady stream fires once");
        }
        assert!(pulse.hit(5_900 + REARM, REARM));
        assert_eq!(pulse.last(), Some(5_900 + REARM));
        assert!(pulse.hit(10, REARM), "time went back");
    }
}
