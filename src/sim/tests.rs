//! Behaviour of the virtual TRACER, each test against the documented numbers.

use std::time::Duration;

use super::chassis::*;
use super::*;
use crate::protocol::faults::{FlagTable, Flags};
use crate::protocol::message::*;
use crate::protocol::LightMode;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

fn chassis(config: SimConfig) -> Chassis {
    Chassis::new(config)
}

fn can() -> Chassis {
    chassis(SimConfig::default())
}

fn serial() -> Chassis {
    chassis(SimConfig { wire: SimWire::Serial, ..SimConfig::default() })
}

fn with_faults(wire: SimWire, faults: &[&str]) -> Chassis {
    let faults = faults.iter().map(|f| f.parse().unwrap()).collect();
    chassis(SimConfig { wire, faults, ..SimConfig::default() })
}

fn motion(linear: f64, angular: f64) -> Message {
    Message::MotionCommand(
        MotionCommand::from_si(
            linear.clamp(-LINEAR_LIMIT, LINEAR_LIMIT),
            angular.clamp(-ANGULAR_LIMIT, ANGULAR_LIMIT),
        )
        .unwrap(),
    )
}

fn raw_motion(linear_mm_s: i16, angular_mrad_s: i16) -> Message {
    Message::MotionCommand(MotionCommand { linear_mm_s, angular_mrad_s })
}

fn serial_motion(linear_percent: i8, angular_percent: i8, fault_clear: u8) -> Message {
    Message::PercentMotionCommand(PercentMotionCommand {
        control_mode: MODE_SERIAL,
        fault_clear,
        linear_percent,
        angular_percent,
        ..PercentMotionCommand::default()
    })
}

/// A CAN robot already in command mode at time 0.
fn can_commanded() -> Chassis {
    let mut robot = can();
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    robot
}

/// Sends `command` every 20 ms from `from` (inclusive) to `to` (exclusive), stepping every millisecond.
fn hold(robot: &mut Chassis, command: &Message, from: u64, to: u64) {
    for start in (from..to).step_by(20) {
        robot.receive(ms(start), command);
        for t in start..(start + 20).min(to) {
            robot.step(ms(t + 1));
        }
    }
}

fn feedback(robot: &mut Chassis, t: Duration) -> Vec<Message> {
    let mut out = Vec::new();
    robot.due_feedback(t, &mut out);
    out
}

fn system_states(messages: &[Message]) -> Vec<SystemState> {
    messages.iter().filter_map(|m| if let Message::SystemState(s) = m { Some(*s) } else { None }).collect()
}

fn low_speed(messages: &[Message], motor: u8) -> Vec<MotorLowSpeed> {
    messages
        .iter()
        .filter_map(|m| match m {
            Message::MotorLowSpeed(ls) if ls.motor == motor => Some(*ls),
            _ => None,
        })
        .collect()
}

/// The system state a full feedback batch at `t` carries (resets the schedule by asking late is fine).
fn reported(robot: &mut Chassis, t: Duration) -> SystemState {
    let mut out = Vec::new();
    robot.due_feedback(t, &mut out);
    *system_states(&out).last().unwrap_or_else(|| panic!("no system state due at {t:?}"))
}

fn close(actual: f64, expected: f64, tolerance: f64) {
    assert!((actual - expected).abs() <= tolerance, "{actual} is not within {tolerance} of {expected}");
}

// ---- modes ----

#[test]
fn boots_in_standby_and_ignores_motion_until_0x421() {
    let mut robot = can();
    let state = robot.state();
    assert_eq!(state.control_mode, ControlMode::Standby);
    assert_eq!(state.motion_block, Some(MotionBlock::NotInCommandMode));
    let system = reported(&mut robot, ms(0));
    assert_eq!(
        (system.vehicle_state, system.control_mode, system.fault_code),
        (VEHICLE_NORMAL, MODE_STANDBY, 0)
    );
    // 26.0 V open-circuit minus 1 A idle x 0.08 ohm = 25.92 V.
    assert_eq!(system.battery_decivolts, 259);

    hold(&mut robot, &motion(1.0, 0.0), 0, 200);
    assert_eq!(robot.state().linear, 0.0);
    assert_eq!(robot.state().commands_ignored, 10);

    robot.receive(ms(200), &Message::ControlModeCommand(MODE_CAN));
    assert_eq!(robot.state().control_mode, ControlMode::Can);
    assert_eq!(reported(&mut robot, ms(200)).control_mode, MODE_CAN);
    hold(&mut robot, &motion(1.0, 0.0), 200, 300);
    close(robot.state().linear, 0.1, 1e-9);

    // Back to standby: the target drops to 0 and further motion is ignored.
    robot.receive(ms(300), &Message::ControlModeCommand(MODE_STANDBY));
    hold(&mut robot, &motion(1.0, 0.0), 300, 500);
    assert_eq!(robot.state().linear, 0.0);
    assert_eq!(reported(&mut robot, ms(500)).control_mode, MODE_STANDBY);

    // Unknown modes change nothing.
    robot.receive(ms(500), &Message::ControlModeCommand(7));
    assert_eq!(robot.state().control_mode, ControlMode::Standby);
}

#[test]
fn mode_serial_over_can_stops_can_motion() {
    let mut robot = can_commanded();
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_SERIAL));
    assert_eq!(robot.state().control_mode_code, MODE_SERIAL);
    hold(&mut robot, &motion(1.0, 0.0), 0, 100);
    assert_eq!(robot.state().linear, 0.0);
}

// ---- motion ----

#[test]
fn ramp_respects_the_acceleration_limits() {
    let mut robot = can_commanded();
    hold(&mut robot, &motion(1.0, 0.0), 0, 100);
    close(robot.state().linear, 0.1, 1e-9);
    hold(&mut robot, &motion(1.0, 0.0), 100, 500);
    close(robot.state().linear, 0.5, 1e-9);
    hold(&mut robot, &motion(1.0, 0.0), 500, 1500);
    assert_eq!(robot.state().linear, 1.0);
    // Braking from 1 m/s to -0.5 m/s takes 1.5 s at 1 m/s².
    hold(&mut robot, &motion(-0.5, 0.0), 1500, 2250);
    close(robot.state().linear, 0.25, 1e-9);
    hold(&mut robot, &motion(-0.5, 0.0), 2250, 3000);
    assert_eq!(robot.state().linear, -0.5);

    let mut robot = can_commanded();
    hold(&mut robot, &motion(0.0, 0.7), 0, 100);
    close(robot.state().angular, 0.2, 1e-9);
}

#[test]
fn pure_rotation_kinematics_and_rpm() {
    let mut robot = can_commanded();
    // 1 rad/s is beyond the SI constructor's 0.7853 limit; the wire carries it fine.
    hold(&mut robot, &raw_motion(0, 1000), 0, 1000);
    let state = robot.state();
    assert_eq!((state.linear, state.angular), (0.0, 1.0));
    let [right, left] = state.motors;
    close(right.wheel_speed, 0.18, 1e-12);
    close(left.wheel_speed, -0.18, 1e-12);
    assert_eq!(state.wheel_speeds(), (left.wheel_speed, right.wheel_speed));
    let rpm = 0.18 / (std::f64::consts::PI * 0.15) * 60.0;
    close(rpm, 22.918, 1e-3);
    close(right.rpm, rpm, 1e-9);
    close(left.rpm, -rpm, 1e-9);

    let out = feedback(&mut robot, ms(1000));
    let high: Vec<_> =
        out.iter().filter_map(|m| if let Message::MotorHighSpeed(h) = m { Some(*h) } else { None }).collect();
    assert_eq!(high.iter().map(|h| (h.motor, h.rpm)).collect::<Vec<_>>(), [(1, 23), (2, -23)]);
    // Steady 0.18 m/s: 2 A/(m/s) x 0.18 = 0.36 A -> 4 deciamps, positive on both sides.
    assert_eq!(high.iter().map(|h| h.current_deciamps).collect::<Vec<_>>(), [4, 4]);
    assert!(out.contains(&Message::MotionState(MotionState {
        linear_mm_s: 0,
        angular_mrad_s: 1000,
        count: 0
    })));
}

#[test]
fn arc_kinematics() {
    let mut robot = can_commanded();
    hold(&mut robot, &raw_motion(500, 500), 0, 1000);
    let (left, right) = robot.state().wheel_speeds();
    close(left, 0.5 - 0.5 * 0.18, 1e-12);
    close(right, 0.5 + 0.5 * 0.18, 1e-12);
}

#[test]
fn odometry_integrates_wheel_distance() {
    let mut robot = can_commanded();
    hold(&mut robot, &motion(0.5, 0.0), 0, 500);
    // The ramp to 0.5 m/s covers v²/2a = 125 mm.
    let state = robot.state();
    assert_eq!((state.odometry_left_mm, state.odometry_right_mm), (125, 125));
    hold(&mut robot, &motion(0.5, 0.0), 500, 2500);
    let state = robot.state();
    assert_eq!((state.odometry_left_mm, state.odometry_right_mm), (1125, 1125));
    let out = feedback(&mut robot, ms(2500));
    assert!(out.contains(&Message::Odometry(Odometry { left_mm: 1125, right_mm: 1125 })));

    // Turning on the spot: the wheels run apart.
    hold(&mut robot, &raw_motion(0, 1000), 2500, 5000);
    let (left, right) = robot.odometry_m();
    assert!(left < 1.125 && right > 1.125, "{left} {right}");
    close((left + right) / 2.0, 1.125 + 0.125, 1e-9); // the linear ramp-down from 0.5 m/s adds 125 mm
}

#[test]
fn stops_500_ms_after_the_last_motion_command() {
    let mut robot = can_commanded();
    robot.receive(ms(0), &motion(1.0, 0.0));
    robot.step(ms(499));
    assert_eq!(robot.state().target_linear, 1.0);
    robot.step(ms(500));
    close(robot.state().linear, 0.5, 1e-9);
    assert_eq!(robot.state().target_linear, 0.0);
    assert_eq!(robot.state().commanded_linear, 1.0);
    robot.step(ms(750));
    close(robot.state().linear, 0.25, 1e-9);
    robot.step(ms(1000));
    assert_eq!(robot.state().linear, 0.0);
    // Still in command mode: a new command moves it again.
    robot.receive(ms(2000), &motion(1.0, 0.0));
    robot.step(ms(2100));
    close(robot.state().linear, 0.1, 1e-9);
}

#[test]
fn commands_within_the_timeout_keep_it_moving() {
    let mut robot = can_commanded();
    for t in (0..3000).step_by(400) {
        robot.receive(ms(t), &motion(0.3, 0.0));
    }
    robot.step(ms(3000));
    assert_eq!(robot.state().linear, 0.3);
}

#[test]
fn huge_and_odd_commands_are_clamped_to_the_chassis_limits() {
    let mut robot = can_commanded();
    hold(&mut robot, &raw_motion(i16::MAX, 0), 0, 4000);
    assert_eq!(robot.state().commanded_linear, 2.3);
    close(robot.state().linear, 2.3, 1e-12);
    hold(&mut robot, &raw_motion(i16::MIN, i16::MAX), 4000, 12_000);
    let state = robot.state();
    // Angular clamped to 3 rad/s, then both scaled so the outer wheel does 2.3 m/s.
    close(state.commanded_angular / state.commanded_linear, -3.0 / 2.3, 1e-12);
    let (left, right) = state.wheel_speeds();
    close(left.abs().max(right.abs()), 2.3, 1e-9);
    assert!(state.linear.abs() <= 2.3 && state.angular.abs() <= 3.0);
}

// ---- feedback timing ----

/// Drives `robot` with the given step sizes (µs) over one simulated second; returns (time, message).
fn collect_second(robot: &mut Chassis, steps_us: impl Fn(u64) -> u64) -> Vec<(Duration, Message)> {
    let mut out = Vec::new();
    let mut batch = Vec::new();
    let mut t = 0u64;
    let mut i = 0;
    while t < 1_000_000 {
        let now = Duration::from_micros(t);
        robot.step(now);
        batch.clear();
        robot.due_feedback(now, &mut batch);
        out.extend(batch.iter().map(|m| (now, *m)));
        t += steps_us(i).max(1);
        i += 1;
    }
    out
}

#[test]
fn feedback_periods_hold_for_any_step_pattern() {
    let mut lcg = 12345u64;
    let mut random = move |low: u64, high: u64| {
        lcg = lcg.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        low + (lcg >> 33) % (high - low + 1)
    };
    let irregular: Vec<u64> = (0..3000).map(|_| random(1, 20_000)).collect();
    let sub_ms: Vec<u64> = (0..3000).map(|_| random(300, 1_700)).collect();
    type Pattern = (&'static str, Box<dyn Fn(u64) -> u64>);
    let patterns: Vec<Pattern> = vec![
        ("1 ms", Box::new(|_| 1_000)),
        ("3 ms", Box::new(|_| 3_000)),
        ("7 ms", Box::new(|_| 7_000)),
        ("19 ms", Box::new(|_| 19_000)),
        ("20 ms", Box::new(|_| 20_000)),
        ("irregular 1-20 ms", Box::new(move |i| irregular[i as usize])),
        ("irregular 0.3-1.7 ms", Box::new(move |i| sub_ms[i as usize])),
    ];
    for (name, steps) in patterns {
        let mut robot = can();
        let out = collect_second(&mut robot, steps);
        let system: Vec<_> = out
            .iter()
            .filter_map(|(t, m)| if let Message::SystemState(s) = m { Some((*t, s.count)) } else { None })
            .collect();
        assert_eq!(system.len(), 50, "{name}");
        for (k, (t, count)) in system.iter().enumerate() {
            // The k-th frame goes out in the call that first reaches k x 20 ms.
            assert_eq!(t.as_micros() / 20_000, k as u128, "{name}: frame {k} at {t:?}");
            assert_eq!(*count, k as u8, "{name}");
        }
        let count = |id: fn(&Message) -> bool| out.iter().filter(|(_, m)| id(m)).count();
        assert_eq!(count(|m| matches!(m, Message::MotionState(_))), 50, "{name}");
        assert_eq!(count(|m| matches!(m, Message::LightState(_))), 50, "{name}");
        assert_eq!(count(|m| matches!(m, Message::Odometry(_))), 50, "{name}");
        assert_eq!(count(|m| matches!(m, Message::MotorHighSpeed(h) if h.motor == 1)), 50, "{name}");
        assert_eq!(count(|m| matches!(m, Message::MotorHighSpeed(h) if h.motor == 2)), 50, "{name}");
        assert_eq!(count(|m| matches!(m, Message::MotorLowSpeed(l) if l.motor == 1)), 10, "{name}");
        assert_eq!(count(|m| matches!(m, Message::MotorLowSpeed(l) if l.motor == 2)), 10, "{name}");
        let slow: Vec<_> = out
            .iter()
            .filter(|(_, m)| matches!(m, Message::MotorLowSpeed(l) if l.motor == 1))
            .map(|(t, _)| t.as_micros() / 100_000)
            .collect();
        assert_eq!(slow, (0..10).collect::<Vec<u128>>(), "{name}");
    }
}

#[test]
fn a_late_call_gets_one_frame_and_the_grid_is_kept() {
    let mut robot = can();
    let first = feedback(&mut robot, ms(0));
    assert_eq!(first.len(), 8, "six 20 ms frames and two 100 ms frames");
    let late = feedback(&mut robot, ms(95));
    assert_eq!(late.len(), 6, "one of each 20 ms frame, no burst, no 100 ms frame");
    assert_eq!(system_states(&late)[0].count, 1);
    assert!(feedback(&mut robot, ms(99)).is_empty());
    let on_grid = feedback(&mut robot, ms(100));
    assert_eq!(on_grid.len(), 8);
    assert_eq!(system_states(&on_grid)[0].count, 2);
    assert!(feedback(&mut robot, ms(119)).is_empty());
    assert_eq!(feedback(&mut robot, ms(120)).len(), 6);
    // Time going backwards emits nothing and changes nothing.
    let before = robot.state();
    assert!(feedback(&mut robot, ms(50)).is_empty());
    assert_eq!(robot.state(), before);
}

#[test]
fn counts_increment_per_frame_and_wrap() {
    let mut robot = can();
    let mut systems = Vec::new();
    let mut lights = Vec::new();
    for k in 0..300u64 {
        for message in feedback(&mut robot, ms(k * 20)) {
            match message {
                Message::SystemState(s) => systems.push(s.count),
                Message::LightState(l) => lights.push(l.count),
                _ => {}
            }
        }
    }
    let expected: Vec<u8> = (0..300u32).map(|k| k as u8).collect();
    assert_eq!(systems, expected);
    assert_eq!(lights, expected);
    assert_eq!(systems[255..258], [255, 0, 1]);
}

#[test]
fn can_and_serial_feedback_sets() {
    let kinds = |messages: &[Message]| messages.iter().map(|m| m.name()).collect::<Vec<_>>();
    let mut robot = can();
    assert_eq!(
        kinds(&feedback(&mut robot, ms(0))),
        [
            "system_state",
            "motion_state",
            "light_state",
            "motor_high_speed",
            "motor_high_speed",
            "odometry",
            "motor_low_speed",
            "motor_low_speed"
        ]
    );
    let mut robot = serial();
    let out = feedback(&mut robot, ms(0));
    assert_eq!(
        kinds(&out),
        ["system_state", "motion_state", "motor_high_speed", "motor_high_speed", "light_state"]
    );
    assert!(matches!(out[2], Message::MotorDriverState(MotorDriverState { motor: 1, .. })));
    assert!(matches!(
        out[3],
        Message::MotorDriverState(MotorDriverState { motor: 2, driver_temperature: 25, .. })
    ));
    // Serial counts advance per kind, like SerialEncoder's frame ids.
    let next = feedback(&mut robot, ms(20));
    assert!(matches!(next[1], Message::MotionState(MotionState { count: 1, .. })));
    assert!(matches!(next[3], Message::MotorDriverState(MotorDriverState { count: 1, .. })));
    // Every message the model emits can be encoded for its wire.
    for message in feedback(&mut can(), ms(0)) {
        crate::protocol::can::encode_v2(&message).unwrap();
    }
    for message in out {
        crate::protocol::serial::encode(&message, 0).unwrap();
    }
}

#[test]
fn version_request_is_answered() {
    let mut robot = can();
    feedback(&mut robot, ms(0));
    robot.receive(ms(5), &Message::VersionRequest);
    let out = feedback(&mut robot, ms(5));
    assert_eq!(out, [Message::VersionResponse(SIM_VERSION)]);
    assert!(feedback(&mut robot, ms(6)).is_empty());
}

// ---- RC, E-stop ----

#[test]
fn rc_override_ignores_the_host() {
    let config = SimConfig { rc_present: true, rc_swb: RcSwitch::Middle, ..SimConfig::default() };
    let mut robot = chassis(config);
    assert_eq!(robot.state().control_mode, ControlMode::Rc);
    assert_eq!(reported(&mut robot, ms(0)).control_mode, MODE_RC);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(1.0, 0.0), 0, 200);
    let state = robot.state();
    assert_eq!(
        (state.linear, state.control_mode, state.motion_block),
        (0.0, ControlMode::Rc, Some(MotionBlock::RcOverride))
    );

    // SWB to the top: standby until 0x421.
    robot.inject(ms(200), FaultKind::SwbTop);
    assert_eq!(reported(&mut robot, ms(200)).control_mode, MODE_STANDBY);
    robot.receive(ms(200), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(1.0, 0.0), 200, 700);
    close(robot.state().linear, 0.5, 1e-9);

    // SWB back to the middle while driving: RC takes over, the robot ramps down, the host mode is gone.
    robot.inject(ms(700), FaultKind::SwbMiddle);
    hold(&mut robot, &motion(1.0, 0.0), 700, 900);
    close(robot.state().linear, 0.3, 1e-9);
    assert_eq!(reported(&mut robot, ms(900)).control_mode, MODE_RC);
    robot.inject(ms(900), FaultKind::SwbTop);
    assert_eq!(robot.state().control_mode, ControlMode::Standby);

    // Serial reports RC as 0.
    let config = SimConfig {
        wire: SimWire::Serial,
        rc_present: true,
        rc_swb: RcSwitch::Middle,
        ..SimConfig::default()
    };
    let mut robot = chassis(config);
    hold(&mut robot, &serial_motion(50, 0, 0), 0, 100);
    assert_eq!(robot.state().linear, 0.0);
    assert_eq!(reported(&mut robot, ms(100)).control_mode, 0);
}

#[test]
fn rc_switch_is_ignored_when_the_transmitter_is_off() {
    let config = SimConfig { rc_present: false, rc_swb: RcSwitch::Middle, ..SimConfig::default() };
    let mut robot = chassis(config);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    assert_eq!(robot.state().control_mode, ControlMode::Can);
}

#[test]
fn estop_stops_at_once_and_needs_0x421_after_release() {
    let mut robot = can_commanded();
    hold(&mut robot, &motion(0.5, 0.0), 0, 1000);
    assert_eq!(robot.state().linear, 0.5);
    robot.inject(ms(1000), FaultKind::EStop);
    let state = robot.state();
    assert_eq!(
        (state.linear, state.vehicle_state, state.control_mode),
        (0.0, VEHICLE_ESTOP, ControlMode::Standby)
    );
    assert_eq!(state.motors[0].current, 0.0);
    let system = reported(&mut robot, ms(1000));
    assert_eq!((system.vehicle_state, system.control_mode), (VEHICLE_ESTOP, MODE_STANDBY));

    // While pressed, mode and motion commands are ignored.
    robot.receive(ms(1000), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(0.5, 0.0), 1000, 1200);
    assert_eq!(robot.state().linear, 0.0);
    assert_eq!(robot.state().motion_block, Some(MotionBlock::EStop));

    robot.inject(ms(1200), FaultKind::EStopRelease);
    let system = reported(&mut robot, ms(1200));
    assert_eq!((system.vehicle_state, system.control_mode), (VEHICLE_NORMAL, MODE_STANDBY));
    hold(&mut robot, &motion(0.5, 0.0), 1200, 1300);
    assert_eq!(robot.state().linear, 0.0);
    robot.receive(ms(1300), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(0.5, 0.0), 1300, 1400);
    close(robot.state().linear, 0.1, 1e-9);
}

#[test]
fn another_host_takes_the_mode_for_long_enough_to_be_reported_on_both_wires() {
    // CAN: driving at 0.5 m/s; an RS232 host selects serial mode; 0x421 is ignored for 200 ms; it brakes.
    let mut robot = can_commanded();
    hold(&mut robot, &motion(0.5, 0.0), 0, 1000);
    robot.inject(ms(1000), FaultKind::OtherHost);
    assert_eq!(reported(&mut robot, ms(1000)).control_mode, MODE_SERIAL);
    robot.receive(ms(1010), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(0.5, 0.0), 1010, 1190);
    let state = robot.state();
    assert_eq!(
        (state.control_mode, state.motion_block),
        (ControlMode::Serial, Some(MotionBlock::NotInCommandMode))
    );
    assert!(state.linear < 0.5, "it brakes: {}", state.linear);
    // After the hold, 0x421 selects CAN mode again.
    robot.receive(ms(1200), &Message::ControlModeCommand(MODE_CAN));
    assert_eq!(reported(&mut robot, ms(1200)).control_mode, MODE_CAN);

    // RS232: every motion frame selects serial mode, yet for 200 ms none does: every report says CAN (1).
    let mut robot = serial();
    hold(&mut robot, &serial_motion(20, 0, 0), 0, 1000);
    assert_eq!(reported(&mut robot, ms(1000)).control_mode, MODE_SERIAL);
    robot.inject(ms(1000), FaultKind::OtherHost);
    for t in (1020..1200).step_by(20) {
        robot.receive(ms(t - 10), &serial_motion(20, 0, 0));
        assert_eq!(reported(&mut robot, ms(t)).control_mode, MODE_CAN, "at {t} ms");
    }
    hold(&mut robot, &serial_motion(20, 0, 0), 1200, 1300);
    assert_eq!(reported(&mut robot, ms(1300)).control_mode, MODE_SERIAL);
}

#[test]
fn scheduled_estop_acts_at_its_millisecond() {
    let mut robot = with_faults(SimWire::CanV2, &["estop@2s", "estop-release@5s"]);
    robot.step(ms(1999));
    assert_eq!(robot.state().vehicle_state, VEHICLE_NORMAL);
    robot.step(ms(2000));
    assert_eq!(robot.state().vehicle_state, VEHICLE_ESTOP);
    robot.step(ms(4999));
    assert_eq!(robot.state().vehicle_state, VEHICLE_ESTOP);
    robot.step(ms(5000));
    assert_eq!(robot.state().vehicle_state, VEHICLE_NORMAL);

    // A time between milliseconds acts at the next one.
    let mut robot = with_faults(SimWire::CanV2, &["estop@1.0005s"]);
    robot.step(Duration::from_micros(1_000_900));
    assert_eq!(robot.state().vehicle_state, VEHICLE_NORMAL);
    robot.step(ms(1001));
    assert_eq!(robot.state().vehicle_state, VEHICLE_ESTOP);

    // At 0: active from the start.
    let robot = with_faults(SimWire::CanV2, &["estop"]);
    assert_eq!(robot.state().vehicle_state, VEHICLE_ESTOP);
}

// ---- faults ----

#[test]
fn motor_comm_fault_latches_until_cleared_for_that_motor() {
    let mut robot = with_faults(SimWire::CanV2, &["motor1-comm@1s"]);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(0.5, 0.0), 0, 999);
    let out = feedback(&mut robot, ms(999));
    assert_eq!(low_speed(&out, 1)[0].driver_state, 0);
    hold(&mut robot, &motion(0.5, 0.0), 999, 1000);
    let state = robot.state();
    assert_eq!(state.motors[0].driver_state, DRIVER_CAN_DISCONNECTED);
    assert_eq!(state.motors[1].driver_state, 0);
    assert_eq!(
        (state.vehicle_state, state.motion_block),
        (VEHICLE_EXCEPTION, Some(MotionBlock::LatchedFault))
    );
    // V2 has no system bit for it: the fault code stays clear.
    assert_eq!(state.fault_code, 0);

    // It slows to a stop (ramped) and stays latched.
    hold(&mut robot, &motion(0.5, 0.0), 1000, 1250);
    close(robot.state().linear, 0.25, 1e-9);
    hold(&mut robot, &motion(0.5, 0.0), 1250, 5000);
    assert_eq!(robot.state().linear, 0.0);
    let out = feedback(&mut robot, ms(5000));
    assert_eq!(low_speed(&out, 1)[0].driver_state, DRIVER_CAN_DISCONNECTED);
    assert_eq!(low_speed(&out, 2)[0].driver_state, 0);

    robot.receive(ms(5000), &Message::FaultClear(CLEAR_MOTOR2));
    assert_eq!(robot.state().motors[0].driver_state, DRIVER_CAN_DISCONNECTED);
    robot.receive(ms(5000), &Message::FaultClear(9));
    assert_eq!(robot.state().motors[0].driver_state, DRIVER_CAN_DISCONNECTED);
    robot.receive(ms(5000), &Message::FaultClear(CLEAR_MOTOR1));
    let state = robot.state();
    assert_eq!(
        (state.motors[0].driver_state, state.vehicle_state, state.motion_block),
        (0, VEHICLE_NORMAL, None)
    );
    hold(&mut robot, &motion(0.5, 0.0), 5000, 5100);
    close(robot.state().linear, 0.1, 1e-9);
}

#[test]
fn overheat_latches_and_clears_only_once_cool() {
    let mut robot = with_faults(SimWire::CanV2, &["motor2-overheat@1s"]);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    robot.step(ms(999));
    assert_eq!(robot.state().motors[1].driver_state, 0);
    let out = feedback(&mut robot, ms(1000));
    let ls = low_speed(&out, 2)[0];
    assert_eq!((ls.driver_temperature, ls.motor_temperature, ls.driver_state), (70, 70, DRIVER_OVERHEAT));
    assert_eq!(low_speed(&out, 1)[0].driver_temperature, 25);
    assert_eq!(system_states(&out)[0].vehicle_state, VEHICLE_EXCEPTION);

    // Still above 65 C: a clear does nothing.
    robot.receive(ms(2000), &Message::FaultClear(CLEAR_ALL));
    assert_eq!(robot.state().motion_block, Some(MotionBlock::LatchedFault));
    // Cooling 70 -> 65 C towards 25 C with tau = 120 s takes 120 ln(45/40) = 14.1 s.
    robot.step(ms(15_000));
    assert!(robot.state().motors[1].driver_temperature > 65.0);
    robot.step(ms(16_000));
    assert!(robot.state().motors[1].driver_temperature < 65.0);
    robot.step(ms(60_000));
    let state = robot.state();
    assert!(state.motors[1].driver_temperature < 55.0, "{}", state.motors[1].driver_temperature);
    assert_eq!(state.motors[1].driver_state, DRIVER_OVERHEAT, "latched although cool");
    robot.receive(ms(60_000), &Message::FaultClear(CLEAR_MOTOR2));
    let state = robot.state();
    assert_eq!((state.motors[1].driver_state, state.vehicle_state), (0, VEHICLE_NORMAL));
}

#[test]
fn rc_lost_sets_its_bit_and_stops_until_restored() {
    let mut robot = with_faults(SimWire::CanV2, &["rc-lost@3s", "rc-restore@4s"]);
    robot.receive(ms(2000), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(0.5, 0.0), 2000, 3000);
    let system = reported(&mut robot, ms(3000));
    assert_eq!((system.fault_code, system.vehicle_state), (V2_RC_DISCONNECTED, VEHICLE_EXCEPTION));
    assert_eq!(
        Flags::new(FlagTable::SystemV2, system.fault_code).iter().map(|f| f.name).collect::<Vec<_>>(),
        ["rc_disconnected"]
    );
    hold(&mut robot, &motion(0.5, 0.0), 3000, 4000);
    assert_eq!(robot.state().linear, 0.0);
    let system = reported(&mut robot, ms(4000));
    assert_eq!((system.fault_code, system.vehicle_state), (0, VEHICLE_NORMAL));
}

#[test]
fn overcurrent_latches_per_motor() {
    let mut robot = with_faults(SimWire::CanV2, &["overcurrent@1s"]);
    robot.step(ms(1000));
    let state = robot.state();
    assert_eq!(state.motors.map(|m| m.driver_state & DRIVER_OVERCURRENT), [DRIVER_OVERCURRENT; 2]);
    robot.receive(ms(1000), &Message::FaultClear(CLEAR_MOTOR1));
    let state = robot.state();
    assert_eq!(state.motors.map(|m| m.driver_state & DRIVER_OVERCURRENT), [0, DRIVER_OVERCURRENT]);
    assert_eq!(state.motion_block, Some(MotionBlock::LatchedFault));
    robot.receive(ms(1000), &Message::FaultClear(CLEAR_ALL));
    assert_eq!(robot.state().vehicle_state, VEHICLE_NORMAL);
}

#[test]
fn driver_disabled_bit_follows_standby() {
    let mut robot = can();
    let out = feedback(&mut robot, ms(0));
    assert_eq!(low_speed(&out, 1)[0].driver_state, DRIVER_DISABLED);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    assert_eq!(robot.state().motors[0].driver_state, 0);
    robot.inject(ms(0), FaultKind::EStop);
    assert_eq!(robot.state().motors[0].driver_state, DRIVER_DISABLED);
}

// ---- battery ----

#[test]
fn battery_thresholds_with_an_accelerated_drain() {
    // 1 A idle x 3600: 1 Ah per second; 5 V over 15 Ah: the open-circuit voltage drops 1/3 V per second.
    let config = SimConfig { battery_drain_factor: 3600.0, ..SimConfig::default() };
    let mut robot = chassis(config);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    let mut transitions = Vec::new();
    let mut last = 0u16;
    for t in 0..15_000u64 {
        robot.step(ms(t));
        let state = robot.state();
        if state.fault_code != last || transitions.is_empty() {
            let decivolts = (state.battery_voltage * 10.0).round() as u16;
            transitions.push((t, state.fault_code, decivolts, state.motion_block));
            last = state.fault_code;
        }
    }
    // Reported voltage = 26 - t/3 - 0.08 rounds to 22.5 V once below 22.55 V, at t = 10.11 s; to 22.0 V
    // at 11.61 s; to 21.5 V at 13.11 s. Each level sets once that has held for 1 s (LEVEL_SET_S), by
    // when the voltage is 1/3 V lower.
    let (t_warn, code, dv, _) = transitions[1];
    assert_eq!((code, dv), (V2_BATTERY_WARNING, 222));
    close(t_warn as f64 / 1000.0, 11.11, 0.002);
    let (t_fault, code, dv, block) = transitions[2];
    assert_eq!((code, dv, block), (V2_BATTERY_FAULT | V2_BATTERY_WARNING, 217, None), "beeps but drives");
    close(t_fault as f64 / 1000.0, 12.61, 0.002);
    assert_eq!(transitions.len(), 3);
    let state = robot.state();
    assert_eq!(state.motion_block, Some(MotionBlock::BatteryCutOff), "cut off below 21.5 V");
    assert_eq!(state.vehicle_state, VEHICLE_EXCEPTION);
    assert!(state.battery_voltage <= 21.5);
    close(state.state_of_charge, 1.0 / 15_000.0, 1e-9);
}

#[test]
fn cut_off_stops_motion_and_a_fresh_battery_restores_it() {
    let mut robot = with_faults(SimWire::CanV2, &["battery-empty@1s", "battery-ok@2s"]);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &motion(0.5, 0.0), 0, 1000);
    let state = robot.state();
    assert_eq!((state.linear, state.motion_block), (0.0, Some(MotionBlock::BatteryCutOff)));
    assert_eq!(state.fault_code, V2_BATTERY_FAULT | V2_BATTERY_WARNING);
    hold(&mut robot, &motion(0.5, 0.0), 1000, 2000);
    assert_eq!(robot.state().linear, 0.0);
    let state = robot.state();
    assert_eq!((state.fault_code, state.motion_block, state.vehicle_state), (0, None, VEHICLE_NORMAL));
    // The host's mode survived (the drive power was cut, not the controller).
    hold(&mut robot, &motion(0.5, 0.0), 2000, 2100);
    close(robot.state().linear, 0.1, 1e-9);
}

#[test]
fn battery_events_and_warnings_clear_by_themselves() {
    let mut robot = with_faults(SimWire::CanV2, &["battery-warning@1s", "battery-low@2s", "battery-ok@3s"]);
    assert_eq!(reported(&mut robot, ms(999)).fault_code, 0);
    let system = reported(&mut robot, ms(1000));
    assert_eq!((system.fault_code, system.battery_decivolts), (V2_BATTERY_WARNING, 223));
    let system = reported(&mut robot, ms(2000));
    assert_eq!((system.fault_code, system.battery_decivolts), (V2_BATTERY_FAULT | V2_BATTERY_WARNING, 218));
    // A fault clear does not clear a battery that is still low.
    robot.receive(ms(2500), &Message::FaultClear(CLEAR_ALL));
    assert_eq!(robot.state().fault_code, V2_BATTERY_FAULT | V2_BATTERY_WARNING);
    assert_eq!(reported(&mut robot, ms(3000)).fault_code, 0);
}

#[test]
fn the_battery_drains_under_load_at_real_speed() {
    let mut robot = can_commanded();
    hold(&mut robot, &motion(1.0, 0.0), 0, 1000);
    let used_before = 1.0 - robot.state().state_of_charge;
    hold(&mut robot, &motion(1.0, 0.0), 1000, 61_000);
    let state = robot.state();
    // 60 s at 1 m/s: 1 A idle + 2 x 2 A = 5 A -> 5/60 Ah of 15 Ah.
    close(state.battery_current, 5.0, 1e-9);
    close((1.0 - state.state_of_charge) - used_before, 5.0 / 60.0 / 15.0, 1e-9);
    close(state.battery_voltage, 26.0 - 5.0 * (1.0 - state.state_of_charge) - 5.0 * 0.08, 1e-9);
    assert!(state.motors[0].driver_temperature > 25.0, "drivers warm up under load");
}

/// The fault code and vehicle state once per millisecond of a run: `commands` gives the motion command
/// to hold at each time (`None`: the host sends nothing, so the robot times out and comes to rest). Also
/// the states themselves, for the voltage checks.
fn battery_run(faults: &[&str], millis: u64, command: impl Fn(u64) -> Option<(f64, f64)>) -> Vec<SimState> {
    let mut robot = with_faults(SimWire::CanV2, faults);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    let mut states = Vec::with_capacity(millis as usize);
    for t in 0..millis {
        if t % 20 == 0 {
            if let Some((linear, angular)) = command(t) {
                robot.receive(ms(t), &motion(linear, angular));
            }
        }
        robot.step(ms(t + 1));
        states.push(robot.state());
    }
    states
}

/// The times (ms) at which the reported bits or the vehicle state changed.
fn bit_changes(states: &[SimState]) -> Vec<u64> {
    states
        .windows(2)
        .filter(|pair| {
            (pair[0].fault_code, pair[0].vehicle_state) != (pair[1].fault_code, pair[1].vehicle_state)
        })
        .map(|pair| pair[1].time.as_millis() as u64)
        .collect()
}

/// The shortest time between two changes (`u64::MAX` with fewer than two).
fn shortest_gap(changes: &[u64]) -> u64 {
    changes.windows(2).map(|pair| pair[1] - pair[0]).min().unwrap_or(u64::MAX)
}

/// Reported voltage = open-circuit voltage (linear in the charge left) - current x resistance.
fn assert_resistive_sag(state: &SimState) {
    let config = SimConfig::default();
    let open_circuit =
        config.battery_empty_v + (config.battery_start_v - config.battery_empty_v) * state.state_of_charge;
    let expected = open_circuit - state.battery_current * config.battery_resistance_ohm;
    close(state.battery_voltage, expected, 1e-9);
}

#[test]
fn a_low_battery_still_drives_sags_under_load_and_recovers_at_rest() {
    // 60 s of 5 s at 0.5 m/s then 5 s standing (the robot times out 500 ms after the last command).
    let states = battery_run(&["battery-low"], 60_000, |t| (t % 10_000 < 5_000).then_some((0.5, 0.0)));
    let both = V2_BATTERY_FAULT | V2_BATTERY_WARNING;
    for state in &states {
        assert_eq!((state.fault_code, state.vehicle_state, state.motion_block), (both, VEHICLE_NORMAL, None));
        assert_resistive_sag(state);
    }
    assert!(bit_changes(&states).is_empty());
    // Cruising at 0.5 m/s: 1 A idle + 2 x 1 A -> 3 A, 0.24 V of sag under the 21.82 V at rest.
    let cruising = &states[4_000];
    close(cruising.linear, 0.5, 1e-9);
    close(cruising.battery_current, 3.0, 1e-9);
    let at_rest = &states[9_000];
    assert_eq!(at_rest.linear, 0.0);
    close(at_rest.battery_current, 1.0, 1e-9);
    // 2 A less through 0.08 ohm, less the charge drawn between the two (about 1 mV).
    close(at_rest.battery_voltage - cruising.battery_voltage, 2.0 * 0.08, 2e-3);
    assert_eq!((cruising.battery_voltage * 10.0).round(), 217.0);
    assert_eq!((at_rest.battery_voltage * 10.0).round(), 218.0);
    assert!(states[59_000].odometry_left_mm > 10_000, "it drove 3 x 2.5 m and more");
}

#[test]
fn a_heavy_load_on_a_low_battery_cuts_off_once_and_stays_off() {
    // 2 m/s: 1 A + 2 x 4 A = 9 A, 0.72 V of sag: 21.2 V, under the 21.5 V cut-off once it has held 1 s.
    let states = battery_run(&["battery-low"], 60_000, |_| Some((2.0, 0.0)));
    let cut = states.iter().position(|s| s.motion_block == Some(MotionBlock::BatteryCutOff)).unwrap();
    let first_at_cut_off = states.iter().position(|s| (s.battery_voltage * 10.0).round() <= 215.0).unwrap();
    // The first sample at or under counts its own millisecond: 1000 ms in all.
    assert_eq!(cut - first_at_cut_off + 1, 1000, "the voltage held at or under 21.5 V for 1 s first");
    assert!(states[cut - 1].linear > 0.5, "it was driving");
    for state in &states[cut..] {
        assert_eq!(
            (state.motion_block, state.vehicle_state),
            (Some(MotionBlock::BatteryCutOff), VEHICLE_EXCEPTION)
        );
        assert_eq!(state.linear, 0.0);
        assert_resistive_sag(state);
    }
    // Drive power off: only the idle current, and the voltage is back to its rest value (no flapping).
    close(states[59_999].battery_current, 1.0, 1e-9);
    assert_eq!((states[59_999].battery_voltage * 10.0).round(), 218.0);
    assert_eq!(bit_changes(&states), vec![cut as u64 + 1]);
}

#[test]
fn the_cut_off_is_released_by_a_charged_pack_only() {
    let mut robot = with_faults(SimWire::CanV2, &["battery-empty@1s", "battery-low@2s", "battery-ok@3s"]);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    robot.step(ms(1500));
    assert_eq!(robot.state().motion_block, Some(MotionBlock::BatteryCutOff));
    // 21.9 V is above the cut-off but not a charged pack: the event is judged at once, at rest.
    robot.step(ms(2500));
    assert_eq!(robot.state().motion_block, None, "a battery event sets the levels of its voltage at once");
    robot.inject(ms(2600), FaultKind::BatteryEmpty);
    robot.step(ms(2999));
    assert_eq!(robot.state().motion_block, Some(MotionBlock::BatteryCutOff));
    robot.step(ms(3000));
    assert_eq!((robot.state().motion_block, robot.state().fault_code), (None, 0));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 12, ..Default::default() })]

    /// Any driving on a low battery for 60 s: the bits and the vehicle state never change twice within
    /// 1 s, a cut-off never comes back by itself, and the voltage is always the resistive sag of the load.
    #[test]
    fn a_low_battery_never_flaps(
        segments in proptest::collection::vec((-2.3f64..2.3, -3.0f64..3.0, 100u64..5_000, proptest::bool::ANY), 1..40),
        start in proptest::sample::select(vec!["battery-warning", "battery-low"]),
    ) {
        let plan: Vec<(u64, Option<(f64, f64)>)> = segments
            .iter()
            .scan(0u64, |end, &(linear, angular, length, drives)| {
                *end += length;
                Some((*end, drives.then_some((linear, angular))))
            })
            .collect();
        let states = battery_run(&[start], 60_000, |t| {
            plan.iter().find(|(end, _)| t < *end).and_then(|(_, command)| *command)
        });
        let changes = bit_changes(&states);
        proptest::prop_assert!(shortest_gap(&changes) >= 1_000, "changes at {changes:?} ms");
        if let Some(cut) = states.iter().position(|s| s.motion_block == Some(MotionBlock::BatteryCutOff)) {
            proptest::prop_assert!(states[cut..].iter().all(|s| s.motion_block == Some(MotionBlock::BatteryCutOff)));
        }
        for state in &states {
            assert_resistive_sag(state);
        }
    }
}

// ---- serial ----

#[test]
fn serial_mode_variant() {
    let mut robot = serial();
    assert_eq!(reported(&mut robot, ms(0)).control_mode, 0);
    // CAN frames mean nothing on the serial link.
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    robot.receive(ms(0), &raw_motion(500, 0));
    // A motion command without serial mode (0x02) is ignored.
    let can_mode = Message::PercentMotionCommand(PercentMotionCommand {
        control_mode: MODE_CAN,
        linear_percent: 10,
        ..PercentMotionCommand::default()
    });
    robot.receive(ms(0), &can_mode);
    assert_eq!(robot.state().commands_ignored, 3);
    assert_eq!(robot.state().control_mode, ControlMode::Standby);

    // The manual's example: mode 0x02, +10 % = 0.15 m/s.
    hold(&mut robot, &serial_motion(10, 0, 0), 0, 500);
    let state = robot.state();
    assert_eq!((state.control_mode, state.linear), (ControlMode::Serial, 0.15));
    let out = feedback(&mut robot, ms(500));
    assert_eq!(system_states(&out)[0].control_mode, MODE_SERIAL);
    assert!(matches!(out[1], Message::MotionState(MotionState { linear_mm_s: 150, angular_mrad_s: 0, .. })));
    // 100 % angular = 0.7853 rad/s.
    hold(&mut robot, &serial_motion(0, 100, 0), 500, 1500);
    close(robot.state().angular, ANGULAR_LIMIT, 1e-12);
    // Timeout applies on serial too.
    robot.step(ms(3000));
    assert_eq!(robot.state().linear, 0.0);
    assert_eq!(robot.state().angular, 0.0);
}

#[test]
fn serial_fault_bits_and_clear_codes() {
    let mut robot = with_faults(SimWire::Serial, &["motor1-overheat@1s", "motor2-comm@1s", "overcurrent@1s"]);
    let system = reported(&mut robot, ms(1000));
    assert_eq!(
        system.fault_code,
        SERIAL_OVERHEAT_PROTECTION
            | SERIAL_DRIVER_OVERHEAT_WARNING
            | SERIAL_MOTOR_COMM[1]
            | SERIAL_OVERCURRENT_PROTECTION
    );
    let names: Vec<_> =
        Flags::new(FlagTable::SystemV1Serial, system.fault_code).iter().map(|f| f.name).collect();
    assert_eq!(
        names,
        [
            "motor2_comm_fault",
            "driver_overheat_protection",
            "motor_overcurrent_protection",
            "driver_overheat_warning"
        ]
    );
    assert_eq!(system.vehicle_state, VEHICLE_EXCEPTION);
    let out = feedback(&mut robot, ms(1020));
    assert!(matches!(
        out[2],
        Message::MotorDriverState(MotorDriverState { motor: 1, driver_temperature: 70, .. })
    ));

    // Motion is refused while latched; clear codes come in the motion command.
    hold(&mut robot, &serial_motion(10, 0, 4), 1020, 1100);
    assert_eq!(robot.state().fault_code & SERIAL_MOTOR_COMM[1], 0, "code 4 clears motor 2 comm");
    assert_eq!(robot.state().linear, 0.0);
    hold(&mut robot, &serial_motion(10, 0, 8), 1100, 1200);
    assert_eq!(robot.state().fault_code & SERIAL_OVERCURRENT_PROTECTION, 0, "code 8 clears over-current");
    hold(&mut robot, &serial_motion(10, 0, 7), 1200, 1300);
    assert_ne!(robot.state().fault_code & SERIAL_OVERHEAT_PROTECTION, 0, "still hot: stays latched");
    robot.step(ms(80_000));
    let state = robot.state();
    assert_eq!(
        state.fault_code, SERIAL_OVERHEAT_PROTECTION,
        "cool: the warning cleared itself, the protection did not"
    );
    // Clear and drive in the same frame.
    hold(&mut robot, &serial_motion(10, 0, 7), 80_000, 80_100);
    let state = robot.state();
    assert_eq!((state.fault_code, state.vehicle_state), (0, VEHICLE_NORMAL));
    close(state.linear, 0.1, 1e-9);
}

#[test]
fn serial_battery_bits_use_the_v1_layout() {
    let mut robot = with_faults(SimWire::Serial, &["battery-low"]);
    assert_eq!(reported(&mut robot, ms(0)).fault_code, SERIAL_BATTERY_WARNING | SERIAL_BATTERY_FAULT);
    hold(&mut robot, &serial_motion(0, 0, 1), 0, 100);
    assert_eq!(robot.state().fault_code, SERIAL_BATTERY_WARNING | SERIAL_BATTERY_FAULT);
}

// ---- lights ----

#[test]
fn lights_are_echoed_and_handed_back() {
    let mut robot = can();
    let light_state = |robot: &mut Chassis, t| {
        feedback(robot, t)
            .into_iter()
            .find_map(|m| if let Message::LightState(l) = m { Some(l) } else { None })
            .unwrap()
    };
    let firmware = light_state(&mut robot, ms(0));
    assert_eq!((firmware.enable, firmware.front_mode, firmware.count), (0, LIGHT_ON, 0));

    robot.receive(ms(10), &Message::LightCommand(Lights::front(LightMode::Custom, 30).unwrap()));
    let echoed = light_state(&mut robot, ms(20));
    assert_eq!(
        echoed,
        Lights { enable: 1, front_mode: LIGHT_CUSTOM, front_brightness: 30, count: 1, ..Lights::default() }
    );

    let too_bright = Lights {
        enable: 1,
        front_mode: LIGHT_CUSTOM,
        front_brightness: 250,
        rear_mode: 9,
        ..Lights::default()
    };
    robot.receive(ms(30), &Message::LightCommand(too_bright));
    let echoed = light_state(&mut robot, ms(40));
    assert_eq!((echoed.front_brightness, echoed.rear_mode), (100, 0));

    let ignored_before = robot.state().commands_ignored;
    robot.receive(ms(50), &Message::LightCommand(Lights { enable: 1, front_mode: 9, ..Lights::default() }));
    robot.receive(ms(50), &Message::LightCommand(Lights { enable: 2, ..Lights::default() }));
    assert_eq!(robot.state().commands_ignored, ignored_before + 2);
    assert_eq!(light_state(&mut robot, ms(60)).front_brightness, 100);

    robot.receive(ms(70), &Message::LightCommand(Lights::release()));
    let back = light_state(&mut robot, ms(80));
    assert_eq!((back.enable, back.front_mode, back.front_brightness), (0, LIGHT_ON, 0));

    // Serial lights too.
    let mut robot = serial();
    robot.receive(ms(0), &Message::LightCommand(Lights::front(LightMode::Breath, 0).unwrap()));
    assert_eq!(robot.state().lights.front_mode, LIGHT_BREATH);
}

// ---- determinism and robustness ----

/// A fixed script of commands and faults, stepped with the given pattern; returns the final state.
fn scripted(steps_us: &[u64]) -> SimState {
    let mut robot = with_faults(SimWire::CanV2, &["estop@5s", "estop-release@5.5s", "motor1-overheat@7.5s"]);
    let script: Vec<(u64, Message)> = (0..400u64)
        .map(|i| {
            let t = i * 20_000 + (i % 7) * 1_300;
            let message = match i {
                0 | 290 => Message::ControlModeCommand(MODE_CAN),
                390 => Message::FaultClear(CLEAR_ALL),
                _ => raw_motion(((i * 37) % 3000) as i16 - 1500, ((i * 91) % 2000) as i16 - 1000),
            };
            (t, message)
        })
        .collect();
    let mut next = 0;
    let mut t = 0u64;
    let mut i = 0;
    let mut out = Vec::new();
    while t < 9_000_000 {
        while next < script.len() && script[next].0 <= t {
            robot.receive(Duration::from_micros(script[next].0), &script[next].1);
            next += 1;
        }
        robot.due_feedback(Duration::from_micros(t), &mut out);
        t += steps_us[i % steps_us.len()];
        i += 1;
    }
    robot.due_feedback(Duration::from_micros(9_000_000), &mut out);
    robot.state()
}

#[test]
fn the_state_does_not_depend_on_the_step_pattern() {
    let reference = scripted(&[1_000]);
    assert!(reference.odometry_left_mm != 0 && reference.motors[0].driver_temperature > 25.0);
    for pattern in [&[250][..], &[3_000], &[19_000, 1_000, 7_300], &[400, 2_100, 13_000, 600]] {
        assert_eq!(scripted(pattern), reference, "{pattern:?}");
    }
}

#[test]
fn huge_time_jumps_finish_and_never_panic() {
    let mut robot = can_commanded();
    robot.receive(ms(0), &raw_motion(1000, 0));
    robot.step(Duration::from_secs(3600 * 24 * 365));
    let state = robot.state();
    assert_eq!((state.linear, state.motion_block), (0.0, Some(MotionBlock::BatteryCutOff)));
    assert_eq!(state.state_of_charge, 0.0);
    let mut out = Vec::new();
    robot.due_feedback(Duration::MAX, &mut out);
    assert_eq!(system_states(&out).len(), 1);
    robot.receive(Duration::MAX, &raw_motion(1000, 0));
    robot.inject(Duration::MAX, FaultKind::BatteryOk);
    robot.step(Duration::MAX);
    let _ = robot.state();
}

#[test]
fn fast_forward_at_rest_matches_stepping() {
    let run = |coarse: bool| {
        let mut robot = with_faults(SimWire::CanV2, &["motor1-overheat@1s", "estop@40s"]);
        if coarse {
            robot.step(ms(60_000));
        } else {
            (1..=60_000).for_each(|t| robot.step(ms(t)));
        }
        robot.state()
    };
    let (fine, coarse) = (run(false), run(true));
    assert_eq!(coarse.vehicle_state, VEHICLE_ESTOP);
    close(coarse.battery_voltage, fine.battery_voltage, 1e-9);
    close(coarse.motors[0].driver_temperature, fine.motors[0].driver_temperature, 1e-9);
    assert_eq!(coarse.fault_code, fine.fault_code);
}

#[test]
fn any_message_is_survived() {
    let everything = [
        Message::MotionCommand(MotionCommand { linear_mm_s: i16::MIN, angular_mrad_s: i16::MIN }),
        Message::PercentMotionCommand(PercentMotionCommand {
            control_mode: 0xFF,
            fault_clear: 0xFF,
            linear_percent: i8::MIN,
            angular_percent: i8::MAX,
            lateral_percent: 5,
            count: 1,
        }),
        Message::LightCommand(Lights {
            enable: 0xFF,
            front_mode: 0xFF,
            front_brightness: 0xFF,
            ..Lights::default()
        }),
        Message::ControlModeCommand(0xFF),
        Message::FaultClear(0xFF),
        Message::VersionRequest,
        Message::SystemState(SystemState::default()),
        Message::MotionState(MotionState::default()),
        Message::LightState(Lights::default()),
        Message::RcState(RcState::default()),
        Message::MotorHighSpeed(MotorHighSpeed::default()),
        Message::MotorDriverState(MotorDriverState::default()),
        Message::MotorLowSpeed(MotorLowSpeed::default()),
        Message::Odometry(Odometry::default()),
        Message::VersionResponse(VersionResponse::default()),
    ];
    for wire in [SimWire::CanV2, SimWire::Serial] {
        let mut robot = chassis(SimConfig { wire, ..SimConfig::default() });
        for (i, message) in everything.iter().cycle().take(200).enumerate() {
            robot.receive(ms(i as u64), message);
        }
        let state = robot.state();
        assert!(state.linear.abs() <= 2.3 && state.angular.abs() <= 3.0);
        // The 9 feedback kinds (117 of the 200) are never obeyed.
        assert!(state.commands_ignored >= 117, "{}", state.commands_ignored);
    }
}

// ---- configuration and cross-checks ----

#[test]
fn config_validation_and_sanitizing() {
    assert_eq!(SimConfig::default().validate(), Ok(()));
    let bad = SimConfig { track_m: f64::NAN, ..SimConfig::default() };
    let err = bad.validate().unwrap_err();
    assert_eq!(err.field, "track_m");
    assert_eq!(err.to_string(), "simulator setting track_m = NaN must be a finite number above 0");
    assert_eq!(bad.clone().sanitized().track_m, 0.36);
    let bad = SimConfig { battery_start_v: 20.0, ..SimConfig::default() };
    assert_eq!(bad.validate().unwrap_err().field, "battery_empty_v");
    let bad = SimConfig { command_timeout: Duration::ZERO, max_linear_accel: -1.0, ..SimConfig::default() };
    assert_eq!(bad.validate().unwrap_err().field, "max_linear_accel");
    let fixed = bad.sanitized();
    assert_eq!(fixed.validate(), Ok(()));
    assert_eq!((fixed.command_timeout, fixed.max_linear_accel), (ms(500), 1.0));
    // A chassis from a broken config still works.
    let mut robot =
        chassis(SimConfig { wheel_diameter_m: 0.0, driver_cooling_s: -1.0, ..SimConfig::default() });
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    hold(&mut robot, &raw_motion(0, 1000), 0, 1000);
    assert!(robot.state().motors[0].rpm.is_finite());
}

#[test]
fn bit_constants_match_the_protocol_tables() {
    let name = |table: FlagTable, bits: u16| Flags::new(table, bits).iter().next().unwrap().name;
    assert_eq!(name(FlagTable::SystemV2, V2_BATTERY_FAULT), "battery_undervoltage_fault");
    assert_eq!(name(FlagTable::SystemV2, V2_BATTERY_WARNING), "battery_undervoltage_warning");
    assert_eq!(name(FlagTable::SystemV2, V2_RC_DISCONNECTED), "rc_disconnected");
    let serial = FlagTable::SystemV1Serial;
    assert_eq!(name(serial, SERIAL_DRIVER_OVERHEAT_WARNING), "driver_overheat_warning");
    assert_eq!(name(serial, SERIAL_OVERCURRENT_WARNING), "motor_overcurrent_warning");
    assert_eq!(name(serial, SERIAL_BATTERY_WARNING), "battery_undervoltage_warning");
    assert_eq!(name(serial, SERIAL_BATTERY_FAULT), "battery_undervoltage_fault");
    assert_eq!(name(serial, SERIAL_MOTOR_COMM[0]), "motor1_comm_fault");
    assert_eq!(name(serial, SERIAL_MOTOR_COMM[1]), "motor2_comm_fault");
    assert_eq!(name(serial, SERIAL_OVERHEAT_PROTECTION), "driver_overheat_protection");
    assert_eq!(name(serial, SERIAL_OVERCURRENT_PROTECTION), "motor_overcurrent_protection");
    let driver = |bits: u8| name(FlagTable::DriverState, u16::from(bits));
    assert_eq!(driver(DRIVER_CAN_DISCONNECTED), "can_disconnected");
    assert_eq!(driver(DRIVER_OVERHEAT), "driver_overheat");
    assert_eq!(driver(DRIVER_OVERCURRENT), "driver_overcurrent");
    assert_eq!(driver(DRIVER_DISABLED), "driver_disabled");
}

#[test]
fn battery_event_texts_name_the_voltages_the_events_set() {
    use super::battery::{EMPTY_EVENT_V, LOW_EVENT_V, WARNING_EVENT_V};
    assert_eq!([WARNING_EVENT_V, LOW_EVENT_V, EMPTY_EVENT_V], [22.4, 21.9, 21.4]);
    for (kind, volts) in [
        (FaultKind::BatteryWarning, WARNING_EVENT_V),
        (FaultKind::BatteryLow, LOW_EVENT_V),
        (FaultKind::BatteryEmpty, EMPTY_EVENT_V),
    ] {
        assert!(kind.description().starts_with(&format!("battery to {volts} V:")), "{kind:?}");
    }
}
