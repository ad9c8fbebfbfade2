//! Differential drive: speed limits, acceleration ramps, wheel speeds, odometry, motor currents and a
//! first-order driver temperature.
//!
//! Motor 1 is the right wheel and motor 2 the left (an assumption: the TRACER manuals give the mapping only
//! in a figure, whose label order 0x252 ... 0x251 matches AgileX's Scout numbering, motor 1 front right).

use super::delay::DelayLine;
use super::SimConfig;

/// Index of a motor in per-motor arrays: motor 1 (right) is 0, motor 2 (left) is 1.
pub(super) const MOTOR_RIGHT: usize = 0;
pub(super) const MOTOR_LEFT: usize = 1;

#[derive(Clone, Debug)]
pub(super) struct Drive {
    /// Half the nominal track: the firmware mixes (v, w) into wheel commands with it.
    half_track: f64,
    wheel_circumference: f64,
    max_linear: f64,
    max_angular: f64,
    linear_step: f64,
    angular_step: f64,
    current_per_speed: f64,
    current_per_accel: f64,
    dt: f64,
    /// Dead time on the target.
    delay: DelayLine,
    /// Per-step fraction of the gap the lag closes, 1 - exp(-dt/tau); `None`: no lag.
    lag_step: Option<f64>,
    /// (left, right) wheel gains.
    gains: (f64, f64),
    /// Actual body (v, w) from the firmware's (v, w): the gains and the effective track. Exactly the
    /// identity with the defaults, so a default robot computes what it always did.
    body: [[f64; 2]; 2],
    odometer_scale: f64,
    /// The acceleration-limited ramp, m/s and rad/s.
    ramp: (f64, f64),
    /// The firmware's body command: the ramp after the lag.
    command: (f64, f64),
    /// True odometers, m.
    left_m: f64,
    right_m: f64,
    /// Motor currents by motor index, A.
    currents: [f64; 2],
}

/// A lag closer than this to its input (m/s, rad/s) has arrived: an exponential never does, and the model
/// must come to rest exactly to skip idle time.
const LAG_ARRIVED: f64 = 1e-9;

impl Drive {
    /// `dt`: the physics step, s.
    pub fn new(config: &SimConfig, dt: f64) -> Self {
        let (left, right) = (config.left_gain, config.right_gain);
        let half_track = config.track_m / 2.0;
        let effective = config.effective_track_m;
        // l = left (v - w h), r = right (v + w h); v' = (l + r) / 2, w' = (r - l) / effective track.
        let body = [
            [(left + right) / 2.0, half_track * (right - left) / 2.0],
            [(right - left) / effective, config.track_m * ((left + right) / 2.0) / effective],
        ];
        let dead_steps = (config.dead_time.as_secs_f64() / dt).round() as usize;
        let lag = config.lag.as_secs_f64();
        Self {
            half_track,
            wheel_circumference: std::f64::consts::PI * config.wheel_diameter_m,
            max_linear: config.max_linear,
            max_angular: config.max_angular,
            linear_step: config.max_linear_accel * dt,
            angular_step: config.max_angular_accel * dt,
            current_per_speed: config.current_per_speed,
            current_per_accel: config.current_per_accel,
            dt,
            delay: DelayLine::new(dead_steps),
            lag_step: (lag > 0.0).then(|| -(-dt / lag).exp_m1()),
            gains: (left, right),
            body,
            odometer_scale: config.odometer_scale,
            ramp: (0.0, 0.0),
            command: (0.0, 0.0),
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

    /// One physics step towards `target` (already limited) as it was the dead time ago: ramp, lag,
    /// integrate the odometers (trapezoid, exact for the piecewise-linear speeds of the ramp), and the
    /// motor currents.
    pub fn advance(&mut self, target: (f64, f64)) {
        let goal = self.delay.pass(target);
        let before = self.wheel_speeds();
        let linear = approach(self.ramp.0, goal.0, self.linear_step);
        let angular = approach(self.ramp.1, goal.1, self.angular_step);
        self.ramp = self.limit_wheels(linear, angular);
        self.command = match self.lag_step {
            None => self.ramp,
            Some(step) => {
                (follow(self.command.0, self.ramp.0, step), follow(self.command.1, self.ramp.1, step))
            }
        };
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

    /// Stops dead (E-stop, power cut): no ramp, no lag, nothing left on the way through the dead time,
    /// and no current since the drivers lose power.
    pub fn stop_now(&mut self) {
        self.ramp = (0.0, 0.0);
        self.command = (0.0, 0.0);
        self.delay.clear();
        self.currents = [0.0; 2];
    }

    /// No motion, and none on the way as long as the target stays zero.
    pub fn at_rest(&self) -> bool {
        self.command == (0.0, 0.0) && self.ramp == (0.0, 0.0) && self.delay.idle()
    }

    /// A step at rest: no motion, no motor current.
    pub fn rest(&mut self) {
        self.currents = [0.0; 2];
    }

    /// Actual body speeds (v, w), m/s and rad/s: those of the actual wheels.
    pub fn speeds(&self) -> (f64, f64) {
        let [[vv, vw], [wv, ww]] = self.body;
        let (v, w) = self.command;
        (vv * v + vw * w, wv * v + ww * w)
    }

    /// (left, right) actual wheel speeds, m/s: the firmware's wheel commands (nominal track) × the gains.
    pub fn wheel_speeds(&self) -> (f64, f64) {
        let turn = self.command.1 * self.half_track;
        (self.gains.0 * (self.command.0 - turn), self.gains.1 * (self.command.0 + turn))
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

    /// (left, right) odometers, mm, as 0x311 carries them: the odometer scale × the true distance (i32,
    /// wrapping like a real counter).
    pub fn odometry_mm(&self) -> (i32, i32) {
        let mm = |m: f64| (m * self.odometer_scale * 1000.0).round() as i64 as i32;
        (mm(self.left_m), mm(self.right_m))
    }

    /// (left, right) true wheel distances, m, unrounded and unscaled.
    pub fn odometry_m(&self) -> (f64, f64) {
        (self.left_m, self.right_m)
    }
}

/// One lag step: closes `step` of the gap to `input` (x += (input - x)(1 - exp(-dt/tau))), and arrives
/// once within [`LAG_ARRIVED`].
fn follow(current: f64, input: f64, step: f64) -> f64 {
    let gap = input - current;
    if gap.abs() <= LAG_ARRIVED {
        input
    } else {
        current + gap * step
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
