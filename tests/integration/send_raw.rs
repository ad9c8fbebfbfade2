//! `tracerctl send-raw` through the in-process simulator and a real pseudo-terminal.

use std::io::Read;
use std::process::{Command, Output, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serialport::SerialPort;
use tracerctl::protocol::serial::{SerialFrame, StreamDecoder, StreamEvent};

use super::monitor::{signal, wait_with_timeout};
use super::util::{stderr, stdout, tracerctl};

fn send_raw(args: &[&str]) -> Output {
    tracerctl().args(args).output().unwrap()
}

#[test]
fn frames_are_explained_then_sent() {
    let output = send_raw(&["--sim", "send-raw", "--force", "421#01", "121#01031E0000000005"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let errors = stdout(&output);
    assert!(errors.contains("421#01 = 0x421 control_mode_command control_mode=can\n"), "{errors}");
    assert!(errors.contains("121#01031E0000000005 = 0x121 light_command"), "{errors}");
    assert!(errors.contains("sent 2 frames on sim"), "{errors}");
    assert!(!errors.contains("zero-velocity"), "nothing moved: {errors}");

    let output = send_raw(&["--sim", "send-raw", "--repeat", "3", "--period", "10", "123#DEADBEEF"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(stdout(&output).contains("123#DEADBEEF = 0x123 raw len=4 data=DEADBEEF"), "{}", stdout(&output));
    assert!(stdout(&output).contains("sent 3 frames on sim"), "{}", stdout(&output));
}

#[test]
fn motion_frames_need_force() {
    for frame in ["111#0096000000000000", "421#01", "130#01000A0000000044"] {
        let output = send_raw(&["--sim", "send-raw", "123#00", frame]);
        assert_eq!(output.status.code(), Some(2), "{frame}: {}", stderr(&output));
        let errors = stderr(&output);
        assert!(errors.contains("refusing to send frames that can move the robot"), "{errors}");
        assert!(errors.contains(&format!("{frame} (0x{}", &frame[..3])), "{errors}");
        assert!(errors.contains("add --force; nothing was sent"), "{errors}");
    }
    let output = send_raw(&["--sim", "send-raw", "--force", "111#0096000000000000"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(stdout(&output).contains("0x111 motion_command linear_velocity=0.15m/s"), "{}", stdout(&output));
    assert!(stdout(&output).contains("then 3 zero-velocity frames to stop the robot"), "{}", stdout(&output));
}

#[test]
fn cansend_sloppiness_is_an_error_and_nothing_is_sent() {
    let cases = [
        ("123#112233445566778899", "column 21: more than 8 data bytes"),
        ("123#1122334455667788zz", "column 21: unexpected text after the frame"),
        ("123#R9", "column 6: remote request length must be a single digit 0-8"),
        ("12#00", "column 1: identifier must have 3 or 8 hex digits"),
        ("123#112", "odd number of hex digits"),
    ];
    for (frame, reason) in cases {
        let output = send_raw(&["--sim", "send-raw", "--force", "421#01", frame]);
        assert_eq!(output.status.code(), Some(2), "{frame}");
        let errors = stderr(&output);
        assert!(errors.contains(&format!("frame 2 '{frame}': ")), "{errors}");
        assert!(errors.contains(reason), "{frame}: {errors}");
        assert!(errors.contains("nothing was sent") && !errors.contains("on sim"), "{errors}");
    }
    let output = send_raw(&[
        "--replay",
        super::util::data("tracer_session.log").to_str().unwrap(),
        "send-raw",
        "123#00",
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--replay is read-only"), "{}", stderr(&output));
    let output = send_raw(&["--sim", "send-raw", "--fix-checksum", "123#00"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--fix-checksum is for RS232 frames"), "{}", stderr(&output));
}

/// The robot's side of a pseudo-terminal: records every frame the host writes, with its arrival time.
pub struct PtyRobot {
    pub path: String,
    frames: Arc<Mutex<Vec<(Instant, SerialFrame)>>>,
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

#[test]
fn rs232_hex_with_a_computed_checksum_reaches_the_port_byte_for_byte() {
    let robot = PtyRobot::start();
    let output =
        send_raw(&["--serial", &robot.path, "send-raw", "--fix-checksum", "5AA50A550200032800000000"]);
    let (_, bytes) = robot.finish();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(bytes, [0x5A, 0xA5, 0x0A, 0x55, 0x02, 0x00, 0x03, 0x28, 0x00, 0x00, 0x00, 0x00, 0x8B]);
    let errors = stdout(&output);
    assert!(errors.contains("5A A5 0A 55 02 00 03 28 00 00 00 00 8B = 0x5502 light_command"), "{errors}");

    // Without --fix-checksum the checksum must be right; a wrong one is refused before anything is sent.
    let robot = PtyRobot::start();
    let output = send_raw(&["--serial", &robot.path, "send-raw", "5A A5 0A 55 02 00 03 28 00 00 00 00 8C"]);
    let (_, bytes) = robot.finish();
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("byte 13: checksum mismatch: computed 0x8B, frame carries 0x8C"),
        "{}",
        stderr(&output)
    );
    assert!(bytes.is_empty());

    // RS232 motion control needs --force too.
    let output =
        send_raw(&["--serial", "/dev/null", "send-raw", "--fix-checksum", "5AA50A550102000A00000000"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("0x5501 motion_command"), "{}", stderr(&output));
}

#[test]
fn sigint_during_repeats_stops_the_robot_at_once() {
    let robot = PtyRobot::start();
    let child = repeat_motion(&robot, 50);
    // 300 ms after the first frame arrives.
    let deadline = Instant::now() + Duration::from_secs(5);
    let first = loop {
        if let Some((at, _)) = robot.frames.lock().unwrap().first() {
            break *at;
        }
        assert!(Instant::now() < deadline, "no frame arrived");
        std::thread::sleep(Duration::from_millis(1));
    };
    std::thread::sleep((first + Duration::from_millis(300)).saturating_duration_since(Instant::now()));
    let signalled = Instant::now();
    signal(child.id(), libc::SIGINT);
    let output = wait_with_timeout(child, Duration::from_secs(5));
    let (frames, _) = robot.finish();
    assert_eq!(output.status.code(), Some(130), "{}", stderr(&output));
    let percent = |frame: &SerialFrame| (frame.command, frame.payload[2] as i8, frame.payload[3] as i8);
    let moving: Vec<&(Instant, SerialFrame)> =
        frames.iter().take_while(|(_, frame)| percent(frame) == (1, 10, 0)).collect();
    assert!((13..=18).contains(&moving.len()), "{} motion frames before the signal", moving.len());
    // A fixed 20 ms schedule.
    let last_moving = moving.last().unwrap().0;
    let mean = last_moving.duration_since(first).as_secs_f64() * 1000.0 / (moving.len() - 1) as f64;
    assert!((18.0..=22.0).contains(&mean), "mean period {mean:.1} ms");
    let tail = &frames[moving.len()..];
    assert_eq!(tail.len(), 3, "then only the zero-velocity frames: {tail:?}");
    assert!(tail.iter().all(|(_, frame)| percent(frame) == (1, 0, 0)), "{tail:?}");
    let late = tail[0].0.saturating_duration_since(signalled);
    assert!(late < Duration::from_millis(50), "zeros {late:?} after the signal");
    let errors = stderr(&output);
    assert!(errors.contains("stopped by SIGINT after"), "{errors}");
    assert!(stdout(&output).contains("then 3 zero-velocity frames"), "{}", stdout(&output));
}

/// `send-raw --force --repeat N --period 20` of a 10 % RS232 motion frame to `robot`.
fn repeat_motion(robot: &PtyRobot, repeat: u32) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_tracerctl"))
        .args([
            "--serial",
            &robot.path,
            "send-raw",
            "--force",
            "--fix-checksum",
            "--period",
            "20",
            "--repeat",
        ])
        .arg(repeat.to_string())
        .arg("5AA50A550102000A00000000")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Ctrl-Z (SIGTSTP) during repeats of a motion frame: zero-velocity frames first, and after SIGCONT the
/// repeats do not carry on (a suspension never resumes motion).
#[test]
fn sigtstp_during_repeats_sends_zeros_and_never_resumes() {
    let robot = PtyRobot::start();
    let child = repeat_motion(&robot, 100);
    let deadline = Instant::now() + Duration::from_secs(5);
    while robot.frames.lock().unwrap().len() < 10 {
        assert!(Instant::now() < deadline, "no frames arrived");
        std::thread::sleep(Duration::from_millis(1));
    }
    let signalled = Instant::now();
    signal(child.id(), libc::SIGTSTP);
    std::thread::sleep(Duration::from_millis(500));
    signal(child.id(), libc::SIGCONT);
    let output = wait_with_timeout(child, Duration::from_secs(5));
    let (frames, _) = robot.finish();
    let percent = |frame: &SerialFrame| (frame.command, frame.payload[2] as i8, frame.payload[3] as i8);
    let after: Vec<(Duration, (u8, i8, i8))> = frames
        .iter()
        .filter(|(at, _)| *at >= signalled)
        .map(|(at, frame)| (at.duration_since(signalled), percent(frame)))
        .collect();
    let first_zero = after.iter().position(|(_, p)| *p == (1, 0, 0)).expect("zeros after SIGTSTP");
    assert!(after[first_zero].0 < Duration::from_millis(50), "zeros {:?} after SIGTSTP", after[first_zero].0);
    assert!(after[first_zero..].iter().all(|(_, p)| *p == (1, 0, 0)), "nothing moves after: {after:?}");
    assert!(frames.len() < 60, "the 100 repeats did not carry on after SIGCONT: {} frames", frames.len());
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stderr(&output).contains("suspended (SIGTSTP)"), "{}", stderr(&output));
}
