//! `tracerctl sim --pty` as a separate process, the robot a test drives over the pseudo-terminal it prints:
//! faults typed on its standard input, its link silenced with SIGSTOP. Shared by the integration tests and
//! the timing group (tests/timing): each binary uses a part.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, Command, Stdio};

/// A running `sim --pty`; killed (woken first, if stopped) when dropped.
pub struct PtySim {
    child: Child,
    /// The pseudo-terminal to drive it on.
    pub path: String,
}

impl PtySim {
    /// The test's own build, for `duration` (`20s`), with `extra` arguments (`--fault estop@0s`).
    pub fn start(duration: &str, extra: &[&str]) -> Self {
        Self::start_with(&assert_cmd::cargo::cargo_bin("tracerctl"), duration, extra)
    }

    /// `binary`'s simulator; no configuration file is read.
    pub fn start_with(binary: &Path, duration: &str, extra: &[&str]) -> Self {
        let mut child = Command::new(binary)
            .args(["sim", "--pty", "--duration", duration])
            .args(extra)
            .env("TRACERCTL_CONFIG", "")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut first = String::new();
        stdout.read_line(&mut first).unwrap();
        let path = first.strip_prefix("PTY ").expect("`PTY <path>` first").trim().to_string();
        // Keep reading (and dropping) what it says, so it never blocks on a full pipe.
        std::thread::spawn(move || std::io::copy(&mut stdout, &mut std::io::sink()));
        Self { child, path }
    }

    /// Types a line on the simulator's standard input (a fault name: `estop`, `battery-low`, ...).
    pub fn inject(&mut self, line: &str) {
        writeln!(self.child.stdin.as_mut().unwrap(), "{line}").unwrap();
    }

    /// Stops the simulator (SIGSTOP): the robot falls silent; [`Self::resume`] or dropping wakes it.
    pub fn pause(&self) {
        self.signal(libc::SIGSTOP);
    }

    pub fn resume(&self) {
        self.signal(libc::SIGCONT);
    }

    fn signal(&self, signal: i32) {
        // SAFETY: kill(2) on our own child, which has not been waited for (its pid is still ours).
        unsafe { libc::kill(self.child.id() as i32, signal) };
    }
}

impl Drop for PtySim {
    fn drop(&mut self) {
        self.resume();
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
