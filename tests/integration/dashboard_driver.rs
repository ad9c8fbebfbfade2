//! Driving the real dashboard from a test: in tmux (`Session`: keys with `send-keys`, the screen with
//! `capture-pane`) or on a pseudo-terminal the test owns (`PtyDashboard`), and reading back what it sent from
//! its `--record` log. Shared by the integration tests and the timing group (tests/timing).
// Shared by the integration tests and the timing group (tests/timing): each binary uses a part.
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use crate::util::tracerctl;

/// Runs tmux against the server listening on `socket`.
fn tmux_on(socket: &Path, args: &[&str]) -> std::process::Output {
    Command::new("tmux")
        .arg("-S")
        .arg(socket)
        .args(args)
        .output()
        .expect("tmux is installed (apt-get install tmux)")
}

/// A tmux session on its own server, whose socket lives in a directory of the test's: no test shares a
/// server with another, nor with one on its way out after its last session ended.
pub(crate) struct Session {
    pub(crate) name: String,
    socket: std::path::PathBuf,
    _socket_dir: tempfile::TempDir,
    _guard: std::sync::MutexGuard<'static, ()>,
}

/// One dashboard at a time: each draws 20 times a second next to a simulator, and several at once on the
/// two-core build machine starve each other's loops past the 250 ms watchdog (which then, rightly, holds
/// zero until the keys are let go).
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

impl Session {
    pub(crate) fn start(name: &str, command: &str) -> Self {
        let guard = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        let socket_dir = tempfile::tempdir().expect("a temporary directory for the tmux socket");
        let socket = socket_dir.path().join("tmux");
        // A starting server can fail on a loaded machine (CI once saw new-session exit non-zero with no
        // other tmux running): try again, and say what tmux said if it never starts.
        let mut said = Vec::new();
        for attempt in 0..3 {
            let output =
                tmux_on(&socket, &["new-session", "-d", "-s", name, "-x", "120", "-y", "40", command]);
            if output.status.success() {
                return Self { name: name.to_string(), socket, _socket_dir: socket_dir, _guard: guard };
            }
            said.push(format!(
                "attempt {attempt}: {} {}",
                output.status,
                String::from_utf8_lossy(&output.stderr).trim()
            ));
            std::thread::sleep(Duration::from_millis(200));
        }
        panic!("tmux new-session never started:\n{}", said.join("\n"));
    }

    /// Runs tmux on this session's server; its standard output.
    pub(crate) fn tmux(&self, args: &[&str]) -> String {
        String::from_utf8_lossy(&tmux_on(&self.socket, args).stdout).into_owned()
    }

    /// Ends the session as a closed terminal would: tmux hangs up on the process (SIGHUP).
    pub(crate) fn hang_up(&self) {
        let _ = tmux_on(&self.socket, &["kill-session", "-t", &self.name]);
    }

    /// Resizes the window (tmux keeps a detached session at the size it is given).
    pub(crate) fn resize(&self, width: u16, height: u16) {
        let output = tmux_on(
            &self.socket,
            &["resize-window", "-t", &self.name, "-x", &width.to_string(), "-y", &height.to_string()],
        );
        assert!(output.status.success(), "tmux resize-window: {}", String::from_utf8_lossy(&output.stderr));
    }

    pub(crate) fn screen(&self) -> String {
        self.tmux(&["capture-pane", "-p", "-t", &self.name])
    }

    pub(crate) fn keys(&self, keys: &[&str]) {
        let mut args = vec!["send-keys", "-t", &self.name];
        args.extend_from_slice(keys);
        self.tmux(&args);
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
        let _ = tmux_on(&self.socket, &["kill-server"]);
    }
}

/// The commanded linear speed of every 0x111 in a candump log, in mm/s.
pub(crate) fn commanded(log: &Path) -> Vec<i16> {
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
pub(crate) fn commanded_at(log: &Path) -> Vec<(f64, i16)> {
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

/// Sends a signal to the dashboard that writes `log` (only to it: not the shell around it, nor the tmux
/// server, whose command line can hold the same text).
pub(crate) fn signal_dashboard(signal: &str, log: &Path) {
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let pattern = format!("^{} .*dashboard --record {}", binary.display(), log.display());
    let status = Command::new("pkill").args([signal, "-f", &pattern]).status().unwrap();
    assert!(status.success(), "the dashboard process was found for {signal}");
}

/// Holds Up (a key every 33 ms, as a terminal's auto-repeat) for `how_long`.
pub(crate) fn hold_up(session: &Session, how_long: Duration) {
    let start = Instant::now();
    while start.elapsed() < how_long {
        session.keys(&["Up"]);
        std::thread::sleep(Duration::from_millis(33));
    }
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

    pub(crate) fn forget(&self) {
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
