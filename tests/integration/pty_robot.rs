//! The robot's side of a real pseudo-terminal for send-raw and drive: it records what the host writes.
// Shared by the integration tests and the timing group (tests/timing): each binary uses a part.
#![allow(dead_code)]

use std::io::Read;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serialport::SerialPort;
use tracerctl::protocol::serial::{SerialFrame, StreamDecoder, StreamEvent};

/// The robot's side of a pseudo-terminal: records every frame the host writes, with its arrival time.
pub struct PtyRobot {
    pub path: String,
    pub frames: Arc<Mutex<Vec<(Instant, SerialFrame)>>>,
    bytes: Arc<Mutex<Vec<u8>>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
    _slave: serialport::TTYPort,
}

impl PtyRobot {
    pub fn start() -> Self {
        let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
        let path = slave.name().unwrap();
        master.set_timeout(Duration::from_millis(2)).unwrap();
        let frames = Arc::new(Mutex::new(Vec::new()));
        let bytes = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let (frames, bytes, stop) = (Arc::clone(&frames), Arc::clone(&bytes), Arc::clone(&stop));
            std::thread::spawn(move || {
                let mut decoder = StreamDecoder::new();
                let mut buffer = [0u8; 256];
                while !stop.load(Ordering::SeqCst) {
                    let Ok(read) = master.read(&mut buffer) else { continue };
                    let now = Instant::now();
                    bytes.lock().unwrap().extend_from_slice(&buffer[..read]);
                    decoder.feed(&buffer[..read], |event| {
                        if let StreamEvent::Frame { frame, .. } = event {
                            frames.lock().unwrap().push((now, frame));
                        }
                    });
                }
            })
        };
        Self { path, frames, bytes, stop, thread: Some(thread), _slave: slave }
    }

    pub fn finish(mut self) -> (Vec<(Instant, SerialFrame)>, Vec<u8>) {
        std::thread::sleep(Duration::from_millis(100));
        self.stop.store(true, Ordering::SeqCst);
        self.thread.take().unwrap().join().unwrap();
        let frames = self.frames.lock().unwrap().clone();
        let bytes = self.bytes.lock().unwrap().clone();
        (frames, bytes)
    }
}
