//! RS232 captures that start with text (issue 28): every byte is decoded, skipped or rejected, and counted.
//! A terminal program's banner before binary frames, and lines of words before hex text, were lost without
//! a word (the banner's 4 KiB made the capture hex text; its words read as labels, then so did the frames).

use crate::util::{json_lines, stderr, tracerctl};

const FRAME: [u8; 13] = [0x5A, 0xA5, 0x0A, 0x55, 0x01, 0x02, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x6B];
const WORDS: [&str; 5] = [
    "Welcome to minicom",
    "OPTIONS: In translation",
    "Compiled on Jan, at",
    "Port ttyUSB, at speed",
    "Press CTRL-A Z for help on special keys",
];

/// `lines` lines of a terminal program's banner, each ending with `end`.
fn banner(lines: usize, end: &str) -> String {
    (0..lines).map(|line| format!("{}{end}", WORDS[line % WORDS.len()])).collect()
}

fn write(dir: &tempfile::TempDir, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn binary_frames_after_a_text_banner_are_decoded_and_the_banner_counted_as_skipped_bytes() {
    let dir = tempfile::tempdir().unwrap();
    // 4,200 bytes of banner (more than the 4 KiB sample, which reads as text), then 20 raw frames.
    let mut bytes = banner(200, "\r\n").into_bytes();
    bytes.truncate(4198);
    bytes.extend_from_slice(b"\r\n");
    let banner_bytes = bytes.len();
    assert_eq!(banner_bytes, 4200);
    bytes.extend(FRAME.iter().cycle().take(13 * 20));
    let path = write(&dir, "banner.cap", &bytes);

    let output = tracerctl().args(["decode", "-f", "json", "--serial"]).arg(&path).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let objects = json_lines(&output);
    assert_eq!(objects.len(), 20, "{}", stderr(&output));
    assert!(objects.iter().all(|o| o["data"] == "5AA50A550102000A000000006B"));

    let output = tracerctl().args(["decode", "--summary", "--serial"]).arg(&path).output().unwrap();
    let report = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert!(
        report.contains("banner.cap: 4460 bytes, 20 frames, 4200 bytes skipped"),
        "the summary counts every byte of the file: {report}"
    );
    let output =
        tracerctl().args(["decode", "--summary", "-f", "json", "--serial"]).arg(&path).output().unwrap();
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let serial = summary.to_string();
    assert!(serial.contains(r#""bytes":4460"#) && serial.contains(r#""skipped_bytes":4200"#), "{serial}");
}

#[test]
fn hex_text_after_400_lines_of_words_is_decoded_and_the_lines_counted() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = banner(400, "\n");
    for _ in 0..20 {
        text.push_str("5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n");
    }
    let path = write(&dir, "words_then_hex.txt", text.as_bytes());
    let output = tracerctl().args(["decode", "-f", "json", "--serial"]).arg(&path).output().unwrap();
    assert_eq!((output.status.code(), json_lines(&output).len()), (Some(0), 20), "{}", stderr(&output));

    let output = tracerctl().args(["decode", "--summary", "--serial"]).arg(&path).output().unwrap();
    let report = String::from_utf8_lossy(&output.stdout);
    assert!(report.contains("decoded 20 frames; skipped 400 lines: 400 comment;"), "{report}");
}

#[test]
fn a_capture_of_text_alone_counts_its_lines() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(&dir, "words.txt", banner(300, "\n").as_bytes());
    let output = tracerctl().args(["decode", "--summary", "--serial"]).arg(&path).output().unwrap();
    let report = String::from_utf8_lossy(&output.stdout);
    // No frames at all is bad input (exit 3, its reason last), but every line is still counted.
    assert_eq!(output.status.code(), Some(3), "{}", stderr(&output));
    assert!(stderr(&output).contains("no TRACER frames in"), "{}", stderr(&output));
    assert!(report.contains("decoded 0 frames; skipped 300 lines: 300 comment;"), "{report}");
}
