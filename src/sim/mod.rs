//! The virtual TRACER: a pure, deterministic model of the chassis (no threads, no clocks, no I/O).
//!
//! Time is passed in as the `Duration` since the simulation started, so the in-process link, the vcan
//! and the pty transports can drive one `Chassis` from a thread while tests drive it exactly. The model
//! consumes and produces typed `Message`s; the transports do the encoding. docs/sim.md describes every
//! parameter, behaviour and fault.
//!
//! Physics advances on a fixed 1 ms grid, so the state at a given time does not depend on how often
//! `step` is called; feedback is due on its own grid (20 ms, 100 ms) and never drifts.

mod battery;
mod chassis;
mod delay;
mod drive;
mod faults;
mod feedback;
mod noise;
mod params;
#[cfg(test)]
mod params_tests;
pub mod serve;
#[cfg(test)]
mod tests;

use std::fmt;
use std::time::Duration;

use crate::protocol::message::Lights;

/// The control mode as the model keeps it; `ControlMode::code` gives the value the wire reports.
pub use crate::protocol::ControlMode;
pub use chassis::Chassis;
pub use faults::{fault_help, FaultKind, FaultParseError, ScheduledFault};
pub use params::{param_help, ParamKind, ParamValue, SimParam, SimParamError, SimParamSetting, SIM_PARAMS};

/// Which link the virtual robot speaks: decides the commands it obeys, the feedback set it sends and the
/// layout of the fault bits it reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimWire {
    /// CAN protocol V2: 0x211/0x221/0x231/0x251/0x252/0x311 every 20 ms, 0x261/0x262 every 100 ms.
    CanV2,
    /// RS232: system, motion, motor 1/2 driver and light status every 20 ms; V1/serial fault bits.
    Serial,
}

impl From<SimWire> for crate::protocol::Wire {
    fn from(wire: SimWire) -> Self {
        match wire {
            SimWire::CanV2 => crate::protocol::Wire::CanV2,
            SimWire::Serial => crate::protocol::Wire::Serial,
        }
    }
}

/// Position of the RC transmitter's SWB switch (TRACER manual 2.3: top = command mode, middle = RC).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RcSwitch {
    /// Command (CAN / serial) control allowed.
    Top,
    /// RC mode: the transmitter has control, host motion commands are ignored.
    Middle,
}

/// Every knob of the model. `Default` is a healthy robot; docs/sim.md gives the source of each value.
#[derive(Clone, Debug, PartialEq)]
pub struct SimConfig {
    pub wire: SimWire,
    /// Distance between the wheel centres, m (manual: "wheelbase" 360 mm, which is the track).
    pub track_m: f64,
    /// Drive wheel diameter, m (assumption: hub motor, no gearbox).
    pub wheel_diameter_m: f64,
    /// Highest linear speed and highest speed of either wheel, m/s (manual: 2.3 m/s no-load).
    pub max_linear: f64,
    /// Highest angular speed, rad/s (assumption).
    pub max_angular: f64,
    /// Linear acceleration limit, m/s² (assumption).
    pub max_linear_accel: f64,
    /// Angular acceleration limit, rad/s² (assumption).
    pub max_angular_accel: f64,
    /// Open-circuit battery voltage at the start, V.
    pub battery_start_v: f64,
    /// Open-circuit voltage once `battery_capacity_ah` is used up, V (assumption).
    pub battery_empty_v: f64,
    /// Charge between `battery_start_v` and `battery_empty_v`, Ah (manual: 15 Ah pack).
    pub battery_capacity_ah: f64,
    /// Internal resistance: the voltage sags by current × resistance, Ω (assumption).
    pub battery_resistance_ohm: f64,
    /// Multiplies the charge drawn, to make the battery run down faster in demos and tests (1 = real time).
    pub battery_drain_factor: f64,
    /// Current of the electronics and lights, always drawn, A (assumption).
    pub idle_current_a: f64,
    /// Motor current per m/s of its wheel's speed, A/(m/s) (assumption).
    pub current_per_speed: f64,
    /// Motor current per m/s² of its wheel's acceleration, A/(m/s²) (assumption).
    pub current_per_accel: f64,
    /// Temperature the motor drivers cool down to, °C.
    pub ambient_temperature_c: f64,
    /// Driver heating: °C per second per A² of motor current (assumption).
    pub driver_heating: f64,
    /// Time constant of a driver cooling towards ambient, s (assumption).
    pub driver_cooling_s: f64,
    /// The RC transmitter is switched on (its SWB switch then decides RC or command mode).
    pub rc_present: bool,
    pub rc_swb: RcSwitch,
    /// Faults and events to inject at given times (`--fault NAME[@TIME]`).
    pub faults: Vec<ScheduledFault>,
    /// Communication protection: the robot stops this long after the last motion command (manual: 500 ms).
    pub command_timeout: Duration,
    /// The drive acts on the target (v, w) as it was this long ago (a delay line on the 1 ms grid): every
    /// target change, the command timeout's and a motion block's zero included; E-stop and battery
    /// cut-off still stop at once. `dead-time`.
    pub dead_time: Duration,
    /// Time constant of a first-order lag of the actual speeds behind the acceleration ramp (0: none). `lag`.
    pub lag: Duration,
    /// Each wheel's actual speed = the firmware's wheel command × its gain. `left-gain`, `right-gain`.
    pub left_gain: f64,
    pub right_gain: f64,
    /// The track the body turns with, m: the firmware mixes wheel commands with the nominal `track_m`, the
    /// body turns at (r − l) / this, and 0x221 reports that. `track-width`.
    pub effective_track_m: f64,
    /// 0x311 odometers report this × the true wheel distance. `odometer-scale`.
    pub odometer_scale: f64,
    /// Standard deviation of Gaussian noise on the reported speeds, RPM, currents and battery voltage, in
    /// units of each field's resolution (0: exact frames). `noise`.
    pub noise: f64,
    /// Seed of the noise generator: the same seed gives the same frames. `seed`.
    pub seed: u64,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            wire: SimWire::CanV2,
            track_m: crate::protocol::constants::TRACK_M,
            wheel_diameter_m: 0.15,
            max_linear: 2.3,
            max_angular: 3.0,
            max_linear_accel: 1.0,
            max_angular_accel: 2.0,
            battery_start_v: 26.0,
            battery_empty_v: 21.0,
            battery_capacity_ah: 15.0,
            battery_resistance_ohm: 0.08,
            battery_drain_factor: 1.0,
            idle_current_a: 1.0,
            current_per_speed: 2.0,
            current_per_accel: 2.0,
            ambient_temperature_c: 25.0,
            driver_heating: 0.0035,
            driver_cooling_s: 120.0,
            rc_present: false,
            rc_swb: RcSwitch::Top,
            faults: Vec::new(),
            command_timeout: crate::protocol::message::COMMAND_TIMEOUT,
            dead_time: Duration::ZERO,
            lag: Duration::ZERO,
            left_gain: 1.0,
            right_gain: 1.0,
            effective_track_m: crate::protocol::constants::TRACK_M,
            odometer_scale: 1.0,
            noise: 0.0,
            seed: 1,
        }
    }
}

/// A configuration value the model cannot work with.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("simulator setting {field} = {value} must be {rule}")]
pub struct SimConfigError {
    pub field: &'static str,
    pub value: String,
    pub rule: String,
}

#[derive(Clone, Copy)]
enum Rule {
    Positive,
    NonNegative,
    Finite,
}

impl Rule {
    fn holds(self, value: f64) -> bool {
        match self {
            Rule::Positive => value.is_finite() && value > 0.0,
            Rule::NonNegative => value.is_finite() && value >= 0.0,
            Rule::Finite => value.is_finite(),
        }
    }
    fn describe(self) -> &'static str {
        match self {
            Rule::Positive => "a finite number above 0",
            Rule::NonNegative => "a finite number, 0 or above",
            Rule::Finite => "a finite number",
        }
    }
}

impl SimConfig {
    /// Every numeric setting with its rule, mutable so `sanitized` can repair it.
    fn numbers(&mut self) -> [(&'static str, &mut f64, Rule); 22] {
        [
            ("track_m", &mut self.track_m, Rule::Positive),
            ("wheel_diameter_m", &mut self.wheel_diameter_m, Rule::Positive),
            ("max_linear", &mut self.max_linear, Rule::Positive),
            ("max_angular", &mut self.max_angular, Rule::Positive),
            ("max_linear_accel", &mut self.max_linear_accel, Rule::Positive),
            ("max_angular_accel", &mut self.max_angular_accel, Rule::Positive),
            ("battery_start_v", &mut self.battery_start_v, Rule::Positive),
            ("battery_empty_v", &mut self.battery_empty_v, Rule::NonNegative),
            ("battery_capacity_ah", &mut self.battery_capacity_ah, Rule::Positive),
            ("battery_resistance_ohm", &mut self.battery_resistance_ohm, Rule::NonNegative),
            ("battery_drain_factor", &mut self.battery_drain_factor, Rule::Positive),
            ("idle_current_a", &mut self.idle_current_a, Rule::NonNegative),
            ("current_per_speed", &mut self.current_per_speed, Rule::NonNegative),
            ("current_per_accel", &mut self.current_per_accel, Rule::NonNegative),
            ("ambient_temperature_c", &mut self.ambient_temperature_c, Rule::Finite),
            ("driver_heating", &mut self.driver_heating, Rule::NonNegative),
            ("driver_cooling_s", &mut self.driver_cooling_s, Rule::Positive),
            ("left_gain", &mut self.left_gain, Rule::Positive),
            ("right_gain", &mut self.right_gain, Rule::Positive),
            ("effective_track_m", &mut self.effective_track_m, Rule::Positive),
            ("odometer_scale", &mut self.odometer_scale, Rule::Positive),
            ("noise", &mut self.noise, Rule::NonNegative),
        ]
    }

    /// Checks every setting; the command line reports the first problem.
    pub fn validate(&self) -> Result<(), SimConfigError> {
        let mut copy = self.clone();
        for (field, value, rule) in copy.numbers() {
            if !rule.holds(*value) {
                return Err(SimConfigError { field, value: value.to_string(), rule: rule.describe().into() });
            }
        }
        if let Some((param, value)) = self.param_out_of_range() {
            return Err(SimConfigError { field: param.field, value, rule: param.allowed_text() });
        }
        if self.battery_empty_v >= self.battery_start_v {
            return Err(SimConfigError {
                field: "battery_empty_v",
                value: self.battery_empty_v.to_string(),
                rule: "below battery_start_v".into(),
            });
        }
        if self.command_timeout.is_zero() {
            return Err(SimConfigError {
                field: "command_timeout",
                value: "0s".into(),
                rule: "above 0".into(),
            });
        }
        Ok(())
    }

    /// The same configuration with every invalid setting replaced by its default, so `Chassis::new`
    /// never has to fail or panic.
    pub fn sanitized(mut self) -> Self {
        let mut defaults = SimConfig::default();
        for ((_, value, rule), (_, default, _)) in self.numbers().into_iter().zip(defaults.numbers()) {
            if !rule.holds(*value) {
                *value = *default;
            }
        }
        self.reset_params_out_of_range();
        if self.battery_empty_v >= self.battery_start_v {
            self.battery_start_v = defaults.battery_start_v;
            self.battery_empty_v = defaults.battery_empty_v;
        }
        if self.command_timeout.is_zero() {
            self.command_timeout = defaults.command_timeout;
        }
        self
    }
}

/// Why host motion commands are not being obeyed, most important first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MotionBlock {
    /// E-stop pressed: stopped at once, every motion and mode command ignored.
    EStop,
    /// Battery at or below the cut-off (`protocol::constants::BATTERY_CUTOFF_DV`): drive power cut.
    BatteryCutOff,
    /// A latched protection (driver over-temperature, over-current, motor communication) until cleared.
    LatchedFault,
    /// The RC transmitter's link is lost.
    RcLost,
    /// The RC transmitter has control (SWB in the middle).
    RcOverride,
    /// Standby (CAN: no 0x421 = 0x01 yet) or the other link's mode.
    NotInCommandMode,
}

impl MotionBlock {
    pub fn as_str(self) -> &'static str {
        match self {
            MotionBlock::EStop => "estop",
            MotionBlock::BatteryCutOff => "battery_cut_off",
            MotionBlock::LatchedFault => "latched_fault",
            MotionBlock::RcLost => "rc_lost",
            MotionBlock::RcOverride => "rc_override",
            MotionBlock::NotInCommandMode => "not_in_command_mode",
        }
    }
}

impl fmt::Display for MotionBlock {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One motor as the model sees it. Index 0 of `SimState::motors` is motor 1 (the right wheel).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotorSnapshot {
    /// Wheel speed, m/s, + = driving the robot forward.
    pub wheel_speed: f64,
    /// Shaft speed, RPM (hub motor: the wheel's), same sign as `wheel_speed`.
    pub rpm: f64,
    /// Motor current, A, never negative.
    pub current: f64,
    /// Driver temperature, °C.
    pub driver_temperature: f64,
    /// The 0x261/0x262 driver-state byte.
    pub driver_state: u8,
}

/// A read-only view of the model, for tests, the dashboard and `sim` status lines.
#[derive(Clone, Debug, PartialEq)]
pub struct SimState {
    /// Physics time: the last whole millisecond simulated.
    pub time: Duration,
    pub wire: SimWire,
    pub control_mode: ControlMode,
    /// `control_mode` as the wire reports it.
    pub control_mode_code: u8,
    /// 0 normal, 1 E-stop, 2 exception (a latched fault, battery cut-off or RC link lost).
    pub vehicle_state: u8,
    /// Why host motion is not obeyed right now, if it is not.
    pub motion_block: Option<MotionBlock>,
    /// The last accepted motion command after clamping to the chassis limits, m/s and rad/s.
    pub commanded_linear: f64,
    pub commanded_angular: f64,
    /// What the ramp heads for now, before the dead time: the command, or 0 after the timeout or while
    /// blocked.
    pub target_linear: f64,
    pub target_angular: f64,
    /// Actual speeds, m/s and rad/s (+ = forward, counter-clockwise).
    pub linear: f64,
    pub angular: f64,
    /// Motor 1 (right) and motor 2 (left).
    pub motors: [MotorSnapshot; 2],
    /// Terminal voltage under load, V.
    pub battery_voltage: f64,
    /// Total battery current, A.
    pub battery_current: f64,
    /// Remaining fraction of `battery_capacity_ah`, 0..=1.
    pub state_of_charge: f64,
    /// The system-state fault code in the wire's layout (V2 table or V1/serial table).
    pub fault_code: u16,
    /// Wheel odometers, mm, as 0x311 reports them (× `odometer_scale`).
    pub odometry_left_mm: i32,
    pub odometry_right_mm: i32,
    /// Light state as reported (count = frames sent so far).
    pub lights: Lights,
    /// Host commands obeyed and ignored (wrong mode, E-stop, another link's message, invalid value).
    pub commands_accepted: u64,
    pub commands_ignored: u64,
}

impl SimState {
    /// (left, right) wheel speeds, m/s: motor 2 and motor 1.
    pub fn wheel_speeds(&self) -> (f64, f64) {
        (self.motors[1].wheel_speed, self.motors[0].wheel_speed)
    }
}
