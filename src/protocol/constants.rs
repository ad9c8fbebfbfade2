//! The robot's facts, written once, each with the manual section it comes from (TRACER user manual
//! v2.0.0): battery thresholds and the chassis geometry. Identifiers are in [`super::id`], their feedback
//! periods in [`super::catalog`]; command limits, control modes and fault-clear codes next to the messages that carry
//! them, in [`super::message`].
//!
//! Thresholds are in 0.1 V, the unit the robot reports (0x211 / 0x151 bytes 2-3, RS232 0x01 d2-3).
//! The manual says "lower than" for each; a reported value has 0.1 V resolution, so the users choose their
//! comparison: the dashboard and the sim flag a reported value at or below a threshold, the doctor only one
//! strictly below it (its unit test pins 22.5 V as a pass).

/// Under-voltage alarm ("warning") at 22.5 V: the manual's safety notes ("charge in time when the device
/// voltage is lower than 22.5V") and Table 3.1 byte 4 bit 1 ("Alarm voltage 22.5V").
pub const BATTERY_WARNING_DV: u16 = 225;
/// Under-voltage protection ("fault"; the robot beeps but still drives) at 22 V: manual 2.1 Status
/// indication, "Replace battery" ("lower than 22V ... beep-beep-beep"), and Table 3.1 byte 4 bit 0
/// ("Protective voltage 22V").
pub const BATTERY_FAULT_DV: u16 = 220;
/// Drive and extension power cut off at 21.5 V: manual 2.1 Status indication, "Replace battery"
/// ("lower than 21.5V, TRACER will actively cut off the power supply ... and drive").
pub const BATTERY_CUTOFF_DV: u16 = 215;

/// The thresholds from highest to lowest, with the short name each is shown under.
pub const BATTERY_THRESHOLDS: [(u16, &str); 3] =
    [(BATTERY_WARNING_DV, "warning"), (BATTERY_FAULT_DV, "fault"), (BATTERY_CUTOFF_DV, "cut-off")];

/// Distance between the wheel centres, m: manual 1.2 Tech specifications, "Wheelbase (mm) 360" (on a
/// two-wheel differential drive that is the track).
pub const TRACK_M: f64 = 0.36;

/// A value in 0.1 V as volts: the nearest `f64`, so `volts(225)` is the literal `22.5`.
pub const fn volts(decivolts: u16) -> f64 {
    decivolts as f64 / 10.0
}

/// Volts to the status frame's decivolts, rounded (a configured threshold; out of range saturates).
pub fn decivolts(volts: f64) -> u16 {
    (volts * 10.0).round().clamp(0.0, f64::from(u16::MAX)) as u16
}

#[cfg(test)]
#[path = "constants_tests.rs"]
mod tests;
