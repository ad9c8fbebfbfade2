//! A fake robot on the master side of a real pseudo-terminal: it sends RS232 system status every 20 ms and
//! records every frame the host sends, with its arrival time.
// Shared by the integration tests and the timing group (tests/timing): each binary uses a part.
#![allow(dead_code)]

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serialport::SerialPort;
use tracerctl::protocol::message::{Message, SystemState};
use tracerctl::protocol::serial::{SerialEncoder, SerialFrame, StreamDecoder, StreamEvent};

pub struct FakeRobot {
    /// The path the host opens (`--serial PATH`).
    pub path: String,
    received: Arc<Mutex<Vec<(Instant, SerialFrame)>>>,
    status: Arc<Mutex<SystemState>>,
    stop: Arc<AtomicBool>,
    mute: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl FakeRobot {
    /// Starts a robot that reports `status` (serial system status) every 20 ms.
    pub fn start(status: SystemState) -> Self {
        Self::start_muted(status, false)
    }

    /// A robot that never says anything (a dead robot behind a live adapter); host frames are recorded.
    pub fn start_silent() -> Self {
        Self::start_muted(healthy(), true)
    }

    fn start_muted(status: SystemState, muted: bool) -> Self {
        let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
        let path = slave.name().expect("the terminal side has a path");
        drop(slave);
        master.set_timeout(Duration::from_millis(5)).unwrap();
        let received = Arc::new(Mutex::new(Vec::new()));
        let status = Arc::new(Mutex::new(status));
        let stop = Arc::new(AtomicBool::new(false));
        let mute = Arc::new(AtomicBool::new(muted));
        let thread = {
            let (received, stop, mute) = (Arc::clone(&received), Arc::clone(&stop), Arc::clone(&mute));
            let status = Arc::clone(&status);
            std::thread::spawn(move || {
                let mut encoder = SerialEncoder::new();
                let mut decoder = StreamDecoder::new();
                let mut buffer = [0u8; 512];
                let mut next_status = Instant::now();
                while !stop.load(Ordering::SeqCst) {
                    if Instant::now() >= next_status && !mute.load(Ordering::SeqCst) {
                        let now_status = *status.lock().unwrap();
                        let bytes = encoder.encode_next(&Message::SystemState(now_status)).unwrap();
                        // Nobody may have the terminal open yet: dropped, as on a real wire.
                        let _ = master.write_all(&bytes);
                        next_status += Duration::from_millis(20);
                    }
                    if let Ok(read) = master.read(&mut buffer) {
                        let now = Instant::now();
                        decoder.feed(&buffer[..read], |event| {
                            if let StreamEvent::Frame { frame, .. } = event {
                                received.lock().unwrap().push((now, frame));
                            }
                        });
                    }
                }
            })
        };
        Self { path, received, status, stop, mute, thread: Some(thread) }
    }

    /// What the robot reports from now on (an E-stop pressed mid-drive, say).
    pub fn set_status(&self, status: SystemState) {
        *self.status.lock().unwrap() = status;
    }

    /// Stops sending status (the robot's feedback disappears); host frames are still recorded.
    pub fn go_silent(&self) {
        self.mute.store(true, Ordering::SeqCst);
    }

    /// Every host frame so far.
    pub fn frames(&self) -> Vec<(Instant, SerialFrame)> {
        self.received.lock().unwrap().clone()
    }
}

impl Drop for FakeRobot {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// A healthy robot in serial mode, 25.9 V, no faults.
pub fn healthy() -> SystemState {
    SystemState { control_mode: 2, battery_decivolts: 259, ..SystemState::default() }
}

/// (linear %, angular %) of an RS232 motion control frame, or None for other frames.
pub fn percent(frame: &SerialFrame) -> Option<(i8, i8)> {
    (frame.frame_type == 0x55 && frame.command == 0x01)
        .then(|| (frame.payload[2] as i8, frame.payload[3] as i8))
}
