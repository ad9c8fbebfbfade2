//! `tracerctl commission` on the simulator: the plan without a link, the refusals that send nothing, a full
//! run with its recording, plot, saved record and comparison, and every abort (E-stop, a fault bit, RC
//! override, SIGTERM, SIGHUP, a key and Space on a pseudo-terminal) ending in zero frames within the
//! recording; and `drive --record`.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

use crate::util::{decode_json, stderr, stdout, tracerctl, wait_with_timeout};

/// A 0x111 frame of a recording: its stamp (µs) and commanded linear and angular speed.
fn commands(log: &Path) -> Vec<(i64, f64, f64)> {
    decode_json(&["--id", "0x111", log.to_str().unwrap()])
        .iter()
        .map(|line| {
            (
                line["ts_ns"].as_i64().unwrap() / 1000,
                line["fields"]["linear_velocity"].as_f64().unwrap(),
                line["fields"]["angular_velocity"].as_f64().unwrap(),
            )
        })
        .collect()
}

/// The last motion commands are zeros, and the first zero after `cause_us` comes within `within_us`.
fn ends_in_zeros_after(log: &Path, cause_us: Option<i64>, within_us: i64) {
    let sent = commands(log);
    assert!(sent.iter().any(|(_, linear, angular)| *linear != 0.0 || *angular != 0.0), "it drove");
    // The sender's stop frames (three) are the last.
    let tail: Vec<_> = sent.iter().rev().take(3).collect();
    assert!(tail.iter().all(|(_, linear, angular)| *linear == 0.0 && *angular == 0.0), "{tail:?}");
    if let Some(cause) = cause_us {
        let first_zero =
            sent.iter().find(|(at, linear, angular)| *at >= cause && *linear == 0.0 && *angular == 0.0);
        let (at, ..) = first_zero.expect("a zero command after the cause");
        assert!(at - cause <= within_us, "first zero {} µs after the cause", at - cause);
    }
}

/// The stamp of the first system state (0x211) whose field `field` is `value`.
fn first_state(log: &Path, field: &str, value: &str) -> Option<i64> {
    decode_json(&["--id", "0x211", log.to_str().unwrap()])
        .iter()
        .find(|line| line["fields"][field] == value)
        .map(|line| line["ts_ns"].as_i64().unwrap() / 1000)
}

#[test]
fn dry_run_prints_the_plan_and_opens_no_link() {
    // No such interface: the plan needs none.
    let output = tracerctl()
        .args(["--iface", "nosuchcan0", "commission", "--dry-run", "--include", "timeout"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    for expected in [
        " 2. forward                     3.3 s",
        "11. commands cease              1.5 s  (from  23.7 s)  nothing sent",
        "bounds: at most 0.300 m/s and 0.500 rad/s",
        "duration: 26.2 s",
        "free space: 1.5 m clear ahead and behind; it ends near where it started",
    ] {
        assert!(text.contains(expected), "{expected:?} in\n{text}");
    }
    let output = tracerctl()
        .args(["commission", "--dry-run", "-f", "json", "--max-linear", "9", "--max-angular", "0.2"])
        .output()
        .unwrap();
    let plan: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    assert_eq!(plan["parameters"]["max_linear_mps"], 0.6, "capped by the pattern's room");
    assert_eq!(plan["parameters"]["max_angular_radps"], 0.2);
    assert_eq!(plan["steps"].as_array().unwrap().len(), 9);
    assert_eq!(plan["steps"][5]["action"], "+0.200 rad/s");
}

#[test]
fn usage_errors_and_no_terminal_without_yes_send_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("never.log");
    for args in [
        vec!["commission", "--max-linear", "-1", "--dry-run"],
        vec!["commission", "--include", "everything", "--dry-run"],
        vec!["commission", "--dry-run", "--compare", "old.json"],
    ] {
        let output = tracerctl().args(&args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
    }
    // Standard input is not a terminal and there is no --yes: refused before the link opens.
    let output =
        tracerctl().args(["--sim", "commission", "--record"]).arg(&record).write_stdin("").output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("run it on a terminal, or give --yes (nothing was sent)"),
        "{}",
        stderr(&output)
    );
    assert!(!record.exists(), "no link was opened, nothing recorded");
    // A threshold in the configuration file that is not a positive number names its key and place.
    let config = dir.path().join("tracerctl.toml");
    std::fs::write(&config, "[commission]\ndead_time_warn_ms = -5\n").unwrap();
    let output =
        tracerctl().env("TRACERCTL_CONFIG", &config).args(["commission", "--dry-run"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("commission.dead_time_warn_ms: -5 is not a positive number"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn a_full_run_on_the_simulator_reports_every_section_records_plots_saves_and_compares() {
    let dir = tempfile::tempdir().unwrap();
    let (record, plot, saved) =
        (dir.path().join("run.log"), dir.path().join("run.svg"), dir.path().join("records"));
    let old = dir.path().join("old.json");
    std::fs::write(
        &old,
        r#"{"type": "commission", "figures": [
            {"name": "left_right_gain_ratio", "step": "whole drive", "value": 0.97, "verdict": "warn"},
            {"name": "dead_time_ms", "step": "a step that is gone", "value": 80.0, "verdict": "pass"}]}"#,
    )
    .unwrap();
    // A threshold from the configuration file: the simulator's 240 ms rise (0.3 m/s at 1 m/s²) warns at 100.
    let config = dir.path().join("config.toml");
    std::fs::write(&config, "[commission]\nrise_time_warn_ms = 100\n").unwrap();
    let output = tracerctl()
        .env("TRACERCTL_CONFIG", &config)
        .args(["--sim", "commission", "--yes", "--record"])
        .arg(&record)
        .arg("--plot")
        .arg(&plot)
        .arg("--save")
        .arg(&saved)
        .arg("--compare")
        .arg(&old)
        .write_stdin("")
        .output()
        .unwrap();
    let text = stdout(&output);
    assert_eq!(output.status.code(), Some(0), "{text}\n{}", stderr(&output));
    for section in [
        "PASS  E-stop",
        "tracerctl commission on sim: a bounded test drive of 9 steps",
        "commission report: sim,",
        "(9 of 9 steps run)",
        "left/right gain ratio",
        "heading drift",
        "track width",
        "odometer scale",
        "internal resistance",
        "open-circuit voltage",
        "stop: ",
        "result: ",
        "compared with ",
        "whole drive              left_right_gain_ratio           0.970",
        "a step that is gone",
    ] {
        assert!(text.contains(section), "{section:?} in\n{text}");
    }
    // The recording: the commands and the feedback, ending in zeros; decode --summary reads it.
    ends_in_zeros_after(&record, None, 0);
    let sent = commands(&record);
    assert!(
        sent.iter().any(|(_, linear, _)| *linear == 0.3) && sent.iter().any(|(_, linear, _)| *linear == -0.3)
    );
    assert!(
        sent.iter().any(|(_, _, angular)| *angular == 0.5)
            && sent.iter().any(|(_, _, angular)| *angular == -0.5)
    );
    assert!(
        sent.iter().all(|(_, linear, angular)| linear.abs() <= 0.3 && angular.abs() <= 0.5),
        "within the caps"
    );
    // Each step is a step: from zero to the full command in one frame.
    let first_moving = sent.iter().position(|(_, linear, _)| *linear != 0.0).unwrap();
    assert_eq!(sent[first_moving].1, 0.3, "no ramp");
    assert!(
        decode_json(&["--id", "0x221", record.to_str().unwrap()]).len() > 500,
        "the feedback is recorded"
    );
    let summary = tracerctl().args(["decode", "--summary"]).arg(&record).output().unwrap();
    assert!(summary.status.success(), "{}", stderr(&summary));
    let rise =
        text.lines().find(|line| line.starts_with("forward") && line.contains("rise")).unwrap_or_default();
    // The threshold from the file judges the step. The figure is timed from the feedback's host stamps, which a
    // busy machine can delay by a few ms (the exact "240 ms" failed here once), so it is held to the issue's
    // tolerance of one 20 ms period around the model's 240 ms, not to the printed digit.
    let (figure, judged) = rise.split_once(" ms  ").unwrap_or_default();
    let rise_ms: f64 = figure.split_whitespace().last().and_then(|ms| ms.parse().ok()).unwrap_or(f64::NAN);
    assert!((rise_ms - 240.0).abs() <= 20.0, "{rise:?} in\n{text}");
    assert!(judged.starts_with("WARN  warn > 100 ms"), "{rise:?} in\n{text}");
    // 0.970 before, 1.000 now: beyond half the 0.02 warning margin.
    let compared = text.lines().find(|line| line.contains("left_right_gain_ratio")).unwrap_or_default();
    assert!(compared.ends_with("DRIFTED"), "{compared}");
    valid_plot_of_nine_steps(&plot);
    saved_record_names_every_figure(&saved);
    live_figures_are_the_recordings(&saved, &record);
}

/// Issue 32: `decode --summary` of the `--record` file gives the live report's figures: the live analysis
/// is fed exactly the recorded frames and stamps (the saved record rounds to 6 decimals).
fn live_figures_are_the_recordings(saved: &Path, record: &Path) {
    let file = std::fs::read_dir(saved).unwrap().next().unwrap().unwrap().path();
    let live: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
    let live_values = |name: &str| -> Vec<f64> {
        live["figures"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|figure| figure["name"] == name)
            .filter_map(|figure| figure["value"].as_f64())
            .collect()
    };
    let output = tracerctl().args(["decode", "--summary", "-f", "json"]).arg(record).output().unwrap();
    let summary: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    let health = &summary["health"];
    let offline = |list: &str, key: &str| -> Vec<f64> {
        health[list].as_array().unwrap().iter().filter_map(|entry| entry[key].as_f64()).collect()
    };
    let same = |what: &str, live: Vec<f64>, offline: Vec<f64>| {
        assert_eq!(live.len(), offline.len(), "{what}: live {live:?}, recording {offline:?}");
        assert!(!live.is_empty(), "{what} measured");
        for (a, b) in live.iter().zip(&offline) {
            assert!((a - b).abs() <= 1e-6 * b.abs().max(1.0), "{what}: live {a}, recording {b}");
        }
    };
    same("dead time", live_values("dead_time_ms"), offline("steps", "dead_time_ms"));
    same("rise time", live_values("rise_time_ms"), offline("steps", "rise_time_ms"));
    same("braking time", live_values("braking_time_ms"), offline("braking", "time_ms"));
    same("deceleration", live_values("deceleration_mps2"), offline("braking", "deceleration_mps2"));
    let one = |value: &serde_json::Value| vec![value.as_f64().unwrap()];
    same(
        "gain ratio",
        live_values("left_right_gain_ratio"),
        one(&health["symmetry"]["left_right_gain_ratio"]),
    );
    same("track width", live_values("track_width_m"), one(&health["geometry"]["track_width_m"]));
    same("odometer scale", live_values("odometer_scale"), one(&health["geometry"]["odometer_scale"]));
}

/// The plot: valid SVG, a panel per step, four series each.
fn valid_plot_of_nine_steps(plot: &Path) {
    let svg = std::fs::read_to_string(plot).unwrap();
    let check = std::process::Command::new("python3")
        .args(["-c", "import sys, xml.etree.ElementTree as E; r = E.parse(sys.argv[1]).getroot(); \
             ns = '{http://www.w3.org/2000/svg}'; g = [e for e in r.iter(ns + 'g') if e.get('class') == 'panel']; \
             print(len(g), sum(len(list(e.iter(ns + 'polyline'))) for e in g))"])
        .arg(plot)
        .output();
    if let Some(check) = check.ok().filter(|check| check.status.success()) {
        assert_eq!(String::from_utf8_lossy(&check.stdout).trim(), "9 36", "9 panels of 4 series");
    } else {
        assert_eq!(svg.matches("<g class=\"panel\"").count(), 9);
    }
}

/// The saved record is the JSON report: every figure named with its unit.
fn saved_record_names_every_figure(saved: &Path) {
    let files: Vec<_> = std::fs::read_dir(saved).unwrap().map(|entry| entry.unwrap().path()).collect();
    assert_eq!(files.len(), 1);
    let name = files[0].file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with("sim-") && name.ends_with("Z.json"), "{name}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&files[0]).unwrap()).unwrap();
    assert_eq!(json["type"], "commission");
    assert_eq!(json["exit_status"], 0);
    assert_eq!(json["abort"], serde_json::Value::Null);
    assert_eq!(json["stop_confirmed"], true);
    assert_eq!(json["parameters"]["max_linear_mps"], 0.3);
    let names: Vec<&str> =
        json["figures"].as_array().unwrap().iter().map(|f| f["name"].as_str().unwrap()).collect();
    for name in [
        "left_right_gain_ratio",
        "heading_drift_deg_per_m",
        "track_width_m",
        "odometer_scale",
        "internal_resistance_ohm",
        "open_circuit_voltage_v",
    ] {
        assert!(names.contains(&name), "{name} in {names:?}");
    }
    assert_eq!(json["thresholds"]["dead_time_ms"]["warn"], 150.0);
}

/// Runs `--sim --fault FAULT commission --yes -f json --record` and returns the record and the recording.
fn aborted_by(fault: &str, dir: &Path) -> (serde_json::Value, std::path::PathBuf, String, Option<i32>) {
    let record = dir.join(format!("{fault}.log"));
    let output = tracerctl()
        .args(["--sim", "--fault", fault, "commission", "--yes", "-f", "json", "--record"])
        .arg(&record)
        .arg("--save")
        .arg(dir.join("records"))
        .write_stdin("")
        .output()
        .unwrap();
    let json: serde_json::Value = serde_json::from_str(&stdout(&output)).expect("one JSON object");
    (json, record, stderr(&output), output.status.code())
}

#[test]
fn an_estop_a_fault_and_rc_override_abort_to_zero_keeping_what_was_measured() {
    let dir = tempfile::tempdir().unwrap();
    // The drive starts after the doctor's 1 s listen: at 4 s it is in the first straight step.
    let (json, record, errors, code) = aborted_by("estop@4s", dir.path());
    assert_eq!(code, Some(4), "{errors}");
    assert_eq!(json["verdict"], "aborted");
    assert_eq!(json["abort"]["reason"], "estop");
    assert!(
        errors.contains("commission aborted: stopped after") && errors.contains("the E-stop was pressed"),
        "{errors}"
    );
    assert!(json["steps"][1]["run"] == true && json["steps"][8]["run"] == false, "{json}");
    assert!(json["figures"].as_array().is_some_and(|figures| !figures.is_empty()), "the partial report");
    // The first zero within a few periods of the E-stop's first frame (one period in the timing group).
    ends_in_zeros_after(&record, first_state(&record, "vehicle_state", "estop"), 100_000);

    let (json, record, errors, code) = aborted_by("motor1-overheat@4s", dir.path());
    assert_eq!(code, Some(4), "{errors}");
    let reason = json["abort"]["reason"].as_str().unwrap();
    assert!(reason == "fault" || reason == "exception", "{json}");
    ends_in_zeros_after(&record, None, 0);

    let (json, record, errors, code) = aborted_by("swb-middle@4s", dir.path());
    assert_eq!(code, Some(4), "{errors}");
    let reason = json["abort"]["reason"].as_str().unwrap();
    assert!(reason == "rc_override" || reason == "mode_changed", "{json}");
    ends_in_zeros_after(&record, first_state(&record, "control_mode", "rc"), 100_000);
    // Three aborted runs saved, none overwriting another.
    assert_eq!(std::fs::read_dir(dir.path().join("records")).unwrap().count(), 3);
}

/// Starts a commission in text mode and returns once its second step has begun.
fn started(
    args: &[&str],
    record: &Path,
    stdin: Stdio,
) -> (std::process::Child, std::thread::JoinHandle<String>) {
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .env("TRACERCTL_CONFIG", "")
        .env("TRACERCTL_PROFILE", "")
        .args(["--sim", "commission", "--record"])
        .arg(record)
        .args(args)
        .stdin(stdin)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (seen, lines) = std::sync::mpsc::channel();
    let mut errors = BufReader::new(child.stderr.take().unwrap());
    let reader = std::thread::spawn(move || {
        let mut all = String::new();
        let mut line = Vec::new();
        // The prompt has no line end of its own in raw mode: split on both.
        while errors.read_until(b'\n', &mut line).is_ok_and(|read| read > 0) {
            let text = String::from_utf8_lossy(&line).into_owned();
            let _ = seen.send(text.clone());
            all.push_str(&text);
            line.clear();
        }
        all
    });
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    loop {
        let line = lines.recv_timeout(Duration::from_secs(20)).expect("progress on stderr");
        if line.contains("step 2/") {
            break;
        }
        assert!(std::time::Instant::now() < deadline);
    }
    std::thread::sleep(Duration::from_millis(500));
    (child, reader)
}

#[cfg(unix)]
#[test]
fn sigterm_and_sighup_mid_drive_stop_with_zeros_and_their_statuses() {
    let dir = tempfile::tempdir().unwrap();
    for (signal, status) in [(libc::SIGTERM, 143), (libc::SIGHUP, 129)] {
        let record = dir.path().join(format!("{signal}.log"));
        let (child, errors) = started(&["--yes"], &record, Stdio::null());
        crate::util::signal(child.id(), signal);
        let output = wait_with_timeout(child, Duration::from_secs(20));
        let errors = errors.join().unwrap();
        assert_eq!(output.status.code(), Some(status), "{errors}");
        assert!(errors.contains("commission stopped by SIG"), "{errors}");
        assert!(stdout(&output).contains("result: ABORTED (signal)"), "{}", stdout(&output));
        ends_in_zeros_after(&record, None, 0);
    }
}

/// A commission on a pseudo-terminal the test types into.
#[cfg(unix)]
fn on_a_terminal(record: &Path, keys_after_start: &[u8]) -> (Option<i32>, String, String) {
    use serialport::SerialPort;
    use std::io::Write;
    let (mut terminal, slave) = serialport::TTYPort::pair().unwrap();
    let slave_path = slave.name().unwrap();
    let stdin = std::fs::OpenOptions::new().read(true).write(true).open(&slave_path).unwrap();
    drop(slave);
    terminal.set_timeout(Duration::from_millis(50)).unwrap();
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .env("TRACERCTL_CONFIG", "")
        .env("TRACERCTL_PROFILE", "")
        .env("TERM", "xterm")
        .args(["--sim", "commission", "--record"])
        .arg(record)
        .stdin(stdin)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut errors = BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    let mut line = Vec::new();
    let mut answered = false;
    while errors.read_until(b'\n', &mut line).is_ok_and(|read| read > 0) {
        let text = String::from_utf8_lossy(&line).into_owned();
        seen.push_str(&text);
        line.clear();
        if text.contains("Start the drive?") && !answered {
            terminal.write_all(b"y").unwrap();
            answered = true;
        }
        if text.contains("step 2/") {
            std::thread::sleep(Duration::from_millis(500));
            terminal.write_all(keys_after_start).unwrap();
            break;
        }
    }
    let mut rest = String::new();
    let _ = std::io::Read::read_to_string(&mut errors, &mut rest);
    seen.push_str(&rest);
    let output = wait_with_timeout(child, Duration::from_secs(20));
    (output.status.code(), stdout(&output), seen)
}

#[cfg(unix)]
#[test]
fn a_key_or_space_on_the_terminal_stops_the_drive_with_zeros() {
    let dir = tempfile::tempdir().unwrap();
    for (key, name) in [(&b"x"[..], "x"), (&b" "[..], "Space")] {
        let record = dir.path().join(format!("{name}.log"));
        let (code, out, errors) = on_a_terminal(&record, key);
        assert_eq!(code, Some(4), "{out}\n{errors}");
        assert!(out.contains("result: ABORTED (key)"), "{out}");
        assert!(errors.contains(&format!("the operator pressed a key ({name})")), "{errors}");
        ends_in_zeros_after(&record, None, 0);
    }
}

#[test]
fn drive_record_holds_the_drives_commands_and_feedback_ending_in_zeros() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("drive.log");
    let output = tracerctl()
        .args(["--sim", "drive", "--linear", "0.2", "--for", "1s", "--record"])
        .arg(&record)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let sent = commands(&record);
    assert!(sent.iter().any(|(_, linear, _)| *linear > 0.19), "{sent:?}");
    ends_in_zeros_after(&record, None, 0);
    let feedback = decode_json(&["--id", "0x221", record.to_str().unwrap()]);
    assert!(
        feedback.iter().any(|line| line["fields"]["linear_velocity"].as_f64().unwrap() > 0.1),
        "the robot moved"
    );
}
