//! The black box killed outright: `kill -9` at 20 moments while recording the simulator, four recordings at
//! a time. Every closed segment decodes with 0 rejected lines, and the open one holds the frames up to at
//! most one second before the kill (a wall-clock window: hence this group).

use std::path::{Path, PathBuf};
use std::process::Stdio;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use serde_json::Value;

use crate::util::{stderr, stdout, tracerctl};

fn now_us() -> u64 {
    SystemTime::now().duration_since(UNIX_EPOCH).unwrap().as_micros() as u64
}

fn segments(dir: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir.join("ring"))
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    found.sort();
    found
}

/// The summary of one segment: (frames, rejected lines, last frame's time in us), and decode's exit status.
fn decode_segment(segment: &Path) -> (u64, u64, u64, Option<i32>) {
    let output = tracerctl().args(["decode", "--summary", "-f", "json"]).arg(segment).output().unwrap();
    let report: Value = serde_json::from_str(&stdout(&output))
        .unwrap_or_else(|error| panic!("{segment:?}: {error}: {}", stderr(&output)));
    // Seconds since the epoch, microseconds in the fraction.
    let last = report["last"].as_f64().map_or(0, |seconds| (seconds * 1e6).round() as u64);
    (
        report["frames"].as_u64().unwrap(),
        report["rejected_lines"].as_u64().unwrap(),
        last,
        output.status.code(),
    )
}

/// A recorder, killed when dropped: a round that fails leaves none running.
struct Recorder(std::process::Child);

impl Drop for Recorder {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// One round: record the simulator, `kill -9` the recorder `after` the first frame is on disk; the loss, µs.
fn kill_round(round: u64, after: Duration) -> u64 {
    let dir = tempfile::tempdir().unwrap();
    let mut recorder = Recorder(
        std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .args(["--sim", "record", "--segment", "1s", "--dir"])
            .arg(dir.path())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap(),
    );
    let deadline = Instant::now() + Duration::from_secs(30);
    // Recording has written something: the loss is measured from a recorded frame.
    while !segments(dir.path()).iter().any(|segment| segment.metadata().is_ok_and(|m| m.len() > 0)) {
        assert!(Instant::now() < deadline, "round {round}: no segment");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(after);
    let killed_at = now_us();
    recorder.0.kill().unwrap();
    recorder.0.wait().unwrap();
    let all = segments(dir.path());
    let (last, closed) = all.split_last().unwrap();
    for segment in closed {
        let (frames, rejected, _, status) = decode_segment(segment);
        assert_eq!((rejected, status), (0, Some(0)), "round {round}: {segment:?}");
        assert!(frames > 0, "round {round}: {segment:?}");
    }
    let (_, rejected, newest_frame, _) = decode_segment(last);
    assert_eq!(rejected, 0, "round {round}: {last:?}");
    // The open segment may have been created an instant before the kill, with nothing in it yet.
    let last_frame = closed.iter().map(|segment| decode_segment(segment).2).fold(newest_frame, u64::max);
    let lost = killed_at.saturating_sub(last_frame);
    assert!(lost <= 1_000_000, "round {round}: the last recorded frame is {lost} us before the kill");
    lost
}

/// Rounds run this many at a time (each recorder and its simulator idle between 50 Hz frames: 47 s one at
/// a time).
const AT_ONCE: u64 = 4;

#[test]
fn kill_9_loses_at_most_the_last_second() {
    // 0.3 to 3.2 s into the recording, a different moment each round.
    let worst = std::thread::scope(|scope| {
        let lanes: Vec<_> = (0..AT_ONCE)
            .map(|lane| {
                scope.spawn(move || {
                    (lane..20)
                        .step_by(AT_ONCE as usize)
                        .map(|round| kill_round(round, Duration::from_millis(300 + (round * 7919) % 2900)))
                        .max()
                        .unwrap_or(0)
                })
            })
            .collect();
        lanes.into_iter().map(|lane| lane.join().unwrap()).max().unwrap_or(0)
    });
    println!("kill -9 x 20: at most {worst} us of frames lost");
}
