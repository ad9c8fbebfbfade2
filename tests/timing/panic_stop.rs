//! A panic on any thread stops the robot: the panic hook sends zero-velocity frames, and the sender never
//! moves the robot again in this process. (Its own test binary: the panic flag is process-wide.)

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tracerctl::control::{panicked, Limits, MotionSender, STOP_FRAMES};
use tracerctl::link::{FrameTx, LinkFrame};
use tracerctl::protocol::Codec;
use tracerctl::protocol::Wire;

struct Recorder(Mutex<mpsc::Sender<(Instant, LinkFrame)>>);

impl FrameTx for Recorder {
    fn send(&self, frame: &LinkFrame) -> std::io::Result<()> {
        let _ = self.0.lock().unwrap().send((Instant::now(), *frame));
        Ok(())
    }
}

fn linear(frame: &LinkFrame) -> Option<i16> {
    match frame {
        LinkFrame::Can(frame) if frame.id() == 0x111 => {
            Some(i16::from_be_bytes([frame.data()[0], frame.data()[1]]))
        }
        _ => None,
    }
}

#[test]
fn a_panic_on_another_thread_stops_the_robot_for_good() {
    let (sender, frames) = mpsc::channel();
    let tx: Arc<dyn FrameTx> = Arc::new(Recorder(Mutex::new(sender)));
    let limits = Limits { linear_accel: 100.0, ..Limits::default() };
    let motion = MotionSender::start(tx, Codec::new(Wire::CanV2), limits, Duration::from_secs(5)).unwrap();
    motion.set_target(0.3, 0.0);
    std::thread::sleep(Duration::from_millis(100));

    // A reader or input thread dies.
    let panicked_at = Instant::now();
    let _ = std::thread::spawn(|| panic!("simulated bug in another thread")).join();
    assert!(panicked());
    // The main loop keeps asking for speed, as a drive loop that has not noticed yet would.
    for _ in 0..10 {
        motion.set_target(0.3, 0.0);
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(!motion.is_running(), "the sender ended itself");

    let frames: Vec<(Instant, LinkFrame)> = frames.try_iter().collect();
    assert!(frames.iter().any(|(_, f)| linear(f) == Some(300)), "it was driving");
    let speeds: Vec<(Instant, i16)> = frames.iter().filter_map(|(at, f)| Some((*at, linear(f)?))).collect();
    let first_zero = speeds.iter().position(|(at, speed)| *at >= panicked_at && *speed == 0).expect("zeros");
    assert!(speeds[first_zero].0.duration_since(panicked_at) < Duration::from_millis(50));
    let rest: Vec<i16> = speeds[first_zero..].iter().map(|(_, speed)| *speed).collect();
    assert!(rest.len() >= STOP_FRAMES && rest.iter().all(|speed| *speed == 0), "only zeros: {rest:?}");
}
