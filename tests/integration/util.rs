//! Helpers shared by the integration tests: run the real binary, find fixtures.
// Shared by the integration tests and the timing group (tests/timing): each binary uses a part.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Output;
use std::time::{Duration, Instant};

use assert_cmd::Command;

pub fn tracerctl() -> Command {
    let mut command = Command::cargo_bin("tracerctl").expect("binary built");
    command.env_remove("NO_COLOR").env_remove("TRACERCTL_IFACE");
    // No configuration file, no profile (.cargo/config.toml sets these for every process cargo runs; said
    // here too for a test binary run by hand). Tests of the files set TRACERCTL_CONFIG=FILE after this.
    command.env("TRACERCTL_CONFIG", "").env("TRACERCTL_PROFILE", "");
    command
}

pub fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

pub fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).expect("utf-8 output")
}

pub fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).expect("utf-8 errors")
}

/// Every line of standard output parsed as one JSON object.
pub fn json_lines(output: &Output) -> Vec<serde_json::Value> {
    stdout(output).lines().map(|line| serde_json::from_str(line).expect("valid JSON line")).collect()
}

/// Runs `tracerctl decode --format json ARGS` and parses every line.
pub fn decode_json(args: &[&str]) -> Vec<serde_json::Value> {
    let output = tracerctl().arg("decode").arg("--format").arg("json").args(args).output().unwrap();
    assert!(output.status.success(), "decode failed: {}", stderr(&output));
    json_lines(&output)
}

/// Sends `signal` to a child process.
pub fn signal(pid: u32, signal: i32) {
    // SAFETY: kill(2) on our own child.
    assert_eq!(unsafe { libc::kill(pid as libc::pid_t, signal) }, 0);
}

/// Waits for a child to end; kills it and fails the test after `timeout`.
pub fn wait_with_timeout(mut child: std::process::Child, timeout: Duration) -> Output {
    let deadline = Instant::now() + timeout;
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("tracerctl did not end within {timeout:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}
