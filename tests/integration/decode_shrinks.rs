//! A file cut short while `decode` reads it (issue 28): every reader (-j1's, the ranges of -jN mapped or
//! read, a compressed file's, an RS232 capture's) says that it shrank, counts only the whole lines that
//! were in it, and exits 1. Before, -j1 and the others ended at the new end with exit 0 (the cut line's start
//! decoded as a line), while -j2 could count a line of the zeros mapped in after SIGBUS, then exit 1.
//!
//! The cut is made while decode is blocked writing its output: the test does not read the pipe until it is
//! full, so decode has read a few hundred kilobytes at most of a 12 MB file when it is cut at 6 MB.

use std::io::{Read, Write};
use std::os::fd::AsRawFd;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::util::stderr;

/// Lines of 46 bytes, each its own stamp.
fn line(index: usize) -> String {
    format!(
        "({:010}.{:06}) can0 211#00000103000000{:02X}\n",
        1_700_000_000 + index / 1000,
        index % 1000,
        index % 256
    )
}

const LINE_BYTES: usize = 46;

/// Runs `tracerctl decode ARGS PATH` (with `env`), cuts `path` to `cut` bytes once its output pipe is full,
/// and returns (exit status, stdout, stderr).
fn decode_while_cut(
    args: &[&str],
    env: Option<(&str, &str)>,
    path: &Path,
    cut: u64,
) -> (Option<i32>, String, String) {
    let mut command = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"));
    command.arg("decode").args(args).arg(path).stdout(Stdio::piped()).stderr(Stdio::piped());
    if let Some((name, value)) = env {
        command.env(name, value);
    }
    let mut child = command.spawn().unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let mut waiting = 0;
    loop {
        let mut queued: libc::c_int = 0;
        // SAFETY: FIONREAD writes one int through a valid pointer, on a pipe we own.
        unsafe { libc::ioctl(stdout.as_raw_fd(), libc::FIONREAD, &mut queued) };
        let wchan = std::fs::read_to_string(format!("/proc/{}/wchan", child.id())).unwrap_or_default();
        if queued > 32768 && wchan.contains("pipe_write") {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "decode ended before its output filled the pipe");
        waiting += 1;
        assert!(waiting < 6000, "the pipe never filled");
        std::thread::sleep(Duration::from_millis(10));
    }
    std::fs::OpenOptions::new().write(true).open(path).unwrap().set_len(cut).unwrap();
    let mut out = Vec::new();
    stdout.read_to_end(&mut out).unwrap();
    let output = crate::monitor::wait_with_timeout(child, Duration::from_secs(60));
    (output.status.code(), String::from_utf8_lossy(&out).into_owned(), stderr(&output))
}

#[test]
fn a_log_cut_short_while_decoded_says_so_and_counts_its_whole_lines_in_every_mode() {
    let dir = tempfile::tempdir().unwrap();
    let lines = 250_000;
    let log: String = (0..lines).map(line).collect();
    assert_eq!(log.len(), lines * LINE_BYTES);
    let original = log.as_bytes();
    // Mid-line: the cut line's start is not a line.
    let cut = 125_000 * LINE_BYTES + 20;
    type Env<'a> = Option<(&'a str, &'a str)>;
    let modes: [(&[&str], Env); 4] = [
        (&["-j1"], None),
        (&["-j2"], None),
        (&["-j3"], Some(("TRACERCTL_CHUNK_BYTES", "70000"))),
        (&["-j2", "-f", "json"], None),
    ];
    for (args, env) in modes {
        let path = dir.path().join("cut.log");
        std::fs::write(&path, original).unwrap();
        let (status, out, errors) = decode_while_cut(args, env, &path, cut as u64);
        let context = format!("{args:?} {env:?}: {errors}");
        assert_eq!(status, Some(1), "{context}");
        let expected = format!("cut.log: it shrank while being read ({} bytes, now {cut})", original.len());
        assert!(errors.contains(&expected), "{context}");
        assert_eq!(out.lines().count(), 125_000, "{context}: the whole lines before the cut, each once");
        assert!(!errors.contains("too long"), "{context}");
        let last = out.lines().last().unwrap_or_default();
        assert!(last.contains("1700000124.000999"), "{context}: the last whole line: {last}");
    }
}

#[test]
fn a_compressed_log_and_an_rs232_capture_cut_short_say_so_too() {
    let dir = tempfile::tempdir().unwrap();
    let log: String = (0..250_000).map(line).collect();
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(log.as_bytes()).unwrap();
    let gz = encoder.finish().unwrap();
    for threads in ["-j1", "-j2"] {
        let path = dir.path().join("cut.log.gz");
        std::fs::write(&path, &gz).unwrap();
        let cut = gz.len() as u64 / 2;
        let (status, out, errors) = decode_while_cut(&[threads], None, &path, cut);
        assert_eq!(status, Some(1), "{threads}: {errors}");
        let expected = format!("cut.log.gz: it shrank while being read ({} bytes, now {cut})", gz.len());
        assert!(errors.contains(&expected), "{threads}: {errors}");
        let decoded = out.lines().count();
        assert!(decoded > 0 && decoded < 250_000, "{threads}: {decoded} lines");
    }
    const FRAME: [u8; 13] = [0x5A, 0xA5, 0x0A, 0x55, 0x01, 0x02, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x6B];
    let capture: Vec<u8> = FRAME.iter().cycle().take(13 * 200_000).copied().collect();
    let path = dir.path().join("cut.cap");
    std::fs::write(&path, &capture).unwrap();
    // Mid-frame.
    let cut = 13 * 100_000 + 5;
    let (status, out, errors) = decode_while_cut(&["--serial"], None, &path, cut);
    assert_eq!(status, Some(1), "{errors}");
    let expected = format!("cut.cap: it shrank while being read ({} bytes, now {cut})", capture.len());
    assert!(errors.contains(&expected), "{errors}");
    assert_eq!(out.lines().count(), 100_000, "the whole frames before the cut");
}
