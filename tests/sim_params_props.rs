//! Property tests for the simulator's `--sim-param`s: any parameter set within the allowed ranges
//! (docs/sim.md), under any motion commands and faults, never panics and never puts NaN or infinity in the
//! model's state or its speeds.

use std::time::Duration;

use proptest::prelude::*;

use tracerctl::protocol::message::*;
use tracerctl::sim::{Chassis, FaultKind, ParamKind, SimConfig, SimParam, SimWire, SIM_PARAMS};

/// A value for `param` within its allowed range, as `--sim-param` text; the ends of the range often.
fn value(param: &'static SimParam) -> BoxedStrategy<String> {
    let (min, max) = (param.allowed_min, param.allowed_max);
    match param.kind {
        ParamKind::Time => prop_oneof![Just(min as u64), Just(max as u64), (min as u64)..=(max as u64)]
            .prop_map(|ms| format!("{ms}ms"))
            .boxed(),
        ParamKind::Number => prop_oneof![Just(min), Just(max), min..=max].prop_map(|x| x.to_string()).boxed(),
        ParamKind::Whole => any::<u64>().prop_map(|seed| seed.to_string()).boxed(),
    }
}

/// Each parameter set with probability 3/4.
fn params() -> impl Strategy<Value = Vec<(&'static str, String)>> {
    let each: Vec<_> = SIM_PARAMS
        .iter()
        .map(|param| proptest::option::weighted(0.75, value(param)).prop_map(|v| (param.name, v)))
        .collect();
    each.prop_map(|set| set.into_iter().filter_map(|(name, value)| Some((name, value?))).collect())
}

#[derive(Clone, Debug)]
enum Event {
    Drive(i16, i16),
    Silence,
    Fault(FaultKind),
    Mode(u8),
}

fn event() -> impl Strategy<Value = Event> {
    prop_oneof![
        6 => (any::<i16>(), any::<i16>()).prop_map(|(v, w)| Event::Drive(v, w)),
        2 => Just(Event::Silence),
        1 => proptest::sample::select(FaultKind::ALL.to_vec()).prop_map(Event::Fault),
        1 => (0u8..3).prop_map(Event::Mode),
    ]
}

fn finite_state(robot: &Chassis) -> Result<(), TestCaseError> {
    let state = robot.state();
    let mut values = vec![
        state.commanded_linear,
        state.commanded_angular,
        state.target_linear,
        state.target_angular,
        state.linear,
        state.angular,
        state.battery_voltage,
        state.battery_current,
        state.state_of_charge,
    ];
    for motor in state.motors {
        values.extend([motor.wheel_speed, motor.rpm, motor.current, motor.driver_temperature]);
    }
    let (left, right) = robot.odometry_m();
    values.extend([left, right]);
    prop_assert!(values.iter().all(|x| x.is_finite()), "{state:?}");
    // Wheels within the top speed times the largest gain (1.5); the body's angular speed within what
    // those wheels give on the narrowest track (0.2 m).
    let fastest = 2.3 * 1.5 + 1e-9;
    prop_assert!(state.motors.iter().all(|m| m.wheel_speed.abs() <= fastest), "{state:?}");
    prop_assert!(state.linear.abs() <= fastest && state.angular.abs() <= 2.0 * fastest / 0.2, "{state:?}");
    prop_assert!(state.battery_voltage >= 0.0 && state.motors.iter().all(|m| m.current >= 0.0));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn any_allowed_parameters_stay_finite_and_never_panic(
        params in params(),
        serial in any::<bool>(),
        events in prop::collection::vec((event(), 20u64..400), 1..25),
    ) {
        let wire = if serial { SimWire::Serial } else { SimWire::CanV2 };
        let mut config = SimConfig { wire, ..SimConfig::default() };
        for (name, value) in &params {
            config.set_param(name, value).unwrap();
        }
        prop_assert_eq!(config.validate(), Ok(()));
        prop_assert_eq!(config.clone().sanitized(), config.clone(), "an allowed set is kept as it is");
        let mut robot = Chassis::new(config);
        let mut now = 0u64;
        let mut out = Vec::new();
        robot.receive(Duration::ZERO, &Message::ControlModeCommand(MODE_CAN));
        for (event, lasts_ms) in events {
            for t in (now..now + lasts_ms).step_by(5) {
                let at = Duration::from_millis(t);
                match event {
                    Event::Drive(v, w) if t % 20 == 0 => {
                        let command = if serial {
                            Message::PercentMotionCommand(PercentMotionCommand {
                                control_mode: 0x02,
                                linear_percent: (v / 256) as i8,
                                angular_percent: (w / 256) as i8,
                                ..PercentMotionCommand::default()
                            })
                        } else {
                            Message::MotionCommand(MotionCommand { linear_mm_s: v, angular_mrad_s: w })
                        };
                        robot.receive(at, &command);
                    }
                    Event::Fault(fault) if t == now => robot.inject(at, fault),
                    Event::Mode(mode) if t == now => robot.receive(at, &Message::ControlModeCommand(mode)),
                    _ => {}
                }
                robot.due_feedback(at, &mut out);
                for message in out.drain(..) {
                    if let Message::MotionState(state) = message {
                        // The body speed as 0x221 carries it: within the fastest wheels, plus 10 sigma of the largest noise.
                        prop_assert!(i32::from(state.linear_mm_s).abs() <= 2300 * 3 / 2 + 100);
                    }
                }
                finite_state(&robot)?;
            }
            now += lasts_ms;
        }
        // A long silence: the robot comes to rest and a day passes at once.
        robot.step(Duration::from_millis(now + 86_400_000));
        finite_state(&robot)?;
        let state = robot.state();
        prop_assert_eq!((state.linear, state.angular), (0.0, 0.0));
    }
}
