//! Response and health: what the robot's own feedback says about how it answers commands.
//!
//! Pure and streaming. [`Analyzer::observe`] takes every message of a run in time order (the commands the
//! host sent and the feedback the robot sent), whatever produced them: a live `commission` run, a
//! `drive --record` file, any candump log given to `decode --summary`. The same frames give the same
//! [`Report`], so a live report and the offline analysis of its recording agree. docs/commission.md gives
//! every metric's method, thresholds and tolerances.
//!
//! The folder: [`plan`] (the commissioning drive, pure data); `stream.rs` (the [`Analyzer`]: bounded queues,
//! stretches between rests, the exact merge of a log's chunks); `segment.rs` (a stretch cut into runs of
//! one command value, each judged); one file per measurement (`steps.rs`, `braking.rs`, `holds.rs`,
//! `timeout.rs`, `battery.rs`); `refit.rs` (every step fitted again with the lag and acceleration of
//! its axis's large steps, once all are known); `sample.rs`, `series.rs` and `fit.rs` (what is kept and the arithmetic).

#[cfg(test)]
mod any_input_tests;
mod battery;
mod braking;
mod fit;
mod holds;
mod lagged_ramp;
pub mod plan;
#[cfg(test)]
mod precision_tests;
mod refit;
mod sample;
mod segment;
mod series;
#[cfg(test)]
mod sim_tests;
mod steps;
mod stream;
mod timeout;

pub use stream::Analyzer;

/// Which command a step changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// m/s.
    Linear,
    /// rad/s.
    Angular,
}

impl Axis {
    pub fn as_str(self) -> &'static str {
        match self {
            Axis::Linear => "linear",
            Axis::Angular => "angular",
        }
    }
}

/// The answer to one command step away from rest (or to another speed).
#[derive(Clone, Debug, PartialEq)]
pub struct StepResponse {
    pub axis: Axis,
    /// The command frame that made the step, µs of the log's clock.
    pub at_us: i64,
    /// Commanded before and after, m/s or rad/s.
    pub from: f64,
    pub to: f64,
    /// From the command frame to the first measured motion.
    pub dead_time_ms: Option<f64>,
    /// 10 % to 90 % of the step.
    pub rise_time_ms: Option<f64>,
    /// Beyond the commanded value, % of the step.
    pub overshoot_percent: Option<f64>,
}

/// A command to zero from motion, and what followed.
#[derive(Clone, Debug, PartialEq)]
pub struct Braking {
    pub axis: Axis,
    pub at_us: i64,
    /// Measured speed when the zero command came, m/s or rad/s.
    pub from_speed: f64,
    /// From the zero command to standstill.
    pub time_ms: f64,
    /// Travelled from the zero command to standstill, m (rad for the angular axis).
    pub distance: f64,
    /// Mean deceleration, m/s² (rad/s²).
    pub deceleration: f64,
}

/// Left against right at straight commands.
#[derive(Clone, Debug, PartialEq)]
pub struct Symmetry {
    /// Left odometer distance over right, at straight commands.
    pub left_right_gain_ratio: f64,
    pub left_m: f64,
    pub right_m: f64,
    /// Heading change per metre driven straight, degrees (+ = to the left).
    pub heading_drift_deg_per_m: f64,
}

/// The chassis as it measures itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// From spin steps: wheel speed difference over measured angular speed, m.
    pub track_width_m: Option<f64>,
    /// Wheel odometers over integrated 0x221 linear speed.
    pub odometer_scale: Option<f64>,
}

/// The robot's own stop when commands ceased.
#[derive(Clone, Debug, PartialEq)]
pub struct CommandTimeout {
    /// The last command frame before the silence, µs.
    pub last_command_us: i64,
    /// From the last command to the robot's own stop, less the dead time.
    pub timeout_ms: f64,
}

/// The battery from voltage against motor current at load steps.
#[derive(Clone, Debug, PartialEq)]
pub enum BatteryEstimate {
    Measured {
        internal_resistance_ohm: f64,
        /// Spread of the per-step estimates (standard deviation), Ω.
        spread_ohm: f64,
        open_circuit_voltage_v: f64,
        load_steps: usize,
    },
    /// Why not, in words ("no current frames", ...): never a guess.
    NotMeasurable(String),
}

/// Everything the analysis found in a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// The first 1000 steps; `steps_not_listed` counts the rest.
    pub steps: Vec<StepResponse>,
    pub steps_not_listed: u64,
    /// The first 1000 stops; `braking_not_listed` counts the rest.
    pub braking: Vec<Braking>,
    pub braking_not_listed: u64,
    pub symmetry: Option<Symmetry>,
    pub geometry: Geometry,
    /// The first time commands ceased while the robot moved.
    pub command_timeout: Option<CommandTimeout>,
    pub battery: BatteryEstimate,
    /// Motion command frames seen (0: a log of feedback only, nothing to analyse).
    pub command_frames: u64,
}

impl Report {
    fn from_found(found: &segment::Found) -> Self {
        let load_steps = &found.load_steps.items;
        let (steps, command_timeout) =
            refit::refit(&found.steps.items, &found.step_fits.items, found.timeout.as_ref());
        Self {
            steps,
            steps_not_listed: found.steps.not_listed,
            braking: found.braking.items.clone(),
            braking_not_listed: found.braking.not_listed,
            symmetry: found.holds.symmetry(),
            geometry: found.holds.geometry(),
            command_timeout,
            battery: battery::estimate(load_steps, found.current_frames, found.voltage_frames),
            command_frames: found.command_frames,
        }
    }
}
