//! What a session keeps of its frames besides the robot status: the `--record` queue and the tap, fed in
//! one order from the reader's and the sender's threads. Both only queue: the recording is written on the
//! recorder's thread and the tap runs on its own (`tracerctl-analysis`), so neither a slow disk nor a slow
//! analysis ever holds up the sender's next frame (a stop frame least of all) or the robot's status.
//!
//! The order is the stamps' order. A received frame is stamped when it arrived (by the kernel, or by the
//! simulator), a sent one when it left; a reader starved of the CPU takes in frames hundreds of ms after
//! they arrived, while the sender has stamped and sent newer ones. So a sent frame waits here until the
//! reader has passed on every frame received before it (it passed on a later one, or found the link idle),
//! at most [`HOLD_LIMIT_US`]: analysed in arrival order, a run is cut at every stamp going back.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use parking_lot::Mutex;

use super::Direction;
use crate::candump::Timestamp;
use crate::link::{self, FrameTx, LinkFrame, Received};
use crate::recorder::RecordQueue;

/// Sees every frame the session's recording holds (every frame received and sent when there is none), in
/// the recording's order and with its stamps, on the session's analysis thread: what `commission` measures
/// live is then exactly what `decode --summary` measures in its `--record` file. It may take its time (a
/// backlog of [`TAP_QUEUE_FRAMES`] frames waits for it), and its caller reads its results under its own lock.
pub type FrameTap = Arc<dyn Fn(&Received, Direction) + Send + Sync>;

/// Frames that may wait for the tap: seconds of a busy bus, so a slow step of the analysis catches up.
pub const TAP_QUEUE_FRAMES: usize = 16_384;

/// How long [`Journal::drain`] waits for the tap to take in what is queued.
const DRAIN_TIMEOUT: Duration = Duration::from_secs(10);
/// A sent frame waits at most this long for the frames received before it, µs (a reader that has stopped
/// reading must not hold the sender's frames back for ever) ...
const HOLD_LIMIT_US: i64 = 1_000_000;
/// ... and at most this many wait (50 Hz for 2 s and more): the oldest goes on first.
const MAX_HELD: usize = 128;

/// What a session keeps of the frames besides the robot status: a recording and a tap.
#[derive(Default)]
pub struct Journaling<'a> {
    /// The recording's file and the command that writes it (its provenance in MCAP).
    pub record: Option<(&'a std::path::Path, &'static str)>,
    pub tap: Option<FrameTap>,
}

enum Tapped {
    Frame(Received, Direction),
    /// Answered once every frame queued before it has been through the tap.
    Drained(SyncSender<()>),
}

/// The recording's queue and the tap's, fed in one order: a frame the recording lost is not tapped either.
#[derive(Clone)]
pub(super) struct Journal {
    queue: Option<RecordQueue>,
    tap: Option<SyncSender<Tapped>>,
    /// Frames the tap never saw because its queue was full.
    tap_lost: Arc<AtomicU64>,
    /// Held across both queues, so both see the reader's and the sender's frames in one order. Only
    /// queueing happens under it.
    order: Arc<Mutex<Order>>,
}

/// Where the merge of the received and the sent frames stands.
struct Order {
    /// Sent frames not passed on yet, oldest first.
    held: VecDeque<Received>,
    /// Every frame received before this (µs) has been passed on.
    received_until: i64,
}

impl Journal {
    /// A journal for `queue` and `tap`; `None` when there is neither. Starts the tap's thread.
    pub(super) fn start(queue: Option<RecordQueue>, tap: Option<FrameTap>) -> std::io::Result<Option<Self>> {
        if queue.is_none() && tap.is_none() {
            return Ok(None);
        }
        let tap = match tap {
            Some(tap) => {
                let (sender, receiver) = mpsc::sync_channel(TAP_QUEUE_FRAMES);
                std::thread::Builder::new()
                    .name("tracerctl-analysis".into())
                    .spawn(move || run_tap(&receiver, &*tap))?;
                Some(sender)
            }
            None => None,
        };
        let order = Order { held: VecDeque::with_capacity(MAX_HELD), received_until: i64::MIN };
        Ok(Some(Self { queue, tap, tap_lost: Arc::default(), order: Arc::new(Mutex::new(order)) }))
    }

    /// A frame received or sent: passed on in the stamps' order (see the module's doc).
    pub(super) fn push(&self, received: Received, direction: Direction) {
        let mut order = self.order.lock();
        let at = micros(&received.ts);
        match direction {
            Direction::Received => {
                self.pass_held(&mut order, at);
                self.pass_on(received, Direction::Received);
                order.received_until = order.received_until.max(at);
            }
            Direction::Sent => {
                if order.held.len() == MAX_HELD {
                    let oldest = order.held.pop_front();
                    oldest.into_iter().for_each(|sent| self.pass_on(sent, Direction::Sent));
                }
                order.held.push_back(received);
                let until = order.received_until.max(at.saturating_sub(HOLD_LIMIT_US));
                self.pass_held(&mut order, until);
            }
        }
    }

    /// The reader found the link idle: every frame received before `since` (stamped before it began to
    /// wait) has been passed on.
    pub(super) fn received_until(&self, since: Timestamp) {
        let mut order = self.order.lock();
        order.received_until = order.received_until.max(micros(&since));
        let until = order.received_until;
        self.pass_held(&mut order, until);
    }

    /// Passes on every frame still held (the reader has stopped).
    pub(super) fn flush(&self) {
        let mut order = self.order.lock();
        self.pass_held(&mut order, i64::MAX);
    }

    /// Passes on the held sent frames stamped at or before `until`, µs.
    fn pass_held(&self, order: &mut Order, until: i64) {
        while let Some(sent) = order.held.front().filter(|sent| micros(&sent.ts) <= until).copied() {
            order.held.pop_front();
            self.pass_on(sent, Direction::Sent);
        }
    }

    /// To the recording's queue and the tap's. Under the order lock.
    fn pass_on(&self, received: Received, direction: Direction) {
        let kept = self.queue.as_ref().is_none_or(|queue| queue.push(received));
        if let (true, Some(tap)) = (kept, &self.tap) {
            if let Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) =
                tap.try_send(Tapped::Frame(received, direction))
            {
                self.tap_lost.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// Waits until the tap has taken in every frame queued so far. What went wrong otherwise: frames it
    /// never saw, an analysis that stopped or did not catch up.
    pub(super) fn drain(&self) -> Result<(), String> {
        let Some(tap) = &self.tap else { return Ok(()) };
        let deadline = Instant::now() + DRAIN_TIMEOUT;
        let (done, drained) = mpsc::sync_channel(1);
        // Not `send`: an analysis that never takes its queue in again must not hold the session's end.
        let mut asking = Tapped::Drained(done);
        let asked = loop {
            match tap.try_send(asking) {
                Ok(()) => break true,
                Err(TrySendError::Full(again)) if Instant::now() < deadline => {
                    asking = again;
                    std::thread::sleep(Duration::from_millis(1));
                }
                Err(_) => break false,
            }
        };
        let finished =
            asked && drained.recv_timeout(deadline.saturating_duration_since(Instant::now())).is_ok();
        let lost = self.tap_lost.load(Ordering::Relaxed);
        match (finished, lost) {
            (false, _) => Err("the live analysis stopped before the session's end: its figures miss frames \
                               the recording holds"
                .to_string()),
            (true, 0) => Ok(()),
            (true, lost) => Err(format!(
                "the live analysis fell behind and missed {lost} frames the recording holds ({TAP_QUEUE_FRAMES} \
                 were queued for it): decode --summary of the recording has the complete figures"
            )),
        }
    }
}

fn micros(ts: &Timestamp) -> i64 {
    ts.as_micros_i64()
}

/// The analysis thread: the tap, frame by frame, until every journal is gone.
fn run_tap(receiver: &Receiver<Tapped>, tap: &(dyn Fn(&Received, Direction) + Send + Sync)) {
    for tapped in receiver {
        match tapped {
            Tapped::Frame(received, direction) => tap(&received, direction),
            Tapped::Drained(done) => {
                let _ = done.send(());
            }
        }
    }
}

/// Sends, then queues what was sent for the recording and the tap.
pub(super) struct RecordingTx {
    pub(super) inner: Arc<dyn FrameTx>,
    pub(super) journal: Journal,
}

impl FrameTx for RecordingTx {
    fn send(&self, frame: &LinkFrame) -> std::io::Result<()> {
        self.inner.send(frame)?;
        self.journal.push(Received { ts: link::now_timestamp(), frame: *frame }, Direction::Sent);
        Ok(())
    }

    fn pending(&self) -> Option<usize> {
        self.inner.pending()
    }

    fn discard_pending(&self) -> link::Discarded {
        self.inner.discard_pending()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::TimestampKind;
    use crate::protocol::CanFrame;
    use std::io;

    struct Nowhere;

    impl FrameTx for Nowhere {
        fn send(&self, _frame: &LinkFrame) -> io::Result<()> {
            Ok(())
        }
    }

    fn frame(id: u32) -> LinkFrame {
        LinkFrame::Can(CanFrame::new(id, &[0; 8]).unwrap())
    }

    /// What the tap saw: identifier and direction.
    type Seen = Arc<Mutex<Vec<(u32, Direction)>>>;

    /// A tap that holds every frame until the test lets it go (an analysis step as slow as you like), and
    /// what it saw.
    fn held_tap() -> (FrameTap, SyncSender<()>, Seen) {
        let (release, released) = mpsc::sync_channel::<()>(0);
        let released = Mutex::new(released);
        let seen = Arc::new(Mutex::new(Vec::new()));
        let tap: FrameTap = {
            let seen = Arc::clone(&seen);
            Arc::new(move |received: &Received, direction| {
                let _ = released.lock().recv();
                if let LinkFrame::Can(can) = received.frame {
                    seen.lock().push((can.id(), direction));
                }
            })
        };
        (tap, release, seen)
    }

    /// A receiver that hears nothing.
    struct Silence;

    impl link::FrameRx for Silence {
        fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>> {
            std::thread::sleep(timeout);
            Ok(None)
        }

        fn stats(&self) -> link::RxStats {
            link::RxStats::default()
        }
    }

    #[test]
    fn a_slow_tap_never_holds_up_the_sender() {
        let (tap, release, seen) = held_tap();
        let link = link::Link {
            name: "can0".to_string(),
            kind: link::LinkKind::SocketCan,
            wire: crate::protocol::Wire::CanV2,
            tx: Arc::new(Nowhere),
            rx: Box::new(Silence),
        };
        let journaling = Journaling { record: None, tap: Some(tap) };
        let session =
            super::super::Session::start(link, None, crate::protocol::ProtocolHint::Auto, journaling)
                .unwrap();
        // The sender's frames, a moving command then stop frames, while the tap is stuck on the first.
        let (sent, all_sent) = mpsc::channel();
        let sender = {
            let tx = Arc::clone(&session.tx);
            std::thread::spawn(move || {
                for id in [0x111, 0x112, 0x113] {
                    tx.send(&frame(id)).unwrap();
                    sent.send(id).unwrap();
                }
            })
        };
        // The tap once ran inside `send`: the second frame waited for the first one's analysis.
        let sent: Vec<u32> =
            (0..3).map_while(|_| all_sent.recv_timeout(Duration::from_secs(20)).ok()).collect();
        let releaser = std::thread::spawn(move || while release.send(()).is_ok() {});
        assert_eq!(sent, [0x111, 0x112, 0x113], "every frame left while the tap was held");
        sender.join().unwrap();
        let finished = session.finish();
        assert_eq!(finished.notes, Vec::<String>::new());
        let expected = [(0x111, Direction::Sent), (0x112, Direction::Sent), (0x113, Direction::Sent)];
        assert_eq!(*seen.lock(), expected, "the tap saw every frame, in order, by the session's end");
        drop(finished);
        releaser.join().unwrap();
    }

    #[test]
    fn a_tap_that_falls_behind_is_reported_with_what_it_missed() {
        let (tap, release, seen) = held_tap();
        let journal = Journal::start(None, Some(tap)).unwrap().unwrap();
        let stamp = link::now_timestamp();
        // One frame taken by the held tap, a full queue behind it, then 5 that cannot be queued.
        let pushed = TAP_QUEUE_FRAMES + 6;
        for _ in 0..pushed {
            journal.push(Received { ts: stamp, frame: frame(0x221) }, Direction::Received);
        }
        // The tap may not have taken its first frame when the queue filled: 5 or 6 lost.
        let lost = journal.tap_lost.load(Ordering::Relaxed);
        assert!((5..=6).contains(&lost), "lost {lost}");
        let releaser = std::thread::spawn(move || while release.send(()).is_ok() {});
        let error = journal.drain().unwrap_err();
        assert!(error.contains(&format!("missed {lost} frames")), "{error}");
        assert_eq!(seen.lock().len() as u64, pushed as u64 - lost);
        drop(journal);
        releaser.join().unwrap();
    }

    /// A frame of identifier `id` stamped `ms` after an epoch.
    fn stamped(id: u32, ms: u64) -> Received {
        let ts = Timestamp {
            secs: 1_700_000_000 + ms / 1000,
            nanos: (ms % 1000) as u32 * 1_000_000,
            kind: TimestampKind::Absolute,
        };
        Received { ts, frame: frame(id) }
    }

    /// What a [`keeping_tap`] saw: identifier and stamp, ms.
    type Kept = Arc<Mutex<Vec<(u32, u64)>>>;

    /// A tap that keeps what it sees, in order.
    fn keeping_tap() -> (FrameTap, Kept) {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let tap: FrameTap = {
            let seen = Arc::clone(&seen);
            Arc::new(move |received: &Received, _| {
                if let LinkFrame::Can(can) = received.frame {
                    let ms =
                        (received.ts.secs - 1_700_000_000) * 1000 + u64::from(received.ts.nanos) / 1_000_000;
                    seen.lock().push((can.id(), ms));
                }
            })
        };
        (tap, seen)
    }

    #[test]
    fn a_late_reader_s_frames_go_before_the_sent_frames_stamped_after_them() {
        let (tap, seen) = keeping_tap();
        let journal = Journal::start(None, Some(tap)).unwrap().unwrap();
        // The sender sends at 10, 20 and 30 ms; the reader, starved, takes in what arrived at 5, 15 and 25
        // only afterwards. Passed on in arrival order, the analysis once saw the stamps go back 25 ms.
        for ms in [10, 20, 30] {
            journal.push(stamped(0x111, ms), Direction::Sent);
        }
        for ms in [5, 15, 25] {
            journal.push(stamped(0x221, ms), Direction::Received);
        }
        journal.drain().unwrap();
        assert_eq!(*seen.lock(), [(0x221, 5), (0x111, 10), (0x221, 15), (0x111, 20), (0x221, 25)]);
        // The reader found the link idle from 40 ms: nothing arrived before, the frame of 30 ms goes on.
        journal.received_until(stamped(0, 40).ts);
        journal.drain().unwrap();
        assert_eq!(seen.lock().last(), Some(&(0x111, 30)));
        // A reader that takes nothing in: a sent frame waits at most a second, then the rest at the end.
        journal.push(stamped(0x111, 1_000), Direction::Sent);
        journal.push(stamped(0x111, 2_500), Direction::Sent);
        journal.drain().unwrap();
        assert_eq!(seen.lock().last(), Some(&(0x111, 1_000)));
        journal.flush();
        journal.drain().unwrap();
        assert_eq!(seen.lock().last(), Some(&(0x111, 2_500)));
        assert_eq!(seen.lock().len(), 8, "nothing lost");
    }

    #[test]
    fn without_a_recording_or_a_tap_there_is_no_journal() {
        assert!(Journal::start(None, None).unwrap().is_none());
    }
}
