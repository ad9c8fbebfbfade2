//! The control mode: one type for what the robot reports (0x211 byte 1, the RS232 system status), what the
//! host requests (0x421, the RS232 motion command's mode byte), the simulator's state and every display.
//!
//! The wire codes live here and nowhere else. V2 firmware reports standby 0 at power-on before any 0x421 (the
//! TRACER manual calls it remote-control mode, copied from V1) and 3 under RC override; V1 and RS232 use 0
//! for RC and have no code of their own for standby.

use strum::{EnumMessage, EnumString, IntoStaticStr, VariantArray};

use super::id::{FrameId, ID_CONTROL_MODE, ID_V1_MOTION_COMMAND};
use super::wire::Wire;

/// Who the robot obeys. Names (`standby`, `can`, `serial`, `rc`) come from the variants.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    EnumString,
    IntoStaticStr,
    EnumMessage,
    VariantArray,
    strum::Display,
)]
#[strum(serialize_all = "snake_case")]
pub enum ControlMode {
    /// Power-on state: only 0x421 (CAN) or a serial-mode motion command (RS232) is obeyed.
    #[strum(message = "Standby (0x421 = 0x00)")]
    Standby,
    #[strum(message = "CAN command mode (0x421 = 0x01)")]
    Can,
    #[strum(message = "Serial command mode (0x421 = 0x02)")]
    Serial,
    /// RC override (transmitter on, SWB in the middle).
    Rc,
}

impl ControlMode {
    /// The modes a host may request (`tracerctl mode`), in the order `--help` lists them.
    pub const REQUESTABLE: [ControlMode; 3] = [ControlMode::Can, ControlMode::Serial, ControlMode::Standby];

    /// `standby`, `can`, `serial` or `rc`.
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// What requesting this mode does, for `--help` (`None` for RC: a host cannot request it).
    pub fn help(self) -> Option<&'static str> {
        self.get_message()
    }

    /// The control-mode byte the robot reports (and 0x421 carries) on `wire`: V2 standby 0, CAN 1, serial 2,
    /// RC 3; V1/RS232 RC 0, CAN 1, serial 2 (standby has no code of its own there and reads 0 like RC).
    pub const fn code(self, wire: Wire) -> u8 {
        match (self, wire) {
            (ControlMode::Standby, _) => 0,
            (ControlMode::Can, _) => 1,
            (ControlMode::Serial, _) => 2,
            (ControlMode::Rc, Wire::CanV2) => 3,
            (ControlMode::Rc, Wire::CanV1 | Wire::Serial) => 0,
        }
    }

    /// The mode a reported byte means on `wire` (0 is standby on V2, RC on V1/RS232); `None` for a byte no
    /// document defines. The inverse of [`ControlMode::code`] (a test checks every byte), written as a match
    /// because decode calls it for every system state it prints.
    pub const fn from_code(wire: Wire, code: u8) -> Option<Self> {
        match (wire, code) {
            (Wire::CanV2, 0) => Some(ControlMode::Standby),
            (Wire::CanV1 | Wire::Serial, 0) => Some(ControlMode::Rc),
            (_, 1) => Some(ControlMode::Can),
            (_, 2) => Some(ControlMode::Serial),
            (Wire::CanV2, 3) => Some(ControlMode::Rc),
            _ => None,
        }
    }

    /// The name of a reported byte, or `0xNN` for an undefined one: `can`, `0x07`.
    pub fn describe(wire: Wire, code: u8) -> String {
        Self::from_code(wire, code).map_or_else(|| format!("0x{code:02X}"), |mode| mode.name().to_string())
    }

    /// The byte that requests this mode on `wire`, if that link can request it: 0x421 takes standby, CAN and
    /// serial (V2); V1 only switches to CAN; RS232 enters serial mode through the motion command's mode byte.
    pub fn request_code(self, wire: Wire) -> Option<u8> {
        match (wire, self) {
            (Wire::CanV2, ControlMode::Standby | ControlMode::Can | ControlMode::Serial)
            | (Wire::CanV1, ControlMode::Can)
            | (Wire::Serial, ControlMode::Serial) => Some(self.code(wire)),
            _ => None,
        }
    }

    /// What selects this mode on `wire`, in words: `0x421 = 0x01` on V2; elsewhere the motion command carries
    /// the mode, so `a zero-speed 0x130 command` (V1) or `a zero-speed RS232 motion command`. `None` when
    /// that link cannot request the mode.
    pub fn request_text(self, wire: Wire) -> Option<String> {
        let code = self.request_code(wire)?;
        Some(match wire {
            Wire::CanV2 => format!("{} = 0x{code:02X}", FrameId::standard(ID_CONTROL_MODE)),
            Wire::CanV1 => format!("a zero-speed {} command", FrameId::standard(ID_V1_MOTION_COMMAND)),
            Wire::Serial => "a zero-speed RS232 motion command".to_string(),
        })
    }

    /// The command mode of a link: CAN on either CAN wire, serial on RS232.
    pub fn command_mode_of(wire: Wire) -> Self {
        match wire {
            Wire::CanV2 | Wire::CanV1 => ControlMode::Can,
            Wire::Serial => ControlMode::Serial,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WIRES: [Wire; 3] = [Wire::CanV2, Wire::CanV1, Wire::Serial];

    #[test]
    fn codes_per_wire() {
        let v2: Vec<_> = ControlMode::VARIANTS.iter().map(|m| m.code(Wire::CanV2)).collect();
        assert_eq!(v2, [0, 1, 2, 3]);
        let serial: Vec<_> = ControlMode::VARIANTS.iter().map(|m| m.code(Wire::Serial)).collect();
        assert_eq!(serial, [0, 1, 2, 0]);
        assert_eq!(ControlMode::from_code(Wire::CanV2, 0), Some(ControlMode::Standby));
        assert_eq!(ControlMode::from_code(Wire::CanV2, 3), Some(ControlMode::Rc));
        assert_eq!(ControlMode::from_code(Wire::Serial, 0), Some(ControlMode::Rc));
        assert_eq!(ControlMode::from_code(Wire::CanV1, 0), Some(ControlMode::Rc));
        assert_eq!(ControlMode::from_code(Wire::Serial, 3), None);
        assert_eq!(ControlMode::from_code(Wire::CanV2, 4), None);
    }

    #[test]
    fn request_texts_name_what_each_wire_sends() {
        let can = |wire| ControlMode::Can.request_text(wire);
        assert_eq!(can(Wire::CanV2).as_deref(), Some("0x421 = 0x01"));
        assert_eq!(ControlMode::Standby.request_text(Wire::CanV2).as_deref(), Some("0x421 = 0x00"));
        assert_eq!(can(Wire::CanV1).as_deref(), Some("a zero-speed 0x130 command"));
        let serial = ControlMode::Serial.request_text(Wire::Serial);
        assert_eq!(serial.as_deref(), Some("a zero-speed RS232 motion command"));
        assert_eq!(can(Wire::Serial), None);
        assert_eq!(ControlMode::Rc.request_text(Wire::CanV2), None);
    }

    #[test]
    fn every_defined_code_round_trips() {
        for wire in WIRES {
            for code in 0..=u8::MAX {
                if let Some(mode) = ControlMode::from_code(wire, code) {
                    assert_eq!(mode.code(wire), code, "{wire:?} {code}");
                }
            }
            for mode in ControlMode::VARIANTS {
                let back = ControlMode::from_code(wire, mode.code(wire));
                // Standby has no code of its own on V1/RS232: it reads back as RC.
                let expected = if wire != Wire::CanV2 && *mode == ControlMode::Standby {
                    ControlMode::Rc
                } else {
                    *mode
                };
                assert_eq!(back, Some(expected), "{wire:?} {mode}");
            }
        }
    }

    #[test]
    fn names_and_parsing_agree() {
        let names: Vec<_> = ControlMode::VARIANTS.iter().map(|m| m.name()).collect();
        assert_eq!(names, ["standby", "can", "serial", "rc"]);
        for mode in ControlMode::VARIANTS {
            assert_eq!(mode.name().parse::<ControlMode>(), Ok(*mode));
            assert_eq!(mode.to_string(), mode.name());
        }
        assert_eq!(ControlMode::describe(Wire::CanV2, 1), "can");
        assert_eq!(ControlMode::describe(Wire::CanV2, 7), "0x07");
    }

    #[test]
    fn requestable_modes_have_help_and_codes() {
        for mode in ControlMode::REQUESTABLE {
            assert!(mode.help().is_some_and(|help| help.contains("0x421")), "{mode}");
        }
        assert_eq!(ControlMode::Rc.help(), None);
        assert_eq!(ControlMode::Standby.request_code(Wire::CanV2), Some(0));
        assert_eq!(ControlMode::Serial.request_code(Wire::CanV2), Some(2));
        assert_eq!(ControlMode::Can.request_code(Wire::CanV1), Some(1));
        assert_eq!(ControlMode::Serial.request_code(Wire::CanV1), None);
        assert_eq!(ControlMode::Standby.request_code(Wire::Serial), None);
        assert_eq!(ControlMode::Rc.request_code(Wire::CanV2), None);
    }
}
