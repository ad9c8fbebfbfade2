//! Messages <-> frames for one wire: the encodings a live link needs (rolling counters, the mode and
//! fault-clear conventions of each wire), and what a frame of either wire is. Pure: no I/O.

use super::can::{self, ProtocolHint};
use super::id::{ID_FAULT_CLEAR, ID_V1_MOTION_COMMAND};
use super::message::{
    Lights, MotionCommand, PercentMotionCommand, CLEAR_ALL, CLEAR_MOTOR1, CLEAR_MOTOR2, MODE_CAN, MODE_SERIAL,
};
use super::serial::{self as serial_codec, SerialEncoder, SerialFrame};
use super::{CanFrame, DecodeError, Decoded, Message, Wire};

/// A frame of either wire: what a link sends and receives, and what [`Codec`] builds and reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkFrame {
    Can(CanFrame),
    Serial(SerialFrame),
}

impl LinkFrame {
    pub fn frame_id(&self) -> crate::protocol::FrameId {
        match self {
            Self::Can(frame) => frame.frame_id(),
            Self::Serial(frame) => frame.frame_id(),
        }
    }
}

/// What a fault clear targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClearTarget {
    All,
    Motor1,
    Motor2,
}

impl ClearTarget {
    /// The 0x441 code (V2).
    fn v2_code(self) -> u8 {
        match self {
            ClearTarget::All => CLEAR_ALL,
            ClearTarget::Motor1 => CLEAR_MOTOR1,
            ClearTarget::Motor2 => CLEAR_MOTOR2,
        }
    }
}

/// What a fault clear of `target` sends on `wire`, in words (what [`Codec::clear_faults`] builds): every
/// report of a clear says it this way.
pub fn clear_description(wire: Wire, target: ClearTarget) -> String {
    match wire {
        Wire::CanV2 => format!("0x{ID_FAULT_CLEAR:03X} = 0x{:02X}", target.v2_code()),
        Wire::CanV1 => format!("the fault-clear codes in zero-speed 0x{ID_V1_MOTION_COMMAND:03X} commands"),
        Wire::Serial => "the fault-clear codes in zero-speed RS232 motion commands".to_string(),
    }
}

/// Messages <-> frames for one wire, with the state some encodings need (RS232 rolling frame ids).
pub struct Codec {
    pub wire: Wire,
    serial: SerialEncoder,
    light_count: u8,
}

impl Codec {
    pub fn new(wire: Wire) -> Self {
        Self { wire, serial: SerialEncoder::new(), light_count: 0 }
    }

    /// Encodes any message for this wire (RS232 frames get the next rolling frame id).
    pub fn encode(&mut self, message: &Message) -> Result<LinkFrame, can::EncodeError> {
        match self.wire {
            Wire::CanV2 => can::encode_v2(message).map(LinkFrame::Can),
            Wire::CanV1 => can::encode_v1(message).map(LinkFrame::Can),
            Wire::Serial => {
                let bytes = self.serial.encode_next(message)?;
                let frame = SerialFrame::from_bytes(&bytes).expect("the encoder writes valid frames");
                Ok(LinkFrame::Serial(frame))
            }
        }
    }

    /// The motion command frame for this wire (percentages on V1 and RS232, which also select the mode).
    pub fn motion(&mut self, command: MotionCommand) -> LinkFrame {
        let message = match self.wire {
            Wire::CanV2 => Message::MotionCommand(command),
            Wire::CanV1 | Wire::Serial => Message::PercentMotionCommand(self.percent(command, 0)),
        };
        self.encode(&message).expect("motion commands encode on every wire")
    }

    fn percent(&self, command: MotionCommand, fault_clear: u8) -> PercentMotionCommand {
        let mode = if self.wire == Wire::Serial { MODE_SERIAL } else { MODE_CAN };
        let (linear, angular) = (command.linear(), command.angular());
        let mut percent = PercentMotionCommand::from_si(mode, linear, angular).unwrap_or_else(|_| {
            let (clamped, _) = MotionCommand::clamped_from_si(linear, angular);
            PercentMotionCommand::from_si(mode, clamped.linear(), clamped.angular()).unwrap_or_default()
        });
        percent.fault_clear = fault_clear;
        percent
    }

    /// Frames that put the robot in command mode: 0x421 = CAN on V2; on V1 and RS232 the motion command
    /// itself carries the mode, so a zero-speed motion command does it.
    pub fn enable_command_mode(&mut self) -> LinkFrame {
        match self.wire {
            Wire::CanV2 => self.encode(&Message::ControlModeCommand(MODE_CAN)).expect("0x421 encodes"),
            Wire::CanV1 | Wire::Serial => self.motion(MotionCommand::STOP),
        }
    }

    /// A control-mode command (V2 only).
    pub fn control_mode(&mut self, mode: u8) -> Option<LinkFrame> {
        (self.wire == Wire::CanV2)
            .then(|| self.encode(&Message::ControlModeCommand(mode)).expect("0x421 encodes"))
    }

    /// The frame that asks for control mode `mode` (0x211's code): 0x421 on V2 CAN, a zero-speed motion
    /// command on RS232 (serial mode) and V1 (CAN mode); `None` when this wire cannot select that mode.
    pub fn select_mode(&mut self, mode: u8) -> Option<LinkFrame> {
        match (self.wire, mode) {
            (Wire::CanV2, _) => self.control_mode(mode),
            (Wire::CanV1, MODE_CAN) | (Wire::Serial, MODE_SERIAL) => Some(self.enable_command_mode()),
            _ => None,
        }
    }

    /// Fault-clear frames: one 0x441 on V2; on V1 and RS232, zero-speed motion commands carrying the
    /// clear codes of the faults that latch (motor comm, driver over-temperature, over-current).
    pub fn clear_faults(&mut self, target: ClearTarget) -> Vec<LinkFrame> {
        if self.wire == Wire::CanV2 {
            return vec![self.encode(&Message::FaultClear(target.v2_code())).expect("0x441 encodes")];
        }
        let codes: &[u8] = match target {
            ClearTarget::All => &[3, 4, 7, 8],
            ClearTarget::Motor1 => &[3],
            ClearTarget::Motor2 => &[4],
        };
        codes
            .iter()
            .map(|&code| {
                let message = Message::PercentMotionCommand(self.percent(MotionCommand::STOP, code));
                self.encode(&message).expect("motion commands encode on every wire")
            })
            .collect()
    }

    /// A light command, with the rolling count byte.
    pub fn lights(&mut self, lights: Lights) -> LinkFrame {
        let lights = Lights { count: self.light_count, ..lights };
        self.light_count = self.light_count.wrapping_add(1);
        self.encode(&Message::LightCommand(lights)).expect("light commands encode on every wire")
    }

    /// Decodes a received frame.
    pub fn decode(&self, frame: &LinkFrame, hint: ProtocolHint) -> Result<Option<Decoded>, DecodeError> {
        match frame {
            LinkFrame::Can(frame) => can::decode(frame, hint),
            LinkFrame::Serial(frame) => Ok(serial_codec::decode(frame)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::MODE_STANDBY;

    fn cansend(frame: Option<LinkFrame>) -> String {
        match frame {
            Some(LinkFrame::Can(frame)) => frame.to_string(),
            other => panic!("expected a CAN frame, got {other:?}"),
        }
    }

    #[test]
    fn v2_mode_frames_are_0x421_with_dlc_1() {
        let mut codec = Codec::new(Wire::CanV2);
        assert_eq!(cansend(codec.select_mode(MODE_CAN)), "421#01");
        assert_eq!(cansend(codec.select_mode(MODE_STANDBY)), "421#00");
        assert_eq!(cansend(codec.select_mode(MODE_SERIAL)), "421#02");
        let Some(LinkFrame::Can(frame)) = codec.select_mode(MODE_CAN) else { panic!() };
        assert_eq!(frame.len(), 1);
    }

    #[test]
    fn serial_mode_over_rs232_is_a_zero_speed_serial_motion_command() {
        let mut codec = Codec::new(Wire::Serial);
        let Some(LinkFrame::Serial(frame)) = codec.select_mode(MODE_SERIAL) else { panic!() };
        // 5A A5 0A 55 01 | mode 02, no fault clear, 0 %, 0 % | frame id 00 | checksum
        let bytes = frame.to_bytes();
        assert_eq!(&bytes[..11], &[0x5A, 0xA5, 0x0A, 0x55, 0x01, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00]);
        let sum = bytes[..12].iter().fold(0u8, |sum, byte| sum.wrapping_add(*byte));
        assert_eq!(bytes[12], sum);
        assert_eq!(codec.select_mode(MODE_CAN), None);
        assert_eq!(codec.select_mode(MODE_STANDBY), None);
    }

    #[test]
    fn v1_can_mode_is_a_zero_speed_0x130() {
        let mut codec = Codec::new(Wire::CanV1);
        let text = cansend(codec.select_mode(MODE_CAN));
        assert!(text.starts_with("130#0100000000000"), "{text}");
        assert_eq!(codec.select_mode(MODE_SERIAL), None);
    }

    #[test]
    fn a_clear_is_described_as_what_the_codec_sends() {
        assert_eq!(clear_description(Wire::CanV2, ClearTarget::All), "0x441 = 0x00");
        assert_eq!(clear_description(Wire::CanV2, ClearTarget::Motor2), "0x441 = 0x02");
        let mut codec = Codec::new(Wire::CanV2);
        assert_eq!(cansend(codec.clear_faults(ClearTarget::Motor2).pop()), "441#02");
        assert_eq!(
            clear_description(Wire::CanV1, ClearTarget::All),
            "the fault-clear codes in zero-speed 0x130 commands"
        );
        let frames = Codec::new(Wire::CanV1).clear_faults(ClearTarget::All);
        assert!(frames.iter().all(|frame| frame.frame_id().to_string() == "0x130"), "{frames:?}");
        assert_eq!(
            clear_description(Wire::Serial, ClearTarget::Motor1),
            "the fault-clear codes in zero-speed RS232 motion commands"
        );
    }
}
