//! Dead reckoning: the robot's pose from wheel odometer deltas (differential drive, midpoint heading).
//!
//! Pure: the caller gives the time since the previous odometry frame, so the dashboard (clock time) and the
//! MCAP writer (log stamps) integrate the same way.

use super::constants::TRACK_M;
use super::message::Odometry;

/// Faster than this a wheel cannot go (TRACER: 2.3 m/s no-load); a bigger odometer step is a reset or a
/// wrap of a restarted robot, and is skipped rather than integrated into the pose.
pub const MAX_WHEEL_SPEED: f64 = 5.0;
/// An odometer step up to this long (m) is always plausible, whatever the time between frames (frames
/// without a stamp have no time between them).
const STEP_SLACK_M: f64 = 0.5;

/// The integrated pose in the odometry frame: x forward at the start, y to the left, heading
/// counter-clockwise.
#[derive(Clone, Copy, Debug, Default)]
pub struct DeadReckoning {
    last: Option<Odometry>,
    /// Distance driven (forward and back add up), m.
    pub trip_m: f64,
    pub x: f64,
    pub y: f64,
    /// rad, kept in -pi..=pi.
    pub heading: f64,
    /// Odometer steps too big to be driving (a reset), skipped.
    pub jumps: u64,
}

impl DeadReckoning {
    /// Folds in one odometry frame, `elapsed_s` seconds after the previous one (0 when unknown).
    pub fn step(&mut self, odometry: Odometry, elapsed_s: f64) {
        let Some(previous) = self.last.replace(odometry) else {
            return;
        };
        // The odometers are i32 mm that wrap.
        let left = f64::from(odometry.left_mm.wrapping_sub(previous.left_mm)) / 1000.0;
        let right = f64::from(odometry.right_mm.wrapping_sub(previous.right_mm)) / 1000.0;
        let plausible = MAX_WHEEL_SPEED * elapsed_s.max(0.0) + STEP_SLACK_M;
        if left.abs() > plausible || right.abs() > plausible {
            self.jumps += 1;
            return;
        }
        let distance = (left + right) / 2.0;
        let turn = (right - left) / TRACK_M;
        let mid = self.heading + turn / 2.0;
        self.x += distance * mid.cos();
        self.y += distance * mid.sin();
        self.heading = normalize_angle(self.heading + turn);
        self.trip_m += distance.abs();
    }

    /// Whether any odometry frame was seen (before that there is no pose).
    pub fn started(&self) -> bool {
        self.last.is_some()
    }

    /// The heading as a unit quaternion about z: `(x, y, z, w)`.
    pub fn orientation(&self) -> (f64, f64, f64, f64) {
        let half = self.heading / 2.0;
        (0.0, 0.0, half.sin(), half.cos())
    }
}

/// -pi..=pi.
pub fn normalize_angle(angle: f64) -> f64 {
    let wrapped = (angle + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    if wrapped <= -std::f64::consts::PI {
        wrapped + std::f64::consts::TAU
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn odo(left_mm: i32, right_mm: i32) -> Odometry {
        Odometry { left_mm, right_mm }
    }

    #[test]
    fn a_straight_drive_moves_along_x() {
        let mut pose = DeadReckoning::default();
        assert!(!pose.started());
        for step in 0..=10 {
            pose.step(odo(step * 100, step * 100), 0.1);
        }
        assert!((pose.x - 1.0).abs() < 1e-9 && pose.y.abs() < 1e-12 && pose.heading == 0.0);
        assert_eq!(pose.orientation(), (0.0, 0.0, 0.0, 1.0));
    }

    #[test]
    fn a_quarter_turn_on_the_spot_points_along_y() {
        let mut pose = DeadReckoning::default();
        let arc = (TRACK_M / 2.0 * std::f64::consts::FRAC_PI_2 * 1000.0).round() as i32;
        pose.step(odo(0, 0), 0.0);
        pose.step(odo(-arc, arc), 1.0);
        assert!((pose.heading - std::f64::consts::FRAC_PI_2).abs() < 0.01);
        let (_, _, z, w) = pose.orientation();
        assert!((z - w).abs() < 0.01, "45 degrees each: {z} {w}");
        assert_eq!(pose.trip_m, 0.0);
    }

    #[test]
    fn a_reset_is_skipped_and_without_stamps_a_step_of_half_a_metre_is_still_driving() {
        let mut pose = DeadReckoning::default();
        pose.step(odo(0, 0), 0.0);
        pose.step(odo(400, 400), 0.0);
        pose.step(odo(900_000, 900_000), 0.02);
        assert_eq!(pose.jumps, 1);
        assert!((pose.x - 0.4).abs() < 1e-9);
    }

    #[test]
    fn angles_wrap_into_minus_pi_to_pi() {
        assert!((normalize_angle(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((normalize_angle(-std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((normalize_angle(-0.5) + 0.5).abs() < 1e-12);
    }
}
