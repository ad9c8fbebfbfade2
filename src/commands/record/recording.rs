//! The recorder's one loop: frames from the link into a batch (handed to the writer thread every second
//! and at each segment's end), each frame to the trigger watcher, triggers into incident windows, and
//! windows that are over to the writer. Watch-only: the link's sending half is never used.

use std::collections::VecDeque;
use std::io;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{SyncSender, TrySendError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;
use serde_json::Value;

use super::incident::Request;
use super::writer::{self, Job, Limits};
use super::Settings;
use crate::blackbox::lock::{Acquired, DirLock};
use crate::blackbox::ring::Bounds;
use crate::blackbox::status::Status;
use crate::blackbox::triggers::{Cause, Trigger, Watcher};
use crate::blackbox::window::{Window, Windows};
use crate::blackbox::{marks, names};
use crate::commands::Global;
use crate::exit::{Failure, FAILURE, SUCCESS};
use crate::link::FrameRx;
use crate::session;
use crate::signals::SignalFlag;

/// Batches go to the writer this often: a crash of the process (kill -9) loses at most this, plus the
/// moments the writer takes to write it, within the one second ...
const BATCH_EVERY: Duration = Duration::from_millis(500);
/// ... or when this large (a replay at full speed).
const BATCH_BYTES: usize = 256 * 1024;
/// Triggers on time (link silence, windows over) and marks are looked at this often.
const TICK: Duration = Duration::from_millis(100);
const MARKS_EVERY: Duration = Duration::from_secs(1);
/// A window on a live link is over this long after its end: frames stamped before it may still be queued.
const LIVE_GRACE_US: u64 = 500_000;
/// A link that cannot be opened is tried again this often.
const REOPEN_EVERY: Duration = Duration::from_secs(1);

pub fn run(global: &Global, dir: &Path, settings: &Settings) -> Result<u8> {
    std::fs::create_dir_all(dir)
        .map_err(|error| anyhow::anyhow!("cannot create {}: {error}", dir.display()))?;
    let _lock = match DirLock::acquire(dir)
        .map_err(|error| anyhow::anyhow!("cannot lock {}: {error}", dir.display()))?
    {
        Acquired::Held(lock) => lock,
        Acquired::Busy(pid) => {
            let who = pid.map_or_else(|| "another process".to_string(), |pid| format!("process {pid}"));
            return Err(Failure {
                code: FAILURE,
                message: format!(
                    "{who} already records into {}: one recorder per directory (see tracerctl record --status --dir {})",
                    dir.display(),
                    dir.display()
                ),
            }
            .into());
        }
    };
    let signals = crate::signals::listen(|_| {})?;
    let marked = listen_usr1()?;
    let link_name = link_name(global);
    let started = wall_us();
    let status = Arc::new(Mutex::new(Status {
        pid: std::process::id(),
        started,
        updated: started,
        link: link_name.clone(),
        state: "starting".to_string(),
        ..Status::default()
    }));
    let limits = Limits {
        bounds: Bounds { max_total: settings.max_total, max_age: micros(settings.max_age) },
        max_incidents: settings.max_incidents,
    };
    let (jobs, writer) = writer::start(dir, limits, Arc::clone(&status))?;
    crate::say!("tracerctl: {}", super::inspect::describe_start(&link_name, dir, settings));
    let mut recorder = Recorder::new(global, dir, settings, jobs, Arc::clone(&status), link_name);
    let end = recorder.run(global, &signals, &marked);
    recorder.finish(&end);
    let _ = writer.join();
    let status = status.lock().clone();
    crate::say!(
        "tracerctl: stopped ({end}): {} frames recorded, {} lost, {} incidents, into {}",
        status.frames_recorded,
        status.frames_lost,
        status.incidents_made,
        dir.display()
    );
    Ok(SUCCESS)
}

/// SIGUSR1 is a mark ("the operator saw something").
#[cfg(unix)]
fn listen_usr1() -> Result<Arc<AtomicBool>> {
    let flag = Arc::new(AtomicBool::new(false));
    signal_hook::flag::register(signal_hook::consts::SIGUSR1, Arc::clone(&flag))?;
    Ok(flag)
}

#[cfg(not(unix))]
fn listen_usr1() -> Result<Arc<AtomicBool>> {
    Ok(Arc::new(AtomicBool::new(false)))
}

fn link_name(global: &Global) -> String {
    match &global.link {
        crate::link::LinkChoice::SocketCan { iface } => iface.clone(),
        crate::link::LinkChoice::Serial { path, .. } => path.display().to_string(),
        crate::link::LinkChoice::Sim => "sim".to_string(),
        crate::link::LinkChoice::Replay { path, .. } => path.display().to_string(),
    }
}

fn wall_us() -> u64 {
    names::micros(&crate::link::now_timestamp())
}

fn micros(duration: Duration) -> u64 {
    u64::try_from(duration.as_micros()).unwrap_or(u64::MAX)
}

/// Why recording ended.
pub enum End {
    Signal(&'static str),
    /// A replayed log or the simulator came to its end.
    SourceEnded,
}

impl std::fmt::Display for End {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            End::Signal(name) => f.write_str(name),
            End::SourceEnded => f.write_str("the source ended"),
        }
    }
}

struct Recorder<'a> {
    dir: &'a Path,
    settings: &'a Settings,
    jobs: SyncSender<Job>,
    status: Arc<Mutex<Status>>,
    link_name: String,
    protocol: crate::protocol::ProtocolHint,
    /// The lines' interface name (a replayed file's path is none).
    iface: String,
    /// A replay's clock is its frames' stamps; other links run on the wall clock.
    replay: bool,
    batch: Vec<u8>,
    batch_lines: u64,
    batch_sent: Instant,
    /// The next batch starts a segment at this time.
    new_segment: Option<u64>,
    segment_start: Option<u64>,
    last_frame: u64,
    watcher: Watcher,
    fired: Vec<Trigger>,
    windows: Windows<Cause>,
    /// The decoded state when the open window's first trigger fired.
    window_state: Value,
    /// Incidents the writer had no room for yet, in order.
    waiting: VecDeque<Request>,
    ticked: Instant,
    marks_read: Instant,
    socket_drops: u64,
}

impl<'a> Recorder<'a> {
    fn new(
        global: &Global,
        dir: &'a Path,
        settings: &'a Settings,
        jobs: SyncSender<Job>,
        status: Arc<Mutex<Status>>,
        link_name: String,
    ) -> Self {
        let replay = matches!(global.link, crate::link::LinkChoice::Replay { .. });
        let iface = if replay { "replay".to_string() } else { link_name.chars().take(15).collect() };
        Self {
            dir,
            settings,
            jobs,
            status,
            link_name,
            protocol: global.protocol,
            iface,
            replay,
            batch: Vec::with_capacity(BATCH_BYTES + 4096),
            batch_lines: 0,
            batch_sent: Instant::now(),
            new_segment: None,
            segment_start: None,
            last_frame: 0,
            watcher: Watcher::new(settings.triggers.clone()),
            fired: Vec::new(),
            windows: Windows::new(micros(settings.before), micros(settings.after)),
            window_state: Value::Null,
            waiting: VecDeque::new(),
            ticked: Instant::now(),
            marks_read: Instant::now(),
            socket_drops: 0,
        }
    }

    /// The recorder's clock, microseconds.
    fn now(&self) -> u64 {
        if self.replay {
            self.last_frame
        } else {
            wall_us()
        }
    }

    /// Opens the link (waiting for it while it cannot be), records until a signal or the source's end,
    /// and opens it again when it goes away.
    fn run(&mut self, global: &Global, signals: &SignalFlag, marked: &AtomicBool) -> End {
        let mut outage: Option<(Instant, String)> = None;
        loop {
            if let Some(caught) = signals.caught() {
                return End::Signal(caught.name());
            }
            let (link, simulator) = match session::open_link(&global.link, global.sim_config()) {
                Ok(opened) => opened,
                Err(error) => {
                    let error = format!("{error:#}");
                    if outage.as_ref().is_none_or(|(_, said)| *said != error) {
                        crate::say!(
                            "tracerctl: cannot open {}: {error}; trying again every second",
                            self.link_name
                        );
                        self.status.lock().state = format!("waiting for {}: {error}", self.link_name);
                    }
                    let since = outage.map_or_else(Instant::now, |(since, _)| since);
                    outage = Some((since, error));
                    self.wait(REOPEN_EVERY, signals, marked);
                    continue;
                }
            };
            if let Some((since, _)) = outage.take() {
                crate::say!(
                    "tracerctl: {} is back after {:.1} s; recording",
                    self.link_name,
                    since.elapsed().as_secs_f64()
                );
                self.status.lock().link_outages += 1;
            }
            self.status.lock().state = "recording".to_string();
            // The kernel's drop counter is the socket's: a link opened again counts from 0.
            self.socket_drops = 0;
            let mut rx = link.rx;
            let ended = self.receive(rx.as_mut(), signals, marked);
            for note in rx.take_notes() {
                crate::say!("tracerctl: {note}");
            }
            drop(simulator);
            match ended {
                Ended::End(end) => {
                    if let Some(report) = rx.report() {
                        crate::say!("tracerctl: {report}");
                    }
                    return end;
                }
                Ended::LinkLost(error) => {
                    let error = lost_why(&global.link, error);
                    crate::say!("tracerctl: lost {}: {error}; waiting for it to come back", self.link_name);
                    self.status.lock().state = format!("waiting for {}: {error}", self.link_name);
                    outage = Some((Instant::now(), String::new()));
                }
            }
        }
    }

    fn receive(&mut self, rx: &mut dyn FrameRx, signals: &SignalFlag, marked: &AtomicBool) -> Ended {
        loop {
            if let Some(caught) = signals.caught() {
                return Ended::End(End::Signal(caught.name()));
            }
            match rx.recv(TICK) {
                Ok(Some(received)) => self.frame(&received),
                Ok(None) => {}
                Err(error) if error.kind() == io::ErrorKind::UnexpectedEof => {
                    return Ended::End(End::SourceEnded);
                }
                Err(error) => return Ended::LinkLost(error.to_string()),
            }
            let drops = rx.stats().socket_drops;
            if drops > self.socket_drops {
                let reason = "the kernel dropped frames: the socket's receive queue was full";
                self.status.lock().lose(drops - self.socket_drops, reason);
                self.socket_drops = drops;
            }
            self.tick(marked);
        }
    }

    /// Waits `time` (a link that cannot be opened), still handing over batches and closing windows.
    fn wait(&mut self, time: Duration, signals: &SignalFlag, marked: &AtomicBool) {
        let until = Instant::now() + time;
        while Instant::now() < until && signals.caught().is_none() {
            std::thread::sleep(TICK);
            self.tick(marked);
        }
    }

    fn frame(&mut self, received: &crate::link::Received) {
        let time = names::micros(&received.ts);
        self.last_frame = time;
        match self.segment_start {
            Some(start) if time.saturating_sub(start) < micros(self.settings.segment) => {}
            _ => {
                self.send_batch();
                self.new_segment = Some(time);
                self.segment_start = Some(time);
            }
        }
        crate::recorder::push_raw_line(&mut self.batch, received, &self.iface);
        self.batch_lines += 1;
        self.watcher.frame(received.ts, &received.frame, &mut self.fired);
        self.take_triggers();
        if self.replay {
            self.close_due(time);
        }
        if self.batch.len() >= BATCH_BYTES {
            self.send_batch();
        }
    }

    fn take_triggers(&mut self) {
        let fired = std::mem::take(&mut self.fired);
        for trigger in &fired {
            self.trigger(names::micros(&trigger.at), trigger.cause.clone());
        }
        self.fired = fired;
        self.fired.clear();
    }

    fn trigger(&mut self, at: u64, cause: Cause) {
        crate::say!("tracerctl: trigger at {}: {}", names::rfc3339_millis(at), cause.describe());
        let opening = self.windows.open().is_none_or(|open| at > open.end);
        let state = if opening { self.watcher.state() } else { Value::Null };
        let previous_state = std::mem::replace(&mut self.window_state, Value::Null);
        if let Some(closed) = self.windows.trigger(at, cause) {
            self.incident(closed, previous_state, None);
        } else if !opening {
            self.window_state = previous_state;
        }
        if opening {
            self.window_state = state;
        }
    }

    fn tick(&mut self, marked: &AtomicBool) {
        if self.batch_sent.elapsed() >= BATCH_EVERY {
            self.send_batch();
        }
        if self.ticked.elapsed() < TICK {
            return;
        }
        self.ticked = Instant::now();
        let now = self.now();
        if !self.replay {
            self.watcher.tick(names::timestamp(now), &mut self.fired);
            self.take_triggers();
            self.close_due(now.saturating_sub(LIVE_GRACE_US));
        }
        if marked.swap(false, Ordering::SeqCst) {
            self.trigger(now, Cause::Mark { note: "SIGUSR1".to_string() });
        }
        if self.marks_read.elapsed() >= MARKS_EVERY {
            self.marks_read = Instant::now();
            self.take_marks(now);
        }
        self.send_waiting();
    }

    fn take_marks(&mut self, now: u64) {
        match marks::take(self.dir) {
            Ok(taken) => {
                for (time, note) in taken {
                    // A replay's clock is not the wall clock the mark was made on.
                    let at = if self.replay { now } else { time };
                    self.trigger(at, Cause::Mark { note });
                }
            }
            Err(error) => crate::say!("tracerctl: cannot read the marks in {}: {error}", self.dir.display()),
        }
    }

    fn close_due(&mut self, now: u64) {
        if let Some(window) = self.windows.due(now) {
            let state = std::mem::replace(&mut self.window_state, Value::Null);
            self.incident(window, state, None);
        }
    }

    fn incident(&mut self, window: Window<Cause>, state: Value, cut_short: Option<String>) {
        // Every line of the window is in a batch sent before the request.
        self.send_batch();
        self.waiting.push_back(Request {
            window,
            state,
            link: self.link_name.clone(),
            protocol: self.protocol,
            before_us: micros(self.settings.before),
            after_us: micros(self.settings.after),
            cut_short,
        });
        self.send_waiting();
    }

    fn send_waiting(&mut self) {
        while let Some(request) = self.waiting.pop_front() {
            match self.jobs.try_send(Job::Incident(Box::new(request))) {
                Ok(()) => {}
                Err(TrySendError::Full(Job::Incident(request))) => {
                    self.waiting.push_front(*request);
                    return;
                }
                Err(_) => {
                    crate::say!("tracerctl: the writer thread has stopped: an incident is lost");
                    return;
                }
            }
        }
    }

    /// Hands the batch to the writer; a writer that far behind loses it, counted.
    fn send_batch(&mut self) {
        self.batch_sent = Instant::now();
        let text = std::mem::replace(&mut self.batch, Vec::with_capacity(BATCH_BYTES + 4096));
        let lines = std::mem::take(&mut self.batch_lines);
        let segment = self.new_segment.take();
        let now = self.now();
        match self.jobs.try_send(Job::Batch { segment, text, lines, now }) {
            Ok(()) => {}
            Err(TrySendError::Full(_)) => {
                // The segment still starts, with the next batch.
                self.new_segment = segment;
                let reason =
                    format!("the disk was too slow: {} s of frames were waiting", writer::QUEUE_BATCHES);
                self.status.lock().lose(lines, &reason);
            }
            Err(TrySendError::Disconnected(_)) => self.status.lock().lose(lines, "the writer thread stopped"),
        }
    }

    /// The end: the last batch, the open window as an incident cut short, and the writer stopped.
    fn finish(&mut self, end: &End) {
        if let Some(window) = self.windows.take() {
            let state = std::mem::replace(&mut self.window_state, Value::Null);
            self.incident(window, state, Some(end.to_string()));
        }
        self.send_batch();
        // Blocking now: nothing is received any more.
        while let Some(request) = self.waiting.pop_front() {
            let _ = self.jobs.send(Job::Incident(Box::new(request)));
        }
        let _ = self.jobs.send(Job::Stop);
    }
}

/// Why a link went away, in words: an interface that no longer exists is said so (the kernel reports
/// "network is down" first, whose advice, bringing it up, does not apply to an unplugged adapter).
fn lost_why(link: &crate::link::LinkChoice, error: String) -> String {
    if let crate::link::LinkChoice::SocketCan { iface } = link {
        // `ip link del` and an unplugged adapter take the interface down first, then away.
        std::thread::sleep(Duration::from_millis(200));
        if cfg!(target_os = "linux") && !Path::new("/sys/class/net").join(iface).exists() {
            return format!("the interface {iface} is gone (adapter unplugged, or the interface deleted)");
        }
        // The socket's error knows no name.
        return error.replace("IFACE", iface);
    }
    error
}

/// How receiving from one opened link ended.
enum Ended {
    End(End),
    LinkLost(String),
}
