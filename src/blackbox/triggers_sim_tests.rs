//! The watcher on the simulator's traffic: each injected fault fires its default trigger once, and ten
//! minutes of clean driving fire none (no false incident). The pure simulator is stepped exactly, as
//! src/sim/tests.rs does, with a host that drives it every 20 ms.

use std::time::Duration;

use super::*;
use crate::protocol::message::{MotionCommand, PercentMotionCommand, MODE_CAN, MODE_SERIAL};
use crate::protocol::Codec;
use crate::sim::{Chassis, SimConfig, SimWire};

fn stamp(time: Duration) -> Timestamp {
    Timestamp { secs: time.as_secs(), nanos: time.subsec_nanos(), kind: TimestampKind::Relative }
}

/// The host's motion command at `t`: a slow weave well inside the limits.
fn command(wire: SimWire, t: Duration) -> Message {
    let seconds = t.as_secs_f64();
    let linear = 1.0 * (seconds * std::f64::consts::TAU / 30.0).sin();
    let angular = 0.4 * (seconds * std::f64::consts::TAU / 17.0).sin();
    match wire {
        SimWire::CanV2 => Message::MotionCommand(MotionCommand::from_si(linear, angular).unwrap()),
        SimWire::Serial => Message::PercentMotionCommand(
            PercentMotionCommand::from_si(MODE_SERIAL, linear, angular).unwrap(),
        ),
    }
}

/// Runs the simulator with `faults` for `seconds` under a host that put it in command mode before its
/// first feedback and drives it every 20 ms; every frame of both sides goes to a default watcher, with a
/// tick every 100 ms. The triggers found, and the robot.
fn simulate_robot(wire: SimWire, faults: &[&str], seconds: u64) -> (Vec<Trigger>, Chassis) {
    let faults = faults.iter().map(|fault| fault.parse().unwrap()).collect();
    let mut robot = Chassis::new(SimConfig { wire, faults, ..SimConfig::default() });
    let mut codec = Codec::new(wire.into());
    let mut watcher = Watcher::new(TriggerSettings::default());
    let mut out = Vec::new();
    let mut feedback = Vec::new();
    if wire == SimWire::CanV2 {
        let mode = Message::ControlModeCommand(MODE_CAN);
        robot.receive(Duration::ZERO, &mode);
        watcher.frame(stamp(Duration::ZERO), &codec.encode(&mode).unwrap(), &mut out);
    }
    for period in 0..seconds * 50 {
        let t = Duration::from_millis(period * 20);
        let host = command(wire, t);
        robot.receive(t, &host);
        watcher.frame(stamp(t), &codec.encode(&host).unwrap(), &mut out);
        feedback.clear();
        robot.due_feedback(t, &mut feedback);
        for (index, message) in feedback.iter().enumerate() {
            let at = t + Duration::from_micros(100 * (index as u64 + 1));
            watcher.frame(stamp(at), &codec.encode(message).unwrap(), &mut out);
        }
        if period % 5 == 0 {
            watcher.tick(stamp(t), &mut out);
        }
    }
    (out, robot)
}

fn simulate(wire: SimWire, faults: &[&str], seconds: u64) -> Vec<Trigger> {
    simulate_robot(wire, faults, seconds).0
}

/// A trigger's cause in short: its slug, and for a fault bit where it came from and its name.
fn label(trigger: &Trigger) -> String {
    match &trigger.cause {
        Cause::Fault { source: FaultSource::System, flag } => format!("fault:{}", flag.name),
        Cause::Fault { source: FaultSource::Driver { motor }, flag } => {
            format!("fault:motor{motor}:{}", flag.name)
        }
        cause => cause.slug().to_string(),
    }
}

/// What each fault (with its recovery 3 s later, which must add nothing) fires, in any order; all between
/// the fault and the next 1.5 s.
const V2_EXPECTED: &[(&[&str], &[&str])] = &[
    (&["estop@5s", "estop-release@8s"], &["estop", "mode-change"]),
    (&["motor1-overheat@5s"], &["vehicle-exception", "fault:motor1:driver_overheat"]),
    (&["motor2-overheat@5s"], &["vehicle-exception", "fault:motor2:driver_overheat"]),
    (
        &["overcurrent@5s"],
        &["vehicle-exception", "fault:motor1:driver_overcurrent", "fault:motor2:driver_overcurrent"],
    ),
    (&["motor1-overcurrent@5s"], &["vehicle-exception", "fault:motor1:driver_overcurrent"]),
    (&["motor2-overcurrent@5s"], &["vehicle-exception", "fault:motor2:driver_overcurrent"]),
    (&["motor1-comm@5s"], &["vehicle-exception", "fault:motor1:can_disconnected"]),
    (&["motor2-comm@5s"], &["vehicle-exception", "fault:motor2:can_disconnected"]),
    // Driven, the battery at 22.4 V open-circuit sags below 22 V: the fault bit follows the warning.
    (
        &["battery-warning@5s", "battery-ok@8s"],
        &["battery-low", "fault:battery_undervoltage_warning", "fault:battery_undervoltage_fault"],
    ),
    (
        &["battery-low@5s", "battery-ok@8s"],
        &[
            "battery-low",
            "fault:battery_undervoltage_warning",
            "fault:battery_undervoltage_fault",
            "vehicle-exception",
        ],
    ),
    (
        &["battery-empty@5s", "battery-ok@8s"],
        &[
            "battery-low",
            "fault:battery_undervoltage_warning",
            "fault:battery_undervoltage_fault",
            "vehicle-exception",
        ],
    ),
    (&["rc-lost@5s", "rc-restore@8s"], &["vehicle-exception", "fault:rc_disconnected"]),
    (&["swb-middle@5s"], &["mode-change", "rc-override"]),
    (&["other-host@5s"], &["mode-change"]),
];

/// RS232 names its bits by the V1/serial table, has no RC bit, and no driver-state frames.
const SERIAL_EXPECTED: &[(&[&str], &[&str])] = &[
    (&["estop@5s", "estop-release@8s"], &["estop", "mode-change"]),
    (
        &["motor1-overheat@5s"],
        &["vehicle-exception", "fault:driver_overheat_warning", "fault:driver_overheat_protection"],
    ),
    (&["overcurrent@5s"], &["vehicle-exception", "fault:motor_overcurrent_protection"]),
    (&["motor2-overcurrent@5s"], &["vehicle-exception", "fault:motor_overcurrent_protection"]),
    (&["motor1-comm@5s"], &["vehicle-exception", "fault:motor1_comm_fault"]),
    (&["motor2-comm@5s"], &["vehicle-exception", "fault:motor2_comm_fault"]),
    (
        &["battery-warning@5s", "battery-ok@8s"],
        &["battery-low", "fault:battery_undervoltage_warning", "fault:battery_undervoltage_fault"],
    ),
    (
        &["battery-empty@5s", "battery-ok@8s"],
        &[
            "battery-low",
            "fault:battery_undervoltage_warning",
            "fault:battery_undervoltage_fault",
            "vehicle-exception",
        ],
    ),
    (&["rc-lost@5s", "rc-restore@8s"], &["vehicle-exception"]),
    (&["swb-middle@5s"], &["mode-change", "rc-override"]),
    (&["other-host@5s"], &["mode-change"]),
];

fn check(wire: SimWire, expected: &[(&[&str], &[&str])]) {
    for (faults, causes) in expected {
        let found = simulate(wire, faults, 20);
        let mut labels: Vec<String> = found.iter().map(label).collect();
        labels.sort();
        let mut wanted: Vec<String> = causes.iter().map(|cause| (*cause).to_string()).collect();
        wanted.sort();
        assert_eq!(labels, wanted, "{wire:?} {faults:?}: {found:#?}");
        for trigger in &found {
            let at = trigger.at.as_secs_f64();
            assert!((5.0..6.5).contains(&at), "{wire:?} {faults:?}: {trigger:?} is not the fault's");
        }
    }
}

#[test]
fn each_simulated_fault_fires_its_triggers_once_on_v2() {
    check(SimWire::CanV2, V2_EXPECTED);
}

#[test]
fn each_simulated_fault_fires_its_triggers_once_on_rs232() {
    check(SimWire::Serial, SERIAL_EXPECTED);
}

#[test]
fn every_simulated_fault_is_covered() {
    let covered: Vec<&str> = V2_EXPECTED
        .iter()
        .flat_map(|(faults, _)| faults.iter())
        .map(|fault| fault.split('@').next().unwrap())
        .collect();
    for fault in crate::sim::FaultKind::ALL {
        assert!(covered.contains(&fault.name()) || fault.name() == "swb-top", "{fault} is not tested");
    }
}

#[test]
fn the_rc_switch_back_to_the_top_is_a_change_into_standby() {
    // The robot dropped the host's mode when the transmitter took over (as a real one does): the switch back
    // leaves it in standby, which is reported; the host's 0x421 afterwards is not.
    let found = simulate(SimWire::CanV2, &["swb-middle@5s", "swb-top@8s"], 12);
    let lines: Vec<String> = found.iter().map(|t| format!("{} {}", t.at.secs, t.cause.describe())).collect();
    assert_eq!(
        lines,
        [
            "5 control mode changed: can -> rc",
            "5 RC override: the RC transmitter took control from can mode (switch SWB in the middle)",
            "8 control mode changed: rc -> standby",
        ]
    );
}

#[test]
fn ten_minutes_of_clean_simulated_driving_fire_nothing() {
    for wire in [SimWire::CanV2, SimWire::Serial] {
        let (found, robot) = simulate_robot(wire, &[], 600);
        assert!(found.is_empty(), "{wire:?}: {found:#?}");
        // It drove all along: the simulator obeys a motion command only when nothing blocks motion.
        assert!(robot.state().commands_accepted >= 30_000, "{wire:?}: {:?}", robot.state());
    }
}
