//! Links to a robot: SocketCAN, RS232, the in-process simulator, and candump replay.
//!
//! A link is split in two: a [`FrameTx`] that any thread may send on (the 50 Hz sender owns a handle), and a
//! [`FrameRx`] owned by the one thread that reads. Both work with [`LinkFrame`]s; [`crate::protocol::Codec`] turns
//! messages into the frames of the link's wire and back, so commands never care which link they use.

#[cfg(target_os = "linux")]
pub mod can_interface;
pub mod channel;
pub mod replay;
pub mod serial;
pub mod serial_access;
#[cfg(target_os = "linux")]
pub mod socketcan;

use std::io;
use std::sync::Arc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use crate::candump::{Timestamp, TimestampKind};
/// Links carry the protocol's frames.
pub use crate::protocol::LinkFrame;
use crate::protocol::Wire;

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
    /// A replayed log: lines read (frames, rejected lines, blank lines and comments).
    pub replayed_lines: u64,
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
    fn discard_pending(&self) -> Discarded {
        Discarded::default()
    }
}

/// What discarding a link's unsent output threw away.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Discarded {
    /// Frames the link counted in its queue and discarded.
    pub frames: usize,
    /// The link discarded output it cannot count: a pseudo-terminal, whose flush drops what its peer has not
    /// taken in yet (frames already written, possibly the latest ones) while its queue always reads as empty.
    pub uncounted: bool,
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

/// Which link to open (the command line's link options, checked).
#[derive(Clone, Debug)]
pub enum LinkChoice {
    SocketCan { iface: String },
    Serial { path: std::path::PathBuf, baud: u32 },
    Sim,
    Replay { path: std::path::PathBuf, speed: f64 },
}
