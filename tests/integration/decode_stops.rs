//! A termination signal ends `decode` promptly whatever it is reading, in every mode: every read loop looks at
//! the stop flag (issue 28). A decompression bomb (a small zstd file that inflates to one endless line)
//! kept `-j2` reading until the line ended: minutes for this one. The line is of `x`, not of zeros: a file
//! of zeros is now refused at once as binary data, not a text log.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::monitor::wait_with_timeout;
use crate::util::stderr;

/// A zstd file that inflates to `frames` x 128 MiB of `x` and no newline: one frame, repeated (a zstd
/// stream may hold many frames), so the file is written in a moment.
fn endless_line_bomb(path: &Path, frames: usize) {
    let mut encoder = zstd::Encoder::new(Vec::new(), 1).unwrap();
    let line = vec![b'x'; 1 << 20];
    for _ in 0..128 {
        encoder.write_all(&line).unwrap();
    }
    let frame = encoder.finish().unwrap();
    let mut file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    for _ in 0..frames {
        file.write_all(&frame).unwrap();
    }
    file.flush().unwrap();
}

/// Whether process `pid` has a handler for `signal` (its `SigCgt` mask in /proc says so).
fn catches(pid: u32, signal: i32) -> bool {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
    let mask = status.lines().find_map(|line| line.strip_prefix("SigCgt:")).map(str::trim);
    mask.and_then(|mask| u64::from_str_radix(mask, 16).ok()).is_some_and(|mask| mask & 1 << (signal - 1) != 0)
}

#[test]
fn a_signal_ends_decode_of_a_decompression_bomb_promptly_in_every_mode() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bomb.log.zst");
    // 1 TiB of one line in a few megabytes: the old -j2 read it to its end (about 12 s per 64 GiB) before
    // it looked at the signal.
    endless_line_bomb(&path, 8192);
    signals_end_decode_of(&path);
}

#[test]
fn a_signal_ends_decode_of_a_sparse_file_promptly_in_every_mode() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sparse.log");
    // 64 KiB of text, then 1 TiB of holes: no disk space, one endless line for the readers of a plain file
    // (the ranges' own).
    let mut file = std::fs::File::create(&path).unwrap();
    file.write_all(&[b'x'; 1 << 16]).unwrap();
    if file.set_len(1 << 40).is_err() {
        eprintln!("skipped: this file system holds no 1 TiB sparse file");
        return;
    }
    signals_end_decode_of(&path);
}

/// SIGINT, SIGTERM and SIGHUP each end `decode --summary PATH` with -j1 and -j2 within seconds, with
/// 128 + the signal.
fn signals_end_decode_of(path: &Path) {
    let signals =
        [(libc::SIGINT, 130, "SIGINT"), (libc::SIGTERM, 143, "SIGTERM"), (libc::SIGHUP, 129, "SIGHUP")];
    for threads in ["1", "2"] {
        for (signal, status, name) in signals {
            let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
                .args(["decode", "--no-progress", "--summary", "-j", threads])
                .arg(path)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap();
            for _ in 0..1000 {
                if catches(child.id(), signal) {
                    break;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            // Reading the endless line by now (a few milliseconds in).
            std::thread::sleep(Duration::from_millis(200));
            assert!(child.try_wait().unwrap().is_none(), "-j{threads}: still reading");
            // SAFETY: kill has no memory preconditions; the child is ours and not yet reaped.
            assert_eq!(unsafe { libc::kill(child.id() as i32, signal) }, 0);
            let output = wait_with_timeout(child, Duration::from_secs(20));
            let errors = stderr(&output);
            assert_eq!(output.status.code(), Some(status), "-j{threads} {name}: {errors}");
            assert!(errors.contains(name), "-j{threads} {name}: {errors}");
        }
    }
}
