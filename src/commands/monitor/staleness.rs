//! Which expected periodic frames have gone stale: each one the catalog gives a period is watched from its
//! first arrival, warned about once when it has been missing for `STALE_PERIODS` periods, and said to have
//! resumed when it comes back. Pure: arrival times and the present are arguments, as the time since the
//! monitor started (the caller's clock, or a test's made-up times); no clock type is read or held here.

use std::time::Duration;

use super::text::human;
use crate::link::LinkFrame;
use crate::protocol::catalog::{Entry, PERIODIC, STALE_PERIODS};
use crate::protocol::Wire;

/// One expected periodic frame and whether it has gone stale.
#[derive(Clone, Copy, Debug)]
struct Tracker {
    what: &'static Entry,
    /// The entry's period.
    period: Duration,
    /// Arrival (since the monitor started) and link timestamp of the last one.
    last: Option<(Duration, f64)>,
    stale: bool,
}

/// The expected periodic frames of one link, and which of them are stale.
#[derive(Clone, Debug)]
pub(super) struct Staleness {
    trackers: Vec<Tracker>,
}

impl Staleness {
    /// The link's own wire only: CAN (V1 and V2; a tracker waits for its first frame) or RS232.
    pub(super) fn new(serial: bool) -> Self {
        let trackers = PERIODIC
            .iter()
            .filter(|what| (what.wire == Wire::Serial) == serial)
            .filter_map(|what| Some(Tracker { what, period: what.period?, last: None, stale: false }))
            .collect();
        Self { trackers }
    }

    /// Notes the arrival of an expected periodic frame at `now` (link timestamp `secs`); says so when a
    /// stale one resumes.
    pub(super) fn arrived(&mut self, frame: &LinkFrame, now: Duration, secs: f64) -> Option<String> {
        let id = match frame {
            LinkFrame::Can(frame) if frame.is_standard_data() => frame.frame_id(),
            LinkFrame::Serial(frame) => frame.frame_id(),
            LinkFrame::Can(_) => return None,
        };
        let tracker = self.trackers.iter_mut().find(|tracker| tracker.what.id == id)?;
        let mut resumed = None;
        if tracker.stale {
            tracker.stale = false;
            // Link timestamps (kernel receive times on SocketCAN), to the millisecond.
            let gap = tracker.last.map_or(0.0, |(_, last)| (secs - last).max(0.0));
            let gap = Duration::from_millis((gap * 1000.0).round() as u64);
            resumed = Some(format!("{} {} resumed after a gap of {}", id, tracker.what.name(), human(gap)));
        }
        tracker.last = Some((now, secs));
        resumed
    }

    /// The warnings for frames gone stale by `now` since the last check, one line per period: "no 0x211
    /// system_state, 0x221 motion_state on can0 for 100 ms (expected every 20 ms)". `scale` is wall-clock
    /// seconds per second of link time (a replay at 2x speed: 0.5); `link` names the link.
    pub(super) fn check(&mut self, now: Duration, scale: f64, link: &str) -> Vec<String> {
        let mut lines: Vec<(u128, String)> = Vec::new();
        for tracker in &mut self.trackers {
            let Some((seen, _)) = tracker.last else { continue };
            let limit = tracker.period * STALE_PERIODS;
            if tracker.stale || now.saturating_sub(seen) < limit.mul_f64(scale) {
                continue;
            }
            tracker.stale = true;
            let name = format!("{} {}", tracker.what.id, tracker.what.name());
            let period = tracker.period.as_millis();
            match lines.iter_mut().find(|(line_period, _)| *line_period == period) {
                Some((_, names)) => {
                    names.push_str(", ");
                    names.push_str(&name);
                }
                None => lines.push((period, name)),
            }
        }
        lines
            .into_iter()
            .map(|(period, names)| {
                let limit = Duration::from_millis(period as u64) * STALE_PERIODS;
                format!("warning: no {names} on {link} for {} (expected every {period} ms)", human(limit))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::CanFrame;

    fn can(id: u32) -> LinkFrame {
        LinkFrame::Can(CanFrame::new(id, &[0; 8]).unwrap())
    }

    #[test]
    fn a_frame_is_stale_after_its_periods_and_resumes_with_the_link_time_gap() {
        let ms = Duration::from_millis;
        let mut staleness = Staleness::new(false);
        assert!(staleness.check(ms(1000), 1.0, "can0").is_empty(), "nothing expected before it was seen");
        assert_eq!(staleness.arrived(&can(0x211), ms(0), 10.0), None);
        assert!(staleness.check(ms(99), 1.0, "can0").is_empty());
        assert_eq!(
            staleness.check(ms(100), 1.0, "can0"),
            ["warning: no 0x211 system_state on can0 for 100 ms (expected every 20 ms)"]
        );
        assert!(staleness.check(ms(200), 1.0, "can0").is_empty(), "warned once");
        assert_eq!(
            staleness.arrived(&can(0x211), ms(300), 10.25).as_deref(),
            Some("0x211 system_state resumed after a gap of 250 ms")
        );
    }

    #[test]
    fn frames_of_one_period_share_a_line_and_a_replay_scales_the_limit() {
        let ms = Duration::from_millis;
        let mut staleness = Staleness::new(false);
        staleness.arrived(&can(0x211), ms(0), 0.0);
        staleness.arrived(&can(0x221), ms(0), 0.0);
        // At twice the speed, 100 ms of log pass in 50 ms.
        assert_eq!(
            staleness.check(ms(50), 0.5, "replay"),
            ["warning: no 0x211 system_state, 0x221 motion_state on replay for 100 ms (expected every 20 ms)"]
        );
    }

    #[test]
    fn an_rs232_link_watches_only_rs232_frames() {
        let mut staleness = Staleness::new(true);
        staleness.arrived(&can(0x211), Duration::ZERO, 0.0);
        assert!(staleness.check(Duration::from_secs(10), 1.0, "/dev/ttyUSB0").is_empty());
    }
}
