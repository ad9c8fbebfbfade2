//! The armed dashboard keeps its word after a stop clears (issue 28, 1.2), in tmux against `--sim`: the
//! robot comes back from an E-stop or an RC override in standby; a fresh drive key after the clear asks
//! for command mode (0x421) and drives once the robot confirms; a key held from before the clear never
//! moves it. Its `--record` log is the witness for what was sent. In the timing group: "held" is a key
//! repeated by tmux faster than the dashboard's 150 ms quiet, which a loaded machine can miss.
//! (The same rule with key-release events, which needs no timing, is in the default run:
//! tests/integration/dashboard_motion.rs.)

use std::path::Path;
use std::time::{Duration, Instant};

use crate::dashboard_driver::{arm, sim_dashboard, Session};

/// Holds Up (a key every 33 ms, as a terminal's auto-repeat) for `how_long`.
fn hold_up(session: &Session, how_long: Duration) {
    let start = Instant::now();
    while start.elapsed() < how_long {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
}

/// The frames the dashboard sent (0x421 and 0x111), in order, from its record.
fn sent(log: &Path) -> Vec<String> {
    crate::dashboard_driver::sent_ids(log).into_iter().filter(|frame| !frame.starts_with("121#")).collect()
}

/// Whether a 0x111 frame commands motion.
fn moving(frame: &str) -> bool {
    frame.starts_with("111#") && frame != "111#0000000000000000"
}

/// Arms, drives, lets `stop` block driving and `clear` end the block, holds Up through the clear (which
/// must not drive), then presses Up afresh: command mode is requested again and the robot moves.
fn resumes_after(name: &str, stop: &str, clear: &str, blocked_words: &str) {
    let faults = format!("--fault {stop}@4s --fault {clear}@7s");
    let (session, _dir, log) = sim_dashboard(name, &faults);
    arm(&session);
    // Driving until the stop, when the start was quick enough (a loaded machine may arm after it).
    hold_up(&session, Duration::from_millis(800));

    let (blocked, screen) = session.wait_for(Duration::from_secs(8), |s| s.contains(blocked_words));
    assert!(blocked, "the stop is shown:\n{screen}");
    let before_clear = sent(&log).len();
    // Up held from before the clear until well after it: a key pressed before the clear never drives.
    let (mut cleared, mut screen) = (false, String::new());
    let until = Instant::now() + Duration::from_secs(8);
    while !cleared && Instant::now() < until {
        hold_up(&session, Duration::from_millis(100));
        screen = session.screen();
        cleared = screen.contains("clear again");
    }
    assert!(cleared, "the clear is shown:\n{screen}");
    hold_up(&session, Duration::from_millis(700));
    let held_through: Vec<String> = sent(&log)[before_clear..].to_vec();
    assert!(
        !held_through.iter().any(|frame| moving(frame)),
        "a key held through the clear drove: {held_through:?}"
    );
    assert!(
        !held_through.contains(&"421#01".to_string()),
        "nothing asked for before a fresh press: {held_through:?}"
    );

    // Let go, then a fresh press: command mode is asked for, confirmed, and the held key drives.
    std::thread::sleep(Duration::from_millis(400));
    let before_press = sent(&log).len();
    hold_up(&session, Duration::from_millis(1500));
    let (said, screen) = session.wait_for(Duration::from_secs(3), |s| s.contains("command mode confirmed"));
    let after: Vec<String> = sent(&log)[before_press..].to_vec();
    let asked = after.iter().position(|frame| frame == "421#01");
    let first_motion = after.iter().position(|frame| moving(frame));
    assert!(asked.is_some(), "command mode asked for again after the clear: {after:?}\n{screen}");
    assert!(first_motion.is_some_and(|at| at > asked.unwrap()), "it drives after asking: {after:?}");
    assert!(said, "the confirmation is said:\n{screen}");
    session.keys(&["q"]);
}

#[test]
fn after_an_estop_release_a_fresh_key_asks_for_command_mode_and_drives() {
    resumes_after("tracerctl-estop-mode", "estop", "estop-release", "E-STOP");
}

#[test]
fn after_rc_override_ends_a_fresh_key_asks_for_command_mode_and_drives() {
    resumes_after("tracerctl-swb-mode", "swb-middle", "swb-top", "RC transmitter has control");
}
