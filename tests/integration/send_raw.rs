//! `tracerctl send-raw` through the in-process simulator and a real pseudo-terminal.

use std::process::Output;

use super::util::{stderr, stdout, tracerctl};
pub(crate) use crate::pty_robot::PtyRobot;

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
