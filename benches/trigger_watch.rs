//! The cost of the black box's trigger watcher per frame, over a generated TRACER log held in memory:
//!
//!   cargo run --release --example gen_log -- 1000000 /tmp/tracer.log
//!   cargo run --release --example trigger_watch -- /tmp/tracer.log [ROUNDS]
//!
//! Prints ns per frame (best of ROUNDS, default 5) with the default triggers alone and with four
//! `--trigger` expressions, the triggers fired, and what that is as a share of one core at the robot's
//! ~500 frames/s and a saturated 500 kbit/s bus's ~4,500 frames/s.

// A benchmark prints its figures; the closed-stream rule (clippy.toml) is for the tool itself.
#![allow(clippy::disallowed_macros)]
use std::time::Instant;

use tracerctl::blackbox::triggers::{TriggerSettings, Watcher};
use tracerctl::candump::{Line, LineParser, Timestamp};
use tracerctl::protocol::LinkFrame;

fn main() {
    let mut args = std::env::args().skip(1);
    let path = args.next().expect("usage: trigger_watch LOG [ROUNDS]");
    let rounds: usize = args.next().and_then(|n| n.parse().ok()).unwrap_or(5);
    let text = std::fs::read(&path).expect("read the log");
    let mut parser = LineParser::new();
    let frames: Vec<(Timestamp, LinkFrame)> = text
        .split(|byte| *byte == b'\n')
        .filter_map(|line| match parser.parse(line) {
            Ok(Line::Frame(record)) => Some((record.ts?, LinkFrame::Can(record.frame))),
            _ => None,
        })
        .collect();
    println!("{} frames from {path}", frames.len());
    let expressions = ["current>15", "battery_voltage<23.0", "id=0x441", "control_mode=rc"];
    for (name, expressions) in [("default triggers", &[][..]), ("defaults + 4 expressions", &expressions[..])]
    {
        let mut best = f64::MAX;
        let mut fired = Vec::new();
        for _ in 0..rounds {
            let settings = TriggerSettings {
                expressions: expressions.iter().map(|text| text.parse().unwrap()).collect(),
                ..TriggerSettings::default()
            };
            let mut watcher = Watcher::new(settings);
            let mut out = Vec::new();
            let start = Instant::now();
            for (at, frame) in &frames {
                watcher.frame(*at, frame, &mut out);
            }
            let ns = start.elapsed().as_nanos() as f64 / frames.len() as f64;
            best = best.min(ns);
            std::hint::black_box(&out);
            fired = out;
        }
        let share = |rate: f64| best * rate / 1e9 * 100.0;
        println!(
            "{name}: {best:.1} ns/frame; {:.4} % of a core at 500 frames/s, {:.4} % at 4,500",
            share(500.0),
            share(4_500.0)
        );
        let mut slugs: Vec<&str> = fired.iter().map(|trigger| trigger.cause.slug()).collect();
        slugs.sort_unstable();
        slugs.dedup();
        let counts: Vec<String> = slugs
            .iter()
            .map(|slug| format!("{slug} x{}", fired.iter().filter(|t| t.cause.slug() == *slug).count()))
            .collect();
        println!("  {} triggers: {}", fired.len(), counts.join(", "));
    }
}
