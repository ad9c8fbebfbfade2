//! Messages <-> CAN frames, protocol V2 and V1.
//!
//! V1 and V2 use disjoint identifiers except 0x151: V1's system state (with a checksum in byte 7), and the
//! ID the TRACER V2 manual gives for system state (firmware sends 0x211). See `docs/protocol.md`.

use super::catalog::{self, StandardIds};
use super::frame::CanFrame;
use super::id::{
    FrameId, ID_CONTROL_MODE, ID_FAULT_CLEAR, ID_LIGHT_COMMAND, ID_LIGHT_STATE, ID_MOTION_COMMAND,
    ID_MOTION_STATE, ID_MOTOR1_HIGH_SPEED, ID_MOTOR1_LOW_SPEED, ID_MOTOR2_HIGH_SPEED, ID_MOTOR2_LOW_SPEED,
    ID_ODOMETRY, ID_RC_STATE, ID_SYSTEM_STATE, ID_SYSTEM_STATE_MANUAL, ID_V1_LIGHT_COMMAND,
    ID_V1_LIGHT_STATE, ID_V1_MOTION_COMMAND, ID_V1_MOTION_STATE, ID_V1_SYSTEM_STATE, ID_VERSION_REQUEST,
    ID_VERSION_RESPONSE,
};
use super::message::*;
use super::payload::{self, Layout};

/// A V2 system state in cansend syntax (normal, standby, 25.9 V, no faults): the example frame of help
/// texts and messages.
pub const EXAMPLE_FRAME: &str = "211#00000103000000B1";

/// Which protocol version to assume where the identifier alone does not tell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ProtocolHint {
    /// Decide per frame: V1 IDs as V1; 0x151 as V1 when its checksum matches, else as V2.
    #[default]
    Auto,
    V1,
    V2,
}

/// A frame with a TRACER identifier that cannot be a valid TRACER message.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    #[error("V1 checksum mismatch on 0x{id:03X}: computed 0x{computed:02X}, frame carries 0x{found:02X}")]
    BadChecksum { id: u32, computed: u8, found: u8 },
    #[error("0x{id:03X} {name} needs at least {need} data bytes, frame has {got}")]
    TooShort { id: u32, name: &'static str, need: usize, got: usize },
}

/// A message that has no encoding on the requested wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{name} has no {wire} encoding")]
pub struct EncodeError {
    pub name: &'static str,
    pub wire: &'static str,
}

/// The catalog's V1 identifiers that V2 does not use (0x151 is shared and excluded).
static V1_ONLY: StandardIds = StandardIds::only_on(Wire::CanV1, &[]);

/// True for identifiers only protocol V1 uses (0x151 is shared and excluded).
pub fn is_v1_only_id(id: u32) -> bool {
    V1_ONLY.contains(id)
}

/// V1 checksum over a frame of `dlc` bytes: (id low + id high + dlc + data[0..dlc-1]) mod 256.
pub fn v1_checksum(id: u32, data: &[u8]) -> u8 {
    let body = &data[..data.len().saturating_sub(1)];
    let seed = (id & 0xFF) as u8;
    let seed = seed.wrapping_add((id >> 8) as u8).wrapping_add(data.len() as u8);
    body.iter().fold(seed, |sum, byte| sum.wrapping_add(*byte))
}

fn be16(data: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([data[at], data[at + 1]])
}
fn be16s(data: &[u8], at: usize) -> i16 {
    i16::from_be_bytes([data[at], data[at + 1]])
}
fn be32s(data: &[u8], at: usize) -> i32 {
    i32::from_be_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]])
}

/// Decodes a frame. `Ok(None)` means the frame is not a TRACER message (unknown ID, extended, remote,
/// error or FD frame): callers show it raw.
#[expect(
    clippy::too_many_lines,
    reason = "one arm per V2 identifier, the codec's table in one place; split, the map of IDs would scatter."
)]
pub fn decode(frame: &CanFrame, hint: ProtocolHint) -> Result<Option<Decoded>, DecodeError> {
    if !frame.is_standard_data() {
        return Ok(None);
    }
    let id = frame.id();
    let data = frame.data();
    let need = |name: &'static str, need: usize| {
        if data.len() < need {
            Err(DecodeError::TooShort { id, name, need, got: data.len() })
        } else {
            Ok(())
        }
    };
    let v2 = |message| Ok(Some(Decoded { wire: Wire::CanV2, message }));

    if id == ID_SYSTEM_STATE_MANUAL {
        return decode_0x151(data, hint);
    }
    if is_v1_only_id(id) {
        return if hint == ProtocolHint::V2 { Ok(None) } else { decode_v1(id, data) };
    }
    match id {
        ID_MOTION_COMMAND => {
            need("motion_command", 4)?;
            v2(Message::MotionCommand(MotionCommand {
                linear_mm_s: be16s(data, 0),
                angular_mrad_s: be16s(data, 2),
            }))
        }
        ID_LIGHT_COMMAND => {
            need("light_command", 8)?;
            v2(payload::decode(Layout::LightCommand, &head(data), data[7]))
        }
        ID_LIGHT_STATE => {
            need("light_state", 8)?;
            v2(payload::decode(Layout::LightState, &head(data), data[7]))
        }
        ID_CONTROL_MODE => {
            need("control_mode_command", 1)?;
            v2(Message::ControlModeCommand(data[0]))
        }
        ID_FAULT_CLEAR => {
            need("fault_clear", 1)?;
            v2(Message::FaultClear(data[0]))
        }
        ID_VERSION_REQUEST => v2(Message::VersionRequest),
        ID_SYSTEM_STATE => {
            need("system_state", 8)?;
            v2(payload::decode(Layout::SystemState, &head(data), data[7]))
        }
        ID_MOTION_STATE => {
            need("motion_state", 4)?;
            // V2 carries no count here (bytes 4-7 are reserved).
            v2(payload::decode(Layout::MotionState, &head(&data[..4]), 0))
        }
        ID_RC_STATE => {
            need("rc_state", 8)?;
            v2(Message::RcState(RcState {
                switches: data[0],
                right_stick_h: data[1] as i8,
                right_stick_v: data[2] as i8,
                left_stick_v: data[3] as i8,
                left_stick_h: data[4] as i8,
                var_a: data[5] as i8,
                count: data[7],
            }))
        }
        ID_MOTOR1_HIGH_SPEED | ID_MOTOR2_HIGH_SPEED => {
            need("motor_high_speed", 8)?;
            v2(Message::MotorHighSpeed(MotorHighSpeed {
                motor: (id - 0x250) as u8,
                rpm: be16s(data, 0),
                current_deciamps: be16s(data, 2),
                pulse_count: be32s(data, 4),
            }))
        }
        ID_MOTOR1_LOW_SPEED | ID_MOTOR2_LOW_SPEED => {
            need("motor_low_speed", 6)?;
            v2(Message::MotorLowSpeed(MotorLowSpeed {
                motor: (id - 0x260) as u8,
                driver_decivolts: be16(data, 0),
                driver_temperature: be16s(data, 2),
                motor_temperature: data[4] as i8,
                driver_state: data[5],
            }))
        }
        ID_ODOMETRY => {
            need("odometry", 8)?;
            v2(Message::Odometry(Odometry { left_mm: be32s(data, 0), right_mm: be32s(data, 4) }))
        }
        ID_VERSION_RESPONSE => {
            need("version_response", 8)?;
            v2(Message::VersionResponse(VersionResponse {
                controller_hw: be16(data, 0),
                driver_hw: be16(data, 2),
                controller_sw: be16(data, 4),
                driver_sw: be16(data, 6),
            }))
        }
        _ => Ok(None),
    }
}

fn decode_0x151(data: &[u8], hint: ProtocolHint) -> Result<Option<Decoded>, DecodeError> {
    if data.len() < 8 {
        return Err(DecodeError::TooShort {
            id: ID_V1_SYSTEM_STATE,
            name: "system_state",
            need: 8,
            got: data.len(),
        });
    }
    let checksum_ok = v1_checksum(ID_V1_SYSTEM_STATE, data) == data[7];
    let as_v1 = match hint {
        ProtocolHint::V1 => true,
        ProtocolHint::V2 => false,
        ProtocolHint::Auto => checksum_ok,
    };
    if as_v1 {
        return decode_v1(ID_V1_SYSTEM_STATE, data);
    }
    let message = payload::decode(Layout::SystemState, &head(data), data[7]);
    Ok(Some(Decoded { wire: Wire::CanV2, message }))
}

fn decode_v1(id: u32, data: &[u8]) -> Result<Option<Decoded>, DecodeError> {
    if data.len() < 8 {
        let entry = catalog::entry(FrameId::standard(id), Wire::CanV1);
        let name = entry.map_or("message", |entry| entry.name());
        return Err(DecodeError::TooShort { id, name, need: 8, got: data.len() });
    }
    let computed = v1_checksum(id, data);
    if computed != data[7] {
        return Err(DecodeError::BadChecksum { id, computed, found: data[7] });
    }
    let layout = match id {
        ID_V1_MOTION_COMMAND => Layout::MotionCommand,
        ID_V1_MOTION_STATE => Layout::MotionState,
        ID_V1_LIGHT_COMMAND => Layout::LightCommand,
        ID_V1_LIGHT_STATE => Layout::LightState,
        ID_V1_SYSTEM_STATE => Layout::SystemState,
        _ => Layout::MotorDriver((id - 0x200) as u8),
    };
    let message = payload::decode(layout, &head(data), data[6]);
    Ok(Some(Decoded { wire: Wire::CanV1, message }))
}

/// Encodes a message for protocol V2. Commands 0x421 and 0x441 use DLC 1 as the TRACER manual specifies.
pub fn encode_v2(message: &Message) -> Result<CanFrame, EncodeError> {
    let mut data = [0u8; 8];
    let (id, len) = match *message {
        Message::MotionCommand(cmd) => {
            data[0..2].copy_from_slice(&cmd.linear_mm_s.to_be_bytes());
            data[2..4].copy_from_slice(&cmd.angular_mrad_s.to_be_bytes());
            (ID_MOTION_COMMAND, 8)
        }
        Message::LightCommand(lights) => {
            data = v2_with_count(message, lights.count);
            (ID_LIGHT_COMMAND, 8)
        }
        Message::LightState(lights) => {
            data = v2_with_count(message, lights.count);
            (ID_LIGHT_STATE, 8)
        }
        Message::ControlModeCommand(mode) => {
            data[0] = mode;
            (ID_CONTROL_MODE, 1)
        }
        Message::FaultClear(code) => {
            data[0] = code;
            (ID_FAULT_CLEAR, 1)
        }
        Message::VersionRequest => {
            data[0] = 0x01;
            (ID_VERSION_REQUEST, 1)
        }
        Message::SystemState(state) => {
            data = v2_with_count(message, state.count);
            (ID_SYSTEM_STATE, 8)
        }
        Message::MotionState(_) => {
            data = v2_with_count(message, 0);
            (ID_MOTION_STATE, 8)
        }
        Message::RcState(rc) => {
            data = [
                rc.switches,
                rc.right_stick_h as u8,
                rc.right_stick_v as u8,
                rc.left_stick_v as u8,
                rc.left_stick_h as u8,
                rc.var_a as u8,
                0,
                rc.count,
            ];
            (ID_RC_STATE, 8)
        }
        Message::MotorHighSpeed(motor) if matches!(motor.motor, 1 | 2) => {
            data[0..2].copy_from_slice(&motor.rpm.to_be_bytes());
            data[2..4].copy_from_slice(&motor.current_deciamps.to_be_bytes());
            data[4..8].copy_from_slice(&motor.pulse_count.to_be_bytes());
            (0x250 + u32::from(motor.motor), 8)
        }
        Message::MotorLowSpeed(motor) if matches!(motor.motor, 1 | 2) => {
            data[0..2].copy_from_slice(&motor.driver_decivolts.to_be_bytes());
            data[2..4].copy_from_slice(&motor.driver_temperature.to_be_bytes());
            data[4] = motor.motor_temperature as u8;
            data[5] = motor.driver_state;
            (0x260 + u32::from(motor.motor), 8)
        }
        Message::Odometry(odo) => {
            data[0..4].copy_from_slice(&odo.left_mm.to_be_bytes());
            data[4..8].copy_from_slice(&odo.right_mm.to_be_bytes());
            (ID_ODOMETRY, 8)
        }
        Message::VersionResponse(v) => {
            data[0..2].copy_from_slice(&v.controller_hw.to_be_bytes());
            data[2..4].copy_from_slice(&v.driver_hw.to_be_bytes());
            data[4..6].copy_from_slice(&v.controller_sw.to_be_bytes());
            data[6..8].copy_from_slice(&v.driver_sw.to_be_bytes());
            (ID_VERSION_RESPONSE, 8)
        }
        _ => return Err(EncodeError { name: message.name(), wire: "CAN V2" }),
    };
    Ok(CanFrame::new(id, &data[..len]).expect("V2 identifiers are standard and DLC <= 8"))
}

/// The shared payload in bytes 0-5 and V2's count in byte 7 (lights, system state, motion state).
fn v2_with_count(message: &Message, count: u8) -> [u8; 8] {
    let (_, bytes, _) = payload::encode(message).expect("a message with the shared layout");
    [bytes[0], bytes[1], bytes[2], bytes[3], bytes[4], bytes[5], 0, count]
}

/// The first six bytes (zero-padded).
fn head(data: &[u8]) -> [u8; 6] {
    let mut bytes = [0u8; 6];
    let len = data.len().min(6);
    bytes[..len].copy_from_slice(&data[..len]);
    bytes
}

/// Encodes a message for protocol V1: count in byte 6, checksum in byte 7.
pub fn encode_v1(message: &Message) -> Result<CanFrame, EncodeError> {
    let Some((layout, bytes, count)) = payload::encode(message) else {
        return Err(EncodeError { name: message.name(), wire: "CAN V1" });
    };
    let id = match layout {
        Layout::MotionCommand => ID_V1_MOTION_COMMAND,
        Layout::MotionState => ID_V1_MOTION_STATE,
        Layout::LightCommand => ID_V1_LIGHT_COMMAND,
        Layout::LightState => ID_V1_LIGHT_STATE,
        Layout::SystemState => ID_V1_SYSTEM_STATE,
        Layout::MotorDriver(motor) => 0x200 + u32::from(motor),
    };
    let mut data = [bytes[0], bytes[1], bytes[2], bytes[3], bytes[4], bytes[5], count, 0];
    data[7] = v1_checksum(id, &data);
    Ok(CanFrame::new(id, &data).expect("V1 identifiers are standard"))
}

/// Encodes for the wire the message belongs to.
pub fn encode(decoded: &Decoded) -> Result<CanFrame, EncodeError> {
    match decoded.wire {
        Wire::CanV1 => encode_v1(&decoded.message),
        Wire::CanV2 => encode_v2(&decoded.message),
        Wire::Serial => {
            Err(EncodeError { name: decoded.message.name(), wire: "CAN (it is a serial message)" })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::faults::Severity;
    use crate::protocol::LightMode;

    fn frame(id: u32, hex_data: &str) -> CanFrame {
        CanFrame::new(id, &hex::decode(hex_data).unwrap()).unwrap()
    }

    fn decode_ok(id: u32, hex_data: &str) -> Decoded {
        decode(&frame(id, hex_data), ProtocolHint::Auto).unwrap().unwrap()
    }

    fn field_names(flags: crate::protocol::Flags) -> Vec<&'static str> {
        flags.iter().map(|f| f.name).collect()
    }

    #[test]
    fn the_example_frame_is_a_normal_standby_system_state() {
        let (id, data) = EXAMPLE_FRAME.split_once('#').unwrap();
        let decoded = decode_ok(u32::from_str_radix(id, 16).unwrap(), data);
        let Message::SystemState(state) = decoded.message else { panic!("{decoded:?}") };
        assert_eq!(
            (decoded.wire, state.vehicle_state, state.control_mode),
            (Wire::CanV2, VEHICLE_NORMAL, MODE_STANDBY)
        );
        assert_eq!((state.battery_decivolts, state.fault_code), (259, 0));
    }

    // protocol-notes.md §8: Hunter SE capture.
    #[test]
    fn hunter_se_system_state_is_normal_standby_25_9_volts() {
        for (data, count) in [("00000103000000B1", 0xB1), ("00000103000000B2", 0xB2)] {
            let decoded = decode_ok(0x211, data);
            assert_eq!(decoded.wire, Wire::CanV2);
            let Message::SystemState(state) = decoded.message else { panic!("{decoded:?}") };
            assert_eq!(state.vehicle_state, VEHICLE_NORMAL);
            assert_eq!(state.control_mode, MODE_STANDBY);
            assert_eq!(state.battery_decivolts, 259);
            assert_eq!(state.battery_voltage(), 25.9);
            assert_eq!(state.fault_code, 0);
            assert!(state.faults(Wire::CanV2).is_empty());
            assert_eq!(state.count, count);
        }
    }

    #[test]
    fn hunter_se_odometry_is_minus_63_and_plus_18_mm() {
        let decoded = decode_ok(0x311, "FFFFFFC100000012");
        assert_eq!(decoded.message, Message::Odometry(Odometry { left_mm: -63, right_mm: 18 }));
    }

    #[test]
    fn hunter_se_motor_and_motion_frames() {
        let decoded = decode_ok(0x251, "0000000F00000054");
        assert_eq!(
            decoded.message,
            Message::MotorHighSpeed(MotorHighSpeed {
                motor: 1,
                rpm: 0,
                current_deciamps: 15,
                pulse_count: 0x54
            })
        );
        // Bytes 6-7 FF FF are reserved on TRACER and must not disturb the speeds.
        let decoded = decode_ok(0x221, "000000000000FFFF");
        assert_eq!(
            decoded.message,
            Message::MotionState(MotionState { linear_mm_s: 0, angular_mrad_s: 0, count: 0 })
        );
    }

    #[test]
    fn hunter_se_low_speed_frame_of_a_third_motor_is_raw_on_tracer() {
        // 0x263 exists on four-motor bases; TRACER has two, so it stays a raw frame.
        assert_eq!(decode(&frame(0x263, "01070027D8400000"), ProtocolHint::Auto), Ok(None));
        // The same payload on 0x262 decodes: 26.3 V, driver 39 C, no motor sensor (-40), state 0x40.
        let decoded = decode_ok(0x262, "01070027D8400000");
        let Message::MotorLowSpeed(motor) = decoded.message else { panic!() };
        assert_eq!(motor.motor, 2);
        assert_eq!(motor.driver_decivolts, 263);
        assert_eq!(motor.driver_temperature, 39);
        assert_eq!(motor.motor_temperature, -40);
        assert_eq!(motor.driver_state, 0x40);
        assert_eq!(field_names(motor.driver_faults()), ["driver_disabled"]);
        assert_eq!(motor.driver_faults().worst(), Some(Severity::Info));
    }

    // protocol-notes.md §8: Bunker Mini capture.
    #[test]
    fn bunker_mini_estop_frame() {
        let decoded = decode_ok(0x211, "0100010000800000");
        let Message::SystemState(state) = decoded.message else { panic!() };
        assert!(state.is_estop());
        assert_eq!(state.battery_voltage(), 25.6);
        assert_eq!(state.fault_code, 0x0080);
        assert_eq!(field_names(state.faults(Wire::CanV2)), ["reserved_byte5_bit7"]);
    }

    #[test]
    fn bunker_mini_rc_state_all_switches_up() {
        let decoded = decode_ok(0x241, "AA00000000000061");
        let Message::RcState(rc) = decoded.message else { panic!() };
        assert_eq!(rc.count, 0x61);
        for index in 0..4 {
            assert_eq!(rc_switch_name((rc.switches >> (2 * index)) & 3), Some("up"));
        }
        assert_eq!(decode_ok(0x311, "0000000000000000").message, Message::Odometry(Odometry::default()));
    }

    // Manual and SDK examples for commands.
    #[test]
    fn motion_command_examples_encode_byte_exact() {
        let cases = [
            ((0.15, 0.0), "111#0096000000000000"),
            ((0.0, 0.05), "111#0000003200000000"),
            ((-0.5, 0.3), "111#FE0C012C00000000"),
            ((0.0, -ANGULAR_LIMIT), "111#0000FCEF00000000"),
        ];
        for ((linear, angular), text) in cases {
            let cmd = MotionCommand::from_si(linear, angular).unwrap();
            let frame = encode_v2(&Message::MotionCommand(cmd)).unwrap();
            assert_eq!(frame.to_string(), text);
            let back = decode(&frame, ProtocolHint::Auto).unwrap().unwrap();
            assert_eq!(back.message, Message::MotionCommand(cmd));
        }
    }

    #[test]
    fn encoding_rounds_to_nearest_where_agilex_truncates() {
        // AgileX: (int16_t)(-0.511 * 1000) = -510.
        assert_eq!(MotionCommand::from_si(-0.511, 0.0).unwrap().linear_mm_s, -511);
        assert_eq!(MotionCommand::from_si(0.0, 0.0004).unwrap().angular_mrad_s, 0);
        assert_eq!(MotionCommand::from_si(0.0, 0.0006).unwrap().angular_mrad_s, 1);
    }

    #[test]
    fn out_of_range_speeds_are_rejected_or_clamped_explicitly() {
        assert!(matches!(MotionCommand::from_si(1.6, 0.0), Err(RangeError::OutOfRange { .. })));
        assert!(matches!(MotionCommand::from_si(0.0, f64::NAN), Err(RangeError::NotFinite { .. })));
        let (cmd, clamped) = MotionCommand::clamped_from_si(-9.0, 2.0);
        assert!(clamped);
        assert_eq!(cmd, MotionCommand { linear_mm_s: -1500, angular_mrad_s: 785 });
        let (_, clamped) = MotionCommand::clamped_from_si(1.0, -0.5);
        assert!(!clamped);
        assert!(Lights::front(LightMode::Custom, 101).is_err());
    }

    #[test]
    fn light_mode_and_fault_clear_commands() {
        let lights = Lights { count: 5, ..Lights::front(LightMode::Custom, 30).unwrap() };
        assert_eq!(encode_v2(&Message::LightCommand(lights)).unwrap().to_string(), "121#01031E0000000005");
        assert_eq!(encode_v2(&Message::ControlModeCommand(MODE_CAN)).unwrap().to_string(), "421#01");
        assert_eq!(encode_v2(&Message::FaultClear(CLEAR_MOTOR2)).unwrap().to_string(), "441#02");
        assert_eq!(encode_v2(&Message::VersionRequest).unwrap().to_string(), "411#01");
        // The SDK's DLC-8 form of 0x421 decodes the same.
        assert_eq!(decode_ok(0x421, "0100000000000000").message, Message::ControlModeCommand(1));
    }

    #[test]
    fn v1_manual_examples_have_valid_checksums() {
        for (data, linear, angular) in
            [("01000A0000000044", 10, 0), ("0100000A00000044", 0, 10), ("010000000000003A", 0, 0)]
        {
            let decoded = decode_ok(0x130, data);
            assert_eq!(decoded.wire, Wire::CanV1);
            let Message::PercentMotionCommand(cmd) = decoded.message else { panic!() };
            assert_eq!((cmd.control_mode, cmd.linear_percent, cmd.angular_percent), (1, linear, angular));
            assert_eq!(encode_v1(&decoded.message).unwrap(), frame(0x130, data));
        }
        let decoded = decode_ok(0x130, "01000A0000000044");
        let Message::PercentMotionCommand(cmd) = decoded.message else { panic!() };
        assert_eq!(cmd.linear(), 0.15);
    }

    #[test]
    fn v1_bad_checksum_is_reported_with_both_values() {
        let result = decode(&frame(0x130, "01000A0000000045"), ProtocolHint::Auto);
        assert_eq!(result, Err(DecodeError::BadChecksum { id: 0x130, computed: 0x44, found: 0x45 }));
        // With a V2 hint, V1-only IDs belong to other robots: raw, not an error.
        assert_eq!(decode(&frame(0x130, "01000A0000000045"), ProtocolHint::V2), Ok(None));
    }

    #[test]
    fn id_0x151_is_v1_with_a_valid_checksum_and_v2_layout_otherwise() {
        let v1 = SystemState {
            control_mode: 1,
            battery_decivolts: 250,
            fault_code: 0x0040,
            count: 9,
            ..Default::default()
        };
        let v1_frame = encode_v1(&Message::SystemState(v1)).unwrap();
        assert_eq!(v1_frame.id(), 0x151);
        let decoded = decode(&v1_frame, ProtocolHint::Auto).unwrap().unwrap();
        assert_eq!(decoded, Decoded { wire: Wire::CanV1, message: Message::SystemState(v1) });
        assert_eq!(field_names(v1.faults(Wire::CanV1)), ["driver_overheat_protection"]);

        // The manual's V2 "0x151" (count in byte 7, no checksum) decodes with the V2 layout.
        let decoded = decode_ok(0x151, "00010103010000B1");
        assert_eq!(decoded.wire, Wire::CanV2);
        let Message::SystemState(state) = decoded.message else { panic!() };
        assert_eq!((state.battery_decivolts, state.count), (259, 0xB1));
        assert_eq!(field_names(state.faults(Wire::CanV2)), ["battery_undervoltage_fault"]);
        // Forced V1, the same frame is a checksum error.
        assert!(matches!(
            decode(&frame(0x151, "00010103010000B1"), ProtocolHint::V1),
            Err(DecodeError::BadChecksum { .. })
        ));
    }

    #[test]
    fn unknown_extended_remote_and_short_frames() {
        assert_eq!(decode(&frame(0x123, "00"), ProtocolHint::Auto), Ok(None));
        let extended = CanFrame::new_extended(0x211, &[0; 8]).unwrap();
        assert_eq!(decode(&extended, ProtocolHint::Auto), Ok(None));
        let remote = CanFrame::new_remote(0x211, false, 8).unwrap();
        assert_eq!(decode(&remote, ProtocolHint::Auto), Ok(None));
        assert_eq!(
            decode(&frame(0x211, "0000"), ProtocolHint::Auto),
            Err(DecodeError::TooShort { id: 0x211, name: "system_state", need: 8, got: 2 })
        );
    }

    #[test]
    fn messages_without_a_wire_form_say_so() {
        let err = encode_v1(&Message::Odometry(Odometry::default())).unwrap_err();
        assert_eq!(err.to_string(), "odometry has no CAN V1 encoding");
        assert!(encode_v2(&Message::PercentMotionCommand(Default::default())).is_err());
        let bad_motor = MotorHighSpeed { motor: 3, ..Default::default() };
        assert!(encode_v2(&Message::MotorHighSpeed(bad_motor)).is_err());
    }
}
