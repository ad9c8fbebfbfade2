//! Caps and ramps: the limits a drive is given, checked and clamped to the protocol, and one step of the
//! sender's control law. Pure (no thread, no clock: the time step is an argument), so it is tested alone.

use std::time::Duration;

use crate::protocol::message::{MotionCommand, ANGULAR_LIMIT, LINEAR_LIMIT};

/// Caps and ramps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// m/s; never above the protocol limit.
    pub max_linear: f64,
    /// rad/s.
    pub max_angular: f64,
    /// m/s², speeding up.
    pub linear_accel: f64,
    /// rad/s², speeding up.
    pub angular_accel: f64,
    /// m/s², slowing down (braking); at least `linear_accel`.
    pub linear_decel: f64,
    /// rad/s², slowing down; at least `angular_accel`.
    pub angular_decel: f64,
}

impl Default for Limits {
    /// Safe defaults for driving next to people: 0.5 m/s, 0.5 rad/s, reached in about a second; braking three
    /// times as strong (from 0.15 m/s to zero in 0.1 s, from 0.5 m/s in 0.33 s).
    fn default() -> Self {
        Self {
            max_linear: 0.5,
            max_angular: 0.5,
            linear_accel: 0.5,
            angular_accel: 1.0,
            linear_decel: 1.5,
            angular_decel: 3.0,
        }
    }
}

/// One of the [`Limits`], to say which one is wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitName {
    MaxLinear,
    MaxAngular,
    LinearAccel,
    AngularAccel,
    LinearDecel,
    AngularDecel,
}

impl LimitName {
    fn words(self) -> &'static str {
        match self {
            LimitName::MaxLinear => "the linear speed cap",
            LimitName::MaxAngular => "the angular speed cap",
            LimitName::LinearAccel => "the linear acceleration",
            LimitName::AngularAccel => "the angular acceleration",
            LimitName::LinearDecel => "the linear deceleration",
            LimitName::AngularDecel => "the angular deceleration",
        }
    }
}

/// Limits that cannot drive a ramp. Plain words: the command line names its own options.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum LimitError {
    #[error("{} must be a positive number, not {value}", name.words())]
    NotPositive { name: LimitName, value: f64 },
    /// Braking (`decel`) weaker than speeding up (`accel`), linear (m/s²) or angular (rad/s²).
    #[error(
        "{} ({decel}) must be at least {} ({accel}): braking is never weaker than speeding up",
        if *angular { LimitName::AngularDecel.words() } else { LimitName::LinearDecel.words() },
        if *angular { LimitName::AngularAccel.words() } else { LimitName::LinearAccel.words() }
    )]
    BrakingWeaker { angular: bool, decel: f64, accel: f64 },
}

impl Limits {
    /// Clamps caps to the protocol limits and rejects nonsense (braking weaker than accelerating too).
    pub fn validated(self) -> Result<Self, LimitError> {
        let positive = |value: f64, name: LimitName| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(LimitError::NotPositive { name, value })
            }
        };
        positive(self.max_linear, LimitName::MaxLinear)?;
        positive(self.max_angular, LimitName::MaxAngular)?;
        positive(self.linear_accel, LimitName::LinearAccel)?;
        positive(self.angular_accel, LimitName::AngularAccel)?;
        positive(self.linear_decel, LimitName::LinearDecel)?;
        positive(self.angular_decel, LimitName::AngularDecel)?;
        for (angular, decel, accel) in
            [(false, self.linear_decel, self.linear_accel), (true, self.angular_decel, self.angular_accel)]
        {
            if decel < accel {
                return Err(LimitError::BrakingWeaker { angular, decel, accel });
            }
        }
        Ok(Self {
            max_linear: self.max_linear.min(LINEAR_LIMIT),
            max_angular: self.max_angular.min(ANGULAR_LIMIT),
            ..self
        })
    }

    /// How long braking from `command` to zero takes.
    pub fn braking_time(&self, command: MotionCommand) -> Duration {
        let seconds =
            (command.linear().abs() / self.linear_decel).max(command.angular().abs() / self.angular_decel);
        Duration::from_secs_f64(seconds.clamp(0.0, 60.0))
    }
}

/// One step of the sender's control law: clamp the target, then move `current` towards it within the
/// acceleration (speeding up) or deceleration (slowing down, reversing) allowed in `dt`. Pure, so the ramp is
/// tested without threads.
pub fn ramp_step(current: (f64, f64), target: (f64, f64), limits: &Limits, dt: Duration) -> (f64, f64) {
    let dt = dt.as_secs_f64();
    let clamp = |value: f64, cap: f64| if value.is_nan() { 0.0 } else { value.clamp(-cap, cap) };
    (
        axis_step(
            current.0,
            clamp(target.0, limits.max_linear),
            limits.linear_accel * dt,
            limits.linear_decel * dt,
        ),
        axis_step(
            current.1,
            clamp(target.1, limits.max_angular),
            limits.angular_accel * dt,
            limits.angular_decel * dt,
        ),
    )
}

fn axis_step(from: f64, to: f64, accel_step: f64, decel_step: f64) -> f64 {
    let toward = |to: f64, step: f64| from + (to - from).clamp(-step, step);
    if from * to < 0.0 {
        // Reversing: brake to zero first (the next ticks speed up the other way).
        toward(0.0, decel_step)
    } else if to.abs() < from.abs() {
        toward(to, decel_step)
    } else {
        toward(to, accel_step)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::sender::PERIOD;

    #[test]
    fn ramp_respects_acceleration_and_caps() {
        let limits = Limits { max_linear: 0.5, max_angular: 0.4, ..Limits::default() };
        let mut current = (0.0, 0.0);
        current = ramp_step(current, (2.0, -2.0), &limits, PERIOD);
        assert!((current.0 - 0.01).abs() < 1e-12 && (current.1 + 0.02).abs() < 1e-12, "{current:?}");
        for _ in 0..100 {
            current = ramp_step(current, (2.0, -2.0), &limits, PERIOD);
        }
        assert_eq!(current, (0.5, -0.4), "capped");
        assert_eq!(ramp_step((0.0, 0.0), (f64::NAN, 0.1), &limits, PERIOD).0, 0.0);
    }

    #[test]
    fn braking_uses_its_own_stronger_deceleration() {
        let limits = Limits::default();
        // Slowing down: 1.5 m/s² and 3 rad/s², three times the acceleration.
        let braked = ramp_step((0.5, -0.4), (0.0, 0.0), &limits, PERIOD);
        assert!((braked.0 - 0.47).abs() < 1e-12 && (braked.1 + 0.34).abs() < 1e-12, "{braked:?}");
        // Slowing to a lower speed in the same direction brakes too; speeding up accelerates.
        assert!((ramp_step((0.5, 0.0), (0.2, 0.0), &limits, PERIOD).0 - 0.47).abs() < 1e-12);
        assert!((ramp_step((0.2, 0.0), (0.5, 0.0), &limits, PERIOD).0 - 0.21).abs() < 1e-12);
        // Reversing brakes to zero first and never overshoots it in that step.
        let mut current = (0.3, 0.0);
        let mut steps = 0;
        while current.0 > 0.0 {
            current = ramp_step(current, (-0.3, 0.0), &limits, PERIOD);
            steps += 1;
        }
        assert_eq!(current.0, 0.0);
        assert!((10..=11).contains(&steps), "0.3 m/s at 1.5 m/s² is 0.2 s (+ rounding): {steps}");
        assert!(ramp_step(current, (-0.3, 0.0), &limits, PERIOD).0 < 0.0);
        // From 0.15 m/s, zero within 150 ms (the requirement), whatever the grid phase.
        let mut current = (0.15, 0.0);
        let mut elapsed = Duration::ZERO;
        while current.0 > 0.0 {
            current = ramp_step(current, (0.0, 0.0), &limits, PERIOD);
            elapsed += PERIOD;
        }
        assert!(elapsed <= Duration::from_millis(120), "{elapsed:?}");
        assert_eq!(
            limits.braking_time(MotionCommand { linear_mm_s: 150, angular_mrad_s: 0 }).as_millis(),
            100
        );
    }

    #[test]
    fn braking_weaker_than_accelerating_is_refused() {
        let error = Limits { linear_decel: 0.3, ..Limits::default() }.validated().unwrap_err();
        assert_eq!(error, LimitError::BrakingWeaker { angular: false, decel: 0.3, accel: 0.5 });
        assert_eq!(
            error.to_string(),
            "the linear deceleration (0.3) must be at least the linear acceleration (0.5): braking is never \
             weaker than speeding up"
        );
        assert!(Limits { angular_decel: 0.5, ..Limits::default() }.validated().is_err());
        assert!(Limits { linear_decel: f64::INFINITY, ..Limits::default() }.validated().is_err());
    }

    #[test]
    fn limits_are_validated_and_clamped_to_the_protocol() {
        let limits = Limits { max_linear: 9.0, ..Limits::default() }.validated().unwrap();
        assert_eq!(limits.max_linear, LINEAR_LIMIT);
        assert!(Limits { linear_accel: 0.0, ..Limits::default() }.validated().is_err());
        assert!(Limits { max_angular: f64::NAN, ..Limits::default() }.validated().is_err());
    }
}
