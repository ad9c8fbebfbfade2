//! The report as text for a technician: one function per section.

use std::fmt::Write as _;
use std::time::{Duration, UNIX_EPOCH};

use super::report::{FaultRow, FaultSource, IdRow, Reading, Report, Unit};
use super::{nanos, At};
use crate::candump::{Timestamp, TimestampKind};
use crate::commands::decode::totals_line;

pub(super) fn render(report: &Report) -> String {
    let mut out = String::new();
    input_section(&mut out, report);
    ids_section(&mut out, report);
    events_section(&mut out, report);
    faults_section(&mut out, report);
    battery_section(&mut out, report);
    odometry_section(&mut out, report);
    speeds_section(&mut out, report);
    bus_errors_section(&mut out, report);
    rejected_section(&mut out, report);
    super::health::text(&mut out, &report.health);
    out
}

fn input_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "Input");
    let _ = writeln!(w, "  {}", totals_line(report.input));
    for (name, serial) in &report.input.serial {
        let _ = writeln!(
            w,
            "  serial {name}: {} bytes, {} frames, {} bad checksums, {} bad length bytes, {} bad frame types, \
             {} bytes skipped, {} sync losses",
            serial.bytes,
            serial.frames,
            serial.bad_checksum,
            serial.bad_length,
            serial.bad_type,
            serial.skipped_bytes,
            serial.sync_losses
        );
    }
    let interfaces = &report.interfaces;
    if !interfaces.listed.is_empty() {
        let _ = write!(w, "  interfaces: {}", interfaces.listed.join(", "));
        match interfaces.not_listed {
            0 => {}
            n if interfaces.more_than => {
                let _ = write!(w, " and more than {n} more");
            }
            n => {
                let _ = write!(w, " and {n} more");
            }
        }
        let _ = writeln!(w);
    }
    let _ = writeln!(w, "  protocol: {}", report.protocol);
    let _ = writeln!(w, "  time span: {}", span_text(report.first, report.last));
}

fn ids_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nFrames per ID");
    let _ = writeln!(
        w,
        "  {:<10} {:<22} {:>10} {:>9} {:>10}  lost (count-byte skips)",
        "id", "message", "frames", "rate/s", "worst gap"
    );
    for row in &report.ids {
        let rate = row.rate.map_or_else(|| "-".to_string(), |rate| format!("{rate:.1}"));
        let gap =
            row.worst_gap.as_ref().map_or_else(|| "-".to_string(), |gap| format!("{:.3} s", gap.seconds));
        let _ = writeln!(
            w,
            "  {:<10} {:<22} {:>10} {:>9} {:>10}  {}",
            row.key.to_string(),
            row.msg,
            row.frames,
            rate,
            gap,
            lost_text(row)
        );
    }
}

/// Frames lost according to the count byte, and invalid frames.
fn lost_text(row: &IdRow) -> String {
    let mut text = match &row.counter {
        Some(counter) => {
            let mut text = format!("{} in {} skips", counter.frames_lost, counter.skips);
            if counter.repeats > 0 {
                let _ = write!(text, ", {} repeated", counter.repeats);
            }
            text
        }
        None => "-".to_string(),
    };
    if row.invalid > 0 {
        let _ = write!(text, " ({} invalid)", row.invalid);
    }
    text
}

fn events_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nControl mode and vehicle state");
    if report.events.is_empty() {
        let _ = writeln!(w, "  no system-state frames");
    }
    for (at, text) in report.events {
        let _ = writeln!(w, "  {}  {text}", at_text(at));
    }
    if report.events_not_listed > 0 {
        let _ = writeln!(w, "  ... and {} more changes not listed", report.events_not_listed);
    }
}

fn faults_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nFaults (first and last seen)");
    if report.faults.is_empty() {
        let _ = writeln!(w, "  none");
    }
    for fault in &report.faults {
        fault_line(w, fault);
    }
}

fn fault_line(w: &mut String, fault: &FaultRow) {
    let source = match fault.source {
        FaultSource::System => "system",
        FaultSource::Motor(0) => "motor 1",
        FaultSource::Motor(1) => "motor 2",
        FaultSource::Motor(_) => "motor ?",
    };
    let info = &fault.info;
    let _ = writeln!(
        w,
        "  {source:<8} {} [{}] in {} frames, first {}, last {}\n           {}: {}",
        info.name,
        info.severity,
        fault.frames,
        at_text(&fault.first),
        at_text(&fault.last),
        info.meaning,
        info.action
    );
}

fn battery_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nBattery");
    match &report.battery {
        Some(battery) => {
            for (name, reading) in [("min", &battery.min), ("max", &battery.max), ("last", &battery.last)] {
                let _ = writeln!(w, "  {name} {} at {}", value_text(reading), at_text(&reading.at));
            }
        }
        None => {
            let _ = writeln!(w, "  no system-state frames");
        }
    }
}

fn odometry_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nOdometry");
    for wheel in &report.wheels {
        let name = wheel.name;
        let Some((first, last)) = wheel.odometer_mm else {
            let _ = writeln!(w, "  {name:<5} no odometry frames");
            continue;
        };
        let _ = write!(
            w,
            "  {name:<5} travelled {:.3} m, net {:+.3} m (odometer {:.3} -> {:.3} m)",
            wheel.travelled_mm as f64 / 1000.0,
            (last - first) as f64 / 1000.0,
            first as f64 / 1000.0,
            last as f64 / 1000.0
        );
        if wheel.resets > 0 {
            let _ = write!(w, ", {} odometer jumps ignored", wheel.resets);
        }
        let _ = writeln!(w);
    }
}

fn speeds_section(w: &mut String, report: &Report) {
    let _ = writeln!(w, "\nTop speeds");
    for speed in &report.speeds {
        let text = speed
            .reading
            .map_or_else(|| "-".to_string(), |r| format!("{} at {}", value_text(&r), at_text(&r.at)));
        let _ = writeln!(w, "  {:<17} {text}", speed.name.replace('_', " "));
    }
    for motor in &report.motors {
        if let (Some(rpm), Some(current)) = (motor.rpm, motor.current) {
            let _ = writeln!(
                w,
                "  {:<17} {} at {}; current {} at {}",
                format!("motor {}", motor.number),
                value_text(&rpm),
                at_text(&rpm.at),
                value_text(&current),
                at_text(&current.at)
            );
        }
    }
}

fn bus_errors_section(w: &mut String, report: &Report) {
    let dropped = report.input.candump_dropped;
    if report.error_frames.is_empty() && dropped == 0 {
        return;
    }
    let _ = writeln!(w, "\nBus errors");
    if !report.error_frames.is_empty() {
        let classes: Vec<String> =
            report.error_frames.iter().map(|count| format!("{} x{}", count.class, count.frames)).collect();
        let _ = writeln!(w, "  error frames: {}", classes.join(", "));
    }
    if dropped > 0 {
        let _ = writeln!(w, "  candump reported {dropped} frames dropped by the socket");
    }
}

fn rejected_section(w: &mut String, report: &Report) {
    let input = report.input;
    let _ = writeln!(w, "\nRejected input");
    if input.rejected.rejected.is_empty() {
        let _ = writeln!(w, "  none");
    }
    for rejection in &input.rejected.rejected {
        let _ = writeln!(w, "  {:>8}  {}", rejection.count, rejection.describe_after_count());
    }
    if input.skipped.total() > 0 {
        let _ = writeln!(w, "  skipped lines: {}", input.skipped.describe());
    }
}

/// The value with its unit: volts and amps to 0.1, speeds signed to 0.001, rpm signed and whole.
fn value_text(reading: &Reading) -> String {
    match reading.unit {
        Unit::Volts => format!("{:.1} V", reading.value()),
        Unit::Amps => format!("{:.1} A", reading.value()),
        Unit::MetresPerSecond => format!("{:+.3} m/s", reading.value()),
        Unit::RadiansPerSecond => format!("{:+.3} rad/s", reading.value()),
        Unit::Rpm => format!("{:+} rpm", reading.raw),
    }
}

fn span_text(first: Option<Timestamp>, last: Option<Timestamp>) -> String {
    match (first, last) {
        (Some(first), Some(last)) => {
            let length = nanos(&last).saturating_sub(nanos(&first)) as f64 / 1e9;
            format!("{} .. {} ({length:.3} s)", ts_text(&first), ts_text(&last))
        }
        _ => "no timestamps".to_string(),
    }
}

/// The first second of the year 10000, which RFC 3339 (four-digit years) cannot show.
const YEAR_10000_SECS: u64 = 253_402_300_800;

/// Absolute stamps as UTC date-time, relative ones as seconds since the start of the capture. A stamp
/// beyond the year 9999 (a corrupted line) is shown as the number of seconds it holds.
fn ts_text(ts: &Timestamp) -> String {
    match ts.kind {
        TimestampKind::Absolute if ts.secs < YEAR_10000_SECS => {
            let time = UNIX_EPOCH + Duration::new(ts.secs, ts.nanos);
            let mut text = String::new();
            match write!(text, "{}", humantime::format_rfc3339_micros(time)) {
                Ok(()) => text,
                Err(_) => seconds_text(ts),
            }
        }
        TimestampKind::Absolute => seconds_text(ts),
        TimestampKind::Relative => format!("+{}.{:06} s", ts.secs, ts.nanos / 1000),
    }
}

fn seconds_text(ts: &Timestamp) -> String {
    format!("{}.{:06} s", ts.secs, ts.nanos / 1000)
}

fn at_text(at: &At) -> String {
    match &at.ts {
        Some(ts) => ts_text(ts),
        None => format!("frame #{}", at.frame),
    }
}
