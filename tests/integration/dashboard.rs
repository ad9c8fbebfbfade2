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

pub(crate) struct Session {
    pub(crate) name: String,
    _guard: std::sync::MutexGuard<'static, ()>,
}

/// One dashboard at a time: each draws 20 times a second next to a simulator, and several at once on the
/// two-core build machine starve each other's loops past the 250 ms watchdog (which then, rightly, holds
/// zero until the keys are let go).
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

impl Session {
    pub(crate) fn start(name: &str, command: &str) -> Self {
        let guard = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let _ = Command::new("tmux").args(["kill-session", "-t", name]).output();
        let status = Command::new("tmux")
            .args(["new-session", "-d", "-s", name, "-x", "120", "-y", "40", command])
            .status()
            .expect("tmux is installed (apt-get install tmux)");
        assert!(status.success());
        Self { name: name.to_string(), _guard: guard }
    }

    pub(crate) fn screen(&self) -> String {
        tmux(&["capture-pane", "-p", "-t", &self.name])
    }

    pub(crate) fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", &self.name];
        args.extend_from_slice(keys);
        tmux(&args);
    }

    /// Waits until the screen satisfies `check`; the last screen either way.
    pub(crate) fn wait_for(&self, timeout: Duration, check: impl Fn(&str) -> bool) -> (bool, String) {
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

/// Seconds since the epoch, as the record's timestamps.
pub(crate) fn wall_clock() -> f64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs_f64()
}

/// (timestamp, commanded linear speed in mm/s) of every 0x111 in a candump log.
fn commanded_at(log: &Path) -> Vec<(f64, i16)> {
    let output = tracerctl().args(["decode", "--format", "json", "--id", "0x111"]).arg(log).output().unwrap();
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).unwrap();
            let at = value["ts"].as_f64().expect("a timestamp");
            (at, (value["fields"]["linear_velocity"].as_f64().unwrap() * 1000.0).round() as i16)
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

/// Starts `tracerctl --sim dashboard EXTRA --record LOG` in tmux and waits for it to draw; the temporary
/// directory holding the log lives as long as the returned handle.
pub(crate) fn sim_dashboard(name: &str, extra: &str) -> (Session, tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("session.log");
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command =
        format!("{} --sim dashboard {extra} --record {}; sleep 30", binary.display(), log.display());
    let session = Session::start(&format!("{name}-{}", std::process::id()), &command);
    let (up, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("│robot"));
    assert!(up, "{screen}");
    (session, dir, log)
}

/// Arms driving: `a`, the prompt, `y`; the header says ARMED.
pub(crate) fn arm(session: &Session) {
    session.keys(&["a"]);
    let (asked, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("Arm driving?"));
    assert!(asked, "a asks before arming:\n{screen}");
    session.keys(&["y"]);
    let (armed, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("· ARMED ·"));
    assert!(armed, "y arms:\n{screen}");
}

/// Every 0x111 and 0x421 the dashboard sent, from its `--record` log (lines marked as sent by tracerctl
/// are the ones with these identifiers: the simulator never sends them).
pub(crate) fn sent_ids(log: &Path) -> Vec<String> {
    std::fs::read_to_string(log)
        .unwrap_or_default()
        .lines()
        .filter_map(|line| line.split_whitespace().nth(2))
        .filter(|frame| frame.starts_with("111#") || frame.starts_with("421#") || frame.starts_with("121#"))
        .map(str::to_string)
        .collect()
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
        let _ = Command::new("tmux").args(["kill-session", "-t", &session.name]).output();
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

/// Sends a signal to the dashboard that writes `log` (only to it: not the shell around it, nor the tmux
/// server, whose command line can hold the same text).
fn signal_dashboard(signal: &str, log: &Path) {
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let pattern = format!("^{} .*dashboard --record {}", binary.display(), log.display());
    let status = Command::new("pkill").args([signal, "-f", &pattern]).status().unwrap();
    assert!(status.success(), "the dashboard process was found for {signal}");
}

/// Holds Up (a key every 33 ms, as a terminal's auto-repeat) for `how_long`.
fn hold_up(session: &Session, how_long: Duration) {
    let start = Instant::now();
    while start.elapsed() < how_long {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
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

/// The dashboard on a 100x30 pseudo-terminal this test owns; with `kitty`, it answers the keyboard-protocol
/// query as kitty, foot or WezTerm would, so the dashboard gets key release events.
pub(crate) struct PtyDashboard {
    child: std::process::Child,
    keys: serialport::TTYPort,
    shown: std::sync::Arc<std::sync::Mutex<String>>,
    done: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

impl PtyDashboard {
    pub(crate) fn start(robot_path: &str, kitty: bool) -> Self {
        use serialport::SerialPort;
        use std::io::{Read, Write};
        use std::sync::atomic::{AtomicBool, Ordering};
        use std::sync::{Arc, Mutex};
        let (terminal, terminal_slave) = serialport::TTYPort::pair().unwrap();
        let terminal_path = terminal_slave.name().unwrap();
        drop(terminal_slave);
        // A 100x30 terminal (a new pseudo-terminal is 0x0, where nothing is drawn).
        let size = libc::winsize { ws_row: 30, ws_col: 100, ws_xpixel: 0, ws_ypixel: 0 };
        // SAFETY: TIOCSWINSZ with a valid winsize on an open pseudo-terminal.
        unsafe { libc::ioctl(std::os::fd::AsRawFd::as_raw_fd(&terminal), libc::TIOCSWINSZ, &size) };
        let open = || std::fs::OpenOptions::new().read(true).write(true).open(&terminal_path).unwrap();
        let child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .args(["--serial", robot_path, "dashboard"])
            .env("TERM", "xterm-256color")
            .stdin(open())
            .stdout(open())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let done = Arc::new(AtomicBool::new(false));
        let shown = Arc::new(Mutex::new(String::new()));
        {
            let (mut screen, mut answer) = (terminal.try_clone().unwrap(), terminal.try_clone().unwrap());
            let (done, shown) = (Arc::clone(&done), Arc::clone(&shown));
            std::thread::spawn(move || {
                let mut buffer = [0u8; 65536];
                screen.set_timeout(Duration::from_millis(50)).unwrap();
                while !done.load(Ordering::SeqCst) {
                    if let Ok(read) = screen.read(&mut buffer) {
                        let text = &buffer[..read];
                        if kitty && text.windows(4).any(|w| w == b"\x1b[?u") {
                            let _ = answer.write_all(b"\x1b[?0u\x1b[?62;22c");
                        }
                        let mut shown = shown.lock().unwrap();
                        shown.push_str(&String::from_utf8_lossy(text));
                        let keep = shown.len().saturating_sub(50_000);
                        shown.drain(..keep);
                    }
                }
            });
        }
        Self { child, keys: terminal, shown, done }
    }

    /// Waits until `needle` was drawn (since the last `forget`).
    pub(crate) fn wait_for(&self, needle: &str) {
        let deadline = Instant::now() + Duration::from_secs(10);
        while !self.shown.lock().unwrap().contains(needle) {
            assert!(Instant::now() < deadline, "{needle:?} never shown");
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn forget(&self) {
        self.shown.lock().unwrap().clear();
    }

    pub(crate) fn type_keys(&mut self, bytes: &[u8]) {
        std::io::Write::write_all(&mut self.keys, bytes).unwrap();
    }

    pub(crate) fn arm(&mut self) {
        self.type_keys(b"a");
        self.wait_for("Arm driving?");
        self.type_keys(b"y");
        self.wait_for("ARMED");
    }

    pub(crate) fn quit(mut self) {
        self.type_keys(b"q");
        let _ = self.child.wait();
        self.done.store(true, std::sync::atomic::Ordering::SeqCst);
    }
}

/// (arrival, linear percent) of the RS232 motion frames a fake robot received.
pub(crate) fn percents(robot: &crate::serial_peer::FakeRobot) -> Vec<(Instant, i8)> {
    robot
        .frames()
        .iter()
        .filter(|(_, f)| f.frame_type == 0x55 && f.command == 0x01)
        .map(|(at, f)| (*at, f.payload[2] as i8))
        .collect()
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
