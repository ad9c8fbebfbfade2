//! `tracerctl drive` against the in-process simulator and, byte for byte, over a real pseudo-terminal.

use std::time::{Duration, Instant};

use tracerctl::protocol::message::{SystemState, VEHICLE_ESTOP};

use crate::serial_peer::{healthy, percent, FakeRobot};
use crate::util::{stderr, stdout, tracerctl};

#[test]
fn drives_the_simulator_and_stops_when_time_is_up() {
    let output = tracerctl().args(["--sim", "drive", "--linear", "0.3", "--for", "2s"]).output().unwrap();
    let report = stdout(&output);
    assert_eq!(output.status.code(), Some(0), "{report}{}", stderr(&output));
    assert!(report.contains("robot: normal, mode standby"), "the simulator boots in standby: {report}");
    // One status line a second when stdout is not a terminal; by the second, the robot moves at 0.3 m/s.
    let moving = report.lines().filter(|l| l.contains("measured +0.3") || l.contains("measured +0.29"));
    assert!(moving.count() >= 1, "{report}");
    assert!(report.contains("(time up)"), "{report}");
    assert!(report.contains("last command +0.000 m/s +0.000 rad/s"), "{report}");
}

#[test]
fn caps_are_applied_and_said() {
    let output = tracerctl().args(["--sim", "drive", "--linear", "-3", "--for", "200ms"]).output().unwrap();
    assert!(stderr(&output).contains("capped: -3.000 m/s +0.000 rad/s -> -0.500 m/s"), "{}", stderr(&output));
}

#[test]
fn serial_frames_byte_for_byte_on_a_real_pseudo_terminal() {
    let robot = FakeRobot::start(healthy());
    let output = tracerctl()
        .args(["--serial", &robot.path, "drive", "--linear", "0.3", "--angular", "-0.2", "--for", "1500ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    std::thread::sleep(Duration::from_millis(50));
    let frames = robot.frames();
    assert!(frames.len() >= 60, "about 50 frames a second for 1.5 s, got {}", frames.len());
    for (_, frame) in &frames {
        let bytes = frame.to_bytes();
        // 5A A5 0A 55 01, mode 02 (serial), no fault clear, reserved bytes zero, checksum = sum of 0..12.
        assert_eq!(&bytes[..5], &[0x5A, 0xA5, 0x0A, 0x55, 0x01]);
        assert_eq!((bytes[5], bytes[6], bytes[9], bytes[10]), (0x02, 0x00, 0x00, 0x00));
        let sum = bytes[..12].iter().fold(0u8, |sum, b| sum.wrapping_add(*b));
        assert_eq!(bytes[12], sum);
    }
    // Frame ids roll by one.
    for pair in frames.windows(2) {
        assert_eq!(pair[1].1.frame_id, pair[0].1.frame_id.wrapping_add(1));
    }
    // Ramped up to 0.3 m/s = 20 % and -0.2 rad/s = -25 % (of 0.7853), then down to zero at the end.
    let timed: Vec<(Instant, (i8, i8))> =
        frames.iter().filter_map(|(at, f)| Some((*at, percent(f)?))).collect();
    let speeds: Vec<(i8, i8)> = timed.iter().map(|(_, speed)| *speed).collect();
    assert!(speeds.contains(&(20, -25)), "{speeds:?}");
    // Ramped at 0.5 m/s² up (33 % of full scale per second) and braked at 1.5 m/s² (100 %/s): a step never
    // exceeds what the time between the frames allows (plus one percent of rounding), even when a loaded
    // machine delays a tick.
    for pair in timed.windows(2) {
        let dt = pair[1].0.duration_since(pair[0].0).as_secs_f64().max(0.02);
        let braking = pair[1].1 .0.abs() < pair[0].1 .0.abs();
        let rate = if braking { 1.5 } else { 0.5 };
        let allowed = rate / 1.5 * 100.0 * dt + 1.0;
        let step = f64::from((pair[1].1 .0 - pair[0].1 .0).abs());
        assert!(step <= allowed, "a jump of {step} % in {dt} s: {speeds:?}");
    }
    assert_eq!(&speeds[speeds.len() - 3..], &[(0, 0); 3]);
}

#[test]
fn refuses_to_start_on_estop_or_silence_and_says_why() {
    let robot = FakeRobot::start(SystemState { vehicle_state: VEHICLE_ESTOP, ..healthy() });
    let output = tracerctl()
        .args(["--serial", &robot.path, "drive", "--linear", "0.2", "--for", "1s"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(4));
    assert!(stderr(&output).contains("not driving: the E-stop is pressed"), "{}", stderr(&output));
    assert!(robot.frames().iter().all(|(_, f)| percent(f).is_none_or(|p| p == (0, 0))), "nothing that moves");

    let silent = FakeRobot::start(healthy());
    // A second pseudo-terminal nobody answers on: open it, but talk to nobody.
    let (_master, slave) = serialport::TTYPort::pair().unwrap();
    let path = serialport::SerialPort::name(&slave).unwrap();
    drop(slave);
    let output =
        tracerctl().args(["--serial", &path, "drive", "--linear", "0.2", "--for", "1s"]).output().unwrap();
    assert_eq!(output.status.code(), Some(4));
    assert!(stderr(&output).contains("nothing received on"), "{}", stderr(&output));
    drop(silent);
}
