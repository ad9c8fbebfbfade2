//! The identifiers the robot sends on a fixed period: the one table monitor's staleness check and the
//! dashboard's link panel read (protocol notes §2.6-2.12, §5, §6.2).

use std::time::Duration;

use super::can::{
    ID_LIGHT_STATE, ID_MOTION_STATE, ID_MOTOR1_HIGH_SPEED, ID_MOTOR1_LOW_SPEED, ID_MOTOR2_HIGH_SPEED,
    ID_MOTOR2_LOW_SPEED, ID_ODOMETRY, ID_SYSTEM_STATE, ID_V1_LIGHT_STATE, ID_V1_MOTION_STATE, ID_V1_MOTOR1,
    ID_V1_MOTOR2, ID_V1_SYSTEM_STATE,
};
use super::message::Wire;

/// One frame the robot sends on a fixed period.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Periodic {
    /// The CAN identifier, or an RS232 frame's `type << 8 | command` (`0xAA01`).
    pub id: u32,
    pub wire: Wire,
    /// The decoded message's name (`Message::name`), as monitor prints it.
    pub name: &'static str,
    /// A short label for the dashboard's link panel.
    pub label: &'static str,
    /// Nominal period, in milliseconds.
    pub period_ms: u64,
}

impl Periodic {
    pub const fn period(&self) -> Duration {
        Duration::from_millis(self.period_ms)
    }
}

const fn periodic(id: u32, wire: Wire, name: &'static str, label: &'static str, period_ms: u64) -> Periodic {
    Periodic { id, wire, name, label, period_ms }
}

/// RS232 feedback identifiers (`type << 8 | command`, protocol notes §6.2).
const SERIAL_SYSTEM_STATE: u32 = 0xAA01;
const SERIAL_MOTION_STATE: u32 = 0xAA02;
const SERIAL_MOTOR1: u32 = 0xAA03;
const SERIAL_MOTOR2: u32 = 0xAA04;
const SERIAL_LIGHT_STATE: u32 = 0xAA07;

/// Every periodic robot frame. V1's period is not documented: the slower 100 ms, so nothing is called
/// stale early. CAN and RS232 identifiers do not overlap (RS232 ones are above 0x7FF).
pub const PERIODIC: &[Periodic] = &[
    // CAN V2 (manual; 0x261/0x262 every 100 ms).
    periodic(ID_SYSTEM_STATE, Wire::CanV2, "system_state", "system", 20),
    periodic(ID_MOTION_STATE, Wire::CanV2, "motion_state", "motion", 20),
    periodic(ID_LIGHT_STATE, Wire::CanV2, "light_state", "lights", 20),
    periodic(ID_MOTOR1_HIGH_SPEED, Wire::CanV2, "motor_high_speed", "motor 1", 20),
    periodic(ID_MOTOR2_HIGH_SPEED, Wire::CanV2, "motor_high_speed", "motor 2", 20),
    periodic(ID_ODOMETRY, Wire::CanV2, "odometry", "odometry", 20),
    periodic(ID_MOTOR1_LOW_SPEED, Wire::CanV2, "motor_low_speed", "driver 1", 100),
    periodic(ID_MOTOR2_LOW_SPEED, Wire::CanV2, "motor_low_speed", "driver 2", 100),
    // CAN V1.
    periodic(ID_V1_MOTION_STATE, Wire::CanV1, "motion_state", "V1 motion", 100),
    periodic(ID_V1_LIGHT_STATE, Wire::CanV1, "light_state", "V1 lights", 100),
    periodic(ID_V1_SYSTEM_STATE, Wire::CanV1, "system_state", "system", 100),
    periodic(ID_V1_MOTOR1, Wire::CanV1, "motor_high_speed", "V1 motor 1", 100),
    periodic(ID_V1_MOTOR2, Wire::CanV1, "motor_high_speed", "V1 motor 2", 100),
    // RS232.
    periodic(SERIAL_SYSTEM_STATE, Wire::Serial, "system_state", "system", 20),
    periodic(SERIAL_MOTION_STATE, Wire::Serial, "motion_state", "motion", 20),
    periodic(SERIAL_MOTOR1, Wire::Serial, "motor_high_speed", "motor 1", 20),
    periodic(SERIAL_MOTOR2, Wire::Serial, "motor_high_speed", "motor 2", 20),
    periodic(SERIAL_LIGHT_STATE, Wire::Serial, "light_state", "lights", 20),
];

/// The periodic frame with this identifier (CAN, or RS232 `0xAAxx`), if it is one.
pub fn periodic_frame(id: u32) -> Option<&'static Periodic> {
    PERIODIC.iter().find(|entry| entry.id == id)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::can::{self, v1_checksum, ProtocolHint};
    use crate::protocol::frame::CanFrame;
    use crate::protocol::serial::{self, SerialFrame};
    use crate::protocol::Decoded;

    /// What the codec makes of an all-zero frame with this entry's identifier (V1 with its checksum).
    fn decode(entry: &Periodic) -> Option<Decoded> {
        match entry.wire {
            Wire::Serial => {
                let [_, _, frame_type, command] = entry.id.to_be_bytes();
                serial::decode(&SerialFrame { frame_type, command, payload: [0; 6], frame_id: 0 })
            }
            Wire::CanV1 | Wire::CanV2 => {
                let mut data = [0u8; 8];
                let hint = if entry.wire == Wire::CanV1 {
                    data[7] = v1_checksum(entry.id, &data);
                    ProtocolHint::V1
                } else {
                    ProtocolHint::V2
                };
                can::decode(&CanFrame::new(entry.id, &data).unwrap(), hint).unwrap()
            }
        }
    }

    #[test]
    fn every_entry_has_a_codec_a_label_and_a_period() {
        for entry in PERIODIC {
            let decoded = decode(entry).unwrap_or_else(|| panic!("0x{:X}: no codec decodes it", entry.id));
            assert_eq!(decoded.wire, entry.wire, "0x{:X}", entry.id);
            assert_eq!(decoded.message.name(), entry.name, "0x{:X}", entry.id);
            assert!(
                !entry.label.is_empty() && entry.label.len() <= 10,
                "0x{:X}: label {:?}",
                entry.id,
                entry.label
            );
            assert!(entry.period_ms > 0, "0x{:X}: no period", entry.id);
        }
    }

    #[test]
    fn identifiers_are_unique() {
        for (i, entry) in PERIODIC.iter().enumerate() {
            assert!(PERIODIC[i + 1..].iter().all(|other| other.id != entry.id), "0x{:X} twice", entry.id);
        }
    }

    #[test]
    fn looks_up_by_identifier() {
        assert_eq!(
            periodic_frame(0x261).map(|p| (p.label, p.period())),
            Some(("driver 1", Duration::from_millis(100)))
        );
        assert_eq!(periodic_frame(0xAA07).map(|p| p.name), Some("light_state"));
        assert_eq!(periodic_frame(0x111), None);
    }
}
