//! `dashboard --record` and `monitor --log`: every frame as a candump -L line (RS232 frames in hex), written on
//! a thread of its own behind a bounded queue, so neither the 50 Hz sender nor a reader ever waits for the
//! disk. Nothing is lost silently: a frame that could not be queued (the disk is slower than the bus) or
//! written (a full disk, ENOSPC) is counted with the reason, for the screen and the exit report.
//!
//! A `.mcap` file is written as MCAP instead (output::mcap, decoded and formatted on the recorder's thread,
//! written by the MCAP writer's own thread), its current chunk closed and flushed at least every
//! [`MCAP_FLUSH`], so a recording killed outright (SIGKILL) stays readable up to then; a normal end (any
//! signal but SIGKILL) finishes it with its summary and index.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use parking_lot::Mutex;

use crate::candump;
use crate::link::{LinkFrame, Received};
use crate::output::mcap::{is_mcap_path, Compression, McapWriter, Provenance};
use crate::output::{number, Event, FrameRef};
use crate::protocol::detect::{ProtocolDetector, Verdict};
use crate::protocol::ProtocolHint;

/// Frames the queue holds before further ones are counted as lost (seconds of a busy bus).
pub const QUEUE_FRAMES: usize = 8192;
/// The writer takes up to this many queued frames per write.
const BATCH_FRAMES: usize = 256;
/// An MCAP recording's chunk is closed and written out at least this often: what a SIGKILL can lose.
pub const MCAP_FLUSH: Duration = Duration::from_secs(1);

/// The recording's file: created (and so checked) before anything starts.
pub struct LogFile {
    file: File,
    path: PathBuf,
    /// Set for a `.mcap` name: written as MCAP, frames decoded with `hint`.
    mcap: Option<(McapWriter<BufWriter<File>>, ProtocolHint)>,
}

impl LogFile {
    /// Creates the file; a `.mcap` name is an MCAP recording whose metadata names `command` (monitor,
    /// dashboard), with frames decoded as `hint` says.
    pub fn create(path: &Path, command: &'static str, hint: ProtocolHint) -> Result<Self> {
        let file =
            File::create(path).with_context(|| format!("cannot create the log file {}", path.display()))?;
        let mcap = if is_mcap_path(path) {
            let out = BufWriter::new(file.try_clone().context("cannot open the recording twice")?);
            let provenance = Provenance { command, sources: Vec::new() };
            let writer = McapWriter::new(out, Compression::default(), provenance)
                .map_err(|error| anyhow::anyhow!("cannot write {}: {error}", path.display()))?;
            Some((writer, hint))
        } else {
            None
        };
        Ok(Self { file, path: path.to_path_buf(), mcap })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// A candump -L line for a CAN frame; for an RS232 frame, its 13 bytes in hex with the stamp and port in a
/// comment (`5AA50AAA01... # (1700000000.002500) /dev/ttyUSB0`), which `decode --serial FILE` reads.
pub fn push_raw_line(out: &mut Vec<u8>, received: &Received, iface: &str) {
    match &received.frame {
        LinkFrame::Can(frame) => candump::write_log_line(out, Some(received.ts), iface, frame),
        LinkFrame::Serial(frame) => {
            number::push_hex(out, &frame.to_bytes());
            out.extend_from_slice(b" # (");
            number::push_timestamp(out, &received.ts);
            out.extend_from_slice(b") ");
            out.extend_from_slice(iface.as_bytes());
            out.push(b'\n');
        }
    }
}

/// Frames the recording lost, and why (the first reason; a full disk stays full).
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct RecordLoss {
    pub frames: u64,
    pub reason: String,
}

#[derive(Default)]
struct Losses {
    frames: AtomicU64,
    reason: Mutex<Option<String>>,
}

impl Losses {
    fn add(&self, frames: u64, reason: impl FnOnce() -> String) {
        if frames == 0 {
            return;
        }
        let mut first = self.reason.lock();
        if first.is_none() {
            *first = Some(reason());
        }
        self.frames.fetch_add(frames, Ordering::SeqCst);
    }

    fn get(&self) -> Option<RecordLoss> {
        let frames = self.frames.load(Ordering::SeqCst);
        let reason = self.reason.lock().clone();
        (frames > 0).then(|| RecordLoss { frames, reason: reason.unwrap_or_default() })
    }
}

enum Item {
    Frame(Received),
    Close,
}

/// Where frames go to be recorded: any thread may hold one; `push` never blocks.
#[derive(Clone)]
pub struct RecordQueue {
    queue: SyncSender<Item>,
    losses: Arc<Losses>,
}

impl RecordQueue {
    /// Queues a frame; if the writer is that far behind, the frame is counted as lost instead. True when
    /// it was queued (so a tap beside the recording can keep exactly what the recording holds).
    pub fn push(&self, received: Received) -> bool {
        match self.queue.try_send(Item::Frame(received)) {
            Ok(()) => true,
            Err(TrySendError::Full(_)) => {
                self.losses.add(1, || {
                    format!("the disk was too slow: the recording queue ({QUEUE_FRAMES} frames) was full")
                });
                false
            }
            Err(TrySendError::Disconnected(_)) => {
                self.losses.add(1, || "the recording thread stopped".to_string());
                false
            }
        }
    }
}

/// The recording: its writer thread and the counts of what it lost.
pub struct Recorder {
    queue: RecordQueue,
    path: PathBuf,
    writer: Option<JoinHandle<()>>,
}

impl Recorder {
    /// Starts writing to `file`; lines name the interface `iface` (at most 15 characters, as candump's).
    pub fn start(file: LogFile, iface: &str) -> Result<Self> {
        Self::with_capacity(file, iface, QUEUE_FRAMES)
    }

    fn with_capacity(file: LogFile, iface: &str, capacity: usize) -> Result<Self> {
        let (sender, inbox) = mpsc::sync_channel(capacity);
        let losses = Arc::new(Losses::default());
        let path = file.path.clone();
        let iface: String = iface.chars().take(15).collect();
        let writer = {
            let losses = Arc::clone(&losses);
            std::thread::Builder::new()
                .name("tracerctl-record".into())
                .spawn(move || write_loop(file, &iface, &inbox, &losses))
                .context("cannot start the recording thread")?
        };
        Ok(Self { queue: RecordQueue { queue: sender, losses }, path, writer: Some(writer) })
    }

    pub fn queue(&self) -> RecordQueue {
        self.queue.clone()
    }

    /// Queues a frame (never waits; see [`RecordQueue::push`]).
    pub fn push(&self, received: Received) -> bool {
        self.queue.push(received)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What was lost so far.
    pub fn losses(&self) -> Option<RecordLoss> {
        self.queue.losses.get()
    }

    /// Writes what is queued, stops the writer, and returns what was lost in all.
    pub fn close(&mut self) -> Option<RecordLoss> {
        if let Some(writer) = self.writer.take() {
            // Blocking: the writer is draining the queue, so there is room soon.
            let _ = self.queue.queue.send(Item::Close);
            let _ = writer.join();
        }
        self.losses()
    }

    /// `the recording bus.log lost 1234 frames (No space left on device (os error 28))`
    pub fn describe(&self, loss: &RecordLoss) -> String {
        format!("the recording {} lost {} frames ({})", self.path.display(), loss.frames, loss.reason)
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        self.close();
    }
}

/// Takes what is queued in batches, one write each; a failed write loses its batch, counted with the error.
fn write_loop(mut file: LogFile, iface: &str, inbox: &Receiver<Item>, losses: &Losses) {
    if let Some((writer, hint)) = file.mcap.take() {
        return McapRecording::new(writer, hint, iface).run(inbox, losses);
    }
    let mut lines = Vec::with_capacity(BATCH_FRAMES * 48);
    let mut open = true;
    while open {
        let Ok(first) = inbox.recv() else { return };
        lines.clear();
        let mut frames = 0u64;
        let mut next = Some(first);
        while let Some(item) = next.take() {
            match item {
                Item::Frame(received) => {
                    push_raw_line(&mut lines, &received, iface);
                    frames += 1;
                }
                Item::Close => open = false,
            }
            if open && frames < BATCH_FRAMES as u64 {
                next = inbox.try_recv().ok();
            }
        }
        if let Err(error) = file.file.write_all(&lines) {
            losses.add(frames, || error.to_string());
        }
    }
}

/// An MCAP recording on the recorder's thread: each frame decoded into an [`Event`] as decode does.
struct McapRecording<'a> {
    writer: McapWriter<BufWriter<File>>,
    hint: ProtocolHint,
    detector: ProtocolDetector,
    serial: bool,
    iface: &'a str,
    /// The first write error: the file is unusable after it, every later frame is counted lost.
    failed: Option<String>,
}

impl<'a> McapRecording<'a> {
    fn new(mut writer: McapWriter<BufWriter<File>>, hint: ProtocolHint, iface: &'a str) -> Self {
        writer.set_sources(vec![iface.to_string()]);
        Self { writer, hint, detector: ProtocolDetector::default(), serial: false, iface, failed: None }
    }

    fn run(mut self, inbox: &Receiver<Item>, losses: &Losses) {
        let mut flushed = Instant::now();
        loop {
            // Wakes up to close the chunk of a quiet bus too.
            let item = match inbox.recv_timeout(MCAP_FLUSH) {
                Ok(item) => Some(item),
                Err(mpsc::RecvTimeoutError::Timeout) => None,
                Err(mpsc::RecvTimeoutError::Disconnected) => Some(Item::Close),
            };
            match item {
                Some(Item::Frame(received)) => self.frame(&received, losses),
                Some(Item::Close) => break,
                None => {}
            }
            if flushed.elapsed() >= MCAP_FLUSH {
                flushed = Instant::now();
                if let Err(error) = self.writer.flush() {
                    self.failed.get_or_insert_with(|| error.to_string());
                }
            }
        }
        self.finish(losses);
    }

    fn frame(&mut self, received: &Received, losses: &Losses) {
        if let Some(reason) = &self.failed {
            losses.add(1, || reason.clone());
            return;
        }
        let ts = Some(received.ts);
        let event = match &received.frame {
            LinkFrame::Can(frame) => {
                let decoded = self.detector.observe_and_decode(frame, self.hint);
                Event { ts, iface: self.iface, dir: None, frame: FrameRef::Can(frame), decoded }
            }
            LinkFrame::Serial(frame) => {
                self.serial = true;
                let decoded = Ok(crate::protocol::serial::decode(frame));
                Event { ts, iface: self.iface, dir: None, frame: FrameRef::Serial(frame), decoded }
            }
        };
        if let Err(error) = self.writer.event(&event) {
            let reason = error.to_string();
            losses.add(1, || reason.clone());
            self.failed = Some(reason);
        }
    }

    /// The metadata, summary and index; a failure is counted as the loss of the file's last chunk.
    fn finish(self, losses: &Losses) {
        let protocol = match self.detector.verdict() {
            _ if self.serial => "serial",
            Verdict::V1 => "can-v1",
            Verdict::V2 => "can-v2",
            Verdict::Unknown | Verdict::Mixed => "unknown",
        };
        if self.failed.is_some() {
            return;
        }
        match self.writer.finish(protocol) {
            Ok(mut out) => {
                if let Err(error) = out.flush() {
                    losses.add(1, || format!("cannot finish the MCAP file: {error}"));
                }
            }
            Err(error) => losses.add(1, || format!("cannot finish the MCAP file: {error}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::{Timestamp, TimestampKind};
    use crate::protocol::CanFrame;

    fn frame(n: u8) -> Received {
        Received {
            ts: Timestamp { secs: 1_700_000_000, nanos: 0, kind: TimestampKind::Absolute },
            frame: LinkFrame::Can(CanFrame::new(0x211, &[n]).unwrap()),
        }
    }

    #[test]
    fn every_frame_is_written_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bus.log");
        let mut recorder = Recorder::start(
            LogFile::create(&path, "monitor", ProtocolHint::Auto).unwrap(),
            "a-very-long-interface-name",
        )
        .unwrap();
        let queue = recorder.queue();
        for n in 0..100 {
            queue.push(frame(n));
        }
        assert_eq!(recorder.close(), None);
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 100);
        assert_eq!(text.lines().next(), Some("(1700000000.000000) a-very-long-int 211#00"));
        assert_eq!(text.lines().last(), Some("(1700000000.000000) a-very-long-int 211#63"));
    }

    #[test]
    fn a_mcap_name_records_mcap_finished_with_its_metadata_on_close() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bus.MCAP");
        let file = LogFile::create(&path, "dashboard", ProtocolHint::Auto).unwrap();
        let mut recorder = Recorder::start(file, "can0").unwrap();
        for n in 0..100 {
            recorder.push(frame(n));
        }
        assert_eq!(recorder.close(), None);
        let bytes = std::fs::read(&path).unwrap();
        let summary = ::mcap::Summary::read(&bytes).unwrap().expect("finished: a summary");
        let index = &summary.metadata_indexes[0];
        let metadata = ::mcap::read::metadata(&bytes, index).unwrap().metadata;
        assert_eq!(metadata["command"], "dashboard");
        assert_eq!(metadata["sources"], "[\"can0\"]");
        assert_eq!(metadata["protocol"], "can-v2");
        let raw = ::mcap::MessageStream::new(&bytes)
            .unwrap()
            .filter(|message| message.as_ref().unwrap().channel.topic == "/tracer/raw")
            .count();
        assert_eq!(raw, 100);
    }

    // /dev/full is Linux's.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_full_disk_is_counted_with_its_reason() {
        let mut recorder = Recorder::start(
            LogFile::create(Path::new("/dev/full"), "monitor", ProtocolHint::Auto).unwrap(),
            "can0",
        )
        .unwrap();
        let queue = recorder.queue();
        for n in 0..50 {
            queue.push(frame(n));
        }
        let loss = recorder.close().unwrap();
        assert_eq!(loss.frames, 50);
        assert!(loss.reason.contains("No space left on device"), "{loss:?}");
        assert_eq!(
            recorder.describe(&loss),
            format!("the recording /dev/full lost 50 frames ({})", loss.reason)
        );
    }

    #[test]
    fn a_full_queue_never_blocks_and_counts_what_it_drops() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bus.log");
        let mut recorder = Recorder::with_capacity(
            LogFile::create(&path, "monitor", ProtocolHint::Auto).unwrap(),
            "can0",
            4,
        )
        .unwrap();
        let queue = recorder.queue();
        let start = std::time::Instant::now();
        for n in 0..=255 {
            for _ in 0..40 {
                queue.push(frame(n));
            }
        }
        assert!(start.elapsed() < std::time::Duration::from_secs(1), "pushing never waits");
        let loss = recorder.close();
        let written = std::fs::read_to_string(&path).unwrap().lines().count() as u64;
        let lost = loss.as_ref().map_or(0, |loss| loss.frames);
        assert_eq!(written + lost, 256 * 40, "every frame is written or counted");
        if let Some(loss) = loss {
            assert!(loss.reason.contains("queue"), "{loss:?}");
        }
    }
}
