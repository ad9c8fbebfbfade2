//! Outputs and inputs of the real binary: an output that is an input is refused before anything is
//! truncated (exit 2, both named, the input unchanged byte for byte); a full disk is one line naming the
//! file and the cause; an input without a single frame (empty, binary, only comments) is exit 3 with one
//! line saying why, in `decode` and `--replay` alike.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::util::{data, stderr, stdout, tracerctl};

/// A directory holding `cap.log` (a copy of a fixture with a bad line) and its spellings: `./cap.log` is
/// given relative to the directory, which the commands run in.
struct Capture {
    dir: tempfile::TempDir,
    original: Vec<u8>,
}

impl Capture {
    fn new(name: &str) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let original = std::fs::read(data("decode/bad_line15.log")).unwrap();
        std::fs::write(dir.path().join(name), &original).unwrap();
        Self { dir, original }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    fn run(&self, args: &[&str]) -> Output {
        tracerctl().current_dir(self.dir.path()).args(args).output().unwrap()
    }

    /// Exit 2 naming both spellings, and every byte of the input still there.
    fn assert_refused(&self, output: &Output, written: &str, read: &str, input: &str) {
        let errors = stderr(output);
        assert_eq!(output.status.code(), Some(2), "{errors}");
        assert_eq!(errors.lines().count(), 1, "{errors}");
        assert!(errors.contains(written) && errors.contains(read), "{errors}");
        assert!(errors.contains("is the same file as"), "{errors}");
        assert_eq!(std::fs::read(self.path(input)).unwrap(), self.original, "{input} was changed");
        assert!(stdout(output).is_empty(), "{}", stdout(output));
    }
}

#[test]
fn decode_refuses_an_output_that_is_an_input_by_any_name() {
    let capture = Capture::new("cap.log");
    std::fs::hard_link(capture.path("cap.log"), capture.path("hard.log")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink("cap.log", capture.path("soft.log")).unwrap();
    let mut spellings = vec!["cap.log", "./cap.log", "hard.log"];
    if cfg!(unix) {
        spellings.push("soft.log");
    }
    for output in &spellings {
        for format in ["text", "json", "csv"] {
            for threads in ["-j1", "-j2"] {
                let refused = capture.run(&["decode", threads, "-f", format, "-o", output, "cap.log"]);
                capture.assert_refused(&refused, &format!("-o {output}"), "the input cap.log", "cap.log");
            }
        }
        // Among other inputs, and the summary's report too.
        let good = data("decode/good14.log");
        let args = ["decode", "--summary", "-o", output, good.to_str().unwrap(), "./cap.log"];
        capture.assert_refused(
            &capture.run(&args),
            &format!("-o {output}"),
            "the input ./cap.log",
            "cap.log",
        );
    }
    // The plot's SVG is an output too.
    std::fs::hard_link(capture.path("cap.log"), capture.path("plot.svg")).unwrap();
    let refused = capture.run(&["decode", "--plot", "plot.svg", "cap.log"]);
    capture.assert_refused(&refused, "--plot plot.svg", "the input cap.log", "cap.log");
    // An RS232 capture read with --serial.
    let refused = capture.run(&["decode", "--serial", "cap.log", "-o", "hard.log"]);
    capture.assert_refused(&refused, "-o hard.log", "--serial cap.log", "cap.log");
    // Another file is written as ever.
    let written = capture.run(&["decode", "-o", "out.txt", "cap.log"]);
    assert_eq!(written.status.code(), Some(0), "{}", stderr(&written));
    assert_eq!(std::fs::read_to_string(capture.path("out.txt")).unwrap().lines().count(), 14);
}

#[test]
fn decode_refuses_to_write_mcap_over_its_input() {
    let capture = Capture::new("cap.mcap");
    for args in [
        &["decode", "-f", "mcap", "-o", "cap.mcap", "cap.mcap"][..],
        &["decode", "-o", "./cap.mcap", "cap.mcap"],
    ] {
        let refused = capture.run(args);
        capture.assert_refused(
            &refused,
            &format!("-o {}", args[args.len() - 2]),
            "the input cap.mcap",
            "cap.mcap",
        );
    }
}

/// `decode -o cap.log - < cap.log` (and with no input named: standard input is read).
#[cfg(unix)]
#[test]
fn decode_refuses_an_output_that_is_its_standard_input() {
    let capture = Capture::new("cap.log");
    for args in [&["decode", "-o", "cap.log", "-"][..], &["decode", "-o", "./cap.log"]] {
        let stdin = std::fs::File::open(capture.path("cap.log")).unwrap();
        // The file itself on standard input (not a pipe of its bytes, as assert_cmd would make).
        let refused = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .current_dir(capture.dir.path())
            .args(args)
            .stdin(stdin)
            .output()
            .unwrap();
        capture.assert_refused(&refused, &format!("-o {}", args[2]), "standard input", "cap.log");
    }
}

#[test]
fn a_replay_is_never_overwritten_by_its_own_log_or_recording() {
    let capture = Capture::new("rp.log");
    std::fs::hard_link(capture.path("rp.log"), capture.path("hard.log")).unwrap();
    for (command, option) in [("monitor", "--log"), ("dashboard", "--record")] {
        for output in ["rp.log", "./rp.log", "hard.log"] {
            let refused = capture.run(&["--replay", "rp.log", "--speed", "0", command, option, output]);
            capture.assert_refused(&refused, &format!("{option} {output}"), "--replay rp.log", "rp.log");
        }
    }
    // monitor's log is created only once the replayed log opened: a missing one leaves the file alone.
    let missing = capture.run(&["--replay", "missing.log", "monitor", "--log", "rp.log"]);
    assert_eq!(missing.status.code(), Some(1), "{}", stderr(&missing));
    assert_eq!(std::fs::read(capture.path("rp.log")).unwrap(), capture.original);
}

// ---- a full disk ----

/// The one line a full disk gives: the file's name and the system's words.
fn assert_disk_full(output: &Output, name: &str, what: &str) {
    let errors = stderr(output);
    assert_eq!(output.status.code(), Some(1), "{what}: {errors}");
    let last = errors.lines().last().unwrap_or_default();
    assert_eq!(
        last,
        format!("tracerctl: cannot write {name}: No space left on device (os error 28)"),
        "{what}"
    );
    let said = errors.lines().filter(|line| line.contains("cannot write")).count();
    assert_eq!(said, 1, "{what}: said once\n{errors}");
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_one_line_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let log = data("tracer_session.log");
    let full = dir.path().join("x.mcap");
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    let full_csv = dir.path().join("x.csv");
    std::os::unix::fs::symlink("/dev/full", &full_csv).unwrap();
    for threads in ["-j1", "-j2"] {
        for (format, output) in
            [("mcap", &full), ("csv", &full_csv), ("json", &full_csv), ("text", &full_csv)]
        {
            let run = tracerctl()
                .args(["decode", threads, "-f", format, "-o"])
                .arg(output)
                .arg(&log)
                .output()
                .unwrap();
            assert_disk_full(&run, &output.display().to_string(), &format!("{threads} -f {format}"));
        }
        let dev_full =
            tracerctl().args(["decode", threads, "-f", "csv", "-o", "/dev/full"]).arg(&log).output().unwrap();
        assert_disk_full(&dev_full, "/dev/full", &format!("{threads} -o /dev/full"));
        let stdout_full = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .args(["decode", threads])
            .arg(&log)
            .stdout(std::fs::File::create("/dev/full").unwrap())
            .output()
            .unwrap();
        assert_disk_full(&stdout_full, "standard output", &format!("{threads} > /dev/full"));
        let summary_full = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .args(["decode", threads, "--summary"])
            .arg(&log)
            .stdout(std::fs::File::create("/dev/full").unwrap())
            .output()
            .unwrap();
        assert_disk_full(&summary_full, "standard output", &format!("{threads} --summary > /dev/full"));
    }
}

/// A disk that fills after the file began (the MCAP header written, the frames not): said once, with the
/// file's name. A file-size limit stands in for the full disk (EFBIG instead of ENOSPC, same paths).
#[cfg(target_os = "linux")]
#[test]
fn an_output_that_fills_midway_is_said_once() {
    use std::os::unix::process::CommandExt;
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("big.log");
    let session = std::fs::read_to_string(data("tracer_session.log")).unwrap();
    std::fs::write(&log, session.repeat(200)).unwrap();
    for (format, name) in [("mcap", "out.mcap"), ("csv", "out.csv"), ("json", "out.json")] {
        for threads in ["-j1", "-j2"] {
            let output = dir.path().join(name);
            let mut command = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracerctl"));
            command
                .args(["decode", threads, "--mcap-compression", "none", "-f", format, "-o"])
                .arg(&output)
                .arg(&log);
            // SAFETY: between fork and exec only async-signal-safe calls: signal(2) and setrlimit(2).
            unsafe {
                command.pre_exec(|| {
                    libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
                    let limit = libc::rlimit { rlim_cur: 64 * 1024, rlim_max: 64 * 1024 };
                    if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                        return Err(std::io::Error::last_os_error());
                    }
                    Ok(())
                });
            }
            let run = command.output().unwrap();
            let what = format!("{threads} -f {format}");
            let name = output.display().to_string();
            let (errors, said) =
                (stderr(&run), format!("tracerctl: cannot write {name}: File too large (os error 27)"));
            assert_eq!(run.status.code(), Some(1), "{what}: {errors}");
            assert_eq!(errors.lines().last(), Some(said.as_str()), "{what}: {errors}");
            assert_eq!(
                errors.lines().filter(|line| line.contains("cannot write")).count(),
                1,
                "{what}: {errors}"
            );
        }
    }
}

// ---- no frames at all ----

/// Random bytes, the same every run.
fn random_bytes(count: usize) -> Vec<u8> {
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    (0..count)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 24) as u8
        })
        .collect()
}

fn one_line(output: &Output, expected: &str, what: &str) {
    assert_eq!(output.status.code(), Some(3), "{what}: {}", stderr(output));
    assert_eq!(stderr(output), format!("tracerctl: {expected}\n"), "{what}");
}

#[test]
fn no_frames_at_all_is_exit_3_with_the_reason_in_decode_and_replay() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path.display().to_string()
    };
    let random = write("random.bin", &random_bytes(3000));
    let empty = write("empty.log", b"");
    let comments = write("comments.log", b"# recorded by hand\n\n# nothing came\n");
    let binary = format!(
        "{random} is binary data, not a text log, which tracerctl does not read: an RS232 capture? use \
         `tracerctl decode --serial {random}`"
    );
    let cases = [
        (&random, binary.clone(), binary),
        (&empty, format!("no frames in {empty}: empty"), format!("nothing to replay: {empty} is empty")),
        (
            &comments,
            format!("no frames in {comments}: all 3 lines blank or comments"),
            format!("nothing to replay: {comments} has no candump frames (3 lines, all blank or comments)"),
        ),
    ];
    for (path, decoded, replayed) in &cases {
        for extra in [&["-j1"][..], &["-j2"], &["-f", "json"], &["--summary"]] {
            let output = tracerctl().arg("decode").args(extra).arg(path).output().unwrap();
            one_line(&output, decoded, &format!("decode {extra:?} {path}"));
        }
        let monitor = tracerctl().args(["--replay", path, "--speed", "0", "monitor"]).output().unwrap();
        assert_eq!(monitor.status.code(), Some(3), "monitor {path}: {}", stderr(&monitor));
        assert_eq!(
            stderr(&monitor).lines().filter(|line| line.contains(replayed.as_str())).count(),
            1,
            "{}",
            stderr(&monitor)
        );
    }
    // Text whose every line is rejected: the first ten shown, the totals, then the reason, last.
    let garbage = write("garbage.log", "RX 0x211 00 00 01 03 00 00 00 B1\n".repeat(20).as_bytes());
    for threads in ["-j1", "-j2"] {
        let output = tracerctl().args(["decode", threads, &garbage]).output().unwrap();
        let errors = stderr(&output);
        assert_eq!(output.status.code(), Some(3), "{errors}");
        assert_eq!(errors.matches(": column 1: not a candump line").count(), 10, "{errors}");
        assert!(errors.contains("decoded 0 frames from 20 lines; rejected 20 lines"), "{errors}");
        let reason = format!(
            "tracerctl: no frames in {garbage}: all 20 lines rejected or skipped (20 rejected, 0 skipped)"
        );
        assert_eq!(errors.lines().last(), Some(reason.as_str()), "{errors}");
    }
    // Several inputs without a frame: every reason on the one line.
    let both = tracerctl().args(["decode", &empty, &comments]).output().unwrap();
    let reasons =
        format!("no frames in {empty}: empty; no frames in {comments}: all 3 lines blank or comments");
    one_line(&both, &reasons, "decode empty comments");
    // Standard input too, and an empty RS232 capture.
    let piped = tracerctl().args(["decode", "-"]).write_stdin(Vec::new()).output().unwrap();
    one_line(&piped, "no frames in <stdin>: empty", "decode - < empty");
    let serial = tracerctl().args(["decode", "--serial", &empty]).output().unwrap();
    one_line(&serial, &format!("no TRACER frames in {empty}: empty"), "decode --serial empty");
    // A log with frames beside an empty one: exit 0, the empty one named after the output.
    let good = data("decode/good14.log");
    let mixed = tracerctl().arg("decode").arg(&empty).arg(&good).output().unwrap();
    assert_eq!(mixed.status.code(), Some(0), "{}", stderr(&mixed));
    assert_eq!(stdout(&mixed).lines().count(), 14);
    assert_eq!(stderr(&mixed), format!("tracerctl: no frames in {empty}: empty\n"));
    assert!(Path::new(&empty).exists());
}
