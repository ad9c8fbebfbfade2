//! `--sim-param NAME=VALUE`: with `--sim` the in-process robot gets the parameters, `sim` serves a robot
//! with them (and says which), and every mistake is a usage error that names the parameter, its range and
//! unit.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

use crate::util::{stderr, stdout, tracerctl};

#[test]
fn the_in_process_robot_gets_the_parameters() {
    let output = tracerctl()
        .args(["--sim", "--sim-param", "dead-time=100ms", "--sim-param", "left-gain=0.95", "doctor"])
        .args(["--listen", "300ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        stdout(&output).contains("PASS  link               in-process virtual TRACER"),
        "{}",
        stdout(&output)
    );
    // 24 V open-circuit less 1 A idle x 0.3 ohm: the battery doctor reads is the parameters' one.
    let output = tracerctl()
        .args(["--sim", "--sim-param", "battery-ocv=24", "--sim-param", "battery_r=0.3", "doctor"])
        .args(["--listen", "300ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let battery = stdout(&output).lines().find(|line| line.starts_with("PASS  battery")).map(str::to_string);
    assert_eq!(battery.as_deref(), Some("PASS  battery            23.7 V"), "{}", stdout(&output));
}

#[test]
fn mistakes_are_usage_errors_naming_the_parameter_range_and_unit() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["--sim", "--sim-param", "warp=9", "doctor"],
            "unknown simulator parameter \"warp\"; parameters: dead-time, lag, max-accel, left-gain, right-gain, \
             track-width, odometer-scale, command-timeout, battery-ocv, battery-r, noise, seed",
        ),
        (&["--sim", "--sim-param", "dead-time=3s", "doctor"], "dead-time: '3s' is out of range: give from 0 to 2000 ms"),
        (&["sim", "--pty", "--sim-param", "left-gain=fast"], "left-gain: 'fast' is not a number; give from 0.5 to 1.5 (a ratio)"),
        (&["--sim", "--sim-param", "battery-ocv=40", "doctor"], "battery-ocv: '40' is out of range: give from 18 to 30 V"),
        (&["--sim", "--sim-param", "noise", "doctor"], "'noise' is not NAME=VALUE (e.g. dead-time=100ms)"),
        (
            &["--sim-param", "lag=50ms", "doctor"],
            "--sim-param sets a parameter of the simulator: add --sim (e.g. tracerctl --sim --sim-param dead-time=100ms doctor)",
        ),
    ];
    for (args, text) in cases {
        let output = tracerctl().args(args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
        assert!(stderr(&output).contains(text), "{args:?}: {}", stderr(&output));
        assert!(stdout(&output).is_empty(), "{args:?}");
    }
    let output = tracerctl().args(["decode", "--sim-param", "lag=50ms", "x.log"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("--sim-param is for live links"), "{}", stderr(&output));
}

/// `sim --pty ARGS` started; its first stdout lines after the PTY path, and the battery line of a doctor
/// run over the pseudo-terminal.
#[cfg(unix)]
fn serve_and_doctor(args: &[&str], startup_lines: usize) -> (Vec<String>, Option<String>) {
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["sim", "--pty", "--duration", "20s"])
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let first = lines.next().unwrap().unwrap();
    let path = first.strip_prefix("PTY ").expect("`PTY <path>` first").trim().to_string();
    let startup = lines.by_ref().take(startup_lines).map(Result::unwrap).collect();
    let output = tracerctl().args(["--serial", &path, "doctor", "--listen", "500ms"]).output().unwrap();
    let _ = child.kill();
    let _ = child.wait();
    let battery = stdout(&output).lines().find(|line| line.contains("  battery  ")).map(str::to_string);
    (startup, battery)
}

#[test]
#[cfg(unix)]
fn sim_serves_a_robot_with_the_parameters_and_lists_them() {
    let args =
        ["--sim-param", "battery-ocv=24.5", "--sim-param", "dead-time=0.12s", "--sim-param", "noise=0"];
    let (startup, battery) = serve_and_doctor(&args, 2);
    assert!(startup[0].starts_with("connect with: "), "{startup:?}");
    // Only what differs from the defaults (noise=0 is the default).
    assert_eq!(startup[1], "chassis parameters: dead-time=120ms battery-ocv=24.5");
    // 24.5 V less 1 A idle x 0.08 ohm = 24.42 V.
    assert_eq!(battery.as_deref(), Some("PASS  battery            24.4 V"));
}

#[test]
#[cfg(unix)]
fn a_low_battery_option_is_kept_not_replaced_by_the_default() {
    // 20 V is under the model's 21 V "empty": it lowers empty instead of falling back to 26 V.
    let (startup, battery) = serve_and_doctor(&["--battery", "20"], 2);
    assert_eq!(startup[1], "chassis parameters: battery-ocv=20");
    assert_eq!(
        battery.as_deref(),
        Some("FAIL  battery            19.9 V: below the 22 V protection voltage")
    );
}
