//! A fake TRACER that misbehaves on command, on the master side of a real pseudo-terminal (the host opens the
//! terminal side with `--serial PATH`). Every host frame is recorded with its arrival time.
//!
//! What it can do, each a method that takes effect within a couple of milliseconds:
//! - report system status every 20 ms (healthy, E-stop, exception, or none at all: [`FaultyRobot::set_status`]);
//! - report motion feedback every 20 ms that follows the last command, optionally lagging, or that stays at 0
//!   (a robot that does not follow), or none ([`FaultyRobot::set_motion`]). A following robot applies its own
//!   500 ms command timeout: no command for 500 ms and it stands still, as the chassis does;
//! - stop reading (a stalled adapter: the host's bytes pile up in the terminal's buffers) and resume;
//! - vanish: close the pseudo-terminal's master, so the host's side hangs up;
//! - flood garbage bytes, alone or interleaved with the valid feedback;
//! - stop all feedback ([`FaultyRobot::go_silent`]).
//!
//! Timing: one thread reads with a 2 ms timeout and writes the feedback on a 20 ms grid, so an arrival time
//! is late by at most the time the thread waits to be scheduled.

use std::collections::VecDeque;
use std::ffi::{CStr, CString};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use tracerctl::protocol::message::{
    Message, MotionState, SystemState, MODE_SERIAL, VEHICLE_ESTOP, VEHICLE_EXCEPTION,
};
use tracerctl::protocol::serial::{SerialEncoder, SerialFrame, StreamDecoder, StreamEvent};

/// The chassis reports every 20 ms.
pub const FEEDBACK_PERIOD: Duration = Duration::from_millis(20);
/// The chassis stops by itself when no motion command came for this long.
pub const COMMAND_TIMEOUT: Duration = Duration::from_millis(500);

/// What the motion feedback (RS232 0xAA/0x02) says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionFeedback {
    /// No motion feedback frames at all.
    Off,
    /// The measured speed is the command received `lag` ago (zero once the 500 ms command timeout ran out).
    Follow { lag: Duration },
    /// Motion feedback that always says 0: the wheels do not turn, whatever is commanded.
    StandStill,
}

#[derive(Clone, Copy, Debug)]
struct Behaviour {
    status: Option<SystemState>,
    motion: MotionFeedback,
    reading: bool,
    /// Garbage bytes written every 20 ms (split around the feedback frames).
    garbage: usize,
    vanish: bool,
}

struct Shared {
    behaviour: Mutex<Behaviour>,
    received: Mutex<Vec<(Instant, SerialFrame)>>,
    vanished: Mutex<Option<Instant>>,
    stop: AtomicBool,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

pub struct FaultyRobot {
    /// The path the host opens (`--serial PATH`).
    pub path: String,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
}

impl FaultyRobot {
    /// A robot that reports `status` every 20 ms and whose measured speed follows the commands at once.
    pub fn start(status: SystemState) -> Self {
        Self::with(Some(status), MotionFeedback::Follow { lag: Duration::ZERO })
    }

    /// A robot that says nothing (yet): no status, no motion feedback.
    pub fn silent() -> Self {
        Self::with(None, MotionFeedback::Off)
    }

    pub fn with(status: Option<SystemState>, motion: MotionFeedback) -> Self {
        let (master, path) = open_pty();
        let shared = Arc::new(Shared {
            behaviour: Mutex::new(Behaviour { status, motion, reading: true, garbage: 0, vanish: false }),
            received: Mutex::new(Vec::new()),
            vanished: Mutex::new(None),
            stop: AtomicBool::new(false),
        });
        let thread = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name("faulty-robot".into())
                .spawn(move || run(&shared, master))
                .unwrap()
        };
        Self { path, shared, thread: Some(thread) }
    }

    fn change(&self, change: impl FnOnce(&mut Behaviour)) {
        change(&mut lock(&self.shared.behaviour));
    }

    /// Reports `status` every 20 ms from now on (`None`: no status frames).
    pub fn set_status(&self, status: Option<SystemState>) {
        self.change(|b| b.status = status);
    }

    pub fn set_motion(&self, motion: MotionFeedback) {
        self.change(|b| b.motion = motion);
    }

    /// No feedback of any kind from now on (host frames are still read and recorded).
    pub fn go_silent(&self) {
        self.change(|b| {
            b.status = None;
            b.motion = MotionFeedback::Off;
        });
    }

    /// Stops reading: what the host writes stays in the terminal's buffers (a stalled adapter).
    pub fn stop_reading(&self) {
        self.change(|b| b.reading = false);
    }

    pub fn resume_reading(&self) {
        self.change(|b| b.reading = true);
    }

    /// `bytes` of garbage every 20 ms, around whatever feedback is on (0: no garbage).
    pub fn flood(&self, bytes: usize) {
        self.change(|b| b.garbage = bytes);
    }

    /// Closes the pseudo-terminal's master (the robot, cable and adapter are gone); returns when it is closed.
    pub fn vanish(&self) -> Instant {
        self.change(|b| b.vanish = true);
        let deadline = Instant::now() + Duration::from_secs(5);
        loop {
            if let Some(at) = *lock(&self.shared.vanished) {
                return at;
            }
            assert!(Instant::now() < deadline, "the fake robot did not close its terminal");
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Every host frame so far, with its arrival time.
    pub fn frames(&self) -> Vec<(Instant, SerialFrame)> {
        lock(&self.shared.received).clone()
    }

    /// Every RS232 motion command so far as (arrival, (linear %, angular %)).
    pub fn motion(&self) -> Vec<(Instant, (i8, i8))> {
        lock(&self.shared.received).iter().filter_map(|(at, frame)| Some((*at, percent(frame)?))).collect()
    }
}

impl Drop for FaultyRobot {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// (linear %, angular %) of an RS232 motion control frame (type 0x55, command 0x01), or None.
pub fn percent(frame: &SerialFrame) -> Option<(i8, i8)> {
    (frame.frame_type == 0x55 && frame.command == 0x01)
        .then(|| (frame.payload[2] as i8, frame.payload[3] as i8))
}

/// A healthy robot in serial mode, 25.9 V, no faults.
pub fn healthy() -> SystemState {
    SystemState { control_mode: MODE_SERIAL, battery_decivolts: 259, ..SystemState::default() }
}

pub fn estop() -> SystemState {
    SystemState { vehicle_state: VEHICLE_ESTOP, ..healthy() }
}

/// "System exception" with no fault bit set: nothing says why, and the wheels do not turn.
pub fn exception() -> SystemState {
    SystemState { vehicle_state: VEHICLE_EXCEPTION, ..healthy() }
}

/// What the robot measures now, from the commands it received (arrival, percent).
fn measured(commands: &VecDeque<(Instant, (i8, i8))>, now: Instant, lag: Duration) -> MotionState {
    let Some(seen_by) = now.checked_sub(lag) else { return MotionState::default() };
    let latest = commands.iter().rev().find(|(at, _)| *at <= seen_by);
    match latest {
        Some((at, (linear, angular))) if seen_by.duration_since(*at) <= COMMAND_TIMEOUT => MotionState {
            // 1 % = 15 mm/s and 7.853 mrad/s (the RS232 full scales, 1.5 m/s and 0.7853 rad/s).
            linear_mm_s: i16::from(*linear) * 15,
            angular_mrad_s: (f64::from(*angular) * 7.853).round() as i16,
            count: 0,
        },
        _ => MotionState::default(),
    }
}

/// Deterministic garbage: random bytes, with now and then a frame header whose frame is broken (a bad
/// checksum, a wrong length byte or type, or cut short), so the host's decoder must resynchronise.
struct Garbage {
    state: u64,
}

impl Garbage {
    fn next(&mut self) -> u64 {
        // xorshift64*
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        self.state.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn fill(&mut self, out: &mut Vec<u8>, len: usize) {
        let start = out.len();
        while out.len() - start < len {
            let roll = self.next();
            match roll % 16 {
                0 => {
                    out.extend_from_slice(&[0x5A, 0xA5, 0x0A, 0xAA, 0x02, 0x7F, 0x00, 0x7F, 0x00, 0, 0, 1, 0])
                }
                1 => out.extend_from_slice(&[0x5A, 0xA5, 0x0B, 0xAA, 0x01]),
                2 => out.extend_from_slice(&[0x5A, 0xA5, 0x0A, 0x33, 0x01]),
                3 => out.extend_from_slice(&[0x5A, 0xA5, 0x0A, 0xAA]),
                _ => out.extend_from_slice(&roll.to_le_bytes()),
            }
        }
        out.truncate(start + len);
        // Garbage must never be a valid frame by chance (the host would act on it).
        let mut decoder = StreamDecoder::new();
        let mut valid = false;
        decoder.feed(&out[start..], |event| valid |= matches!(event, StreamEvent::Frame { .. }));
        if valid {
            out.truncate(start);
            out.resize(start + len, 0x00);
        }
    }
}

fn run(shared: &Shared, master: OwnedFd) {
    let mut encoder = SerialEncoder::new();
    let mut decoder = StreamDecoder::new();
    let mut garbage = Garbage { state: 0x9E37_79B9_7F4A_7C15 };
    let mut commands: VecDeque<(Instant, (i8, i8))> = VecDeque::new();
    let mut buffer = [0u8; 4096];
    let mut next_tick = Instant::now();
    while !shared.stop.load(Ordering::SeqCst) {
        let behaviour = *lock(&shared.behaviour);
        if behaviour.vanish {
            // The caller's `vanish` returns once this is recorded; the master fd is closed on return.
            *lock(&shared.vanished) = Some(Instant::now());
            return;
        }
        let now = Instant::now();
        if now >= next_tick {
            let mut out = Vec::with_capacity(behaviour.garbage + 2 * 13);
            garbage.fill(&mut out, behaviour.garbage / 2);
            if let Some(status) = behaviour.status {
                out.extend_from_slice(&encoder.encode_next(&Message::SystemState(status)).unwrap());
            }
            garbage.fill(&mut out, behaviour.garbage - behaviour.garbage / 2);
            let state = match behaviour.motion {
                MotionFeedback::Off => None,
                MotionFeedback::StandStill => Some(MotionState::default()),
                MotionFeedback::Follow { lag } => Some(measured(&commands, now, lag)),
            };
            if let Some(state) = state {
                out.extend_from_slice(&encoder.encode_next(&Message::MotionState(state)).unwrap());
            }
            if !out.is_empty() {
                // Nobody may have the terminal open yet, or the host is slow: dropped, as on a real wire.
                write_master(&master, &out);
            }
            // The next point on the 20 ms grid; after a delay, no burst of late reports.
            next_tick += FEEDBACK_PERIOD;
            if next_tick <= now {
                next_tick = now + FEEDBACK_PERIOD;
            }
        }
        if !behaviour.reading {
            std::thread::sleep(Duration::from_millis(2));
            continue;
        }
        if let Some(read) = read_master(&master, &mut buffer) {
            let arrived = Instant::now();
            let mut received = lock(&shared.received);
            decoder.feed(&buffer[..read], |event| {
                if let StreamEvent::Frame { frame, .. } = event {
                    received.push((arrived, frame));
                    if let Some(speed) = percent(&frame) {
                        commands.push_back((arrived, speed));
                    }
                }
            });
            // Enough history for any lag the tests use.
            while commands.len() > 1000 {
                commands.pop_front();
            }
        }
    }
}

/// Reads what the host wrote, waiting up to 2 ms. Not through `serialport`'s `read`: it reports a hang-up
/// (POLLHUP, the host closed its side) as an error before reading, and the bytes the host wrote before it
/// went away are exactly what some scenarios are about.
fn read_master(master: &OwnedFd, buffer: &mut [u8]) -> Option<usize> {
    let mut poll = libc::pollfd { fd: master.as_raw_fd(), events: libc::POLLIN, revents: 0 };
    // SAFETY: one valid pollfd.
    let ready = unsafe { libc::poll(&mut poll, 1, 2) };
    if ready == 1 && poll.revents & libc::POLLIN != 0 {
        // SAFETY: reads into a buffer of the given length.
        let read = unsafe { libc::read(poll.fd, buffer.as_mut_ptr().cast(), buffer.len()) };
        if read > 0 {
            return Some(read as usize);
        }
    }
    if ready == 1 {
        // Nobody has the terminal side open (yet, or any more) and nothing is left to read: do not spin.
        std::thread::sleep(Duration::from_millis(2));
    }
    None
}

/// Writes what it can without waiting: bytes the host's side has no room for are lost, as on a real wire.
fn write_master(master: &OwnedFd, bytes: &[u8]) {
    // SAFETY: writes from a buffer of the given length.
    let _ = unsafe { libc::write(master.as_raw_fd(), bytes.as_ptr().cast(), bytes.len()) };
}

/// A new pseudo-terminal: the master (non-blocking) and the terminal side's path.
///
/// Opened close-on-exec, unlike `serialport::TTYPort::pair`: a master without it is inherited by every
/// process the tests spawn meanwhile, the host under test included, and a robot could then never vanish
/// (closing our copy would not hang up the host's side). The terminal side is set raw once, as
/// `TTYPort::pair` does (its default line discipline would echo the robot's feedback back to it before the
/// host opens the terminal).
pub fn open_pty() -> (OwnedFd, String) {
    let ptmx = CString::new("/dev/ptmx").unwrap();
    let flags = libc::O_RDWR | libc::O_NOCTTY | libc::O_CLOEXEC | libc::O_NONBLOCK;
    // SAFETY: plain libc calls on descriptors this function owns; ptsname_r gets a buffer and its length.
    unsafe {
        let fd = libc::open(ptmx.as_ptr(), flags);
        assert!(fd >= 0, "open /dev/ptmx: {}", std::io::Error::last_os_error());
        let master = OwnedFd::from_raw_fd(fd);
        assert_eq!(libc::grantpt(fd), 0, "grantpt");
        assert_eq!(libc::unlockpt(fd), 0, "unlockpt");
        let mut name = [0 as libc::c_char; 128];
        assert_eq!(libc::ptsname_r(fd, name.as_mut_ptr(), name.len()), 0, "ptsname_r");
        let path = CStr::from_ptr(name.as_ptr()).to_owned();
        let slave = libc::open(path.as_ptr(), libc::O_RDWR | libc::O_NOCTTY | libc::O_CLOEXEC);
        assert!(slave >= 0, "open {path:?}: {}", std::io::Error::last_os_error());
        let slave = OwnedFd::from_raw_fd(slave);
        let mut termios = std::mem::zeroed::<libc::termios>();
        assert_eq!(libc::tcgetattr(slave.as_raw_fd(), &mut termios), 0, "tcgetattr");
        libc::cfmakeraw(&mut termios);
        assert_eq!(libc::tcsetattr(slave.as_raw_fd(), libc::TCSANOW, &termios), 0, "tcsetattr");
        drop(slave);
        (master, path.into_string().unwrap())
    }
}
