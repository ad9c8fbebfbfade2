//! Stopping the robot whatever happens: the stop sequence every sender shares, and the emergency stop the
//! panic hook sends on the link of the running sender (after a panic on any thread, no sender moves the
//! robot again in this process).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use parking_lot::Mutex;

use crate::link::{is_queue_full, Discarded, FrameTx, LinkFrame};
use crate::protocol::message::MotionCommand;
use crate::protocol::Codec;

/// How many zero-velocity frames end a drive (a lost frame or two must not matter).
pub const STOP_FRAMES: usize = 3;
/// How long the stop frames are retried while the transmit queue is full.
const STOP_RETRY: Duration = Duration::from_millis(100);

/// Set by the panic hook: after a panic on any thread, no sender moves the robot again in this process.
static PANICKED: AtomicBool = AtomicBool::new(false);

/// True once any thread of this process has panicked.
pub fn panicked() -> bool {
    PANICKED.load(Ordering::SeqCst)
}

/// Motion frames a sender is sending right now. A sender counts itself in, then looks at [`PANICKED`]; the
/// panic hook sets the flag, then waits for the count to fall before its zeros: so either the sender sees
/// the flag and sends nothing, or its frame is out before the zeros (a tick that had checked the flag just
/// before a panic sent one 0.3 m/s frame after the hook's zeros: seen in CI).
static MOTION_IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);
/// How long the panic hook waits for a motion frame in flight (bounded: the panicking thread may be the one
/// that was sending it).
const IN_FLIGHT_WAIT: Duration = Duration::from_millis(50);

/// Sends one motion frame unless a panic has stopped the robot (`None` then).
pub(super) fn send_motion_frame(tx: &dyn FrameTx, frame: &LinkFrame) -> Option<std::io::Result<()>> {
    MOTION_IN_FLIGHT.fetch_add(1, Ordering::SeqCst);
    let result = (!panicked()).then(|| tx.send(frame));
    MOTION_IN_FLIGHT.fetch_sub(1, Ordering::SeqCst);
    result
}

/// The frame and link the panic hook uses to stop the robot.
type Emergency = (Arc<dyn FrameTx>, LinkFrame);
static EMERGENCY: OnceLock<Mutex<Option<Emergency>>> = OnceLock::new();

fn emergency() -> &'static Mutex<Option<Emergency>> {
    EMERGENCY.get_or_init(|| Mutex::new(None))
}

/// What the panic hook stops the robot with: the running sender's link and stop frame, or `None` once
/// that sender has ended.
pub(super) fn set_emergency(stop: Option<Emergency>) {
    *emergency().lock() = stop;
}

/// Sends zero-velocity frames on the link of the running sender, if any (used by panic hooks).
pub fn emergency_stop() {
    PANICKED.store(true, Ordering::SeqCst);
    let deadline = Instant::now() + IN_FLIGHT_WAIT;
    while MOTION_IN_FLIGHT.load(Ordering::SeqCst) > 0 && Instant::now() < deadline {
        std::thread::yield_now();
    }
    if let Some(guard) = emergency().try_lock() {
        if let Some((tx, frame)) = guard.as_ref() {
            tx.discard_pending();
            for _ in 0..STOP_FRAMES {
                let _ = tx.send(frame);
            }
        }
    }
}

/// Installs (once) a panic hook that sends zero-velocity frames before the usual panic report.
pub fn install_panic_hook() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            emergency_stop();
            previous(info);
        }));
    });
}

/// The stop sequence every sender shares (the 50 Hz sender, send-raw): discard what the link still holds for
/// output, so the zeros are not queued behind stale motion, then [`STOP_FRAMES`] zero-velocity frames (each
/// encoded anew, so RS232 frame ids keep rolling), each retried for up to [`STOP_RETRY`] while the transmit
/// queue is full. Every attempt's result goes to `record`. Returns (stop frames sent, what was discarded).
pub fn send_stop_frames(
    tx: &dyn FrameTx,
    codec: &mut Codec,
    mut record: impl FnMut(std::io::Result<()>),
) -> (usize, Discarded) {
    let discarded = tx.discard_pending();
    let deadline = Instant::now() + STOP_RETRY;
    let mut sent = 0;
    for _ in 0..STOP_FRAMES {
        let frame = codec.motion(MotionCommand::STOP);
        loop {
            match tx.send(&frame) {
                Ok(()) => {
                    sent += 1;
                    record(Ok(()));
                    break;
                }
                Err(error) if is_queue_full(&error) && Instant::now() < deadline => {
                    record(Err(error));
                    std::thread::sleep(Duration::from_millis(2));
                }
                Err(error) => {
                    record(Err(error));
                    break;
                }
            }
        }
    }
    (sent, discarded)
}
