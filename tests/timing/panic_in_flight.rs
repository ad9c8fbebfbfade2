//! A motion frame already on its way when a panic stops the robot goes out before the stop frames, never
//! after them. (Its own test binary: the panic flag is process-wide.)

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tracerctl::control::{emergency_stop, Limits, MotionSender};
use tracerctl::link::{FrameTx, LinkFrame};
use tracerctl::protocol::{Codec, Wire};

/// A link whose sends of moving frames take 30 ms (a slow adapter); it records each frame with the time its
/// send ended, and says when the first moving frame's send began.
struct SlowLink {
    done: Mutex<mpsc::Sender<(Instant, LinkFrame)>>,
    moving_began: Mutex<Option<mpsc::Sender<()>>>,
}

fn linear(frame: &LinkFrame) -> Option<i16> {
    match frame {
        LinkFrame::Can(frame) if frame.id() == 0x111 => {
            Some(i16::from_be_bytes([frame.data()[0], frame.data()[1]]))
        }
        _ => None,
    }
}

impl FrameTx for SlowLink {
    fn send(&self, frame: &LinkFrame) -> std::io::Result<()> {
        if linear(frame).is_some_and(|speed| speed != 0) {
            if let Some(began) = self.moving_began.lock().unwrap().take() {
                let _ = began.send(());
            }
            std::thread::sleep(Duration::from_millis(30));
        }
        let _ = self.done.lock().unwrap().send((Instant::now(), *frame));
        Ok(())
    }
}

#[test]
fn a_motion_frame_in_flight_at_a_panic_goes_out_before_the_stop_frames() {
    let (done_tx, done) = mpsc::channel();
    let (began_tx, began) = mpsc::channel();
    let link = SlowLink { done: Mutex::new(done_tx), moving_began: Mutex::new(Some(began_tx)) };
    let tx: Arc<dyn FrameTx> = Arc::new(link);
    let limits = Limits { linear_accel: 100.0, ..Limits::default() };
    let motion = MotionSender::start(tx, Codec::new(Wire::CanV2), limits, Duration::from_secs(5)).unwrap();
    motion.set_target(0.3, 0.0);
    // The sender is inside its send of a moving frame: the panic hook stops the robot now.
    began.recv_timeout(Duration::from_secs(5)).expect("a moving frame");
    let stopped_at = Instant::now();
    emergency_stop();
    assert!(stopped_at.elapsed() < Duration::from_secs(1), "the hook's wait is bounded");
    let deadline = Instant::now() + Duration::from_secs(2);
    while motion.is_running() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(!motion.is_running(), "the sender ended itself");
    let frames: Vec<(Instant, i16)> =
        done.try_iter().filter_map(|(at, frame)| Some((at, linear(&frame)?))).collect();
    assert!(frames.iter().any(|&(_, speed)| speed != 0), "it was moving: {frames:?}");
    // The stop: the first zero sent after the hook ran (zeros before it are the sender's start).
    let stop = frames.iter().position(|&(at, speed)| at >= stopped_at && speed == 0).expect("stop frames");
    let after: Vec<i16> = frames[stop..].iter().map(|&(_, speed)| speed).collect();
    assert!(after.iter().all(|&speed| speed == 0), "only zeros after the stop: {after:?}");
}
