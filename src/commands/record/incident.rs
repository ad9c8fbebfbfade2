//! An incident's files, made from the ring once its window is over: `frames.log` (the ring's lines of the
//! window, byte for byte), `frames.mcap` (for Foxglove), `summary.txt` and `summary.json` (decode
//! --summary's report of the window) and `incident.json` (causes, times, the decoded state at the
//! trigger). Written into a hidden folder and renamed when complete: a listed incident is whole.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde_json::{json, Value};

use crate::blackbox::ring::Ring;
use crate::blackbox::triggers::Cause;
use crate::blackbox::window::Window;
use crate::blackbox::{incidents_dir, names};
use crate::candump::{Line, LineParser, Timestamp};
use crate::commands::decode::summary::Summary;
use crate::commands::decode::InputStats;
use crate::output::mcap::{Compression, McapWriter, Provenance};
use crate::output::{Event, FrameRef};
use crate::protocol::detect::{ProtocolDetector, Verdict};
use crate::protocol::serial::SerialFrame;
use crate::protocol::ProtocolHint;

/// The files of every incident.
pub const FRAMES: &str = "frames.log";
pub const MCAP: &str = "frames.mcap";
pub const SUMMARY_TEXT: &str = "summary.txt";
pub const SUMMARY_JSON: &str = "summary.json";
pub const INCIDENT: &str = "incident.json";

/// What the receive loop hands over when a window is over.
pub struct Request {
    pub window: Window<Cause>,
    /// The watcher's decoded state when the first trigger fired.
    pub state: Value,
    pub link: String,
    pub protocol: ProtocolHint,
    pub before_us: u64,
    pub after_us: u64,
    /// Why the window was closed before its end (`SIGTERM`, `the replay ended`).
    pub cut_short: Option<String>,
}

impl Request {
    /// `E-stop pressed; fault bit set: ...`
    pub fn causes_text(&self) -> String {
        let mut text = String::new();
        for (index, (_, cause)) in self.window.causes.iter().enumerate() {
            if index > 0 {
                text.push_str("; ");
            }
            text.push_str(&cause.describe());
        }
        text
    }
}

pub struct Made {
    pub name: String,
    pub frames: u64,
}

/// Writes the incident of `request` under `DIR/incidents/`.
pub fn write(dir: &Path, ring: &Ring, request: &Request) -> Result<Made> {
    let incidents = incidents_dir(dir);
    let slug = request.window.causes.first().map_or("trigger", |(_, cause)| cause.slug());
    let name = free_name(&incidents, &names::incident_name(request.window.trigger, slug));
    let partial = incidents.join(format!(".{name}.partial"));
    fs::create_dir_all(&partial).with_context(|| format!("cannot create {}", partial.display()))?;
    let result = fill(&partial, ring, request, &name);
    let frames = match result {
        Ok(frames) => frames,
        Err(error) => {
            let _ = fs::remove_dir_all(&partial);
            return Err(error);
        }
    };
    let done = incidents.join(&name);
    fs::rename(&partial, &done)
        .with_context(|| format!("cannot rename {} to {}", partial.display(), done.display()))?;
    Ok(Made { name, frames })
}

/// `NAME`, or `NAME-2`, `NAME-3`... when taken (two incidents in the same second for the same cause).
fn free_name(incidents: &Path, name: &str) -> String {
    let mut candidate = name.to_string();
    let mut number = 2;
    while incidents.join(&candidate).exists() {
        candidate = format!("{name}-{number}");
        number += 1;
    }
    candidate
}

fn fill(folder: &Path, ring: &Ring, request: &Request, name: &str) -> Result<u64> {
    let frames_path = folder.join(FRAMES);
    let mut out = BufWriter::new(
        File::create(&frames_path).with_context(|| format!("cannot create {}", frames_path.display()))?,
    );
    let mut write_error: Option<io::Error> = None;
    let window = &request.window;
    let back = ring
        .read_between(window.start, window.end, |line| {
            if write_error.is_none() {
                if let Err(error) = out.write_all(line) {
                    write_error = Some(error);
                }
            }
        })
        .with_context(|| format!("cannot read the ring {}", ring.dir().display()))?;
    if let Some(error) = write_error {
        return Err(error).with_context(|| format!("cannot write {}", frames_path.display()));
    }
    out.into_inner()
        .map_err(|e| e.into_error())
        .and_then(|file| file.sync_data())
        .with_context(|| format!("cannot write {}", frames_path.display()))?;
    let decoded = decode_window(folder, &frames_path, request)?;
    let incident = incident_json(request, name, back.lines, &back.damaged, &decoded);
    write_json(&folder.join(INCIDENT), &incident)?;
    Ok(back.lines)
}

/// What decoding the window found, for incident.json.
struct Decoded {
    protocol: &'static str,
    unreadable_lines: u64,
}

/// frames.log read back into the summary and the MCAP file.
fn decode_window(folder: &Path, frames_path: &Path, request: &Request) -> Result<Decoded> {
    let mcap_path = folder.join(MCAP);
    let file = File::create(&mcap_path).with_context(|| format!("cannot create {}", mcap_path.display()))?;
    let provenance = Provenance { command: "record", sources: vec![request.link.clone()] };
    let mut mcap = McapWriter::new(BufWriter::new(file), Compression::default(), provenance)
        .map_err(|error| anyhow::anyhow!("cannot write {}: {error}", mcap_path.display()))?;
    let mut summary = Summary::default();
    let mut stats = InputStats::default();
    let mut detector = ProtocolDetector::default();
    let (mut serial, mut unreadable_lines) = (false, 0u64);
    let mut parser = LineParser::new();
    // Streamed: a window extended by trigger after trigger has no bound but the ring's.
    let file = File::open(frames_path).with_context(|| format!("cannot read {}", frames_path.display()))?;
    let mut reader = io::BufReader::new(file);
    let mut buffer = Vec::with_capacity(128);
    loop {
        buffer.clear();
        if io::BufRead::read_until(&mut reader, b'\n', &mut buffer)
            .with_context(|| format!("cannot read {}", frames_path.display()))?
            == 0
        {
            break;
        }
        stats.lines += 1;
        let line = buffer.strip_suffix(b"\n").unwrap_or(&buffer);
        let event_result = if let Some((frame, ts, port)) = serial_line(line) {
            serial = true;
            let decoded = Ok(crate::protocol::serial::decode(&frame));
            let event =
                Event { ts: Some(ts), iface: port, dir: None, frame: FrameRef::Serial(&frame), decoded };
            summary.event(&event);
            mcap.event(&event)
        } else if let Ok(Line::Frame(record)) = parser.parse(line) {
            let decoded = detector.observe_and_decode(&record.frame, request.protocol);
            let event = Event {
                ts: record.ts,
                iface: record.iface,
                dir: record.dir,
                frame: FrameRef::Can(&record.frame),
                decoded,
            };
            summary.event(&event);
            mcap.event(&event)
        } else {
            unreadable_lines += 1;
            continue;
        };
        stats.frames += 1;
        stats.decoded_lines += 1;
        event_result.map_err(|error| anyhow::anyhow!("cannot write {}: {error}", mcap_path.display()))?;
    }
    let protocol = match detector.verdict() {
        _ if serial => "serial",
        Verdict::V1 => "can-v1",
        Verdict::V2 => "can-v2",
        Verdict::Unknown | Verdict::Mixed => "unknown",
    };
    let mut out = mcap
        .finish(protocol)
        .map_err(|error| anyhow::anyhow!("cannot write {}: {error}", mcap_path.display()))?;
    out.flush().with_context(|| format!("cannot write {}", mcap_path.display()))?;
    let report = summary.report(&stats, &detector);
    fs::write(folder.join(SUMMARY_TEXT), report).with_context(|| format!("cannot write {SUMMARY_TEXT}"))?;
    write_json(&folder.join(SUMMARY_JSON), &summary.to_json(&stats, &detector))?;
    Ok(Decoded { protocol, unreadable_lines })
}

/// An RS232 line as the recorder writes it: `5AA5...(26 hex digits) # (secs.micros) PORT`.
fn serial_line(line: &[u8]) -> Option<(SerialFrame, Timestamp, &str)> {
    let comment = memchr::memmem::find(line, b" # (")?;
    let hex = &line[..comment];
    let mut bytes = [0u8; 13];
    if hex.len() != 26 {
        return None;
    }
    for (index, pair) in hex.chunks(2).enumerate() {
        let text = std::str::from_utf8(pair).ok()?;
        bytes[index] = u8::from_str_radix(text, 16).ok()?;
    }
    let frame = SerialFrame::from_bytes(&bytes).ok()?;
    let us = names::line_time(line)?;
    let close = memchr::memchr(b')', &line[comment..])? + comment;
    let port = std::str::from_utf8(line.get(close + 2..)?).ok()?;
    Some((frame, names::timestamp(us), port))
}

fn incident_json(request: &Request, name: &str, frames: u64, damaged: &[String], decoded: &Decoded) -> Value {
    let window = &request.window;
    let causes: Vec<Value> = window
        .causes
        .iter()
        .map(|(at, cause)| json!({"cause": cause.slug(), "description": cause.describe(), "time": names::rfc3339_millis(*at)}))
        .collect();
    json!({
        "incident": name,
        "trigger_time": names::rfc3339_millis(window.trigger),
        "causes": causes,
        "window": {
            "from": names::rfc3339_millis(window.start),
            "to": names::rfc3339_millis(window.end),
            // Exact bounds (inclusive), microseconds since the epoch as in the frames' stamps.
            "from_us": window.start,
            "to_us": window.end,
            "before_s": request.before_us as f64 / 1e6,
            "after_s": request.after_us as f64 / 1e6,
            "cut_short": request.cut_short,
        },
        "frames": frames,
        "unreadable_lines": decoded.unreadable_lines,
        "damaged_segments": damaged,
        "link": request.link,
        "protocol": decoded.protocol,
        "state_at_trigger": request.state,
        "files": [FRAMES, MCAP, SUMMARY_TEXT, SUMMARY_JSON, INCIDENT],
        "tracerctl": env!("CARGO_PKG_VERSION"),
    })
}

fn write_json(path: &Path, value: &Value) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// Complete incidents in `DIR/incidents/`, oldest first (their names start with their time).
pub fn list(dir: &Path) -> Vec<(String, PathBuf)> {
    let Ok(entries) = fs::read_dir(incidents_dir(dir)) else { return Vec::new() };
    let mut incidents: Vec<(String, PathBuf)> = entries
        .flatten()
        .filter(|entry| entry.path().is_dir())
        .map(|entry| (entry.file_name().to_string_lossy().into_owned(), entry.path()))
        .filter(|(name, _)| names::incident_time(name).is_some())
        .collect();
    incidents.sort();
    incidents
}

/// Removes incidents a crash left half-written.
pub fn remove_partial(dir: &Path) {
    let Ok(entries) = fs::read_dir(incidents_dir(dir)) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') && name.ends_with(".partial") {
            let _ = fs::remove_dir_all(entry.path());
        }
    }
}

/// Removes the oldest incident; its name, or `None` when there is none.
pub fn remove_oldest(dir: &Path) -> Option<String> {
    let (name, path) = list(dir).into_iter().next()?;
    fs::remove_dir_all(&path).ok()?;
    Some(name)
}

/// Removes the oldest incidents beyond `keep`; how many.
pub fn keep_newest(dir: &Path, keep: u32) -> u64 {
    let incidents = list(dir);
    let extra = incidents.len().saturating_sub(keep as usize);
    incidents[..extra].iter().filter(|(_, path)| fs::remove_dir_all(path).is_ok()).count() as u64
}
