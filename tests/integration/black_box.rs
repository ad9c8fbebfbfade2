//! `tracerctl record`, the black box, run for real on the simulator and on replayed logs: the ring, the
//! incidents and what they hold, --status, --list, --mark, one recorder per directory.

use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::util::{stderr, stdout, tracerctl, wait_with_timeout};

/// Starts `tracerctl LINK... record --dir DIR ARGS...` with stderr captured.
fn start(link: &[&str], dir: &Path, args: &[&str]) -> Child {
    let mut command = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"));
    command.args(link).arg("record").arg("--dir").arg(dir).args(args);
    command.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("tracerctl starts")
}

/// Waits (up to a minute: a loaded machine is slow, this asserts no time) until `ready` holds.
fn wait_until(what: &str, mut ready: impl FnMut() -> bool) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !ready() {
        assert!(Instant::now() < deadline, "waited a minute for {what}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn status_json(dir: &Path) -> Option<Value> {
    serde_json::from_str(&std::fs::read_to_string(dir.join("status.json")).ok()?).ok()
}

fn incidents(dir: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir.join("incidents"))
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.path())
                .filter(|p| !p.file_name().unwrap().to_string_lossy().starts_with('.'))
                .collect()
        })
        .unwrap_or_default();
    found.sort();
    found
}

/// Every line of every ring segment, in order (the segments decompressed with the zstd library).
fn ring_lines(dir: &Path) -> Vec<String> {
    let mut segments: Vec<PathBuf> =
        std::fs::read_dir(dir.join("ring")).unwrap().flatten().map(|e| e.path()).collect();
    segments.sort();
    let mut lines = Vec::new();
    for segment in segments {
        let text = zstd::decode_all(std::fs::File::open(&segment).unwrap()).unwrap();
        lines.extend(String::from_utf8(text).unwrap().lines().map(str::to_string));
    }
    lines
}

fn line_us(line: &str) -> u64 {
    let stamp = &line[1..line.find(')').unwrap()];
    let (secs, micros) = stamp.split_once('.').unwrap();
    secs.parse::<u64>().unwrap() * 1_000_000 + micros.parse::<u64>().unwrap()
}

fn stop(child: Child) -> std::process::Output {
    crate::util::signal(child.id(), libc::SIGTERM);
    wait_with_timeout(child, Duration::from_secs(60))
}

#[test]
fn a_mark_keeps_exactly_the_rings_frames_of_its_window() {
    let dir = tempfile::tempdir().unwrap();
    let child = start(&["--sim"], dir.path(), &["--segment", "1s", "--before", "2s", "--after", "1s"]);
    wait_until("frames recorded", || {
        status_json(dir.path()).is_some_and(|s| s["frames_recorded"].as_u64() > Some(200))
    });
    let marked = tracerctl()
        .args(["record", "--mark", "--dir"])
        .arg(dir.path())
        .arg("the lift door")
        .output()
        .unwrap();
    assert!(marked.status.success(), "{}", stderr(&marked));
    assert!(stderr(&marked).contains("it becomes an incident within a second"), "{}", stderr(&marked));
    wait_until("the incident", || incidents(dir.path()).len() == 1);
    // --status while it runs: exit 0, running.
    let status =
        tracerctl().args(["record", "--status", "-f", "json", "--dir"]).arg(dir.path()).output().unwrap();
    assert_eq!(status.status.code(), Some(0), "{}", stderr(&status));
    let report: Value = serde_json::from_str(&stdout(&status)).unwrap();
    assert_eq!(report["running"], true);
    assert_eq!(report["incidents"], 1);
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let log = stderr(&output);
    assert!(log.contains("watch-only: nothing is ever sent"), "{log}");
    assert!(log.contains("stopped (SIGTERM)"), "{log}");

    let incident = &incidents(dir.path())[0];
    assert!(incident.file_name().unwrap().to_string_lossy().ends_with("-mark"), "{incident:?}");
    let facts: Value =
        serde_json::from_str(&std::fs::read_to_string(incident.join("incident.json")).unwrap()).unwrap();
    assert_eq!(facts["causes"][0]["cause"], "mark");
    assert_eq!(facts["causes"][0]["description"], "mark: the lift door");
    let (from, to) =
        (facts["window"]["from_us"].as_u64().unwrap(), facts["window"]["to_us"].as_u64().unwrap());
    assert_eq!(to - from, 3_000_000);
    // Byte for byte the ring's lines in [from, to].
    let expected: Vec<String> =
        ring_lines(dir.path()).into_iter().filter(|line| (from..=to).contains(&line_us(line))).collect();
    let kept: Vec<String> =
        std::fs::read_to_string(incident.join("frames.log")).unwrap().lines().map(str::to_string).collect();
    assert!(kept.len() > 100, "{}", kept.len());
    assert_eq!(kept, expected);
    assert_eq!(facts["frames"], kept.len());
    // The summaries are decode --summary's of the window.
    let summary =
        tracerctl().args(["decode", "--summary"]).arg(incident.join("frames.log")).output().unwrap();
    assert_eq!(std::fs::read_to_string(incident.join("summary.txt")).unwrap(), stdout(&summary));
    let summary = tracerctl()
        .args(["decode", "--summary", "-f", "json"])
        .arg(incident.join("frames.log"))
        .output()
        .unwrap();
    let ours: Value =
        serde_json::from_str(&std::fs::read_to_string(incident.join("summary.json")).unwrap()).unwrap();
    assert_eq!(ours, serde_json::from_str::<Value>(&stdout(&summary)).unwrap());
    // The MCAP file holds every frame on /tracer/raw.
    let mcap = std::fs::read(incident.join("frames.mcap")).unwrap();
    let raw = mcap::MessageStream::new(&mcap)
        .unwrap()
        .filter(|message| message.as_ref().unwrap().channel.topic == "/tracer/raw")
        .count();
    assert_eq!(raw, kept.len());

    // After the stop: --status says it is not running (exit 1), with the counts; --list names the incident.
    let status =
        tracerctl().args(["record", "--status", "-f", "json", "--dir"]).arg(dir.path()).output().unwrap();
    assert_eq!(status.status.code(), Some(1));
    let report: Value = serde_json::from_str(&stdout(&status)).unwrap();
    assert_eq!(report["running"], false);
    assert_eq!(report["status"]["state"], "stopped");
    assert_eq!(report["status"]["frames_recorded"].as_u64().unwrap(), ring_lines(dir.path()).len() as u64);
    assert_eq!(report["status"]["frames_lost"], 0);
    let list = tracerctl().args(["record", "--list", "--dir"]).arg(dir.path()).output().unwrap();
    assert!(
        stdout(&list).starts_with(&incident.file_name().unwrap().to_string_lossy().to_string()),
        "{}",
        stdout(&list)
    );
    assert!(stdout(&list).contains("mark: the lift door"), "{}", stdout(&list));
}

#[test]
fn segments_read_with_decode_and_hold_every_frame_recorded() {
    let dir = tempfile::tempdir().unwrap();
    let child = start(&["--sim"], dir.path(), &["--segment", "1s"]);
    wait_until("three segments", || std::fs::read_dir(dir.path().join("ring")).is_ok_and(|d| d.count() >= 3));
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let recorded = status_json(dir.path()).unwrap()["frames_recorded"].as_u64().unwrap();
    let mut decoded = 0;
    let mut segments: Vec<PathBuf> =
        std::fs::read_dir(dir.path().join("ring")).unwrap().flatten().map(|e| e.path()).collect();
    segments.sort();
    assert!(segments.len() >= 3);
    for segment in &segments {
        let output = tracerctl().args(["decode", "--summary", "-f", "json"]).arg(segment).output().unwrap();
        assert!(output.status.success(), "{segment:?}: {}", stderr(&output));
        let report: Value = serde_json::from_str(&stdout(&output)).unwrap();
        assert_eq!(report["rejected_lines"], 0, "{segment:?}");
        decoded += report["frames"].as_u64().unwrap();
    }
    assert_eq!(decoded, recorded);
    // Each segment's lines are within its time: the name is its first frame's time.
    let lines = ring_lines(dir.path());
    assert!(lines.windows(2).all(|pair| line_us(&pair[0]) <= line_us(&pair[1])), "in time order");
}

#[test]
fn one_recorder_per_directory_and_a_mark_needs_one() {
    let dir = tempfile::tempdir().unwrap();
    let marked = tracerctl().args(["record", "--mark", "--dir"]).arg(dir.path()).output().unwrap();
    assert_eq!(marked.status.code(), Some(1));
    assert!(stderr(&marked).contains("no recorder runs in"), "{}", stderr(&marked));
    assert!(!dir.path().join("marks").exists(), "no mark left behind");
    let child = start(&["--sim"], dir.path(), &[]);
    wait_until("the recorder", || status_json(dir.path()).is_some());
    let second = tracerctl().args(["--sim", "record", "--dir"]).arg(dir.path()).output().unwrap();
    assert_eq!(second.status.code(), Some(1));
    assert!(
        stderr(&second).contains(&format!("process {} already records into", child.id())),
        "{}",
        stderr(&second)
    );
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
}

#[test]
fn status_and_list_of_a_missing_directory_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothing");
    for flag in ["--status", "--list"] {
        let output = tracerctl().args(["record", flag, "--dir"]).arg(&missing).output().unwrap();
        assert_eq!(output.status.code(), Some(1), "{flag}");
        assert!(stderr(&output).contains("is not a recorder directory"), "{flag}: {}", stderr(&output));
    }
    let output = tracerctl().args(["record", "--list", "--dir"]).arg(dir.path()).output().unwrap();
    assert_eq!(stdout(&output), format!("no incidents in {}\n", dir.path().display()));
}

#[test]
fn dry_run_shows_the_instance_link_and_settings() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("can0", "link: SocketCAN can0"),
        ("dev/ttyUSB0", "link: serial /dev/ttyUSB0 at 115200 baud"),
        ("ttyACM1", "link: serial /dev/ttyACM1 at 115200 baud"),
    ];
    for (instance, link) in cases {
        let output = tracerctl()
            .args([
                "record",
                "--dry-run",
                "--instance",
                instance,
                "--max-total",
                "500MB",
                "--trigger",
                "battery_voltage<23.0",
                "--dir",
            ])
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", stderr(&output));
        let text = stdout(&output);
        assert!(
            text.starts_with(&format!("{link}\ninstance: {instance}\ndirectory: {}\n", dir.path().display())),
            "{text}"
        );
        assert!(text.contains("max-total: 476.8 MiB\n"), "{text}");
        assert!(text.contains("battery_voltage<23.0"), "{text}");
    }
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none(), "a dry run creates nothing");
}

#[test]
fn bad_record_options_are_usage_errors() {
    let unknown =
        tracerctl().args(["record", "--dry-run", "--trigger", "battery_voltag<23"]).output().unwrap();
    assert_eq!(unknown.status.code(), Some(2));
    assert!(stderr(&unknown).contains("did you mean battery_voltage"), "{}", stderr(&unknown));
    let cases: [&[&str]; 5] = [
        &["record", "--max-total", "10KiB"],
        &["record", "--max-total", "lots"],
        &["record", "--segment", "0s"],
        &["--sim", "record", "--instance", "can0"],
        &["record", "--status", "--mark"],
    ];
    for args in cases {
        let output = tracerctl().args(args).output().unwrap();
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
    }
}

/// A tmpfs of `size` mounted on `at` for the test's life (root only).
struct Tmpfs(PathBuf);

impl Tmpfs {
    fn mount(at: &Path, size: &str) -> Tmpfs {
        let status = std::process::Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(at)
            .status()
            .expect("mount runs");
        assert!(status.success(), "mount -t tmpfs failed: this test needs root");
        Tmpfs(at.to_path_buf())
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount").arg("-l").arg(&self.0).status();
    }
}

/// Fills the file system of `path` until it refuses (ENOSPC).
fn fill(path: &Path) {
    use std::io::Write;
    let mut file = std::fs::File::create(path).unwrap();
    let block = vec![0xA5u8; 64 * 1024];
    loop {
        if file.write_all(&block).is_err() {
            let _ = file.write_all(&block[..512]);
            let _ = file.write_all(&block[..1]);
            return;
        }
    }
}

#[test]
#[ignore = "needs root: mounts a 4 MiB tmpfs (.ci/run runs the ignored integration tests as root)"]
fn a_full_disk_shrinks_the_ring_counts_losses_and_recording_resumes() {
    let base = tempfile::tempdir().unwrap();
    let _disk = Tmpfs::mount(base.path(), "4m");
    let dir = base.path().join("rec");
    // A first run leaves closed segments and an incident ...
    let child = start(&["--sim"], &dir, &["--segment", "1s", "--before", "1s", "--after", "1s"]);
    wait_until("segments", || std::fs::read_dir(dir.join("ring")).is_ok_and(|d| d.count() >= 5));
    tracerctl().args(["record", "--mark", "--dir"]).arg(&dir).assert().success();
    wait_until("the incident", || incidents(&dir).len() == 1);
    let incident = incidents(&dir)[0].clone();
    assert_eq!(stop(child).status.code(), Some(0));
    // ... a second one writes one long segment: on a full disk it removes the closed ones to grow, then
    // counts the frames it cannot write.
    let child = start(&["--sim"], &dir, &["--segment", "1h"]);
    wait_until("frames recorded", || {
        status_json(&dir).is_some_and(|s| s["frames_recorded"].as_u64() > Some(100))
    });
    fill(&base.path().join("filler"));
    wait_until("the ring shrinking", || {
        status_json(&dir).is_some_and(|s| s["ring_segments_removed"].as_u64() > Some(0))
    });
    wait_until("frames lost", || status_json(&dir).is_some_and(|s| s["frames_lost"].as_u64() > Some(0)));
    let during = status_json(&dir).unwrap();
    assert!(during["losses"][0]["reason"].as_str().unwrap().contains("is full"), "{during}");
    assert!(during["state"].as_str().unwrap().starts_with("losing frames: the disk holding"), "{during}");
    // Room again: it records again by itself.
    std::fs::remove_file(base.path().join("filler")).unwrap();
    let recorded = during["frames_recorded"].as_u64().unwrap();
    wait_until("recording again", || {
        status_json(&dir).is_some_and(|s| {
            s["frames_recorded"].as_u64() > Some(recorded + 100) && s["state"] == "recording"
        })
    });
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let log = stderr(&output);
    assert!(log.contains("is full, with nothing older left to remove"), "{log}");
    assert!(log.contains("recording again ("), "{log}");
    assert!(incident.join("frames.log").is_file(), "the incident was kept: incidents go last");
    let end = status_json(&dir).unwrap();
    assert!(end["frames_lost"].as_u64() > Some(0), "{end}");
    assert_eq!(end["incidents_removed"], 0, "{end}");
}

#[test]
fn an_rs232_recording_keeps_hex_lines_and_its_incidents_decode() {
    let sim = crate::pty_sim::PtySim::start("20s", &[]);
    let dir = tempfile::tempdir().unwrap();
    let child =
        start(&["--serial", &sim.path], dir.path(), &["--segment", "1s", "--before", "1s", "--after", "1s"]);
    wait_until("frames recorded", || {
        status_json(dir.path()).is_some_and(|s| s["frames_recorded"].as_u64() > Some(50))
    });
    tracerctl().args(["record", "--mark", "--dir"]).arg(dir.path()).assert().success();
    wait_until("the incident", || incidents(dir.path()).len() == 1);
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    // 13 bytes in hex, the stamp and the port in a comment, as monitor --log writes them.
    let lines = ring_lines(dir.path());
    let line = &lines[0];
    assert_eq!(line.find(" # ("), Some(26), "{line}");
    assert!(line.starts_with("5AA5"), "{line}");
    assert!(line.ends_with(&format!(") {}", sim.path)), "{line}");
    let incident = &incidents(dir.path())[0];
    let facts: Value =
        serde_json::from_str(&std::fs::read_to_string(incident.join("incident.json")).unwrap()).unwrap();
    assert_eq!(facts["protocol"], "serial");
    assert_eq!(facts["unreadable_lines"], 0);
    let frames = facts["frames"].as_u64().unwrap();
    assert!(frames > 10, "{facts}");
    // decode --serial reads the incident's frames; its summary counted every frame.
    let decoded = tracerctl().args(["decode", "--serial"]).arg(incident.join("frames.log")).output().unwrap();
    assert!(decoded.status.success(), "{}", stderr(&decoded));
    assert_eq!(stdout(&decoded).lines().count() as u64, frames);
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(incident.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["frames"].as_u64(), Some(frames));
}

#[test]
fn max_incidents_removes_the_oldest_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let child = start(&["--sim"], dir.path(), &["--before", "0s", "--after", "0s", "--max-incidents", "2"]);
    wait_until("the recorder", || status_json(dir.path()).is_some());
    let mut names = Vec::new();
    for number in 1..=3 {
        tracerctl()
            .args(["record", "--mark", "--dir"])
            .arg(dir.path())
            .arg(format!("mark {number}"))
            .assert()
            .success();
        wait_until("the incident", || {
            let listed: Vec<String> = incidents(dir.path())
                .iter()
                .map(|p| std::fs::read_to_string(p.join("incident.json")).unwrap())
                .collect();
            listed.iter().any(|text| text.contains(&format!("mark: mark {number}")))
        });
        names.push(incidents(dir.path()).last().unwrap().clone());
    }
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(incidents(dir.path()), names[1..], "the two newest are kept");
    assert!(
        stderr(&output).contains("removed the 1 oldest incident(s): more than --max-incidents 2 are kept"),
        "{}",
        stderr(&output)
    );
    let end = status_json(dir.path()).unwrap();
    assert_eq!(
        (end["incidents_made"].as_u64(), end["incidents_removed"].as_u64()),
        (Some(3), Some(1)),
        "{end}"
    );
}

#[test]
fn an_instance_that_names_a_profile_takes_its_link_and_recorder_settings() {
    let dir = tempfile::tempdir().unwrap();
    let config = dir.path().join("config.toml");
    std::fs::write(
        &config,
        "[record]\nsegment = \"2m\"\n\n[profiles.corridor]\nlink.iface = \"vcan7\"\nrecord.before = \"10s\"\nrecord.triggers = [\"battery_voltage<23.5\"]\n",
    )
    .unwrap();
    let run = |instance: &str| {
        let output = tracerctl()
            .env("TRACERCTL_CONFIG", &config)
            .args(["record", "--dry-run", "--instance", instance, "--dir"])
            .arg(dir.path().join("rec"))
            .output()
            .unwrap();
        assert!(output.status.success(), "{}", stderr(&output));
        stdout(&output)
    };
    let profiled = run("corridor");
    assert!(profiled.starts_with("link: SocketCAN vcan7\ninstance: corridor\n"), "{profiled}");
    assert!(profiled.contains("segment: 2m\n") && profiled.contains("before: 10s\n"), "{profiled}");
    assert!(profiled.contains("battery_voltage<23.5"), "{profiled}");
    // Any other name is a link, with the file's settings but not the profile's.
    let plain = run("can1");
    assert!(plain.starts_with("link: SocketCAN can1\ninstance: can1\n"), "{plain}");
    assert!(plain.contains("segment: 2m\n") && plain.contains("before: 1m\n"), "{plain}");
}

/// Ten minutes of a robot in command mode at 25.9 V: 0x211 every 20 ms, an E-stop pressed for 2 s at
/// 100 s, 250 s and 400 s. Returns the log and the onsets (microseconds).
fn estop_session() -> (String, Vec<u64>) {
    const T0: u64 = 1_700_000_000_000_000;
    let onsets: Vec<u64> = [100u64, 250, 400].iter().map(|s| T0 + s * 1_000_000).collect();
    let mut log = String::new();
    for tick in 0..30_000u64 {
        let at = T0 + tick * 20_000;
        let pressed = onsets.iter().any(|onset| (*onset..onset + 2_000_000).contains(&at));
        log.push_str(&format!(
            "({}.{:06}) can0 211#{:02X}010103000000{:02X}\n",
            at / 1_000_000,
            at % 1_000_000,
            u8::from(pressed),
            tick % 256
        ));
    }
    (log, onsets)
}

#[test]
fn a_replay_at_full_speed_gives_one_incident_per_estop_onset() {
    let dir = tempfile::tempdir().unwrap();
    let (log, onsets) = estop_session();
    let path = dir.path().join("session.log");
    std::fs::write(&path, log).unwrap();
    // decode --summary sees the same onsets.
    let summary = tracerctl().args(["decode", "--summary"]).arg(&path).output().unwrap();
    assert_eq!(stdout(&summary).matches("normal -> estop").count(), onsets.len(), "{}", stdout(&summary));
    let rec = dir.path().join("rec");
    let output = tracerctl()
        .args(["--replay"])
        .arg(&path)
        .args(["--speed", "0", "record", "--dir"])
        .arg(&rec)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let made = incidents(&rec);
    assert_eq!(made.len(), onsets.len(), "{made:?}\n{}", stderr(&output));
    for (incident, onset) in made.iter().zip(&onsets) {
        assert!(incident.file_name().unwrap().to_string_lossy().ends_with("-estop"), "{incident:?}");
        let facts: Value =
            serde_json::from_str(&std::fs::read_to_string(incident.join("incident.json")).unwrap()).unwrap();
        let causes = facts["causes"].as_array().unwrap();
        assert_eq!(causes.len(), 1, "only the E-stop: {facts}");
        assert_eq!(facts["window"]["from_us"].as_u64(), Some(onset - 60_000_000), "{facts}");
        assert_eq!(facts["window"]["to_us"].as_u64(), Some(onset + 30_000_000), "{facts}");
        assert_eq!(facts["frames"], 4501, "90 s at 50 Hz, both ends in: {facts}");
        let text = std::fs::read_to_string(incident.join("summary.txt")).unwrap();
        assert_eq!(text.matches("normal -> estop").count(), 1, "{text}");
    }
}

#[test]
fn a_simulated_estop_makes_exactly_one_incident_of_the_rings_frames() {
    let dir = tempfile::tempdir().unwrap();
    let child = start(
        &["--sim", "--fault", "estop@3s"],
        dir.path(),
        &["--segment", "2s", "--before", "2s", "--after", "1s"],
    );
    wait_until("the incident", || incidents(dir.path()).len() == 1);
    // A few seconds more: the E-stop stays pressed, which is no new onset.
    let deadline = Instant::now() + Duration::from_secs(3);
    while Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(100));
    }
    let output = stop(child);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let made = incidents(dir.path());
    assert_eq!(made.len(), 1, "{made:?}\n{}", stderr(&output));
    let facts: Value =
        serde_json::from_str(&std::fs::read_to_string(made[0].join("incident.json")).unwrap()).unwrap();
    assert!(facts["causes"].as_array().unwrap().iter().any(|c| c["cause"] == "estop"), "{facts}");
    let (from, to) =
        (facts["window"]["from_us"].as_u64().unwrap(), facts["window"]["to_us"].as_u64().unwrap());
    let expected: Vec<String> =
        ring_lines(dir.path()).into_iter().filter(|line| (from..=to).contains(&line_us(line))).collect();
    let kept: Vec<String> =
        std::fs::read_to_string(made[0].join("frames.log")).unwrap().lines().map(str::to_string).collect();
    assert_eq!(kept, expected);
    let text = std::fs::read_to_string(made[0].join("summary.txt")).unwrap();
    assert!(text.contains("estop"), "{text}");
    assert!(facts["state_at_trigger"].is_object(), "{facts}");
}
