//! A live session with the robot: the link, a reader thread that keeps the latest robot status, and the
//! codec for sending. Every live command (monitor aside, which reads frames itself) is built on it.

pub mod confirm;
pub mod health;
mod journal;

pub use journal::{FrameTap, Journaling, TAP_QUEUE_FRAMES};
use journal::{Journal, RecordingTx};

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use parking_lot::{Condvar, Mutex, MutexGuard};

use crate::link::{self, FrameRx, FrameTx, LinkChoice, LinkFrame, LinkKind, RxStats};
use crate::protocol::detect::{ProtocolDetector, Verdict};
use crate::protocol::error_frame::{ErrorFrame, ErrorTally};
use crate::protocol::message::{
    Lights, MotionState, MotorDriverState, MotorHighSpeed, MotorLowSpeed, Odometry, RcState, SystemState,
};
use crate::protocol::{CanFrame, Codec, Decoded, FrameId, Message, ProtocolHint, Wire};
use crate::recorder::{LogFile, RecordLoss, Recorder};

/// How many distinct identifiers `RobotStatus::id_counts` keeps.
pub const MAX_COUNTED_IDS: usize = 64;

/// The latest of everything the robot reported.
#[derive(Clone, Debug, Default)]
pub struct RobotStatus {
    /// System state and the wire it came on (which decides the fault-bit table).
    pub system: Option<(Instant, SystemState, Wire)>,
    /// System-state frames received (0x211, 0x151, RS232 system status).
    pub system_frames: u64,
    pub motion: Option<(Instant, MotionState)>,
    pub lights: Option<(Instant, Lights)>,
    pub motor_high: [Option<MotorHighSpeed>; 2],
    pub motor_driver: [Option<MotorDriverState>; 2],
    pub motor_low: [Option<MotorLowSpeed>; 2],
    pub odometry: Option<Odometry>,
    /// RC transmitter state (0x241), if the robot sends it.
    pub rc: Option<(Instant, RcState)>,
    /// The latest CAN error frame, and every error frame counted by class (they are not identifiers).
    pub last_error_frame: Option<CanFrame>,
    pub error_tally: ErrorTally,
    pub detector: ProtocolDetector,
    pub frames: u64,
    /// Frames per identifier, in identifier order. At most [`MAX_COUNTED_IDS`] identifiers; the rest are
    /// only in `frames`.
    /// Error frames are not here (their "identifier" is a set of error classes): see `error_tally`.
    pub id_counts: Vec<(FrameId, u64)>,
    /// When the robot sent the latest frame: the kernel's receive timestamp on SocketCAN (so a backlog
    /// drained late, after a suspension say, is seen as old), the time it was read on other links.
    pub last_frame: Option<Instant>,
    pub rx: RxStats,
    /// Set when the link failed or ended; the reader has stopped.
    pub link_error: Option<String>,
    /// The source came to its end (a replayed log's last frame, a stopped simulator): not a failure.
    pub link_ended: bool,
}

impl RobotStatus {
    fn count(&mut self, frame: &LinkFrame) {
        if let LinkFrame::Can(can) = frame {
            if let Some(error) = ErrorFrame::from_frame(can) {
                self.error_tally.add(&error);
                return;
            }
        }
        let key = frame.frame_id();
        if let Some((_, count)) = self.id_counts.iter_mut().find(|(id, _)| *id == key) {
            *count += 1;
        } else if self.id_counts.len() < MAX_COUNTED_IDS {
            self.id_counts.push((key, 1));
            self.id_counts.sort_unstable_by_key(|(id, _)| *id);
        }
    }

    fn apply(&mut self, now: Instant, decoded: &Decoded) {
        match decoded.message {
            Message::SystemState(state) => {
                self.system = Some((now, state, decoded.wire));
                self.system_frames += 1;
            }
            Message::MotionState(state) => self.motion = Some((now, state)),
            Message::LightState(lights) => self.lights = Some((now, lights)),
            Message::MotorHighSpeed(motor) if matches!(motor.motor, 1 | 2) => {
                self.motor_high[usize::from(motor.motor - 1)] = Some(motor)
            }
            Message::MotorDriverState(motor) if matches!(motor.motor, 1 | 2) => {
                self.motor_driver[usize::from(motor.motor - 1)] = Some(motor)
            }
            Message::MotorLowSpeed(motor) if matches!(motor.motor, 1 | 2) => {
                self.motor_low[usize::from(motor.motor - 1)] = Some(motor)
            }
            Message::Odometry(odometry) => self.odometry = Some(odometry),
            Message::RcState(rc) => self.rc = Some((now, rc)),
            _ => {}
        }
    }

    /// The latest system state, if it is no older than `max_age`.
    pub fn fresh_system(&self, max_age: Duration) -> Option<(SystemState, Wire)> {
        self.system.filter(|(at, ..)| at.elapsed() <= max_age).map(|(_, state, wire)| (state, wire))
    }
}

struct Shared {
    status: Mutex<RobotStatus>,
    changed: Condvar,
    stop: AtomicBool,
}

/// An open session. Dropping it stops the reader thread (and the simulator of `--sim`).
pub struct Session {
    pub name: String,
    pub kind: LinkKind,
    pub tx: Arc<dyn FrameTx>,
    codec: Mutex<Codec>,
    hint: ProtocolHint,
    shared: Arc<Shared>,
    reader: Option<JoinHandle<ReaderEnd>>,
    recorder: Option<Recorder>,
    /// The recording's and the tap's queues, to wait for the tap at the end.
    journal: Option<Journal>,
    simulator: Option<crate::sim::serve::Running>,
}

impl Session {
    /// Opens the chosen link and starts reading. With `--sim`, starts a virtual TRACER first.
    pub fn open(choice: &LinkChoice, hint: ProtocolHint, sim: Option<crate::sim::SimConfig>) -> Result<Self> {
        Self::open_recording(choice, hint, sim, None)
    }

    /// As [`Session::open`], also writing every frame received and sent to `record` (candump -L lines; RS232
    /// frames in hex), flushed per line. The dashboard's `--record`.
    pub fn open_recording(
        choice: &LinkChoice,
        hint: ProtocolHint,
        sim: Option<crate::sim::SimConfig>,
        record: Option<&std::path::Path>,
    ) -> Result<Self> {
        let journal = Journaling { record: record.map(|path| (path, "dashboard")), tap: None };
        Self::open_journaled(choice, hint, sim, journal)
    }

    /// As [`Session::open`], writing the recording `journal` names (for the command it names) and handing
    /// every frame it holds to the tap, in the recording's order and with its stamps.
    pub fn open_journaled(
        choice: &LinkChoice,
        hint: ProtocolHint,
        sim: Option<crate::sim::SimConfig>,
        journal: Journaling<'_>,
    ) -> Result<Self> {
        let (link, simulator) = open_link(choice, sim)?;
        Self::start(link, simulator, hint, journal)
    }

    /// A session on a link that is already open (an in-process channel in tests, say).
    pub fn from_link(link: link::Link, hint: ProtocolHint) -> Result<Self> {
        Self::start(link, None, hint, Journaling::default())
    }

    fn start(
        link: link::Link,
        simulator: Option<crate::sim::serve::Running>,
        hint: ProtocolHint,
        journaling: Journaling<'_>,
    ) -> Result<Self> {
        let wire_for_can = match hint {
            ProtocolHint::V1 => Wire::CanV1,
            _ => Wire::CanV2,
        };
        let wire = if link.wire == Wire::Serial { Wire::Serial } else { wire_for_can };
        let shared = Arc::new(Shared {
            status: Mutex::new(RobotStatus::default()),
            changed: Condvar::new(),
            stop: AtomicBool::new(false),
        });
        // `dashboard --record`, `drive --record`, `commission --record`.
        let recorder = match journaling.record {
            Some((path, command)) => {
                Some(Recorder::start(LogFile::create(path, command, hint)?, &link.name)?)
            }
            None => None,
        };
        let journal = Journal::start(recorder.as_ref().map(Recorder::queue), journaling.tap)
            .context("cannot start the analysis thread")?;
        let tx: Arc<dyn FrameTx> = match &journal {
            Some(journal) => Arc::new(RecordingTx { inner: link.tx, journal: journal.clone() }),
            None => link.tx,
        };
        let reader = {
            let shared = Arc::clone(&shared);
            let rx = link.rx;
            let codec = Codec::new(wire);
            let kernel_stamps = link.kind == LinkKind::SocketCan;
            let journal = journal.clone();
            std::thread::Builder::new()
                .name("tracerctl-reader".into())
                .spawn(move || read_loop(rx, codec, hint, &shared, journal, kernel_stamps))
                .context("cannot start the reader thread")?
        };
        Ok(Self {
            name: link.name,
            kind: link.kind,
            tx,
            codec: Mutex::new(Codec::new(wire)),
            hint,
            shared,
            reader: Some(reader),
            recorder,
            journal,
            simulator,
        })
    }

    /// The protocol version the user asked for (`--protocol`).
    pub fn hint(&self) -> ProtocolHint {
        self.hint
    }

    /// The wire commands are encoded for.
    pub fn wire(&self) -> Wire {
        self.codec().wire
    }

    /// The codec (for building frames to send).
    pub fn codec(&self) -> MutexGuard<'_, Codec> {
        self.codec.lock()
    }

    /// A copy of the latest status.
    pub fn status(&self) -> RobotStatus {
        self.shared.status.lock().clone()
    }

    /// Waits until `check` returns `Some` for the status, or `timeout` passes.
    pub fn wait_for<T>(
        &self,
        timeout: Duration,
        mut check: impl FnMut(&RobotStatus) -> Option<T>,
    ) -> Option<T> {
        let deadline = Instant::now() + timeout;
        let mut status = self.shared.status.lock();
        loop {
            if let Some(found) = check(&status) {
                return Some(found);
            }
            let now = Instant::now();
            if now >= deadline {
                return None;
            }
            self.shared.changed.wait_for(&mut status, deadline - now);
        }
    }

    /// Sleeps until the reader takes in a frame (the status changes) or `timeout` passes: a loop that
    /// must act on the robot's state at once wakes on it, not on its own period.
    pub fn wait_for_change(&self, timeout: Duration) {
        let mut status = self.shared.status.lock();
        self.shared.changed.wait_for(&mut status, timeout);
    }

    /// Waits for a system-state frame newer than `after` (so a reply to something just sent).
    pub fn wait_system_after(&self, after: Instant, timeout: Duration) -> Option<(SystemState, Wire)> {
        self.wait_for(timeout, |status| {
            status.system.filter(|(at, ..)| *at > after).map(|(_, state, wire)| (state, wire))
        })
    }

    /// In auto mode on CAN, listens up to `timeout` for the robot's protocol version and encodes for it.
    /// Returns what was seen, to tell the user.
    pub fn settle_protocol(&self, timeout: Duration) -> Verdict {
        let verdict = self
            .wait_for(timeout, |status| match status.detector.verdict() {
                Verdict::Unknown => None,
                verdict => Some(verdict),
            })
            .unwrap_or(Verdict::Unknown);
        let mut codec = self.codec();
        if self.hint == ProtocolHint::Auto && codec.wire != Wire::Serial && verdict == Verdict::V1 {
            *codec = Codec::new(Wire::CanV1);
        }
        verdict
    }

    /// Sends one frame.
    pub fn send(&self, frame: &LinkFrame) -> Result<()> {
        self.tx.send(frame).with_context(|| format!("cannot send on {}", self.name))
    }

    /// The simulator behind `--sim`, if any.
    pub fn simulator(&self) -> Option<&crate::sim::serve::Running> {
        self.simulator.as_ref()
    }

    /// Frames the `--record` recording lost so far (a full disk, a disk slower than the bus).
    pub fn recording_losses(&self) -> Option<RecordLoss> {
        self.recorder.as_ref().and_then(Recorder::losses)
    }

    /// Ends the session: stops the reader, writes out the recording, and says what was lost or rejected.
    pub fn finish(mut self) -> Finished {
        let reader = self.stop_reader();
        // The reader has stopped: the sent frames waiting for its frames go on.
        self.journal.iter().for_each(Journal::flush);
        let recording = self.recorder.as_mut().and_then(|recorder| {
            let loss = recorder.close()?;
            Some(recorder.describe(&loss))
        });
        let ReaderEnd { rx, mut notes, report } =
            reader.unwrap_or(ReaderEnd { rx: RxStats::default(), notes: Vec::new(), report: None });
        // After the reader: every frame received and sent is queued for the tap; its figures are complete
        // once it has taken them in.
        if let Some(Err(incomplete)) = self.journal.as_ref().map(Journal::drain) {
            notes.push(incomplete);
        }
        Finished { rx, notes, report, recording }
    }

    fn stop_reader(&mut self) -> Option<ReaderEnd> {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.reader.take().and_then(|reader| reader.join().ok())
    }
}

/// What a finished session has to report.
#[derive(Debug, Default)]
pub struct Finished {
    /// The link's final counters.
    pub rx: RxStats,
    /// What the source said about itself (a replay's first rejected lines), not yet shown.
    pub notes: Vec<String>,
    /// The source's closing line (a replay's totals, when lines were rejected).
    pub report: Option<String>,
    /// `the recording FILE lost N frames (why)`, when it lost any.
    pub recording: Option<String>,
}

impl Drop for Session {
    fn drop(&mut self) {
        self.stop_reader();
        self.journal.iter().for_each(Journal::flush);
        // After the reader: everything received and sent is queued; write it all before going.
        if let Some(recorder) = self.recorder.as_mut() {
            recorder.close();
        }
    }
}

/// Opens the chosen link; with `--sim`, also starts the virtual TRACER on the other end (stopped when the
/// returned handle drops). For commands that read frames themselves (monitor).
pub fn open_link(
    choice: &LinkChoice,
    sim: Option<crate::sim::SimConfig>,
) -> Result<(link::Link, Option<crate::sim::serve::Running>)> {
    Ok(match choice {
        LinkChoice::Sim => {
            let config = sim.unwrap_or_default();
            let wire = match config.wire {
                crate::sim::SimWire::Serial => Wire::Serial,
                crate::sim::SimWire::CanV2 => Wire::CanV2,
            };
            let (host, robot) = link::channel::pair(wire, LinkKind::Sim, "sim");
            (host, Some(crate::sim::serve::start(config, robot)?))
        }
        LinkChoice::Replay { path, speed } => (link::replay::open(path, *speed)?, None),
        LinkChoice::Serial { path, baud } => (link::serial::open(path, *baud)?, None),
        LinkChoice::SocketCan { iface } => (open_socketcan(iface)?, None),
    })
}

#[cfg(target_os = "linux")]
fn open_socketcan(iface: &str) -> Result<link::Link> {
    link::socketcan::open(iface)
}

#[cfg(not(target_os = "linux"))]
fn open_socketcan(_iface: &str) -> Result<link::Link> {
    anyhow::bail!("SocketCAN exists only on Linux: use --serial PORT or --sim")
}

/// The moment a frame stamped `ts` (wall clock, by the kernel) was received, on the monotonic clock. A
/// stamp in the future (the wall clock stepped back) counts as now; one older than a minute as a minute.
pub(crate) fn sent_at(ts: &crate::candump::Timestamp) -> Instant {
    let now = Instant::now();
    let stamp = Duration::new(ts.secs, ts.nanos);
    let wall = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or(Duration::ZERO);
    let age = wall.saturating_sub(stamp).min(Duration::from_secs(60));
    now.checked_sub(age).unwrap_or(now)
}

/// Which way a frame crossed the link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Received,
    Sent,
}

/// What the reader thread hands back when it stops.
struct ReaderEnd {
    rx: RxStats,
    notes: Vec<String>,
    report: Option<String>,
}

fn read_loop(
    mut rx: Box<dyn FrameRx>,
    codec: Codec,
    hint: ProtocolHint,
    shared: &Shared,
    journal: Option<Journal>,
    kernel_stamps: bool,
) -> ReaderEnd {
    // Kept for the end: the dashboard's screen is no place for them (a replay notes a few lines at most).
    let mut notes = Vec::new();
    while !shared.stop.load(Ordering::SeqCst) {
        let waiting_since = link::now_timestamp();
        let received = rx.recv(Duration::from_millis(20));
        let mut status = shared.status.lock();
        status.rx = rx.stats();
        if status.rx.rejected_lines > 0 {
            notes.extend(rx.take_notes());
        }
        match received {
            Ok(Some(received)) => {
                if let Some(journal) = &journal {
                    journal.push(received, Direction::Received);
                }
                let now = if kernel_stamps { sent_at(&received.ts) } else { Instant::now() };
                status.frames += 1;
                status.count(&received.frame);
                status.last_frame = Some(now);
                if let LinkFrame::Can(frame) = &received.frame {
                    status.detector.observe(frame);
                    if frame.kind() == crate::protocol::FrameKind::Error {
                        status.last_error_frame = Some(*frame);
                    }
                }
                let hint = match hint {
                    ProtocolHint::Auto => status.detector.hint(),
                    forced => forced,
                };
                if let Ok(Some(decoded)) = codec.decode(&received.frame, hint) {
                    status.apply(now, &decoded);
                }
                shared.changed.notify_all();
            }
            Ok(None) => {
                if let Some(journal) = &journal {
                    journal.received_until(waiting_since);
                }
            }
            Err(error) => {
                status.link_ended = error.kind() == std::io::ErrorKind::UnexpectedEof;
                status.link_error = Some(error.to_string());
                shared.changed.notify_all();
                break;
            }
        }
    }
    notes.extend(rx.take_notes());
    ReaderEnd { rx: rx.stats(), notes, report: rx.report() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::{Timestamp, TimestampKind};
    use crate::link::{FrameTx, Received};
    use std::io;

    /// A SocketCAN receiver with a backlog: frames the robot sent `age` ago, all read now (as after a
    /// suspension), then nothing.
    struct Backlog {
        frames: Vec<Received>,
    }

    impl FrameRx for Backlog {
        fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>> {
            if self.frames.is_empty() {
                std::thread::sleep(timeout);
                return Ok(None);
            }
            Ok(Some(self.frames.remove(0)))
        }

        fn stats(&self) -> RxStats {
            RxStats::default()
        }
    }

    struct Nowhere;

    impl FrameTx for Nowhere {
        fn send(&self, _frame: &LinkFrame) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_backlog_drained_late_is_as_old_as_the_kernel_stamped_it() {
        let stamped = link::now_timestamp();
        let two_seconds_ago =
            Timestamp { secs: stamped.secs - 2, nanos: stamped.nanos, kind: TimestampKind::Absolute };
        let status_frame = CanFrame::new(0x211, &[0, 1, 1, 3, 0, 0, 0, 0xB1]).unwrap();
        let frames =
            (0..10).map(|_| Received { ts: two_seconds_ago, frame: LinkFrame::Can(status_frame) }).collect();
        let backlog = link::Link {
            name: "can0".to_string(),
            kind: LinkKind::SocketCan,
            wire: Wire::CanV2,
            tx: Arc::new(Nowhere),
            rx: Box::new(Backlog { frames }),
        };
        let session = Session::from_link(backlog, ProtocolHint::Auto).unwrap();
        let status =
            session.wait_for(Duration::from_secs(1), |s| (s.frames == 10).then(|| s.clone())).unwrap();
        let age = status.last_frame.unwrap().elapsed();
        assert!(age >= Duration::from_millis(1900) && age < Duration::from_millis(2500), "{age:?}");
        assert!(status.fresh_system(Duration::from_secs(1)).is_none(), "two-second-old status is not fresh");
        assert!(status.system.is_some());
    }
}
