//! `doctor --probe` cut short by Ctrl-C (issue 28, 1.6): an interrupted probe found nothing out, so the
//! report says its result is unknown, never "the robot cannot be driven", and exits 130.

use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};

/// Runs `--sim doctor --probe` and sends SIGINT once the mode check is printed (the zero-motion probe, half
/// a second of frames, comes next): (exit status, what was printed after the signal).
#[cfg(unix)]
fn interrupted_probe() -> (Option<i32>, String) {
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .env("NO_COLOR", "1")
        .args(["--sim", "doctor", "--probe", "--listen", "300ms"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut before = String::new();
    while !before.contains("probe: mode") {
        let mut line = String::new();
        assert_ne!(out.read_line(&mut line).unwrap(), 0, "the probe started:\n{before}");
        before.push_str(&line);
    }
    // SAFETY: kill() with a child's pid and SIGINT has no memory effects.
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    let mut after = String::new();
    out.read_to_string(&mut after).unwrap();
    (child.wait().unwrap().code(), after)
}

#[cfg(unix)]
#[test]
fn an_interrupted_probe_is_unknown_not_a_robot_that_cannot_be_driven() {
    // A loaded machine may deliver the signal only after the probe's half second: then try again.
    let (status, after) = (0..5)
        .map(|_| interrupted_probe())
        .find(|(_, after)| !after.contains("PASS  probe: zero motion"))
        .expect("a signal that arrived during the probe in one of five runs");
    assert_eq!(status, Some(130), "{after}");
    let probe = after.lines().find(|line| line.contains("probe: zero motion")).unwrap_or_default();
    assert!(probe.starts_with("SKIP"), "not a FAIL of the robot: {after}");
    assert!(
        probe.contains("interrupted by SIGINT after") && probe.contains("the result is unknown"),
        "{probe}"
    );
    assert!(!after.contains("cannot be driven"), "{after}");
    assert!(after.contains("Result: unknown: the probe was interrupted by SIGINT"), "{after}");
}
