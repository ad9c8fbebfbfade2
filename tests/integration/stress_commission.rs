//! Stress (run by .ci/run with `--ignored`): `commission` on the simulator, several at once under CPU hogs.
//! A CI run once saw a commission on a busy machine measure nothing and say PASS: the starved reader's
//! frames were recorded and analysed behind sent frames stamped up to 405 ms later, and every stamp going
//! back restarted the analysis. Each run must measure every step and stop, from a recording in stamp order.

use std::process::Output;

use crate::stress::{cores, under_cpu_hogs};
use crate::util::{stderr, stdout};

/// The stamps of a candump -L recording, s.
fn stamps(recording: &str) -> Vec<f64> {
    recording.lines().filter_map(|line| line.strip_prefix('(')?.split(')').next()?.parse().ok()).collect()
}

#[test]
#[ignore = "stress: a minute of CPU; run by .ci/run with --ignored"]
fn stress_commission_under_load_measures_every_step() {
    let dir = tempfile::tempdir().unwrap();
    let runs = cores() * 2;
    let outputs: Vec<Output> = under_cpu_hogs(|| {
        let children: Vec<_> = (0..runs)
            .map(|run| {
                std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
                    .env("TRACERCTL_CONFIG", "")
                    .env("TRACERCTL_PROFILE", "")
                    .args(["--sim", "commission", "--yes", "--record"])
                    .arg(dir.path().join(format!("run{run}.log")))
                    .stdin(std::process::Stdio::null())
                    .stdout(std::process::Stdio::piped())
                    .stderr(std::process::Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        children.into_iter().map(|child| child.wait_with_output().unwrap()).collect()
    });
    for (run, output) in outputs.iter().enumerate() {
        let text = stdout(output);
        assert_eq!(output.status.code(), Some(0), "run {run}: {text}\n{}", stderr(output));
        for step in ["forward", "back", "spin left", "spin right"] {
            let rise = text.lines().find(|line| line.starts_with(step) && line.contains("rise time"));
            assert!(rise.is_some_and(|line| line.contains(" ms ")), "run {run}: {step} rise in\n{text}");
            let brake = format!("brake after {step}");
            let deceleration =
                text.lines().find(|line| line.starts_with(&brake) && line.contains("deceleration"));
            assert!(deceleration.is_some(), "run {run}: {brake} in\n{text}");
        }
        assert!(text.contains("result: PASS"), "run {run}: {text}");
        let recording = std::fs::read_to_string(dir.path().join(format!("run{run}.log"))).unwrap();
        let stamps = stamps(&recording);
        assert!(stamps.len() > 2000, "run {run}: {} frames recorded", stamps.len());
        let back = stamps.windows(2).map(|pair| pair[0] - pair[1]).fold(0.0, f64::max);
        // A received frame may come in a hair behind a sent one stamped as it arrived.
        assert!(back <= 0.005, "run {run}: a stamp {:.1} ms back in the recording", back * 1000.0);
    }
    eprintln!("stress: {runs} commissions at once under {}x2 CPU hogs, every step measured", cores());
}
