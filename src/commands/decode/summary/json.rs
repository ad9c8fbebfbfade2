//! The report as one JSON object (docs/json.md, section 6).

use serde_json::{json, Value as Json};

use super::report::{FaultRow, FaultSource, IdRow, Reading, Report};
use super::At;
use crate::candump::Timestamp;
use crate::commands::decode::InputStats;

pub(super) fn render(report: &Report) -> Json {
    let mut object = input_json(report.input);
    let battery = report.battery.as_ref();
    let report_fields = json!({
        "protocol": report.protocol,
        "interfaces": report.interfaces.listed,
        "interfaces_not_listed": report.interfaces.not_listed,
        "first": ts(report.first),
        "last": ts(report.last),
        "ids": report.ids.iter().map(id_json).collect::<Vec<_>>(),
        "events": report.events.iter().map(|(a, text)| json!({"at": at(a), "event": text})).collect::<Vec<_>>(),
        "events_not_listed": report.events_not_listed,
        "faults": report.faults.iter().map(fault_json).collect::<Vec<_>>(),
        "battery": {"min": reading(battery.map(|b| b.min)), "max": reading(battery.map(|b| b.max)),
            "last": reading(battery.map(|b| b.last))},
        "odometry": report.wheels.iter().map(|w| json!({"travelled": w.travelled_mm as f64 / 1000.0,
            "net": w.odometer_mm.map(|(f, l)| (l - f) as f64 / 1000.0), "resets": w.resets})).collect::<Vec<_>>(),
        "top_speeds": report.speeds.iter().map(|s| (s.name.to_string(), reading(s.reading)))
            .collect::<serde_json::Map<_, _>>(),
        "motors": report.motors.iter().map(|m| json!({"motor": m.number, "rpm": reading(m.rpm),
            "current": reading(m.current)})).collect::<Vec<_>>(),
        "error_frames": report.error_frames.iter().map(|e| json!({"class": e.class, "frames": e.frames}))
            .collect::<Vec<_>>(),
        "health": super::health::json(&report.health),
    });
    if let (Some(object), Json::Object(fields)) = (object.as_object_mut(), report_fields) {
        object.extend(fields);
    }
    object
}

/// The totals of the inputs: lines, frames, skipped and rejected input, RS232 streams.
fn input_json(stats: &InputStats) -> Json {
    let skipped = &stats.skipped;
    json!({
        "lines": stats.lines,
        "frames": stats.frames,
        "decoded_lines": stats.decoded_lines,
        "rejected_lines": stats.rejected_lines,
        "skipped": {"blank": skipped.blank, "comment": skipped.comment,
            "error_text": skipped.error_text, "can_xl": skipped.can_xl, "dropcount": skipped.dropcount},
        "rejected": stats.rejected.rejected.iter().map(|r| {
            let mut object = json!({"reason": r.reason, "count": r.count, "first_at": r.first_at});
            if let Some(longest) = r.longest {
                object["longest"] = json!(longest);
            }
            object
        }).collect::<Vec<_>>(),
        "invalid_frames": stats.invalid_frames,
        "candump_dropped": stats.candump_dropped,
        "serial": stats.serial.iter().map(|(name, s)| json!({"input": name, "bytes": s.bytes, "frames": s.frames,
            "bad_checksum": s.bad_checksum, "bad_length": s.bad_length, "bad_type": s.bad_type,
            "skipped_bytes": s.skipped_bytes, "sync_losses": s.sync_losses})).collect::<Vec<_>>(),
    })
}

fn id_json(row: &IdRow) -> Json {
    json!({
        "id": row.key.to_string(), "msg": row.msg, "frames": row.frames,
        "first": ts(row.first), "last": ts(row.last),
        "worst_gap": row.worst_gap.as_ref().map(|gap| gap.seconds),
        "worst_gap_at": ts(row.worst_gap.as_ref().map(|gap| gap.at)),
        "frames_lost": row.counter.as_ref().map(|c| c.frames_lost),
        "count_skips": row.counter.as_ref().map(|c| c.skips),
        "count_repeats": row.counter.as_ref().map(|c| c.repeats),
        "invalid": row.invalid,
    })
}

fn fault_json(fault: &FaultRow) -> Json {
    let source = match fault.source {
        FaultSource::System => "system".to_string(),
        FaultSource::Motor(index) => format!("motor{}", index + 1),
    };
    let info = &fault.info;
    json!({"source": source, "name": info.name, "severity": info.severity.as_str(), "action": info.action,
        "frames": fault.frames, "first": at(&fault.first), "last": at(&fault.last)})
}

fn reading(reading: Option<Reading>) -> Json {
    reading.map_or(Json::Null, |r| json!({"value": r.value(), "at": at(&r.at)}))
}

fn at(at: &At) -> Json {
    json!({ "ts": ts(at.ts), "frame": at.frame })
}

fn ts(ts: Option<Timestamp>) -> Option<f64> {
    ts.map(|t| exact_seconds(&t))
}

/// Seconds as the nearest f64 to the exact decimal, so JSON shows `0.3`, not `0.30000000000000004`.
fn exact_seconds(ts: &Timestamp) -> f64 {
    let text = if ts.nanos % 1000 == 0 {
        format!("{}.{:06}", ts.secs, ts.nanos / 1000)
    } else {
        format!("{}.{:09}", ts.secs, ts.nanos)
    };
    text.parse().unwrap_or_else(|_| ts.as_secs_f64())
}
