//! Braking: from a zero command after motion to standstill, its time, distance and mean deceleration.

use super::fit::crossing;
use super::sample::Motion;
use super::series::within;
use super::steps::{level, threshold, value, BEFORE_US};
use super::{Axis, Braking};

/// The mean deceleration is taken between these fractions of the speed at the zero command (each crossing
/// interpolated): the part of the stop after the dead time and before the last creep, where an
/// acceleration-limited chassis decelerates at its limit.
const BAND: (f64, f64) = (0.1, 0.9);

/// The stop of `axis` after the zero command at `t0`, searched until `end`; `None` when the robot was not
/// moving or did not come to rest.
pub(super) fn brake(motion: &[Motion], axis: Axis, t0: i64, end: i64) -> Option<Braking> {
    let at_command = motion.partition_point(|m| m.t <= t0).checked_sub(1)?;
    let speed = value(&motion[at_command], axis);
    let (_, sigma) = level(motion, axis, t0 - BEFORE_US, t0)?;
    let threshold = threshold(sigma);
    if speed.abs() <= 2.0 * threshold {
        return None;
    }
    let direction = speed.signum();
    let range = within(motion, t0 + 1, end, |m| m.t);
    let after = &motion[range.clone()];
    let still = after.iter().position(|m| direction * value(m, axis) <= threshold)?;
    let last_moving = if still == 0 { &motion[at_command] } else { &after[still - 1] };
    let (t_moving, v_moving) = (last_moving.t as f64, value(last_moving, axis));
    let (t_still, v_still) = (after[still].t as f64, value(&after[still], axis));
    // Where the line between the last moving sample and the first still one meets zero.
    let stop = if direction * v_still <= 0.0 && v_moving != v_still {
        t_moving + v_moving / (v_moving - v_still) * (t_still - t_moving)
    } else {
        t_still
    };
    let mut travelled = 0.0;
    let mut previous = (t0 as f64, speed);
    for m in &after[..still] {
        let v = value(m, axis);
        travelled += (previous.1 + v) / 2.0 * (m.t as f64 - previous.0);
        previous = (m.t as f64, v);
    }
    travelled += previous.1 / 2.0 * (stop - previous.0);
    // From the sample at the zero command to the first still one: each crossing between two samples.
    let stopping = &motion[at_command..=range.start + still];
    let points = stopping.iter().map(|m| (m.t, value(m, axis)));
    let high = crossing(points.clone(), BAND.1 * speed, -direction);
    let low = crossing(points, BAND.0 * speed, -direction);
    let deceleration = match (high, low) {
        (Some(high), Some(low)) if low > high => (BAND.1 - BAND.0) * speed.abs() / ((low - high) / 1e6),
        _ => speed.abs() / ((stop - t0 as f64).max(1.0) / 1e6),
    };
    Some(Braking {
        axis,
        at_us: t0,
        from_speed: speed,
        time_ms: (stop - t0 as f64) / 1000.0,
        distance: direction * travelled / 1e6,
        deceleration,
    })
}

#[cfg(test)]
mod tests {
    use super::super::steps::tests::linear;
    use super::*;

    #[test]
    fn a_ramp_down_gives_its_deceleration_time_and_distance() {
        // 300 mm/s, zero command at 400 ms, 40 ms dead time, then 1 m/s² (20 mm/s per sample): zero at 740 ms.
        let mut speeds = vec![300; 23];
        speeds.extend((1..=15).map(|n| 300 - 20 * n));
        speeds.extend([0; 20]);
        let motion = linear(0, &speeds);
        let braking = brake(&motion, Axis::Linear, 400_000, 2_000_000).unwrap();
        assert_eq!(braking.from_speed, 0.3);
        assert!((braking.deceleration - 1.0).abs() < 1e-9, "{braking:?}");
        assert!((braking.time_ms - 340.0).abs() < 1e-9, "{braking:?}");
        // 40 ms at 0.3 m/s, then 0.3 s of a linear stop: 0.012 + 0.045 m.
        assert!((braking.distance - 0.057).abs() < 1e-9, "{braking:?}");
    }

    #[test]
    fn no_braking_without_motion_or_without_a_stop() {
        let motion = linear(0, &[0; 50]);
        assert_eq!(brake(&motion, Axis::Linear, 200_000, 900_000), None);
        let moving = linear(0, &[-200; 50]);
        assert_eq!(brake(&moving, Axis::Linear, 200_000, 900_000), None);
    }

    #[test]
    fn reverse_motion_brakes_with_a_positive_deceleration() {
        let mut speeds = vec![-200; 20];
        speeds.extend([-200, -150, -100, -50, 0, 0, 0]);
        let motion = linear(0, &speeds);
        let braking = brake(&motion, Axis::Linear, 380_000, 600_000).unwrap();
        assert!((braking.deceleration - 2.5).abs() < 1e-9, "{braking:?}");
        assert!((braking.time_ms - 100.0).abs() < 1e-9);
        assert!((braking.distance - 0.012).abs() < 1e-9, "{braking:?}");
    }
}
