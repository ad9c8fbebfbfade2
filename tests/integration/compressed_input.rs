//! Compressed logs are inflated on their own thread (issue 14): what `decode` writes for a `.zst` or a
//! `.gz` log is what it writes for the plain file, damage is reported as before, and a decoder that stops
//! early does not wait for the thread.

use std::io::{Read, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::monitor::wait_with_timeout;
use crate::util::{stderr, tracerctl};

/// A generated TRACER session of `lines` lines: status frames whose count byte runs (and skips now and
/// then), motion feedback, a mode command, and (with `bad_lines`) one line in 1000 no parser reads.
fn session(lines: usize, bad_lines: bool) -> Vec<u8> {
    let mut log = Vec::with_capacity(lines * 48);
    for i in 0..lines {
        let micros = 1_700_000_000_000_000u64 + i as u64 * 5_000;
        let (seconds, fraction) = (micros / 1_000_000, micros % 1_000_000);
        let line = match i % 5 {
            0 => {
                format!("({seconds}.{fraction:06}) can0 211#00000103000000{:02X}\n", (i / 5 + i / 997) % 256)
            }
            1 => {
                format!("({seconds}.{fraction:06}) can0 221#{:04X}{:04X}00000000\n", i % 3000, (i * 7) % 900)
            }
            2 if bad_lines && i % 1000 == 2 => "not a candump line\n".to_string(),
            2 => format!("({seconds}.{fraction:06}) can0 421#01\n"),
            3 => format!("({seconds}.{fraction:06}) can1 18FF0001#0102\n"),
            _ => format!("({seconds}.{fraction:06}) can0 231#00{:02X}000000000000\n", i % 200),
        };
        log.extend_from_slice(line.as_bytes());
    }
    log
}

fn gzip(data: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(data).unwrap();
    encoder.finish().unwrap()
}

fn zstd(data: &[u8]) -> Vec<u8> {
    zstd::encode_all(data, 1).unwrap()
}

/// `decode ARGS PATH`: (exit status, stdout, stderr).
fn decode(args: &[&str], path: &Path) -> (i32, Vec<u8>, String) {
    let output = tracerctl().arg("decode").args(args).arg(path).output().unwrap();
    (output.status.code().unwrap_or(-1), output.stdout.clone(), stderr(&output))
}

#[test]
fn zst_and_gz_logs_decode_exactly_like_the_plain_file_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let plain = session(60_000, true); // about 2.5 MB: ten blocks of the decompression thread
    let files = [("plain.log", plain.clone()), ("log.zst", zstd(&plain)), ("log.gz", gzip(&plain))];
    for (name, bytes) in &files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    for args in [&[][..], &["-f", "json"], &["-f", "csv"], &["--summary"], &["--summary", "-f", "json"]] {
        let plain_path = dir.path().join("plain.log");
        let (code, expected, plain_errors) = decode(args, &plain_path);
        assert_eq!(code, 0, "{args:?}: {plain_errors}");
        assert!(expected.len() > 1000, "{args:?}: the plain file decodes to something");
        // The bad lines are reported with the same line numbers.
        assert!(plain_errors.contains("plain.log:1003: column 6: missing '#'"), "{args:?}: {plain_errors}");
        for (name, _) in &files[1..] {
            let path = dir.path().join(name);
            let (code, output, errors) = decode(args, &path);
            assert_eq!(code, 0, "{name} {args:?}: {errors}");
            // The summary names the file where it saw the first bad line.
            let as_plain =
                |text: &str| text.replace(&path.display().to_string(), &plain_path.display().to_string());
            assert_eq!(as_plain(&errors), plain_errors, "{name} {args:?}");
            let output = as_plain(&String::from_utf8(output).unwrap());
            assert!(output.as_bytes() == expected, "{name} {args:?}: output differs from the plain file's");
        }
    }
    // Standard input goes through the same thread.
    let output =
        tracerctl().args(["decode", "--summary", "-"]).write_stdin(files[1].1.clone()).output().unwrap();
    let plain_name = dir.path().join("plain.log").display().to_string();
    let summary = String::from_utf8(output.stdout).unwrap().replace("<stdin>", &plain_name);
    assert!(summary.as_bytes() == decode(&["--summary"], &dir.path().join("plain.log")).1, "{summary}");
}

#[test]
fn a_truncated_zst_log_reports_the_damage_after_the_lines_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let plain = session(60_000, false);
    let whole = zstd(&plain);
    let path = dir.path().join("cut.log.zst");
    std::fs::write(&path, &whole[..whole.len() / 2]).unwrap();
    let (code, output, errors) = decode(&[], &path);
    assert_eq!(code, 3, "{errors}");
    let said = format!(
        "tracerctl: {}: the zstd data ends early, at byte {} (the end of the file), inside a frame: ",
        path.display(),
        whole.len() / 2
    );
    assert!(errors.trim_end().starts_with(&said) && errors.lines().count() == 1, "{errors}");
    let plain_path = dir.path().join("plain.log");
    std::fs::write(&plain_path, &plain).unwrap();
    let (_, expected, _) = decode(&[], &plain_path);
    assert!(!output.is_empty() && expected.starts_with(&output), "what was written is the start of the log");
}

#[test]
fn a_corrupt_gz_log_reports_the_damage_naming_the_compression() {
    let dir = tempfile::tempdir().unwrap();
    let mut bytes = gzip(&session(60_000, false));
    let middle = bytes.len() / 2;
    bytes[middle..middle + 64].fill(0xA5);
    let path = dir.path().join("bad.log.gz");
    std::fs::write(&path, &bytes).unwrap();
    let (code, _, errors) = decode(&["--summary"], &path);
    assert_eq!(code, 3, "{errors}");
    let prefix = format!("tracerctl: {}: the gzip data is corrupt, found at byte ", path.display());
    // Garbage inflated before the checksum failed is rejected line by line first.
    assert!(errors.lines().last().is_some_and(|last| last.starts_with(&prefix)), "{errors}");
}

#[test]
fn a_closed_standard_output_ends_decode_of_a_large_zst_log_promptly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.log.zst");
    std::fs::write(&path, zstd(&session(400_000, false))).unwrap();
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["decode", "--no-progress"])
        .arg(&path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 4096];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap(); // then the pipe is closed
                                                                  // Ends within 30 s of its output being closed.
    let output = wait_with_timeout(child, Duration::from_secs(30));
    let errors = stderr(&output);
    assert_eq!((output.status.code(), errors.as_str()), (Some(0), ""), "a closed output is a quiet success");
}

#[test]
fn ctrl_c_ends_a_quiet_compressed_stream_on_standard_input() {
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
        .args(["decode", "--no-progress", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // One whole zstd frame, then the pipe stays open and quiet, as from a live `candump | zstd`.
    let mut stdin = child.stdin.take().unwrap();
    stdin.write_all(&zstd(&session(1000, false))).unwrap();
    stdin.flush().unwrap();
    let mut lines = std::io::BufRead::lines(std::io::BufReader::new(child.stdout.take().unwrap()));
    for _ in 0..1000 {
        lines.next().unwrap().unwrap();
    }
    // Every line is out, so decode waits for more: the decompression thread is blocked on the pipe.
    let killed = Command::new("kill").arg("-INT").arg(child.id().to_string()).status().unwrap();
    assert!(killed.success());
    // Ends within 30 s of Ctrl-C, standard input still open.
    let output = wait_with_timeout(child, Duration::from_secs(30));
    drop(stdin);
    let errors = stderr(&output);
    assert_eq!(output.status.code(), Some(130), "{errors}");
    assert!(errors.contains("SIGINT: decoded 1000 frames from 1000 lines"), "{errors}");
}
