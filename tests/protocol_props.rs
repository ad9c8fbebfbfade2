//! Property tests for the CAN codec: every message round-trips through V2 or V1 frames, decoding never
//! panics, and SI constructors round to nearest within the documented ranges.

use proptest::prelude::*;

use tracerctl::protocol::can::{decode, encode_v1, encode_v2, ProtocolHint};
use tracerctl::protocol::message::*;
use tracerctl::protocol::{CanFrame, Decoded, Wire};

fn lights() -> impl Strategy<Value = Lights> {
    (any::<u8>(), any::<u8>(), any::<u8>(), any::<u8>(), any::<u8>(), any::<u8>()).prop_map(
        |(enable, front_mode, front_brightness, rear_mode, rear_brightness, count)| Lights {
            enable,
            front_mode,
            front_brightness,
            rear_mode,
            rear_brightness,
            count,
        },
    )
}

fn system_state() -> impl Strategy<Value = SystemState> {
    (any::<u8>(), any::<u8>(), any::<u16>(), any::<u16>(), any::<u8>()).prop_map(
        |(vehicle_state, control_mode, battery_decivolts, fault_code, count)| SystemState {
            vehicle_state,
            control_mode,
            battery_decivolts,
            fault_code,
            count,
        },
    )
}

/// Every message protocol V2 can carry.
fn v2_message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (any::<i16>(), any::<i16>())
            .prop_map(|(l, a)| Message::MotionCommand(MotionCommand { linear_mm_s: l, angular_mrad_s: a })),
        lights().prop_map(Message::LightCommand),
        lights().prop_map(Message::LightState),
        any::<u8>().prop_map(Message::ControlModeCommand),
        any::<u8>().prop_map(Message::FaultClear),
        Just(Message::VersionRequest),
        system_state().prop_map(Message::SystemState),
        (any::<i16>(), any::<i16>()).prop_map(|(l, a)| Message::MotionState(MotionState {
            linear_mm_s: l,
            angular_mrad_s: a,
            count: 0
        })),
        (any::<u8>(), any::<[i8; 5]>(), any::<u8>()).prop_map(|(switches, s, count)| Message::RcState(
            RcState {
                switches,
                right_stick_h: s[0],
                right_stick_v: s[1],
                left_stick_v: s[2],
                left_stick_h: s[3],
                var_a: s[4],
                count
            }
        )),
        (1u8..=2, any::<i16>(), any::<i16>(), any::<i32>()).prop_map(|(motor, rpm, current, pulses)| {
            Message::MotorHighSpeed(MotorHighSpeed {
                motor,
                rpm,
                current_deciamps: current,
                pulse_count: pulses,
            })
        }),
        (1u8..=2, any::<u16>(), any::<i16>(), any::<i8>(), any::<u8>()).prop_map(
            |(motor, v, dt, mt, state)| {
                Message::MotorLowSpeed(MotorLowSpeed {
                    motor,
                    driver_decivolts: v,
                    driver_temperature: dt,
                    motor_temperature: mt,
                    driver_state: state,
                })
            }
        ),
        (any::<i32>(), any::<i32>())
            .prop_map(|(l, r)| Message::Odometry(Odometry { left_mm: l, right_mm: r })),
        any::<[u16; 4]>().prop_map(|v| Message::VersionResponse(VersionResponse {
            controller_hw: v[0],
            driver_hw: v[1],
            controller_sw: v[2],
            driver_sw: v[3]
        })),
    ]
}

/// Every message protocol V1 can carry.
fn v1_message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (any::<u8>(), any::<u8>(), any::<[i8; 3]>(), any::<u8>()).prop_map(|(mode, clear, p, count)| {
            Message::PercentMotionCommand(PercentMotionCommand {
                control_mode: mode,
                fault_clear: clear,
                linear_percent: p[0],
                angular_percent: p[1],
                lateral_percent: p[2],
                count,
            })
        }),
        (any::<i16>(), any::<i16>(), any::<u8>()).prop_map(|(l, a, count)| Message::MotionState(
            MotionState { linear_mm_s: l, angular_mrad_s: a, count }
        )),
        lights().prop_map(|l| Message::LightCommand(Lights { ..l })),
        lights().prop_map(Message::LightState),
        system_state().prop_map(Message::SystemState),
        (1u8..=2, any::<u16>(), any::<i16>(), any::<i8>(), any::<u8>()).prop_map(
            |(motor, current, rpm, t, count)| {
                Message::MotorDriverState(MotorDriverState {
                    motor,
                    current_deciamps: current,
                    rpm,
                    driver_temperature: t,
                    count,
                })
            }
        ),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn v2_messages_round_trip(message in v2_message()) {
        let frame = encode_v2(&message).unwrap();
        for hint in [ProtocolHint::Auto, ProtocolHint::V2, ProtocolHint::V1] {
            let decoded = decode(&frame, hint).unwrap();
            prop_assert_eq!(decoded, Some(Decoded { wire: Wire::CanV2, message }));
        }
    }

    #[test]
    fn v1_messages_round_trip_with_a_valid_checksum(message in v1_message()) {
        let frame = encode_v1(&message).unwrap();
        for hint in [ProtocolHint::Auto, ProtocolHint::V1] {
            prop_assert_eq!(decode(&frame, hint).unwrap(), Some(Decoded { wire: Wire::CanV1, message }));
        }
        // Any change to the checksum byte is detected.
        let mut data = frame.data().to_vec();
        data[7] = data[7].wrapping_add(1);
        let corrupted = CanFrame::new(frame.id(), &data).unwrap();
        prop_assert!(decode(&corrupted, ProtocolHint::V1).is_err());
    }

    #[test]
    fn decoding_never_panics(id in 0u32..=0x7FF, data in proptest::collection::vec(any::<u8>(), 0..=8),
                             extended in any::<bool>()) {
        let frame = if extended { CanFrame::new_extended(id, &data) } else { CanFrame::new(id, &data) }.unwrap();
        for hint in [ProtocolHint::Auto, ProtocolHint::V1, ProtocolHint::V2] {
            let _ = decode(&frame, hint);
        }
    }

    #[test]
    fn si_commands_round_to_nearest_inside_the_limits(linear in -LINEAR_LIMIT..=LINEAR_LIMIT,
                                                       angular in -ANGULAR_LIMIT..=ANGULAR_LIMIT) {
        let command = MotionCommand::from_si(linear, angular).unwrap();
        prop_assert!((command.linear() - linear).abs() <= 0.0005 + 1e-12);
        prop_assert!((command.angular() - angular).abs() <= 0.0005 + 1e-12);
        let percent = PercentMotionCommand::from_si(MODE_SERIAL, linear, angular).unwrap();
        prop_assert!((percent.linear() - linear).abs() <= LINEAR_LIMIT * 0.005 + 1e-9);
    }

    #[test]
    fn si_commands_outside_the_limits_are_rejected_or_clamped(excess in 0.001f64..100.0, sign in prop::bool::ANY) {
        let linear = if sign { LINEAR_LIMIT + excess } else { -LINEAR_LIMIT - excess };
        prop_assert!(MotionCommand::from_si(linear, 0.0).is_err());
        let (clamped, was_clamped) = MotionCommand::clamped_from_si(linear, 0.0);
        prop_assert!(was_clamped);
        prop_assert_eq!(clamped.linear_mm_s.unsigned_abs(), 1500);
    }
}
