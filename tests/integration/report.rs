//! `tracerctl report`, the support bundle: its members listed exactly (by the real `tar` and by the tar
//! crate), README.txt naming each, no secret from the environment and no home directory in any byte, the
//! size cap kept and the omissions said, a recorder directory's incidents and ring segments taken byte for
//! byte, `--replay` and a missing interface, no file overwritten, a closed stdout.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::Output;

use crate::util::{data, stderr, tracerctl};

/// The members of a bundle as the real `tar -tzf` lists them.
fn tar_list(bundle: &Path) -> Vec<String> {
    let output = std::process::Command::new("tar").arg("-tzf").arg(bundle).output().expect("tar runs");
    assert!(output.status.success(), "tar -tzf: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).unwrap().lines().map(str::to_string).collect()
}

/// Every member's name and bytes, read with the tar crate.
fn members(bundle: &Path) -> Vec<(String, Vec<u8>)> {
    let file = std::fs::File::open(bundle).unwrap();
    let mut archive = tar::Archive::new(flate2::read::GzDecoder::new(file));
    archive
        .entries()
        .unwrap()
        .map(|entry| {
            let mut entry = entry.unwrap();
            let mut bytes = Vec::new();
            entry.read_to_end(&mut bytes).unwrap();
            (entry.path().unwrap().display().to_string(), bytes)
        })
        .collect()
}

/// The bundle's whole tar stream, decompressed.
fn all_bytes(bundle: &Path) -> Vec<u8> {
    let mut bytes = Vec::new();
    flate2::read::GzDecoder::new(std::fs::File::open(bundle).unwrap()).read_to_end(&mut bytes).unwrap();
    bytes
}

fn member<'a>(members: &'a [(String, Vec<u8>)], suffix: &str) -> &'a str {
    let (_, bytes) =
        members.iter().find(|(name, _)| name.ends_with(suffix)).unwrap_or_else(|| panic!("no {suffix}"));
    std::str::from_utf8(bytes).unwrap()
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|window| window == needle)
}

/// Runs `tracerctl LINK... report ARGS...` in `cwd`.
fn report(cwd: &Path, link: &[&str], args: &[&str]) -> Output {
    tracerctl()
        .current_dir(cwd)
        .args(link)
        .arg("report")
        .args(["--listen", "300ms"])
        .args(args)
        .output()
        .unwrap()
}

const ESSENTIALS: [&str; 8] = [
    "host.txt",
    "doctor.txt",
    "doctor.json",
    "robot.txt",
    "robot.json",
    "listen.log",
    "README.txt",
    "report.json",
];

fn under(folder: &str, names: &[&str]) -> Vec<String> {
    names.iter().map(|name| format!("{folder}/{name}")).collect()
}

#[test]
fn a_sim_report_holds_exactly_its_files_each_named_in_the_readme() {
    let dir = tempfile::tempdir().unwrap();
    let output = report(
        dir.path(),
        &["--sim"],
        &["-o", "b.tar.gz", "--dir", dir.path().join("none").to_str().unwrap()],
    );
    assert_eq!(output.status.code(), Some(2), "a --dir that does not exist: {}", stderr(&output));
    assert!(stderr(&output).contains("--dir"), "{}", stderr(&output));

    let output = report(dir.path(), &["--sim"], &["-o", "b.tar.gz"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(String::from_utf8_lossy(&output.stdout), "b.tar.gz\n");
    let bundle = dir.path().join("b.tar.gz");
    let expected = under("b", &ESSENTIALS);
    assert_eq!(tar_list(&bundle), expected);
    let members = members(&bundle);
    assert_eq!(members.iter().map(|(name, _)| name.clone()).collect::<Vec<_>>(), expected);

    let readme = member(&members, "README.txt");
    for name in ESSENTIALS {
        assert!(
            readme.lines().any(|line| line.trim_start().starts_with(&format!("{name} "))),
            "{name} not in {readme}"
        );
    }
    assert!(readme.contains("Left out: nothing."), "{readme}");
    let robot = member(&members, "robot.txt");
    assert!(
        robot
            .contains("firmware version: controller hw 1.0, driver hw 1.0, controller sw 1.0, driver sw 1.0"),
        "{robot}"
    );
    assert!(robot.contains("protocol: V2"), "{robot}");
    let robot_json: serde_json::Value = serde_json::from_str(member(&members, "robot.json")).unwrap();
    assert_eq!(robot_json["firmware_version"]["answered"], true);
    assert!(robot_json["rates"]["frames"].as_u64().unwrap() > 0);
    let doctor: serde_json::Value = serde_json::from_str(member(&members, "doctor.json")).unwrap();
    assert_eq!(doctor["drivable"], true);
    assert!(member(&members, "doctor.txt").starts_with("tracerctl doctor: the in-process virtual TRACER"));
    // The listen: the robot's frames and the two version requests the report sent.
    let listen = member(&members, "listen.log");
    assert!(listen.lines().filter(|line| line.contains(" sim 211#")).count() >= 5, "{listen}");
    assert!(listen.contains(" sim 411#01\n") && listen.contains(" sim 4A1#01\n"), "{listen}");
    let index: serde_json::Value = serde_json::from_str(member(&members, "report.json")).unwrap();
    let listed: Vec<&str> =
        index["files"].as_array().unwrap().iter().map(|f| f["name"].as_str().unwrap()).collect();
    assert_eq!(listed, &ESSENTIALS[..6]);
    assert_eq!(index["max_size"], 50_000_000);
}

/// A fake home holding the replayed log and the recorder's directory; a secret in the environment.
#[test]
fn no_secret_from_the_environment_and_no_home_directory_is_in_any_byte() {
    let dir = tempfile::tempdir().unwrap();
    let home = dir.path().join("fakehome-zq81");
    let record = home.join("record");
    std::fs::create_dir_all(record.join("incidents/20261128T134100Z-estop")).unwrap();
    std::fs::write(record.join("incidents/20261128T134100Z-estop/summary.txt"), "estop\n").unwrap();
    let replayed = home.join("capture.log");
    std::fs::copy(data("tracer_session.log"), &replayed).unwrap();
    let secret = "hunter2-4f1d9c-never-in-a-bundle";
    let output = tracerctl()
        .current_dir(dir.path())
        .env("TRACERCTL_TEST_SECRET", secret)
        .env("HOME", &home)
        .env("SECRET_TOKEN", secret)
        .arg("--replay")
        .arg(&replayed)
        .args(["report", "--listen", "300ms", "-o", "s.tar.gz", "--dir"])
        .arg(&record)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let bundle = dir.path().join("s.tar.gz");
    let bytes = all_bytes(&bundle);
    assert!(!contains(&bytes, secret.as_bytes()), "the secret is in the bundle");
    assert!(!contains(&bytes, b"fakehome-zq81"), "the home directory is in the bundle");
    assert!(!contains(&bytes, dir.path().to_str().unwrap().as_bytes()), "a path above home is in the bundle");
    let members = members(&bundle);
    // The paths are there, written from ~.
    assert!(member(&members, "doctor.txt").contains("replaying ~/capture.log (read-only)"));
    assert!(member(&members, "README.txt").contains("Recorder directory: ~/record."));
    assert!(!stderr(&output).contains("fakehome-zq81"), "{}", stderr(&output));
}

/// A recorder's directory: `count` incidents a minute apart from 12:00 (frames.log of `frame_bytes`
/// incompressible bytes), one-minute ring segments from 12:00 for `segments` minutes, a status file, and
/// a symbolic link that must not be followed.
fn recorder_fixture(root: &Path, count: usize, frame_bytes: usize, segments: u32) -> PathBuf {
    let record = root.join("record");
    for index in 0..count {
        let incident = record.join(format!("incidents/20261128T12{index:02}00Z-fault"));
        std::fs::create_dir_all(&incident).unwrap();
        std::fs::write(incident.join("incident.json"), format!("{{\"cause\":[\"fault\"],\"n\":{index}}}\n"))
            .unwrap();
        std::fs::write(incident.join("summary.txt"), format!("summary {index}\n")).unwrap();
        std::fs::write(incident.join("summary.json"), "{}\n").unwrap();
        std::fs::write(incident.join("frames.log"), noise(frame_bytes, index as u64 + 1)).unwrap();
        std::fs::write(incident.join("frames.mcap"), noise(frame_bytes / 4, index as u64 + 100)).unwrap();
    }
    let ring = record.join("ring");
    std::fs::create_dir_all(&ring).unwrap();
    for minute in 0..segments {
        let path = ring.join(format!("20261128T12{minute:02}00.000Z.log.zst"));
        let lines = format!("(1795870800.000000) can0 211#00000103000000{minute:02X}\n");
        std::fs::write(&path, zstd::encode_all(lines.as_bytes(), 3).unwrap()).unwrap();
        // Written through its minute (the recorder's segments end where the next begins).
        let end = std::time::UNIX_EPOCH
            + std::time::Duration::from_secs(1_795_867_200 + u64::from(minute) * 60 + 59);
        std::fs::File::options().write(true).open(&path).unwrap().set_modified(end).unwrap();
    }
    std::fs::write(record.join("status.json"), "{\"running\":false}\n").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("/etc/passwd", ring.join("20261128T125900.000Z.log.zst")).unwrap();
    record
}

/// Bytes that do not compress (xorshift).
fn noise(len: usize, seed: u64) -> Vec<u8> {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..len)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state as u8
        })
        .collect()
}

#[test]
fn a_recorders_newest_incidents_and_last_ring_minutes_are_taken_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let record = recorder_fixture(dir.path(), 3, 1000, 15);
    let dir_arg = record.to_str().unwrap();
    let output = report(
        dir.path(),
        &["--sim"],
        &["-o", "r.tar.gz", "--dir", dir_arg, "--incidents", "2", "--ring-minutes", "3"],
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let bundle = dir.path().join("r.tar.gz");
    let mut expected = under("r", &ESSENTIALS[..6]);
    expected.push("r/recorder/timeline.txt".to_string());
    for incident in ["20261128T120100Z-fault", "20261128T120200Z-fault"] {
        for file in ["frames.log", "frames.mcap", "incident.json", "summary.json", "summary.txt"] {
            expected.push(format!("r/recorder/incidents/{incident}/{file}"));
        }
    }
    // The last write is 12:14:59: three minutes back is 12:11:59, held by the 12:11 segment.
    for minute in 11..15 {
        expected.push(format!("r/recorder/ring/20261128T12{minute:02}00.000Z.log.zst"));
    }
    expected.push("r/recorder/status.json".to_string());
    expected.extend(under("r", &ESSENTIALS[6..]));
    assert_eq!(tar_list(&bundle), expected);

    let members = members(&bundle);
    for (name, bytes) in &members {
        if let Some(relative) = name.strip_prefix("r/recorder/").filter(|n| *n != "timeline.txt") {
            assert_eq!(
                bytes,
                &std::fs::read(record.join(relative)).unwrap(),
                "{name} is not the recorder's file"
            );
        }
    }
    let timeline = member(&members, "recorder/timeline.txt");
    assert_eq!(
        timeline,
        "3 incident(s), newest first\n\
         2026-11-28 12:02:00 UTC  fault                    in the bundle\n\
         2026-11-28 12:01:00 UTC  fault                    in the bundle\n\
         2026-11-28 12:00:00 UTC  fault                    not taken (--incidents)\n"
    );
    let readme = member(&members, "README.txt");
    assert!(readme.contains("1 older incident(s): only the newest 2 are taken (--incidents)"), "{readme}");
    let segment_line =
        readme.lines().find(|line| line.trim_start().starts_with("recorder/ring/20261128T121400.000Z"));
    assert!(
        segment_line.is_some_and(|line| line.contains("  ring segment from 2026-11-28 12:14:00 UTC")),
        "{readme}"
    );
    // No recorder runs there: the listen is kept.
    assert!(stderr(&output).contains("the frames are kept: no recorder is running"), "{}", stderr(&output));
}

#[test]
fn the_size_cap_holds_and_what_it_left_out_is_said() {
    let dir = tempfile::tempdir().unwrap();
    // Four incidents of 1.5 MB frames that do not compress, under a 4 MB cap: two fit.
    let record = recorder_fixture(dir.path(), 4, 1_500_000, 3);
    let dir_arg = record.to_str().unwrap();
    let output = report(dir.path(), &["--sim"], &["-o", "c.tar.gz", "--dir", dir_arg, "--max-size", "4MB"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let bundle = dir.path().join("c.tar.gz");
    let size = std::fs::metadata(&bundle).unwrap().len();
    assert!(size <= 4_000_000, "{size} bytes under a 4 MB cap");
    assert!(size > 2_900_000, "{size}: the two newest incidents' frames fit");
    let list = tar_list(&bundle);
    let frames: Vec<&String> = list.iter().filter(|name| name.ends_with("frames.log")).collect();
    assert_eq!(
        frames,
        [
            "c/recorder/incidents/20261128T120200Z-fault/frames.log",
            "c/recorder/incidents/20261128T120300Z-fault/frames.log"
        ]
    );
    // Every incident's summaries are there, newest or not; the ring's small segments too.
    assert_eq!(list.iter().filter(|name| name.ends_with("summary.txt")).count(), 4);
    assert_eq!(list.iter().filter(|name| name.ends_with(".log.zst")).count(), 3);
    let members = members(&bundle);
    let readme = member(&members, "README.txt");
    let left = "recorder/incidents/20261128T120100Z-fault/frames.log (1.5 MB): over the size cap (--max-size 4.0 MB)";
    assert!(readme.contains(left), "{readme}");
    let index: serde_json::Value = serde_json::from_str(member(&members, "report.json")).unwrap();
    // The two older frames.log, and the MCAP files (last in preference) of the two older incidents.
    let left_out: Vec<&str> = index["left_out"]
        .as_array()
        .unwrap()
        .iter()
        .map(|omitted| omitted["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        left_out,
        [
            "recorder/incidents/20261128T120100Z-fault/frames.log",
            "recorder/incidents/20261128T120000Z-fault/frames.log",
            "recorder/incidents/20261128T120100Z-fault/frames.mcap",
            "recorder/incidents/20261128T120000Z-fault/frames.mcap",
        ]
    );
    let said = stderr(&output);
    assert!(said.contains("tracerctl: left out of the bundle: 4 file(s), 3.8 MB"), "{said}");
    assert!(said.contains("over the size cap (--max-size 4.0 MB)"), "{said}");
}

#[test]
fn a_replay_gives_a_bundle_with_the_version_not_asked() {
    let dir = tempfile::tempdir().unwrap();
    let output = tracerctl()
        .current_dir(dir.path())
        .arg("--replay")
        .arg(data("tracer_session.log"))
        .args(["report", "--listen", "300ms", "-o", "p.tar.gz"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let members = members(&dir.path().join("p.tar.gz"));
    let robot = member(&members, "robot.txt");
    assert!(
        robot.contains("firmware version: not asked: --replay is read-only: nothing was sent"),
        "{robot}"
    );
    let listen = member(&members, "listen.log");
    assert!(listen.starts_with('(') && listen.contains(" replay 211#00000103000000B1\n"), "{listen}");

    let output = tracerctl()
        .current_dir(dir.path())
        .arg("--replay")
        .arg(data("tracer_session.log"))
        .args(["report", "--probe"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2), "--probe on a replay is a usage error");
}

#[cfg(target_os = "linux")]
#[test]
fn offline_a_missing_interface_still_gives_a_bundle_whose_doctor_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let output = report(dir.path(), &["--iface", "nosuchcan7"], &["-o", "o.tar.gz"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let bundle = dir.path().join("o.tar.gz");
    // Nothing heard, nothing recorded: no listen.log.
    let mut expected = under("o", &ESSENTIALS[..5]);
    expected.extend(under("o", &ESSENTIALS[6..]));
    assert_eq!(tar_list(&bundle), expected);
    let members = members(&bundle);
    let doctor = member(&members, "doctor.txt");
    assert!(doctor.contains("FAIL") && doctor.contains("nosuchcan7"), "{doctor}");
    let robot = member(&members, "robot.txt");
    assert!(robot.contains("not asked: the link could not be used"), "{robot}");
    assert!(member(&members, "host.txt").contains("interface nosuchcan7: does not exist"));
}

#[test]
fn an_existing_file_an_input_and_the_recorders_directory_are_never_written() {
    let dir = tempfile::tempdir().unwrap();
    let existing = dir.path().join("keep.tar.gz");
    std::fs::write(&existing, "precious").unwrap();
    let output = report(dir.path(), &["--sim"], &["-o", "keep.tar.gz"]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("keep.tar.gz exists: give another name with -o, or --force"),
        "{}",
        stderr(&output)
    );
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "precious");

    let replayed = dir.path().join("in.log");
    std::fs::copy(data("tracer_session.log"), &replayed).unwrap();
    let output = tracerctl()
        .current_dir(dir.path())
        .args(["--replay", "in.log", "report", "--force", "-o", "in.log"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert_eq!(std::fs::read(&replayed).unwrap(), std::fs::read(data("tracer_session.log")).unwrap());

    let record = recorder_fixture(dir.path(), 1, 10, 1);
    let inside = record.join("incidents/b.tar.gz");
    let output =
        report(dir.path(), &["--sim"], &["--dir", record.to_str().unwrap(), "-o", inside.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    assert!(stderr(&output).contains("into the recorder's directory"), "{}", stderr(&output));
    assert!(!inside.exists());

    let output = report(dir.path(), &["--sim"], &["-o", "keep.tar.gz", "--force"]);
    assert_eq!(output.status.code(), Some(0), "--force replaces it: {}", stderr(&output));
    assert_eq!(tar_list(&existing).len(), ESSENTIALS.len());
}

#[test]
fn a_directory_as_output_gets_the_default_name_and_a_closed_stdout_is_no_panic() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("usb");
    std::fs::create_dir(&out).unwrap();
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let output = std::process::Command::new("bash")
        .arg("-c")
        .arg(format!("'{}' --sim report --listen 300ms -o '{}' >&-", binary.display(), out.display()))
        .output()
        .unwrap();
    let said = stderr(&output);
    assert_eq!(output.status.code(), Some(0), "{said}");
    assert!(!said.contains("panicked"), "{said}");
    let made: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(made.len(), 1, "{made:?}");
    let name = &made[0];
    assert!(name.starts_with("tracerctl-report-") && name.ends_with("Z.tar.gz"), "{name}");
    // The time is the compact UTC form: YYYYMMDDTHHMMSSZ.
    let stamp = &name[name.len() - "20261128T134100Z.tar.gz".len()..name.len() - ".tar.gz".len()];
    assert!(stamp.len() == 16 && stamp.as_bytes()[8] == b'T', "{stamp}");
    assert!(said.contains(&format!("tracerctl: report: wrote {}", out.join(name).display())), "{said}");
}
