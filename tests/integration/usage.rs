//! Usage errors and messages that tell the truth (issue 11, §1 and §5): out-of-range durations and numbers
//! are usage errors (exit 2, never a panic), options of another link are refused, a closed stderr panics
//! nothing, a busy serial port is called busy, signals end `monitor` over RS232 as on other links, a silent
//! RS232 port gets RS232 advice, and a warning that clears itself does not fail `clear-errors`.

use std::io::{BufRead, BufReader};
use std::os::fd::{FromRawFd, OwnedFd};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use tracerctl::commands::clear_errors;
use tracerctl::exit::Failure;
use tracerctl::link::LinkChoice;
use tracerctl::protocol::serial::SerialFrame;
use tracerctl::protocol::ClearTarget;
use tracerctl::protocol::ProtocolHint;
use tracerctl::session::Session;
use tracerctl::sim::{FaultKind, ScheduledFault, SimConfig};

use crate::serial_peer::{healthy, FakeRobot};
use crate::util::{stderr, stdout, tracerctl};

fn run(args: &[&str]) -> Output {
    tracerctl().args(args).output().unwrap()
}

// ---- durations and numbers ----

#[test]
fn durations_out_of_range_are_usage_errors_with_the_range_not_panics() {
    for (args, range) in [
        (&["--sim", "drive", "--for", "1e20"][..], "from 0s to 1day"),
        (&["sim", "--duration", "1e20"], "from 0s to 30days"),
        (&["--sim", "doctor", "--listen", "1e20"], "from 100ms to 10m"),
        (&["--sim", "monitor", "--duration", "1e19"], "from 0s to 30days"),
        (&["--sim", "doctor", "--listen", "1e19"], "from 100ms to 10m"),
        (&["--sim", "mode", "can", "--timeout", "nan"], "from 0s to 10m"),
        (&["--sim", "drive", "--for", "-1s"], "from 0s to 1day"),
        (&["--sim", "monitor", "--silence", "inf"], "from 0s to 1h"),
    ] {
        let output = run(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
        let expected = format!("out of range: give a duration {range}");
        assert!(stderr(&output).contains(&expected), "{args:?}: {}", stderr(&output));
    }
}

#[test]
fn bad_numbers_and_unknown_faults_are_usage_errors() {
    let output = run(&["--sim", "drive", "--linear", "nan", "--for", "1s"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("'nan' is not a number from -100 to 100"), "{}", stderr(&output));

    let output = run(&["sim", "--fault", "bogus", "--duration", "1s"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output)
            .contains("unknown fault \"bogus\"; known faults: estop, estop-release, motor1-overheat"),
        "{}",
        stderr(&output)
    );

    // Limits that contradict each other are a command-line mistake too.
    let output = run(&["--sim", "drive", "--accel", "2", "--decel", "1", "--for", "0"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--decel (1 m/s²) must be at least --accel"), "{}", stderr(&output));
}

// ---- options that do not apply ----

#[test]
fn replay_speed_given_to_drive_is_refused_naming_linear() {
    let output = run(&["--sim", "drive", "--speed", "0.3", "--for", "1s"]);
    assert_eq!(output.status.code(), Some(2), "it drove at 0 m/s: {}", stderr(&output));
    let message = stderr(&output);
    assert!(message.contains("--replay <FILE>"), "{message}");
    assert!(
        message.contains("--speed sets the replay speed and needs --replay; drive's speed is --linear"),
        "{message}"
    );
}

#[test]
fn options_of_another_link_are_usage_errors() {
    for (args, tip) in [
        (
            &["--sim", "--iface", "can1", "monitor", "--duration", "0"][..],
            "--iface names a SocketCAN interface",
        ),
        (&["--serial", "/dev/ttyUSB9", "--iface", "can1", "monitor"], "--iface names a SocketCAN interface"),
        (&["--baud", "9600", "monitor"], "--baud sets the rate of a --serial port"),
        (&["--sim", "--baud", "9600", "monitor"], "--baud sets the rate of a --serial port"),
        (&["--iface", "can0", "--speed", "2", "monitor"], "--speed sets the replay speed"),
    ] {
        let output = run(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
        assert!(stderr(&output).contains(tip), "{args:?}: {}", stderr(&output));
    }
    let output = run(&["--sim", "decode", "211#00000103000000B1"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--sim is for live links; decode reads files"), "{}", stderr(&output));
    let output = run(&["--iface", "vcan0", "sim", "--pty", "--duration", "0"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("--pty serves on a new pseudo-terminal"), "{}", stderr(&output));
}

#[test]
fn an_interface_named_in_the_environment_does_not_conflict_with_other_links() {
    let output = tracerctl()
        .env("TRACERCTL_IFACE", "tracerctl9")
        .args(["--sim", "drive", "--linear", "0.1", "--for", "100ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    // Still the default interface when no other link is chosen.
    let output = tracerctl()
        .env("TRACERCTL_IFACE", "tracerctl9")
        .args(["doctor", "--listen", "100ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(4));
    assert!(stdout(&output).starts_with("tracerctl doctor: tracerctl9 (SocketCAN)"), "{}", stdout(&output));
    // --iface still wins over the environment.
    let output = tracerctl()
        .env("TRACERCTL_IFACE", "tracerctl9")
        .args(["--iface", "tracerctl8", "doctor", "--listen", "100ms"])
        .output()
        .unwrap();
    assert!(stdout(&output).starts_with("tracerctl doctor: tracerctl8 (SocketCAN)"), "{}", stdout(&output));
}

// ---- a closed stderr ----

/// A stderr whose reader is gone before the process starts: every write to it fails (EPIPE).
fn closed_stderr() -> Stdio {
    let mut fds = [0; 2];
    // SAFETY: pipe(2) fills two new descriptors that nothing else owns.
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0);
    // SAFETY: each descriptor is owned once, here.
    let (reader, writer) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    drop(reader);
    Stdio::from(writer)
}

fn with_closed_stderr(args: &[&str]) -> Output {
    let mut command = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"));
    command.env_remove("NO_COLOR").env_remove("TRACERCTL_IFACE");
    command.args(args).stdin(Stdio::null()).stdout(Stdio::piped()).stderr(closed_stderr());
    command.output().unwrap()
}

#[test]
fn decode_with_rejects_and_a_closed_stderr_decodes_and_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("bad.log");
    std::fs::write(&log, "not a candump line\n(1.000000) can0 211#00000103000000B1\nbad again\n").unwrap();
    let log = log.to_str().unwrap();
    let output = with_closed_stderr(&["decode", log]);
    assert_eq!(output.status.code(), Some(0), "rejects are reported, not fatal");
    assert!(stdout(&output).contains("0x211 system_state vehicle_state=normal"), "{}", stdout(&output));
    let output = with_closed_stderr(&["decode", "--strict", log]);
    assert_eq!(output.status.code(), Some(3));
}

#[test]
fn send_raw_and_usage_errors_with_a_closed_stderr_do_not_panic() {
    let output = with_closed_stderr(&["--sim", "send-raw", "131#010000000000003B"]);
    assert_eq!(output.status.code(), Some(0));
    let output = with_closed_stderr(&["--sim", "drive", "--for", "1e20"]);
    assert_eq!(output.status.code(), Some(2));
    let output = with_closed_stderr(&["--sim", "bogus-command"]);
    assert_eq!(output.status.code(), Some(2));
}

/// (linear %, angular %) of an RS232 motion control frame, or None for other frames.
fn percent(frame: &SerialFrame) -> Option<(i8, i8)> {
    (frame.frame_type == 0x55 && frame.command == 0x01)
        .then(|| (frame.payload[2] as i8, frame.payload[3] as i8))
}

/// The status and the report are on stdout (docs/troubleshooting.md, "Closed standard error"): a closed
/// stderr loses only the messages, and the drive runs and stops as usual.
#[test]
fn drive_with_a_closed_stderr_still_drives_and_reports_on_stdout() {
    let robot = FakeRobot::start(healthy());
    let output = with_closed_stderr(&["--serial", &robot.path, "drive", "--linear", "0.3", "--for", "1s"]);
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert!(stdout(&output).contains("(time up)"), "{}", stdout(&output));
    assert!(
        stdout(&output).contains("last command +0.000 m/s +0.000 rad/s"),
        "stop frames sent: {}",
        stdout(&output)
    );
    let moving = robot.frames().iter().filter(|(_, f)| percent(f).is_some_and(|p| p != (0, 0))).count();
    assert!(moving > 0, "it drove");
}

#[test]
fn sim_keeps_serving_with_a_closed_stderr() {
    let started = Instant::now();
    let output = with_closed_stderr(&["sim", "--pty", "--duration", "1s"]);
    assert_eq!(output.status.code(), Some(0));
    assert!(started.elapsed() >= Duration::from_millis(900), "ended after {:?}", started.elapsed());
}

// ---- serial ports ----

#[test]
fn a_serial_port_held_by_another_program_is_busy_not_missing() {
    let robot = FakeRobot::start(healthy());
    // Another program holds the port: serialport opens exclusively (TIOCEXCL and an exclusive flock).
    let _holder =
        serialport::new(robot.path.as_str(), 115_200).open().expect("the first opener gets the port");
    for command in [&["drive", "--linear", "0.1", "--for", "1s"][..], &["monitor", "--duration", "1s"]] {
        let output = tracerctl().args(["--serial", &robot.path]).args(command).output().unwrap();
        let message = stderr(&output);
        assert_eq!(output.status.code(), Some(1), "{command:?}: {message}");
        assert!(message.contains(&format!("serial port {} is busy: another program has it open", robot.path)));
        assert!(message.contains(&format!("`fuser -v {}`", robot.path)), "{message}");
        assert!(!message.contains("does not exist"), "{message}");
    }
    let output = tracerctl().args(["--serial", &robot.path, "doctor", "--format", "json"]).output().unwrap();
    assert_eq!(output.status.code(), Some(4), "{}", stderr(&output));
    let report: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    let port =
        report["checks"].as_array().unwrap().iter().find(|c| c["id"] == "serial_port").unwrap().clone();
    assert_eq!(port["status"], "fail", "{port}");
    assert!(port["action"].as_str().unwrap().contains("is busy"), "{port}");
}

#[test]
fn monitor_over_serial_ends_with_the_signal_status() {
    for (signal, status) in [(libc::SIGINT, 130), (libc::SIGTERM, 143), (libc::SIGHUP, 129)] {
        let robot = FakeRobot::start(healthy());
        let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .env_remove("NO_COLOR")
            .args(["--serial", &robot.path, "monitor"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap());
        let mut first = String::new();
        lines.read_line(&mut first).unwrap();
        assert!(!first.is_empty(), "monitor printed nothing");
        // Let it settle into waiting for the next frame, where a signal interrupts the read.
        std::thread::sleep(Duration::from_millis(200));
        // SAFETY: kill(2) on our own child, not yet reaped.
        assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
        let drain = std::thread::spawn(move || std::io::copy(&mut lines, &mut std::io::sink()));
        let output = child.wait_with_output().unwrap();
        let _ = drain.join();
        let report = stderr(&output);
        assert_eq!(output.status.code(), Some(status), "signal {signal}: {report}");
        assert!(!report.contains("failed"), "signal {signal}: {report}");
        assert!(!report.contains("Interrupted system call"), "signal {signal}: {report}");
    }
}

/// A pseudo-terminal nobody answers on.
fn silent_port() -> (serialport::TTYPort, String) {
    let (master, slave) = serialport::TTYPort::pair().unwrap();
    let path = serialport::SerialPort::name(&slave).unwrap();
    drop(slave);
    (master, path)
}

fn assert_rs232_advice(message: &str) {
    assert!(message.contains("115200 baud 8N1"), "{message}");
    assert!(
        message.contains("null-modem (adapter TX to the robot's RX, adapter RX to the robot's TX)"),
        "{message}"
    );
    assert!(message.contains("GND connected"), "{message}");
    assert!(message.contains("serial control mode"), "{message}");
    assert!(!message.contains("bitrate"), "CAN advice on RS232: {message}");
}

#[test]
fn a_silent_serial_port_gets_rs232_advice_not_can_advice() {
    let (_master, path) = silent_port();
    let output = run(&["--serial", &path, "drive", "--linear", "0.1", "--for", "1s"]);
    assert_eq!(output.status.code(), Some(4), "{}", stderr(&output));
    assert_rs232_advice(&stderr(&output));

    let output = run(&["--serial", &path, "monitor", "--duration", "800ms", "--silence", "300ms"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(stderr(&output).contains("warning: nothing received on"), "{}", stderr(&output));
    assert_rs232_advice(&stderr(&output));

    let output = run(&["--serial", &path, "doctor", "--format", "json", "--listen", "300ms"]);
    let report: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    let frames = report["checks"].as_array().unwrap().iter().find(|c| c["id"] == "frames").unwrap().clone();
    assert_rs232_advice(frames["action"].as_str().unwrap());

    // CAN keeps the CAN advice.
    let advice = tracerctl::link::silence_advice(tracerctl::protocol::Wire::CanV2);
    assert!(advice.contains("the bitrate (500000)") && !advice.contains("115200"), "{advice}");
}

// ---- clear-errors ----

#[test]
fn clear_errors_succeeds_when_only_a_self_clearing_warning_remains() {
    let config = SimConfig {
        faults: vec![ScheduledFault { at: Duration::ZERO, fault: FaultKind::BatteryWarning }],
        ..SimConfig::default()
    };
    let session = Session::open(&LinkChoice::Sim, ProtocolHint::Auto, Some(config)).unwrap();
    let mut out = Vec::new();
    let args = clear_errors::Options { target: ClearTarget::All, timeout: Duration::from_millis(600) };
    let result = clear_errors::execute(&session, &args, &mut out);
    let out = String::from_utf8(out).unwrap();
    let code = result.unwrap_or_else(|error| {
        error.downcast_ref::<Failure>().map_or_else(
            || panic!("{error:#}"),
            |failure| panic!("exit {}: {} ({out})", failure.code, failure.message),
        )
    });
    assert_eq!(code, 0, "{out}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out}");
    assert_eq!(
        lines[0],
        "remaining: battery_undervoltage_warning [warning] — finish the task and charge soon"
    );
    assert!(lines[1].starts_with("status: normal, mode standby, 22."), "{out}");
    assert!(lines[1].ends_with("faults: battery_undervoltage_warning [warning]"), "{out}");
    assert_eq!(
        lines[2],
        "the robot can be driven: the warning remains and clears itself once the cause goes (a fault clear \
         cannot reset a warning)"
    );
}

/// A serial port this user may not open is explained from its real owner, group and mode: run as `nobody`
/// (setpriv, as root here: root itself bypasses the permission check) on a file of each mode.
#[cfg(target_os = "linux")]
#[test]
fn a_port_that_cannot_be_opened_is_explained_from_its_owner_group_and_mode() {
    use std::os::unix::fs::PermissionsExt;
    // SAFETY: geteuid has no preconditions.
    if unsafe { libc::geteuid() } != 0 {
        eprintln!("not root: setpriv cannot run tracerctl as another user; the message is unit-tested");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
    let port = dir.path().join("ttyUSB0");
    std::fs::write(&port, b"").unwrap();
    let as_nobody = |group: &str, mode: u32, groups: &str| {
        let status = std::process::Command::new("chgrp").arg(group).arg(&port).status().unwrap();
        assert!(status.success(), "chgrp {group}");
        std::fs::set_permissions(&port, std::fs::Permissions::from_mode(mode)).unwrap();
        let output = std::process::Command::new("setpriv")
            .args(["--reuid=65534", "--regid=65534", groups])
            .arg(env!("CARGO_BIN_EXE_tracerctl"))
            .arg("--serial")
            .arg(&port)
            .arg("monitor")
            .output()
            .expect("setpriv (util-linux)");
        assert_eq!(output.status.code(), Some(1));
        String::from_utf8_lossy(&output.stderr).trim_end().to_string()
    };
    let path = port.display();
    assert_eq!(
        as_nobody("dialout", 0o660, "--clear-groups"),
        format!(
            "tracerctl: permission denied opening {path} (-rw-rw---- root:dialout): only root and the dialout \
             group may open it; add yourself to the group (`sudo usermod -aG dialout $USER`, then log in again)"
        )
    );
    // Not a dialout device: dialout is not suggested.
    let closed = as_nobody("root", 0o600, "--clear-groups");
    assert_eq!(
        closed,
        format!(
            "tracerctl: permission denied opening {path} (-rw------- root:root): only root may open it; give it a \
             group with a udev rule (docs/troubleshooting.md, Serial ports) or run as root"
        )
    );
    let other_group = as_nobody("disk", 0o660, "--clear-groups");
    assert!(other_group.contains("root:disk") && other_group.contains("usermod -aG disk"), "{other_group}");
    assert!(!other_group.contains("dialout"), "{other_group}");
}

/// can-utils habits through the real binary: exit 2 and the tracerctl spelling (every spelling is in
/// cli.rs's unit tests).
#[test]
fn can_utils_habits_are_usage_errors_with_the_tracerctl_spelling() {
    for (args, tip) in [
        (&["monitor", "can0"][..], "tip: the interface is `--iface can0`: tracerctl --iface can0 monitor"),
        (&["send-raw", "can0", "121#01031E0000000005"], "tip: the interface is `--iface can0`"),
        (&["drive", "--time", "2s"], "tip: drive's time is `--for 2s`"),
    ] {
        let output = crate::util::tracerctl().args(args).output().unwrap();
        let errors = crate::util::stderr(&output);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {errors}");
        assert!(errors.contains(tip), "{args:?}: {errors}");
    }
}
