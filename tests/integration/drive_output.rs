//! Where `drive` and `send-raw` write: the status and results on stdout (a line fitted to the terminal, full
//! lines in a pipe, or JSON), diagnostics on stderr; a closed stdout never panics and the robot still ends
//! stopped; frames the robot would reject need `--force`.

use std::io::{BufRead, BufReader, Read};
use std::os::fd::{AsRawFd, BorrowedFd};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
use tracerctl::protocol::serial::SerialFrame;

use crate::send_raw::PtyRobot;
use crate::serial_peer::{healthy, FakeRobot};
use crate::util::{json_lines, stderr, stdout, tracerctl};

/// (linear %, angular %) of an RS232 motion control frame, or None for other frames.
fn percent(frame: &SerialFrame) -> Option<(i8, i8)> {
    (frame.frame_type == 0x55 && frame.command == 0x01)
        .then(|| (frame.payload[2] as i8, frame.payload[3] as i8))
}

fn binary() -> Command {
    let mut command = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"));
    command.env_remove("NO_COLOR").env_remove("TRACERCTL_IFACE").stdin(Stdio::null());
    command
}

/// What a terminal shows of `output`: every run of characters between line ends and carriage returns, with
/// the escape sequences (`ESC [ ... letter`) taken out.
fn screen_segments(output: &str) -> Vec<String> {
    let mut plain = String::new();
    let mut chars = output.chars().peekable();
    while let Some(ch) = chars.next() {
        if ch == '\x1b' && chars.peek() == Some(&'[') {
            for next in chars.by_ref() {
                if next.is_ascii_alphabetic() {
                    break;
                }
            }
        } else {
            plain.push(ch);
        }
    }
    plain.split(['\n', '\r']).map(str::to_string).collect()
}

/// `tracerctl ARGS` with stdout and stderr on a pseudo-terminal of `columns` x 24; everything it showed.
fn on_terminal(columns: u16, args: &[&str]) -> (std::process::ExitStatus, String) {
    let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
    let size = libc::winsize { ws_row: 24, ws_col: columns, ws_xpixel: 0, ws_ypixel: 0 };
    // SAFETY: TIOCSWINSZ reads the winsize given; the descriptor is the open terminal.
    assert_eq!(unsafe { libc::ioctl(slave.as_raw_fd(), libc::TIOCSWINSZ, &size) }, 0, "TIOCSWINSZ");
    // SAFETY: the descriptor stays open (slave lives to the end); the clone is close-on-exec.
    let terminal = unsafe { BorrowedFd::borrow_raw(slave.as_raw_fd()) }.try_clone_to_owned().unwrap();
    let mut child = binary()
        .args(args)
        .stdout(Stdio::from(terminal.try_clone().unwrap()))
        .stderr(Stdio::from(terminal))
        .spawn()
        .unwrap();
    serialport::SerialPort::set_timeout(&mut master, Duration::from_millis(50)).unwrap();
    let mut shown = Vec::new();
    let mut buffer = [0u8; 4096];
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        let read = master.read(&mut buffer).unwrap_or(0);
        shown.extend_from_slice(&buffer[..read]);
        if read == 0 && child.try_wait().unwrap().is_some() {
            break;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            break;
        }
    }
    let status = child.wait().unwrap();
    assert!(Instant::now() <= deadline, "still running: {}", String::from_utf8_lossy(&shown));
    drop(slave);
    (status, String::from_utf8_lossy(&shown).into_owned())
}

#[test]
fn the_status_fits_an_80_column_terminal() {
    let (status, shown) = on_terminal(80, &["--sim", "drive", "--linear", "0.2", "--duration", "2s"]);
    assert_eq!(status.code(), Some(0), "{shown}");
    for segment in screen_segments(&shown) {
        assert!(
            segment.chars().count() <= 80,
            "{} columns: {segment:?}\nin {shown:?}",
            segment.chars().count()
        );
    }
    // Redrawn in place about four times a second, each time with the speeds, faults, battery and mode.
    let redraws: Vec<&str> = shown.split("\r\x1b[K").skip(1).collect();
    assert!(redraws.len() >= 4, "{shown:?}");
    let last = redraws.last().unwrap().lines().next().unwrap();
    assert!(
        last.starts_with("sent +0.20 +0.00 meas +0.20 +0.00  normal, faults: none  25.9 V  mode can"),
        "{last:?}"
    );
    assert!(shown.contains("stopped after"), "{shown:?}");
}

#[test]
fn a_pipe_gets_full_status_lines_on_stdout_and_no_diagnostics() {
    let output =
        tracerctl().args(["--sim", "drive", "--linear", "0.2", "--duration", "2s"]).output().unwrap();
    let (out, errors) = (stdout(&output), stderr(&output));
    assert_eq!(output.status.code(), Some(0), "{errors}");
    assert_eq!(errors, "", "a clean drive says nothing on stderr");
    assert!(!out.contains('\r') && !out.contains('\x1b'), "{out:?}");
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].starts_with("robot: normal, mode standby, 25.9 V, faults: none"), "{out}");
    let statuses: Vec<&&str> =
        lines.iter().filter(|line| line.contains(" s  target +0.200 m/s +0.000 rad/s")).collect();
    assert!((2..=3).contains(&statuses.len()), "one full line a second: {out}");
    assert!(statuses.iter().all(|line| line.contains("normal, faults: none  25.9 V  mode ")), "{out}");
    let end = lines.iter().position(|line| line.starts_with("stopped after") && line.ends_with("(time up)"));
    let end = end.unwrap_or_else(|| panic!("{out}"));
    assert!(lines[end + 1].ends_with("motion frames sent"), "{out}");
    assert_eq!(lines.last(), Some(&"  last command +0.000 m/s +0.000 rad/s"), "{out}");

    // A warning is a diagnostic: stderr.
    let output =
        tracerctl().args(["--sim", "drive", "--linear", "-3", "--duration", "200ms"]).output().unwrap();
    assert!(stderr(&output).contains("capped: -3.000 m/s +0.000 rad/s -> -0.500 m/s"), "{}", stderr(&output));
    assert!(!stdout(&output).contains("capped"), "{}", stdout(&output));
}

fn assert_velocity(value: &Value) {
    assert!(value["linear_velocity"].is_f64() && value["angular_velocity"].is_f64(), "{value}");
}

#[test]
fn json_status_lines_and_the_final_report() {
    let output = tracerctl()
        .args(["--sim", "drive", "--linear", "0.2", "--duration", "1s", "--format", "json"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(stderr(&output), "");
    let records = json_lines(&output);
    let (report, statuses) = records.split_last().unwrap();
    assert!(!statuses.is_empty());
    for status in statuses {
        assert_eq!(status["type"], "status", "{status}");
        assert!(status["elapsed"].as_f64().is_some_and(|t| (0.0..1.5).contains(&t)), "{status}");
        assert_eq!(status["target"]["linear_velocity"], 0.2, "{status}");
        assert_velocity(&status["target"]);
        assert_velocity(&status["sent"]);
        assert!(status["measured"].is_null() || status["measured"]["linear_velocity"].is_f64(), "{status}");
        let robot = &status["robot"];
        assert_eq!(robot["vehicle_state"], "normal", "{status}");
        assert!(["standby", "can"].contains(&robot["control_mode"].as_str().unwrap()), "{status}");
        assert_eq!(robot["battery_voltage"], 25.9, "{status}");
        assert_eq!(robot["faults"], serde_json::json!([]), "{status}");
        assert!(status["send_error"].is_null(), "{status}");
    }
    assert_eq!(report["type"], "report", "{report}");
    assert_eq!(report["end"], "time_up", "{report}");
    assert_eq!(report["signal"], Value::Null, "{report}");
    assert_eq!(report["exit_status"], 0, "{report}");
    assert_eq!(report["stop_confirmed"], true, "{report}");
    assert_eq!(report["last_command"], serde_json::json!({"linear_velocity": 0.0, "angular_velocity": 0.0}));
    assert!(report["elapsed"].as_f64().is_some_and(|t| t >= 1.0), "{report}");
    assert!(report["frames_sent"].as_u64().is_some_and(|n| n >= 40), "{report}");
    for count in ["send_errors", "not_sent", "held_back", "discarded", "watchdog_trips"] {
        assert_eq!(report[count], 0, "{count}: {report}");
    }
    assert!(report["distance"].as_f64().is_some_and(|d| d > 0.05), "{report}");
    assert_eq!(report["peak_linear_velocity"], 0.2, "{report}");
    assert!(report["message"].as_str().unwrap().contains("motion frames sent"), "{report}");
}

/// Drives the RS232 fake robot with stdout on a pipe the test holds.
fn drive_serial(robot: &FakeRobot, args: &[&str]) -> Child {
    binary()
        .args(["--serial", &robot.path, "drive"])
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn finish(mut child: Child) -> (Option<i32>, String) {
    let deadline = Instant::now() + Duration::from_secs(10);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("drive did not end");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let mut errors = String::new();
    child.stderr.take().unwrap().read_to_string(&mut errors).unwrap();
    (child.wait().unwrap().code(), errors)
}

#[test]
#[ignore = "timing group: reaches full speed within 5 s and reads the wire after 50 ms, which a busy machine misses; .ci/run runs it alone"]
fn a_closed_stdout_stops_the_robot_and_never_panics() {
    // Closed once the robot drives at full speed: the next status line cannot be written.
    let robot = FakeRobot::start(healthy());
    let mut child = drive_serial(&robot, &["--linear", "0.3", "--format", "json"]);
    let mut first = String::new();
    BufReader::new(child.stdout.as_mut().unwrap()).read_line(&mut first).unwrap();
    assert!(serde_json::from_str::<Value>(&first).is_ok_and(|v| v["type"] == "status"), "{first}");
    let deadline = Instant::now() + Duration::from_secs(5);
    while !robot.frames().iter().any(|(_, frame)| percent(frame) == Some((20, 0))) {
        assert!(Instant::now() < deadline, "never reached 20 %");
        std::thread::sleep(Duration::from_millis(10));
    }
    drop(child.stdout.take());
    let (code, errors) = finish(child);
    assert_eq!(code, Some(1), "{errors}");
    assert!(errors.contains("the status output went away"), "{errors}");
    assert!(!errors.contains("panicked"), "{errors}");
    std::thread::sleep(Duration::from_millis(50));
    let speeds: Vec<(i8, i8)> = robot.frames().iter().filter_map(|(_, frame)| percent(frame)).collect();
    assert!(speeds.contains(&(20, 0)), "{speeds:?}");
    assert_eq!(&speeds[speeds.len() - 3..], &[(0, 0); 3], "ends with zero-velocity frames");

    // Closed before anything is written (`drive | head -c0`): the same, whenever the close is noticed.
    let robot = FakeRobot::start(healthy());
    let mut child = drive_serial(&robot, &["--linear", "0.3"]);
    drop(child.stdout.take());
    let (code, errors) = finish(child);
    assert_eq!(code, Some(1), "{errors}");
    assert!(errors.contains("the status output went away") && !errors.contains("panicked"), "{errors}");
    std::thread::sleep(Duration::from_millis(50));
    let last = robot.frames().iter().rev().find_map(|(_, frame)| percent(frame));
    assert!(last.is_none_or(|speed| speed == (0, 0)), "nothing moves after: {last:?}");
}

#[test]
fn send_raw_says_what_it_sent_on_stdout() {
    let output = tracerctl().args(["--sim", "send-raw", "--force", "111#0096000000000000"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        "111#0096000000000000 = 0x111 motion_command linear_velocity=0.15m/s angular_velocity=0rad/s\n\
         sent 1 frame on sim\nthen 3 zero-velocity frames to stop the robot\n"
    );
    assert_eq!(stderr(&output), "");

    let output = tracerctl()
        .args(["--sim", "send-raw", "--force", "-f", "json", "111#0096000000000000"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let records = json_lines(&output);
    assert_eq!(records.len(), 2, "{records:?}");
    assert_eq!(records[0]["type"], "frame");
    assert_eq!(records[0]["text"], "111#0096000000000000");
    assert_eq!(records[0]["needs_force"], true);
    assert_eq!(records[0]["decoded"]["msg"], "motion_command");
    assert_eq!(records[0]["decoded"]["fields"]["linear_velocity"], 0.15);
    assert_eq!(
        records[1],
        serde_json::json!({"type": "result", "link": "sim", "frames": 1, "sent": 1, "not_sent": 0,
            "stop_frames": 3, "stopped_by": null, "error": null})
    );
}

#[test]
fn send_raw_still_sends_and_stops_with_stdout_closed() {
    let robot = PtyRobot::start();
    let mut child = binary()
        .args(["--serial", &robot.path, "send-raw", "--force", "--fix-checksum", "--repeat", "10"])
        .arg("5AA50A550102000A00000000")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let (code, errors) = finish(child);
    let (frames, _) = robot.finish();
    assert_eq!(code, Some(0), "a closed stdout is no failure to send: {errors}");
    assert!(!errors.contains("panicked"), "{errors}");
    let speeds: Vec<(i8, i8)> = frames.iter().filter_map(|(_, frame)| percent(frame)).collect();
    // The stop discards what the port has not sent yet (the last repeat, at times), then the zeros go.
    let (moving, zeros) = speeds.split_at(speeds.len() - 3);
    assert_eq!(zeros, [(0, 0); 3], "ends with the zero-velocity frames: {speeds:?}");
    assert!((9..=10).contains(&moving.len()) && moving.iter().all(|s| *s == (10, 0)), "{speeds:?}");
}

#[test]
fn frames_the_robot_would_reject_need_force() {
    // A light command one byte short: decode calls it invalid, the robot would drop it.
    let output = tracerctl().args(["--sim", "send-raw", "121#01031E00000000"]).output().unwrap();
    let errors = stderr(&output);
    assert_eq!(output.status.code(), Some(2), "{errors}");
    assert!(
        errors.contains("refusing to send frames the robot would reject: 121#01031E00000000"),
        "{errors}"
    );
    assert!(errors.contains("needs at least 8 data bytes, frame has 7"), "{errors}");
    assert!(
        errors.contains("add --force to send it anyway") && errors.ends_with("nothing was sent\n"),
        "{errors}"
    );
    assert_eq!(stdout(&output), "");

    let output = tracerctl().args(["--sim", "send-raw", "--force", "121#01031E00000000"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(stdout(&output).ends_with("sent 1 frame on sim\n"), "{}", stdout(&output));
}
