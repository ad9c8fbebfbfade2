//! The dashboard end to end: the real binary inside tmux against `--sim`. Keys go in with `send-keys`, the
//! screen comes back with `capture-pane`, and the session's `--record` log is the witness for what was sent.
//! tmux does not pass key releases, so this exercises the auto-repeat deadline path.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::util::tracerctl;

pub(crate) use crate::dashboard_driver::*;

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
    // The footer says "key release: -" until the terminal has answered (or not) the keyboard query: on a
    // loaded machine, after the first screens.
    let (settled, screen) = session
        .wait_for(Duration::from_secs(10), |s| s.contains("key release:") && !s.contains("key release: -"));
    assert!(
        settled && screen.contains("key release: auto-repeat timeout"),
        "tmux passes no releases:\n{screen}"
    );
    arm(&session);

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
fn opens_watching_and_sends_nothing_until_armed() {
    let (session, _dir, log) = sim_dashboard("tracerctl-watch", "");
    let screen = session.screen();
    assert!(screen.contains("· WATCHING ·"), "{screen}");
    // Watching for a second: the simulator's feedback is recorded, nothing is sent.
    std::thread::sleep(Duration::from_millis(1000));
    // An arrow key asks to arm and does not drive; any other key keeps watching.
    session.keys(&["Up"]);
    let (asked, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("Arm driving?"));
    assert!(asked, "{screen}");
    session.keys(&["n"]);
    let (closed, screen) = session.wait_for(Duration::from_secs(5), |s| !s.contains("Arm driving?"));
    assert!(closed && screen.contains("· WATCHING ·"), "{screen}");
    session.keys(&["l"]);
    session.keys(&["Escape"]);
    std::thread::sleep(Duration::from_millis(300));
    let recorded = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(recorded.lines().count() > 20, "the feedback was recorded: {recorded}");
    assert_eq!(sent_ids(&log), Vec::<String>::new(), "watching sends nothing");

    // Armed: 0x421 first, then motion at 50 Hz; a disarms: zeros, then nothing more.
    arm(&session);
    std::thread::sleep(Duration::from_millis(500));
    session.keys(&["a"]);
    let (disarmed, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("· WATCHING ·"));
    assert!(disarmed, "{screen}");
    std::thread::sleep(Duration::from_millis(200));
    let sent = sent_ids(&log);
    assert_eq!(sent.first().map(String::as_str), Some("421#01"), "{sent:?}");
    assert!(sent.len() > 15, "about 25 motion frames in 0.5 s: {sent:?}");
    std::thread::sleep(Duration::from_millis(500));
    assert_eq!(sent_ids(&log), sent, "nothing is sent once disarmed");
    assert_eq!(sent.last().map(String::as_str), Some("111#0000000000000000"));
}

#[test]
fn watch_only_never_arms() {
    let (session, _dir, log) = sim_dashboard("tracerctl-watchonly", "--watch");
    assert!(session.screen().contains("WATCH ONLY"), "{}", session.screen());
    for key in ["a", "Up", "y", "m", "y", "c", "y"] {
        session.keys(&[key]);
        std::thread::sleep(Duration::from_millis(50));
    }
    let (said, screen) = session.wait_for(Duration::from_secs(3), |s| s.contains("watch-only (--watch)"));
    assert!(said, "{screen}");
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(sent_ids(&log), Vec::<String>::new());
    session.keys(&["q"]);
    let (ended, screen) =
        session.wait_for(Duration::from_secs(5), |s| s.contains("nothing was sent (never armed)"));
    assert!(ended, "{screen}");
}

#[test]
fn refuses_without_a_terminal() {
    let output = tracerctl().args(["--sim", "dashboard"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("the dashboard needs a terminal"));
}

/// Starts a dashboard in tmux, drives for a moment, and ends it with `finish`; returns the commands recorded.
fn drive_then(name: &str, finish: impl FnOnce(&Session, &Path)) -> Vec<i16> {
    let (session, _dir, log) = sim_dashboard(name, "");
    arm(&session);
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(1500) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    // It drove (on a loaded machine tmux may deliver the repeats late, and the deadline brakes in between,
    // so the very last frame need not be moving).
    assert!(
        commanded(&log).iter().rev().take(50).any(|mm| *mm > 0),
        "driving before the exit:\n{}",
        session.screen()
    );
    finish(&session, &log);
    std::thread::sleep(Duration::from_millis(500));
    commanded(&log)
}

#[test]
fn ssh_drop_sigterm_and_ctrl_c_all_leave_zero_velocity_on_the_bus() {
    // The terminal goes away, as when SSH drops: tmux hangs up on the process (SIGHUP).
    let speeds = drive_then("tracerctl-hup", |session, _| {
        session.hang_up();
    });
    assert_eq!(speeds.last(), Some(&0), "SIGHUP: {speeds:?}");

    let speeds = drive_then("tracerctl-term", |_, log| signal_dashboard("-TERM", log));
    assert_eq!(speeds.last(), Some(&0), "SIGTERM: {speeds:?}");

    let speeds = drive_then("tracerctl-ctrlc", |session, _| {
        session.keys(&["C-c"]);
        let (ended, screen) =
            session.wait_for(Duration::from_secs(5), |s| s.contains("quit: the robot was stopped"));
        assert!(ended, "Ctrl-C quits:\n{screen}");
    });
    assert_eq!(speeds.last(), Some(&0), "Ctrl-C: {speeds:?}");
}

#[test]
fn after_sigstop_the_first_frame_is_zero_and_keys_typed_meanwhile_do_not_drive() {
    let (session, _dir, log) = sim_dashboard("tracerctl-sigstop", "");
    arm(&session);
    hold_up(&session, Duration::from_millis(1500));
    // Stopped while the key still counts as held; keys typed while it is stopped pile up in the terminal.
    signal_dashboard("-STOP", &log);
    std::thread::sleep(Duration::from_millis(300));
    for _ in 0..10 {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    std::thread::sleep(Duration::from_millis(900));
    let resumed_at = wall_clock();
    signal_dashboard("-CONT", &log);
    let (said, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("suspended for"));
    assert!(said, "the dashboard says what happened:\n{screen}");
    std::thread::sleep(Duration::from_millis(600));
    let timed = commanded_at(&log);
    assert!(timed.iter().any(|(at, mm)| *at < resumed_at && *mm > 0), "it was driving: {timed:?}");
    let after: Vec<i16> = timed.iter().filter(|(at, _)| *at >= resumed_at).map(|(_, mm)| *mm).collect();
    assert!(!after.is_empty(), "still armed and sending after the resume");
    assert!(after.iter().all(|mm| *mm == 0), "no motion after the resume, backlog included: {after:?}");
    // A fresh press drives again.
    hold_up(&session, Duration::from_millis(600));
    std::thread::sleep(Duration::from_millis(100));
    assert!(commanded(&log).iter().rev().take(30).any(|mm| *mm > 0), "a fresh press drives");
}
