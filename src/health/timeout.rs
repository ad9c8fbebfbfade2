//! The command timeout: when commands cease while the robot moves, the time from the last command frame to
//! the onset of the robot's own deceleration, less the dead time.

use super::sample::Motion;
use super::steps::{level, onset, threshold, Onset, BEFORE_US};
use super::{Axis, CommandTimeout};

/// The stop after the last command frame at `last` (commands then ceased), searched until `end`; `dead_us`
/// is the dead time measured at the step that started the motion (the robot's stop is delayed by it too).
/// The stop's onset too (`refit.rs` may fit it again).
pub(super) fn timeout(
    motion: &[Motion],
    axis: Axis,
    (last, end): (i64, i64),
    dead_us: Option<f64>,
) -> Option<(CommandTimeout, Onset)> {
    let (moving, sigma) = level(motion, axis, last - BEFORE_US, last)?;
    let threshold = threshold(sigma);
    if moving.abs() <= 2.0 * threshold {
        return None;
    }
    // The speed leaves its level towards zero: a change of -moving.
    let change = -moving;
    let start = onset(motion, axis, (last, end), moving, (change.signum(), change, threshold))?;
    let figure = CommandTimeout {
        last_command_us: last,
        timeout_ms: (start.at - last as f64 - dead_us.unwrap_or(0.0)) / 1000.0,
    };
    Some((figure, start))
}

#[cfg(test)]
mod tests {
    use super::super::steps::tests::linear;
    use super::*;

    #[test]
    fn the_stop_after_the_timeout_less_the_dead_time() {
        // 100 mm/s; the last command at 1 s; the robot slows at 1 m/s² from 1.530 s (timeout 500 ms, dead
        // time 30 ms): 90 mm/s at 1.540 s, 70 at 1.560 s.
        let speeds: Vec<i32> = (0..120).map(|n| (100 - ((n * 20 - 1530).max(0))).clamp(0, 100)).collect();
        let motion = linear(0, &speeds);
        let (found, _) = timeout(&motion, Axis::Linear, (1_000_000, 2_400_000), Some(30_000.0)).unwrap();
        assert_eq!(found.last_command_us, 1_000_000);
        assert!((found.timeout_ms - 500.0).abs() < 1e-6, "{found:?}");
        let (without, _) = timeout(&motion, Axis::Linear, (1_000_000, 2_400_000), None).unwrap();
        assert!((without.timeout_ms - 530.0).abs() < 1e-6);
    }

    #[test]
    fn nothing_when_the_robot_was_not_moving_or_never_stopped() {
        assert_eq!(timeout(&linear(0, &[0; 100]), Axis::Linear, (1_000_000, 1_900_000), None), None);
        assert_eq!(timeout(&linear(0, &[100; 100]), Axis::Linear, (1_000_000, 1_900_000), None), None);
    }
}
