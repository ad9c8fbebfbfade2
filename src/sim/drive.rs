//! Differential drive: speed limits, acceleration ramps, wheel speeds, odometry, motor currents and a
//! first-order driver temperature.
//!
//! Motor 1 is the right wheel and motor 2 the left (an assumption: the TRACER manuals give the mapping only
//! in a figure, whose label order 0x252 ... 0x251 matches AgileX's Scout numbering, motor 1 front right).

use super::SimConfig;

/// Index of a motor in per-motor arrays: motor 1 (right) is 0, motor 2 (left) is 1.
pub(super) const MOTOR_RIGHT: usize = 0;
pub(super) const MOTOR_LEFT: usize = 1;

#[derive(Clone, Debug)]
pub(super) struct Drive {
    half_track: f64,
    wheel_circumference: f64,
    max_linear: f64,
    max_angular: f64,
    linear_step: f64,
    angular_step: f64,
    current_per_speed: f64,
    current_per_accel: f64,
    dt: f64,
    /// Actual body speeds, m/s and rad/s.
    linear: f64,
    angular: f64,
    /// Odometers, m.
    left_m: f64,
    right_m: f64,
    /// Motor currents by motor index, A.
    currents: [f64; 2],
}

impl Drive {
    /// `dt`: the physics step, s.
    pub fn new(config: &SimConfig, dt: f64) -> Self {
        Self {
            half_track: config.track_m / 2.0,
            wheel_circumference: std::f64::consts::PI * config.wheel_diameter_m,
            max_linear: config.max_linear,
            max_angular: config.max_angular,
            linear_step: config.max_linear_accel * dt,
            angular_step: config.max_angular_accel * dt,
            current_per_speed: config.current_per_speed,
            current_per_accel: config.current_per_accel,
            dt,
            linear: 0.0,
            angular: 0.0,
            left_m: 0.0,
            right_m: 0.0,
            currents: [0.0; 2],
        }
    }

    /// A requested (v, w) within the chassis limits: each clamped (NaN = 0), then both scaled down together
    /// (keeping the curvature) until neither wheel is faster than `max_linear`.
    pub fn limit(&self, linear: f64, angular: f64) -> (f64, f64) {
        let clamp = |value: f64, limit: f64| if value.is_nan() { 0.0 } else { value.clamp(-limit, limit) };
        self.limit_wheels(clamp(linear, self.max_linear), clamp(angular, self.max_angular))
    }

    fn limit_wheels(&self, linear: f64, angular: f64) -> (f64, f64) {
        let fastest_wheel = linear.abs() + angular.abs() * self.half_track;
        if fastest_wheel > self.max_linear {
            let scale = self.max_linear / fastest_wheel;
            (linear * scale, angular * scale)
        } else {
            (linear, angular)
        }
    }

    /// One physics step towards `target` (already limited): ramp, integrate the odometers (trapezoid,
    /// exact for the piecewise-linear speeds of the ramp), and the motor currents.
    pub fn advance(&mut self, target: (f64, f64)) {
        let before = self.wheel_speeds();
        let linear = approach(self.linear, target.0, self.linear_step);
        let angular = approach(self.angular, target.1, self.angular_step);
        (self.linear, self.angular) = self.limit_wheels(linear, angular);
        let after = self.wheel_speeds();
        self.left_m += (before.0 + after.0) / 2.0 * self.dt;
        self.right_m += (before.1 + after.1) / 2.0 * self.dt;
        let current = |before: f64, after: f64| {
            let accel = (after - before) / self.dt;
            self.current_per_speed * after.abs() + self.current_per_accel * accel.abs()
        };
        self.currents[MOTOR_RIGHT] = current(before.1, after.1);
        self.currents[MOTOR_LEFT] = current(before.0, after.0);
    }

    /// Stops dead (E-stop, power cut): no ramp, and no current since the drivers lose power.
    pub fn stop_now(&mut self) {
        self.linear = 0.0;
        self.angular = 0.0;
        self.currents = [0.0; 2];
    }

    /// No motion, and none on the way as long as the target stays zero.
    pub fn at_rest(&self) -> bool {
        self.linear == 0.0 && self.angular == 0.0
    }

    /// A step at rest: no motion, no motor current.
    pub fn rest(&mut self) {
        self.currents = [0.0; 2];
    }

    pub fn speeds(&self) -> (f64, f64) {
        (self.linear, self.angular)
    }

    /// (left, right) wheel speeds, m/s.
    pub fn wheel_speeds(&self) -> (f64, f64) {
        let turn = self.angular * self.half_track;
        (self.linear - turn, self.linear + turn)
    }

    /// Wheel speed of a motor index, m/s.
    pub fn motor_wheel_speed(&self, motor: usize) -> f64 {
        let (left, right) = self.wheel_speeds();
        if motor == MOTOR_RIGHT {
            right
        } else {
            left
        }
    }

    /// Hub motor, no gearbox: shaft RPM = wheel RPM.
    pub fn rpm(&self, motor: usize) -> f64 {
        self.motor_wheel_speed(motor) / self.wheel_circumference * 60.0
    }

    pub fn current(&self, motor: usize) -> f64 {
        self.currents[motor]
    }

    pub fn total_motor_current(&self) -> f64 {
        self.currents.iter().sum()
    }

    /// (left, right) odometers, mm, as 0x311 carries them (i32, wrapping like a real counter).
    pub fn odometry_mm(&self) -> (i32, i32) {
        let mm = |m: f64| (m * 1000.0).round() as i64 as i32;
        (mm(self.left_m), mm(self.right_m))
    }

    /// (left, right) odometers, m, unrounded.
    pub fn odometry_m(&self) -> (f64, f64) {
        (self.left_m, self.right_m)
    }
}

/// One ramp step: reaches `target` exactly once within `max_step`.
fn approach(current: f64, target: f64, max_step: f64) -> f64 {
    let gap = target - current;
    if gap.abs() <= max_step {
        target
    } else {
        current + max_step.copysign(gap)
    }
}

/// A motor driver's temperature: heats with the square of its current, cools exponentially to ambient.
#[derive(Clone, Debug)]
pub(super) struct Thermal {
    ambient: f64,
    heating: f64,
    /// Per-step decay factor of the excess temperature, exp(-dt/tau): stable for any time constant.
    decay: f64,
    dt: f64,
    pub celsius: f64,
}

impl Thermal {
    pub fn new(config: &SimConfig, dt: f64) -> Self {
        Self {
            ambient: config.ambient_temperature_c,
            heating: config.driver_heating,
            decay: (-dt / config.driver_cooling_s).exp(),
            dt,
            celsius: config.ambient_temperature_c,
        }
    }

    pub fn advance(&mut self, current: f64) {
        self.celsius = self.ambient + (self.celsius - self.ambient) * self.decay;
        self.celsius += self.heating * current * current * self.dt;
    }

    /// `steps` steps without current, in one go.
    pub fn cool(&mut self, steps: u64) {
        self.celsius = self.ambient + (self.celsius - self.ambient) * self.decay.powf(steps as f64);
    }
}
