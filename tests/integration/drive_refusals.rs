//! When `drive` must not drive, or must stop by itself (issue 28): no speed given, no feedback at all, and
//! the robot reporting the vehicle state "exception". What reached the wire is the witness.

use tracerctl::protocol::serial::SerialFrame;

use crate::serial_peer::{healthy, FakeRobot};
use crate::util::{json_lines, stderr, tracerctl};

/// (linear %, angular %) of an RS232 motion control frame, or None for other frames.
fn percent(frame: &SerialFrame) -> Option<(i8, i8)> {
    (frame.frame_type == 0x55 && frame.command == 0x01)
        .then(|| (frame.payload[2] as i8, frame.payload[3] as i8))
}

#[test]
fn drive_without_a_speed_is_a_usage_error_and_sends_nothing() {
    let robot = FakeRobot::start(healthy());
    let output = tracerctl().args(["--serial", &robot.path, "drive", "--for", "1s"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    let error = stderr(&output);
    assert!(error.contains("drive needs a speed: give --linear M/S and/or --angular RAD/S"), "{error}");
    assert_eq!(robot.frames().len(), 0, "nothing is sent: command mode is not taken from ROS");

    // An explicit zero still holds the robot at zero (and takes serial mode to do it).
    let output = tracerctl()
        .args(["--serial", &robot.path, "drive", "--linear", "0", "--for", "300ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let speeds: Vec<(i8, i8)> = robot.frames().iter().filter_map(|(_, frame)| percent(frame)).collect();
    assert!(speeds.len() >= 5, "zero commands at 50 Hz: {speeds:?}");
    assert!(speeds.iter().all(|speed| *speed == (0, 0)), "{speeds:?}");
}

#[test]
fn no_feedback_at_all_is_exit_4_even_with_ignore_faults_and_sends_nothing() {
    for extra in [&["--ignore-faults"][..], &[]] {
        let robot = FakeRobot::start_silent();
        let output = tracerctl()
            .args(["--serial", &robot.path, "drive", "--linear", "0.2", "--for", "1s"])
            .args(extra)
            .output()
            .unwrap();
        let error = stderr(&output);
        assert_eq!(output.status.code(), Some(4), "{extra:?}: {error}");
        assert!(error.contains("not driving: nothing received on"), "{extra:?}: {error}");
        assert!(!error.contains("--ignore-faults"), "no hint to override what was never received: {error}");
        assert_eq!(robot.frames().len(), 0, "{extra:?}: nothing is sent blind");
    }
}

#[test]
fn a_vehicle_exception_stops_the_drive_at_once_with_exit_4_and_the_reason() {
    // motor1-comm latches a motor driver's lost link: the robot reports the vehicle state exception and no
    // longer obeys; drive ends on that, not on its later "did not follow" check.
    let output = tracerctl()
        .args(["--sim", "--fault", "motor1-comm@1s", "drive", "--linear", "0.3", "--for", "3s"])
        .args(["--format", "json"])
        .output()
        .unwrap();
    let error = stderr(&output);
    assert_eq!(output.status.code(), Some(4), "{error}");
    assert!(error.contains("the robot reports a system exception"), "{error}");
    let report = json_lines(&output).pop().expect("a report line");
    assert_eq!(report["end"], "exception", "{report}");
    assert_eq!(report["exit_status"], 4, "{report}");
    assert_eq!(report["last_command"]["linear_velocity"], 0.0, "zero at the end: {report}");
}
