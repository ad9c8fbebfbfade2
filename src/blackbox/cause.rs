//! Why an incident was opened: each trigger's cause, its slug (the incident directory's last word) and one
//! line for people. Pure.

use std::time::Duration;

use crate::protocol::error_frame::ErrorFrame;
use crate::protocol::{ControlMode, FlagInfo, FrameId, Wire};

/// Which frame a fault bit came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaultSource {
    /// The system state's fault bytes (0x211, V1 0x151, RS232 0xAA01).
    System,
    /// A motor driver's state byte (0x261 / 0x262), motor 1 or 2.
    Driver { motor: u8 },
}

/// The CAN controller's error state, as error frames report it (linux/can/error.h).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum BusState {
    ErrorActive,
    ErrorWarning,
    ErrorPassive,
    BusOff,
}

impl BusState {
    pub fn name(self) -> &'static str {
        match self {
            BusState::ErrorActive => "error-active",
            BusState::ErrorWarning => "error-warning",
            BusState::ErrorPassive => "error-passive",
            BusState::BusOff => "bus-off",
        }
    }

    /// The state an error frame reports, or `self` when it reports none (a bus error, a lost arbitration).
    pub fn after(self, error: &ErrorFrame) -> BusState {
        const RESTARTED: u32 = 0x100;
        const BACK_TO_ACTIVE: u8 = 0x40;
        const PASSIVE: u8 = 0x10 | 0x20;
        const WARNING: u8 = 0x04 | 0x08;
        if error.is_bus_off() {
            BusState::BusOff
        } else if error.controller & PASSIVE != 0 {
            BusState::ErrorPassive
        } else if error.controller & WARNING != 0 {
            BusState::ErrorWarning
        } else if error.classes & RESTARTED != 0 || error.controller & BACK_TO_ACTIVE != 0 {
            BusState::ErrorActive
        } else {
            self
        }
    }
}

/// What made a trigger fire.
#[derive(Clone, Debug, PartialEq)]
pub enum Cause {
    /// The vehicle state went to E-stop (1).
    EStop,
    /// A fault bit of severity warning or worse was set (`[info]` bits never trigger).
    Fault { source: FaultSource, flag: FlagInfo },
    /// The vehicle state went to exception (2): a latched fault, battery cut-off or the RC link lost.
    VehicleException,
    /// The reported control mode changed (codes as reported on `wire`).
    ModeChange { wire: Wire, from: u8, to: u8 },
    /// The RC transmitter took control from a host's command mode (`from`).
    RcOverride { wire: Wire, from: u8 },
    /// No system status (`id`) for longer than `limit` (its period x 5).
    LinkSilence { id: FrameId, limit: Duration },
    /// The battery went below the warning threshold.
    BatteryLow { volts: f64, threshold: f64 },
    /// A CAN error frame (the first after a quiet re-arm time).
    ErrorFrame { error: ErrorFrame },
    /// The CAN controller's error state got worse.
    BusState { from: BusState, to: BusState },
    /// A `--trigger` expression became true; `detail` says on which value.
    Expression { text: String, detail: String },
    /// The operator's mark (`record --mark`, SIGUSR1).
    Mark { note: String },
}

impl Cause {
    /// A word for a directory name, `[a-z0-9-]+`.
    pub fn slug(&self) -> &'static str {
        match self {
            Cause::EStop => "estop",
            Cause::Fault { .. } => "fault",
            Cause::VehicleException => "vehicle-exception",
            Cause::ModeChange { .. } => "mode-change",
            Cause::RcOverride { .. } => "rc-override",
            Cause::LinkSilence { .. } => "link-silence",
            Cause::BatteryLow { .. } => "battery-low",
            Cause::ErrorFrame { .. } => "error-frame",
            Cause::BusState { .. } => "bus-state",
            Cause::Expression { .. } => "trigger",
            Cause::Mark { .. } => "mark",
        }
    }

    /// One line for people.
    pub fn describe(&self) -> String {
        match self {
            Cause::EStop => "E-stop pressed".to_string(),
            Cause::Fault { source, flag } => {
                let place = match source {
                    FaultSource::System => String::new(),
                    FaultSource::Driver { motor } => format!("motor {motor} driver: "),
                };
                format!("fault bit set: {place}{} [{}]: {}", flag.name, flag.severity, flag.meaning)
            }
            Cause::VehicleException => {
                "vehicle state exception (a latched fault, battery cut-off or the RC link lost)".to_string()
            }
            Cause::ModeChange { wire, from, to } => {
                format!("control mode changed: {} -> {}", mode_name(*wire, *from), mode_name(*wire, *to))
            }
            Cause::RcOverride { wire, from } => format!(
                "RC override: the RC transmitter took control from {} mode (switch SWB in the middle)",
                mode_name(*wire, *from)
            ),
            Cause::LinkSilence { id, limit } => {
                format!("link silence: no system status ({id}) for more than {} ms", limit.as_millis())
            }
            Cause::BatteryLow { volts, threshold } => {
                format!("battery {volts:.1} V, below the warning threshold of {threshold:.1} V")
            }
            Cause::ErrorFrame { error } => {
                let classes: Vec<&str> = error.class_names().collect();
                let controller: Vec<&str> = error.controller_names().collect();
                let classes =
                    if classes.is_empty() { "no class set".to_string() } else { classes.join(", ") };
                if controller.is_empty() {
                    format!("CAN error frame: {classes}")
                } else {
                    format!("CAN error frame: {classes} ({})", controller.join(", "))
                }
            }
            Cause::BusState { from, to } => format!("CAN bus state: {} -> {}", from.name(), to.name()),
            Cause::Expression { text, detail } => format!("trigger {text}: {detail}"),
            Cause::Mark { note } if note.trim().is_empty() => "mark".to_string(),
            Cause::Mark { note } => format!("mark: {}", note.trim()),
        }
    }
}

/// A reported mode's name: `can`, `0x07`; V1/RS232's 0 is `rc/standby`, as those wires report both as 0.
fn mode_name(wire: Wire, code: u8) -> String {
    if wire != Wire::CanV2 && code == 0 {
        "rc/standby".to_string()
    } else {
        ControlMode::describe(wire, code)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::faults::FlagTable;
    use crate::protocol::CanFrame;

    fn error(class: u32, data: &[u8]) -> ErrorFrame {
        ErrorFrame::from_frame(&CanFrame::new_error(class, data).unwrap()).unwrap()
    }

    #[test]
    fn every_cause_has_a_slug_fit_for_a_directory_and_a_line() {
        let causes = [
            Cause::EStop,
            Cause::Fault { source: FaultSource::Driver { motor: 1 }, flag: FlagTable::DriverState.info(3) },
            Cause::VehicleException,
            Cause::ModeChange { wire: Wire::CanV2, from: 1, to: 3 },
            Cause::RcOverride { wire: Wire::Serial, from: 2 },
            Cause::LinkSilence { id: FrameId::Standard(0x211), limit: Duration::from_millis(100) },
            Cause::BatteryLow { volts: 22.4, threshold: 22.5 },
            Cause::ErrorFrame { error: error(0x004, &[0, 0x01, 0, 0, 0, 0, 0, 0]) },
            Cause::BusState { from: BusState::ErrorActive, to: BusState::BusOff },
            Cause::Expression { text: "current>15".into(), detail: "current = 16.2 (0x251)".into() },
            Cause::Mark { note: " wheel slipped ".into() },
        ];
        let lines: Vec<String> = causes.iter().map(Cause::describe).collect();
        assert_eq!(
            lines,
            [
                "E-stop pressed",
                "fault bit set: motor 1 driver: driver_overheat [warning]: driver over-temperature (SDK layout)",
                "vehicle state exception (a latched fault, battery cut-off or the RC link lost)",
                "control mode changed: can -> rc",
                "RC override: the RC transmitter took control from serial mode (switch SWB in the middle)",
                "link silence: no system status (0x211) for more than 100 ms",
                "battery 22.4 V, below the warning threshold of 22.5 V",
                "CAN error frame: controller_problem (rx_overflow)",
                "CAN bus state: error-active -> bus-off",
                "trigger current>15: current = 16.2 (0x251)",
                "mark: wheel slipped",
            ]
        );
        let slugs: Vec<&str> = causes.iter().map(Cause::slug).collect();
        assert_eq!(
            slugs,
            [
                "estop",
                "fault",
                "vehicle-exception",
                "mode-change",
                "rc-override",
                "link-silence",
                "battery-low",
                "error-frame",
                "bus-state",
                "trigger",
                "mark"
            ]
        );
        for slug in slugs {
            assert!(
                slug.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-'),
                "{slug}"
            );
        }
        assert_eq!(Cause::Mark { note: String::new() }.describe(), "mark");
    }

    #[test]
    fn the_bus_state_follows_the_error_frames() {
        let active = BusState::ErrorActive;
        assert_eq!(active.after(&error(0x004, &[0, 0x08, 0, 0, 0, 0, 96, 0])), BusState::ErrorWarning);
        assert_eq!(active.after(&error(0x004, &[0, 0x20, 0, 0, 0, 0, 128, 0])), BusState::ErrorPassive);
        assert_eq!(active.after(&error(0x040, &[])), BusState::BusOff);
        assert_eq!(BusState::BusOff.after(&error(0x100, &[])), BusState::ErrorActive);
        assert_eq!(BusState::ErrorPassive.after(&error(0x004, &[0, 0x40, 0, 0, 0, 0, 0, 0])), active);
        // A bus error or lost arbitration says nothing of the state.
        assert_eq!(BusState::ErrorPassive.after(&error(0x080, &[])), BusState::ErrorPassive);
        assert_eq!(active.after(&error(0x002, &[])), active);
    }
}
