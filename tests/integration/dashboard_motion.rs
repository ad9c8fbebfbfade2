//! The dashboard's motion and prompt rules of issue 28 (1.2, 1.7) on the real binary: after a stop clears
//! into a robot out of command mode, a fresh press asks for command mode and the key held since drives once
//! confirmed (on a pseudo-terminal with key-release events: no timing involved); `c` while watching arms
//! and goes on to the clear prompt; a replay's footer offers only what works (tmux against `--sim`). The
//! tmux version of the first, which relies on auto-repeat timing, is in the timing group
//! (tests/timing/dashboard_mode.rs).

use std::time::{Duration, Instant};

use crate::dashboard_driver::{sim_dashboard, Session};

/// `c` while watching asks to arm; `y` arms and goes on to the clear prompt it was pressed for (issue 28,
/// 1.7: it armed and forgot the clear). The clear itself still asks first: nothing is sent but 0x421.
#[test]
fn clear_while_watching_arms_then_asks_to_clear() {
    let (session, _dir, log) = sim_dashboard("tracerctl-clear-arm", "");
    session.keys(&["c"]);
    let (asked, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("Arm driving?"));
    assert!(asked, "c asks to arm first:\n{screen}");
    session.keys(&["y"]);
    // The header follows the arming state at its next refresh (every 50 ms), the prompt at once.
    let (clear, screen) =
        session.wait_for(Duration::from_secs(5), |s| s.contains("Clear faults?") && s.contains("· ARMED ·"));
    assert!(clear, "armed, then the clear prompt:\n{screen}");
    session.keys(&["n"]);
    let (closed, screen) = session.wait_for(Duration::from_secs(5), |s| !s.contains("Clear faults?"));
    assert!(closed, "{screen}");
    std::thread::sleep(Duration::from_millis(300));
    let record = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(!record.contains(" 441#"), "no clear was sent without its own yes");
    session.keys(&["q"]);
}

/// A replay cannot be driven: its footer offers only the keys that do something there.
#[test]
fn a_replay_footer_offers_only_what_works() {
    let log = crate::util::data("tracer_session.log");
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command = format!("{} --replay {} dashboard; sleep 30", binary.display(), log.display());
    let session = Session::start(&format!("tracerctl-replay-footer-{}", std::process::id()), &command);
    let (up, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("│robot"));
    assert!(up, "{screen}");
    let footer = screen.lines().find(|line| line.trim_end().ends_with("q quit")).unwrap_or_default();
    assert_eq!(footer.split_whitespace().collect::<Vec<_>>().join(" "), "? help q quit", "{screen}");
    session.keys(&["q"]);
}

/// With key-release events (a kitty-protocol terminal): the fresh press after an E-stop clears into a robot
/// out of command mode asks for it, nothing moves until the robot reports it, and then the key held since
/// that press drives without being pressed again (before: the confirmation dropped the held key, and a
/// repeat never revives one).
#[test]
fn with_release_events_the_key_held_since_the_fresh_press_drives_once_confirmed() {
    use crate::dashboard_driver::{percents, PtyDashboard};
    use crate::serial_peer::{healthy, FakeRobot};
    use tracerctl::protocol::message::{SystemState, VEHICLE_ESTOP};
    let robot = FakeRobot::start(healthy());
    let mut dash = PtyDashboard::start(&robot.path, true);
    dash.wait_for("kitty protocol");
    dash.arm();
    let hold = |dash: &mut PtyDashboard, how_long: Duration| {
        let until = Instant::now() + how_long;
        while Instant::now() < until {
            std::thread::sleep(Duration::from_millis(33));
            dash.type_keys(b"\x1b[1;1:2A");
        }
    };
    std::thread::sleep(Duration::from_millis(200));
    dash.type_keys(b"\x1b[1;1:1A");
    hold(&mut dash, Duration::from_millis(800));
    dash.type_keys(b"\x1b[1;1:3A");
    robot.set_status(SystemState { vehicle_state: VEHICLE_ESTOP, ..healthy() });
    dash.wait_for("E-STOP");
    // Released, and back in mode 0 (RC on RS232: not the serial command mode) as after a power cycle.
    robot.set_status(SystemState { control_mode: 0, ..healthy() });
    dash.wait_for("clear again");
    std::thread::sleep(Duration::from_millis(300));
    let pressed = Instant::now();
    dash.type_keys(b"\x1b[1;1:1A");
    hold(&mut dash, Duration::from_millis(400));
    // The robot takes serial mode from the frames it was sent.
    let confirmed = Instant::now();
    robot.set_status(healthy());
    hold(&mut dash, Duration::from_millis(1000));
    dash.type_keys(b"\x1b[1;1:3A");
    std::thread::sleep(Duration::from_millis(300));
    // (The screen's words are checked in tmux above: a raw terminal stream redraws only changed cells.)
    dash.quit();
    let frames = percents(&robot);
    let waiting: Vec<i8> =
        frames.iter().filter(|(at, _)| *at >= pressed && *at < confirmed).map(|(_, p)| *p).collect();
    assert!(!waiting.is_empty() && waiting.iter().all(|p| *p == 0), "nothing moves before: {waiting:?}");
    let after: Vec<i8> = frames.iter().filter(|(at, _)| *at >= confirmed).map(|(_, p)| *p).collect();
    assert!(after.contains(&10), "the held key drives once confirmed: {after:?}");
    assert_eq!(after.last(), Some(&0), "and brakes to zero on release");
}
