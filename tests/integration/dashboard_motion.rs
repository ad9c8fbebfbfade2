//! The armed dashboard keeps its word after a stop clears (issue 28, 1.2): the robot comes back from an
//! E-stop or an RC override in standby, and the screen says "press a key to drive". A fresh drive key
//! after the clear asks for command mode (0x421) and drives once the robot confirms; a key held from
//! before the clear never moves it. The real binary in tmux against `--sim`; its `--record` log is the
//! witness for what was sent.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::dashboard::{arm, sim_dashboard, Session};

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
    crate::dashboard::sent_ids(log).into_iter().filter(|frame| !frame.starts_with("121#")).collect()
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
    use crate::dashboard::{percents, PtyDashboard};
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
