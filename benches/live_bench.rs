//! Live-path measurements for docs/performance.md, against the release binary over a real pseudo-terminal
//! (the test plays the robot on the master side).
//!
//!   cargo build --release && cargo run --release --example live_bench -- [SECONDS]
//!
//! 1. drive: the period of motion frames as they arrive (p50/p99/max deviation from 20 ms) and the CPU
//!    the drive process uses (utime + stime from /proc, as a share of one core).
//! 2. monitor at normal traffic: the robot's 4 feedback frames every 20 ms; CPU share of one core.
//! 3. monitor under a flood: frames written as fast as the terminal takes them; frames counted by the
//!    monitor versus frames sent (none may be lost).
//! 4. dashboard: on a pseudo-terminal this program owns (it types the arrow keys and drains the screen),
//!    against the robot on a second one: CPU share with 50 Hz feedback, bytes drawn per second, and the
//!    time from an arrow-key byte to the first motion frame that changed.
//! 5. stops: release-to-zero with kitty release events (this program answers the keyboard-protocol query)
//!    and with the auto-repeat deadline, Space-to-zero, signal-to-zero for drive (SIGINT, SIGTERM, SIGHUP,
//!    SIGTSTP), and what drive sends after SIGSTOP / SIGCONT.

// A benchmark prints its figures; the closed-stream rule (clippy.toml) is for the tool itself.
#![allow(clippy::disallowed_macros)]
use std::io::{Read, Write};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serialport::SerialPort;
use tracerctl::protocol::message::{Message, MotionState, MotorDriverState, SystemState};
use tracerctl::protocol::serial::{SerialEncoder, StreamDecoder, StreamEvent};

fn binary() -> std::path::PathBuf {
    let exe = std::env::current_exe().unwrap();
    exe.parent().unwrap().parent().unwrap().join("tracerctl")
}

/// CPU seconds (user + system) a process has used so far.
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    let ticks: f64 = fields.get(11).and_then(|v| v.parse().ok()).unwrap_or(0.0)
        + fields.get(12).and_then(|v| v.parse().ok()).unwrap_or(0.0);
    ticks / 100.0
}

fn pty() -> (serialport::TTYPort, String) {
    let (mut master, slave) = serialport::TTYPort::pair().expect("pseudo-terminal");
    let path = slave.name().unwrap();
    drop(slave);
    master.set_timeout(Duration::from_millis(2)).unwrap();
    (master, path)
}

/// A pseudo-terminal of 100x30 for the dashboard (a new one is 0x0, where nothing is drawn).
fn terminal_pty() -> (serialport::TTYPort, String) {
    let (master, path) = pty();
    let size = libc::winsize { ws_row: 30, ws_col: 100, ws_xpixel: 0, ws_ypixel: 0 };
    // SAFETY: TIOCSWINSZ with a valid winsize on an open pseudo-terminal.
    unsafe { libc::ioctl(std::os::fd::AsRawFd::as_raw_fd(&master), libc::TIOCSWINSZ, &size) };
    (master, path)
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

fn feedback(encoder: &mut SerialEncoder) -> Vec<u8> {
    let status = SystemState { control_mode: 2, battery_decivolts: 259, ..Default::default() };
    let messages = [
        Message::SystemState(status),
        Message::MotionState(MotionState { linear_mm_s: 300, ..Default::default() }),
        Message::MotorDriverState(MotorDriverState {
            motor: 1,
            rpm: 38,
            current_deciamps: 15,
            ..Default::default()
        }),
        Message::MotorDriverState(MotorDriverState {
            motor: 2,
            rpm: -38,
            current_deciamps: 15,
            ..Default::default()
        }),
    ];
    messages.iter().flat_map(|m| encoder.encode_next(m).unwrap()).collect()
}

/// Reads host frames on a thread of its own (blocking reads), so arrival times are not delayed by the
/// feedback writer.
/// (arrival, linear percent) of every motion frame.
fn record_motion_frames(mut reader: Box<dyn SerialPort>) -> std::sync::mpsc::Receiver<(Instant, i8)> {
    let (sender, arrivals) = std::sync::mpsc::channel();
    reader.set_timeout(Duration::from_millis(500)).unwrap();
    std::thread::spawn(move || {
        let mut decoder = StreamDecoder::new();
        let mut buffer = [0u8; 256];
        loop {
            match reader.read(&mut buffer) {
                Ok(read) => {
                    let now = Instant::now();
                    let mut stop = false;
                    decoder.feed(&buffer[..read], |event| {
                        if let StreamEvent::Frame { frame, .. } = event {
                            if frame.frame_type == 0x55 && frame.command == 0x01 {
                                stop |= sender.send((now, frame.payload[2] as i8)).is_err();
                            }
                        }
                    });
                    if stop {
                        return;
                    }
                }
                Err(error) if error.kind() == std::io::ErrorKind::TimedOut => {}
                // No one on the terminal side yet: the master sees a hang-up until the host opens it.
                Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => {
                    std::thread::sleep(Duration::from_millis(1))
                }
                Err(_) => return,
            }
        }
    });
    arrivals
}

fn drive(seconds: u64) {
    let (mut master, path) = pty();
    let arrivals_rx = record_motion_frames(master.try_clone().unwrap());
    let mut child = Command::new(binary())
        .args(["--serial", &path, "drive", "--linear", "0.3", "--for", &format!("{seconds}s")])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut encoder = SerialEncoder::new();
    let mut next_feedback = Instant::now();
    let start = Instant::now();
    let mut cpu_start = None;
    let mut cpu_end = None;
    while child.try_wait().unwrap().is_none() {
        let _ = master.write_all(&feedback(&mut encoder));
        next_feedback += Duration::from_millis(20);
        let elapsed = start.elapsed();
        if cpu_start.is_none() && elapsed > Duration::from_secs(1) {
            cpu_start = Some((Instant::now(), cpu_seconds(child.id())));
        }
        if cpu_end.is_none() && elapsed > Duration::from_secs(seconds.saturating_sub(1).max(2)) {
            cpu_end = Some((Instant::now(), cpu_seconds(child.id())));
        }
        std::thread::sleep(next_feedback.saturating_duration_since(Instant::now()));
    }
    let arrivals: Vec<Instant> = arrivals_rx.try_iter().map(|(at, _)| at).collect();
    // Skip the first second (start-up, ramp) and the stop frames at the end.
    let steady: Vec<Instant> =
        arrivals.iter().copied().filter(|t| t.duration_since(start) > Duration::from_secs(1)).collect();
    let mut deviations: Vec<f64> =
        steady.windows(2).map(|w| (w[1].duration_since(w[0]).as_secs_f64() * 1000.0 - 20.0).abs()).collect();
    deviations.truncate(deviations.len().saturating_sub(3));
    deviations.sort_by(f64::total_cmp);
    let cpu = match (cpu_start, cpu_end) {
        (Some((t0, c0)), Some((t1, c1))) => (c1 - c0) / t1.duration_since(t0).as_secs_f64() * 100.0,
        _ => f64::NAN,
    };
    println!(
        "drive: {} periods measured; deviation from 20 ms: p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms; CPU {:.2} % of one core",
        deviations.len(),
        percentile(&deviations, 0.5),
        percentile(&deviations, 0.99),
        deviations.last().copied().unwrap_or(0.0),
        cpu
    );
}

fn monitor_normal(seconds: u64) {
    let (mut master, path) = pty();
    let mut child = Command::new(binary())
        .args(["--serial", &path, "monitor", "--format", "json", "--duration", &format!("{seconds}s")])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut encoder = SerialEncoder::new();
    let start = Instant::now();
    let mut next = Instant::now();
    let mut cpu_start = None;
    let mut cpu_end = None;
    while child.try_wait().unwrap().is_none() {
        if Instant::now() >= next {
            let _ = master.write_all(&feedback(&mut encoder));
            next += Duration::from_millis(20);
        }
        let elapsed = start.elapsed();
        if cpu_start.is_none() && elapsed > Duration::from_secs(1) {
            cpu_start = Some((Instant::now(), cpu_seconds(child.id())));
        }
        if cpu_end.is_none() && elapsed > Duration::from_secs(seconds.saturating_sub(1).max(2)) {
            cpu_end = Some((Instant::now(), cpu_seconds(child.id())));
        }
        let mut sink = [0u8; 256];
        let _ = master.read(&mut sink);
        std::thread::sleep(Duration::from_millis(1));
    }
    if let (Some((t0, c0)), Some((t1, c1))) = (cpu_start, cpu_end) {
        println!(
            "monitor: 200 frames/s (4 x 50 Hz) for {:.1} s: CPU {:.2} % of one core",
            t1.duration_since(t0).as_secs_f64(),
            (c1 - c0) / t1.duration_since(t0).as_secs_f64() * 100.0
        );
    }
}

fn monitor_flood(frames: usize) {
    let (mut master, path) = pty();
    let child = Command::new(binary())
        .args(["--serial", &path, "monitor", "--format", "json", "--duration", "30s"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(500));
    let mut encoder = SerialEncoder::new();
    let status = Message::SystemState(SystemState { battery_decivolts: 259, ..Default::default() });
    let mut batch = Vec::with_capacity(13 * 1000);
    let start = Instant::now();
    let mut sent = 0;
    master.set_timeout(Duration::from_secs(5)).unwrap();
    while sent < frames {
        batch.clear();
        for _ in 0..1000.min(frames - sent) {
            batch.extend_from_slice(&encoder.encode_next(&status).unwrap());
            sent += 1;
        }
        master.write_all(&batch).unwrap();
    }
    let elapsed = start.elapsed();
    std::thread::sleep(Duration::from_millis(500));
    // SAFETY: kill only sends a signal to a process id; no memory is touched.
    unsafe { libc::kill(child.id() as i32, libc::SIGINT) };
    let output = child.wait_with_output().unwrap();
    let report = String::from_utf8_lossy(&output.stderr);
    // The exit report's per-ID row: "  0xAA01  system_state  <frames>  <rate>".
    let counted = report
        .lines()
        .find(|l| l.trim_start().starts_with("0xAA01"))
        .and_then(|l| l.split_whitespace().nth(2))
        .unwrap_or("(no 0xAA01 row)")
        .to_string();
    println!(
        "monitor flood: {sent} frames written in {:.3} s ({:.0} frames/s); monitor counted {counted}",
        elapsed.as_secs_f64(),
        sent as f64 / elapsed.as_secs_f64()
    );
}

fn dashboard(seconds: u64) {
    use std::sync::atomic::Ordering;
    let mut dash = Dash::start(false);
    let pid = dash.child.id();
    let (cpu0, drawn0, t0) = (cpu_seconds(pid), dash.drawn.load(Ordering::Relaxed), Instant::now());
    std::thread::sleep(Duration::from_secs(seconds));
    let elapsed = t0.elapsed().as_secs_f64();
    let cpu = (cpu_seconds(pid) - cpu0) / elapsed * 100.0;
    let drawn_per_s = (dash.drawn.load(Ordering::Relaxed) - drawn0) as f64 / elapsed;
    dash.frames();

    // Key to frame: one Up (legacy terminals send ESC [ A), then let it expire and the ramp settle.
    let mut latencies = Vec::new();
    for _ in 0..15 {
        let pressed = Instant::now();
        dash.type_keys(b"\x1b[A", 2500);
        let first = dash.frames().into_iter().find(|(at, speed)| *at >= pressed && *speed != 0);
        if let Some((at, _)) = first {
            latencies.push(at.duration_since(pressed).as_secs_f64() * 1000.0);
        }
    }
    dash.quit();
    latencies.sort_by(f64::total_cmp);
    println!(
        "dashboard: CPU {cpu:.2} % of one core with 50 Hz feedback ({drawn_per_s:.0} bytes drawn per second); \
         key to first changed motion frame over {} presses: p50 {:.2} ms, max {:.2} ms",
        latencies.len(),
        percentile(&latencies, 0.5),
        latencies.last().copied().unwrap_or(f64::NAN)
    );
}

/// A dashboard on a terminal this program owns, against a robot on a second pseudo-terminal that sends
/// feedback every 20 ms from a thread. `kitty`: answer the keyboard-protocol query, so the dashboard gets
/// release events. Returns the child, the key writer, the motion frames and a stop flag for the feeder.
struct Dash {
    child: std::process::Child,
    keys: serialport::TTYPort,
    arrivals: std::sync::mpsc::Receiver<(Instant, i8)>,
    done: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// Bytes the dashboard has drawn so far.
    drawn: std::sync::Arc<std::sync::atomic::AtomicU64>,
}

impl Dash {
    fn start(kitty: bool) -> Self {
        use std::sync::atomic::{AtomicBool, Ordering};
        use std::sync::Arc;
        let (robot, robot_path) = pty();
        let (terminal, terminal_path) = terminal_pty();
        let arrivals = record_motion_frames(robot.try_clone().unwrap());
        let slave = || std::fs::OpenOptions::new().read(true).write(true).open(&terminal_path).unwrap();
        let child = Command::new(binary())
            .args(["--serial", &robot_path, "dashboard"])
            .env("TERM", "xterm-256color")
            .stdin(slave())
            .stdout(slave())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let done = Arc::new(AtomicBool::new(false));
        let drawn = Arc::new(std::sync::atomic::AtomicU64::new(0));
        // The screen: drained (a terminal that is not read would block the dashboard), bytes counted; the
        // keyboard-protocol query (CSI ? u) answered when `kitty`.
        {
            let (mut screen, mut answer, done) =
                (terminal.try_clone().unwrap(), terminal.try_clone().unwrap(), Arc::clone(&done));
            let drawn = Arc::clone(&drawn);
            std::thread::spawn(move || {
                let mut buffer = [0u8; 65536];
                screen.set_timeout(Duration::from_millis(100)).unwrap();
                while !done.load(Ordering::SeqCst) {
                    if let Ok(read) = screen.read(&mut buffer) {
                        drawn.fetch_add(read as u64, Ordering::Relaxed);
                        let text = &buffer[..read];
                        if kitty && text.windows(4).any(|w| w == b"\x1b[?u") {
                            // Flags 0 (none pushed yet), then the primary device attributes.
                            let _ = answer.write_all(b"\x1b[?0u\x1b[?62;22c");
                        }
                    }
                }
            });
        }
        {
            let (mut robot, done) = (robot, Arc::clone(&done));
            std::thread::spawn(move || {
                let mut encoder = SerialEncoder::new();
                let mut next = Instant::now();
                while !done.load(Ordering::SeqCst) {
                    let _ = robot.write_all(&feedback(&mut encoder));
                    next += Duration::from_millis(20);
                    std::thread::sleep(next.saturating_duration_since(Instant::now()));
                }
            });
        }
        let mut dash = Self { child, keys: terminal, arrivals, done, drawn };
        std::thread::sleep(Duration::from_millis(if kitty { 1500 } else { 3500 }));
        dash.type_keys(b"a", 300);
        dash.type_keys(b"y", 500);
        dash
    }

    fn type_keys(&mut self, bytes: &[u8], then_ms: u64) {
        self.keys.write_all(bytes).unwrap();
        std::thread::sleep(Duration::from_millis(then_ms));
    }

    /// Motion frames since the last call.
    fn frames(&self) -> Vec<(Instant, i8)> {
        self.arrivals.try_iter().collect()
    }

    fn quit(mut self) {
        self.type_keys(b"q", 300);
        self.done.store(true, std::sync::atomic::Ordering::SeqCst);
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Milliseconds from `from` to the first zero frame at or after it.
fn to_zero(frames: &[(Instant, i8)], from: Instant) -> Option<f64> {
    frames
        .iter()
        .find(|(at, percent)| *at >= from && *percent == 0)
        .map(|(at, _)| at.duration_since(from).as_secs_f64() * 1000.0)
}

fn summary(name: &str, mut samples: Vec<f64>) {
    samples.sort_by(f64::total_cmp);
    if samples.is_empty() {
        println!("stops: {name}: no samples");
        return;
    }
    println!(
        "stops: {name}: {} runs, p50 {:.1} ms, max {:.1} ms",
        samples.len(),
        percentile(&samples, 0.5),
        samples.last().unwrap()
    );
}

#[expect(clippy::too_many_lines, reason = "each stop path measured in turn, the same way, in one place")]
fn stops() {
    // Release events (kitty protocol): press, repeats every 33 ms for 1 s, release.
    let mut dash = Dash::start(true);
    let mut release_events = Vec::new();
    for _ in 0..5 {
        dash.frames();
        dash.type_keys(b"\x1b[1;1:1A", 33);
        for _ in 0..30 {
            dash.type_keys(b"\x1b[1;1:2A", 33);
        }
        let moving = dash.frames().iter().any(|(_, percent)| *percent == 10);
        let released = Instant::now();
        dash.type_keys(b"\x1b[1;1:3A", 600);
        if moving {
            release_events.extend(to_zero(&dash.frames(), released));
        }
    }
    dash.quit();
    summary("release event to zero, from 0.15 m/s (kitty protocol)", release_events);

    // No release events: auto-repeat every 33 ms for 1 s, then nothing; the deadline ends the hold.
    let mut dash = Dash::start(false);
    let mut deadline = Vec::new();
    for _ in 0..5 {
        dash.frames();
        for _ in 0..30 {
            dash.type_keys(b"\x1b[A", 33);
        }
        let last_key = Instant::now() - Duration::from_millis(33);
        std::thread::sleep(Duration::from_millis(900));
        let frames = dash.frames();
        if frames.iter().any(|(_, percent)| *percent == 10) {
            deadline.extend(to_zero(&frames, last_key));
        }
    }
    // Space from full speed (scale 100 %: 0.5 m/s = 33 %): zero at once, no ramp in between.
    for _ in 0..7 {
        dash.type_keys(b"+", 20);
    }
    let mut space = Vec::new();
    let mut ramp_frames = 0;
    for _ in 0..5 {
        for _ in 0..45 {
            dash.type_keys(b"\x1b[A", 33);
        }
        dash.frames();
        let pressed = Instant::now();
        dash.type_keys(b" ", 1200);
        let frames = dash.frames();
        if let Some(ms) = to_zero(&frames, pressed) {
            space.push(ms);
            ramp_frames += frames.iter().filter(|(at, p)| *at >= pressed && *p != 0 && *p != 33).count();
        }
    }
    dash.quit();
    summary("last auto-repeat to zero, from 0.15 m/s (learned deadline, 33 ms repeats)", deadline);
    summary("Space to zero, from 0.5 m/s", space);
    println!("stops: frames between full speed and zero after Space: {ramp_frames} (0 = no ramp)");

    // drive: signal to the first zero frame, on a pseudo-terminal.
    for (name, signal) in [("SIGINT", 2), ("SIGTERM", 15), ("SIGHUP", 1), ("SIGTSTP", 20)] {
        let mut samples = Vec::new();
        for _ in 0..5 {
            let (master, path) = pty();
            let arrivals = record_motion_frames(master.try_clone().unwrap());
            let mut child = Command::new(binary())
                .args(["--serial", &path, "drive", "--linear", "0.3"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .unwrap();
            let mut master = master;
            let mut encoder = SerialEncoder::new();
            let started = Instant::now();
            let mut seen = Vec::new();
            while started.elapsed() < Duration::from_millis(1500) {
                let _ = master.write_all(&feedback(&mut encoder));
                std::thread::sleep(Duration::from_millis(20));
            }
            seen.extend(arrivals.try_iter());
            let sent = Instant::now();
            // SAFETY: kill only sends a signal to a process id; no memory is touched.
            unsafe { libc::kill(child.id() as i32, signal) };
            let until = Instant::now() + Duration::from_millis(300);
            while Instant::now() < until {
                let _ = master.write_all(&feedback(&mut encoder));
                std::thread::sleep(Duration::from_millis(20));
            }
            if signal == 20 {
                // SAFETY: kill only sends a signal to a process id; no memory is touched.
                unsafe { libc::kill(child.id() as i32, libc::SIGCONT) };
            }
            let _ = child.wait();
            seen.extend(arrivals.try_iter());
            if seen.iter().any(|(at, p)| *at < sent && *p == 20) {
                samples.extend(to_zero(&seen, sent));
            }
        }
        summary(&format!("drive: {name} to zero on a pseudo-terminal, from 0.3 m/s"), samples);
    }

    // drive: SIGSTOP for 0.8 s at full speed, then SIGCONT: what reaches the robot after the resume.
    let (master, path) = pty();
    let arrivals = record_motion_frames(master.try_clone().unwrap());
    let child = Command::new(binary())
        .args(["--serial", &path, "drive", "--linear", "0.3"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut master = master;
    let mut encoder = SerialEncoder::new();
    let mut feed = |how_long: Duration, master: &mut serialport::TTYPort| {
        let until = Instant::now() + how_long;
        while Instant::now() < until {
            let _ = master.write_all(&feedback(&mut encoder));
            std::thread::sleep(Duration::from_millis(20));
        }
    };
    feed(Duration::from_millis(1500), &mut master);
    // SAFETY: kill only sends a signal to a process id; no memory is touched.
    unsafe { libc::kill(child.id() as i32, libc::SIGSTOP) };
    feed(Duration::from_millis(800), &mut master);
    arrivals.try_iter().for_each(drop);
    let resumed = Instant::now();
    // SAFETY: kill only sends a signal to a process id; no memory is touched.
    unsafe { libc::kill(child.id() as i32, libc::SIGCONT) };
    feed(Duration::from_millis(500), &mut master);
    let output = child.wait_with_output().unwrap();
    let after: Vec<i8> = arrivals.try_iter().filter(|(at, _)| *at >= resumed).map(|(_, p)| p).collect();
    let message = String::from_utf8_lossy(&output.stderr);
    println!(
        "stops: drive SIGSTOP 0.8 s / SIGCONT: frames after the resume {after:?}, exit {:?}, {}",
        output.status.code(),
        message.lines().last().unwrap_or("").split(';').next().unwrap_or("")
    );
}

fn main() {
    let seconds: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    if std::env::args().nth(2).as_deref() == Some("stops") {
        stops();
        return;
    }
    drive(seconds);
    monitor_normal(seconds);
    monitor_flood(200_000);
    dashboard(seconds);
    stops();
}
