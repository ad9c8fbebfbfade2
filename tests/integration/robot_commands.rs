//! `tracerctl mode`, `clear-errors` and `lights`: the real binary against the in-process simulator
//! (`--sim`, a healthy robot), and the commands' `execute` functions on sessions whose simulator is
//! configured with faults, an E-stop or an RC transmitter.

use std::time::Duration;

use tracerctl::commands::{clear_errors, lights, mode};
use tracerctl::exit::{Failure, NOT_DONE, USAGE};
use tracerctl::link::LinkChoice;
use tracerctl::protocol::message::{LIGHT_CUSTOM, VEHICLE_NORMAL};
use tracerctl::protocol::ClearTarget;
use tracerctl::protocol::LightMode;
use tracerctl::protocol::ProtocolHint;
use tracerctl::session::Session;
use tracerctl::sim::{ControlMode, FaultKind, RcSwitch, ScheduledFault, SimConfig, SimWire};

use crate::util::{stderr, stdout, tracerctl};

// ---- the real binary, --sim (healthy robot, boots in standby) ----

#[test]
fn mode_can_switches_the_simulator_out_of_standby() {
    let output = tracerctl().args(["--sim", "mode", "can"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(stdout(&output), "control mode: standby -> can (normal, 25.9 V, faults: none)\n");
}

#[test]
fn mode_standby_when_already_in_standby_says_so() {
    let output = tracerctl().args(["--sim", "mode", "standby"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(stdout(&output), "control mode: already standby (normal, 25.9 V, faults: none)\n");
}

#[test]
fn clear_errors_on_a_healthy_robot() {
    let output = tracerctl().args(["--sim", "clear-errors"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        "no faults were set\nstatus: normal, mode standby, 25.9 V, faults: none\n",
        "the drivers' disabled bit (info, normal in standby) is not a fault"
    );
}

#[test]
fn lights_custom_brightness_is_confirmed_by_0x231() {
    let output =
        tracerctl().args(["--sim", "lights", "--front", "custom", "--brightness", "30"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(stdout(&output), "lights: front custom 30 % (confirmed by 0x231)\n");
}

#[test]
fn lights_release_is_confirmed_by_0x231() {
    let output = tracerctl().args(["--sim", "lights", "--release"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        "lights: released to the firmware (confirmed by 0x231: firmware control, front on)\n"
    );
}

#[test]
fn lights_brightness_without_custom_is_a_usage_error() {
    let output =
        tracerctl().args(["--sim", "lights", "--front", "on", "--brightness", "30"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        stderr(&output),
        "tracerctl: --brightness applies only to --front custom (the other modes have a fixed brightness)\n"
    );
    assert_eq!(stdout(&output), "");

    let output = tracerctl().args(["--sim", "lights", "--front", "custom"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(stderr(&output), "tracerctl: --front custom needs --brightness PERCENT (0-100)\n");
}

#[test]
fn commands_that_send_refuse_a_replay() {
    let log = tempfile::NamedTempFile::new().unwrap();
    let path = log.path().to_str().unwrap();
    for args in [&["mode", "can"][..], &["clear-errors"], &["lights", "--release"]] {
        let output = tracerctl().args(["--replay", path]).args(args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&output).starts_with("tracerctl: --replay is read-only"),
            "{args:?}: {}",
            stderr(&output)
        );
    }
}

// ---- through the library, with a configured simulator ----

fn session(config: SimConfig) -> Session {
    Session::open(&LinkChoice::Sim, ProtocolHint::Auto, Some(config)).expect("the simulator starts")
}

fn at_start(faults: &[FaultKind]) -> SimConfig {
    SimConfig {
        faults: faults.iter().map(|&fault| ScheduledFault { at: Duration::ZERO, fault }).collect(),
        ..SimConfig::default()
    }
}

/// The exit status and the one-line error (empty on success) of a command, with what it printed.
fn outcome(result: anyhow::Result<u8>, out: Vec<u8>) -> (u8, String, String) {
    let printed = String::from_utf8(out).unwrap();
    match result {
        Ok(code) => (code, String::new(), printed),
        Err(error) => {
            let failure =
                error.downcast_ref::<Failure>().unwrap_or_else(|| panic!("not a Failure: {error:#}"));
            (failure.code, failure.message.clone(), printed)
        }
    }
}

fn run_mode(session: &Session, mode: ControlMode) -> (u8, String, String) {
    let mut out = Vec::new();
    let result =
        mode::execute(session, &mode::Options { mode, timeout: Duration::from_millis(600) }, &mut out);
    outcome(result, out)
}

fn run_clear(session: &Session, target: ClearTarget) -> (u8, String, String) {
    let mut out = Vec::new();
    let args = clear_errors::Options { target, timeout: Duration::from_millis(600) };
    let result = clear_errors::execute(session, &args, &mut out);
    outcome(result, out)
}

fn sim_mode(session: &Session) -> ControlMode {
    session.simulator().expect("a simulator").state().control_mode
}

#[test]
fn mode_can_then_standby_reaches_the_simulator() {
    let session = session(SimConfig::default());
    let (code, error, out) = run_mode(&session, ControlMode::Can);
    assert_eq!((code, error.as_str()), (0, ""));
    assert_eq!(out, "control mode: standby -> can (normal, 25.9 V, faults: none)\n");
    assert_eq!(sim_mode(&session), ControlMode::Can);

    let (code, _, out) = run_mode(&session, ControlMode::Can);
    assert_eq!((code, out.as_str()), (0, "control mode: already can (normal, 25.9 V, faults: none)\n"));

    let (code, _, out) = run_mode(&session, ControlMode::Standby);
    assert_eq!((code, out.as_str()), (0, "control mode: can -> standby (normal, 25.9 V, faults: none)\n"));
    assert_eq!(sim_mode(&session), ControlMode::Standby);
}

#[test]
fn mode_can_with_the_estop_pressed_says_so() {
    let session = session(at_start(&[FaultKind::EStop]));
    let (code, error, out) = run_mode(&session, ControlMode::Can);
    assert_eq!(code, NOT_DONE, "{error}");
    assert_eq!(out, "");
    assert!(
        error.starts_with("the robot is still in standby mode (estop, 25.9 V, faults: none), not can"),
        "{error}"
    );
    assert!(error.contains("sending 0x421 = 0x01 3 times"), "sent once and resent twice: {error}");
    assert!(error.ends_with("the E-stop is pressed: release both E-stop buttons, then try again"), "{error}");
    assert_eq!(sim_mode(&session), ControlMode::Standby);

    // Released: the same command now works.
    session.simulator().unwrap().inject(FaultKind::EStopRelease);
    std::thread::sleep(Duration::from_millis(60));
    let (code, error, out) = run_mode(&session, ControlMode::Can);
    assert_eq!(code, 0, "{error}");
    assert_eq!(out, "control mode: standby -> can (normal, 25.9 V, faults: none)\n");
}

#[test]
fn mode_can_under_rc_override_points_at_swb() {
    let session = session(SimConfig { rc_present: true, rc_swb: RcSwitch::Middle, ..SimConfig::default() });
    let (code, error, _) = run_mode(&session, ControlMode::Can);
    assert_eq!(code, NOT_DONE, "{error}");
    assert!(error.starts_with("the robot is still in rc mode (normal, "), "{error}");
    assert!(error.contains("put switch SWB at the top"), "{error}");
    assert_eq!(sim_mode(&session), ControlMode::Rc);
}

#[test]
fn mode_over_rs232_selects_serial_mode_and_refuses_the_others() {
    let session = session(SimConfig { wire: SimWire::Serial, ..SimConfig::default() });
    // RS232 reports standby as 0, the code it shares with RC mode.
    let (code, error, out) = run_mode(&session, ControlMode::Serial);
    assert_eq!(code, 0, "{error}");
    assert_eq!(out, "control mode: rc -> serial (normal, 25.9 V, faults: none)\n");
    assert_eq!(sim_mode(&session), ControlMode::Serial);

    for choice in [ControlMode::Can, ControlMode::Standby] {
        let (code, error, out) = run_mode(&session, choice);
        assert_eq!((code, out.as_str()), (USAGE, ""), "{choice:?}");
        assert!(
            error.starts_with("RS232 has no control-mode command: over --serial only `mode serial` works")
        );
    }
    assert_eq!(sim_mode(&session), ControlMode::Serial);
}

#[test]
fn clear_errors_clears_a_latched_motor_comm_fault() {
    let session = session(at_start(&[FaultKind::Motor1Comm]));
    assert_eq!(session.simulator().unwrap().state().motors[0].driver_state & 0x10, 0x10);
    let (code, error, out) = run_clear(&session, ClearTarget::All);
    assert_eq!(code, 0, "{error}");
    assert_eq!(
        out,
        "cleared: vehicle_exception [fault]\ncleared: motor1 can_disconnected [fault]\n\
         status: normal, mode standby, 25.9 V, faults: none\n"
    );
    let state = session.simulator().unwrap().state();
    assert_eq!((state.vehicle_state, state.motors[0].driver_state & 0x10), (VEHICLE_NORMAL, 0));
}

#[test]
fn clear_errors_for_the_other_motor_leaves_the_fault_and_says_why() {
    let session = session(at_start(&[FaultKind::Motor1Comm]));
    let (code, error, out) = run_clear(&session, ClearTarget::Motor2);
    assert_eq!(code, NOT_DONE, "{error}");
    assert!(
        out.contains("remaining: motor1 can_disconnected [fault] — check the internal CAN wiring"),
        "{out}"
    );
    assert!(error.starts_with("2 faults still set after sending 0x441 = 0x02 (2 times): "), "{error}");
    assert!(
        error.contains(
            "motor1 can_disconnected: not targeted by this clear: run `tracerctl clear-errors motor1`"
        ),
        "{error}"
    );
    assert_eq!(session.simulator().unwrap().state().motors[0].driver_state & 0x10, 0x10);
}

#[test]
fn clear_errors_reports_a_low_battery_as_remaining() {
    let session = session(at_start(&[FaultKind::BatteryLow]));
    let (code, error, out) = run_clear(&session, ClearTarget::All);
    assert_eq!(code, NOT_DONE, "{error}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[..2],
        [
            "remaining: battery_undervoltage_fault [fault] — charge or replace the battery; motion is cut below 21.5 V",
            "remaining: battery_undervoltage_warning [warning] — finish the task and charge soon",
        ],
        "{out}"
    );
    assert!(lines[2].starts_with("status: normal, mode standby, 21."), "{out}");
    assert!(!out.contains("cleared:"), "{out}");
    assert!(error.starts_with("2 faults still set after sending 0x441 = 0x00"), "{error}");
    assert!(
        error.contains("battery_undervoltage_fault: the cause persists: the battery is at 21."),
        "{error}"
    );
}

#[test]
fn clear_errors_over_rs232_uses_the_serial_fault_bits() {
    let session = session(SimConfig {
        wire: SimWire::Serial,
        faults: vec![ScheduledFault { at: Duration::ZERO, fault: FaultKind::Motor2Comm }],
        ..SimConfig::default()
    });
    let (code, error, out) = run_clear(&session, ClearTarget::Motor2);
    assert_eq!(code, 0, "{error}");
    assert_eq!(
        out,
        "cleared: vehicle_exception [fault]\ncleared: motor2_comm_fault [fault]\n\
         status: normal, mode serial, 25.9 V, faults: none\n",
        "the clear codes ride in serial-mode motion commands, which also select serial mode"
    );
}

#[test]
fn lights_through_the_library_reach_the_simulator() {
    let session = session(SimConfig::default());
    let args = lights::Options {
        front: Some(LightMode::Custom),
        brightness: Some(55),
        rear: None,
        rear_brightness: None,
        release: false,
        timeout: Duration::from_millis(600),
    };
    let mut out = Vec::new();
    let (code, error, out) = {
        let result = lights::execute(&session, &args, &mut out);
        outcome(result, out)
    };
    assert_eq!(code, 0, "{error}");
    assert_eq!(out, "lights: front custom 55 % (confirmed by 0x231)\n");
    let shown = session.simulator().unwrap().state().lights;
    assert_eq!((shown.enable, shown.front_mode, shown.front_brightness), (1, LIGHT_CUSTOM, 55));
}
