//! The dashboard's stop windows, in tmux and on a pseudo-terminal with key release events.

use std::time::{Duration, Instant};

use crate::dashboard_driver::{
    arm, commanded, commanded_at, hold_up, percents, signal_dashboard, sim_dashboard,
};
use crate::dashboard_driver::{wall_clock, PtyDashboard, Session};

#[test]
fn space_sends_zero_at_once_and_a_held_key_needs_a_fresh_press() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("space.log");
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    // Full speed 1.5 m/s so a ramp would show: from there the old Space took 3.1 s.
    let command = format!(
        "{} --sim dashboard --max-linear 1.5 --accel 100 --decel 100 --record {}; sleep 30",
        binary.display(),
        log.display()
    );
    let session = Session::start(&format!("tracerctl-space-{}", std::process::id()), &command);
    let (up, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("│robot"));
    assert!(up, "{screen}");
    arm(&session);
    for _ in 0..10 {
        session.keys(&["+"]);
    }
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(1000) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    // Space while Up is still being held (auto-repeat goes on for a while): zero at once, and it stays zero.
    let space_at = wall_clock();
    session.keys(&["Space"]);
    let again = Instant::now();
    while again.elapsed() < Duration::from_millis(500) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    std::thread::sleep(Duration::from_millis(300));
    let timed = commanded_at(&log);
    let before: Vec<i16> = timed.iter().filter(|(at, _)| *at < space_at).map(|(_, mm)| *mm).collect();
    let after: Vec<(f64, i16)> = timed.iter().filter(|(at, _)| *at >= space_at).copied().collect();
    assert_eq!(before.last(), Some(&1500), "at full speed before Space: {before:?}");
    // The key takes a moment through tmux: a regular frame at full speed may still leave before it acts.
    let first_zero = after.iter().position(|(_, mm)| *mm == 0).expect("zero after Space");
    assert!(after[..first_zero].iter().all(|(_, mm)| *mm == 1500), "no ramp, straight to zero: {after:?}");
    assert!(after[first_zero].0 - space_at < 0.1, "zero within 0.1 s of Space: {after:?}");
    assert!(after[first_zero..].iter().all(|(_, mm)| *mm == 0), "the held key did not resume: {after:?}");
    // Let go (the deadline passes), press again: it drives.
    std::thread::sleep(Duration::from_millis(800));
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(500) {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
    std::thread::sleep(Duration::from_millis(100));
    assert!(commanded(&log).iter().rev().take(5).any(|mm| *mm > 0), "a fresh press drives again");
}

#[test]
fn ctrl_z_sends_zero_then_suspends_and_gives_the_terminal_back() {
    let (session, _dir, log) = sim_dashboard("tracerctl-ctrlz", "");
    arm(&session);
    hold_up(&session, Duration::from_millis(1500));
    let pressed_at = wall_clock();
    session.keys(&["C-z"]);
    // Suspended: the alternate screen is gone (the terminal was given back before stopping).
    let (gone, screen) = session.wait_for(Duration::from_secs(5), |s| !s.contains("│robot"));
    assert!(gone, "the terminal was given back:\n{screen}");
    std::thread::sleep(Duration::from_millis(700));
    let resumed_at = wall_clock();
    signal_dashboard("-CONT", &log);
    let (back, screen) =
        session.wait_for(Duration::from_secs(5), |s| s.contains("│robot") && s.contains("suspended for"));
    assert!(back, "the dashboard takes the terminal back and says why it holds zero:\n{screen}");
    std::thread::sleep(Duration::from_millis(400));
    // The record is written on its own thread, stamped when each frame was sent: read it after the resume.
    let timed = commanded_at(&log);
    let before: Vec<(f64, i16)> = timed.iter().filter(|(at, _)| *at < resumed_at).copied().collect();
    assert!(before.iter().any(|(_, mm)| *mm > 0), "it was driving: {before:?}");
    assert_eq!(
        before.last().map(|(_, mm)| *mm),
        Some(0),
        "the last frame before stopping is zero: {before:?}"
    );
    let first_zero = before.iter().find(|(at, mm)| *at >= pressed_at && *mm == 0).unwrap().0;
    assert!(first_zero - pressed_at < 0.2, "zero within 200 ms of Ctrl-Z: {}", first_zero - pressed_at);
    let while_stopped = before.iter().filter(|(at, _)| *at > pressed_at + 0.3).count();
    assert_eq!(while_stopped, 0, "nothing is sent while stopped: {before:?}");
    let after: Vec<i16> = timed.iter().filter(|(at, _)| *at >= resumed_at).map(|(_, mm)| *mm).collect();
    assert!(!after.is_empty() && after.iter().all(|mm| *mm == 0), "{after:?}");
    session.keys(&["q"]);
}

#[test]
fn with_release_events_a_release_brakes_to_zero_within_150_ms_of_frames() {
    use crate::serial_peer::{healthy, FakeRobot};
    let robot = FakeRobot::start(healthy());
    let mut dash = PtyDashboard::start(&robot.path, true);
    dash.wait_for("kitty protocol");
    dash.arm();
    std::thread::sleep(Duration::from_millis(200));
    // Press, repeats for 1.2 s (0.15 m/s = 10 % on RS232 once ramped), release.
    dash.type_keys(b"\x1b[1;1:1A");
    for _ in 0..36 {
        std::thread::sleep(Duration::from_millis(33));
        dash.type_keys(b"\x1b[1;1:2A");
    }
    let released = Instant::now();
    dash.type_keys(b"\x1b[1;1:3A");
    std::thread::sleep(Duration::from_millis(500));
    dash.quit();
    let frames = percents(&robot);
    let before: Vec<i8> = frames.iter().filter(|(at, _)| *at < released).map(|(_, p)| *p).collect();
    assert_eq!(before.last(), Some(&10), "at 0.15 m/s when released: {before:?}");
    let after: Vec<i8> = frames.iter().filter(|(at, _)| *at >= released).map(|(_, p)| *p).collect();
    let to_zero = after.iter().position(|p| *p == 0).expect("zero after the release");
    // 0.15 m/s at 1.5 m/s² is 0.1 s: five 20 ms frames, the first sent at once; 7 frames (140 ms) at most.
    // (At the old 0.5 m/s² it took 15 frames, 290 ms.)
    assert!(to_zero <= 6, "{to_zero} frames before zero after the release: {after:?}");
    assert!(after[..to_zero].windows(2).all(|w| w[1] <= w[0]), "braking, never speeding up: {after:?}");
    let zero_at = frames.iter().find(|(at, p)| *at >= released && *p == 0).unwrap().0;
    eprintln!("release event to zero: {:?} ({to_zero} frames)", zero_at - released);
}

/// An E-stop reported while driving: zero at once (and said on screen); a key still held does not resume
/// once it is released (the E-stop, then the key); a fresh press does. (Before: `keys +0.15 sent +0.15`
/// under E-STOP.)
#[test]
fn an_estop_sends_zero_and_driving_resumes_only_on_a_fresh_press_once_clear() {
    use crate::serial_peer::{healthy, FakeRobot};
    use tracerctl::protocol::message::{SystemState, VEHICLE_ESTOP};
    let robot = FakeRobot::start(healthy());
    let mut dash = PtyDashboard::start(&robot.path, true);
    dash.wait_for("kitty protocol");
    dash.arm();
    std::thread::sleep(Duration::from_millis(200));
    dash.forget();
    let hold = |dash: &mut PtyDashboard, how_long: Duration| {
        let until = Instant::now() + how_long;
        while Instant::now() < until {
            std::thread::sleep(Duration::from_millis(33));
            dash.type_keys(b"\x1b[1;1:2A");
        }
    };
    dash.type_keys(b"\x1b[1;1:1A");
    hold(&mut dash, Duration::from_millis(1000));
    dash.forget();
    let pressed = Instant::now();
    robot.set_status(SystemState { vehicle_state: VEHICLE_ESTOP, ..healthy() });
    // Up is still held (repeats go on) through the E-stop and after it is released.
    hold(&mut dash, Duration::from_millis(600));
    let cleared = Instant::now();
    robot.set_status(healthy());
    hold(&mut dash, Duration::from_millis(600));
    dash.type_keys(b"\x1b[1;1:3A");
    std::thread::sleep(Duration::from_millis(300));
    let frames = percents(&robot);
    let during: Vec<i8> = frames.iter().filter(|(at, _)| *at >= pressed).map(|(_, p)| *p).collect();
    assert!(
        frames.iter().any(|(at, p)| *at < pressed && *p == 10),
        "driving at 0.15 m/s before the E-stop: {frames:?}"
    );
    // The status comes every 20 ms: the zero follows within a few frames, and never a ramp back up.
    let first_zero = during.iter().position(|p| *p == 0).expect("zero after the E-stop");
    assert!(first_zero <= 5, "{during:?}");
    assert!(during[first_zero..].iter().all(|p| *p == 0), "held key never resumed: {during:?}");
    assert!(frames.iter().any(|(at, _)| *at > cleared), "still armed and sending");
    // A fresh press after the E-stop cleared drives again.
    let fresh = Instant::now();
    dash.type_keys(b"\x1b[1;1:1A");
    hold(&mut dash, Duration::from_millis(500));
    dash.type_keys(b"\x1b[1;1:3A");
    std::thread::sleep(Duration::from_millis(200));
    dash.quit();
    let again: Vec<i8> = percents(&robot).iter().filter(|(at, _)| *at >= fresh).map(|(_, p)| *p).collect();
    assert!(again.contains(&10), "a fresh press drives again: {again:?}");
    assert_eq!(again.last(), Some(&0));
}
