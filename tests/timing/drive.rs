//! `tracerctl drive` over a real pseudo-terminal: how soon the zero-velocity frames reach the robot.

use std::process::Stdio;
use std::time::{Duration, Instant};

use crate::serial_peer::{healthy, percent, FakeRobot};
use crate::util::stderr;

#[test]
fn stops_when_the_robot_falls_silent() {
    let robot = FakeRobot::start(healthy());
    let driver = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["--serial", &robot.path, "drive", "--linear", "0.3", "--for", "20s"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1200));
    let silent_at = Instant::now();
    robot.go_silent();
    let output = driver.wait_with_output().unwrap();
    let report = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{report}");
    assert!(report.contains("no frames from the robot for 1 s"), "{report}");
    std::thread::sleep(Duration::from_millis(30));
    let frames = robot.frames();
    let last = frames.iter().rev().find_map(|(_, f)| percent(f));
    assert_eq!(last, Some((0, 0)), "ends with zeros");
    let stopped = frames.iter().find(|(at, f)| *at > silent_at && percent(f) == Some((0, 0))).unwrap().0;
    let after = stopped.duration_since(silent_at);
    assert!(after < Duration::from_millis(1300), "stopped {after:?} after the feedback stopped");
}

/// The zero-velocity frame must reach the robot within 50 ms of the signal.
#[cfg(unix)]
#[test]
fn every_termination_signal_stops_the_robot_within_50_ms() {
    for (signal, status) in [(libc::SIGINT, 130), (libc::SIGTERM, 143), (libc::SIGHUP, 129)] {
        let robot = FakeRobot::start(healthy());
        let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .args(["--serial", &robot.path, "drive", "--linear", "0.3"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until it drives at full speed.
        let deadline = Instant::now() + Duration::from_secs(5);
        while !robot.frames().iter().any(|(_, f)| percent(f) == Some((20, 0))) {
            assert!(Instant::now() < deadline, "never reached 20 %");
            std::thread::sleep(Duration::from_millis(10));
        }
        let sent = Instant::now();
        // SAFETY: kill(2) on our own child, not yet waited for (its pid is still ours).
        unsafe { libc::kill(child.id() as i32, signal) };
        let exit = child.wait().unwrap();
        std::thread::sleep(Duration::from_millis(30));
        assert_eq!(exit.code(), Some(status), "exit status after signal {signal}");
        let frames = robot.frames();
        let first_zero = frames
            .iter()
            .find(|(at, f)| *at >= sent && percent(f) == Some((0, 0)))
            .map(|(at, _)| at.duration_since(sent))
            .expect("a zero-velocity frame after the signal");
        assert!(first_zero < Duration::from_millis(50), "signal {signal}: zero after {first_zero:?}");
        let last = frames.iter().rev().find_map(|(_, f)| percent(f));
        assert_eq!(last, Some((0, 0)), "signal {signal}: nothing moves after the stop");
    }
}
