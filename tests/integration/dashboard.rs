//! The dashboard end to end: the real binary inside tmux against `--sim`. Keys go in with `send-keys`, the
//! screen comes back with `capture-pane`, and the session's `--record` log is the witness for what was sent.
//! tmux does not pass key releases, so this exercises the auto-repeat deadline path.

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use crate::util::tracerctl;

fn tmux(args: &[&str]) -> String {
    let output = Command::new("tmux").args(args).output().expect("tmux is installed (apt-get install tmux)");
    String::from_utf8_lossy(&output.stdout).into_owned()
}

struct Session {
    name: String,
}

impl Session {
    fn start(name: &str, command: &str) -> Self {
        let _ = Command::new("tmux").args(["kill-session", "-t", name]).output();
        let status = Command::new("tmux")
            .args(["new-session", "-d", "-s", name, "-x", "120", "-y", "40", command])
            .status()
            .expect("tmux is installed (apt-get install tmux)");
        assert!(status.success());
        Self { name: name.to_string() }
    }

    fn screen(&self) -> String {
        tmux(&["capture-pane", "-p", "-t", &self.name])
    }

    fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", &self.name];
        args.extend_from_slice(keys);
        tmux(&args);
    }

    /// Waits until the screen satisfies `check`; the last screen either way.
    fn wait_for(&self, timeout: Duration, check: impl Fn(&str) -> bool) -> (bool, String) {
        let deadline = Instant::now() + timeout;
        loop {
            let screen = self.screen();
            if check(&screen) {
                return (true, screen);
            }
            if Instant::now() > deadline {
                return (false, screen);
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        let _ = Command::new("tmux").args(["kill-session", "-t", &self.name]).output();
    }
}

/// The commanded linear speed of every 0x111 in a candump log, in mm/s.
fn commanded(log: &Path) -> Vec<i16> {
    let output = tracerctl().args(["decode", "--format", "json", "--id", "0x111"]).arg(log).output().unwrap();
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).unwrap();
            (value["fields"]["linear_velocity"].as_f64().unwrap() * 1000.0).round() as i16
        })
        .collect()
}

/// The robot's measured linear speed as the speeds panel shows it (its `robot` row: m/s, rad/s).
fn measured(screen: &str) -> Option<f64> {
    screen.lines().find_map(|line| {
        let after = line.split("│robot").nth(1)?;
        after.split_whitespace().next()?.parse().ok()
    })
}

#[test]
fn arrows_drive_the_simulator_release_stops_it_and_q_restores_the_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("session.log");
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    // A shell around it prints the exit status afterwards and keeps the pane open to be read.
    let command = format!(
        "{} --sim dashboard --record {}; echo \"exit status $?\"; sleep 30",
        binary.display(),
        log.display()
    );
    let session = Session::start(&format!("tracerctl-test-{}", std::process::id()), &command);
    let (up, screen) =
        session.wait_for(Duration::from_secs(10), |s| s.contains("tracerctl") && s.contains("sim"));
    assert!(up, "the dashboard came up:\n{screen}");
    assert!(screen.contains("key release: auto-repeat timeout"), "tmux passes no releases:\n{screen}");

    // Hold Up: tmux forwards one key per send, like a terminal's auto-repeat (33 ms interval). Halfway
    // through, the robot must be moving.
    let pressed = Instant::now();
    let mut while_held = None;
    while pressed.elapsed() < Duration::from_millis(3000) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
        if while_held.is_none() && pressed.elapsed() > Duration::from_millis(2000) {
            while_held = Some(session.screen());
        }
    }
    let screen = while_held.unwrap();
    let speed = measured(&screen).expect("a speeds panel");
    assert!(speed > 0.05, "the measured speed on screen moved while Up was held ({speed}):\n{screen}");
    assert!(screen.contains("keys    +0.15"), "the keys ask for 30 % of 0.5 m/s:\n{screen}");

    // Let go: the deadline expires, the ramp brings the command to zero, the robot stops.
    let (stopped, screen) =
        session.wait_for(Duration::from_secs(3), |s| measured(s).is_some_and(|v| v.abs() < 0.005));
    assert!(stopped, "the robot stopped after the key was released:\n{screen}");

    session.keys(&["q"]);
    let (ended, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("exit status"));
    assert!(ended, "q ends the dashboard:\n{screen}");
    assert!(screen.contains("exit status 0"), "{screen}");
    assert!(
        screen.contains("tracerctl: quit: the robot was stopped"),
        "back on the normal screen:\n{screen}"
    );
    assert!(!screen.contains("│robot"), "the alternate screen is gone:\n{screen}");
    // The shell is in its normal (cooked, echoing) mode again: typed text appears as typed.
    session.keys(&["echo restored-$((6*7))", "Enter"]);
    let (echoed, screen) = session.wait_for(Duration::from_secs(2), |s| s.contains("echo restored-"));
    assert!(echoed || screen.contains("restored-42"), "{screen}");

    let speeds = commanded(&log);
    assert!(speeds.iter().any(|mm| *mm > 50), "the record shows motion commands: {speeds:?}");
    assert_eq!(speeds.last(), Some(&0), "the record ends with zero velocity");
}

#[test]
fn refuses_without_a_terminal() {
    let output = tracerctl().args(["--sim", "dashboard"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("the dashboard needs a terminal"));
}

/// Starts a dashboard in tmux, drives for a moment, and ends it with `finish`; returns the commands recorded.
fn drive_then(name: &str, finish: impl FnOnce(&Session, &Path)) -> Vec<i16> {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("session.log");
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command = format!("{} --sim dashboard --record {}; sleep 30", binary.display(), log.display());
    let session = Session::start(&format!("{name}-{}", std::process::id()), &command);
    let (up, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("│robot"));
    assert!(up, "{screen}");
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(1500) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    // Still held: the last commands move the robot.
    assert!(commanded(&log).last().is_some_and(|mm| *mm > 0), "driving before the exit");
    finish(&session, &log);
    std::thread::sleep(Duration::from_millis(500));
    commanded(&log)
}

#[test]
fn ssh_drop_sigterm_and_ctrl_c_all_leave_zero_velocity_on_the_bus() {
    // The terminal goes away, as when SSH drops: tmux hangs up on the process (SIGHUP).
    let speeds = drive_then("tracerctl-hup", |session, _| {
        let _ = Command::new("tmux").args(["kill-session", "-t", &session.name]).output();
    });
    assert_eq!(speeds.last(), Some(&0), "SIGHUP: {speeds:?}");

    let speeds = drive_then("tracerctl-term", |_, log| {
        let pattern = format!("dashboard --record {}", log.display());
        let status = Command::new("pkill").args(["-TERM", "-f", &pattern]).status().unwrap();
        assert!(status.success(), "the dashboard process was found");
    });
    assert_eq!(speeds.last(), Some(&0), "SIGTERM: {speeds:?}");

    let speeds = drive_then("tracerctl-ctrlc", |session, _| {
        session.keys(&["C-c"]);
        let (ended, screen) =
            session.wait_for(Duration::from_secs(5), |s| s.contains("quit: the robot was stopped"));
        assert!(ended, "Ctrl-C quits:\n{screen}");
    });
    assert_eq!(speeds.last(), Some(&0), "Ctrl-C: {speeds:?}");
}
