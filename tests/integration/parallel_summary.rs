//! `decode -j N --summary` merges per-chunk partial summaries (issue 14); a chunk whose partial cannot be
//! merged exactly (more interface names or identifiers than the report lists) is replayed instead. Either
//! way the report is `-j1`'s, byte for byte.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Output;

use crate::util::{stderr, stdout, tracerctl};

fn decode(path: &Path, threads: u16, chunk_bytes: Option<usize>, extra: &[&str]) -> Output {
    let mut command = tracerctl();
    command.arg("decode").arg(format!("-j{threads}")).arg("--summary").args(extra).arg(path);
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    command.output().unwrap()
}

/// 15,000 lines: system states changing mode and E-stop, and from line 3000 on 400 names used once, then
/// names from 100 interfaces; 4500 distinct extended identifiers, then seven more taking turns (past the 64
/// names and 4096 rows the report lists one by one).
fn crowded_log() -> String {
    let mut log = String::new();
    for n in 0..15_000u32 {
        let stamp = format!("({}.{:06})", 1_700_000_000 + n / 100, (n % 100) * 10_000);
        let iface = match n {
            ..3000 => format!("can{}", n % 3),
            // Each its own name: a chunk of these lists more names than fit.
            3000..3400 => format!("v{n}"),
            _ => format!("can{}", (n * 37) % 100),
        };
        if n % 2 == 0 {
            let (mode, state) = ((n / 500) % 3, u32::from(n % 1700 < 20));
            // The count byte steps by one, skipping one value every 700 frames.
            let count = (n / 2 + n / 1400) % 256;
            writeln!(log, "{stamp} {iface} 211#{state:02X}{mode:02X}0103000000{count:02X}").unwrap();
        } else {
            let id = match n {
                ..3000 => 0x1000 + n % 40,
                3000..12_000 => 0x10_0000 + (n / 2 * 7919) % 9000,
                // Past the rows: seven identifiers taking turns, all counted in the overflow row.
                _ => 0x20_0000 + n % 7,
            };
            writeln!(log, "{stamp} {iface} {id:08X}#{:02X}", n % 256).unwrap();
        }
    }
    log
}

#[test]
fn partial_summaries_and_replayed_chunks_give_the_single_pass_report() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("crowded.log");
    std::fs::write(&path, crowded_log()).unwrap();
    for extra in [&[][..], &["-f", "json"]] {
        let single = decode(&path, 1, None, extra);
        let report = stdout(&single);
        assert!(single.status.success(), "{}", stderr(&single));
        if extra.is_empty() {
            assert!(report.contains("decoded 15000 frames from 15000 lines"), "{report}");
            assert!(report.contains("other ids (beyond 4096)"), "{report}");
        }
        for bytes in [97, 4000, 65_536, 1 << 20] {
            let parallel = decode(&path, 2, Some(bytes), extra);
            let what = format!("{extra:?} TRACERCTL_CHUNK_BYTES={bytes}");
            assert_eq!(stdout(&parallel), report, "stdout of {what}");
            assert_eq!(stderr(&parallel), stderr(&single), "stderr of {what}");
            assert_eq!(parallel.status.code(), single.status.code(), "exit status of {what}");
        }
    }
}

/// A candump log of the simulator driven through the commissioning plan `runs` times (timeout probe
/// included, a different battery each run), then a minute of driving that never rests: the analysis of
/// issue 32 finds steps, stops, holds, a timeout and load steps in it.
fn commissioning_log(runs: u32) -> String {
    commissioning_log_with(runs, true, |run| tracerctl::sim::SimConfig {
        battery_resistance_ohm: 0.3 + 0.1 * f64::from(run),
        ..tracerctl::sim::SimConfig::default()
    })
}

/// [`commissioning_log`] with each run's simulator from `config`, and the restless minute or not.
pub(crate) fn commissioning_log_with(
    runs: u32,
    restless_minute: bool,
    config: impl Fn(u32) -> tracerctl::sim::SimConfig,
) -> String {
    use std::time::Duration;
    use tracerctl::candump::{write_log_line, Timestamp, TimestampKind};
    use tracerctl::health::plan::{self, Action, PlanOptions};
    use tracerctl::protocol::can::encode_v2;
    use tracerctl::protocol::message::{Message, MotionCommand, MODE_CAN};
    use tracerctl::sim::Chassis;

    let mut log = Vec::new();
    let mut line = |now: Duration, message: &Message| {
        let micros = 1_700_000_000_000_000 + now.as_micros() as u64;
        let ts = Timestamp {
            secs: micros / 1_000_000,
            nanos: (micros % 1_000_000) as u32 * 1000,
            kind: TimestampKind::Absolute,
        };
        write_log_line(&mut log, Some(ts), "can0", &encode_v2(message).unwrap());
    };
    let options = PlanOptions { include_timeout: true, ..PlanOptions::default() };
    let mut now = Duration::ZERO;
    let mut feedback = Vec::new();
    for run in 0..runs {
        let mut chassis = Chassis::new(config(run));
        let start = now;
        chassis.receive(Duration::ZERO, &Message::ControlModeCommand(MODE_CAN));
        line(now, &Message::ControlModeCommand(MODE_CAN));
        let mut actions: Vec<(Action, Duration)> =
            plan::steps(&options).iter().map(|step| (step.action, step.duration)).collect();
        if restless_minute && run + 1 == runs {
            // A minute of a command that changes every period: no rest.
            for n in 0..3000 {
                let linear = 0.3 * (f64::from(n) / 50.0).sin();
                actions.push((Action::Command { linear, angular: 0.0 }, Duration::from_millis(20)));
            }
        }
        for (action, duration) in actions {
            let until = now + duration;
            while now < until {
                if let Action::Command { linear, angular } = action {
                    let command = Message::MotionCommand(MotionCommand::from_si(linear, angular).unwrap());
                    chassis.receive(now - start, &command);
                    line(now, &command);
                }
                feedback.clear();
                chassis.due_feedback(now - start, &mut feedback);
                for message in &feedback {
                    line(now, message);
                }
                now += Duration::from_millis(20);
            }
        }
        now += Duration::from_secs(2);
    }
    String::from_utf8(log).unwrap()
}

/// The health section of `decode -j N --summary` is the single pass's, byte for byte, whatever the chunks:
/// chunks that rest merge from their replayed start, chunks that do not are replayed whole.
#[test]
fn the_health_section_is_the_same_with_any_chunking() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("commissioning.log");
    std::fs::write(&path, commissioning_log(3)).unwrap();
    for extra in [&[][..], &["-f", "json"]] {
        let single = decode(&path, 1, None, extra);
        let report = stdout(&single);
        assert!(single.status.success(), "{}", stderr(&single));
        if extra.is_empty() {
            let health = &report[report.find("Response and health").expect("the section")..];
            assert!(health.contains("steps: 15"), "{health}");
            assert!(health.contains("command timeout: 500 ms"), "{health}");
            // Three batteries of 0.3, 0.4 and 0.5 Ω: one estimate over their load steps.
            assert!(
                health.contains("battery: internal resistance 0.399 Ω (spread 0.083 Ω, 27 load steps)"),
                "{health}"
            );
        }
        for (threads, bytes) in [(2, 97), (3, 4000), (2, 65_536), (2, 1 << 20)] {
            let parallel = decode(&path, threads, Some(bytes), extra);
            let what = format!("{extra:?} -j{threads} TRACERCTL_CHUNK_BYTES={bytes}");
            assert_eq!(stdout(&parallel), report, "stdout of {what}");
            assert_eq!(stderr(&parallel), stderr(&single), "stderr of {what}");
        }
    }
}
