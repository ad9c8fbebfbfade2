//! The chassis parameters of `--sim-param`, each checked at the feedback level: a CAN robot driven by
//! motion commands at 50 Hz, its feedback collected every millisecond, the effect read from the frames a
//! host would see (0x221, 0x251/0x252, 0x311, 0x211). And the defaults give the frames of the model before
//! the parameters existed, byte for byte.

use std::time::Duration;

use super::*;
use crate::protocol::message::*;

fn ms(n: u64) -> Duration {
    Duration::from_millis(n)
}

/// A robot and the feedback it sent, with the millisecond each frame was due.
struct Run {
    robot: Chassis,
    frames: Vec<(u64, Message)>,
}

/// A CAN robot with these `--sim-param`s, in command mode at 0.
fn run(params: &[(&str, &str)]) -> Run {
    run_with(SimConfig::default(), params)
}

fn run_with(mut config: SimConfig, params: &[(&str, &str)]) -> Run {
    for (name, value) in params {
        config.set_param(name, value).unwrap();
    }
    let mut robot = Chassis::new(config);
    robot.receive(ms(0), &Message::ControlModeCommand(MODE_CAN));
    Run { robot, frames: Vec::new() }
}

impl Run {
    /// From `from` to `to` (ms, exclusive): sends (v m/s, w rad/s) every 20 ms from `from` (none for
    /// `None`) and collects the feedback due at every millisecond.
    fn drive(&mut self, command: Option<(f64, f64)>, from: u64, to: u64) {
        for t in from..to {
            if let Some((linear, angular)) = command.filter(|_| (t - from) % 20 == 0) {
                let command = MotionCommand {
                    linear_mm_s: (linear * 1000.0).round() as i16,
                    angular_mrad_s: (angular * 1000.0).round() as i16,
                };
                self.robot.receive(ms(t), &Message::MotionCommand(command));
            }
            let mut out = Vec::new();
            self.robot.due_feedback(ms(t), &mut out);
            self.frames.extend(out.into_iter().map(|message| (t, message)));
        }
    }

    fn motion(&self) -> Vec<(u64, MotionState)> {
        let motion =
            |(t, m): &(u64, Message)| if let Message::MotionState(s) = m { Some((*t, *s)) } else { None };
        self.frames.iter().filter_map(motion).collect()
    }

    /// 0x221 of the slot at `t`: (mm/s, mrad/s).
    fn motion_at(&self, t: u64) -> (i16, i16) {
        let (_, state) = self.motion().into_iter().find(|(at, _)| *at == t).expect("a slot at t");
        (state.linear_mm_s, state.angular_mrad_s)
    }

    fn odometry_at(&self, t: u64) -> (i32, i32) {
        let odometry = self.frames.iter().find_map(|(at, m)| match m {
            Message::Odometry(o) if *at == t => Some((o.left_mm, o.right_mm)),
            _ => None,
        });
        odometry.expect("a slot at t")
    }

    /// 0x251 and 0x252 of the slot at `t`.
    fn motors_at(&self, t: u64) -> Vec<MotorHighSpeed> {
        let motor = |(at, m): &(u64, Message)| match m {
            Message::MotorHighSpeed(s) if *at == t => Some(*s),
            _ => None,
        };
        self.frames.iter().filter_map(motor).collect()
    }

    fn battery_decivolts_at(&self, t: u64) -> u16 {
        let system = self.frames.iter().find_map(|(at, m)| match m {
            Message::SystemState(s) if *at == t => Some(s.battery_decivolts),
            _ => None,
        });
        system.expect("a slot at t")
    }
}

fn standard_deviation(values: &[f64]) -> f64 {
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    (values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
}

// ---- the defaults are today's model ----

#[test]
fn every_new_field_at_its_default_is_the_default_config() {
    let spelled_out = SimConfig {
        dead_time: Duration::ZERO,
        lag: Duration::ZERO,
        left_gain: 1.0,
        right_gain: 1.0,
        effective_track_m: crate::protocol::constants::TRACK_M,
        odometer_scale: 1.0,
        noise: 0.0,
        seed: 1,
        ..SimConfig::default()
    };
    assert_eq!(spelled_out, SimConfig::default());
    assert_eq!(SimConfig::default().effective_track_m, SimConfig::default().track_m);
    assert_eq!(SimConfig::default().non_default_params(), Vec::<String>::new());
}

/// A long run of both wires through driving, turning, the command timeout, an E-stop, a latched fault,
/// a low battery and lights: every feedback message and a state snapshot every 100 ms, hashed (FNV-1a
/// over their Debug text, which prints every float exactly).
fn golden_digest(config: SimConfig) -> u64 {
    let mut text = String::new();
    let mut robot = Chassis::new(config.clone());
    let serial = config.wire == SimWire::Serial;
    let drive = |linear: f64, angular: f64| {
        if serial {
            Message::PercentMotionCommand(
                PercentMotionCommand::from_si(MODE_SERIAL, linear, angular).unwrap(),
            )
        } else {
            Message::MotionCommand(MotionCommand::from_si(linear, angular).unwrap())
        }
    };
    type Step = (u64, u64, Option<(f64, f64)>);
    let plan: [Step; 8] = [
        (0, 2000, Some((1.0, 0.0))),
        (2000, 3000, Some((0.5, 0.6))),
        (3000, 4200, None),
        (4200, 5000, Some((-0.3, -0.7))),
        (5000, 6000, Some((1.5, 0.78))),
        (6000, 7000, Some((0.0, 0.0))),
        (7000, 8000, Some((0.8, -0.4))),
        (8000, 9000, None),
    ];
    let mut out = Vec::new();
    for t in 0..9000u64 {
        let now = std::time::Duration::from_micros(t * 1000 + 250);
        if t == 0 || t == 6500 {
            robot.receive(now, &Message::ControlModeCommand(MODE_CAN));
        }
        if t == 100 {
            robot.receive(
                now,
                &Message::LightCommand(Lights {
                    enable: 1,
                    front_mode: 3,
                    front_brightness: 70,
                    ..Lights::default()
                }),
            );
        }
        if t == 5500 {
            robot.inject(now, FaultKind::EStop);
        }
        if t == 5800 {
            robot.inject(now, FaultKind::EStopRelease);
        }
        if t == 7500 {
            robot.inject(now, FaultKind::Motor1Comm);
        }
        if t == 7700 {
            robot.receive(now, &Message::FaultClear(0));
            robot.inject(now, FaultKind::BatteryLow);
        }
        if t % 20 == 0 {
            for (from, to, command) in plan {
                if (from..to).contains(&t) {
                    if let Some((linear, angular)) = command {
                        robot.receive(now, &drive(linear, angular));
                    }
                }
            }
        }
        robot.due_feedback(now, &mut out);
        if t % 100 == 0 {
            text.push_str(&format!("{:?}\n{:?}\n", out, robot.state()));
            out.clear();
        }
    }
    text.push_str(&format!("{out:?}"));
    text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[test]
fn defaults_give_the_frames_of_the_model_before_the_parameters() {
    // Captured from the model before `--sim-param` existed (commit 751dec6) with this same scenario.
    assert_eq!(golden_digest(SimConfig::default()), 0x110a_8668_08cf_080e);
    assert_eq!(
        golden_digest(SimConfig { wire: SimWire::Serial, ..SimConfig::default() }),
        0x0479_0747_41cb_5f58
    );
    // Every parameter set to its default value explicitly changes nothing either ...
    let mut explicit = SimConfig::default();
    for param in SIM_PARAMS {
        let value = param.get(&SimConfig::default());
        let text = match param.kind {
            ParamKind::Time => format!("{value}ms"),
            ParamKind::Number => value.to_string(),
            ParamKind::Whole => (value as u64).to_string(),
        };
        explicit.set_param(param.name, &text).unwrap();
    }
    assert_eq!(explicit, SimConfig::default());
    // ... while the digest does see a change of any one.
    for (name, value) in [("dead-time", "20ms"), ("lag", "10ms"), ("left-gain", "0.99"), ("noise", "0.5")] {
        let mut config = SimConfig::default();
        config.set_param(name, value).unwrap();
        assert_ne!(golden_digest(config), 0x110a_8668_08cf_080e, "{name}");
    }
}

// ---- dead time ----

#[test]
fn dead_time_delays_the_first_motion_to_the_slot_after_command_plus_dead_time() {
    for dead_ms in [0u64, 1, 37, 100, 200] {
        let mut run = run(&[("dead-time", &format!("{dead_ms}ms"))]);
        run.drive(Some((0.5, 0.0)), 40, 600);
        let first_moving = run.motion().into_iter().find(|(_, s)| s.linear_mm_s != 0).unwrap().0;
        // The command acts on the drive at tick 40 + dead time, so the model moves from the next tick.
        let expected = (40 + dead_ms + 1).div_ceil(20) * 20;
        assert_eq!(first_moving, expected, "dead time {dead_ms} ms");
        assert_eq!(run.motion_at(expected - 20), (0, 0));
    }
}

#[test]
fn dead_time_delays_the_timeout_stop_but_not_an_estop() {
    // Last command at 980 ms: the 500 ms timeout zeroes the target at 1480 ms, which the drive sees
    // 100 ms later. Braking at 1 m/s2: 20 mm/s per slot.
    let mut delayed = run(&[("dead-time", "100ms")]);
    delayed.drive(Some((0.5, 0.0)), 0, 1000);
    delayed.drive(None, 1000, 2000);
    assert_eq!(delayed.motion_at(1580).0, 500);
    assert_eq!(delayed.motion_at(1600).0, 480);
    let mut prompt = run(&[]);
    prompt.drive(Some((0.5, 0.0)), 0, 1000);
    prompt.drive(None, 1000, 2000);
    assert_eq!((prompt.motion_at(1480).0, prompt.motion_at(1500).0), (500, 480));

    let mut estop = run(&[("dead-time", "200ms")]);
    estop.drive(Some((0.5, 0.0)), 0, 1000);
    estop.robot.inject(ms(1000), FaultKind::EStop);
    estop.drive(Some((0.5, 0.0)), 1000, 1500);
    assert_eq!(estop.motion_at(980).0, 500);
    assert!(estop.motion().iter().filter(|(t, _)| *t >= 1000).all(|(_, s)| s.linear_mm_s == 0));
    assert_eq!(estop.robot.state().linear, 0.0);
}

#[test]
fn dead_time_delays_a_motion_block_stop_like_any_target_change() {
    // A latched fault zeroes the target (ramped), through the dead time.
    let mut run = run(&[("dead-time", "60ms")]);
    run.drive(Some((0.5, 0.0)), 0, 1000);
    run.robot.inject(ms(1000), FaultKind::Motor1Comm);
    run.drive(Some((0.5, 0.0)), 1000, 1200);
    assert_eq!(run.motion_at(1060).0, 500);
    assert_eq!(run.motion_at(1080).0, 480);
}

// ---- lag and acceleration ----

#[test]
fn lag_closes_63_percent_of_the_gap_in_one_time_constant() {
    // A 40 ms ramp (0.2 m/s at 5 m/s2) into a 100 ms lag, from 40 ms.
    let mut run = run(&[("lag", "100ms"), ("max-accel", "5")]);
    run.drive(None, 0, 40);
    run.drive(Some((0.2, 0.0)), 40, 1000);
    let (v, tau, ramp): (f64, f64, f64) = (200.0, 0.1, 0.04);
    // A first-order lag behind a ramp of length `ramp`, t after the ramp started (continuous time).
    let lagged = |t: f64| v * (1.0 - (tau / ramp) * ((ramp / tau).exp() - 1.0) * (-t / tau).exp());
    let at_one_tau = f64::from(run.motion_at(140).0);
    assert!((at_one_tau - lagged(0.1)).abs() <= 1.0, "{at_one_tau} vs {}", lagged(0.1));
    // One time constant later the remaining gap has shrunk to 1/e: 63.2 % of it closed.
    let later = f64::from(run.motion_at(240).0);
    let closed = (later - at_one_tau) / (v - at_one_tau);
    assert!((closed - 0.632).abs() * (v - at_one_tau) <= 1.0, "{closed}");
    assert_eq!(run.motion_at(980).0, 200, "settles on the command");
    // Without a lag the ramp alone: 0.2 m/s after 40 ms.
    let mut prompt = self::run(&[("max-accel", "5")]);
    prompt.drive(Some((0.2, 0.0)), 40, 100);
    assert_eq!((prompt.motion_at(60).0, prompt.motion_at(80).0), (100, 200));
}

#[test]
fn a_lagged_robot_comes_to_rest_exactly_so_idle_time_is_skipped() {
    let mut run = run(&[("lag", "2s"), ("dead-time", "2s")]);
    run.drive(Some((1.0, 0.5)), 0, 3000);
    run.drive(None, 3000, 4000);
    // A day later at once: the lag arrived at zero and nothing is left on the way.
    run.robot.step(Duration::from_secs(86_400));
    let state = run.robot.state();
    assert_eq!((state.linear, state.angular), (0.0, 0.0));
    assert_eq!(state.time, Duration::from_secs(86_400));
}

#[test]
fn max_accel_limits_the_ramp_both_ways_and_the_angular_ramp_at_twice_it() {
    let mut run = run(&[("max-accel", "0.5")]);
    run.drive(Some((1.0, 0.0)), 40, 160);
    assert_eq!(run.motion_at(140).0, 50, "0.5 m/s2 for 100 ms");
    run.drive(Some((0.3, 0.0)), 160, 2000);
    run.drive(Some((0.0, 0.0)), 2000, 2200);
    assert_eq!(run.motion_at(2100).0, 250, "braking at 0.5 m/s2 too");
    let mut spin = self::run(&[("max-accel", "0.5")]);
    spin.drive(Some((0.0, 1.0)), 40, 200);
    assert_eq!(spin.motion_at(140).1, 100, "1 rad/s2 for 100 ms");
}

// ---- wheels and geometry ----

#[test]
fn wheel_gains_scale_each_wheel_and_the_odometers() {
    let mut run = run(&[("left-gain", "0.95"), ("right-gain", "1.05")]);
    run.drive(Some((0.5, 0.0)), 0, 3000);
    let (left, right) = run.odometry_at(2980);
    let ratio = f64::from(left) / f64::from(right);
    assert!((ratio / (0.95 / 1.05) - 1.0).abs() < 0.001, "{ratio}");
    // The body speeds of the actual wheels (0.475 and 0.525 m/s): v = 0.5, w = 0.05 / 0.36.
    assert_eq!(run.motion_at(2980), (500, 139));
    let motors = run.motors_at(2980);
    // Motor 1 is the right wheel: 0.525 m/s = 66.8 RPM; the left 0.475 m/s = 60.5 RPM.
    assert_eq!((motors[0].rpm, motors[1].rpm), (67, 60));
    // RS232 motion status reports the same body speeds.
    let mut serial =
        run_with(SimConfig { wire: SimWire::Serial, ..SimConfig::default() }, &[("left-gain", "0.9")]);
    let command = PercentMotionCommand::from_si(MODE_SERIAL, 0.6, 0.0).unwrap();
    for t in (0..2000).step_by(20) {
        serial.robot.receive(ms(t), &Message::PercentMotionCommand(command));
        serial.robot.step(ms(t + 19));
    }
    let state = serial.robot.state();
    let (v, w) = (command.linear(), (command.linear() - 0.9 * command.linear()) / 0.36);
    assert!((state.linear - (0.9 * v + v) / 2.0).abs() < 1e-9 && (state.angular - w).abs() < 1e-9);
    let mut out = Vec::new();
    serial.robot.due_feedback(ms(2000), &mut out);
    let motion =
        out.iter().find_map(|m| if let Message::MotionState(s) = m { Some(*s) } else { None }).unwrap();
    assert_eq!(
        (motion.linear_mm_s, motion.angular_mrad_s),
        (((0.95 * v) * 1000.0).round() as i16, (w * 1000.0).round() as i16)
    );
}

#[test]
fn track_width_turns_the_body_by_the_effective_track() {
    let mut run = run(&[("track-width", "0.40")]);
    run.drive(Some((0.0, 1.0)), 0, 3000);
    // The firmware mixes 1 rad/s into wheels at +-0.18 m/s (nominal 0.36 m); they turn the body at
    // 0.36 / 0.40 rad/s.
    let (_, measured_w) = run.motion_at(2000);
    assert_eq!(measured_w, 900);
    let (l0, r0) = run.odometry_at(1000);
    let (l1, r1) = run.odometry_at(2000);
    let track = f64::from((r1 - r0) - (l1 - l0)) / 1000.0 / (f64::from(measured_w) / 1000.0);
    assert!((track / 0.40 - 1.0).abs() < 0.005, "{track}");
    assert_eq!(((r1 - r0), (l1 - l0)), (180, -180));
}

#[test]
fn odometer_scale_scales_0x311_only() {
    let mut run = run(&[("odometer-scale", "1.03")]);
    run.drive(Some((0.5, 0.0)), 0, 2001);
    let (left_m, right_m) = run.robot.odometry_m();
    let (left, right) = run.odometry_at(2000);
    assert_eq!((left, right), ((left_m * 1030.0).round() as i32, (right_m * 1030.0).round() as i32));
    assert!((f64::from(left) / (left_m * 1000.0) / 1.03 - 1.0).abs() < 0.001);
    assert_eq!(run.motion_at(2000).0, 500, "the speeds are not scaled");
    assert_eq!(run.robot.state().odometry_left_mm, left, "the state reports what 0x311 does");
}

// ---- command timeout and battery ----

#[test]
fn command_timeout_starts_braking_that_long_after_the_last_command() {
    for (timeout, onset) in [("300ms", 1280), ("0.5s", 1480), ("800ms", 1780)] {
        let mut run = run(&[("command-timeout", timeout)]);
        run.drive(Some((0.5, 0.0)), 0, 1000);
        run.drive(None, 1000, 2500);
        // Last command at 980 ms.
        assert_eq!(run.motion_at(onset).0, 500, "{timeout}");
        assert_eq!(run.motion_at(onset + 20).0, 480, "{timeout}");
    }
}

#[test]
fn the_battery_reads_open_circuit_voltage_minus_current_times_resistance() {
    let mut run = run(&[("battery-ocv", "25"), ("battery-r", "0.2")]);
    run.drive(None, 0, 100);
    assert_eq!(run.battery_decivolts_at(80), 248, "at rest: 1 A idle");
    run.drive(Some((1.0, 0.0)), 100, 3000);
    let motors = run.motors_at(2980);
    let current = 1.0 + f64::from(motors[0].current_deciamps + motors[1].current_deciamps) / 10.0;
    assert_eq!(current, 5.0, "1 A idle + 2 A per motor at 1 m/s");
    let expected = (25.0 - current * 0.2) * 10.0;
    assert!((f64::from(run.battery_decivolts_at(2980)) - expected).abs() <= 1.0);
    assert_eq!(run.battery_decivolts_at(2980), 240);
}

// ---- noise ----

/// 1000 0x221 frames cruising at 0.5 m/s (after 1 s to settle).
fn steady_frames(params: &[(&str, &str)]) -> Run {
    let mut run = run(params);
    run.drive(Some((0.5, 0.1)), 0, 21_000);
    run
}

#[test]
fn noise_has_the_standard_deviation_asked_for_in_each_fields_resolution() {
    for sigma in [1.0, 2.0] {
        let run = steady_frames(&[("noise", &sigma.to_string()), ("seed", "7")]);
        let speeds: Vec<f64> =
            run.motion().iter().filter(|(t, _)| *t >= 1000).map(|(_, s)| f64::from(s.linear_mm_s)).collect();
        assert_eq!(speeds.len(), 1000);
        let deviation = standard_deviation(&speeds);
        assert!((deviation / sigma - 1.0).abs() < 0.1, "noise {sigma}: {deviation} mm/s");
        let mean = speeds.iter().sum::<f64>() / speeds.len() as f64;
        assert!((mean - 500.0).abs() < 0.3, "{mean}");
        let angular: Vec<f64> = run
            .motion()
            .iter()
            .filter(|(t, _)| *t >= 1000)
            .map(|(_, s)| f64::from(s.angular_mrad_s))
            .collect();
        assert!((standard_deviation(&angular) / sigma - 1.0).abs() < 0.1);
        let volts: Vec<f64> = run
            .frames
            .iter()
            .filter_map(|(t, m)| match m {
                Message::SystemState(s) if *t >= 1000 => Some(f64::from(s.battery_decivolts)),
                _ => None,
            })
            .collect();
        assert!((standard_deviation(&volts) / sigma - 1.0).abs() < 0.15, "{}", standard_deviation(&volts));
        let currents = run.frames.iter().filter_map(|(_, m)| match m {
            Message::MotorHighSpeed(s) => Some(s.current_deciamps),
            _ => None,
        });
        assert!(currents.clone().all(|c| c >= 0));
        assert!(currents.collect::<std::collections::BTreeSet<_>>().len() > 5, "currents are noisy too");
    }
}

#[test]
fn noise_is_reproducible_and_touches_only_reported_values() {
    let frames = |params: &[(&str, &str)]| steady_frames(params).frames;
    let noisy = frames(&[("noise", "1"), ("seed", "42")]);
    assert_eq!(noisy, frames(&[("noise", "1"), ("seed", "42")]), "the same seed, the same frames");
    assert_ne!(noisy, frames(&[("noise", "1"), ("seed", "43")]));
    let quiet = frames(&[("noise", "0"), ("seed", "42")]);
    assert_eq!(quiet, frames(&[]), "noise 0 is today's frames, whatever the seed");
    let odometry = |frames: &[(u64, Message)]| -> Vec<Message> {
        frames.iter().filter(|(_, m)| matches!(m, Message::Odometry(_))).map(|(_, m)| *m).collect()
    };
    assert_eq!(odometry(&noisy), odometry(&quiet), "odometers are exact");
    let noisy_state = steady_frames(&[("noise", "2")]).robot.state();
    assert_eq!(noisy_state, steady_frames(&[]).robot.state(), "the model's state has no noise");
    // At rest a motor's current reads 0 A, noise or not.
    let mut rest = run(&[("noise", "3")]);
    rest.drive(None, 0, 1000);
    assert!(rest
        .frames
        .iter()
        .all(|(_, m)| !matches!(m, Message::MotorHighSpeed(s) if s.current_deciamps != 0)));
}
