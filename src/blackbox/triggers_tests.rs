//! The watcher against hand-made frame streams: each default trigger once for its onset and never on a clean
//! log, re-arming, silence found in `tick` and in `frame`, hysteresis, expressions, CAN V1 and RS232, and
//! random streams (proptest).

use proptest::prelude::*;

use super::*;
use crate::protocol::can::{encode_v1, encode_v2};
use crate::protocol::message::{
    Lights, MotionCommand, MotionState, MotorDriverState, MotorHighSpeed, MotorLowSpeed, Odometry,
    PercentMotionCommand, MODE_CAN, MODE_RC, MODE_SERIAL, MODE_STANDBY, VEHICLE_NORMAL,
};

/// Milliseconds since the start of a capture.
fn ms(t: u64) -> Timestamp {
    Timestamp { secs: t / 1000, nanos: (t % 1000) as u32 * 1_000_000, kind: TimestampKind::Relative }
}

fn v2(message: Message) -> LinkFrame {
    LinkFrame::Can(encode_v2(&message).unwrap())
}

fn v1(message: Message) -> LinkFrame {
    LinkFrame::Can(encode_v1(&message).unwrap())
}

fn rs232(message: Message) -> LinkFrame {
    LinkFrame::Serial(serial::encode(&message, 7).unwrap())
}

fn error_frame(class: u32, data: &[u8]) -> LinkFrame {
    LinkFrame::Can(CanFrame::new_error(class, data).unwrap())
}

/// A healthy robot in CAN mode at 25.9 V.
fn healthy() -> SystemState {
    SystemState {
        vehicle_state: VEHICLE_NORMAL,
        control_mode: MODE_CAN,
        battery_decivolts: 259,
        fault_code: 0,
        count: 0,
    }
}

/// The robot's feedback as a test steers it: its status, its drivers' state bytes, its wire.
#[derive(Clone, Copy, Debug)]
struct Robot {
    wire: Wire,
    status: SystemState,
    drivers: [u8; 2],
    /// Motor currents, 0.1 A.
    currents: [i16; 2],
}

impl Robot {
    fn new(wire: Wire) -> Self {
        let status = if wire == Wire::Serial {
            SystemState { control_mode: MODE_SERIAL, ..healthy() }
        } else {
            healthy()
        };
        Self { wire, status, drivers: [0; 2], currents: [12, 14] }
    }

    /// The frames of one 20 ms period at `t` ms: the host's motion command, then the robot's feedback.
    fn frames(&self, t: u64) -> Vec<LinkFrame> {
        let encode = |message| match self.wire {
            Wire::CanV2 => v2(message),
            Wire::CanV1 => v1(message),
            Wire::Serial => rs232(message),
        };
        let mut frames = Vec::new();
        let command = match self.wire {
            Wire::CanV2 => Message::MotionCommand(MotionCommand { linear_mm_s: 500, angular_mrad_s: 0 }),
            _ => Message::PercentMotionCommand(PercentMotionCommand {
                control_mode: self.status.control_mode.max(1),
                linear_percent: 30,
                ..PercentMotionCommand::default()
            }),
        };
        frames.push(encode(command));
        frames.push(encode(Message::SystemState(self.status)));
        frames.push(encode(Message::MotionState(MotionState {
            linear_mm_s: 500,
            angular_mrad_s: 0,
            count: 0,
        })));
        frames.push(encode(Message::LightState(Lights { front_mode: 1, ..Lights::default() })));
        for motor in 0..2 {
            let current = self.currents[motor];
            frames.push(encode(if self.wire == Wire::CanV2 {
                Message::MotorHighSpeed(MotorHighSpeed {
                    motor: motor as u8 + 1,
                    rpm: 1200,
                    current_deciamps: current,
                    pulse_count: t as i32,
                })
            } else {
                Message::MotorDriverState(MotorDriverState {
                    motor: motor as u8 + 1,
                    current_deciamps: current as u16,
                    rpm: 1200,
                    driver_temperature: 30,
                    count: 0,
                })
            }));
        }
        if self.wire == Wire::CanV2 {
            frames.push(v2(Message::Odometry(Odometry { left_mm: t as i32, right_mm: t as i32 })));
            if t % 100 == 0 {
                for motor in 0..2 {
                    frames.push(v2(Message::MotorLowSpeed(MotorLowSpeed {
                        motor: motor as u8 + 1,
                        driver_decivolts: 259,
                        driver_temperature: 30,
                        motor_temperature: 28,
                        driver_state: self.drivers[motor],
                    })));
                }
            }
        }
        frames
    }
}

/// Feeds the robot's frames every 20 ms over [from, to) ms, 0.1 ms apart within a period, with a tick
/// every 100 ms; the triggers found.
fn run(watcher: &mut Watcher, robot: &Robot, from: u64, to: u64) -> Vec<Trigger> {
    let mut out = Vec::new();
    for t in (from..to).step_by(20) {
        for (index, frame) in robot.frames(t).iter().enumerate() {
            let at = Timestamp { nanos: ms(t).nanos + index as u32 * 100_000, ..ms(t) };
            watcher.frame(at, frame, &mut out);
        }
        if t % 100 == 0 {
            watcher.tick(ms(t), &mut out);
        }
    }
    out
}

fn causes(triggers: &[Trigger]) -> Vec<String> {
    triggers.iter().map(|trigger| trigger.cause.describe()).collect()
}

fn watcher() -> Watcher {
    Watcher::new(TriggerSettings::default())
}

fn with_expressions(expressions: &[&str]) -> Watcher {
    let expressions = expressions.iter().map(|text| text.parse().unwrap()).collect();
    Watcher::new(TriggerSettings { expressions, ..TriggerSettings::default() })
}

#[test]
fn a_clean_log_fires_nothing_on_any_wire() {
    for wire in WIRES {
        let mut watcher = watcher();
        let robot = Robot::new(wire);
        assert_eq!(causes(&run(&mut watcher, &robot, 0, 60_000)), Vec::<String>::new(), "{wire:?}");
    }
}

#[test]
fn an_estop_fires_once_for_its_onset_and_again_after_rearming() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    assert!(run(&mut watcher, &robot, 0, 2_000).is_empty());
    robot.status.vehicle_state = VEHICLE_ESTOP;
    let pressed = run(&mut watcher, &robot, 2_000, 5_000);
    assert_eq!(causes(&pressed), ["E-stop pressed"]);
    assert_eq!(pressed[0].at, Timestamp { nanos: 100_000, ..ms(2_000) }, "the status frame that showed it");
    robot.status.vehicle_state = VEHICLE_NORMAL;
    assert!(run(&mut watcher, &robot, 5_000, 5_500).is_empty());
    // Pressed again 0.5 s after the release: within the re-arm time, so the same incident.
    robot.status.vehicle_state = VEHICLE_ESTOP;
    assert!(run(&mut watcher, &robot, 5_500, 6_000).is_empty());
    robot.status.vehicle_state = VEHICLE_NORMAL;
    assert!(run(&mut watcher, &robot, 6_000, 7_000).is_empty());
    robot.status.vehicle_state = VEHICLE_ESTOP;
    let again = run(&mut watcher, &robot, 7_000, 8_000);
    assert_eq!(causes(&again), ["E-stop pressed"]);
    assert_eq!(again[0].at.secs, 7);
}

#[test]
fn states_already_bad_at_the_start_are_reported_once_but_a_mode_is_no_change() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    robot.status = SystemState {
        vehicle_state: VEHICLE_ESTOP,
        control_mode: MODE_RC,
        battery_decivolts: 221,
        fault_code: 0x0400,
        ..healthy()
    };
    let found = causes(&run(&mut watcher, &robot, 0, 3_000));
    assert_eq!(
        found,
        [
            "E-stop pressed",
            "battery 22.1 V, below the warning threshold of 22.5 V",
            "fault bit set: rc_disconnected [fault]: RC transmitter disconnection protection",
        ]
    );
}

#[test]
fn each_fault_bit_fires_once_and_info_bits_never() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    robot.drivers = [0x40, 0x40 | 0x80]; // driver_disabled, driver_reset: [info]
    assert!(run(&mut watcher, &robot, 0, 1_000).is_empty());
    robot.status.fault_code = 0x0200;
    robot.drivers[1] |= 0x08;
    let found = causes(&run(&mut watcher, &robot, 1_000, 2_000));
    assert_eq!(
        found,
        [
            "fault bit set: battery_undervoltage_warning [warning]: battery below the 22.5 V alarm voltage",
            "fault bit set: motor 2 driver: driver_overheat [warning]: driver over-temperature (SDK layout)",
        ]
    );
    // A second bit while the first stays set fires for itself; an undefined bit is worth a look.
    robot.status.fault_code = 0x0200 | 0x0100 | 0x0080;
    let found = causes(&run(&mut watcher, &robot, 2_000, 3_000));
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].contains("reserved_byte5_bit7 [unknown]"), "{found:?}");
    assert!(found[1].contains("battery_undervoltage_fault [fault]"), "{found:?}");
    robot.status.fault_code = 0;
    robot.drivers = [0x40; 2];
    assert!(run(&mut watcher, &robot, 3_000, 10_000).is_empty(), "clearing fires nothing");
}

#[test]
fn a_vehicle_exception_fires_once() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    run(&mut watcher, &robot, 0, 500);
    robot.status.vehicle_state = VEHICLE_EXCEPTION;
    let found = run(&mut watcher, &robot, 500, 3_000);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].cause, Cause::VehicleException);
    assert_eq!(found[0].cause.slug(), "vehicle-exception");
}

#[test]
fn mode_changes_and_rc_override_on_v2() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    robot.status.control_mode = MODE_STANDBY;
    run(&mut watcher, &robot, 0, 500);
    robot.status.control_mode = MODE_CAN;
    assert!(run(&mut watcher, &robot, 500, 2_000).is_empty(), "a host taking control is not an incident");
    robot.status.control_mode = MODE_RC;
    let found = run(&mut watcher, &robot, 2_000, 4_000);
    assert_eq!(
        causes(&found),
        [
            "control mode changed: can -> rc",
            "RC override: the RC transmitter took control from can mode (switch SWB in the middle)",
        ]
    );
    assert_eq!(found[1].cause, Cause::RcOverride { wire: Wire::CanV2, from: MODE_CAN });
    robot.status.control_mode = MODE_STANDBY;
    assert_eq!(causes(&run(&mut watcher, &robot, 4_000, 6_000)), ["control mode changed: rc -> standby"]);
    // A power cycle of the robot itself: CAN -> standby.
    robot.status.control_mode = MODE_CAN;
    run(&mut watcher, &robot, 6_000, 8_000);
    robot.status.control_mode = MODE_STANDBY;
    assert_eq!(causes(&run(&mut watcher, &robot, 8_000, 10_000)), ["control mode changed: can -> standby"]);
    // From standby the transmitter overrides no host: a mode change, no RC override.
    robot.status.control_mode = MODE_RC;
    assert_eq!(causes(&run(&mut watcher, &robot, 10_000, 12_000)), ["control mode changed: standby -> rc"]);
}

#[test]
fn a_flapping_mode_fires_once_per_quiet_rearm_time() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    run(&mut watcher, &robot, 0, 500);
    let mut found = Vec::new();
    for step in 0..10 {
        robot.status.control_mode = if step % 2 == 0 { MODE_RC } else { MODE_CAN };
        found.extend(run(&mut watcher, &robot, 500 + step * 200, 700 + step * 200));
    }
    assert_eq!(
        causes(&found),
        [
            "control mode changed: can -> rc",
            "RC override: the RC transmitter took control from can mode (switch SWB in the middle)",
        ]
    );
}

#[test]
fn rc_override_on_rs232_and_v1_where_0_means_rc() {
    for (wire, command) in [(Wire::Serial, MODE_SERIAL), (Wire::CanV1, MODE_CAN)] {
        let mut watcher = watcher();
        let mut robot = Robot::new(wire);
        robot.status.control_mode = 0;
        assert!(run(&mut watcher, &robot, 0, 1_000).is_empty(), "{wire:?}: at 0 from the start");
        robot.status.control_mode = command;
        assert!(run(&mut watcher, &robot, 1_000, 3_000).is_empty(), "{wire:?}: the host takes control");
        robot.status.control_mode = 0;
        let found = run(&mut watcher, &robot, 3_000, 5_000);
        let kinds: Vec<&str> = found.iter().map(|t| t.cause.slug()).collect();
        assert_eq!(kinds, ["mode-change", "rc-override"], "{wire:?}");
        assert_eq!(found[1].cause, Cause::RcOverride { wire, from: command });
    }
}

#[test]
fn rc_override_from_the_swb_switch_of_0x241() {
    let mut watcher = watcher();
    let robot = Robot::new(Wire::CanV2);
    let mut out = Vec::new();
    run(&mut watcher, &robot, 0, 500);
    let rc = |switches| v2(Message::RcState(RcState { switches, ..RcState::default() }));
    // SWB bits 3:2; 0b10 up, 0b01 middle.
    watcher.frame(ms(500), &rc(0b1010_1010), &mut out);
    watcher.frame(ms(520), &rc(0b1010_0110), &mut out);
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].cause, Cause::RcOverride { wire: Wire::CanV2, from: MODE_CAN });
    assert_eq!(out[0].at, ms(520));
    // The status follows with RC: the same override, one more cause (the mode change).
    let mut robot = robot;
    robot.status.control_mode = MODE_RC;
    assert_eq!(causes(&run(&mut watcher, &robot, 540, 1_000)), ["control mode changed: can -> rc"]);
}

#[test]
fn link_silence_is_found_by_tick_once_per_silence() {
    let mut watcher = watcher();
    let robot = Robot::new(Wire::CanV2);
    run(&mut watcher, &robot, 0, 1_000);
    // The last status came at 980.1 ms; the limit is 5 x 20 ms.
    let mut out = Vec::new();
    for t in (1_000..3_000).step_by(100) {
        watcher.tick(ms(t), &mut out);
    }
    assert_eq!(out.len(), 1, "{out:?}");
    assert_eq!(
        out[0].cause,
        Cause::LinkSilence { id: FrameId::Standard(0x211), limit: Duration::from_millis(100) }
    );
    assert_eq!(out[0].at, Timestamp { nanos: 80_100_000, ..ms(1_000) }, "0.9801 s + 0.1 s");
    assert_eq!(out[0].cause.describe(), "link silence: no system status (0x211) for more than 100 ms");
    // Back for 0.5 s, silent again: within the re-arm time. Back for 2 s, silent again: a new incident.
    run(&mut watcher, &robot, 3_000, 3_500);
    let mut out = Vec::new();
    (3_600..4_000).step_by(100).for_each(|t| watcher.tick(ms(t), &mut out));
    run(&mut watcher, &robot, 4_000, 6_000);
    assert!(out.is_empty(), "{out:?}");
    (6_100..7_000).step_by(100).for_each(|t| watcher.tick(ms(t), &mut out));
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].at, Timestamp { nanos: 80_100_000, ..ms(6_000) }, "5.9801 s + 0.1 s");
}

#[test]
fn link_silence_is_found_by_the_next_frame_after_a_gap() {
    // A replay at full speed: no tick between the frames, only the frames' own stamps.
    let mut watcher = watcher();
    let robot = Robot::new(Wire::CanV2);
    run(&mut watcher, &robot, 0, 1_000);
    let mut out = Vec::new();
    watcher.frame(ms(1_080), &robot.frames(1_080)[0], &mut out);
    assert!(out.is_empty(), "the motion command at 1.08 s is within the limit");
    let found = run(&mut watcher, &robot, 9_000, 10_000);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].cause.slug(), "link-silence");
    assert_eq!(found[0].at, Timestamp { nanos: 80_100_000, ..ms(1_000) });
    // Status stopping while other frames go on: found by those frames.
    let mut watcher = Watcher::new(TriggerSettings::default());
    run(&mut watcher, &robot, 0, 1_000);
    let mut out = Vec::new();
    for t in (1_000..2_000).step_by(20) {
        watcher.frame(ms(t), &robot.frames(t)[0], &mut out);
    }
    assert_eq!(out.len(), 1);
    assert_eq!(out[0].at, Timestamp { nanos: 80_100_000, ..ms(1_000) });
}

#[test]
fn no_silence_before_any_status_and_v1_waits_five_of_its_periods() {
    let mut watcher = watcher();
    let mut out = Vec::new();
    (0..10_000).step_by(100).for_each(|t| watcher.tick(ms(t), &mut out));
    assert!(out.is_empty());
    let robot = Robot::new(Wire::CanV1);
    run(&mut watcher, &robot, 10_000, 11_000);
    watcher.tick(ms(11_400), &mut out);
    assert!(out.is_empty(), "V1's status is every 100 ms: silent after 500 ms");
    watcher.tick(ms(11_500), &mut out);
    assert_eq!(out.len(), 1);
    assert_eq!(
        out[0].cause,
        Cause::LinkSilence { id: FrameId::Standard(0x151), limit: Duration::from_millis(500) }
    );
}

#[test]
fn a_noisy_battery_fires_once_thanks_to_the_hysteresis() {
    let mut watcher = watcher();
    let mut robot = Robot::new(Wire::CanV2);
    let mut found = Vec::new();
    // Sagging under load: 22.6, 22.4, 22.7, 22.3, ... for 10 s, each value for 0.2 s, so up to 0.6 s above.
    for (step, decivolts) in [226u16, 224, 227, 223, 227, 227, 227, 224].iter().cycle().take(50).enumerate() {
        robot.status.battery_decivolts = *decivolts;
        let from = step as u64 * 200;
        found.extend(run(&mut watcher, &robot, from, from + 200));
    }
    assert_eq!(causes(&found), ["battery 22.4 V, below the warning threshold of 22.5 V"]);
    // Charged to 22.8 V (threshold + 0.3 V) for 1 s: re-armed; low again fires again.
    robot.status.battery_decivolts = 228;
    run(&mut watcher, &robot, 10_000, 11_000);
    robot.status.battery_decivolts = 220;
    let again = run(&mut watcher, &robot, 11_000, 12_000);
    assert_eq!(again.len(), 1);
    assert_eq!(again[0].cause, Cause::BatteryLow { volts: 22.0, threshold: 22.5 });
}

#[test]
fn the_battery_threshold_is_a_setting() {
    let settings = TriggerSettings { battery_warning_volts: 24.0, ..TriggerSettings::default() };
    let mut watcher = Watcher::new(settings);
    let mut robot = Robot::new(Wire::CanV2);
    robot.status.battery_decivolts = 240;
    assert!(run(&mut watcher, &robot, 0, 1_000).is_empty(), "24.0 is not below 24.0");
    robot.status.battery_decivolts = 239;
    assert_eq!(run(&mut watcher, &robot, 1_000, 2_000).len(), 1);
}

#[test]
fn error_frames_fire_once_per_burst_and_bus_state_changes_for_the_worse() {
    let mut watcher = watcher();
    let mut out = Vec::new();
    let overrun = error_frame(0x004, &[0, 0x01, 0, 0, 0, 0, 0, 0]);
    for t in 0..50 {
        watcher.frame(ms(t * 10), &overrun, &mut out);
    }
    assert_eq!(causes(&out), ["CAN error frame: controller_problem (rx_overflow)"]);
    out.clear();
    let warning = error_frame(0x004, &[0, 0x08, 0, 0, 0, 0, 96, 0]);
    let passive = error_frame(0x004, &[0, 0x20, 0, 0, 0, 0, 128, 0]);
    let bus_off = error_frame(0x040, &[0; 8]);
    let restarted = error_frame(0x100, &[0; 8]);
    watcher.frame(ms(600), &warning, &mut out);
    watcher.frame(ms(700), &passive, &mut out);
    watcher.frame(ms(800), &bus_off, &mut out);
    watcher.frame(ms(900), &restarted, &mut out);
    assert_eq!(
        causes(&out),
        [
            "CAN bus state: error-active -> error-warning",
            "CAN bus state: error-warning -> error-passive",
            "CAN bus state: error-passive -> bus-off",
        ]
    );
    // Bus-off again soon after the restart: within the re-arm time. After 1 s of error-active: again.
    out.clear();
    watcher.frame(ms(1_000), &bus_off, &mut out);
    watcher.frame(ms(1_100), &restarted, &mut out);
    assert!(out.is_empty(), "{out:?}");
    watcher.frame(ms(2_100), &bus_off, &mut out);
    assert_eq!(causes(&out), ["CAN bus state: error-active -> bus-off"]);
    let state = watcher.state();
    assert_eq!(state["bus"]["state"], "bus-off");
    assert_eq!(state["bus"]["error_frames"], 57);
    assert_eq!(state["bus"]["last_error_frame"]["classes"], serde_json::json!(["bus_off"]));
}

#[test]
fn expressions_on_fields_fire_on_any_carrier_and_on_identifiers() {
    let mut watcher = with_expressions(&["current>15", "battery_voltage<23.0", "id=0x441"]);
    let mut robot = Robot::new(Wire::CanV2);
    assert!(run(&mut watcher, &robot, 0, 1_000).is_empty());
    robot.currents = [160, 14];
    let found = run(&mut watcher, &robot, 1_000, 2_000);
    assert_eq!(causes(&found), ["trigger current>15: current = 16.0 (0x251)"]);
    // Motor 2 above while motor 1 drops: still true, the same onset.
    robot.currents = [150, 170];
    assert!(run(&mut watcher, &robot, 2_000, 3_000).is_empty());
    robot.currents = [12, 14];
    run(&mut watcher, &robot, 3_000, 4_000);
    robot.currents = [12, 151];
    assert_eq!(
        causes(&run(&mut watcher, &robot, 4_000, 5_000)),
        ["trigger current>15: current = 15.1 (0x252)"]
    );
    robot.status.battery_decivolts = 229;
    let found = run(&mut watcher, &robot, 5_000, 6_000);
    assert_eq!(found.len(), 1, "22.9 V is not below the warning threshold");
    assert_eq!(found[0].cause.describe(), "trigger battery_voltage<23.0: battery_voltage = 22.9 (0x211)");
    let clear = v2(Message::FaultClear(0));
    let mut out = Vec::new();
    watcher.frame(ms(6_000), &clear, &mut out);
    watcher.frame(ms(6_500), &clear, &mut out);
    watcher.frame(ms(7_600), &clear, &mut out);
    // The robot's feedback stopped at 6 s: a link silence too, found by the 0x441 at 6.5 s.
    assert_eq!(
        causes(&out),
        [
            "trigger id=0x441: 0x441 seen",
            "link silence: no system status (0x211) for more than 100 ms",
            "trigger id=0x441: 0x441 seen"
        ]
    );
    assert_eq!((out[0].at, out[2].at), (ms(6_000), ms(7_600)));
    let state = watcher.state();
    assert_eq!(state["triggers"][1], serde_json::json!({"trigger": "battery_voltage<23.0", "holds": true}));
}

#[test]
fn without_defaults_only_expressions_fire() {
    let expressions = vec!["vehicle_state=estop".parse().unwrap()];
    let mut watcher =
        Watcher::new(TriggerSettings { defaults: false, expressions, ..TriggerSettings::default() });
    let mut robot = Robot::new(Wire::CanV2);
    robot.status =
        SystemState { vehicle_state: VEHICLE_ESTOP, battery_decivolts: 200, fault_code: 0x0700, ..healthy() };
    let found = run(&mut watcher, &robot, 0, 1_000);
    assert_eq!(causes(&found), ["trigger vehicle_state=estop: vehicle_state = estop (0x211)"]);
    let mut out = Vec::new();
    watcher.tick(ms(5_000), &mut out);
    assert!(out.is_empty());
    assert_eq!(watcher.state()["estop"], true, "the state is kept all the same");
}

#[test]
fn rs232_and_v1_frames_fire_the_same_triggers() {
    for wire in [Wire::Serial, Wire::CanV1] {
        let mut watcher = watcher();
        let mut robot = Robot::new(wire);
        run(&mut watcher, &robot, 0, 1_000);
        robot.status.vehicle_state = VEHICLE_ESTOP;
        robot.status.fault_code = 0x0040 | 0x0004; // driver over-temperature protection, motor 1 comm
        robot.status.battery_decivolts = 222;
        let found = causes(&run(&mut watcher, &robot, 1_000, 3_000));
        assert_eq!(
            found,
            [
                "E-stop pressed",
                "battery 22.2 V, below the warning threshold of 22.5 V",
                "fault bit set: motor1_comm_fault [fault]: no communication with motor driver 1",
                "fault bit set: driver_overheat_protection [protection]: motor driver above 65 C: output \
                 limited, motion commands ignored",
            ],
            "{wire:?}"
        );
    }
}

#[test]
fn the_state_holds_the_latest_of_everything() {
    let mut watcher = with_expressions(&["rpm>0"]);
    let mut robot = Robot::new(Wire::CanV2);
    robot.status.fault_code = 0x0400;
    robot.drivers = [0x40, 0x10];
    run(&mut watcher, &robot, 0, 1_000);
    let state = watcher.state();
    assert_eq!(state["vehicle_state"], "normal");
    assert_eq!(state["control_mode"], "can");
    assert_eq!(state["battery_voltage"], 25.9);
    assert_eq!(state["wire"], "can-v2");
    assert_eq!(state["messages"]["0x211"]["fields"]["faults"], serde_json::json!(["rc_disconnected"]));
    assert_eq!(state["messages"]["0x252"]["fields"]["current"], 1.4);
    assert_eq!(
        state["messages"]["0x262"]["fields"]["driver_faults"],
        serde_json::json!(["can_disconnected"])
    );
    assert_eq!(state["messages"]["0x111"]["msg"], "motion_command");
    let faults: Vec<(&str, &str)> = state["faults"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["source"].as_str().unwrap(), f["name"].as_str().unwrap()))
        .collect();
    assert_eq!(
        faults,
        [("system", "rc_disconnected"), ("motor 2 driver", "can_disconnected")],
        "no [info] bit"
    );
    assert_eq!(state["link"]["status_id"], "0x211");
    assert_eq!(state["link"]["silence_limit_ms"], 100);
    assert_eq!(state["link"]["silent"], false);
    assert_eq!(state["link"]["last_status_kind"], "relative");
    assert_eq!(state["bus"]["last_error_frame"], serde_json::Value::Null);
    assert_eq!(state["triggers"][0]["holds"], true);
    assert_eq!(state["estop"], false);
}

#[test]
fn settings_default_to_the_protocols_threshold() {
    let settings = TriggerSettings::default();
    assert!(settings.defaults && settings.expressions.is_empty());
    assert_eq!(settings.battery_warning_volts, 22.5);
    assert_eq!(settings.rearm, Duration::from_secs(1));
}

/// A frame of any kind the watcher may meet: TRACER identifiers of every wire with random data, other
/// identifiers, error frames, RS232 frames.
fn any_frame() -> impl Strategy<Value = LinkFrame> {
    let ids = prop_oneof![
        prop::sample::select(vec![
            0x111u32, 0x121, 0x130, 0x131, 0x140, 0x141, 0x151, 0x201, 0x202, 0x211, 0x221, 0x231, 0x241,
            0x251, 0x252, 0x261, 0x262, 0x311, 0x41A, 0x421, 0x441,
        ]),
        0u32..0x800,
    ];
    prop_oneof![
        6 => (ids, prop::collection::vec(any::<u8>(), 0..=8))
            .prop_map(|(id, data)| LinkFrame::Can(CanFrame::new(id, &data).unwrap())),
        1 => (0u32..0x400, prop::collection::vec(any::<u8>(), 0..=8))
            .prop_map(|(class, data)| LinkFrame::Can(CanFrame::new_error(class, &data).unwrap())),
        2 => (prop::sample::select(vec![0x55u8, 0xAA]), 1u8..8, any::<[u8; 6]>(), any::<u8>()).prop_map(
            |(frame_type, command, payload, frame_id)| {
                LinkFrame::Serial(serial::SerialFrame { frame_type, command, payload, frame_id })
            }
        ),
    ]
}

/// A frame, or a tick, after a gap in ms.
#[derive(Clone, Debug)]
enum Step {
    Frame(u64, LinkFrame),
    Tick(u64),
}

fn any_step() -> impl Strategy<Value = Step> {
    let gap = prop_oneof![8 => 0u64..30, 1 => 0u64..3_000];
    prop_oneof![
        9 => (gap.clone(), any_frame()).prop_map(|(gap, frame)| Step::Frame(gap, frame)),
        1 => gap.prop_map(Step::Tick),
    ]
}

proptest! {
    #[test]
    fn random_streams_never_panic_and_never_fire_before_the_previous_call(
        steps in prop::collection::vec(any_step(), 1..400),
        expression in prop::sample::select(vec!["rpm>100", "id=0x211", "faults=rc_disconnected", "control_mode!=can"]),
    ) {
        let expressions = vec![expression.parse().unwrap()];
        let mut watcher = Watcher::new(TriggerSettings { expressions, ..TriggerSettings::default() });
        let (mut now, mut before) = (1_000u64, 0u64);
        for step in steps {
            let mut out = Vec::new();
            let called_at = match step {
                Step::Frame(gap, frame) => {
                    now += gap;
                    watcher.frame(ms(now), &frame, &mut out);
                    now
                }
                Step::Tick(gap) => {
                    now += gap;
                    watcher.tick(ms(now), &mut out);
                    now
                }
            };
            for trigger in &out {
                let at = nanos_of(trigger.at);
                prop_assert!(at <= nanos_of(ms(called_at)), "{trigger:?} after its call at {called_at} ms");
                prop_assert!(at >= nanos_of(ms(before)), "{trigger:?} before the previous call at {before} ms");
                prop_assert!(!trigger.cause.describe().is_empty());
            }
            before = called_at;
        }
        let _ = watcher.state();
    }

    #[test]
    fn a_clock_that_jumps_around_never_panics(
        frames in prop::collection::vec((any::<u64>(), any::<u32>(), any_frame()), 1..100),
    ) {
        let mut watcher = watcher();
        let mut out = Vec::new();
        for (secs, nanos, frame) in frames {
            let at = Timestamp { secs, nanos: nanos % 1_000_000_000, kind: TimestampKind::Absolute };
            watcher.frame(at, &frame, &mut out);
            watcher.tick(at, &mut out);
        }
        let _ = watcher.state();
    }
}
