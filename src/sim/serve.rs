//! Runs the chassis model on a link: host frames in, feedback frames out, on the simulator's own clock.
//! Used by `--sim` (an in-process channel) and by `tracerctl sim` (vcan, a real port or a pseudo-terminal).

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::Context;

use super::{Chassis, FaultKind, SimConfig, SimState};
use crate::link::{Codec, Link, LinkKind};
use crate::protocol::ProtocolHint;

/// How often the loop wakes when nothing arrives: fine enough for 20 ms feedback periods.
const TICK: Duration = Duration::from_millis(2);

/// A simulator running on its own thread.
pub struct Running {
    stop: Arc<AtomicBool>,
    injections: Sender<FaultKind>,
    state: Arc<Mutex<SimState>>,
    thread: Option<JoinHandle<io::Result<()>>>,
}

impl Running {
    /// Injects a fault now (E-stop toggle, motor fault, ...).
    pub fn inject(&self, fault: FaultKind) {
        let _ = self.injections.send(fault);
    }

    /// The simulated robot's state as of its last step.
    pub fn state(&self) -> SimState {
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).clone()
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
    let thread = {
        let (stop, state) = (Arc::clone(&stop), Arc::clone(&state));
        std::thread::Builder::new()
            .name("tracerctl-sim".into())
            .spawn(move || run(config, link, &stop, &inbox, &state))
            .context("cannot start the simulator thread")?
    };
    Ok(Running { stop, injections, state, thread: Some(thread) })
}

/// The simulator loop; returns when `stop` is set or the host end of an in-process link goes away.
pub fn run(
    config: SimConfig,
    mut link: Link,
    stop: &AtomicBool,
    injections: &Receiver<FaultKind>,
    state: &Mutex<SimState>,
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
            *state.lock().unwrap_or_else(|poisoned| poisoned.into_inner()) = chassis.state();
        }
        for message in &feedback {
            let Ok(frame) = codec.encode(message) else { continue };
            match link.tx.send(&frame) {
                Ok(()) => {}
                // Nobody is listening on a pseudo-terminal or the bus is busy: a robot drops it too.
                Err(error) if matches!(error.kind(), io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock) => {
                }
                Err(error) if error.kind() == io::ErrorKind::BrokenPipe && in_process => return Ok(()),
                Err(error) if error.kind() == io::ErrorKind::BrokenPipe => {}
                Err(error) => return Err(error),
            }
        }
    }
    Ok(())
}
