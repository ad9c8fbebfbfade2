//! Runs the chassis model on a link: host frames in, feedback frames out, on the simulator's own clock.
//! Used by `--sim` (an in-process channel) and by `tracerctl sim` (vcan, a real port or a pseudo-terminal).

use std::io;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::Context;
use parking_lot::Mutex;

use super::{Chassis, FaultKind, SimConfig, SimState};
use crate::link::{Link, LinkKind};
use crate::protocol::Codec;
use crate::protocol::ProtocolHint;

/// How often the loop wakes when nothing arrives: fine enough for 20 ms feedback periods.
const TICK: Duration = Duration::from_millis(2);

/// A simulator running on its own thread.
pub struct Running {
    stop: Arc<AtomicBool>,
    injections: Sender<FaultKind>,
    state: Arc<Mutex<SimState>>,
    not_sent: Arc<AtomicU64>,
    thread: Option<JoinHandle<io::Result<()>>>,
}

impl Running {
    /// Injects a fault now (E-stop toggle, motor fault, ...).
    pub fn inject(&self, fault: FaultKind) {
        let _ = self.injections.send(fault);
    }

    /// The simulated robot's state as of its last step.
    pub fn state(&self) -> SimState {
        self.state.lock().clone()
    }

    /// Feedback frames the link could not take (a full transmit queue: a busy bus).
    pub fn not_sent(&self) -> u64 {
        self.not_sent.load(Ordering::Relaxed)
    }

    /// True when the simulator thread has ended (stopped, or failed: see [`Running::stop`]).
    pub fn has_ended(&self) -> bool {
        self.thread.as_ref().is_none_or(|thread| thread.is_finished())
    }

    /// Stops the simulator and waits for its thread; the error that ended it early, if any.
    pub fn stop(mut self) -> io::Result<()> {
        self.shutdown()
    }

    fn shutdown(&mut self) -> io::Result<()> {
        self.stop.store(true, Ordering::SeqCst);
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(_)) => Err(io::Error::other("the simulator thread panicked")),
            None => Ok(()),
        }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.shutdown();
    }
}

/// Starts a simulator on `link` (the robot's end) in a thread.
pub fn start(config: SimConfig, link: Link) -> anyhow::Result<Running> {
    let stop = Arc::new(AtomicBool::new(false));
    let (injections, inbox) = mpsc::channel();
    let state = Arc::new(Mutex::new(Chassis::new(config.clone()).state()));
    let not_sent = Arc::new(AtomicU64::new(0));
    let thread = {
        let (stop, state, not_sent) = (Arc::clone(&stop), Arc::clone(&state), Arc::clone(&not_sent));
        std::thread::Builder::new()
            .name("tracerctl-sim".into())
            .spawn(move || run(config, link, &stop, &inbox, &state, &not_sent))
            .context("cannot start the simulator thread")?
    };
    Ok(Running { stop, injections, state, not_sent, thread: Some(thread) })
}

/// The simulator loop; returns when `stop` is set or the host end of an in-process link goes away.
pub fn run(
    config: SimConfig,
    mut link: Link,
    stop: &AtomicBool,
    injections: &Receiver<FaultKind>,
    state: &Mutex<SimState>,
    not_sent: &AtomicU64,
) -> io::Result<()> {
    let mut chassis = Chassis::new(config);
    let mut codec = Codec::new(link.wire);
    // Only the in-process link has a host that can go away for good; a pseudo-terminal or a bus with no
    // one listening just loses the frames, as a real robot's would.
    let in_process = link.kind == LinkKind::Sim;
    let start = Instant::now();
    let mut feedback = Vec::new();
    while !stop.load(Ordering::SeqCst) {
        let now = start.elapsed();
        while let Ok(fault) = injections.try_recv() {
            chassis.inject(now, fault);
        }
        match link.rx.recv(TICK) {
            Ok(Some(received)) => {
                if let Ok(Some(decoded)) = codec.decode(&received.frame, ProtocolHint::V2) {
                    chassis.receive(start.elapsed(), &decoded.message);
                }
            }
            Ok(None) => {}
            Err(error) if error.kind() == io::ErrorKind::UnexpectedEof => return Ok(()),
            Err(error) => return Err(error),
        }
        let now = start.elapsed();
        chassis.step(now);
        feedback.clear();
        chassis.due_feedback(now, &mut feedback);
        // Publish the state before the frames that report it, so whoever reacts to a frame sees it.
        if !feedback.is_empty() {
            *state.lock() = chassis.state();
        }
        for message in &feedback {
            let Ok(frame) = codec.encode(message) else { continue };
            match link.tx.send(&frame) {
                Ok(()) => {}
                // Nobody is listening on a pseudo-terminal, or the bus is busy (ENOBUFS: the transmit queue
                // is full): a robot drops the frame too, and goes on. Counted for the report.
                Err(error) if crate::link::is_queue_full(&error) => {
                    not_sent.fetch_add(1, Ordering::Relaxed);
                }
                Err(error) if error.kind() == io::ErrorKind::BrokenPipe && in_process => return Ok(()),
                Err(error) if error.kind() == io::ErrorKind::BrokenPipe => {}
                Err(error) => return Err(error),
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::{FrameTx, LinkFrame};
    use crate::protocol::Wire;

    /// A bus whose transmit queue is full for the first `full` sends (ENOBUFS), then takes every frame.
    struct BusyBus {
        full: AtomicU64,
        sent: AtomicU64,
    }

    impl FrameTx for BusyBus {
        fn send(&self, _frame: &LinkFrame) -> io::Result<()> {
            if self.full.load(Ordering::SeqCst) > 0 {
                self.full.fetch_sub(1, Ordering::SeqCst);
                return Err(io::Error::from_raw_os_error(libc::ENOBUFS));
            }
            self.sent.fetch_add(1, Ordering::SeqCst);
            Ok(())
        }
    }

    #[test]
    fn a_full_transmit_queue_is_a_busy_bus_not_the_end() {
        let bus = Arc::new(BusyBus { full: AtomicU64::new(40), sent: AtomicU64::new(0) });
        let (_host, robot) = crate::link::channel::pair(Wire::CanV2, LinkKind::SocketCan, "can0");
        let link = Link { tx: Arc::clone(&bus) as Arc<dyn FrameTx>, ..robot };
        let running = start(SimConfig::default(), link).unwrap();
        std::thread::sleep(Duration::from_millis(300));
        assert!(!running.has_ended(), "the simulator keeps running after ENOBUFS");
        assert_eq!(running.not_sent(), 40, "every frame the queue refused is counted");
        assert!(bus.sent.load(Ordering::SeqCst) > 20, "and it sends again once the queue drains");
        running.stop().expect("no error ended it");
    }
}
