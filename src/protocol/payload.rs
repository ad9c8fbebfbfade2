//! The six-byte payloads that CAN protocol V1 and RS232 share, message for message: V1 puts a count and a
//! checksum after them (bytes 6-7), RS232 a frame id and a checksum. V2 lights, system state and motion state
//! use the same first bytes (with V2's count in byte 7). One codec, so the layouts are written once.

use super::message::*;

/// Which layout the six bytes have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Percentages: mode, fault clear, linear %, angular %, lateral %.
    MotionCommand,
    /// Linear mm/s and angular mrad/s (int16 BE).
    MotionState,
    LightCommand,
    LightState,
    /// Vehicle state, mode, battery (0.1 V, u16 BE), fault code (u16 BE).
    SystemState,
    /// Motor driver 1 or 2: current (0.1 A, u16 BE), rpm (i16 BE), driver temperature (i8).
    MotorDriver(u8),
}

fn be16(p: &[u8; 6], at: usize) -> u16 {
    u16::from_be_bytes([p[at], p[at + 1]])
}

/// The message in `payload`, with `count` (V1 count byte, RS232 frame id, V2 count byte).
pub fn decode(layout: Layout, p: &[u8; 6], count: u8) -> Message {
    let lights = Lights {
        enable: p[0],
        front_mode: p[1],
        front_brightness: p[2],
        rear_mode: p[3],
        rear_brightness: p[4],
        count,
    };
    match layout {
        Layout::MotionCommand => Message::PercentMotionCommand(PercentMotionCommand {
            control_mode: p[0],
            fault_clear: p[1],
            linear_percent: p[2] as i8,
            angular_percent: p[3] as i8,
            lateral_percent: p[4] as i8,
            count,
        }),
        Layout::MotionState => Message::MotionState(MotionState {
            linear_mm_s: be16(p, 0) as i16,
            angular_mrad_s: be16(p, 2) as i16,
            count,
        }),
        Layout::LightCommand => Message::LightCommand(lights),
        Layout::LightState => Message::LightState(lights),
        Layout::SystemState => Message::SystemState(SystemState {
            vehicle_state: p[0],
            control_mode: p[1],
            battery_decivolts: be16(p, 2),
            fault_code: be16(p, 4),
            count,
        }),
        Layout::MotorDriver(motor) => Message::MotorDriverState(MotorDriverState {
            motor,
            current_deciamps: be16(p, 0),
            rpm: be16(p, 2) as i16,
            driver_temperature: p[4] as i8,
            count,
        }),
    }
}

/// The layout, the six bytes and the count of a message that has this form; `None` otherwise.
pub fn encode(message: &Message) -> Option<(Layout, [u8; 6], u8)> {
    let pair = |value: u16| value.to_be_bytes();
    let lights = |l: &Lights| [l.enable, l.front_mode, l.front_brightness, l.rear_mode, l.rear_brightness, 0];
    Some(match *message {
        Message::PercentMotionCommand(c) => (
            Layout::MotionCommand,
            [
                c.control_mode,
                c.fault_clear,
                c.linear_percent as u8,
                c.angular_percent as u8,
                c.lateral_percent as u8,
                0,
            ],
            c.count,
        ),
        Message::MotionState(s) => {
            let (l, a) = (pair(s.linear_mm_s as u16), pair(s.angular_mrad_s as u16));
            (Layout::MotionState, [l[0], l[1], a[0], a[1], 0, 0], s.count)
        }
        Message::LightCommand(l) => (Layout::LightCommand, lights(&l), l.count),
        Message::LightState(l) => (Layout::LightState, lights(&l), l.count),
        Message::SystemState(s) => {
            let (b, f) = (pair(s.battery_decivolts), pair(s.fault_code));
            (Layout::SystemState, [s.vehicle_state, s.control_mode, b[0], b[1], f[0], f[1]], s.count)
        }
        // TRACER has two motor drivers.
        Message::MotorDriverState(m) if matches!(m.motor, 1 | 2) => {
            let (c, r) = (pair(m.current_deciamps), pair(m.rpm as u16));
            (Layout::MotorDriver(m.motor), [c[0], c[1], r[0], r[1], m.driver_temperature as u8, 0], m.count)
        }
        _ => return None,
    })
}
