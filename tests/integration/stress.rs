//! Stress (issue 28, run by .ci/run with `--ignored`, not by the default `cargo test`): the chunk-boundary
//! runs of `decode -j` many times at once under CPU load, each compared with `-j1`. Once, under heavy load,
//! `-j3 --plot --summary` with 197-byte chunks reported 22 frames from 42 lines where `-j1` reports 24 from
//! 47 (the tail from the two over-long lines on); a race that loses a chunk would show here as a difference
//! (and, since, as "internal error: chunk N ... was lost"). `STRESS_SECONDS` bounds it (default 120).

use std::path::Path;
use std::process::Output;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use crate::parallel_logs::awkward_log;
use crate::util::tracerctl;

/// The modes the loss was seen in and those around it: (arguments, whether a plot is written).
const MODES: [(&[&str], bool); 4] = [
    (&["--plot", "--summary"], true),
    (&["--summary"], false),
    (&["-f", "json"], false),
    (&["-t", "d"], false),
];

/// `decode -jTHREADS ARGS PATH` with `chunk_bytes` chunks (the plot to `plot`, given its place after
/// `--plot`); its output and the SVG.
fn run(
    path: &Path,
    threads: u16,
    chunk_bytes: Option<u64>,
    args: &[&str],
    plot: Option<&Path>,
) -> (Output, String) {
    let mut command = tracerctl();
    command.arg("decode").arg(format!("-j{threads}"));
    for &arg in args {
        command.arg(arg);
        if arg == "--plot" {
            command.arg(plot.unwrap());
        }
    }
    command.arg(path);
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    let output = command.output().unwrap();
    let svg = plot.map(|plot| std::fs::read_to_string(plot).unwrap_or_default()).unwrap_or_default();
    (output, svg)
}

/// The machine's cores.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get())
}

/// `body` while two busy threads per core spin.
pub fn under_cpu_hogs<T>(body: impl FnOnce() -> T) -> T {
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        for _ in 0..cores() * 2 {
            scope.spawn(|| {
                let mut spin = 0u64;
                while !done.load(Ordering::Relaxed) {
                    spin = std::hint::black_box(spin.wrapping_add(1));
                }
            });
        }
        let result = body();
        done.store(true, Ordering::Relaxed);
        result
    })
}

/// A small pseudo-random sequence (xorshift), so each runner tries other chunk sizes and thread counts.
fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

#[test]
#[ignore = "stress: minutes of CPU; run by .ci/run with --ignored"]
fn stress_chunk_boundaries_under_load_change_nothing() {
    let seconds = std::env::var("STRESS_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(120);
    let deadline = Instant::now() + Duration::from_secs(seconds);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("awkward.log");
    std::fs::write(&path, awkward_log()).unwrap();
    let references: Vec<(Output, String)> = MODES
        .iter()
        .map(|&(args, plotted)| {
            run(&path, 1, None, args, plotted.then(|| dir.path().join("one.svg")).as_deref())
        })
        .collect();
    let cores = cores();
    let (runs, failures) = (AtomicU64::new(0), parking_lot::Mutex::new(Vec::new()));
    // Under CPU hogs: the load the loss was seen under.
    under_cpu_hogs(|| {
        std::thread::scope(|scope| {
            let runners: Vec<_> = (0..cores * 2)
                .map(|runner| {
                    let (path, dir, references, runs, failures) =
                        (&path, dir.path(), &references, &runs, &failures);
                    scope.spawn(move || {
                        let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ (runner as u64 + 1);
                        let plot = dir.join(format!("runner{runner}.svg"));
                        while Instant::now() < deadline {
                            let mode = next(&mut state) as usize % MODES.len();
                            let (args, plotted) = MODES[mode];
                            let threads = 2 + (next(&mut state) % 3) as u16;
                            // The seen failure's 197 among sizes 1 to 256.
                            let bytes = [197, 1 + next(&mut state) % 256][(next(&mut state) % 2) as usize];
                            let (output, svg) =
                                run(path, threads, Some(bytes), args, plotted.then_some(plot.as_path()));
                            let (reference, reference_svg) = &references[mode];
                            let same = output.stdout == reference.stdout
                                && output.stderr == reference.stderr
                                && output.status.code() == reference.status.code()
                                && svg == *reference_svg;
                            runs.fetch_add(1, Ordering::Relaxed);
                            if !same {
                                let stdout = String::from_utf8_lossy(&output.stdout);
                                let stderr = String::from_utf8_lossy(&output.stderr);
                                let head: String = stdout.lines().take(3).collect::<Vec<_>>().join(" | ");
                                failures
                                    .lock()
                                    .push(format!("{args:?} -j{threads} chunks {bytes}: {head} / {stderr}"));
                            }
                        }
                    })
                })
                .collect();
            for runner in runners {
                runner.join().unwrap();
            }
        })
    });
    let failures = failures.into_inner();
    let runs = runs.into_inner();
    eprintln!(
        "stress: {runs} runs of decode -j2..4 in {seconds} s under {cores}x2 CPU hogs, {} differed",
        failures.len()
    );
    assert!(runs > 0);
    assert!(
        failures.is_empty(),
        "{} of {runs} runs differ from -j1:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
