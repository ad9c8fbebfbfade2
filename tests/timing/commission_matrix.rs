//! Issue 32 §3, the abort matrix on RS232: every abort cause injected in the middle of every step of
//! `tracerctl commission` (`--max-linear 0.6`: the straights last 1.7 s), the host on a pseudo-terminal relayed
//! to `tracerctl sim --pty` ([`Relay`]: the witness of both directions), the operator's terminal another
//! pseudo-terminal. Each run is judged from the wire: after the cause (its first frame from the robot, or
//! the moment the harness pressed the key or sent the signal) the first zero motion frame comes within one
//! 20 ms period (+ [`HARNESS_CLOCK`] when the cause is not on the wire), no non-zero frame follows it, the
//! exit status is non-zero and the JSON report names the cause, marks the steps run, and keeps every figure
//! a full run measures for the steps finished before.
//!
//! Runs go [`PARALLEL`] at a time (`MATRIX_PARALLEL`); `MATRIX_CAUSES` / `MATRIX_STEPS` (comma-separated
//! names / step numbers from 1) select a part (`peer-stalled` runs only when named: a pseudo-terminal
//! shows the host no output queue, so no host can see its peer stall there; the VM's sja1000 suite proves
//! that cause on a real 8250 UART, check `commission_serial_stalled` in tests/vm/README.md); `MATRIX_BIN`
//! runs another build (the proof that a broken one fails). One table of every run is printed, then the
//! failures.

use std::io::Read;
use std::os::fd::AsRawFd;
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tracerctl::protocol::message::{Message, SystemState};
use tracerctl::protocol::serial::decode;

use crate::fault_peer::{open_pty, percent};
use crate::pty_sim::PtySim;
use crate::relay::{Relay, Side};

/// One motion period.
const PERIOD: Duration = Duration::from_millis(20);
/// When the cause is the harness's own act (a key written to the terminal, a signal), the moment it acted is
/// read on the harness's clock, not on the wire: the terminal's and the scheduler's delays between that
/// moment and the process seeing it are allowed for.
const HARNESS_CLOCK: Duration = Duration::from_millis(10);
/// The relay reads both directions on one thread; a zero frame it reads late (scheduled late on a loaded
/// machine) looks late by as much. 20.4 ms was measured once in 100 runs at load 3 (commission looks at
/// the robot's status every 20 ms, so its own worst case is one period plus its wake-up).
const RELAY_READ: Duration = Duration::from_millis(3);
/// commission's silence limit (drive's guard: no frame for 1 s is a lost link).
const FEEDBACK_LOST: Duration = Duration::from_secs(1);
/// commission starts a moving step only when the robot was heard from within 100 ms; one period more for the
/// step that began just inside it.
const FRESH_FEEDBACK: Duration = Duration::from_millis(120);
/// How long the relay stays stalled.
const STALL: Duration = Duration::from_millis(600);
const PARALLEL: usize = 6;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum How {
    /// A fault typed on the simulator's standard input.
    Sim(&'static str),
    /// Bytes typed on the operator's terminal.
    Keys(&'static [u8]),
    Signal(i32),
    /// SIGSTOP to the simulator.
    Silence,
    /// The relay stops reading the host.
    Stall,
}

#[derive(Clone, Copy, Debug)]
struct Cause {
    name: &'static str,
    how: How,
    /// The report's `abort.reason`, the exit status, and words its message must hold.
    reason: &'static str,
    status: i32,
    words: &'static str,
}

const CAUSES: [Cause; 12] = [
    Cause { name: "estop", how: How::Sim("estop"), reason: "estop", status: 4, words: "E-stop" },
    Cause {
        name: "fault",
        how: How::Sim("battery-low"),
        reason: "fault",
        status: 4,
        words: "a fault appeared",
    },
    Cause { name: "exception", how: How::Sim("rc-lost"), reason: "exception", status: 4, words: "" },
    Cause { name: "rc-override", how: How::Sim("swb-middle"), reason: "rc_override", status: 4, words: "RC" },
    Cause {
        name: "mode-change",
        how: How::Sim("other-host"),
        reason: "mode_changed",
        status: 4,
        words: "left command mode",
    },
    Cause { name: "key", how: How::Keys(b"x"), reason: "key", status: 4, words: "pressed a key (x)" },
    Cause { name: "space", how: How::Keys(b" "), reason: "key", status: 4, words: "pressed a key (Space)" },
    Cause { name: "ctrl-c", how: How::Keys(b"\x03"), reason: "signal", status: 130, words: "SIGINT" },
    Cause {
        name: "sigterm",
        how: How::Signal(libc::SIGTERM),
        reason: "signal",
        status: 143,
        words: "SIGTERM",
    },
    Cause { name: "sighup", how: How::Signal(libc::SIGHUP), reason: "signal", status: 129, words: "SIGHUP" },
    Cause {
        name: "link-silence",
        how: How::Silence,
        reason: "link_lost",
        status: 1,
        words: "no frames from the robot",
    },
    Cause { name: "peer-stalled", how: How::Stall, reason: "peer_stalled", status: 1, words: "not draining" },
];

fn bin() -> std::path::PathBuf {
    std::env::var_os("MATRIX_BIN").map_or_else(|| assert_cmd::cargo::cargo_bin("tracerctl"), Into::into)
}

/// The plan's steps (name, start, duration) from `commission --dry-run --format json`.
fn plan() -> Vec<(String, Duration, Duration)> {
    let output = Command::new(bin())
        .args(["commission", "--dry-run", "--format", "json", "--max-linear", "0.6"])
        .env("TRACERCTL_CONFIG", "")
        .output()
        .unwrap();
    let plan: serde_json::Value = serde_json::from_slice(&output.stdout).expect("the plan as JSON");
    let mut start = Duration::ZERO;
    plan["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|step| {
            let duration = Duration::from_secs_f64(step["duration_s"].as_f64().unwrap());
            let entry = (step["name"].as_str().unwrap().to_string(), start, duration);
            start += duration;
            entry
        })
        .collect()
}

/// One run's outcome.
struct Run {
    cause: &'static str,
    step: usize,
    /// From the cause to the first zero frame.
    latency: Option<Duration>,
    failures: Vec<String>,
    evidence: String,
}

/// A run: `Some(step)` injects the cause in the middle of that step (from 0); `None` is the full reference.
#[expect(
    clippy::too_many_lines,
    reason = "one run of the matrix: start, inject, judge, in the order they happen"
)]
fn run(cause: Option<Cause>, step: usize, plan: &[(String, Duration, Duration)]) -> (Run, serde_json::Value) {
    let mut sim = PtySim::start_with(&bin(), "60s", &[]);
    let relay = Relay::start(&sim.path);
    let (terminal, terminal_path) = open_pty();
    let open = || std::fs::OpenOptions::new().read(true).write(true).open(&terminal_path).unwrap();
    let mut child = Command::new(bin())
        .args(["--serial", &relay.path, "commission", "--yes", "--max-linear", "0.6", "--format", "json"])
        .env("TRACERCTL_CONFIG", "")
        .env("TRACERCTL_PROFILE", "")
        .stdin(open())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id() as i32;
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let stdout = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = out.read_to_string(&mut text);
        text
    });
    let stderr = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = err.read_to_string(&mut text);
        text
    });
    let mut failures = Vec::new();
    // The plan starts with the first motion frame (settle: zeros).
    let deadline = Instant::now() + Duration::from_secs(20);
    let plan_start = loop {
        if let Some((at, _)) = relay.frames(Side::Host).iter().find(|(_, frame)| percent(frame).is_some()) {
            break Some(*at);
        }
        if Instant::now() > deadline || child.try_wait().unwrap().is_some() {
            break None;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    let mut acted = None;
    if let (Some(cause), Some(plan_start)) = (cause, plan_start) {
        let (_, start, duration) = &plan[step];
        let at = plan_start + *start + *duration / 2;
        std::thread::sleep(at.saturating_duration_since(Instant::now()));
        acted = Some(Instant::now());
        match cause.how {
            How::Sim(name) => sim.inject(name),
            How::Keys(bytes) => {
                // SAFETY: writes from a buffer of the given length to our terminal's master.
                unsafe { libc::write(terminal.as_raw_fd(), bytes.as_ptr().cast(), bytes.len()) };
            }
            // SAFETY: kill(2) on our own children.
            How::Signal(signal) => unsafe {
                libc::kill(pid, signal);
            },
            How::Silence => sim.pause(),
            How::Stall => {
                relay.stall(true);
                std::thread::sleep(STALL);
                relay.stall(false);
            }
        }
    } else if plan_start.is_none() {
        failures.push("the drive never began (no motion frame)".to_string());
    }
    let deadline = Instant::now() + Duration::from_secs(30);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status.code();
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            failures.push("still running 30 s after the cause: killed".to_string());
            break child.wait().unwrap().code();
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    std::thread::sleep(Duration::from_millis(100));
    let stdout = stdout.join().unwrap();
    let stderr = stderr.join().unwrap();
    let log = relay.log();
    drop(relay);
    drop(sim);
    let report: serde_json::Value =
        stdout.lines().last().and_then(|line| serde_json::from_str(line).ok()).unwrap_or_default();
    let mut run = Run {
        cause: cause.map_or("none", |c| c.name),
        step,
        latency: None,
        failures,
        evidence: String::new(),
    };
    if let (Some(cause), Some(acted), Some(plan_start)) = (cause, acted, plan_start) {
        judge(&mut run, cause, (plan_start, acted), &log, status, &report, plan);
    } else if cause.is_none() && report["abort"] != serde_json::Value::Null {
        run.failures.push(format!("the reference run was aborted: {}", report["abort"]));
    }
    if !run.failures.is_empty() {
        run.evidence = evidence(&log, acted, status, &stderr);
    }
    (run, report)
}

/// (vehicle state, fault code, mode) of every system status from the robot, with its time.
fn robot_states(log: &[crate::relay::Chunk]) -> Vec<(Instant, (u8, u16, u8))> {
    crate::relay::frames(log, Side::Robot)
        .iter()
        .filter_map(|(at, frame)| match decode(frame)?.message {
            Message::SystemState(SystemState { vehicle_state, fault_code, control_mode, .. }) => {
                Some((*at, (vehicle_state, fault_code, control_mode)))
            }
            _ => None,
        })
        .collect()
}

fn motion(log: &[crate::relay::Chunk]) -> Vec<(Instant, (i8, i8))> {
    crate::relay::frames(log, Side::Host)
        .iter()
        .filter_map(|(at, frame)| Some((*at, percent(frame)?)))
        .collect()
}

fn judge(
    run: &mut Run,
    cause: Cause,
    (plan_start, acted): (Instant, Instant),
    log: &[crate::relay::Chunk],
    status: Option<i32>,
    report: &serde_json::Value,
    plan: &[(String, Duration, Duration)],
) {
    let fail = |run: &mut Run, what: String| run.failures.push(what);
    let motion = motion(log);
    // When the cause began, on the wire where it shows there.
    let (cause_at, allowance) = match cause.how {
        How::Sim(_) => {
            let states = robot_states(log);
            let before = states.iter().rev().find(|(at, _)| *at <= acted).map(|(_, state)| *state);
            match states.iter().find(|(at, state)| *at > acted && Some(*state) != before) {
                Some((at, _)) => (*at, RELAY_READ),
                None => {
                    fail(run, "the cause never showed in the robot's status".to_string());
                    return;
                }
            }
        }
        How::Keys(_) | How::Signal(_) => (acted, HARNESS_CLOCK),
        How::Silence => {
            let last = log.iter().rfind(|(at, side, _)| *side == Side::Robot && *at <= acted + PERIOD);
            (last.map_or(acted, |(at, _, _)| *at) + FEEDBACK_LOST, HARNESS_CLOCK)
        }
        // What the robot reads once it reads again: the zeros first, nothing moving after them.
        How::Stall => (acted + STALL, Duration::ZERO),
    };
    let after: Vec<_> = motion.iter().filter(|(at, _)| *at >= cause_at).collect();
    match after.iter().position(|(_, speed)| *speed == (0, 0)) {
        Some(first) => {
            let latency = after[first].0.duration_since(cause_at);
            run.latency = Some(latency);
            let window = if cause.how == How::Stall { Duration::from_millis(5) } else { PERIOD + allowance };
            if latency > window || (cause.how == How::Stall && first > 0) {
                fail(run, format!("first zero frame {latency:?} after the cause ({first} moving before it), limit {window:?}"));
            }
            let moving = after[first..].iter().filter(|(_, speed)| *speed != (0, 0)).count();
            if moving > 0 {
                fail(run, format!("{moving} non-zero motion frames after the first zero"));
            }
        }
        None => fail(run, "no zero motion frame after the cause".to_string()),
    }
    if cause.how == How::Silence {
        // A robot that fell silent at rest is not driven blind: the next moving step waits for its feedback
        // (which never comes) until the silence limit ends the drive.
        let silent_from = cause_at - FEEDBACK_LOST;
        let at_rest = motion
            .iter()
            .rfind(|(at, _)| *at <= silent_from + FRESH_FEEDBACK)
            .is_some_and(|(_, speed)| *speed == (0, 0));
        let blind = motion
            .iter()
            .filter(|(at, speed)| *at > silent_from + FRESH_FEEDBACK && *speed != (0, 0))
            .count();
        if at_rest && blind > 0 {
            fail(run, format!("{blind} moving frames sent to a robot that fell silent at rest"));
        }
    }
    if status != Some(cause.status) {
        fail(run, format!("exit status {status:?}, wanted {}", cause.status));
    }
    if report["abort"]["reason"] != cause.reason {
        fail(run, format!("report's abort {}, wanted reason {}", report["abort"], cause.reason));
    }
    let message = report["abort"]["message"].as_str().unwrap_or_default();
    if !message.contains(cause.words) {
        fail(run, format!("report's message {message:?} does not say {:?}", cause.words));
    }
    let run_flags: Vec<bool> =
        report["steps"].as_array().map(|s| s.iter().map(|s| s["run"] == true).collect()).unwrap_or_default();
    // The step the cause came in (link silence counts from its start, 1 s after the last frame).
    // The harness's clock and commission's step clock differ by a few ms: a cause this close to a step's
    // start may fall on either side of it (link silence, judged 1 s after the mid-step act, lands on one).
    const BOUNDARY: Duration = Duration::from_millis(60);
    let since = cause_at.saturating_duration_since(plan_start);
    let wanted_at = |at: Duration| {
        let last = plan.iter().rposition(|(_, start, _)| *start <= at).unwrap_or(0);
        (0..plan.len()).map(|index| index <= last).collect::<Vec<bool>>()
    };
    let wanted = wanted_at(since);
    let either = [wanted_at(since.saturating_sub(BOUNDARY)), wanted_at(since + BOUNDARY)];
    if run_flags != wanted && !either.contains(&run_flags) {
        fail(run, format!("steps run {run_flags:?}, wanted {wanted:?}"));
    }
}

/// Figures a full run measures for `step_names` are in an aborted run's report, with a value.
fn measured_before(
    run: &mut Run,
    report: &serde_json::Value,
    reference: &serde_json::Value,
    plan: &[(String, Duration, Duration)],
) {
    let finished: Vec<&str> = plan[..run.step].iter().map(|(name, _, _)| name.as_str()).collect();
    let figures = |report: &serde_json::Value| -> Vec<(String, String, bool)> {
        report["figures"]
            .as_array()
            .map(|all| {
                all.iter()
                    .map(|f| {
                        let name = f["name"].as_str().unwrap_or_default().to_string();
                        let step = f["step"].as_str().unwrap_or_default().to_string();
                        (name, step, !f["value"].is_null())
                    })
                    .collect()
            })
            .unwrap_or_default()
    };
    let got = figures(report);
    for (name, step, valued) in figures(reference) {
        if valued && finished.contains(&step.as_str()) && !got.contains(&(name.clone(), step.clone(), true)) {
            run.failures.push(format!("{name} of {step} (a finished step) is missing from the report"));
        }
    }
    for (name, step, valued) in got {
        let index = plan.iter().position(|(plan_step, _, _)| *plan_step == step);
        if valued && index.is_some_and(|index| index > run.step) {
            run.failures.push(format!("{name} of {step} (never begun) has a value"));
        }
    }
}

fn evidence(
    log: &[crate::relay::Chunk],
    acted: Option<Instant>,
    status: Option<i32>,
    stderr: &str,
) -> String {
    let zero = acted.unwrap_or_else(Instant::now);
    let at = |t: Instant| {
        if t >= zero {
            format!("+{:.1}", t.duration_since(zero).as_secs_f64() * 1000.0)
        } else {
            format!("-{:.1}", zero.duration_since(t).as_secs_f64() * 1000.0)
        }
    };
    let mut text = format!("exit {status:?}; ms from the act:\n");
    let motion = motion(log);
    for (t, speed) in motion.iter().filter(|(t, _)| *t + Duration::from_millis(100) >= zero).take(30) {
        text.push_str(&format!("  host {} {speed:?}\n", at(*t)));
    }
    for (t, state) in robot_states(log).iter().filter(|(t, _)| *t + Duration::from_millis(60) >= zero).take(6)
    {
        text.push_str(&format!("  robot {} (vehicle, faults, mode) {state:?}\n", at(*t)));
    }
    text.push_str(&format!("  stderr: {}\n", stderr.trim().lines().last().unwrap_or_default()));
    text
}

/// The items `env` names, or all but `unless_named` when it is empty.
fn selected<T>(
    all: &[T],
    env: &str,
    unless_named: &[&str],
    name: impl Fn(usize, &T) -> String,
) -> Vec<usize> {
    let wanted = std::env::var(env).unwrap_or_default();
    let wanted: Vec<&str> = wanted.split(',').filter(|s| !s.is_empty()).collect();
    (0..all.len())
        .filter(|&i| {
            let name = name(i, &all[i]);
            if wanted.is_empty() {
                !unless_named.contains(&name.as_str())
            } else {
                wanted.contains(&name.as_str())
            }
        })
        .collect()
}

#[test]
// No #[ignore]: the timing target is left out of `cargo test` (test = false); .ci/run runs it alone.
fn every_abort_cause_at_every_step_leaves_zeros_on_the_rs232_wire() {
    let started = Instant::now();
    let plan = plan();
    assert_eq!(plan.len(), 9, "the plan's steps: {plan:?}");
    // A pseudo-terminal reports no output queue, so the host cannot see its peer stall (the measured
    // outcome: the drive runs on and the frames held in the terminal arrive late, once the peer reads
    // again); that cause needs a real UART (the VM's `commission_serial_stalled`) and runs only when named.
    let causes = selected(&CAUSES, "MATRIX_CAUSES", &["peer-stalled"], |_, cause| cause.name.to_string());
    let steps = selected(&plan, "MATRIX_STEPS", &[], |i, _| (i + 1).to_string());
    // The longest runs first, so the last ones to finish are short.
    let mut jobs: Vec<(Option<Cause>, usize)> = vec![(None, plan.len() - 1)];
    for &step in steps.iter().rev() {
        jobs.extend(causes.iter().map(|&cause| (Some(CAUSES[cause]), step)));
    }
    let parallel = std::env::var("MATRIX_PARALLEL").ok().and_then(|n| n.parse().ok()).unwrap_or(PARALLEL);
    let queue = Arc::new(Mutex::new(jobs.into_iter()));
    let results = Arc::new(Mutex::new(Vec::new()));
    let plan = Arc::new(plan);
    let workers: Vec<_> = (0..parallel)
        .map(|_| {
            let (queue, results, plan) = (Arc::clone(&queue), Arc::clone(&results), Arc::clone(&plan));
            std::thread::spawn(move || loop {
                let Some((cause, step)) = queue.lock().unwrap().next() else { break };
                let outcome = run(cause, step, &plan);
                results.lock().unwrap().push(outcome);
            })
        })
        .collect();
    for worker in workers {
        worker.join().unwrap();
    }
    let mut results = std::mem::take(&mut *results.lock().unwrap());
    let reference = results.iter().position(|(run, _)| run.cause == "none").map(|i| results.remove(i));
    let (reference_run, reference_report) = reference.expect("the reference run");
    let mut failed = Vec::new();
    if !reference_run.failures.is_empty() {
        failed.push(format!("reference: {:?}", reference_run.failures));
    }
    results.sort_by_key(|(run, _)| (CAUSES.iter().position(|c| c.name == run.cause), run.step));
    println!("cause          step  zero after (ms)  verdict");
    let mut worst = Duration::ZERO;
    for (run, report) in &mut results {
        measured_before(run, report, &reference_report, &plan);
        let latency = run.latency.map_or("-".to_string(), |l| format!("{:.1}", l.as_secs_f64() * 1000.0));
        if CAUSES.iter().any(|c| c.name == run.cause && matches!(c.how, How::Sim(_))) {
            worst = worst.max(run.latency.unwrap_or_default());
        }
        let verdict = if run.failures.is_empty() { "ok".to_string() } else { run.failures.join("; ") };
        println!("{:14} {:>4}  {latency:>15}  {verdict}", run.cause, run.step + 1);
        if !run.failures.is_empty() {
            failed.push(format!(
                "{} at step {} ({}): {}\n{}",
                run.cause,
                run.step + 1,
                plan[run.step].0,
                run.failures.join("; "),
                run.evidence
            ));
        }
    }
    println!(
        "{} runs, {} at a time, in {:.0} s; worst wire-cause latency {:.1} ms",
        results.len() + 1,
        parallel,
        started.elapsed().as_secs_f64(),
        worst.as_secs_f64() * 1000.0
    );
    assert!(
        failed.is_empty(),
        "{} of {} runs failed:\n{}",
        failed.len(),
        results.len() + 1,
        failed.join("\n")
    );
}
