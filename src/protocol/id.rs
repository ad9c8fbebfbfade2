//! The identifiers: one typed frame identifier ([`FrameId`]: what monitor's and the summary's tables, the
//! session's counts, the dashboard's link panel, the catalog and the `--id` filter are keyed by, ordered and
//! printed one way), and the robot's own identifiers, each written once: the CAN V2 and V1 IDs, the RS232
//! frame types and command codes. A leaf: the codecs (`can.rs`, `serial.rs`) and the catalog read it, and it
//! reads nothing else of the protocol.

use std::fmt;

// CAN protocol V2 identifiers.
pub const ID_MOTION_COMMAND: u32 = 0x111;
pub const ID_LIGHT_COMMAND: u32 = 0x121;
pub const ID_SYSTEM_STATE: u32 = 0x211;
pub const ID_MOTION_STATE: u32 = 0x221;
pub const ID_LIGHT_STATE: u32 = 0x231;
pub const ID_RC_STATE: u32 = 0x241;
pub const ID_MOTOR1_HIGH_SPEED: u32 = 0x251;
pub const ID_MOTOR2_HIGH_SPEED: u32 = 0x252;
pub const ID_MOTOR1_LOW_SPEED: u32 = 0x261;
pub const ID_MOTOR2_LOW_SPEED: u32 = 0x262;
pub const ID_ODOMETRY: u32 = 0x311;
pub const ID_VERSION_REQUEST: u32 = 0x411;
pub const ID_VERSION_RESPONSE: u32 = 0x41A;
/// The AgileX SDK's version query since 2023 (protocol-notes 2.13): the request `01` (DLC 1), answered by
/// frames of eight ASCII characters each on the same identifier. Not in the TRACER manuals.
pub const ID_VERSION_TEXT: u32 = 0x4A1;
pub const ID_CONTROL_MODE: u32 = 0x421;
pub const ID_FAULT_CLEAR: u32 = 0x441;
/// The system-state ID printed in the TRACER V2 manual; also V1's system state.
pub const ID_SYSTEM_STATE_MANUAL: u32 = 0x151;

// CAN protocol V1 identifiers.
pub const ID_V1_MOTION_COMMAND: u32 = 0x130;
pub const ID_V1_MOTION_STATE: u32 = 0x131;
pub const ID_V1_LIGHT_COMMAND: u32 = 0x140;
pub const ID_V1_LIGHT_STATE: u32 = 0x141;
pub const ID_V1_SYSTEM_STATE: u32 = 0x151;
pub const ID_V1_MOTOR1: u32 = 0x201;
pub const ID_V1_MOTOR2: u32 = 0x202;

// RS232 frame types (`type << 8 | command` is the frame's identifier).
/// Frames the host sends.
pub const TYPE_CONTROL: u8 = 0x55;
/// Frames the chassis sends.
pub const TYPE_FEEDBACK: u8 = 0xAA;

// Feedback (0xAA) command ids.
pub const CMD_SYSTEM_STATUS: u8 = 0x01;
pub const CMD_MOTION_STATUS: u8 = 0x02;
pub const CMD_MOTOR1_DRIVER: u8 = 0x03;
pub const CMD_MOTOR2_DRIVER: u8 = 0x04;
pub const CMD_LIGHT_STATUS: u8 = 0x07;
// Control (0x55) command ids.
pub const CMD_MOTION_CONTROL: u8 = 0x01;
pub const CMD_LIGHT_CONTROL: u8 = 0x02;

/// A frame's identifier on either wire. Ordered standard CAN, extended CAN, RS232, then by value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum FrameId {
    /// An 11-bit CAN identifier (`0x211`).
    Standard(u16),
    /// A 29-bit CAN identifier (`0x00000211`: always eight digits, so it never reads as a standard one).
    Extended(u32),
    /// An RS232 frame's `type << 8 | command` (`0xAA01`: always four digits).
    Serial(u16),
}

impl FrameId {
    /// A standard CAN identifier from the codec's `u32` constants (bits above the 11th dropped).
    pub const fn standard(id: u32) -> Self {
        Self::Standard((id & 0x7FF) as u16)
    }

    /// The identifier of an RS232 frame from its type and command bytes.
    pub const fn serial(frame_type: u8, command: u8) -> Self {
        Self::Serial(u16::from_be_bytes([frame_type, command]))
    }

    /// The number without its kind: the CAN identifier, or `type << 8 | command`.
    pub const fn value(self) -> u32 {
        match self {
            Self::Standard(id) | Self::Serial(id) => id as u32,
            Self::Extended(id) => id,
        }
    }

    /// The index of a standard identifier in a 2048-entry table.
    pub const fn standard_index(self) -> Option<usize> {
        match self {
            Self::Standard(id) => Some(id as usize),
            _ => None,
        }
    }

    /// Reads an identifier as the user writes it, with or without `0x`: up to three hex digits is a standard
    /// CAN identifier, eight digits (or a value above 0x7FF given with five to seven) an extended one, and
    /// four digits an RS232 `type << 8 | command` when its type byte is one (`AA01`, `5501`), otherwise a
    /// standard identifier written with a leading zero (`0211`).
    pub fn parse(text: &str) -> Result<Self, String> {
        let digits = text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")).unwrap_or(text);
        if digits.is_empty() || digits.len() > 8 || !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(format!(
                "{text:?} is not an identifier (up to 8 hex digits, such as 0x211 or 0xAA01)"
            ));
        }
        let value = u32::from_str_radix(digits, 16).map_err(|error| format!("{text:?}: {error}"))?;
        match digits.len() {
            4 if value > 0x7FF && matches!(value >> 8, 0x55 | 0xAA) => Ok(Self::Serial(value as u16)),
            1..=4 if value <= 0x7FF => Ok(Self::Standard(value as u16)),
            4 => Err(format!(
                "{text:?}: above 0x7FF and not an RS232 identifier (0x55xx or 0xAAxx); write an extended CAN \
                 identifier with eight digits ({value:08X})"
            )),
            _ if value <= 0x1FFF_FFFF => Ok(Self::Extended(value)),
            _ => Err(format!("{text:?} is above 0x1FFFFFFF, the largest CAN identifier")),
        }
    }
}

impl fmt::Display for FrameId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Standard(id) => write!(f, "0x{id:03X}"),
            Self::Extended(id) => write!(f, "0x{id:08X}"),
            Self::Serial(id) => write!(f, "0x{id:04X}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printed_one_way_by_kind() {
        assert_eq!(FrameId::Standard(0x211).to_string(), "0x211");
        assert_eq!(FrameId::Standard(0x1).to_string(), "0x001");
        assert_eq!(FrameId::Extended(0x211).to_string(), "0x00000211");
        assert_eq!(FrameId::serial(0xAA, 0x01).to_string(), "0xAA01");
    }

    #[test]
    fn ordered_standard_extended_serial() {
        let mut ids = vec![
            FrameId::Serial(0xAA01),
            FrameId::Extended(1),
            FrameId::Standard(0x7FF),
            FrameId::Standard(1),
        ];
        ids.sort();
        assert_eq!(
            ids,
            [FrameId::Standard(1), FrameId::Standard(0x7FF), FrameId::Extended(1), FrameId::Serial(0xAA01)]
        );
    }

    #[test]
    fn parses_what_users_write() {
        assert_eq!(FrameId::parse("0x211"), Ok(FrameId::Standard(0x211)));
        assert_eq!(FrameId::parse("211"), Ok(FrameId::Standard(0x211)));
        assert_eq!(FrameId::parse("0211"), Ok(FrameId::Standard(0x211)));
        assert_eq!(FrameId::parse("0xAA01"), Ok(FrameId::Serial(0xAA01)));
        assert_eq!(FrameId::parse("5501"), Ok(FrameId::Serial(0x5501)));
        assert_eq!(FrameId::parse("00000211"), Ok(FrameId::Extended(0x211)));
        assert_eq!(FrameId::parse("1234ABCD"), Ok(FrameId::Extended(0x1234ABCD)));
        assert_eq!(FrameId::parse("12345"), Ok(FrameId::Extended(0x12345)));
        for bad in ["", "0x", "xyz", "123456789", "0x1234", "FFFFFFFF"] {
            assert!(FrameId::parse(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn parse_reads_back_what_display_prints() {
        for id in [
            FrameId::Standard(0),
            FrameId::Standard(0x7FF),
            FrameId::Extended(0x1FFF_FFFF),
            FrameId::Serial(0xAA07),
        ] {
            assert_eq!(FrameId::parse(&id.to_string()), Ok(id));
        }
    }
}
