//! Nothing lost silently on the live paths: a standard output nobody reads (`monitor | less`, not scrolling),
//! a recording on a full disk (`--log` / `--record` to /dev/full, where writes fail with ENOSPC), and a
//! `--replay` log with lines that are not candump lines.

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use super::dashboard::Session;
#[cfg(target_os = "linux")]
use super::serial_peer::{healthy, FakeRobot};
use super::util::{data, stderr, stdout, tracerctl};

fn binary() -> std::path::PathBuf {
    assert_cmd::cargo::cargo_bin("tracerctl")
}

fn wall_clock() -> f64 {
    SystemTime::now().duration_since(UNIX_EPOCH).unwrap().as_secs_f64()
}

/// The first number after `after` in `text`.
fn number_after(text: &str, after: &str) -> Option<u64> {
    let rest = &text[text.find(after)? + after.len()..];
    let digits: String = rest.trim_start().chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// A run of `tracerctl ARGS` whose standard output nobody read for its first 3 s.
struct UnreadRun {
    /// When the run began (wall clock, as the JSON `ts` stamps are).
    started: f64,
    /// The `ts` of every line read once reading began.
    stamps: Vec<f64>,
    errors: String,
}

/// Runs `tracerctl ARGS` (a 4 s `monitor --format json`) with a standard output that is a pipe nobody reads
/// for 3 s, as with a pager that is not scrolling, then reads all of it.
fn run_with_stdout_unread(args: &[&str]) -> UnreadRun {
    let (mut output, stdout) = stdout_pipe();
    let mut child = Command::new(binary()).args(args).stdout(stdout).stderr(Stdio::piped()).spawn().unwrap();
    let started = wall_clock();
    let mut errors = child.stderr.take().unwrap();
    let errors = std::thread::spawn(move || {
        let mut text = String::new();
        errors.read_to_string(&mut text).unwrap();
        text
    });
    std::thread::sleep(Duration::from_secs(3));
    let mut text = String::new();
    output.read_to_string(&mut text).unwrap();
    let status = child.wait().unwrap();
    let errors = errors.join().unwrap();
    assert!(status.success(), "{errors}");
    let stamps = text
        .lines()
        .map(|line| serde_json::from_str::<serde_json::Value>(line).unwrap()["ts"].as_f64().unwrap())
        .collect();
    UnreadRun { started, stamps, errors }
}

/// A pipe for a child's standard output (the read end, and the write end to hand to the child), one page
/// deep where the system allows: it fills within the first second even at the 50 lines a second of a
/// single RS232 status frame, which would take 5 s to fill the default 64 KiB.
fn stdout_pipe() -> (std::fs::File, Stdio) {
    use std::os::fd::{FromRawFd, OwnedFd};
    let mut fds = [0; 2];
    // Close-on-exec, or children of tests running at the same time would hold the write end open.
    #[cfg(target_os = "linux")]
    // SAFETY: pipe2 fills in two new descriptors.
    let made = unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) };
    #[cfg(not(target_os = "linux"))]
    // SAFETY: pipe fills in two new descriptors; fcntl on them.
    let made = unsafe {
        let made = libc::pipe(fds.as_mut_ptr());
        for fd in fds {
            libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC);
        }
        made
    };
    assert_eq!(made, 0, "{}", std::io::Error::last_os_error());
    #[cfg(target_os = "linux")]
    // SAFETY: fcntl on a descriptor we own.
    assert!(unsafe { libc::fcntl(fds[0], libc::F_SETPIPE_SZ, 4096) } >= 4096);
    // SAFETY: the two descriptors are new and owned by nothing else.
    let (read, write) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    (read.into(), write.into())
}

/// What a stdout nobody reads must not change: reception and its stamps, the silence checks, the counts.
/// `per_second`: the fewest frames stamped in each second of the blocked stretch; `per_10ms`: the most
/// stamped within 10 ms (a backlog read at once, once stdout took output again, would be hundreds).
fn assert_reception_went_on(run: &UnreadRun, per_second: usize, per_10ms: usize) {
    let UnreadRun { started, stamps, errors } = run;
    // Reception went on at full rate: the bus never looked silent. (A loaded test machine may stall the
    // sender for a real 100 ms or so, which the staleness check rightly reports; never for seconds.)
    for false_alarm in ["silent", "nothing received", "of silence"] {
        assert!(!errors.contains(false_alarm), "{false_alarm:?} in:\n{errors}");
    }
    for gap in errors.lines().filter_map(|line| line.split_once("resumed after a gap of ")) {
        assert!(gap.1.ends_with(" ms"), "a gap of seconds: {}", gap.1);
    }
    // The stamps of what was read are spread over the run as the frames came, blocked seconds included.
    let first = stamps[0];
    assert!((first - started).abs() < 1.0, "first stamp {first}, started {started}");
    for second in 0..3 {
        let within = stamps.iter().filter(|ts| (*ts - first).floor() as i32 == second).count();
        assert!(within >= per_second, "{within} frames stamped in second {second} of the blocked stretch");
    }
    let longest_gap = stamps.windows(2).map(|pair| pair[1] - pair[0]).fold(0.0, f64::max);
    assert!(longest_gap < 1.0, "no frame stamped for {longest_gap:.3} s");
    let bunched = (0..stamps.len())
        .map(|i| stamps[i..].iter().take_while(|ts| **ts - stamps[i] < 0.010).count())
        .max()
        .unwrap_or(0);
    assert!(bunched <= per_10ms, "{bunched} frames stamped within 10 ms");
    // Every frame meant for output was either read here or counted as dropped.
    let shown = number_after(errors, "frames,").expect("the summary's count of frames shown");
    let dropped = match errors.find("output: standard output fell behind") {
        Some(at) => number_after(&errors[at..], "s);").expect("a dropped count"),
        None => 0,
    };
    assert_eq!(stamps.len() as u64 + dropped, shown, "{errors}");
    // A pipe that stayed full for seconds was noticed, once.
    assert_eq!(errors.matches("standard output is not keeping up").count(), 1, "{errors}");
}

#[test]
fn a_stdout_nobody_reads_delays_neither_the_stamps_nor_the_silence_checks() {
    // The simulator stamps its frames as it sends them: this shows the silence checks and the output queue.
    let run = run_with_stdout_unread(&["--sim", "monitor", "--format", "json", "--duration", "4s"]);
    assert_reception_went_on(&run, 100, PER_10MS_SIM);
}

/// The simulator sends each 20 ms cycle's frames together, stamped alike (8 at most; a loaded machine may
/// make it send a few cycles late at once).
const PER_10MS_SIM: usize = 50;

/// Over RS232 frames are stamped when read from the port: a monitor waiting for stdout would read seconds
/// of them at once, stamped within a millisecond, after a silence warning.
#[cfg(target_os = "linux")]
#[test]
#[ignore = "timing group: the spacing of the stamps of frames read under a stalled reader, which a busy machine stretches; .ci/run runs it alone"]
fn a_stdout_nobody_reads_delays_no_stamp_of_frames_read_from_a_serial_port() {
    let robot = FakeRobot::start(healthy());
    let run =
        run_with_stdout_unread(&["--serial", &robot.path, "monitor", "--format", "json", "--duration", "4s"]);
    drop(robot);
    // The robot reports every 20 ms: 50 a second (half of that allows for a loaded machine).
    // A read takes what has arrived, stamped alike: a few frames when the machine is loaded, never seconds'.
    assert_reception_went_on(&run, 25, 15);
}

#[test]
fn monitor_log_on_a_full_disk_counts_every_lost_frame_and_exits_1() {
    let output =
        tracerctl().args(["--sim", "monitor", "--duration", "1s", "--log", "/dev/full"]).output().unwrap();
    let errors = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{errors}");
    // The monitor itself went on: frames were shown.
    assert!(stdout(&output).lines().count() > 100, "{errors}");
    assert_eq!(
        errors.matches("warning: the recording /dev/full is losing frames: No space left on device").count(),
        1,
        "{errors}"
    );
    let total = number_after(&errors, "total:").expect("a total line");
    let lost = number_after(&errors, "the recording /dev/full lost").expect("the loss at exit");
    assert_eq!(lost, total, "every frame was lost, and counted: {errors}");
    assert!(
        errors.contains(&format!("lost {lost} frames (No space left on device (os error 28))")),
        "{errors}"
    );
}

#[test]
fn a_closed_stdout_is_a_quiet_end_but_not_for_a_recording_that_lost_frames() {
    let mut child = Command::new(binary())
        .args(["--sim", "monitor", "--log", "/dev/full"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 1];
    child.stdout.as_mut().unwrap().read_exact(&mut first).unwrap();
    drop(child.stdout.take()); // `| head -c1`
    let output = super::monitor::wait_with_timeout(child, Duration::from_secs(10));
    let errors = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{errors}");
    assert!(errors.contains("tracerctl: the recording /dev/full lost"), "{errors}");
}

#[test]
fn dashboard_record_on_a_full_disk_shows_the_loss_and_exits_1() {
    let command =
        format!("{} --sim dashboard --record /dev/full; echo EXIT=$?; sleep 30", binary().display());
    let session = Session::start(&format!("tracerctl-full-{}", std::process::id()), &command);
    let (shown, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("RECORDING LOST"));
    assert!(shown, "{screen}");
    assert!(screen.contains("No space left on device"), "{screen}");
    session.keys(&["q"]);
    let (ended, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("EXIT="));
    assert!(ended, "{screen}");
    assert!(screen.contains("EXIT=1"), "{screen}");
    let joined = screen.replace('\n', "");
    assert!(joined.contains("tracerctl: the recording /dev/full lost"), "{screen}");
    assert!(joined.contains("frames (No space left on device (os error 28))"), "{screen}");
}

#[test]
fn replay_reports_rejected_lines_as_decode_does() {
    let log = data("replay/mixed.log");
    let output =
        tracerctl().args(["--replay", log.to_str().unwrap(), "--speed", "0", "monitor"]).output().unwrap();
    let errors = stderr(&output);
    assert_eq!(output.status.code(), Some(0), "{errors}");
    assert_eq!(stdout(&output).lines().count(), 7);
    let path = log.display().to_string();
    let decoded = tracerctl().args(["decode", &path]).output().unwrap();
    // The same lines, file:line and reasons as decode's.
    let prefix = format!("tracerctl: {path}:");
    let rejected = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|line| line.strip_prefix(&prefix).is_some_and(|rest| rest.starts_with(char::is_numeric)))
            .map(str::to_string)
            .collect()
    };
    let from_replay = rejected(&errors);
    assert_eq!(from_replay.len(), 10, "{errors}");
    assert_eq!(from_replay, rejected(&stderr(&decoded)));
    assert_eq!(from_replay[1], format!("tracerctl: {path}:6: column 1: not a candump line"));
    let totals = errors.lines().find(|line| line.contains("replayed")).expect("a totals line");
    assert!(
        totals.starts_with(&format!(
            "tracerctl: {path}: replayed 7 frames from 18 lines; rejected 10: 1 x unterminated timestamp"
        )),
        "{totals}"
    );
    assert!(totals.contains(&format!("3 x not a candump line (first at {path}:6)")), "{totals}");
}

#[test]
fn a_megabyte_of_garbage_replays_as_a_data_error_with_the_first_lines_shown() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("garbage.log");
    let line = "RX 0x211 00 00 01 03 00 00 00 B1 some adapter's own format\n";
    let lines = 1_000_000 / line.len();
    std::fs::write(&log, line.repeat(lines)).unwrap();
    let path = log.display().to_string();
    let output = tracerctl().args(["--replay", &path, "--speed", "0", "monitor"]).output().unwrap();
    let errors = stderr(&output);
    assert_eq!(output.status.code(), Some(3), "{errors}");
    assert_eq!(errors.matches(": column 1: not a candump line").count(), 10, "{errors}");
    assert!(errors.contains(&format!("tracerctl: {path}:1: column 1: not a candump line")), "{errors}");
    assert!(
        errors.contains("further rejected input is only counted (see the totals at the end)"),
        "{errors}"
    );
    assert!(
        errors.contains(&format!(
            "replayed 0 frames from {lines} lines; rejected {lines}: {lines} x not a candump line (first at {path}:1)"
        )),
        "{errors}"
    );
    assert!(
        errors.contains(&format!(
            "tracerctl: nothing to replay: {path} has no candump frames ({lines} lines rejected)"
        )),
        "{errors}"
    );
}

#[test]
fn dashboard_replay_of_garbage_says_so_after_the_screen_and_exits_3() {
    let log = data("replay/garbage.log");
    let command = format!(
        "{} --replay {} --speed 0 dashboard; echo EXIT=$?; sleep 30",
        binary().display(),
        log.display()
    );
    let session = Session::start(&format!("tracerctl-garbage-{}", std::process::id()), &command);
    let (up, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("WATCH ONLY"));
    assert!(up, "{screen}");
    session.keys(&["q"]);
    let (ended, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("EXIT="));
    assert!(ended, "{screen}");
    assert!(screen.contains("EXIT=3"), "{screen}");
    let joined = screen.replace('\n', "");
    assert!(joined.contains("garbage.log:1: column 1: not a candump line"), "{screen}");
    assert!(joined.contains("replayed 0 frames from 40 lines; rejected 40"), "{screen}");
    assert!(joined.contains("nothing to replay"), "{screen}");
}

#[test]
fn replay_reads_what_decode_reads_and_refuses_what_it_refuses() {
    let dir = tempfile::tempdir().unwrap();
    // A gzipped candump log (named .log: the magic bytes decide) and a Vector ASC log replay their frames.
    let plain = std::fs::read(data("replay/mixed.log")).unwrap();
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    std::io::Write::write_all(&mut encoder, &plain).unwrap();
    let gz = dir.path().join("mixed.log");
    std::fs::write(&gz, encoder.finish().unwrap()).unwrap();
    for log in [gz, data("formats/vector.asc")] {
        let output = tracerctl()
            .args(["--replay", log.to_str().unwrap(), "--speed", "0", "monitor", "--format", "json"])
            .output()
            .unwrap();
        let decoded = tracerctl().args(["decode", "-f", "json", log.to_str().unwrap()]).output().unwrap();
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
        let frames = stdout(&output).lines().count();
        assert!(frames > 0, "{}", log.display());
        assert_eq!(frames, stdout(&decoded).lines().count(), "{}", log.display());
    }
    // A BLF log is refused in one line, exit 3, as decode does.
    let blf = dir.path().join("trace.blf");
    std::fs::write(&blf, b"LOGG\x90\x00\x00\x00rest of a binary logging file").unwrap();
    let output = tracerctl().args(["--replay", blf.to_str().unwrap(), "monitor"]).output().unwrap();
    assert_eq!(output.status.code(), Some(3));
    let errors = stderr(&output);
    assert_eq!(errors.lines().count(), 1, "{errors}");
    assert!(errors.contains("Vector BLF"), "{errors}");
}
