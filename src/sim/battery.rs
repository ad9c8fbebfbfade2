//! The battery: charge drawn, a linear open-circuit voltage, a resistive sag, and the three thresholds of
//! the TRACER manual (`protocol::constants`): warning, fault (beeping), drive cut-off.

use super::SimConfig;
// Thresholds in 0.1 V, compared with the voltage the robot reports (so a reported value at a threshold
// sets its level).
use crate::protocol::constants::{
    volts, BATTERY_CUTOFF_DV as CUT_OFF_DECIVOLTS, BATTERY_FAULT_DV as FAULT_DECIVOLTS,
    BATTERY_WARNING_DV as WARNING_DECIVOLTS,
};
/// A level clears only 0.2 V above its threshold, so the sag of a start does not make the bits flicker.
const HYSTERESIS_DECIVOLTS: u16 = 2;

/// Open-circuit voltages the battery events jump to: 0.1 V under each threshold (22.4, 21.9, 21.4 V), so
/// the level sets at once.
pub(super) const WARNING_EVENT_V: f64 = volts(WARNING_DECIVOLTS - 1);
pub(super) const LOW_EVENT_V: f64 = volts(FAULT_DECIVOLTS - 1);
pub(super) const EMPTY_EVENT_V: f64 = volts(CUT_OFF_DECIVOLTS - 1);

/// Which levels are active.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Levels {
    pub warning: bool,
    pub fault: bool,
    pub cut_off: bool,
}

#[derive(Clone, Debug)]
pub(super) struct Battery {
    start_v: f64,
    empty_v: f64,
    capacity_ah: f64,
    resistance: f64,
    drain_factor: f64,
    used_ah: f64,
    current: f64,
    levels: Levels,
}

impl Battery {
    pub fn new(config: &SimConfig) -> Self {
        let mut battery = Self {
            start_v: config.battery_start_v,
            empty_v: config.battery_empty_v,
            capacity_ah: config.battery_capacity_ah,
            resistance: config.battery_resistance_ohm,
            drain_factor: config.battery_drain_factor,
            used_ah: 0.0,
            current: config.idle_current_a,
            levels: Levels::default(),
        };
        battery.update_levels();
        battery
    }

    /// Draws `current` amperes for `seconds`.
    pub fn draw(&mut self, current: f64, seconds: f64) {
        self.current = current;
        self.used_ah = (self.used_ah + current * seconds * self.drain_factor / 3600.0).min(self.capacity_ah);
        self.update_levels();
    }

    pub fn state_of_charge(&self) -> f64 {
        (1.0 - self.used_ah / self.capacity_ah).clamp(0.0, 1.0)
    }

    pub fn open_circuit_voltage(&self) -> f64 {
        self.empty_v + (self.start_v - self.empty_v) * self.state_of_charge()
    }

    /// Terminal voltage under the present load.
    pub fn voltage(&self) -> f64 {
        (self.open_circuit_voltage() - self.current * self.resistance).max(0.0)
    }

    pub fn decivolts(&self) -> u16 {
        (self.voltage() * 10.0).round().clamp(0.0, f64::from(u16::MAX)) as u16
    }

    pub fn current(&self) -> f64 {
        self.current
    }

    pub fn levels(&self) -> Levels {
        self.levels
    }

    /// Sets the charge so the open-circuit voltage is `volts` (battery events; `start_v` = a fresh pack).
    pub fn set_open_circuit_voltage(&mut self, volts: f64) {
        let fraction = ((volts - self.empty_v) / (self.start_v - self.empty_v)).clamp(0.0, 1.0);
        self.used_ah = self.capacity_ah * (1.0 - fraction);
        self.update_levels();
    }

    fn update_levels(&mut self) {
        let dv = self.decivolts();
        let level = |active: bool, threshold: u16| {
            if active {
                dv <= threshold + HYSTERESIS_DECIVOLTS
            } else {
                dv <= threshold
            }
        };
        self.levels = Levels {
            warning: level(self.levels.warning, WARNING_DECIVOLTS),
            fault: level(self.levels.fault, FAULT_DECIVOLTS),
            cut_off: level(self.levels.cut_off, CUT_OFF_DECIVOLTS),
        };
    }
}
