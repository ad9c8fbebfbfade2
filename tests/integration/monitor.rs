//! `tracerctl monitor` against the in-process simulator, candump replays and a real pseudo-terminal.

use std::io::{BufRead, BufReader, Write};
use std::os::fd::AsRawFd;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
use serialport::SerialPort;
use tracerctl::protocol::message::{Message, MotionState, SystemState};
use tracerctl::protocol::serial::SerialEncoder;

use super::util::{data, json_lines, stderr, stdout, tracerctl};
pub use super::util::{signal, wait_with_timeout};

fn monitor(args: &[&str]) -> Output {
    tracerctl().args(args).output().unwrap()
}

/// The summary row of `id` on stderr: (msg, frames, rate).
fn summary_row(output: &Output, id: &str) -> Option<(String, u64, Option<f64>)> {
    let text = stderr(output);
    let line = text.lines().find(|line| line.split_whitespace().next() == Some(id))?;
    let fields: Vec<&str> = line.split_whitespace().collect();
    Some((fields[1].to_string(), fields[2].parse().unwrap(), fields[3].parse().ok()))
}

/// The `total:` line's numbers: frames, error frames, socket drops, checksum errors, skipped bytes.
fn totals(output: &Output) -> Vec<u64> {
    let text = stderr(output);
    let line = text.lines().find(|line| line.trim_start().starts_with("total:")).expect("a total line");
    line.split(|c: char| !c.is_ascii_digit()).filter(|s| !s.is_empty()).map(|s| s.parse().unwrap()).collect()
}

fn with_msg<'a>(lines: &'a [Value], msg: &str) -> Vec<&'a Value> {
    lines.iter().filter(|line| line["msg"] == msg).collect()
}

#[test]
fn sim_json_shows_the_robot_at_fifty_hertz_and_counts_on_exit() {
    let output = monitor(&["--sim", "monitor", "--format", "json", "--duration", "1s"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let lines = json_lines(&output);
    let states = with_msg(&lines, "system_state");
    assert!((35..=60).contains(&states.len()), "{} system_state frames in 1 s", states.len());
    for state in &states {
        let volts = state["fields"]["battery_voltage"].as_f64().unwrap();
        assert!((volts - 26.0).abs() < 0.5, "battery {volts} V");
        assert_eq!((state["iface"].as_str(), state["id"].as_str()), (Some("sim"), Some("0x211")));
        assert_eq!(state["wire"], "can-v2");
    }
    assert!(with_msg(&lines, "motion_state").len() >= 35);
    assert!(with_msg(&lines, "odometry").len() >= 35);
    // Receive timestamps, in order, spanning about the second.
    let stamps: Vec<f64> = lines.iter().map(|line| line["ts"].as_f64().unwrap()).collect();
    assert!(stamps.windows(2).all(|pair| pair[0] <= pair[1]));
    let span = stamps.last().unwrap() - stamps[0];
    assert!((0.7..=1.1).contains(&span), "span {span}");
    // Per-identifier counts on stderr match what was printed, at about 50 per second.
    let (msg, frames, rate) = summary_row(&output, "0x211").expect("0x211 counted");
    assert_eq!((msg.as_str(), frames), ("system_state", states.len() as u64));
    let rate = rate.unwrap();
    assert!((45.0..=55.0).contains(&rate), "rate {rate}");
    assert_eq!(summary_row(&output, "0x261").unwrap().0, "motor_low_speed");
    assert_eq!(totals(&output)[0], lines.len() as u64, "total frames = lines printed");
    assert!(stdout(&output).lines().all(|line| !line.contains("warning")), "warnings go to stderr");
}

#[test]
fn raw_lines_are_candump_log_lines_that_decode_reads_back() {
    let output = monitor(&["--sim", "monitor", "--raw", "--duration", "500ms"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() > 100, "{} lines", lines.len());
    for line in &lines {
        let (stamp, rest) = line.split_once(") ").unwrap();
        let (secs, micros) = stamp.trim_start_matches('(').split_once('.').unwrap();
        assert!(secs.len() == 10 && micros.len() == 6, "{line}");
        let (iface, frame) = rest.split_once(' ').unwrap();
        assert_eq!(iface, "sim");
        assert!(frame.len() == 20 && frame.as_bytes()[3] == b'#', "{line}");
    }
    let decode =
        tracerctl().args(["decode", "--format", "json", "-"]).write_stdin(text.clone()).output().unwrap();
    assert!(decode.status.success(), "{}", stderr(&decode));
    let decoded = json_lines(&decode);
    assert_eq!(decoded.len(), lines.len());
    for (line, json) in lines.iter().zip(&decoded) {
        let frame = line.rsplit(' ').next().unwrap();
        let id = format!("0x{}", &frame[..3]);
        assert_eq!((json["id"].as_str(), json["data"].as_str()), (Some(id.as_str()), Some(&frame[4..])));
    }
    assert!(with_msg(&decoded, "system_state").len() > 15);
}

#[test]
fn the_log_file_holds_every_frame_printed_and_decode_reads_it() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("bus.log");
    let log_arg = log.to_str().unwrap();
    let output = monitor(&["--sim", "monitor", "--format", "json", "--duration", "1s", "--log", log_arg]);
    assert!(output.status.success(), "{}", stderr(&output));
    let printed = json_lines(&output);
    let output_decode = tracerctl().args(["decode", "--format", "json", log_arg]).output().unwrap();
    assert!(output_decode.status.success(), "{}", stderr(&output_decode));
    let logged = json_lines(&output_decode);
    assert!(printed.len() > 200);
    assert_eq!(logged.len(), printed.len(), "same frame count");
    for (a, b) in printed.iter().zip(&logged) {
        assert_eq!((&a["id"], &a["data"], &a["msg"]), (&b["id"], &b["data"], &b["msg"]));
        // The log keeps microseconds, as candump -L does.
        let (ta, tb) = (a["ts"].as_f64().unwrap(), b["ts"].as_f64().unwrap());
        assert!((ta - tb).abs() < 2e-6, "{ta} {tb}");
    }

    let bad = monitor(&["--sim", "monitor", "--duration", "100ms", "--log", "/nonexistent-dir/bus.log"]);
    assert_eq!(bad.status.code(), Some(1));
    assert!(stderr(&bad).contains("cannot create the log file /nonexistent-dir/bus.log"), "{}", stderr(&bad));
}

#[test]
fn filters_choose_what_is_shown_but_everything_is_counted_and_logged() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("all.log");
    let output = monitor(&[
        "--sim",
        "monitor",
        "--format",
        "json",
        "--duration",
        "500ms",
        "--id",
        "0x211",
        "--log",
        log.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", stderr(&output));
    let lines = json_lines(&output);
    assert!(lines.len() >= 15, "{}", lines.len());
    assert!(lines.iter().all(|line| line["id"] == "0x211"));
    assert!(summary_row(&output, "0x221").unwrap().1 >= 15, "0x221 still counted");
    let logged = std::fs::read_to_string(&log).unwrap();
    assert!(logged.lines().any(|line| line.contains(" sim 221#")), "the log is unfiltered");

    let output =
        monitor(&["--sim", "monitor", "--format", "csv", "--duration", "300ms", "--msg", "odometry"]);
    let text = stdout(&output);
    let mut rows = text.lines();
    assert!(rows.next().unwrap().starts_with("ts,"), "CSV header first");
    let rows: Vec<&str> = rows.collect();
    assert!(rows.len() >= 8 && rows.iter().all(|row| row.contains(",0x311,")), "{text}");
}

#[test]
fn a_replay_is_printed_whole_and_ends_with_status_0() {
    let log = data("tracer_session.log");
    let output = monitor(&["--replay", log.to_str().unwrap(), "--speed", "0", "monitor", "--format", "json"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let lines = json_lines(&output);
    let ids: Vec<&str> = lines.iter().map(|line| line["id"].as_str().unwrap()).collect();
    assert_eq!(
        ids,
        [
            "0x211", "0x421", "0x211", "0x111", "0x221", "0x211", "0x311", "0x311", "0x211", "0x211",
            "0x262", "0x251", "0x221", "0x311", "0x211"
        ]
    );
    assert_eq!(lines[0]["ts"].as_f64(), Some(1_700_000_000.0));
    assert_eq!(lines[0]["iface"], "replay");
    assert!(stderr(&output).contains("(end of the source): 15 frames, 15 shown"), "{}", stderr(&output));
    assert_eq!(summary_row(&output, "0x211").unwrap().1, 6);
}

#[test]
fn a_gap_in_a_periodic_frame_is_warned_about_and_its_return_noted() {
    let log = data("monitor_gap.log");
    let output = monitor(&["--replay", log.to_str().unwrap(), "--speed", "1", "monitor"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let errors = stderr(&output);
    let stale: Vec<&str> = errors.lines().filter(|line| line.contains("warning: no ")).collect();
    let expected = format!(
        "tracerctl: warning: no 0x211 system_state on {} for 100 ms (expected every 20 ms)",
        log.display()
    );
    assert_eq!(stale, [expected.as_str()]);
    assert!(errors.contains("tracerctl: 0x211 system_state resumed after a gap of 300 ms"), "{errors}");
    assert!(!errors.contains("silent"), "{errors}");
    assert_eq!(stdout(&output).lines().count(), 58, "warnings are not on stdout");
}

#[test]
fn a_closed_pipe_ends_quietly_and_a_signal_with_128_plus_its_number() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_tracerctl"))
        .args(["--sim", "monitor"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut reader = BufReader::new(child.stdout.take().unwrap());
    let mut first = String::new();
    reader.read_line(&mut first).unwrap();
    assert!(first.contains(" sim 0x2"), "{first}");
    drop(reader);
    let output = wait_with_timeout(child, Duration::from_secs(5));
    assert_eq!(output.status.code(), Some(0));
    assert_eq!(stderr(&output), "", "quietly");

    let child = Command::new(env!("CARGO_BIN_EXE_tracerctl"))
        .args(["--sim", "monitor", "--format", "json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(400));
    signal(child.id(), libc::SIGINT);
    let output = wait_with_timeout(child, Duration::from_secs(5));
    assert_eq!(output.status.code(), Some(130), "{}", stderr(&output));
    assert!(stderr(&output).contains("(SIGINT)"), "{}", stderr(&output));
    let lines = json_lines(&output);
    assert!(lines.len() > 50, "frames up to the signal were written: {}", lines.len());
    assert_eq!(totals(&output)[0], lines.len() as u64);
}

#[test]
fn serial_feedback_is_decoded_after_noise_and_a_corrupted_frame() {
    let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
    let path = slave.name().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_tracerctl"))
        .args(["--serial", &path, "monitor", "--format", "json", "--duration", "1s"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut encoder = SerialEncoder::new();
    let state = |decivolts| {
        Message::SystemState(SystemState {
            control_mode: 2,
            battery_decivolts: decivolts,
            ..Default::default()
        })
    };
    let motion = Message::MotionState(MotionState { linear_mm_s: 150, ..Default::default() });
    let start = Instant::now();
    for tick in 0..40u32 {
        let volts = if tick < 20 { 259 } else { 247 };
        let mut bytes = encoder.encode_next(&state(volts)).unwrap().to_vec();
        bytes.extend_from_slice(&encoder.encode_next(&motion).unwrap());
        if tick == 20 {
            // Noise, then a system status whose checksum is wrong, before the good frames.
            let mut corrupted = encoder.encode_next(&state(100)).unwrap();
            corrupted[12] = corrupted[12].wrapping_add(1);
            let mut spoiled = vec![0x00, 0x5A, 0x13, 0xFF];
            spoiled.extend_from_slice(&corrupted);
            spoiled.extend_from_slice(&bytes);
            bytes = spoiled;
        }
        master.write_all(&bytes).unwrap();
        let next = start + Duration::from_millis(20 * u64::from(tick + 1));
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    let output = wait_with_timeout(child, Duration::from_secs(5));
    drop(slave);
    assert!(output.status.success(), "{}", stderr(&output));
    let lines = json_lines(&output);
    let states = with_msg(&lines, "system_state");
    let volts: Vec<f64> =
        states.iter().map(|state| state["fields"]["battery_voltage"].as_f64().unwrap()).collect();
    assert_eq!(volts.iter().filter(|&&v| v == 25.9).count(), 20, "{volts:?}");
    assert_eq!(volts.iter().filter(|&&v| v == 24.7).count(), 20, "every frame after the noise: {volts:?}");
    assert!(!volts.contains(&10.0), "the corrupted frame is dropped");
    assert!(states
        .iter()
        .all(|state| state["id"] == "0xAA01" && state["wire"] == "serial" && state["iface"] == path));
    let motions = with_msg(&lines, "motion_state");
    assert_eq!(motions.len(), 40);
    assert_eq!(motions[0]["fields"]["linear_velocity"], 0.15);
    let totals = totals(&output);
    assert_eq!(totals[0], 80, "frames");
    assert_eq!(totals[3], 1, "one serial checksum error");
    assert!(totals[4] >= 4, "skipped bytes: {totals:?}");
    assert_eq!(summary_row(&output, "0xAA01").unwrap().1, 40);
}

#[test]
fn a_lost_link_ends_with_status_1_and_the_counts() {
    let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
    // The child must not inherit the terminal, or it would never see it close. (Children of tests running
    // at the same time may still inherit it, for as long as they live: hence the generous time limit.)
    for fd in [master.as_raw_fd(), slave.as_raw_fd()] {
        // SAFETY: fcntl on descriptors we own.
        assert_eq!(unsafe { libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC) }, 0);
    }
    let path = slave.name().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_tracerctl"))
        .args(["--serial", &path, "monitor", "--format", "json", "--duration", "20s"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let state = Message::SystemState(SystemState { battery_decivolts: 259, ..Default::default() });
    master.write_all(&SerialEncoder::new().encode_next(&state).unwrap()).unwrap();
    std::thread::sleep(Duration::from_millis(300));
    // The adapter goes away: both ends of the terminal close.
    drop(slave);
    drop(master);
    let started = Instant::now();
    let output = wait_with_timeout(child, Duration::from_secs(15));
    assert!(started.elapsed() < Duration::from_secs(10), "ends with the link, not at --duration");
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    let errors = stderr(&output);
    assert!(errors.contains(&format!("tracerctl: the link {path} failed: ")), "{errors}");
    assert_eq!(json_lines(&output).len(), 1);
    assert_eq!(summary_row(&output, "0xAA01").unwrap().1, 1);
}
