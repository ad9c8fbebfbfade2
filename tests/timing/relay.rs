//! A relay on the RS232 wire between the host (`tracerctl --serial PATH`, PATH a pseudo-terminal this relay
//! owns) and a robot on another pseudo-terminal (`tracerctl sim --pty`): every byte both ways is forwarded at
//! once and logged with the moment the relay read it, the witness of what each side put on the wire. It can
//! stop reading the host's side (a peer that stalled: what the host writes stays in the terminal's buffers)
//! while it keeps forwarding the robot's feedback.

use std::ffi::CString;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use tracerctl::protocol::serial::{SerialFrame, StreamDecoder, StreamEvent};

use crate::fault_peer::open_pty;

/// Who wrote the bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Host,
    Robot,
}

/// Bytes read from one side, and when.
pub type Chunk = (Instant, Side, Vec<u8>);

pub struct Relay {
    /// The path the host opens.
    pub path: String,
    log: Arc<Mutex<Vec<Chunk>>>,
    stalled: Arc<AtomicBool>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Relay {
    /// Relays between a new pseudo-terminal (for the host) and the robot's terminal at `robot_path`.
    pub fn start(robot_path: &str) -> Self {
        let (host, path) = open_pty();
        let robot = open_raw(robot_path);
        let log = Arc::new(Mutex::new(Vec::new()));
        let stalled = Arc::new(AtomicBool::new(false));
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let (log, stalled, stop) = (Arc::clone(&log), Arc::clone(&stalled), Arc::clone(&stop));
            std::thread::Builder::new()
                .name("rs232-relay".into())
                .spawn(move || relay(&host, &robot, &log, &stalled, &stop))
                .unwrap()
        };
        Self { path, log, stalled, stop, thread: Some(thread) }
    }

    /// Stops (true) or resumes (false) reading what the host writes.
    pub fn stall(&self, on: bool) {
        self.stalled.store(on, Ordering::SeqCst);
    }

    /// Every chunk so far.
    pub fn log(&self) -> Vec<Chunk> {
        self.log.lock().unwrap().clone()
    }

    /// Every frame one side wrote so far, with the moment its last byte was read.
    pub fn frames(&self, side: Side) -> Vec<(Instant, SerialFrame)> {
        frames(&self.log(), side)
    }
}

impl Drop for Relay {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The frames in a log from one side (the decoder `tracerctl decode --serial` uses).
pub fn frames(log: &[Chunk], side: Side) -> Vec<(Instant, SerialFrame)> {
    let mut decoder = StreamDecoder::new();
    let mut out = Vec::new();
    for (at, from, bytes) in log.iter().filter(|(_, from, _)| *from == side) {
        let _ = from;
        decoder.feed(bytes, |event| {
            if let StreamEvent::Frame { frame, .. } = event {
                out.push((*at, frame));
            }
        });
    }
    out
}

fn open_raw(path: &str) -> OwnedFd {
    let name = CString::new(path).unwrap();
    // SAFETY: plain libc calls on a descriptor this function owns.
    unsafe {
        let fd =
            libc::open(name.as_ptr(), libc::O_RDWR | libc::O_NOCTTY | libc::O_CLOEXEC | libc::O_NONBLOCK);
        assert!(fd >= 0, "open {path}: {}", std::io::Error::last_os_error());
        let owned = OwnedFd::from_raw_fd(fd);
        let mut termios = std::mem::zeroed::<libc::termios>();
        assert_eq!(libc::tcgetattr(fd, &mut termios), 0, "tcgetattr {path}");
        libc::cfmakeraw(&mut termios);
        assert_eq!(libc::tcsetattr(fd, libc::TCSANOW, &termios), 0, "tcsetattr {path}");
        owned
    }
}

fn relay(host: &OwnedFd, robot: &OwnedFd, log: &Mutex<Vec<Chunk>>, stalled: &AtomicBool, stop: &AtomicBool) {
    let mut buffer = [0u8; 4096];
    while !stop.load(Ordering::SeqCst) {
        let reading_host = !stalled.load(Ordering::SeqCst);
        let mut polls = [
            libc::pollfd { fd: robot.as_raw_fd(), events: libc::POLLIN, revents: 0 },
            libc::pollfd {
                fd: host.as_raw_fd(),
                events: if reading_host { libc::POLLIN } else { 0 },
                revents: 0,
            },
        ];
        // SAFETY: two valid pollfds.
        let ready = unsafe { libc::poll(polls.as_mut_ptr(), 2, 2) };
        if ready <= 0 {
            continue;
        }
        let mut moved = false;
        for (index, (from, to, side)) in
            [(robot, host, Side::Robot), (host, robot, Side::Host)].into_iter().enumerate()
        {
            if polls[index].revents & libc::POLLIN == 0 {
                continue;
            }
            // SAFETY: reads into a buffer of the given length.
            let read = unsafe { libc::read(from.as_raw_fd(), buffer.as_mut_ptr().cast(), buffer.len()) };
            if read > 0 {
                let bytes = buffer[..read as usize].to_vec();
                let at = Instant::now();
                // Written without waiting: what the other side has no room for is lost, as on a wire.
                // SAFETY: writes from a buffer of the given length.
                let _ = unsafe { libc::write(to.as_raw_fd(), bytes.as_ptr().cast(), bytes.len()) };
                log.lock().unwrap().push((at, side, bytes));
                moved = true;
            }
        }
        if !moved {
            // A hang-up (nobody has the host's side open yet, or any more): do not spin.
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}
