//! The configuration file and its profiles, through the real binary: `TRACERCTL_CONFIG` points at a
//! temporary file; each precedence level is seen in `config show` and in what a command does.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::serial_peer::{healthy, FakeRobot};
use crate::util::{stderr, stdout, tracerctl};

const FILE: &str = r#"# A site's file.
[link]
iface = "can5"
protocol = "v2"

[drive]
max_linear = 0.6
key_timeout = "300ms"

[record]
max_total = "500MB"
triggers = ["battery_voltage<23.0", "motor_current>15"]
default_triggers = false

[profiles.tracer-07]
link.iface = "can1"
drive.max_linear = 0.8
drive.accel = 0.7

[profiles.slow]
drive.max_linear = 0.2
"#;

struct Config {
    _dir: tempfile::TempDir,
    path: PathBuf,
}

fn config(text: &str) -> Config {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("config.toml");
    std::fs::write(&path, text).unwrap();
    Config { _dir: dir, path }
}

fn run(config: &Path, env: &[(&str, &str)], args: &[&str]) -> Output {
    let mut command = tracerctl();
    command.env("TRACERCTL_CONFIG", config);
    for (name, value) in env {
        command.env(name, value);
    }
    command.args(args).output().unwrap()
}

/// `config show -f json`'s row for `key`.
fn shown(config: &Path, env: &[(&str, &str)], args: &[&str], key: &str) -> serde_json::Value {
    let mut args = args.to_vec();
    args.extend(["config", "show", "-f", "json"]);
    let output = run(config, env, &args);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let report: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    let rows = report["values"].as_array().unwrap();
    rows.iter().find(|row| row["key"] == key).cloned().unwrap_or_else(|| panic!("{key}: {report}"))
}

/// The cap drive says it applied when asked for 3 m/s on the simulator.
fn drive_cap(config: &Path, env: &[(&str, &str)], args: &[&str]) -> String {
    drive_cap_with(config, env, args, &[])
}

/// As [`drive_cap`], with drive's own options `drive_args`.
fn drive_cap_with(config: &Path, env: &[(&str, &str)], args: &[&str], drive_args: &[&str]) -> String {
    let mut all = args.to_vec();
    all.extend(["--sim", "drive", "--linear", "3", "--for", "100ms"]);
    all.extend(drive_args);
    let output = run(config, env, &all);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let said = stderr(&output);
    let capped = said.lines().find(|line| line.contains("capped:")).unwrap_or_else(|| panic!("{said}"));
    capped.split("-> ").nth(1).unwrap().split(' ').next().unwrap().to_string()
}

#[test]
fn each_precedence_level_in_config_show_and_in_drive() {
    let file = config(FILE);
    let path = file.path.as_path();
    let at = |line: u64| serde_json::json!(line);
    // Built-in default: no file at all.
    let none = config("");
    let row = shown(&none.path, &[], &[], "drive.max_linear");
    assert_eq!((row["value"].clone(), row["source"].clone()), (serde_json::json!(0.5), "default".into()));
    assert_eq!(drive_cap(&none.path, &[], &[]), "+0.500");
    // File beats default.
    let row = shown(path, &[], &[], "drive.max_linear");
    assert_eq!(
        (row["value"].clone(), row["source"].clone(), row["line"].clone()),
        (serde_json::json!(0.6), "file".into(), at(7))
    );
    assert_eq!(drive_cap(path, &[], &[]), "+0.600");
    // Profile beats file, chosen by the environment or by the option.
    let row = shown(path, &[("TRACERCTL_PROFILE", "tracer-07")], &[], "drive.max_linear");
    assert_eq!(
        (row["value"].clone(), row["source"].clone(), row["profile"].clone()),
        (serde_json::json!(0.8), "profile".into(), "tracer-07".into())
    );
    assert_eq!(drive_cap(path, &[("TRACERCTL_PROFILE", "tracer-07")], &[]), "+0.800");
    assert_eq!(drive_cap(path, &[], &["--profile", "slow"]), "+0.200");
    // --profile beats TRACERCTL_PROFILE.
    assert_eq!(drive_cap(path, &[("TRACERCTL_PROFILE", "tracer-07")], &["--profile", "slow"]), "+0.200");
    // The flag beats the profile.
    assert_eq!(drive_cap_with(path, &[], &["--profile", "tracer-07"], &["--max-linear", "0.3"]), "+0.300");
}

#[test]
fn the_interface_env_beats_the_profile_and_the_flag_beats_both() {
    let file = config(FILE);
    let path = file.path.as_path();
    let iface = |env: &[(&str, &str)], args: &[&str]| {
        let row = shown(path, env, args, "link.iface");
        (row["value"].as_str().unwrap().to_string(), row["source"].as_str().unwrap().to_string())
    };
    assert_eq!(iface(&[], &[]), ("can5".into(), "file".into()));
    assert_eq!(iface(&[], &["--profile", "tracer-07"]), ("can1".into(), "profile".into()));
    assert_eq!(
        iface(&[("TRACERCTL_IFACE", "can3")], &["--profile", "tracer-07"]),
        ("can3".into(), "env".into())
    );
    assert_eq!(
        iface(&[("TRACERCTL_IFACE", "can3")], &["--profile", "tracer-07", "--iface", "can4"]),
        ("can4".into(), "flag".into())
    );
    let row = shown(path, &[("TRACERCTL_IFACE", "can3")], &[], "link.iface");
    assert_eq!(row["variable"], "TRACERCTL_IFACE");
    // The protocol: a global option with a default the file replaces.
    assert_eq!(shown(path, &[], &[], "link.protocol")["value"], "v2");
    let row = shown(path, &[], &["--protocol", "v1"], "link.protocol");
    assert_eq!(
        (row["value"].as_str(), row["source"].as_str(), row["flag"].as_str()),
        (Some("v1"), Some("flag"), Some("--protocol"))
    );
}

#[test]
fn config_show_text_names_each_source() {
    let file = config(FILE);
    let output =
        run(&file.path, &[("TRACERCTL_PROFILE", "tracer-07")], &["--iface", "can9", "config", "show"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    let name = file.path.display();
    let line = |key: &str| {
        let found = text
            .lines()
            .find(|line| line.starts_with(&format!("{key} ")))
            .unwrap_or_else(|| panic!("{key}: {text}"));
        found.split_whitespace().collect::<Vec<_>>().join(" ")
    };
    assert!(text.starts_with(&format!("exists  {name}\n(TRACERCTL_CONFIG names the only file read)\nprofile tracer-07 (env TRACERCTL_PROFILE)\n")), "{text}");
    assert_eq!(line("link.iface"), "link.iface can9 flag --iface");
    assert_eq!(line("drive.max_linear"), format!("drive.max_linear 0.8 profile tracer-07 ({name}:17)"));
    assert_eq!(line("drive.key_timeout"), format!("drive.key_timeout 300ms file {name}:8"));
    assert_eq!(line("drive.max_angular"), "drive.max_angular 0.5 default");
    assert_eq!(line("link.baud"), "link.baud 115200 default");
    // The recorder's keys, read and shown before `record` takes them.
    assert_eq!(line("record.max_total"), format!("record.max_total 500MB file {name}:11"));
    assert_eq!(
        line("record.triggers"),
        format!("record.triggers [\"battery_voltage<23.0\", \"motor_current>15\"] file {name}:12")
    );
    assert_eq!(line("record.default_triggers"), format!("record.default_triggers false file {name}:13"));
    assert_eq!(line("record.segment"), "record.segment 1m default");
}

#[test]
fn a_profiles_serial_port_is_the_link_a_command_uses() {
    let robot = FakeRobot::start(healthy());
    let file =
        config(&format!("[link]\niface = \"can5\"\n[profiles.bench]\nlink.serial = \"{}\"\n", robot.path));
    let output = run(&file.path, &[], &["--profile", "bench", "drive", "--linear", "0.2", "--for", "300ms"]);
    assert_eq!(output.status.code(), Some(0), "{}{}", stdout(&output), stderr(&output));
    assert!(!robot.frames().is_empty(), "drive sent its frames to the profile's serial port");
    let row = shown(&file.path, &[], &["--profile", "bench"], "link.serial");
    assert_eq!(row["value"].as_str(), Some(robot.path.as_str()));
    // The profile's serial port replaces the file's CAN interface; `--sim` replaces both.
    assert_eq!(shown(&file.path, &[], &["--profile", "bench"], "link.iface")["source"], "default");
    let output =
        run(&file.path, &[], &["--profile", "bench", "--sim", "drive", "--linear", "0.2", "--for", "100ms"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
}

#[test]
fn a_file_cannot_raise_the_caps_above_the_robots_limits() {
    let file = config("[drive]\nmax_linear = 9\nmax_angular = 50\n");
    assert_eq!(drive_cap(&file.path, &[], &[]), "+1.500");
    let output = run(&file.path, &[], &["--sim", "drive", "--angular", "5", "--for", "100ms"]);
    assert!(stderr(&output).contains("-> +0.000 m/s +0.785 rad/s"), "{}", stderr(&output));
}

fn usage_error(text: &str, args: &[&str]) -> String {
    let file = config(text);
    let output = run(&file.path, &[], args);
    assert_eq!(output.status.code(), Some(2), "{}{}", stdout(&output), stderr(&output));
    assert_eq!(stdout(&output), "", "nothing done");
    let message = stderr(&output);
    message.replace(&file.path.display().to_string(), "FILE")
}

#[test]
fn unknown_keys_and_bad_values_are_usage_errors_at_file_line_column() {
    let run_sim = &["--sim", "drive", "--linear", "0.1", "--for", "100ms"][..];
    assert_eq!(
        usage_error("[drive]\nmax_linear = 0.5\nmax_linaer = 0.8\n", run_sim),
        "tracerctl: FILE:3:1: unknown key drive.max_linaer (did you mean drive.max_linear?)\n"
    );
    // The flag's own check and words, at the value.
    assert_eq!(
        usage_error("[drive]\nmax_linear = -1\n", run_sim),
        "tracerctl: FILE:2:14: drive.max_linear: '-1' is not a number from 0.001 to 100\n"
    );
    assert_eq!(
        usage_error("[drive]\nkey_timeout = \"5s\"\n", &["config", "show"]),
        "tracerctl: FILE:2:15: drive.key_timeout: '5s' is out of range: give a duration from 20ms to 1s 250ms (e.g. 2s, 500ms)\n"
    );
    assert_eq!(
        usage_error("[link]\nprotocol = \"v3\"\n", &["config", "show"]),
        "tracerctl: FILE:2:12: link.protocol: 'v3' is not one of auto, v1, v2\n"
    );
    assert_eq!(
        usage_error("[profiles.x]\nlink.baud = 0\n", &["config", "show"]),
        "tracerctl: FILE:2:13: link.baud: 0 is not in 1..=4000000\n"
    );
    // Limits that contradict each other: the file's value named by its key and place.
    assert_eq!(
        usage_error("[drive]\naccel = 2\n", run_sim),
        "tracerctl: FILE:2:9: --decel (1.5 m/s²) must be at least drive.accel (2 m/s²): braking is never weaker than speeding up\n"
    );
    assert!(usage_error("[drive\n", &["config", "show"]).starts_with("tracerctl: FILE:1:"));
    assert_eq!(
        usage_error("[record]\nmax_total = \"lots\"\n", &["config", "show"]),
        "tracerctl: FILE:2:13: record.max_total: 'lots' is not a size such as 1GiB, 500MB or 4096 (bytes)\n"
    );
}

#[test]
fn an_unknown_profile_is_a_usage_error_listing_the_profiles() {
    assert_eq!(
        usage_error(FILE, &["--profile", "tracer-08", "config", "show"]),
        "tracerctl: unknown profile 'tracer-08'; the profiles are: tracer-07, slow (in FILE)\n"
    );
    let file = config(FILE);
    let output = run(&file.path, &[("TRACERCTL_PROFILE", "nope")], &["--sim", "drive", "--linear", "0.1"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("unknown profile 'nope'"), "{}", stderr(&output));
}

#[test]
fn config_path_lists_the_files_even_when_one_is_wrong() {
    let file = config("[drive]\nmax_linaer = 1\n");
    let output = run(&file.path, &[], &["config", "path"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        format!("exists  {}\n(TRACERCTL_CONFIG names the only file read)\n", file.path.display())
    );
    // An override that names no file is an error naming it (exit 1); a directory cannot be read.
    let missing = file.path.with_file_name("absent.toml");
    let output = run(&missing, &[], &["config", "show"]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!("tracerctl: {} (TRACERCTL_CONFIG): no such file\n", missing.display())
    );
    let directory = file.path.parent().unwrap();
    let output = run(directory, &[], &["config", "show"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).starts_with(&format!("tracerctl: cannot read {}", directory.display())),
        "{}",
        stderr(&output)
    );
}

#[test]
fn the_standard_files_are_the_site_then_the_users() {
    let home = tempfile::tempdir().unwrap();
    let user_dir = home.path().join("xdg/tracerctl");
    std::fs::create_dir_all(&user_dir).unwrap();
    std::fs::write(user_dir.join("config.toml"), "[drive]\nmax_angular = 0.3\n").unwrap();
    let output = tracerctl()
        .env_remove("TRACERCTL_CONFIG")
        .env("XDG_CONFIG_HOME", home.path().join("xdg"))
        .args(["config", "path"])
        .output()
        .unwrap();
    let lines: Vec<String> = stdout(&output).lines().map(str::to_string).collect();
    assert_eq!(lines[1], format!("exists  {}", user_dir.join("config.toml").display()));
    assert!(lines[0].ends_with(" /etc/tracerctl/config.toml"), "{lines:?}");
    // The user's file is read (the site's may exist on this machine: only the user's value is checked).
    let output = tracerctl()
        .env_remove("TRACERCTL_CONFIG")
        .env("XDG_CONFIG_HOME", home.path().join("xdg"))
        .args(["config", "show", "-f", "json"])
        .output()
        .unwrap();
    let report: serde_json::Value =
        serde_json::from_str(&stdout(&output)).unwrap_or_else(|_| panic!("{}", stderr(&output)));
    let row = report["values"]
        .as_array()
        .unwrap()
        .iter()
        .find(|row| row["key"] == "drive.max_angular")
        .unwrap()
        .clone();
    assert_eq!((row["value"].clone(), row["line"].clone()), (serde_json::json!(0.3), serde_json::json!(2)));
}

#[test]
fn the_test_suite_reads_no_configuration_file() {
    // .cargo/config.toml sets these for every process cargo runs, so a binary spawned without the helper
    // (bash, tmux, std::process::Command) reads no one's file either.
    assert_eq!(std::env::var("TRACERCTL_CONFIG").as_deref(), Ok(""));
    assert_eq!(std::env::var("TRACERCTL_PROFILE").as_deref(), Ok(""));
    let output = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["config", "path"])
        .output()
        .unwrap();
    assert_eq!(stdout(&output), "(TRACERCTL_CONFIG is empty: no file is read)\n");
}

#[test]
fn the_configured_warning_voltage_is_the_one_doctor_judges_the_battery_by() {
    let battery = |text: &str| {
        let file = config(text);
        let output = run(&file.path, &[], &["--sim", "doctor", "--listen", "300ms", "-f", "json"]);
        let report: serde_json::Value =
            serde_json::from_str(&String::from_utf8(output.stdout).unwrap()).unwrap();
        let checks = report["checks"].as_array().unwrap();
        checks.iter().find(|check| check["id"] == "battery").unwrap().clone()
    };
    // The simulator's battery: 25.9 V.
    assert_eq!(battery("")["status"], "pass");
    let warned = battery("[battery]\nwarning_volts = 26.0\n");
    assert_eq!(warned["status"], "warn", "{warned}");
    assert!(warned["finding"].as_str().unwrap().contains("below the 26 V alarm voltage"), "{warned}");
}
