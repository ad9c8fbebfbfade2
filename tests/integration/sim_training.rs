//! The simulator as a training tool: `--fault NAME@TIME` with `--sim` for every command (the in-process
//! robot shows a CAN V2 E-stop, latched motor fault or dying battery without vcan), the fault language in
//! `sim --help`, and the completion of `--fault`'s values.

use std::time::Duration;

use serde_json::Value;
use tracerctl::exit::{NOT_DONE, SUCCESS, USAGE};
use tracerctl::sim::FaultKind;

use crate::util::{json_lines, stderr, stdout, tracerctl};

/// `tracerctl --sim --fault FAULT doctor --format json`: the exit status and the report.
fn doctor(faults: &[&str]) -> (i32, Value) {
    let mut command = tracerctl();
    command.arg("--sim");
    for fault in faults {
        command.args(["--fault", fault]);
    }
    let output = command.args(["doctor", "--format", "json", "--listen", "400ms"]).output().unwrap();
    let report = serde_json::from_slice(&output.stdout)
        .unwrap_or_else(|error| panic!("{error}: {}{}", stdout(&output), stderr(&output)));
    (output.status.code().unwrap(), report)
}

/// The (status, finding) of the doctor's check with this id.
fn check(report: &Value, id: &str) -> (String, String) {
    let check = report["checks"]
        .as_array()
        .unwrap()
        .iter()
        .find(|check| check["id"] == id)
        .unwrap_or_else(|| panic!("no check {id} in {report:#}"));
    (check["status"].as_str().unwrap().to_string(), check["finding"].as_str().unwrap().to_string())
}

#[test]
fn fault_without_sim_is_a_usage_error_naming_sim() {
    let commands: [&[&str]; 8] = [
        &["doctor"],
        &["dashboard"],
        &["monitor", "--duration", "1s"],
        &["drive", "--linear", "0.1", "--for", "1s"],
        &["mode", "can"],
        &["clear-errors"],
        &["lights", "--release"],
        &["send-raw", "121#0101000000000000"],
    ];
    for args in commands {
        for placement in [&["--fault", "estop@0s"][..], &["--iface", "vcan0", "--fault", "estop"]] {
            let output = tracerctl().args(placement).args(args).output().unwrap();
            assert_eq!(output.status.code(), Some(i32::from(USAGE)), "{placement:?} {args:?}");
            let message = stderr(&output);
            assert!(message.contains("add --sim"), "{args:?}: {message}");
        }
    }
    // The option is global: after the command too.
    let output = tracerctl().args(["doctor", "--fault", "estop"]).output().unwrap();
    assert_eq!(output.status.code(), Some(i32::from(USAGE)));
    // decode reads files: --fault is refused with the other live-link options.
    let output = tracerctl().args(["decode", "--fault", "estop", "-"]).output().unwrap();
    assert_eq!(output.status.code(), Some(i32::from(USAGE)));
    assert!(stderr(&output).contains("--fault is for live links; decode reads files"), "{}", stderr(&output));
}

#[test]
fn fault_names_and_times_are_checked_for_sim_and_for_the_in_process_robot() {
    for args in [&["--sim", "--fault", "motor3-comm", "doctor"][..], &["sim", "--fault", "motor3-comm"]] {
        let output = tracerctl().args(args).output().unwrap();
        assert_eq!(output.status.code(), Some(i32::from(USAGE)), "{args:?}");
        let message = stderr(&output);
        assert!(
            message.contains("unknown fault \"motor3-comm\"; known faults: estop, estop-release,"),
            "{message}"
        );
    }
    let output = tracerctl().args(["--sim", "--fault", "estop@soon", "doctor"]).output().unwrap();
    assert_eq!(output.status.code(), Some(i32::from(USAGE)));
    assert!(stderr(&output).contains("bad time \"soon\""), "{}", stderr(&output));
}

#[test]
fn doctor_on_the_sim_fails_the_estop_check() {
    let (code, report) = doctor(&["estop@0s"]);
    assert_eq!(code, i32::from(NOT_DONE));
    assert_eq!(check(&report, "estop"), ("fail".into(), "pressed: the robot will not move".into()));
    assert_eq!(check(&report, "faults").0, "pass");
    assert_eq!(report["drivable"], false);
}

#[test]
fn doctor_on_the_sim_fails_a_latched_motor_fault_and_a_dying_battery() {
    let (code, report) = doctor(&["motor1-comm@0s", "battery-low"]);
    assert_eq!(code, i32::from(NOT_DONE));
    let (status, finding) = check(&report, "faults");
    assert_eq!(status, "fail");
    assert!(finding.starts_with("0x0300: battery_undervoltage_fault [fault]"), "{finding}");
    assert!(finding.contains("motor 1 can_disconnected [fault]"), "{finding}");
    let (status, finding) = check(&report, "battery");
    assert_eq!((status.as_str(), finding.as_str()), ("fail", "21.8 V: below the 22 V protection voltage"));
    assert_eq!(check(&report, "estop").0, "pass");
}

#[test]
fn doctor_on_a_healthy_sim_passes_the_fault_checks() {
    let (_, report) = doctor(&[]);
    for id in ["estop", "faults", "battery"] {
        assert_eq!(check(&report, id).0, "pass", "{id}: {report:#}");
    }
}

#[test]
fn clear_errors_clears_a_latched_fault_in_the_sim_and_reports_one_that_stays() {
    let output = tracerctl().args(["--sim", "--fault", "motor2-comm@0s", "clear-errors"]).output().unwrap();
    assert_eq!(output.status.code(), Some(i32::from(SUCCESS)), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.contains("cleared: motor2 can_disconnected [fault]"), "{text}");
    assert!(text.contains("status: normal"), "{text}");

    // A driver at 70 °C stays latched until it cools under 65 °C.
    let output = tracerctl().args(["--sim", "--fault", "motor1-overheat", "clear-errors"]).output().unwrap();
    assert_eq!(output.status.code(), Some(i32::from(NOT_DONE)));
    let text = stdout(&output);
    assert!(text.contains("remaining: motor1 driver_overheat"), "{text}");
    assert!(stderr(&output).contains("motor 1's driver is at 70 °C"), "{}", stderr(&output));
}

#[test]
fn monitor_on_the_sim_sees_the_fault_bits_from_their_time() {
    let output = tracerctl()
        .args(["--sim", "--fault", "rc-lost@300ms", "--fault", "motor1-comm@300ms", "monitor"])
        .args(["--format", "json", "--duration", "700ms"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(i32::from(SUCCESS)), "{}", stderr(&output));
    let frames = json_lines(&output);
    let systems: Vec<&Value> = frames.iter().filter(|f| f["msg"] == "system_state").collect();
    assert!(systems.len() >= 20, "{} system states", systems.len());
    // Before 300 ms nothing is set; after, the RC-disconnected bit (0x0400) and vehicle state exception.
    assert_eq!(systems[0]["fields"]["fault_code"], 0);
    assert_eq!(systems[0]["fields"]["vehicle_state"], "normal");
    let last = systems.last().unwrap();
    assert_eq!(last["fields"]["fault_code"], 0x0400);
    assert_eq!(last["fields"]["faults"], serde_json::json!(["rc_disconnected"]));
    assert_eq!(last["fields"]["vehicle_state"], "exception");
    let motor1 = frames.iter().rfind(|f| f["msg"] == "motor_low_speed" && f["fields"]["motor"] == 1).unwrap();
    let faults = motor1["fields"]["driver_faults"].as_array().unwrap();
    assert!(faults.contains(&Value::from("can_disconnected")), "{motor1}");
}

#[test]
fn the_dashboard_on_the_sim_shows_a_fault_latching() {
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command = format!("{} --sim --fault motor1-comm@1s dashboard --watch; sleep 30", binary.display());
    let session = crate::dashboard::Session::start(&format!("simtrain-{}", std::process::id()), &command);
    let (up, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("│robot"));
    assert!(up, "{screen}");
    assert!(!screen.contains("can_disconnected"), "not before its time:\n{screen}");
    let (latched, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("can_disconnected"));
    assert!(latched, "the latched fault shows:\n{screen}");
    session.keys(&["q"]);
}

#[test]
fn sim_help_documents_every_fault_and_the_run_time_language() {
    let output = tracerctl().args(["sim", "--help"]).output().unwrap();
    let help = stdout(&output);
    for fault in FaultKind::ALL {
        let line = format!("  {:<18}  {}", fault.name(), fault.description());
        assert!(help.contains(&line), "{line:?} missing from:\n{help}");
    }
    assert!(help.contains("type one NAME per line on standard input: it acts at once"), "{help}");
    assert!(help.contains("tracerctl --sim --fault estop@0s doctor"), "{help}");
    let _files = crate::generated::GENERATED_FILES.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let man = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/man/tracerctl-sim.1"),
    )
    .unwrap();
    assert!(man.contains("motor1\\-overheat") && man.contains("standard input"), "the man page has it too");
}

#[test]
fn the_bash_completion_offers_the_fault_names() {
    let _files = crate::generated::GENERATED_FILES.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let script = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("completions/tracerctl.bash"),
    )
    .unwrap();
    let names: Vec<&str> = FaultKind::ALL.iter().map(|fault| fault.name()).collect();
    let offered = format!("compgen -W \"{}\"", names.join(" "));
    assert!(script.contains(&offered), "no `{offered}` in completions/tracerctl.bash");
    // Every command that takes --sim completes it, and `--fault` never falls back to file names.
    let fault_cases = script.matches("        --fault)\n").count();
    let completing = script.matches(&offered).count();
    assert!(
        fault_cases >= 10 && completing == fault_cases,
        "{fault_cases} --fault cases, {completing} complete names"
    );
}

#[test]
fn sim_answers_every_line_typed_on_its_standard_input() {
    use std::io::Write;
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["sim", "--pty", "--duration", "1500ms"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(b"estop\n\n  Motor1_Comm \nbogus\nestop-release@2s\n").unwrap();
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(i32::from(SUCCESS)));
    let lines: Vec<String> =
        stderr(&output).lines().filter(|line| line.starts_with("sim: ")).map(str::to_string).collect();
    assert_eq!(
        lines,
        [
            "sim: injected estop".to_string(),
            "sim: injected Motor1_Comm".to_string(),
            format!("sim: unknown fault \"bogus\"; known faults: {}", FaultKind::names()),
            "sim: not injected: a fault typed here acts at once, so type the name alone (estop-release); \
             --fault NAME@TIME schedules one from the start"
                .to_string(),
        ]
    );
    // The status line shows both (RS232 on a pseudo-terminal: motor 1 communication is bit 0x0004).
    let report = stderr(&output);
    assert!(report.contains("estop, 25.9 V, fault code 0x0004, motion blocked: estop"), "{report}");
}
