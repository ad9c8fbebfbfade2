//! Property tests for the virtual TRACER: no message sequence makes it panic or exceed its limits, the
//! odometers equal the integrated wheel speeds, and feedback keeps its 20 ms grid for any step pattern.

use std::time::Duration;

use proptest::prelude::*;

use tracerctl::protocol::message::*;
use tracerctl::sim::{Chassis, FaultKind, SimConfig, SimState, SimWire};

fn lights() -> impl Strategy<Value = Lights> {
    (any::<u8>(), 0u8..6, any::<u8>(), any::<u8>()).prop_map(
        |(enable, front_mode, front_brightness, count)| Lights {
            enable: enable % 3,
            front_mode,
            front_brightness,
            count,
            ..Lights::default()
        },
    )
}

/// Host commands of both links, with garbage values, and a few feedback messages a confused host might echo.
fn message() -> impl Strategy<Value = Message> {
    prop_oneof![
        4 => (any::<i16>(), any::<i16>()).prop_map(|(linear_mm_s, angular_mrad_s)| {
            Message::MotionCommand(MotionCommand { linear_mm_s, angular_mrad_s })
        }),
        4 => (0u8..4, 0u8..10, any::<i8>(), any::<i8>()).prop_map(|(control_mode, fault_clear, l, a)| {
            Message::PercentMotionCommand(PercentMotionCommand {
                control_mode,
                fault_clear,
                linear_percent: l,
                angular_percent: a,
                ..PercentMotionCommand::default()
            })
        }),
        2 => (0u8..5).prop_map(Message::ControlModeCommand),
        1 => (0u8..4).prop_map(Message::FaultClear),
        1 => lights().prop_map(Message::LightCommand),
        1 => Just(Message::VersionRequest),
        1 => any::<u16>().prop_map(|fault_code| Message::SystemState(SystemState { fault_code, ..SystemState::default() })),
        1 => any::<i32>().prop_map(|left_mm| Message::Odometry(Odometry { left_mm, right_mm: 0 })),
    ]
}

/// Every fault, or only those that never stop the wheels dead (E-stop and battery cut-off do).
fn fault(instant_stops: bool) -> impl Strategy<Value = FaultKind> {
    let dead_stop = |f: &FaultKind| {
        matches!(
            f,
            FaultKind::EStop | FaultKind::BatteryWarning | FaultKind::BatteryLow | FaultKind::BatteryEmpty
        )
    };
    let faults: Vec<FaultKind> =
        FaultKind::ALL.into_iter().filter(|f| instant_stops || !dead_stop(f)).collect();
    proptest::sample::select(faults)
}

#[derive(Clone, Debug)]
enum Action {
    Receive(Message),
    Inject(FaultKind),
    Feedback,
}

fn actions(instant_stops: bool) -> impl Strategy<Value = Vec<(u64, Action)>> {
    let action = prop_oneof![
        6 => message().prop_map(Action::Receive),
        1 => fault(instant_stops).prop_map(Action::Inject),
        3 => Just(Action::Feedback),
    ];
    // Gaps in µs: mostly short, sometimes long enough for a timeout or a full ramp.
    let gap = prop_oneof![12 => 0u64..25_000, 1 => 0u64..1_500_000];
    proptest::collection::vec((gap, action), 1..200)
}

fn config(wire: SimWire, rc: bool, battery_drain_factor: f64) -> SimConfig {
    SimConfig { wire, rc_present: rc, battery_drain_factor, ..SimConfig::default() }
}

fn wire() -> impl Strategy<Value = SimWire> {
    prop_oneof![Just(SimWire::CanV2), Just(SimWire::Serial)]
}

fn check_limits(state: &SimState, config: &SimConfig) {
    let eps = 1e-9;
    assert!(state.linear.abs() <= config.max_linear + eps, "{state:?}");
    assert!(state.angular.abs() <= config.max_angular + eps, "{state:?}");
    for motor in &state.motors {
        assert!(motor.wheel_speed.abs() <= config.max_linear + eps, "{state:?}");
        assert!(motor.current >= 0.0 && motor.current.is_finite(), "{state:?}");
        assert!(motor.driver_temperature.is_finite(), "{state:?}");
    }
    assert!(state.commanded_linear.abs() <= config.max_linear + eps);
    assert!(state.battery_voltage.is_finite() && state.battery_voltage >= 0.0);
    assert!((0.0..=1.0).contains(&state.state_of_charge));
    assert!(state.lights.front_brightness <= 100);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn never_panics_and_stays_within_limits(wire in wire(), rc in any::<bool>(), actions in actions(true)) {
        let config = config(wire, rc, 200.0);
        let mut robot = Chassis::new(config.clone());
        let mut out = Vec::new();
        let mut t = 0u64;
        for (gap, action) in actions {
            t += gap;
            let now = Duration::from_micros(t);
            match action {
                Action::Receive(message) => robot.receive(now, &message),
                Action::Inject(fault) => robot.inject(now, fault),
                Action::Feedback => {
                    out.clear();
                    robot.due_feedback(now, &mut out);
                    let state = robot.state();
                    for message in &out {
                        if let Message::MotionState(motion) = message {
                            prop_assert_eq!(motion.linear_mm_s, (state.linear * 1000.0).round() as i16);
                            prop_assert_eq!(motion.angular_mrad_s, (state.angular * 1000.0).round() as i16);
                        }
                    }
                }
            }
            check_limits(&robot.state(), &config);
        }
    }

    #[test]
    fn odometry_equals_the_integrated_wheel_speeds(wire in wire(), actions in actions(false)) {
        // Real-time drain: the battery cannot reach its cut-off (a dead stop) within the 20 s at most.
        let mut robot = Chassis::new(config(wire, false, 1.0));
        // Get it moving on either link.
        robot.receive(Duration::ZERO, &Message::ControlModeCommand(MODE_CAN));
        let (mut left, mut right) = (0.0f64, 0.0f64);
        let (mut prev_left, mut prev_right) = robot.state().wheel_speeds();
        let mut ms = 0u64;
        let mut t = 0u64;
        for (gap, action) in actions {
            t += gap.min(100_000);
            // Sample the wheel speeds on the model's own 1 ms grid up to the action.
            while (ms + 1) * 1000 <= t {
                ms += 1;
                robot.step(Duration::from_millis(ms));
                let (l, r) = robot.state().wheel_speeds();
                left += (prev_left + l) / 2.0 * 0.001;
                right += (prev_right + r) / 2.0 * 0.001;
                (prev_left, prev_right) = (l, r);
            }
            let now = Duration::from_micros(t);
            match action {
                Action::Receive(message) => robot.receive(now, &message),
                Action::Inject(fault) => robot.inject(now, fault),
                Action::Feedback => robot.due_feedback(now, &mut Vec::new()),
            }
            // A command or fault changes targets, never the speed of this instant.
            prop_assert_eq!(robot.state().wheel_speeds(), (prev_left, prev_right));
        }
        let (odo_left, odo_right) = robot.odometry_m();
        prop_assert!((odo_left - left).abs() < 1e-9, "{} vs {}", odo_left, left);
        prop_assert!((odo_right - right).abs() < 1e-9, "{} vs {}", odo_right, right);
        let state = robot.state();
        prop_assert_eq!(state.odometry_left_mm, (odo_left * 1000.0).round() as i32);
        prop_assert_eq!(state.odometry_right_mm, (odo_right * 1000.0).round() as i32);
    }

    #[test]
    fn feedback_keeps_its_grid(wire in wire(), steps in proptest::collection::vec(1u64..=20_000, 1..400)) {
        let mut robot = Chassis::new(config(wire, false, 1.0));
        let mut out = Vec::new();
        let mut t = 0u64;
        let mut last_call = 0;
        let mut counts = Vec::new();
        for step in steps {
            last_call = t;
            out.clear();
            robot.due_feedback(Duration::from_micros(t), &mut out);
            for message in &out {
                if let Message::SystemState(system) = message {
                    prop_assert_eq!(u64::from(system.count), counts.len() as u64 % 256);
                    prop_assert_eq!(t / 20_000, counts.len() as u64, "frame {} at {} µs", counts.len(), t);
                    counts.push(t);
                }
            }
            t += step;
        }
        // Every 20 ms slot up to the last call was served, each exactly once.
        prop_assert_eq!(counts.len() as u64, last_call / 20_000 + 1);
    }
}
