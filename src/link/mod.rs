//! Links to a robot: SocketCAN, RS232, the in-process simulator, and candump replay.
//!
//! A link is split in two: a [`FrameTx`] that any thread may send on (the 50 Hz sender owns a handle), and a
//! [`FrameRx`] owned by the one thread that reads. Both work with [`LinkFrame`]s; [`Codec`] turns messages
//! into the frames of the link's wire and back, so commands never care which link they use.

#[cfg(target_os = "linux")]
pub mod can_interface;
pub mod channel;
pub mod replay;
pub mod serial;
#[cfg(target_os = "linux")]
pub mod socketcan;

use std::io;
use std::sync::Arc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::candump::{Timestamp, TimestampKind};
use crate::protocol::can::{self, ProtocolHint};
use crate::protocol::message::{
    Lights, MotionCommand, PercentMotionCommand, CLEAR_ALL, CLEAR_MOTOR1, CLEAR_MOTOR2, MODE_CAN, MODE_SERIAL,
};
use crate::protocol::serial::{self as serial_codec, SerialEncoder, SerialFrame};
use crate::protocol::{CanFrame, DecodeError, Decoded, Message, Wire};

/// A frame on any link.
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

/// A received frame with its arrival time (kernel timestamp on SocketCAN, wall clock otherwise).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Received {
    pub ts: Timestamp,
    pub frame: LinkFrame,
}

/// Counters a receiver keeps: nothing is lost silently.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RxStats {
    pub frames: u64,
    /// Frames the kernel dropped because the socket's queue was full (SO_RXQ_OVFL).
    pub socket_drops: u64,
    /// CAN error frames received.
    pub error_frames: u64,
    /// RS232: candidates dropped for a bad checksum, and bytes that were not part of a frame.
    pub serial_bad_checksum: u64,
    pub serial_skipped_bytes: u64,
    /// RS232: bytes read, and times frame sync was lost after a good frame.
    pub serial_bytes: u64,
    pub serial_sync_losses: u64,
    /// A replayed log: lines that are not candump lines (see [`FrameRx::take_notes`] for where and why).
    pub rejected_lines: u64,
}

/// The sending half. `&self`, so one handle can be shared by several threads. Sending never blocks for
/// long: a full transmit queue is an error the caller counts ([`is_queue_full`]), not a wait.
pub trait FrameTx: Send + Sync {
    fn send(&self, frame: &LinkFrame) -> io::Result<()>;

    /// Frames accepted earlier that have not left yet, where the link can tell (a serial driver's output
    /// queue). A motion command must not queue behind them: by the time it left it would be stale.
    fn pending(&self) -> Option<usize> {
        None
    }

    /// Discards frames accepted but not yet sent (before the stop frames, so they reach the robot first);
    /// how many, where the link can tell.
    fn discard_pending(&self) -> usize {
        0
    }
}

/// True when a send failed only because the transmit queue is full (SocketCAN's ENOBUFS, a non-blocking
/// socket's EAGAIN, a serial write that timed out): the frame was not sent, the link is still there.
pub fn is_queue_full(error: &io::Error) -> bool {
    matches!(error.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut)
        || error.raw_os_error() == Some(libc::ENOBUFS)
}

/// What a full transmit queue means on this kind of link, in words, for messages and reports.
pub fn queue_full_meaning(kind: LinkKind) -> &'static str {
    match kind {
        LinkKind::Serial => {
            "the serial port's output is full: nobody reads the other end (no peer connected, a stalled \
             adapter, the robot off)"
        }
        _ => {
            "transmit queue full: the bus is busy, no other node acknowledges the frames, or the controller \
             is bus-off (check that the robot is on, the bus wired and terminated, the bitrate 500000, and \
             `ip -details -statistics link show` for the error state)"
        }
    }
}

/// What to check when nothing at all arrives, for this wire: RS232 advice on RS232 (baud, null-modem wiring,
/// serial control mode), CAN advice on CAN. Every command's message and doctor's advice say the same.
pub fn silence_advice(wire: Wire) -> &'static str {
    match wire {
        Wire::Serial => {
            "switch the robot on and set it to serial control mode; check that this is the port wired to the \
             robot's RS232, at 115200 baud 8N1 (--baud), wired null-modem (adapter TX to the robot's RX, adapter \
             RX to the robot's TX) with GND connected"
        }
        Wire::CanV1 | Wire::CanV2 => {
            "switch the robot on; check CAN_H/CAN_L wiring and termination (about 60 ohm between CAN_H and CAN_L \
             with power off), the bitrate (500000), and that this interface is the one wired to the robot"
        }
    }
}

/// The receiving half, owned by one reader thread.
pub trait FrameRx: Send {
    /// The next frame, or `None` when `timeout` passes first. `Err(UnexpectedEof)` when the source ended
    /// (replay finished, simulator stopped).
    fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>>;
    fn stats(&self) -> RxStats;

    /// What the source has to tell the user about itself since the last call (a replayed log's first
    /// rejected lines, with `file:line` and the reason), without the `tracerctl: ` prefix. Most links: none.
    fn take_notes(&mut self) -> Vec<String> {
        Vec::new()
    }

    /// A closing line about the source (a replay's totals, when lines were rejected).
    fn report(&self) -> Option<String> {
        None
    }
}

/// Which kind of link this is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkKind {
    SocketCan,
    Serial,
    Sim,
    Replay,
}

/// An open link.
pub struct Link {
    /// What to call it in messages and logs: the interface name, the port path, `sim`, or the replay file.
    pub name: String,
    pub kind: LinkKind,
    pub wire: Wire,
    pub tx: Arc<dyn FrameTx>,
    pub rx: Box<dyn FrameRx>,
}

/// The current time as an absolute timestamp.
pub fn now_timestamp() -> Timestamp {
    let since = SystemTime::now().duration_since(UNIX_EPOCH).unwrap_or(Duration::ZERO);
    Timestamp { secs: since.as_secs(), nanos: since.subsec_nanos(), kind: TimestampKind::Absolute }
}

/// What a fault clear targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ClearTarget {
    All,
    Motor1,
    Motor2,
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

    /// Fault-clear frames: one 0x441 on V2; on V1 and RS232, zero-speed motion commands carrying the
    /// clear codes of the faults that latch (motor comm, driver over-temperature, over-current).
    pub fn clear_faults(&mut self, target: ClearTarget) -> Vec<LinkFrame> {
        if self.wire == Wire::CanV2 {
            let code = match target {
                ClearTarget::All => CLEAR_ALL,
                ClearTarget::Motor1 => CLEAR_MOTOR1,
                ClearTarget::Motor2 => CLEAR_MOTOR2,
            };
            return vec![self.encode(&Message::FaultClear(code)).expect("0x441 encodes")];
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

/// Link options after validation.
#[derive(Clone, Debug)]
pub enum LinkChoice {
    SocketCan { iface: String },
    Serial { path: std::path::PathBuf, baud: u32 },
    Sim,
    Replay { path: std::path::PathBuf, speed: f64 },
}

impl LinkChoice {
    /// From the global command-line options.
    pub fn from_args(args: &crate::cli::LinkArgs) -> anyhow::Result<Self> {
        if args.sim {
            return Ok(Self::Sim);
        }
        if let Some(path) = &args.replay {
            // The range is checked by clap (`--speed`).
            return Ok(Self::Replay { path: path.clone(), speed: args.speed() });
        }
        match args.serial.as_slice() {
            [] => Ok(Self::SocketCan { iface: args.iface() }),
            [path] => Ok(Self::Serial { path: path.clone(), baud: args.baud() }),
            _ => anyhow::bail!("give one --serial port for a live link"),
        }
    }
}
