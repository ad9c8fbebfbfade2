//! The live part of the report: the doctor's checks, the firmware version query, the protocol and rates,
//! and the listen recorded when no recorder runs. The link is opened as every command opens it, with a
//! tap between it and the session that keeps what crosses it: candump -L lines of every frame received
//! and sent (up to a size, then counted), and the answers to the version query.

use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use parking_lot::Mutex;
use serde_json::json;

use crate::commands::doctor::{self, report::ReportFormat, Diagnosis};
use crate::commands::Global;
use crate::link::{self, FrameRx, FrameTx, LinkChoice, LinkFrame, LinkKind, Received, RxStats};
use crate::protocol::detect::Verdict;
use crate::protocol::version::{self, VersionAnswer};
use crate::protocol::{catalog, Wire};
use crate::session::{RobotStatus, Session};

/// How long to wait for the answer to the version query (the AgileX SDK waits 3 s for its text).
pub const VERSION_WAIT: Duration = Duration::from_secs(3);

/// What crossed the link during the report.
#[derive(Default)]
struct Tapped {
    /// candump -L lines, when recording.
    log: Option<Vec<u8>>,
    log_limit: usize,
    frames: u64,
    /// Frames not kept because the log reached its limit.
    dropped: u64,
    iface: String,
    answer: VersionAnswer,
}

impl Tapped {
    fn take(&mut self, received: &Received, incoming: bool) {
        self.frames += 1;
        if let (true, LinkFrame::Can(frame)) = (incoming, &received.frame) {
            self.answer.observe(frame);
        }
        if let Some(log) = &mut self.log {
            let before = log.len();
            crate::recorder::push_raw_line(log, received, &self.iface);
            if log.len() > self.log_limit {
                log.truncate(before);
                self.dropped += 1;
            }
        }
    }
}

struct TapRx {
    inner: Box<dyn FrameRx>,
    tap: Arc<Mutex<Tapped>>,
}

impl FrameRx for TapRx {
    fn recv(&mut self, timeout: Duration) -> std::io::Result<Option<Received>> {
        let received = self.inner.recv(timeout)?;
        if let Some(received) = &received {
            self.tap.lock().take(received, true);
        }
        Ok(received)
    }

    fn stats(&self) -> RxStats {
        self.inner.stats()
    }

    fn take_notes(&mut self) -> Vec<String> {
        self.inner.take_notes()
    }

    fn report(&self) -> Option<String> {
        self.inner.report()
    }
}

struct TapTx {
    inner: Arc<dyn FrameTx>,
    tap: Arc<Mutex<Tapped>>,
}

impl FrameTx for TapTx {
    fn send(&self, frame: &LinkFrame) -> std::io::Result<()> {
        self.inner.send(frame)?;
        self.tap.lock().take(&Received { ts: link::now_timestamp(), frame: *frame }, false);
        Ok(())
    }

    fn pending(&self) -> Option<usize> {
        self.inner.pending()
    }

    fn discard_pending(&self) -> link::Discarded {
        self.inner.discard_pending()
    }
}

/// The listen the report recorded itself (no recorder running).
pub struct ListenLog {
    pub bytes: Vec<u8>,
    pub frames: u64,
    pub dropped: u64,
}

/// What the live part found.
pub struct Findings {
    pub doctor_text: Vec<u8>,
    pub doctor_json: Vec<u8>,
    pub robot_text: String,
    pub robot_json: serde_json::Value,
    pub listen: Option<ListenLog>,
    /// What the link said about itself (a replay's rejected lines), for stderr.
    pub notes: Vec<String>,
}

/// The settings of the live part.
pub struct Live {
    pub doctor: doctor::Options,
    /// Keep the frames as `listen.log` (no recorder runs), up to this many bytes.
    pub record: Option<usize>,
}

/// Runs the doctor on the link with the tap in place, asks the firmware version, measures the rates.
pub fn examine(global: &Global, live: &Live) -> Result<Findings> {
    let tap = Arc::new(Mutex::new(Tapped {
        log: live.record.map(|_| Vec::new()),
        log_limit: live.record.unwrap_or(0),
        iface: log_iface(&global.link),
        ..Tapped::default()
    }));
    let mut simulator = None;
    let mut opened_at = Instant::now();
    let open = || -> Result<Session> {
        let (mut link, running) = crate::session::open_link(&global.link, global.sim_config())?;
        simulator = running;
        link.rx = Box::new(TapRx { inner: link.rx, tap: Arc::clone(&tap) });
        link.tx = Arc::new(TapTx { inner: link.tx, tap: Arc::clone(&tap) });
        opened_at = Instant::now();
        Session::from_link(link, global.protocol)
    };
    let diagnosis = doctor::diagnose(global, &live.doctor, open)?;
    let doctor_text = diagnosis.render(ReportFormat::Text)?;
    let doctor_json = diagnosis.render(ReportFormat::Json)?;
    let Diagnosis { session, .. } = diagnosis;
    let (status, listened, wire) = match &session {
        Some(session) => (Some(session.status()), opened_at.elapsed(), session.wire()),
        None => (None, Duration::ZERO, Wire::CanV2),
    };
    let version = match &session {
        Some(session) => ask_version(session, status.as_ref(), &tap),
        None => Version::NotAsked("the link could not be used (doctor.txt says why)".to_string()),
    };
    let mut notes = Vec::new();
    let opened = session.is_some();
    if let Some(session) = session {
        let finished = session.finish();
        notes.extend(finished.notes);
        notes.extend(finished.report);
    }
    drop(simulator);
    let tapped = std::mem::take(&mut *tap.lock());
    // A link that could not be opened carried nothing: no empty log to mistake for a silent robot.
    let listen = tapped.log.filter(|_| opened).map(|bytes| ListenLog {
        bytes,
        frames: tapped.frames - tapped.dropped,
        dropped: tapped.dropped,
    });
    let rates = status.as_ref().map(|status| Rates::of(status, listened, wire));
    let name = link_text(&global.link);
    Ok(Findings {
        doctor_text,
        doctor_json,
        robot_text: robot_text(&name, &version, rates.as_ref()),
        robot_json: robot_json(&name, &version, rates.as_ref()),
        listen,
        notes,
    })
}

/// The interface field of the listen's candump lines: the CAN interface, or what the link is.
fn log_iface(choice: &LinkChoice) -> String {
    match choice {
        LinkChoice::SocketCan { iface } => iface.clone(),
        LinkChoice::Serial { path, .. } => path.display().to_string(),
        LinkChoice::Sim => "sim".to_string(),
        LinkChoice::Replay { .. } => "replay".to_string(),
    }
}

fn link_text(choice: &LinkChoice) -> String {
    match choice {
        LinkChoice::SocketCan { iface } => format!("{iface} (SocketCAN)"),
        LinkChoice::Serial { path, baud } => format!("{} (RS232, {baud} baud)", path.display()),
        LinkChoice::Sim => "the in-process virtual TRACER (--sim)".to_string(),
        LinkChoice::Replay { path, .. } => format!("{} (replay)", path.display()),
    }
}

/// The version query's outcome.
enum Version {
    /// The answers in words, and whether they came to our query (or were seen in the traffic).
    Answered {
        lines: Vec<String>,
        text: Option<String>,
        asked: bool,
    },
    NoAnswer {
        sent: Vec<String>,
    },
    NotAsked(String),
}

/// Sends both version requests on a live CAN V2 link where the robot was heard, and waits for an answer.
fn ask_version(session: &Session, status: Option<&RobotStatus>, tap: &Mutex<Tapped>) -> Version {
    let seen = |asked: bool| {
        let tapped = tap.lock();
        let answer = &tapped.answer;
        answer.answered().then(|| Version::Answered {
            lines: answer.describe(),
            text: answer.text().map(str::to_string),
            asked,
        })
    };
    let heard = status.is_some_and(|status| status.frames > 0);
    let refusal = match (session.kind, session.wire()) {
        (LinkKind::Replay, _) => Some("--replay is read-only: nothing was sent".to_string()),
        (_, Wire::Serial) => Some("RS232 has no version query".to_string()),
        (_, Wire::CanV1) => Some("the robot speaks protocol V1; the version query is V2's".to_string()),
        _ if !heard => Some("nothing was heard from the robot, so nothing was asked".to_string()),
        _ if status.is_some_and(|s| s.detector.verdict() == Verdict::V1) => {
            Some("the robot speaks protocol V1; the version query is V2's".to_string())
        }
        _ => None,
    };
    if let Some(reason) = refusal {
        return seen(false).unwrap_or(Version::NotAsked(reason));
    }
    let requests = version::requests();
    let mut sent = Vec::new();
    for frame in requests {
        if let Err(error) = session.send(&LinkFrame::Can(frame)) {
            return Version::NotAsked(format!("the query {frame} could not be sent: {error:#}"));
        }
        sent.push(frame.to_string());
    }
    let deadline = Instant::now() + VERSION_WAIT;
    while Instant::now() < deadline && !tap.lock().answer.is_complete() {
        std::thread::sleep(Duration::from_millis(20));
    }
    seen(true).unwrap_or(Version::NoAnswer { sent })
}

/// Frames per identifier over the listen, against the catalog's periods.
struct Rates {
    listened: Duration,
    frames: u64,
    protocol: String,
    identifiers: Vec<(String, &'static str, u64, Option<f64>)>,
    error_frames: u64,
    errors: String,
    rx: RxStats,
}

impl Rates {
    fn of(status: &RobotStatus, listened: Duration, wire: Wire) -> Self {
        let identifiers = status
            .id_counts
            .iter()
            .map(|(id, count)| {
                let label = catalog::label(*id).unwrap_or("unknown");
                let expected = catalog::periodic_frame(*id)
                    .and_then(|entry| entry.period)
                    .map(|p| 1.0 / p.as_secs_f64());
                (id.to_string(), label, *count, expected)
            })
            .collect();
        Self {
            listened,
            frames: status.frames,
            // The detector tells CAN versions apart; RS232 is its own protocol.
            protocol: match wire {
                Wire::Serial => "RS232".to_string(),
                _ => status.detector.describe(),
            },
            identifiers,
            error_frames: status.error_tally.frames,
            errors: status.error_tally.describe(),
            rx: status.rx,
        }
    }

    fn per_second(&self, count: u64) -> f64 {
        let seconds = self.listened.as_secs_f64();
        if seconds > 0.0 {
            count as f64 / seconds
        } else {
            0.0
        }
    }
}

fn version_lines(version: &Version) -> Vec<String> {
    match version {
        Version::Answered { lines, asked, .. } => {
            let how = if *asked { "answered" } else { "seen in the traffic, not asked" };
            lines.iter().map(|line| format!("{line}, {how}")).collect()
        }
        Version::NoAnswer { sent } => vec![format!(
            "no answer to the version query within {} s (sent {})",
            VERSION_WAIT.as_secs(),
            sent.join(" and ")
        )],
        Version::NotAsked(reason) => vec![format!("not asked: {reason}")],
    }
}

fn robot_text(link: &str, version: &Version, rates: Option<&Rates>) -> String {
    use std::fmt::Write as _;
    let mut out = format!("link: {link}\n");
    for line in version_lines(version) {
        let _ = writeln!(out, "firmware version: {line}");
    }
    let Some(rates) = rates else {
        out.push_str("protocol and rates: not measured (the link could not be used)\n");
        return out;
    };
    let _ = writeln!(out, "protocol: {}", rates.protocol);
    let _ = writeln!(
        out,
        "listened {:.1} s: {} frames ({:.1} /s)",
        rates.listened.as_secs_f64(),
        rates.frames,
        rates.per_second(rates.frames)
    );
    if !rates.identifiers.is_empty() {
        let _ = writeln!(
            out,
            "\n{:<12} {:<14} {:>8} {:>8} {:>9}",
            "identifier", "label", "frames", "per s", "expected"
        );
        for (id, label, count, expected) in &rates.identifiers {
            let expected = expected.map_or_else(|| "-".to_string(), |rate| format!("{rate:.1}"));
            let _ = writeln!(
                out,
                "{id:<12} {label:<14} {count:>8} {:>8.1} {expected:>9}",
                rates.per_second(*count)
            );
        }
        out.push('\n');
    }
    let errors = if rates.error_frames == 0 { "none".to_string() } else { rates.errors.clone() };
    let _ = writeln!(out, "CAN error frames: {errors}");
    let rx = &rates.rx;
    let _ = writeln!(
        out,
        "link counters: {} socket drops, {} serial checksum errors, {} serial bytes skipped, {} serial sync losses, {} replayed lines rejected",
        rx.socket_drops, rx.serial_bad_checksum, rx.serial_skipped_bytes, rx.serial_sync_losses, rx.rejected_lines
    );
    out
}

fn robot_json(link: &str, version: &Version, rates: Option<&Rates>) -> serde_json::Value {
    let version = match version {
        Version::Answered { lines, text, asked } => {
            json!({"answered": true, "asked": asked, "answers": lines, "text": text})
        }
        Version::NoAnswer { sent } => {
            json!({"answered": false, "asked": true, "sent": sent, "waited_s": VERSION_WAIT.as_secs()})
        }
        Version::NotAsked(reason) => json!({"answered": false, "asked": false, "reason": reason}),
    };
    let rates = rates.map(|rates| {
        let identifiers: Vec<_> = rates
            .identifiers
            .iter()
            .map(|(id, label, count, expected)| {
                json!({"id": id, "label": label, "frames": count, "per_second": rates.per_second(*count), "expected_per_second": expected})
            })
            .collect();
        json!({
            "listened_s": rates.listened.as_secs_f64(),
            "protocol": rates.protocol,
            "frames": rates.frames,
            "per_second": rates.per_second(rates.frames),
            "identifiers": identifiers,
            "error_frames": rates.error_frames,
            "socket_drops": rates.rx.socket_drops,
            "serial_bad_checksum": rates.rx.serial_bad_checksum,
            "serial_skipped_bytes": rates.rx.serial_skipped_bytes,
            "serial_sync_losses": rates.rx.serial_sync_losses,
            "rejected_lines": rates.rx.rejected_lines,
        })
    });
    json!({"link": link, "firmware_version": version, "rates": rates})
}
