//! What `record` says of a recorder directory: the start line, `--dry-run`, `--status`, `--list`, and
//! `--mark`, which leaves a note for the running recorder.

use std::io::Write;
use std::path::Path;
use std::time::Duration;

use anyhow::Result;
use serde_json::{json, Value};

use super::incident;
use super::Settings;
use crate::blackbox::lock::DirLock;
use crate::blackbox::ring::Ring;
use crate::blackbox::{marks, names, ring_dir, status};
use crate::commands::decode::ReportFormat;
use crate::commands::Global;
use crate::exit::{Failure, FAILURE, SUCCESS};

/// `recording can0 into DIR, watch-only (nothing is ever sent); ...`
pub fn describe_start(link: &str, dir: &Path, settings: &Settings) -> String {
    let instance = settings.instance.as_ref().map(|name| format!(" (instance {name})")).unwrap_or_default();
    format!(
        "recording {link}{instance} into {}, watch-only: nothing is ever sent. Ring: {} segments, at most {} and {}; \
         incidents: {} before and {} after a trigger, at most {} kept; triggers: {}",
        dir.display(),
        duration_text(settings.segment),
        size_text(settings.max_total),
        duration_text(settings.max_age),
        duration_text(settings.before),
        duration_text(settings.after),
        settings.max_incidents,
        triggers_text(settings)
    )
}

fn triggers_text(settings: &Settings) -> String {
    let mut parts = Vec::new();
    if settings.triggers.defaults {
        parts.push(
            "the defaults (E-stop, faults, vehicle state exception, control-mode change, RC override, link \
             silence, low battery, CAN error frames and bus state)"
                .to_string(),
        );
    }
    parts.extend(settings.triggers.expressions.iter().map(|expression| expression.text().to_string()));
    parts.push("marks (record --mark, SIGUSR1)".to_string());
    parts.join(", ")
}

/// `1 GiB`, `500 MiB`, `12.3 MiB`, `512 B`.
pub fn size_text(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 || value.fract() == 0.0 {
        format!("{value:.0} {}", UNITS[unit])
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

fn duration_text(duration: Duration) -> String {
    humantime::format_duration(duration).to_string()
}

pub fn dry_run(global: &Global, dir: &Path, settings: &Settings) -> Result<u8> {
    let link = match &global.link {
        crate::link::LinkChoice::SocketCan { iface } => format!("SocketCAN {iface}"),
        crate::link::LinkChoice::Serial { path, baud } => format!("serial {} at {baud} baud", path.display()),
        crate::link::LinkChoice::Sim => "the simulator".to_string(),
        crate::link::LinkChoice::Replay { path, .. } => format!("replay of {}", path.display()),
    };
    let text = format!(
        "link: {link}\ninstance: {}\ndirectory: {}\nsegment: {}\nmax-total: {}\nmax-age: {}\nbefore: {}\nafter: {}\n\
         max-incidents: {}\ntriggers: {}\n",
        settings.instance.as_deref().unwrap_or("-"),
        dir.display(),
        duration_text(settings.segment),
        size_text(settings.max_total),
        duration_text(settings.max_age),
        duration_text(settings.before),
        duration_text(settings.after),
        settings.max_incidents,
        triggers_text(settings)
    );
    print_out(&text);
    Ok(SUCCESS)
}

/// Standard output that cannot panic (a closed pipe loses the text, not the run).
fn print_out(text: &str) {
    let mut stdout = std::io::stdout().lock();
    let _ = stdout.write_all(text.as_bytes());
    let _ = stdout.flush();
}

fn missing(dir: &Path) -> anyhow::Error {
    Failure {
        code: FAILURE,
        message: format!(
            "{} is not a recorder directory (no such directory): see tracerctl record --help",
            dir.display()
        ),
    }
    .into()
}

/// One incident for `--status` and `--list`.
fn incident_facts(name: &str, path: &Path) -> Value {
    let facts: Value = std::fs::read_to_string(path.join(incident::INCIDENT))
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or(Value::Null);
    let causes: Vec<Value> = facts["causes"]
        .as_array()
        .map(|causes| causes.iter().map(|cause| cause["description"].clone()).collect())
        .unwrap_or_default();
    let bytes: u64 = std::fs::read_dir(path)
        .map(|entries| entries.flatten().filter_map(|e| e.metadata().ok()).map(|m| m.len()).sum())
        .unwrap_or(0);
    json!({
        "incident": name,
        "path": path.display().to_string(),
        "trigger_time": facts["trigger_time"],
        "causes": causes,
        "frames": facts["frames"],
        "bytes": bytes,
    })
}

fn incident_line(facts: &Value) -> String {
    let causes: Vec<&str> =
        facts["causes"].as_array().map(|c| c.iter().filter_map(Value::as_str).collect()).unwrap_or_default();
    format!(
        "{}  {}  ({} frames, {})",
        facts["incident"].as_str().unwrap_or("?"),
        if causes.is_empty() { "(no incident.json)".to_string() } else { causes.join("; ") },
        facts["frames"].as_u64().map_or_else(|| "?".to_string(), |n| n.to_string()),
        size_text(facts["bytes"].as_u64().unwrap_or(0))
    )
}

pub fn list(dir: &Path, format: ReportFormat) -> Result<u8> {
    if !dir.is_dir() {
        return Err(missing(dir));
    }
    let incidents: Vec<Value> =
        incident::list(dir).iter().map(|(name, path)| incident_facts(name, path)).collect();
    let text = match format {
        ReportFormat::Json => format!("{}\n", serde_json::to_string_pretty(&Value::Array(incidents))?),
        ReportFormat::Text if incidents.is_empty() => format!("no incidents in {}\n", dir.display()),
        ReportFormat::Text => incidents.iter().map(|facts| incident_line(facts) + "\n").collect(),
    };
    print_out(&text);
    Ok(SUCCESS)
}

/// `--status`: exit 0 when a recorder runs in `dir`, 1 when none does (the report is printed either way).
pub fn status(dir: &Path, format: ReportFormat) -> Result<u8> {
    if !dir.is_dir() {
        return Err(missing(dir));
    }
    let holder = DirLock::holder(dir);
    let written = status::read(dir)?;
    let segments = Ring::at(&ring_dir(dir)).segments()?;
    let ring = json!({
        "segments": segments.len(),
        "bytes": segments.iter().map(|s| s.bytes).sum::<u64>(),
        "from": segments.first().map(|s| names::rfc3339_millis(s.start)),
        "last_segment_from": segments.last().map(|s| names::rfc3339_millis(s.start)),
    });
    let incidents = incident::list(dir);
    let last: Vec<Value> =
        incidents.iter().rev().take(5).map(|(name, path)| incident_facts(name, path)).collect();
    let report = json!({
        "dir": dir.display().to_string(),
        "running": holder.is_some(),
        "pid": holder,
        "status": written,
        "ring": ring,
        "incidents": incidents.len(),
        "last_incidents": last,
    });
    let text = match format {
        ReportFormat::Json => format!("{}\n", serde_json::to_string_pretty(&report)?),
        ReportFormat::Text => status_text(&report),
    };
    print_out(&text);
    Ok(if holder.is_some() { SUCCESS } else { FAILURE })
}

fn status_text(report: &Value) -> String {
    let written = &report["status"];
    let mut text = format!("recorder directory {}: ", report["dir"].as_str().unwrap_or("?"));
    match (report["pid"].as_u64(), written.is_null()) {
        (Some(pid), _) => {
            text += &format!(
                "running (process {pid}) since {}, {} {}\n",
                written["started"].as_str().unwrap_or("?"),
                written["state"].as_str().unwrap_or("?"),
                written["link"].as_str().unwrap_or("?")
            )
        }
        (None, true) => text += "not running, and no recorder has written a status here\n",
        (None, false) => {
            text += &format!(
                "not running (the last status was written at {} by process {})\n",
                written["updated"].as_str().unwrap_or("?"),
                written["pid"]
            )
        }
    }
    if !written.is_null() {
        text += &format!(
            "frames: {} recorded, {} lost (status written at {})\n",
            written["frames_recorded"],
            written["frames_lost"],
            written["updated"].as_str().unwrap_or("?")
        );
        for loss in written["losses"].as_array().into_iter().flatten() {
            text +=
                &format!("  lost {} frames: {}\n", loss["frames"], loss["reason"].as_str().unwrap_or("?"));
        }
    }
    let ring = &report["ring"];
    text += &format!(
        "ring: {} segments, {}, from {}\n",
        ring["segments"],
        size_text(ring["bytes"].as_u64().unwrap_or(0)),
        ring["from"].as_str().unwrap_or("-")
    );
    text += &format!("incidents: {}", report["incidents"]);
    let last = report["last_incidents"].as_array().cloned().unwrap_or_default();
    if last.is_empty() {
        text += "\n";
    } else {
        text += "; the last:\n";
        for facts in &last {
            text += &format!("  {}\n", incident_line(facts));
        }
    }
    text
}

pub fn mark(dir: &Path, note: &str) -> Result<u8> {
    let Some(pid) = DirLock::holder(dir) else {
        return Err(Failure {
            code: FAILURE,
            message: format!(
                "no recorder runs in {}: nothing to mark (see tracerctl record --status)",
                dir.display()
            ),
        }
        .into());
    };
    let now = names::micros(&crate::link::now_timestamp());
    let path = marks::write(dir, now, note)
        .map_err(|error| anyhow::anyhow!("cannot leave a mark in {}: {error}", marks::dir(dir).display()))?;
    crate::say!(
        "tracerctl: marked {} for the recorder (process {pid}): it becomes an incident within a second ({})",
        names::rfc3339_millis(now),
        path.display()
    );
    Ok(SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_in_binary_units() {
        assert_eq!(size_text(512), "512 B");
        assert_eq!(size_text(1 << 30), "1 GiB");
        assert_eq!(size_text(1536 * 1024), "1.5 MiB");
        assert_eq!(size_text(u64::MAX), "16777216 TiB");
    }
}
