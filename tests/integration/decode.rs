//! `tracerctl decode` on fixture logs, single frames and serial captures.

use std::io::Write;

use serde_json::json;

use crate::util::{data, decode_json, json_lines, stderr, stdout, tracerctl};

fn session() -> String {
    data("tracer_session.log").display().to_string()
}

#[test]
fn text_output_names_every_field_with_units() {
    let output = tracerctl().args(["decode", &session()]).output().unwrap();
    assert!(output.status.success());
    let text = stdout(&output);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 15, "15 frames, the bad line skipped");
    assert_eq!(
        lines[0],
        "1700000000.000000 can0 0x211 system_state vehicle_state=normal control_mode=standby \
         battery_voltage=25.9V fault_code=0x0000 faults=none count=177"
    );
    assert_eq!(lines[1], "1700000000.020000 can0 0x421 control_mode_command control_mode=can");
    assert_eq!(
        lines[3],
        "1700000000.060000 can0 0x111 motion_command linear_velocity=0.15m/s angular_velocity=0rad/s"
    );
    assert_eq!(
        lines[8],
        "1700000000.140000 can0 0x211 system_state vehicle_state=estop control_mode=can \
         battery_voltage=25.7V fault_code=0x0200 faults=battery_undervoltage_warning[warning] count=181"
    );
    assert_eq!(
        lines[10],
        "1700000000.180000 can0 0x262 motor_low_speed motor=2 driver_voltage=26.3V driver_temperature=39°C \
         motor_temperature=-40°C driver_state=0x40 driver_faults=driver_disabled[info]"
    );
    // The bad line is reported with file:line and the reason, and counted at the end.
    let errors = stderr(&output);
    assert!(errors.contains("tracer_session.log:15: column 1: "), "{errors}");
    assert!(errors.contains("decoded 15 frames from 16 lines; rejected 1"), "{errors}");
}

#[test]
fn json_output_matches_the_documented_schema() {
    let objects = decode_json(&[&session()]);
    assert_eq!(objects.len(), 15);
    assert_eq!(
        objects[0],
        json!({"ts": 1700000000.0, "ts_ns": 1_700_000_000_000_000_000u64, "iface": "can0", "id": "0x211", "data": "00000103000000B1",
               "msg": "system_state", "wire": "can-v2", "dir": null,
               "fields": {"vehicle_state": "normal", "control_mode": "standby", "battery_voltage": 25.9,
                          "fault_code": 0, "faults": [], "count": 177}})
    );
    assert_eq!(objects[4]["ts"], json!(1700000000.0605));
    assert_eq!(objects[12]["fields"], json!({"linear_velocity": -0.2, "angular_velocity": -0.5}));
    assert_eq!(objects[13]["fields"], json!({"left_wheel_odometer": -0.063, "right_wheel_odometer": 0.018}));
    assert_eq!(objects[11]["fields"], json!({"motor": 1, "rpm": 3000, "current": 5.0, "pulse_count": 0}));
    assert_eq!(objects[8]["fields"]["faults"], json!(["battery_undervoltage_warning"]));
    assert_eq!(objects[8]["fields"]["fault_code"], json!(0x0200));
}

#[test]
fn csv_output_has_a_stable_header_and_one_row_per_frame() {
    let output = tracerctl().args(["decode", "--format", "csv", &session()]).output().unwrap();
    let text = stdout(&output);
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..8], ["ts", "iface", "dir", "id", "wire", "msg", "data", "error"]);
    let battery = header.iter().position(|h| *h == "battery_voltage").unwrap();
    let faults = header.iter().position(|h| *h == "faults").unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|line| line.split(',').collect()).collect();
    assert_eq!(rows.len(), 15);
    assert!(rows.iter().all(|row| row.len() == header.len()));
    assert_eq!(rows[0][battery], "25.9");
    assert_eq!(rows[8][faults], "battery_undervoltage_warning");
    assert_eq!(rows[3][battery], "", "a motion command has no battery value");
}

#[test]
fn summary_reports_rates_losses_modes_faults_battery_and_distance() {
    let output = tracerctl().args(["decode", "--summary", &session()]).output().unwrap();
    assert!(output.status.success());
    let report = stdout(&output);
    let row = report.lines().find(|line| line.trim_start().starts_with("0x211")).unwrap();
    assert!(row.contains("system_state"), "{row}");
    // 6 status frames, counts B1 B2 B4 B5 B6 B7: B3 lost.
    assert!(row.contains(" 6 "), "{row}");
    assert!(row.ends_with("1 in 1 skips"), "{row}");
    assert!(report.contains("control mode standby -> can"), "{report}");
    assert!(report.contains("vehicle state normal -> estop (E-stop pressed)"), "{report}");
    assert!(report.contains("vehicle state estop -> normal"), "{report}");
    assert!(report.contains("battery_undervoltage_warning [warning] in 3 frames"), "{report}");
    assert!(report.contains("driver_disabled [info] in 1 frames"), "{report}");
    assert!(report.contains("min 25.6 V at 2023-11-14T22:13:20.160000Z"), "{report}");
    assert!(report.contains("max 25.9 V"), "{report}");
    assert!(report.contains("left  travelled 0.083 m, net -0.063 m"), "{report}");
    assert!(report.contains("right travelled 0.022 m, net +0.018 m"), "{report}");
    assert!(report.contains("measured linear   -0.200 m/s"), "{report}");
    assert!(report.contains("commanded linear  +0.150 m/s"), "{report}");
    assert!(report.contains("motor 1           +3000 rpm"), "{report}");
    assert!(report.contains("protocol: V2"), "{report}");
    assert!(
        report.contains("time span: 2023-11-14T22:13:20.000000Z .. 2023-11-14T22:13:20.260000Z (0.260 s)")
    );
    let rejected = report.split("Rejected input").nth(1).unwrap();
    assert!(rejected.contains("       1  "), "{rejected}");
}

#[test]
fn summary_as_json() {
    let output = tracerctl().args(["decode", "--summary", "--format", "json", &session()]).output().unwrap();
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(report["frames"], 15);
    assert_eq!(report["battery"]["min"]["value"], 25.6);
    let status = report["ids"].as_array().unwrap().iter().find(|id| id["id"] == "0x211").unwrap();
    assert_eq!(status["frames"], 6);
    assert_eq!(status["frames_lost"], 1);
    assert_eq!(report["rejected"][0]["count"], 1);
}

#[test]
fn strict_makes_the_first_bad_line_fatal() {
    let output = tracerctl().args(["decode", "--strict", &session()]).output().unwrap();
    assert_eq!(output.status.code(), Some(3));
    let errors = stderr(&output);
    assert!(errors.starts_with("tracerctl: "), "{errors}");
    assert!(errors.contains("tracer_session.log:15: column 1"), "{errors}");
    assert_eq!(errors.lines().count(), 1, "one clear line: {errors}");
}

#[test]
fn filters_by_message_name_and_id() {
    let odometry = decode_json(&["--msg", "odometry", &session()]);
    assert_eq!(odometry.len(), 3);
    assert!(odometry.iter().all(|o| o["msg"] == "odometry"));
    let ids = decode_json(&["--id", "0x221,111", &session()]);
    let names: Vec<&str> = ids.iter().map(|o| o["id"].as_str().unwrap()).collect();
    assert_eq!(names, ["0x111", "0x221", "0x221"]);
    let output = tracerctl().args(["decode", "--msg", "odometer", &session()]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("unknown message name 'odometer'"));
}

#[test]
fn single_frames_from_the_command_line() {
    let objects = decode_json(&["211#00000103000000B1", "111#FE0C012C00000000", "130#01000A0000000045"]);
    assert_eq!(objects[0]["fields"]["battery_voltage"], 25.9);
    assert_eq!(objects[0]["ts"], serde_json::Value::Null);
    assert_eq!(objects[1]["fields"], json!({"linear_velocity": -0.5, "angular_velocity": 0.3}));
    assert_eq!(objects[2]["msg"], "invalid");
    assert_eq!(objects[2]["error"], "V1 checksum mismatch on 0x130: computed 0x44, frame carries 0x45");
    let output = tracerctl().args(["decode", "211#1122334455667788AA"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("is neither a file nor a valid frame"));
}

#[test]
fn serial_captures_in_raw_bytes_and_hex_text() {
    let dir = tempfile::tempdir().unwrap();
    // Noise, a false start (5A 5A A5), the manual's example, a corrupted frame, and a light command.
    let mut bytes = vec![0x00, 0x5A, 0x5A];
    bytes.extend([0xA5, 0x0A, 0x55, 0x01, 0x02, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x6B]);
    bytes.extend([0x5A, 0xA5, 0x0A, 0x55, 0x01, 0x02, 0x00, 0xF6, 0x00, 0x00, 0x00, 0x01, 0x59]);
    bytes.extend([0x5A, 0xA5, 0x0A, 0x55, 0x02, 0x01, 0x03, 0x32, 0x00, 0x00, 0x00, 0x00, 0x96]);
    let raw = dir.path().join("uart.bin");
    std::fs::write(&raw, &bytes).unwrap();
    let hex_path = dir.path().join("uart.txt");
    let mut hex_file = std::fs::File::create(&hex_path).unwrap();
    writeln!(hex_file, "# captured with minicom").unwrap();
    for chunk in bytes.chunks(13) {
        let line: Vec<String> = chunk.iter().map(|b| format!("0x{b:02X}")).collect();
        writeln!(hex_file, "{}", line.join(", ")).unwrap();
    }
    for path in [&raw, &hex_path] {
        let output = tracerctl().args(["decode", "--format", "json", "--serial"]).arg(path).output().unwrap();
        assert!(output.status.success());
        let objects = json_lines(&output);
        assert_eq!(objects.len(), 2, "{}", path.display());
        assert_eq!(objects[0]["id"], "0x5501");
        assert_eq!(objects[0]["iface"], "serial");
        assert_eq!(objects[0]["data"], "5AA50A550102000A000000006B");
        assert_eq!(objects[0]["fields"]["linear_velocity"], 0.15);
        assert_eq!(objects[0]["fields"]["control_mode"], "serial");
        assert_eq!(objects[1]["msg"], "light_command");
        assert_eq!(objects[1]["fields"]["front_mode"], "custom");
        assert_eq!(objects[1]["fields"]["front_brightness"], 50);
        let errors = stderr(&output);
        assert!(errors.contains("checksum mismatch: computed 0x58, frame carries 0x59"), "{errors}");
    }
}

#[test]
fn reads_standard_input() {
    let output = tracerctl()
        .args(["decode", "-f", "json", "-"])
        .write_stdin("(1700000000.000000) can0 311#FFFFFFC100000012\n")
        .output()
        .unwrap();
    let object: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(object["fields"]["left_wheel_odometer"], -0.063);
}

#[test]
fn closed_pipe_exits_zero_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.log");
    let line = "(1700000000.000000) can0 211#00000103000000B1\n";
    std::fs::write(&path, line.repeat(200_000)).unwrap();
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let output = std::process::Command::new("bash")
        .arg("-c")
        .arg(format!("set -o pipefail; '{}' decode '{}' | head -n 1", binary.display(), path.display()))
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(stdout(&output).lines().count(), 1);
    assert_eq!(stderr(&output), "");
}

#[test]
fn colour_only_when_asked_and_not_by_default_with_no_color() {
    let colored = tracerctl().args(["--color", "always", "decode", "211#00000103010000B1"]).output().unwrap();
    assert!(stdout(&colored).contains("\x1b["));
    assert!(stdout(&colored).contains("battery_undervoltage_fault[fault]"), "severity spelled out");
    // NO_COLOR changes the default only; `--color always` wins (tests/integration/help_layout.rs).
    let plain = tracerctl().env("NO_COLOR", "1").args(["decode", "211#00000103010000B1"]).output().unwrap();
    assert!(!stdout(&plain).contains('\x1b'));
    let piped = tracerctl().args(["decode", "211#00000103010000B1"]).output().unwrap();
    assert!(!stdout(&piped).contains('\x1b'), "not a terminal: no colour");
}

#[test]
fn help_and_version() {
    let help = tracerctl().arg("--help").output().unwrap();
    assert!(stdout(&help).contains("decode"));
    let version = tracerctl().arg("--version").output().unwrap();
    assert_eq!(stdout(&version), format!("tracerctl {}\n", env!("CARGO_PKG_VERSION")));
    let missing = tracerctl().args(["decode", "/nonexistent/capture.log"]).output().unwrap();
    assert_eq!(missing.status.code(), Some(1));
    assert_eq!(
        stderr(&missing),
        "tracerctl: /nonexistent/capture.log: no such file (frames are written like 211#00000103000000B1)\n"
    );
}

#[test]
fn progress_bar_only_on_a_terminal_and_only_for_large_files() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("large.log");
    let line = "(1700000000.000000) can0 211#00000103000000B1\n";
    std::fs::write(&path, line.repeat(200_000)).unwrap(); // 9.2 MB, above the 8 MiB threshold
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    // `script` runs the command on a real pseudo-terminal, so stderr is a terminal.
    let on_terminal = |extra: &str| {
        let command =
            format!("'{}' decode --summary {extra} '{}' > /dev/null", binary.display(), path.display());
        let output =
            std::process::Command::new("script").args(["-qec", &command, "/dev/null"]).output().unwrap();
        assert!(output.status.success(), "{}", stderr(&output));
        String::from_utf8_lossy(&output.stdout).into_owned()
    };
    let shown = on_terminal("");
    assert!(shown.contains("MiB/"), "bytes done/total on the terminal: {shown:?}");
    assert!(!on_terminal("--no-progress").contains("MiB/"));
    // Not a terminal (the test's pipe): never a bar.
    let piped = tracerctl().args(["decode", "--summary"]).arg(&path).output().unwrap();
    assert_eq!(stderr(&piped), "");
}
