//! `send-raw --repeat` over a real pseudo-terminal: how soon SIGINT and SIGTSTP put zeros on the wire.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use tracerctl::protocol::serial::SerialFrame;

use crate::pty_robot::PtyRobot;
use crate::util::{signal, stderr, stdout, wait_with_timeout};

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
