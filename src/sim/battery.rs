//! The battery: charge drawn, a linear open-circuit voltage, a resistive sag under load that recovers at
//! rest, and the three thresholds of the TRACER manual (`protocol::constants`): warning, fault (beeping),
//! drive cut-off, each with hysteresis in value and time so that no bit flaps (docs/sim.md, "Battery").

use super::SimConfig;
// Thresholds in 0.1 V, compared with the voltage the robot reports (so a reported value at a threshold
// sets its level).
use crate::protocol::constants::{
    volts, BATTERY_CUTOFF_DV as CUT_OFF_DECIVOLTS, BATTERY_FAULT_DV as FAULT_DECIVOLTS,
    BATTERY_WARNING_DV as WARNING_DECIVOLTS,
};
/// A level clears only 0.2 V above its threshold (hysteresis on the value) ...
const HYSTERESIS_DECIVOLTS: u16 = 2;
/// ... and changes only once its condition has held this long (hysteresis in time, as a pack monitor
/// filters): the sag of a start sets nothing, and no bit changes faster than once a second.
pub(super) const LEVEL_SET_S: f64 = 1.0;
pub(super) const LEVEL_CLEAR_S: f64 = 2.0;
/// The cut-off latches: drive power comes back only with a pack above the warning threshold (charged or
/// replaced), never by the voltage recovering at rest after the load is gone.
const CUT_OFF_RELEASE_DECIVOLTS: u16 = WARNING_DECIVOLTS;

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

/// One level with its debounce: how long the voltage has asked for the other state.
#[derive(Clone, Copy, Debug, Default)]
struct Level {
    active: bool,
    /// Seconds the reported voltage has continuously been on the other side (0: it is not).
    pending_s: f64,
}

impl Level {
    /// `set`/`clear`: whether the voltage now asks to set or clear the level; `seconds`: time since the
    /// last judgement. The level changes once the request has held for its dwell time.
    fn judge(&mut self, set: bool, clear: bool, seconds: f64) {
        let wants_change = if self.active { clear } else { set };
        if !wants_change {
            self.pending_s = 0.0;
            return;
        }
        self.pending_s += seconds;
        let dwell = if self.active { LEVEL_CLEAR_S } else { LEVEL_SET_S };
        // The 1 ms steps add up to a dwell only to within float rounding.
        if self.pending_s >= dwell - 1e-9 {
            self.active = !self.active;
            self.pending_s = 0.0;
        }
    }

    /// At once, with no dwell (a battery event, power on).
    fn force(&mut self, active: bool) {
        *self = Level { active, pending_s: 0.0 };
    }
}

#[derive(Clone, Debug)]
pub(super) struct Battery {
    start_v: f64,
    empty_v: f64,
    capacity_ah: f64,
    resistance: f64,
    drain_factor: f64,
    idle_current: f64,
    used_ah: f64,
    current: f64,
    warning: Level,
    fault: Level,
    cut_off: Level,
}

impl Battery {
    pub fn new(config: &SimConfig) -> Self {
        let mut battery = Self {
            start_v: config.battery_start_v,
            empty_v: config.battery_empty_v,
            capacity_ah: config.battery_capacity_ah,
            resistance: config.battery_resistance_ohm,
            drain_factor: config.battery_drain_factor,
            idle_current: config.idle_current_a,
            used_ah: 0.0,
            current: config.idle_current_a,
            warning: Level::default(),
            fault: Level::default(),
            cut_off: Level::default(),
        };
        battery.levels_at_rest();
        battery
    }

    /// Draws `current` amperes for `seconds`.
    pub fn draw(&mut self, current: f64, seconds: f64) {
        self.current = current;
        self.used_ah = (self.used_ah + current * seconds * self.drain_factor / 3600.0).min(self.capacity_ah);
        self.update_levels(seconds);
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
        to_decivolts(self.voltage())
    }

    pub fn current(&self) -> f64 {
        self.current
    }

    pub fn levels(&self) -> Levels {
        Levels { warning: self.warning.active, fault: self.fault.active, cut_off: self.cut_off.active }
    }

    /// Sets the charge so the open-circuit voltage is `volts` (battery events; `start_v` = a fresh pack). The
    /// levels follow at once: the event stands for a pack that has been at this voltage for a while.
    pub fn set_open_circuit_voltage(&mut self, volts: f64) {
        let fraction = ((volts - self.empty_v) / (self.start_v - self.empty_v)).clamp(0.0, 1.0);
        self.used_ah = self.capacity_ah * (1.0 - fraction);
        self.levels_at_rest();
    }

    /// The levels of this charge at rest (idle current), set at once.
    fn levels_at_rest(&mut self) {
        let rest = (self.open_circuit_voltage() - self.idle_current * self.resistance).max(0.0);
        let dv = to_decivolts(rest);
        self.warning.force(dv <= WARNING_DECIVOLTS);
        self.fault.force(dv <= FAULT_DECIVOLTS);
        self.cut_off.force(dv <= CUT_OFF_DECIVOLTS);
    }

    /// Each level sets once the reported voltage has been at or below its threshold for [`LEVEL_SET_S`],
    /// and clears once it has been above threshold + hysteresis for [`LEVEL_CLEAR_S`]; the cut-off clears
    /// only above [`CUT_OFF_RELEASE_DECIVOLTS`].
    fn update_levels(&mut self, seconds: f64) {
        let dv = self.decivolts();
        let judge = |level: &mut Level, threshold: u16, release: u16| {
            level.judge(dv <= threshold, dv > release, seconds);
        };
        judge(&mut self.warning, WARNING_DECIVOLTS, WARNING_DECIVOLTS + HYSTERESIS_DECIVOLTS);
        judge(&mut self.fault, FAULT_DECIVOLTS, FAULT_DECIVOLTS + HYSTERESIS_DECIVOLTS);
        judge(&mut self.cut_off, CUT_OFF_DECIVOLTS, CUT_OFF_RELEASE_DECIVOLTS);
    }
}

/// Volts as the robot reports them, in 0.1 V.
pub(super) fn to_decivolts(volts: f64) -> u16 {
    (volts * 10.0).round().clamp(0.0, f64::from(u16::MAX)) as u16
}
