//! Periodic feedback on a fixed grid: the k-th frame is due at k × period, however irregularly the caller
//! asks, and a caller late by several periods gets one frame (not a burst) and the grid is kept.

/// One periodic stream.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ticker {
    period_us: u64,
    /// Index of the next grid slot not yet served.
    next_slot: u64,
}

impl Ticker {
    pub fn new(period_us: u64) -> Self {
        Self { period_us: period_us.max(1), next_slot: 0 }
    }

    /// True if a grid slot at or before `now_us` has not been served yet; serves it and every earlier one.
    pub fn due(&mut self, now_us: u64) -> bool {
        let slot = now_us / self.period_us;
        if slot < self.next_slot {
            return false;
        }
        self.next_slot = slot.saturating_add(1);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_per_slot_and_no_burst_when_late() {
        let mut ticker = Ticker::new(20_000);
        assert!(ticker.due(0));
        assert!(!ticker.due(0));
        assert!(!ticker.due(19_999));
        assert!(ticker.due(20_000));
        // 75 ms late: one frame, and the next is due on the grid at 120 ms.
        assert!(ticker.due(95_000));
        assert!(!ticker.due(99_999));
        assert!(ticker.due(100_000));
        assert!(!ticker.due(119_999));
        assert!(ticker.due(120_000));
        // Time going backwards never emits.
        assert!(!ticker.due(50_000));
        assert!(ticker.due(u64::MAX));
        assert!(!ticker.due(u64::MAX));
    }
}
