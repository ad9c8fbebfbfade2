//! Issue 10 §6, the fault-injection suite: a misbehaving robot ([`FaultyRobot`], on the master side of a real
//! pseudo-terminal) and a misbehaving host (signals, suspension, a closed stderr) against the real binary
//! (`tracerctl --serial PTY drive ...`). Every scenario asserts what reached the wire, with arrival times, and
//! the exit status and message; the behaviour asserted is docs' contract for issue 10 (`drive` section).
//!
//! Every check of a scenario is evaluated before it fails, so a failure lists everything that went wrong,
//! followed by the evidence: the motion commands the robot received (runs of equal commands, with arrival
//! times from the start of `drive`, and the moments the test acted), the exit status and stderr.
//!
//! Timing on a loaded machine: waits poll with generous deadlines; the only tight margins are the contract's
//! (a zero frame within 50 ms of a signal). An arrival time is when the fake robot read the frame, which can
//! only make the host look slower, never faster.

use std::io::{BufRead, BufReader, Read};
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::process::ExitStatusExt;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::fault_peer::{estop, exception, healthy, FaultyRobot, MotionFeedback};
use tracerctl::control::STOP_FRAMES;

/// The contract: a zero-velocity frame reaches the robot within 50 ms of a signal.
const ZERO_WITHIN: Duration = Duration::from_millis(50);
/// Longer than the robot's 500 ms command timeout (issue 10 §1 used 0.8 s).
const SUSPENSION: Duration = Duration::from_millis(800);
/// 0.3 m/s is 20 % of the RS232 full scale (1.5 m/s).
const FULL_SPEED: (i8, i8) = (20, 0);
/// How long to wait for the host to get going (generous: a loaded 2-core machine).
const START: Duration = Duration::from_secs(10);
/// A stopped process cannot write; a frame it wrote just before it stopped may still be read this late by
/// the fake robot's thread on a loaded machine (a test-side allowance, not a contract margin).
const READ_LATENESS: Duration = Duration::from_millis(50);

type Motion = [(Instant, (i8, i8))];

/// A run of equal commands in the evidence is split at a silence longer than this (five periods).
const GAP: Duration = Duration::from_millis(100);

fn moving(speed: (i8, i8)) -> bool {
    speed != (0, 0)
}

fn sleep_until(at: Instant) {
    let now = Instant::now();
    if at > now {
        std::thread::sleep(at - now);
    }
}

/// Lets the fake robot read what is still in flight after the host ended.
fn settle() {
    std::thread::sleep(Duration::from_millis(100));
}

// ---------------------------------------------------------------------------------------------------------
// The host: the real binary as a child process.

struct Drive {
    child: Child,
    pid: i32,
    spawned: Instant,
    stderr: Option<JoinHandle<String>>,
}

/// How the binary ended.
struct Outcome {
    status: ExitStatus,
    /// False when it was still running at the deadline and the test had to end it (SIGCONT, SIGINT, SIGKILL).
    on_its_own: bool,
    stderr: String,
}

impl Outcome {
    /// The exit status the binary chose, if it ended by itself with one.
    fn code(&self) -> Option<i32> {
        self.status.code().filter(|_| self.on_its_own)
    }

    fn describe(&self) -> String {
        let status = match (self.status.code(), self.status.signal()) {
            (Some(code), _) => format!("exit {code}"),
            (None, Some(signal)) => format!("killed by signal {signal}"),
            _ => format!("{:?}", self.status),
        };
        if self.on_its_own {
            status
        } else {
            format!("still running at the deadline; ended by the test ({status})")
        }
    }
}

impl Drive {
    /// `tracerctl --serial PTY drive ARGS`, stderr collected.
    fn spawn(robot: &FaultyRobot, args: &[&str]) -> Self {
        let (mut drive, mut pipe) = Self::spawn_with_output(robot, args);
        drive.stderr = Some(std::thread::spawn(move || {
            let mut text = String::new();
            let _ = pipe.read_to_string(&mut text);
            text
        }));
        drive
    }

    /// The same, the caller reading (or closing) stdout and stderr: one pipe, in the order they were written
    /// (the status and report go to stdout, diagnostics to stderr).
    fn spawn_with_output(robot: &FaultyRobot, args: &[&str]) -> (Self, std::fs::File) {
        let mut fds = [0; 2];
        // SAFETY: pipe2 fills the two descriptors, owned from here on (close-on-exec: no other child
        // spawned meanwhile keeps the write end open).
        assert_eq!(unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) }, 0, "pipe2");
        // SAFETY: the two descriptors pipe2 just returned, owned by nothing else.
        let (read, write) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
        let spawned = Instant::now();
        let child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .env_remove("NO_COLOR")
            .env_remove("TRACERCTL_IFACE")
            .args(["--serial", &robot.path, "drive"])
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::from(write.try_clone().unwrap()))
            .stderr(Stdio::from(write))
            .spawn()
            .expect("tracerctl runs");
        let pid = child.id() as i32;
        (Self { child, pid, spawned, stderr: None }, std::fs::File::from(read))
    }

    /// Sends `signal`; the moment just before it was sent.
    fn signal(&self, signal: i32) -> Instant {
        let at = Instant::now();
        // SAFETY: kill(2) on our own child, not yet reaped (Drive reaps it only in `finish` or drop).
        assert_eq!(unsafe { libc::kill(self.pid, signal) }, 0, "kill({}, {signal})", self.pid);
        at
    }

    /// The process state letter of /proc/PID/stat (R, S, T, Z...).
    fn state(&self) -> Option<char> {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", self.pid)).ok()?;
        stat.rsplit_once(')')?.1.trim_start().chars().next()
    }

    /// When the process was first seen in `state`, polling every millisecond.
    fn wait_state(&self, state: char, timeout: Duration) -> Option<Instant> {
        let deadline = Instant::now() + timeout;
        while Instant::now() < deadline {
            if self.state() == Some(state) {
                return Some(Instant::now());
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        None
    }

    /// True until the process has ended (it may not be reaped yet).
    fn running(&mut self) -> bool {
        self.child.try_wait().unwrap().is_none()
    }

    /// True once the process has `path` open.
    fn has_open(&self, path: &str) -> bool {
        let Ok(fds) = std::fs::read_dir(format!("/proc/{}/fd", self.pid)) else { return false };
        fds.flatten().any(|fd| std::fs::read_link(fd.path()).is_ok_and(|target| target.as_os_str() == path))
    }

    /// Waits up to `timeout` for the binary to end by itself; past it, ends it (SIGCONT in case it is
    /// stopped, SIGINT as an operator would, then SIGKILL).
    fn finish(&mut self, timeout: Duration) -> Outcome {
        let deadline = Instant::now() + timeout;
        let mut on_its_own = true;
        let status = loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                break status;
            }
            if Instant::now() > deadline {
                on_its_own = false;
                self.signal(libc::SIGCONT);
                self.signal(libc::SIGINT);
                let grace = Instant::now() + Duration::from_secs(3);
                while self.child.try_wait().unwrap().is_none() && Instant::now() < grace {
                    std::thread::sleep(Duration::from_millis(10));
                }
                let _ = self.child.kill();
                break self.child.wait().unwrap();
            }
            std::thread::sleep(Duration::from_millis(5));
        };
        let stderr = self.stderr.take().map(|reader| reader.join().unwrap()).unwrap_or_default();
        Outcome { status, on_its_own, stderr }
    }
}

impl Drop for Drive {
    fn drop(&mut self) {
        // A test that panicked half-way must not leave a driver running.
        if self.child.try_wait().ok().flatten().is_none() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// Waits until the motion commands satisfy `check`. If they never do (the binary ended, or the deadline
/// passed), ends the drive, records the failure with its evidence, and returns None: the scenario stops.
fn reach(
    verdict: &mut Verdict,
    robot: &FaultyRobot,
    drive: &mut Drive,
    what: &str,
    check: impl Fn(&Motion) -> bool,
) -> Option<Instant> {
    let deadline = Instant::now() + START;
    while Instant::now() < deadline && drive.running() {
        if check(&robot.motion()) {
            return Some(Instant::now());
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    if check(&robot.motion()) {
        return Some(Instant::now());
    }
    let outcome = drive.finish(Duration::from_secs(1));
    verdict.no_unasked_stall(&outcome);
    verdict.check(false, format!("setup: the robot never received {what} ({})", outcome.describe()));
    verdict.evidence(&robot.motion(), drive.spawned, &[], &outcome);
    None
}

// ---------------------------------------------------------------------------------------------------------
// Evidence and checks.

/// The motion commands as runs of equal commands, with the test's actions interleaved, times from `t0`.
fn timeline(motion: &Motion, t0: Instant, marks: &[(&str, Instant)]) -> String {
    let since = |at: Instant| {
        if at >= t0 {
            format!("+{:.3}", at.duration_since(t0).as_secs_f64())
        } else {
            format!("-{:.3}", t0.duration_since(at).as_secs_f64())
        }
    };
    let mut events: Vec<(Instant, u8, String)> =
        marks.iter().map(|(name, at)| (*at, 0, format!("<< {name}"))).collect();
    let mut start = 0;
    while start < motion.len() {
        let speed = motion[start].1;
        // A run ends at another command, or at a gap of more than five periods (a stopped sender).
        let end = (start + 1..motion.len())
            .find(|&i| motion[i].1 != speed || motion[i].0.duration_since(motion[i - 1].0) > GAP)
            .unwrap_or(motion.len());
        let (first, last) = (motion[start].0, motion[end - 1].0);
        let run = if end - start == 1 {
            String::new()
        } else {
            format!(" x{} (to {} s)", end - start, since(last))
        };
        events.push((first, 1, format!("{:>4} % {:>4} %{run}", speed.0, speed.1)));
        start = end;
    }
    events.sort_by_key(|(at, order, _)| (*at, *order));
    events.iter().map(|(at, _, text)| format!("  {:>8} s  {text}\n", since(*at))).collect()
}

/// Attempts of a case in which the binary reported a suspension the test did not cause.
const ATTEMPTS: usize = 3;

/// Runs a scenario of one case and fails once with every failed check and the evidence.
fn scenario(name: &'static str, body: impl Fn(&mut Verdict)) {
    let mut verdict = Verdict::new(name);
    verdict.case("", body);
    verdict.conclude();
}

/// Collects every failed check of a scenario, then fails once with all of them and the evidence.
#[derive(Default)]
struct Verdict {
    scenario: &'static str,
    case: String,
    failures: Vec<String>,
    evidence: Vec<String>,
    /// The binary said it was suspended (its own clock jumped) where the test suspended nothing.
    stalled: bool,
    notes: Vec<String>,
}

impl Verdict {
    fn new(scenario: &'static str) -> Self {
        Self { scenario, ..Self::default() }
    }

    /// Runs one case of the scenario and keeps its failures and evidence.
    ///
    /// The contract ends `drive` after any gap of more than 200 ms in the sender's own clock ("suspended for
    /// 0.21 s (no command for more than 200 ms) ... drive ended"), and after its main loop stalls for more
    /// than 250 ms (the watchdog). On a loaded 2-core machine (a VM suite and builds next to this one) a
    /// debug binary is sometimes descheduled that long with nobody touching it. An attempt that failed *and*
    /// in which the binary reported such a stall, in a case that suspends nothing, is recorded and run
    /// again, at most three times; the checks are never relaxed, and the last attempt counts whatever
    /// happened.
    fn case(&mut self, name: &str, body: impl Fn(&mut Verdict)) {
        for attempt in 1..=ATTEMPTS {
            let mut case = Verdict { scenario: self.scenario, case: name.to_string(), ..Verdict::default() };
            body(&mut case);
            if !case.failures.is_empty() && case.stalled && attempt < ATTEMPTS {
                let note = format!(
                    "{}attempt {attempt} discarded: the binary reported a suspension or stall the test \
                     did not cause (the machine stalled it); its failures were: {}",
                    case.prefix(),
                    case.failures.join("; ")
                );
                eprintln!("{}: {note}", self.scenario);
                self.notes.push(note);
                continue;
            }
            self.failures.extend(case.failures);
            self.evidence.extend(case.evidence);
            self.notes.extend(case.notes);
            return;
        }
    }

    fn prefix(&self) -> String {
        if self.case.is_empty() {
            String::new()
        } else {
            format!("[{}] ", self.case)
        }
    }

    fn check(&mut self, ok: bool, claim: impl Into<String>) {
        if !ok {
            let prefix = self.prefix();
            self.failures.push(format!("{prefix}{}", claim.into()));
        }
    }

    fn exit(&mut self, outcome: &Outcome, expected: i32) {
        self.check(
            outcome.code() == Some(expected),
            format!("exit {expected} (got: {})", outcome.describe()),
        );
    }

    fn stderr_has(&mut self, outcome: &Outcome, text: &str) {
        self.check(outcome.stderr.contains(text), format!("stderr contains {text:?}"));
    }

    /// For cases that suspend nothing: the binary must not say it was suspended or that its own loop
    /// stalled (if it does, the machine stalled it; see `case`).
    fn no_unasked_stall(&mut self, outcome: &Outcome) {
        let stalled = ["suspended for", "stalled for"].iter().any(|text| outcome.stderr.contains(text));
        self.stalled |= stalled;
        self.check(!stalled, "no suspension or stall reported (the test suspended nothing)");
    }

    /// The first zero frame at or after `at` arrived within `within`; nothing non-zero after it.
    fn zero_within(&mut self, motion: &Motion, at: Instant, within: Duration, what: &str) {
        match motion.iter().position(|(arrived, speed)| *arrived >= at && !moving(*speed)) {
            Some(first) => {
                let after = motion[first].0.duration_since(at);
                self.check(
                    after <= within,
                    format!("a zero frame within {within:?} of {what} (after {after:?})"),
                );
                let moved = motion[first..].iter().filter(|(_, speed)| moving(*speed)).count();
                self.check(
                    moved == 0,
                    format!("no non-zero frame after the zero that followed {what} ({moved})"),
                );
            }
            None => self.check(false, format!("a zero frame within {within:?} of {what} (none at all)")),
        }
    }

    fn ends_with_zero(&mut self, motion: &Motion) {
        let last = motion.last().map(|(_, speed)| *speed);
        self.check(last == Some((0, 0)), format!("the last frame the robot received is zero ({last:?})"));
    }

    /// The evidence of this case, kept if any check failed.
    fn evidence(&mut self, motion: &Motion, t0: Instant, marks: &[(&str, Instant)], outcome: &Outcome) {
        if self.failures.is_empty() {
            return;
        }
        self.evidence.push(format!(
            "{}{}\nwire (arrival from the start of drive, linear % angular %):\n{}stderr:\n{}",
            self.prefix(),
            outcome.describe(),
            timeline(motion, t0, marks),
            outcome.stderr
        ));
    }

    fn conclude(self) {
        if self.failures.is_empty() {
            return;
        }
        let notes =
            if self.notes.is_empty() { String::new() } else { format!("\n\n{}", self.notes.join("\n")) };
        panic!(
            "{}: {} check(s) failed:\n  - {}\n\n{}{notes}",
            self.scenario,
            self.failures.len(),
            self.failures.join("\n  - "),
            self.evidence.join("\n")
        );
    }
}

fn at_full_speed(motion: &Motion) -> bool {
    motion.iter().any(|(_, speed)| *speed == FULL_SPEED)
}

// ---------------------------------------------------------------------------------------------------------
// §1 Suspension and resume.

/// SIGSTOP at full speed, SIGCONT 800 ms later (longer than the robot's 500 ms command timeout: it stopped
/// by itself). Today's binary resumes at once at 20 % (issue 10 §1). Contract: the first frame after SIGCONT
/// is zero, nothing non-zero after it, exit 1, "suspended for X.XX s ... drive ended".
#[test]
fn suspend_resume_sigstop() {
    scenario("suspend_resume_sigstop", |verdict| {
        let robot = FaultyRobot::start(healthy());
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3"]);
        if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
            return;
        }
        let stop_at = drive.signal(libc::SIGSTOP);
        let stopped = drive.wait_state('T', Duration::from_secs(2));
        verdict.check(stopped.is_some(), "the process stopped (state T) after SIGSTOP");
        sleep_until(stop_at + SUSPENSION);
        let cont_at = drive.signal(libc::SIGCONT);
        let outcome = drive.finish(Duration::from_secs(4));
        settle();

        let motion = robot.motion();
        if let Some(stopped) = stopped {
            let during =
                motion.iter().filter(|(at, _)| *at > stopped + READ_LATENESS && *at < cont_at).count();
            verdict.check(during == 0, format!("nothing reached the wire while stopped ({during} frames)"));
        }
        let after: Vec<(Instant, (i8, i8))> =
            motion.iter().copied().filter(|(at, _)| *at >= cont_at).collect();
        let first = after.first().map(|(_, speed)| *speed);
        verdict.check(
            first == Some((0, 0)),
            format!("the first frame after SIGCONT is zero (it was {first:?})"),
        );
        let moved = after.iter().filter(|(_, speed)| moving(*speed)).count();
        verdict.check(moved == 0, format!("no non-zero frame after SIGCONT ({moved} were)"));
        verdict.ends_with_zero(&motion);
        verdict.exit(&outcome, 1);
        verdict.stderr_has(&outcome, "suspended for");
        verdict.stderr_has(&outcome, "drive ended");
        verdict.evidence(&motion, drive.spawned, &[("SIGSTOP", stop_at), ("SIGCONT", cont_at)], &outcome);
    });
}

/// Ctrl-Z at full speed: zero frames first (within 50 ms), then the process stops; on SIGCONT 800 ms later
/// the suspension rule applies (only zeros, exit 1, "suspended for"). Today SIGTSTP stops the process at once
/// with no zero frame, and it resumes driving.
#[test]
fn suspend_resume_sigtstp() {
    scenario("suspend_resume_sigtstp", |verdict| {
        let robot = FaultyRobot::start(healthy());
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3"]);
        if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
            return;
        }
        let tstp_at = drive.signal(libc::SIGTSTP);
        let stopped = drive.wait_state('T', Duration::from_secs(2));
        verdict.check(stopped.is_some(), "the process stopped itself (state T) after SIGTSTP");
        sleep_until(tstp_at + SUSPENSION);
        let cont_at = drive.signal(libc::SIGCONT);
        let outcome = drive.finish(Duration::from_secs(4));
        settle();

        let motion = robot.motion();
        let until_cont: Vec<(Instant, (i8, i8))> =
            motion.iter().copied().filter(|(at, _)| *at < cont_at).collect();
        verdict.zero_within(&until_cont, tstp_at, ZERO_WITHIN, "SIGTSTP");
        if let Some(stopped) = stopped {
            let during =
                motion.iter().filter(|(at, _)| *at > stopped + READ_LATENESS && *at < cont_at).count();
            verdict.check(during == 0, format!("nothing reached the wire while stopped ({during} frames)"));
        }
        let moved = motion.iter().filter(|(at, speed)| *at >= cont_at && moving(*speed)).count();
        verdict.check(moved == 0, format!("only zeros after SIGCONT ({moved} non-zero frames)"));
        verdict.ends_with_zero(&motion);
        verdict.exit(&outcome, 1);
        verdict.stderr_has(&outcome, "suspended for");
        verdict.evidence(&motion, drive.spawned, &[("SIGTSTP", tstp_at), ("SIGCONT", cont_at)], &outcome);
    });
}

// ---------------------------------------------------------------------------------------------------------
// Signals at every phase.

#[derive(Clone, Copy, Debug)]
enum Phase {
    /// Before the first status (the robot stays silent for 300 ms, then answers): nothing may ever move.
    BeforeFirstStatus,
    /// During the ramp up: non-zero frames seen, still below 20 %.
    Ramp,
    FullSpeed,
    /// `--for 1s` is up and the ramp down is under way.
    StopRamp,
}

/// SIGINT, SIGTERM and SIGHUP in each phase: exit 128+n; where motion was being sent, a zero frame within
/// 50 ms and nothing non-zero after it; before the first status, no non-zero frame ever (the robot answers
/// 150 ms after the signal, so a binary that ignored it would drive). Today the handlers are installed only
/// after the first status (killed by the signal in phase a) and time-up wins over a signal during the stop
/// ramp (exit 0 in phase d).
#[test]
fn signals_every_phase() {
    let mut verdict = Verdict::new("signals_every_phase");
    for phase in [Phase::BeforeFirstStatus, Phase::Ramp, Phase::FullSpeed, Phase::StopRamp] {
        for (signal, name) in [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM"), (libc::SIGHUP, "SIGHUP")]
        {
            verdict.case(&format!("{phase:?} {name}"), |case| signal_in_phase(case, phase, signal, name));
        }
    }
    verdict.conclude();
}

fn signal_in_phase(verdict: &mut Verdict, phase: Phase, signal: i32, name: &str) {
    let robot = match phase {
        Phase::BeforeFirstStatus => FaultyRobot::silent(),
        _ => FaultyRobot::start(healthy()),
    };
    let args: &[&str] = match phase {
        Phase::StopRamp => &["--linear", "0.3", "--for", "1s"],
        _ => &["--linear", "0.3"],
    };
    let mut drive = Drive::spawn(&robot, args);
    let mut marks = Vec::new();
    let reached = match phase {
        Phase::BeforeFirstStatus => {
            // Signal 150 ms after the start, once drive has the terminal open (on a loaded machine the
            // process may need longer to get there), while the robot is still silent.
            let deadline = Instant::now() + START;
            while !drive.has_open(&robot.path) && drive.running() && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(2));
            }
            verdict.check(drive.has_open(&robot.path), "setup: drive opened the terminal");
            sleep_until((drive.spawned + Duration::from_millis(150)).max(Instant::now()));
            Some(Instant::now())
        }
        Phase::Ramp => reach(verdict, &robot, &mut drive, "the ramp (1..10 %)", |m| {
            m.last().is_some_and(|(_, speed)| (1..=10).contains(&speed.0))
        }),
        Phase::FullSpeed => reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed),
        Phase::StopRamp => reach(verdict, &robot, &mut drive, "the stop ramp (below 20 % after 20 %)", |m| {
            at_full_speed(m) && m.last().is_some_and(|(_, speed)| (1..20).contains(&speed.0))
        }),
    };
    if reached.is_none() {
        return;
    }
    let signal_at = drive.signal(signal);
    marks.push((name, signal_at));
    if let Phase::BeforeFirstStatus = phase {
        // Then the robot answers, healthy: a binary that ignored the signal would now drive.
        sleep_until(signal_at + Duration::from_millis(150));
        robot.set_status(Some(healthy()));
        robot.set_motion(MotionFeedback::Follow { lag: Duration::ZERO });
        marks.push(("robot answers", Instant::now()));
    }
    let outcome = drive.finish(Duration::from_secs(4));
    settle();

    let motion = robot.motion();
    let last_before = motion.iter().rev().find(|(at, _)| *at < signal_at).map(|(_, speed)| *speed);
    match phase {
        Phase::BeforeFirstStatus => {
            let moved = motion.iter().filter(|(_, speed)| moving(*speed)).count();
            verdict.check(moved == 0, format!("no non-zero frame ever ({moved} were sent)"));
        }
        Phase::Ramp => verdict.check(
            last_before.is_some_and(|speed| (1..20).contains(&speed.0)),
            format!("signalled during the ramp (last frame before it {last_before:?})"),
        ),
        Phase::FullSpeed => verdict.check(
            last_before == Some(FULL_SPEED),
            format!("signalled at full speed (last frame before it {last_before:?})"),
        ),
        Phase::StopRamp => verdict.check(
            last_before.is_some_and(|speed| (1..20).contains(&speed.0)),
            format!("signalled during the stop ramp (last frame before it {last_before:?})"),
        ),
    }
    if !matches!(phase, Phase::BeforeFirstStatus) {
        verdict.zero_within(&motion, signal_at, ZERO_WITHIN, name);
    }
    verdict.exit(&outcome, 128 + signal);
    verdict.no_unasked_stall(&outcome);
    verdict.evidence(&motion, drive.spawned, &marks, &outcome);
}

// ---------------------------------------------------------------------------------------------------------
// §4 Stop frames reach the robot first, and the report tells the truth.

/// The robot stops reading for 1.5 s while drive runs at full speed (a stalled adapter); Ctrl-C 0.7 s into
/// the stall; then it reads again.
///
/// What a pseudo-terminal can show: the bytes written before the robot stopped reading sit in the *robot's*
/// line-discipline buffer (up to 4095 bytes, here ~35 frames = 455 bytes), which the host cannot flush:
/// TIOCOUTQ on the terminal side is always 0 and TCOFLUSH only empties the flip buffer beyond the line
/// discipline. So the stale frames do arrive, then the zeros. What is asserted is what the host controls:
/// no non-zero frame was written after the signal (the stream order is the write order, and the stale
/// frames are no more than the stall allowed before the signal), the zeros follow, exit 130. This passes
/// on today's binary too.
///
/// A real UART is different: the host's frames wait in the host's own tty output buffer and the adapter's
/// FIFO (which TIOCOUTQ counts) until the UART shifts them out at 115200 baud; the fixed binary holds motion
/// frames back while that queue is not empty, and flushes it (TCOFLUSH) before the stop frames, so the robot
/// gets the zeros next and stderr counts what was discarded.
///
/// The robot reports status only (no motion feedback): a robot that gets no commands stands still, and the
/// did-not-follow rule is another scenario.
#[test]
fn peer_stops_reading() {
    scenario("peer_stops_reading", |verdict| {
        stall(verdict, Duration::from_millis(700), Duration::from_millis(1500), None)
    });
}

/// The same stall, long enough (8 s, Ctrl-C at 7.5 s: ~375 frames, 4875 bytes) to overflow the robot's
/// 4095-byte line-discipline buffer into the pseudo-terminal's flip buffer, the part TCOFLUSH on the host's
/// side can discard. Contract: the output queue is flushed before the stop frames, so the robot reads at
/// most what its line discipline held (4095 bytes = 315 frames) before the zeros. Today it reads all of them.
#[test]
fn peer_stops_reading_past_the_line_buffer() {
    // N_TTY keeps 4095 bytes for a reader that does not read; the robot's reads before the stall ended on a
    // frame boundary, so that is exactly 315 whole frames.
    scenario("peer_stops_reading_past_the_line_buffer", |verdict| {
        stall(verdict, Duration::from_millis(7500), Duration::from_millis(8000), Some(4095 / 13))
    });
}

/// Drives at full speed, stops reading for `length`, SIGINT `signal_after` into the stall; then checks
/// what the robot read after the stall: stale frames (at most what could be written before the signal, and
/// at most `held` if given), then zeros, nothing non-zero after them, exit 130.
fn stall(verdict: &mut Verdict, signal_after: Duration, length: Duration, held: Option<usize>) {
    let robot = FaultyRobot::with(Some(healthy()), MotionFeedback::Off);
    let mut drive = Drive::spawn(&robot, &["--linear", "0.3"]);
    if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
        return;
    }
    let stall_at = Instant::now();
    robot.stop_reading();
    sleep_until(stall_at + signal_after);
    let int_at = drive.signal(libc::SIGINT);
    sleep_until(stall_at + length);
    let resume_at = Instant::now();
    robot.resume_reading();
    let outcome = drive.finish(Duration::from_secs(4));
    settle();

    let motion = robot.motion();
    let read_after: Vec<(Instant, (i8, i8))> =
        motion.iter().copied().filter(|(at, _)| *at >= resume_at).collect();
    match read_after.iter().position(|(_, speed)| !moving(*speed)) {
        Some(first) => {
            let after = read_after[first].0.duration_since(resume_at);
            verdict.check(
                after < Duration::from_millis(500),
                format!("the zeros arrive once the robot reads again (after {after:?})"),
            );
            let moved = read_after[first..].iter().filter(|(_, speed)| moving(*speed)).count();
            verdict.check(moved == 0, format!("no non-zero frame after the zeros ({moved})"));
        }
        None => verdict.check(false, "the zeros arrive once the robot reads again (none did)"),
    }
    let stale = read_after.iter().take_while(|(_, speed)| moving(*speed)).count();
    // 50 frames a second from the stall to the signal, plus a frame or two in flight either side.
    let written_before_signal = (int_at.duration_since(stall_at).as_millis() / 20) as usize + 3;
    verdict.check(
        stale <= written_before_signal,
        format!(
            "no non-zero frame written after the signal: {stale} stale frames, at most \
             {written_before_signal} written before it"
        ),
    );
    if let Some(held) = held {
        verdict.check(
            stale <= held,
            format!(
                "what was still queued was discarded before the zeros: {stale} stale frames read, more than \
                 the {held} the robot's own buffer held"
            ),
        );
    }
    verdict.ends_with_zero(&motion);
    verdict.exit(&outcome, 130);
    verdict.no_unasked_stall(&outcome);
    let marks = [("stops reading", stall_at), ("SIGINT", int_at), ("reads again", resume_at)];
    verdict.evidence(&motion, drive.spawned, &marks, &outcome);
}

/// The robot (and its adapter) disappear mid-drive: the pseudo-terminal's master is closed, the host's side
/// hangs up. No stop frame can reach it; the report must say so ("could not be sent", the robot's "500 ms
/// command timeout") instead of today's "last command +0.000 m/s". Exit 1.
#[test]
fn peer_vanishes() {
    scenario("peer_vanishes", |verdict| {
        let robot = FaultyRobot::start(healthy());
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3"]);
        if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
            return;
        }
        let gone_at = robot.vanish();
        let outcome = drive.finish(Duration::from_secs(4));

        let motion = robot.motion();
        verdict.exit(&outcome, 1);
        verdict.stderr_has(&outcome, "could not be sent");
        verdict.stderr_has(&outcome, "500 ms command timeout");
        verdict.check(
            !outcome.stderr.contains("last command +0.000"),
            "stderr does not claim \"last command +0.000\" (no stop frame was sent)",
        );
        verdict.no_unasked_stall(&outcome);
        verdict.evidence(&motion, drive.spawned, &[("robot vanishes", gone_at)], &outcome);
    });
}

// ---------------------------------------------------------------------------------------------------------
// Garbage, silence and a robot that does not move.

/// 500 garbage bytes every 20 ms (random bytes and broken frame headers) around valid status and motion
/// feedback (lagging 60 ms): drive --for 1.5s drives normally and exits 0. The host's frames are intact
/// (rolling ids, serial mode, 20 % reached, zeros at the end), and the report's peak measured speed proves
/// the motion feedback was found in the garbage. Today: passes except the report line (contract §4: final
/// report has "peak measured").
#[test]
fn garbage_flood_with_feedback() {
    scenario("garbage_flood_with_feedback", |verdict| {
        let robot =
            FaultyRobot::with(Some(healthy()), MotionFeedback::Follow { lag: Duration::from_millis(60) });
        robot.flood(500);
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "1.5s"]);
        let outcome = drive.finish(Duration::from_secs(8));
        settle();

        let frames = robot.frames();
        let motion = robot.motion();
        verdict.exit(&outcome, 0);
        verdict.stderr_has(&outcome, "(time up)");
        verdict.stderr_has(&outcome, "peak measured +0.300 m/s");
        verdict.check(frames.len() >= 60, format!("about 50 frames a second for 1.5 s ({})", frames.len()));
        verdict.check(frames.len() == motion.len(), "every host frame is a motion command");
        verdict.check(
            frames.iter().all(|(_, f)| f.payload[0] == 0x02 && f.payload[1] == 0x00),
            "every motion command says serial mode, no fault clear",
        );
        // Ids roll by one, except where the stop's flush dropped what the pseudo-terminal had not passed on
        // yet (the latest frames, on a loaded machine): allowed only right before the stop frames, and only
        // when the report says the flush was uncounted (it once said nothing while a frame went missing).
        let breaks: Vec<usize> = (1..frames.len())
            .filter(|&i| frames[i].1.frame_id != frames[i - 1].1.frame_id.wrapping_add(1))
            .collect();
        let before_stop = frames.len().saturating_sub(STOP_FRAMES);
        let reported = outcome.stderr.contains(tracerctl::commands::drive::UNCOUNTED_DISCARD);
        verdict.check(
            breaks.is_empty() || (breaks == [before_stop] && reported),
            format!(
                "frame ids roll by one (nothing lost or corrupted towards the robot), but for a reported flush \
                 before the stop frames: breaks at {breaks:?} of {}, stop frames from {before_stop}",
                frames.len()
            ),
        );
        verdict.check(at_full_speed(&motion), "reached 20 %");
        let tail: Vec<(i8, i8)> = motion.iter().rev().take(3).map(|(_, s)| *s).collect();
        verdict.check(tail == [(0, 0); 3], format!("ends with three zeros ({tail:?})"));
        verdict.no_unasked_stall(&outcome);
        verdict.evidence(&motion, drive.spawned, &[], &outcome);
    });
}

/// Only garbage, no valid frame: drive refuses (exit 4) and never sends a non-zero frame. Passes today.
#[test]
fn garbage_flood_without_feedback() {
    scenario("garbage_flood_without_feedback", |verdict| {
        let robot = FaultyRobot::silent();
        robot.flood(500);
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "1.5s"]);
        let outcome = drive.finish(Duration::from_secs(8));
        settle();

        let motion = robot.motion();
        verdict.exit(&outcome, 4);
        verdict.stderr_has(&outcome, "not driving");
        let moved = motion.iter().filter(|(_, speed)| moving(*speed)).count();
        verdict.check(moved == 0, format!("no non-zero frame ({moved})"));
        verdict.evidence(&motion, drive.spawned, &[], &outcome);
    });
}

/// All feedback stops at full speed: a zero frame within 1.3 s of the silence (the 1 s feedback timeout,
/// plus margin), nothing non-zero after, exit 1, "no frames from the robot for 1 s". Passes today.
#[test]
fn feedback_stops() {
    scenario("feedback_stops", |verdict| {
        let robot = FaultyRobot::start(healthy());
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "20s"]);
        if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
            return;
        }
        let silent_at = Instant::now();
        robot.go_silent();
        let outcome = drive.finish(Duration::from_secs(5));
        settle();

        let motion = robot.motion();
        verdict.zero_within(&motion, silent_at, Duration::from_millis(1300), "the silence");
        verdict.ends_with_zero(&motion);
        verdict.exit(&outcome, 1);
        verdict.stderr_has(&outcome, "no frames from the robot for 1 s");
        verdict.no_unasked_stall(&outcome);
        verdict.evidence(&motion, drive.spawned, &[("robot falls silent", silent_at)], &outcome);
    });
}

/// Motion feedback present but the wheels never turn (measured 0.000 m/s throughout), with the status saying
/// "exception" and with it saying "normal": drive --linear 0.3 --for 2s must not report success. Contract:
/// exit 4, "the robot did not follow the command" with the reason (state, mode) on that line, and the final
/// report's "distance 0.00 m" and "peak measured +0.000 m/s". Today: exit 0, "time up".
#[test]
fn robot_does_not_follow() {
    let mut verdict = Verdict::new("robot_does_not_follow");
    verdict.case("status normal", |verdict| {
        let robot = FaultyRobot::with(Some(healthy()), MotionFeedback::StandStill);
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "2s"]);
        let outcome = drive.finish(Duration::from_secs(8));
        settle();

        let motion = robot.motion();
        verdict.exit(&outcome, 4);
        let line = outcome.stderr.lines().find(|line| line.contains("the robot did not follow the command"));
        verdict.check(line.is_some(), "stderr says \"the robot did not follow the command\"");
        if let Some(line) = line {
            verdict.check(
                line.contains("normal") && line.contains("serial"),
                "with the reason (normal, mode serial) on that line",
            );
        }
        verdict.stderr_has(&outcome, "distance 0.00 m");
        verdict.stderr_has(&outcome, "peak measured +0.000 m/s");
        verdict.check(!outcome.stderr.contains("(time up)"), "not reported as \"time up\"");
        verdict.ends_with_zero(&motion);
        verdict.no_unasked_stall(&outcome);
        verdict.evidence(&motion, drive.spawned, &[], &outcome);
    });
    // A robot in the vehicle state exception ignores commands: drive does not start (issue 28, as for an
    // E-stop), and says why.
    verdict.case("status exception", |verdict| {
        let robot = FaultyRobot::with(Some(exception()), MotionFeedback::StandStill);
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "2s"]);
        let outcome = drive.finish(Duration::from_secs(8));
        settle();

        let motion = robot.motion();
        verdict.exit(&outcome, 4);
        verdict.stderr_has(&outcome, "not driving: the robot reports a system exception");
        verdict.check(motion.iter().all(|(_, speed)| *speed == (0, 0)), "nothing that moves was sent");
        verdict.evidence(&motion, drive.spawned, &[], &outcome);
    });
    verdict.conclude();
}

/// The robot turns to the vehicle state exception at full speed (a latched fault): zeros soon after, as for
/// an E-stop (250 ms, the same allowance), nothing non-zero after, exit 4, the reason said (issue 28: it
/// went on commanding for 1.75 s and ended on "did not follow").
#[test]
fn exception_mid_drive() {
    scenario("exception_mid_drive", |verdict| {
        let robot = FaultyRobot::start(healthy());
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "20s"]);
        if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
            return;
        }
        let raised_at = Instant::now();
        robot.set_status(Some(exception()));
        let outcome = drive.finish(Duration::from_secs(5));
        settle();

        let motion = robot.motion();
        verdict.zero_within(&motion, raised_at, Duration::from_millis(250), "the exception");
        verdict.ends_with_zero(&motion);
        verdict.exit(&outcome, 4);
        verdict.stderr_has(&outcome, "the robot reports a system exception");
        verdict.no_unasked_stall(&outcome);
        verdict.evidence(&motion, drive.spawned, &[("exception", raised_at)], &outcome);
    });
}

/// The E-stop is pressed at full speed (the status says so from then on): zeros soon after the first E-stop
/// status (250 ms: the test's allowance for the main loop's 20 ms poll on a loaded machine; the contract
/// gives no figure), nothing non-zero after, exit 4, "the E-stop was pressed". Passes today.
#[test]
fn estop_mid_drive() {
    scenario("estop_mid_drive", |verdict| {
        let robot = FaultyRobot::start(healthy());
        let mut drive = Drive::spawn(&robot, &["--linear", "0.3", "--for", "20s"]);
        if reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none() {
            return;
        }
        let pressed_at = Instant::now();
        robot.set_status(Some(estop()));
        let outcome = drive.finish(Duration::from_secs(5));
        settle();

        let motion = robot.motion();
        verdict.zero_within(&motion, pressed_at, Duration::from_millis(250), "the E-stop");
        verdict.ends_with_zero(&motion);
        verdict.exit(&outcome, 4);
        verdict.stderr_has(&outcome, "the E-stop was pressed");
        verdict.no_unasked_stall(&outcome);
        verdict.evidence(&motion, drive.spawned, &[("E-stop pressed", pressed_at)], &outcome);
    });
}

// ---------------------------------------------------------------------------------------------------------
// A misbehaving host.

/// The reader of drive's output (stdout and stderr, one pipe) goes away (a closed pipe, a dead `| head -1`),
/// in two cases: right after the
/// first line (the robot has not moved yet), and after the first line once the robot is at full speed (the
/// pipe's buffer takes the status lines written meanwhile). Its next line cannot be written. Contract: the
/// robot is stopped (zeros last), no panic (not 101), exit 1. At full speed the zeros must come within 2.5 s
/// of the close (the test's allowance: status lines go to a pipe once a second; the contract gives no
/// figure). Today a broken pipe is treated as a quiet success: exit 0.
#[test]
fn output_reader_goes_away() {
    let mut verdict = Verdict::new("output_reader_goes_away");
    for full_speed in [false, true] {
        let name = if full_speed { "closed at full speed" } else { "closed after the first line" };
        verdict.case(name, |verdict| {
            let robot = FaultyRobot::start(healthy());
            let (mut drive, pipe) = Drive::spawn_with_output(&robot, &["--linear", "0.3"]);
            let mut reader = BufReader::new(pipe);
            let mut first = String::new();
            let _ = reader.read_line(&mut first);
            if full_speed && reach(verdict, &robot, &mut drive, "full speed (20 %)", at_full_speed).is_none()
            {
                return;
            }
            drop(reader);
            let closed_at = Instant::now();
            let mut outcome = drive.finish(Duration::from_secs(6));
            outcome.stderr = format!("(the first line, then the reader went away) {first}");
            settle();

            let motion = robot.motion();
            verdict.check(
                first.starts_with("robot: "),
                format!("the first line is the robot's state ({first:?})"),
            );
            verdict.check(outcome.status.code() != Some(101), "no panic (exit 101)");
            verdict.exit(&outcome, 1);
            verdict.ends_with_zero(&motion);
            if full_speed {
                verdict.zero_within(&motion, closed_at, Duration::from_millis(2500), "the close");
            }
            verdict.evidence(&motion, drive.spawned, &[("output reader gone", closed_at)], &outcome);
        });
    }
    verdict.conclude();
}
