//! The one thing to know now: which alert wins when several hold at once. The renderer draws the winner
//! (its words and colour); the order is decided here, from the app state alone.
//!
//! Worst first: the link (a replay that ended, a link that failed, a stale or missing status), then the
//! robot's fresh status (E-stop, faults that block driving, other reasons it cannot drive, the control mode,
//! warnings), then the arming state.

use super::app::{App, Arming, BatteryZone, FaultLine, StatusAge, SystemView};
use crate::protocol::Wire;

/// The alert line's subject, worst first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Alert {
    /// A replay reached its end: not a failure, the log's last values stay on screen.
    ReplayEnded,
    /// The link failed, with the link's own words.
    LinkFailed(String),
    /// No fresh system status for this long: every value shown is old.
    Stale { deciseconds: u64 },
    /// Not a single frame yet.
    NothingReceived,
    /// Frames arrive, but no system status among them.
    NoSystemStatus,
    /// The E-stop is pressed, and why the robot cannot drive.
    EStop { reason: String },
    /// Faults that block driving, worst first.
    BlockingFaults(Vec<FaultLine>),
    /// Another reason the robot cannot drive (a latched state, RC override).
    CannotDrive { reason: String },
    /// The robot is not in this link's command mode; `mode` is its control mode code on `wire`.
    NotInCommandMode { wire: Wire, mode: u8 },
    /// Drivable, with warnings (a fault bit or the battery).
    Warnings,
    /// Nothing wrong: the arming state says what happens next.
    Ready(Arming),
}

impl App {
    /// The alert that wins now: the link's first, then the robot's from its fresh status.
    pub fn alert(&self) -> Alert {
        match self.link_alert() {
            Ok(system) => self.robot_alert(system),
            Err(alert) => alert,
        }
    }

    /// The link's alert, worst first, or the fresh system status when the link has none.
    fn link_alert(&self) -> Result<SystemView, Alert> {
        let shown = &self.shown;
        if shown.link_ended {
            return Err(Alert::ReplayEnded);
        }
        if let Some(error) = &shown.link_error {
            return Err(Alert::LinkFailed(error.clone()));
        }
        match (shown.status_age, shown.system) {
            (StatusAge::Stale { deciseconds }, _) => Err(Alert::Stale { deciseconds }),
            (StatusAge::Fresh, Some(system)) => Ok(system),
            _ if !shown.received_any => Err(Alert::NothingReceived),
            _ => Err(Alert::NoSystemStatus),
        }
    }

    /// The robot's alert from its fresh status, worst first: E-stop, faults, the mode, warnings, then arming.
    fn robot_alert(&self, system: SystemView) -> Alert {
        let state = system.state();
        let faults = self.faults();
        if state.is_estop() {
            return Alert::EStop { reason: state.why_not_drivable(system.wire).unwrap_or_default() };
        }
        let blocking: Vec<FaultLine> =
            faults.iter().filter(|fault| fault.info.severity.blocks_driving()).copied().collect();
        if !blocking.is_empty() {
            return Alert::BlockingFaults(blocking);
        }
        if let Some(reason) = state.why_not_drivable(system.wire) {
            return Alert::CannotDrive { reason };
        }
        if !system.in_command_mode() {
            return Alert::NotInCommandMode { wire: system.wire, mode: system.control_mode };
        }
        let battery = BatteryZone::of(system.decivolts, self.battery_warning_dv);
        if faults.iter().any(|fault| fault.info.severity.is_problem()) || battery != BatteryZone::Ok {
            return Alert::Warnings;
        }
        Alert::Ready(self.arming)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::Limits;
    use crate::protocol::message::{VEHICLE_ESTOP, VEHICLE_EXCEPTION, VEHICLE_NORMAL};
    use crate::protocol::{ControlMode, Severity};

    /// A CAN V2 robot in command mode on 25.9 V, with a fresh status and no faults.
    fn ready() -> App {
        let mut app = App::new("can0", Limits::default(), false);
        app.shown.received_any = true;
        app.shown.status_age = StatusAge::Fresh;
        app.shown.system = Some(SystemView {
            vehicle_state: VEHICLE_NORMAL,
            control_mode: ControlMode::command_mode_of(Wire::CanV2).code(Wire::CanV2),
            decivolts: 259,
            fault_code: 0,
            wire: Wire::CanV2,
        });
        app
    }

    fn system(app: &mut App) -> &mut SystemView {
        app.shown.system.as_mut().unwrap()
    }

    /// Every condition below the link's at once: E-stop, a blocking fault, out of command mode, a warning.
    fn everything_wrong() -> App {
        let mut app = ready();
        let system = system(&mut app);
        system.vehicle_state = VEHICLE_ESTOP;
        system.control_mode = ControlMode::Standby.code(Wire::CanV2);
        system.decivolts = 221;
        // Driver over-temperature protection (blocks) and the battery's warning bit.
        system.fault_code = 0x0040 | 0x0200;
        system.wire = Wire::CanV1;
        app
    }

    #[test]
    fn the_link_comes_before_the_robot() {
        let mut app = everything_wrong();
        app.shown.link_ended = true;
        app.shown.link_error = Some("end of the replayed log".to_string());
        app.shown.status_age = StatusAge::Stale { deciseconds: 30 };
        assert_eq!(app.alert(), Alert::ReplayEnded, "an ended replay is not a failure");
        app.shown.link_ended = false;
        assert_eq!(app.alert(), Alert::LinkFailed("end of the replayed log".to_string()));
        app.shown.link_error = None;
        assert_eq!(app.alert(), Alert::Stale { deciseconds: 30 }, "a stale status hides the robot's");
        app.shown.status_age = StatusAge::Never;
        app.shown.system = None;
        assert_eq!(app.alert(), Alert::NoSystemStatus);
        app.shown.received_any = false;
        assert_eq!(app.alert(), Alert::NothingReceived);
    }

    #[test]
    fn a_fresh_status_without_a_system_state_is_not_ready() {
        let mut app = ready();
        app.shown.system = None;
        assert_eq!(app.alert(), Alert::NoSystemStatus);
    }

    #[test]
    fn the_robot_worst_first() {
        let mut app = everything_wrong();
        let Alert::EStop { reason } = app.alert() else { panic!("{:?}", app.alert()) };
        assert!(reason.contains("E-stop"), "{reason}");
        // Without the E-stop: the blocking fault, then what else stops it, then the mode, then the warnings.
        system(&mut app).vehicle_state = VEHICLE_EXCEPTION;
        let Alert::BlockingFaults(faults) = app.alert() else { panic!("{:?}", app.alert()) };
        assert_eq!(faults.iter().map(|f| f.info.name).collect::<Vec<_>>(), ["driver_overheat_protection"]);
        assert!(faults.iter().all(|f| f.info.severity.blocks_driving()));
        system(&mut app).fault_code = 0x0200;
        assert!(matches!(app.alert(), Alert::CannotDrive { .. }), "{:?}", app.alert());
        system(&mut app).vehicle_state = VEHICLE_NORMAL;
        let standby = ControlMode::Standby.code(Wire::CanV1);
        assert_eq!(app.alert(), Alert::NotInCommandMode { wire: Wire::CanV1, mode: standby });
        system(&mut app).control_mode = ControlMode::command_mode_of(Wire::CanV1).code(Wire::CanV1);
        assert_eq!(app.alert(), Alert::Warnings);
    }

    #[test]
    fn a_low_battery_alone_is_a_warning() {
        let mut app = ready();
        system(&mut app).decivolts = 221;
        assert_eq!(app.alert(), Alert::Warnings);
        system(&mut app).decivolts = 259;
        assert_eq!(app.alert(), Alert::Ready(Arming::Watching));
    }

    #[test]
    fn info_lines_do_not_warn() {
        let mut app = ready();
        // Both drivers disabled (standby-like): listed as [info], not a warning.
        for motor in &mut app.shown.motors {
            motor.driver_state = Some(0x40);
        }
        assert!(app.faults().iter().all(|f| f.info.severity == Severity::Info));
        assert_eq!(app.alert(), Alert::Ready(Arming::Watching));
    }

    #[test]
    fn ready_says_the_arming_state() {
        let mut app = ready();
        for arming in [Arming::Watching, Arming::WatchOnly, Arming::Armed] {
            app.set_arming(arming);
            assert_eq!(app.alert(), Alert::Ready(arming));
        }
    }
}
