//! Property: `decode -j N` with any chunk size writes what `-j1` writes (stdout, stderr, exit status), on
//! random logs of valid, bad, blank and awkward lines; in every mode, the summary and `-t d` sums included.
// Test diagnostics may print; the closed-stream rule (clippy.toml) is for the tool itself.
#![allow(clippy::disallowed_macros)]

use std::path::Path;
use std::process::Output;

use assert_cmd::Command;
use proptest::prelude::*;

/// Lines whose meaning depends on the lines before them are here on purpose (error-frame text, 0x151 after
/// V1 or V2 traffic, a Pengutronix header before `<0x...>` frames).
const LINES: &[&str] = &[
    "(1700000000.000000) can0 211#00000103000000B1",
    "(1700000000.020000) can0 211#00000103000000FF",
    "(1700000000.040000) can0 211#0000010300000000",
    "(1700000000.060000) can0 221#0096000000000000\r",
    "(1700000000.080000) can0 151#0000000000000000",
    "(1700000000.100000) can0 131#0000000000000000",
    "(1700000000.120000) can0 311#0000000A000000",
    "(1700000000.140000) can0 1234567#00",
    "211#00000103000000B1",
    "211#0011",
    "211#XY",
    "",
    "   ",
    "\r",
    "# a comment",
    "this line is not candump",
    "(1700000000.1) can0 211#ZZ",
    " (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME",
    "\tcontroller-problem{}",
    "\tbus-off",
    "DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 3)",
    "interface = can1, family = 29, type = 3, proto = 1",
    "<0x211> [8] 00 00 01 03 00 00 00 b1 ",
    "  can0  221   [8]  00 00 00 00 00 00 00 01",
    " (000.020000)  can0  211   [8]  00 00 01 03 00 00 00 B2",
    " (001.990000)  can1  221   [8]  00 96 00 00 00 00 00 00",
    " (000.500000)  can0  211   [8]  00 00 ZZ 03 00 00 00 B2",
    "(1700000003.000000) can0 211#00010103010000B3",
    "(1700000001.000000) can0 251#0100020000000000",
    // Ends that the parser finds in the chunk itself (no search for the newline first).
    "(1700000001.020000) can0 211#00000103000000B4 R",
    "(1700000001.040000) can0 221#0011 T\r",
    "(1700000001.060000) can0 221#0011 X",
    "(1700000001.080000) can0 221#0011\r\r",
    "(1700000001.100000) can0 221#",
];

/// Vector ASC lines after a fixed header (which makes the file ASC): `base dec` / `base hex` change how the
/// lines after them read, some lines read only in one base.
const ASC_HEADER: &str = "date Tue Nov 24 10:00:00.000 2026\nbase hex  timestamps absolute\n";
const ASC_LINES: &[&str] = &[
    "   0.020000 1  211             Rx   d 8 00 00 01 03 00 00 00 B1",
    "   0.040000 1  529             Rx   d 8 0 0 1 3 0 0 0 200",
    "   0.050000 1  221             Rx   d 8 00 96 00 00 00 00 00 01\r",
    "   0.060000 2  18FF0001x       Rx   d 2 01 02",
    "   0.070000 1  123             Tx   r 4",
    "base dec  timestamps absolute",
    "base hex  timestamps absolute\r",
    "   0.080000 1  ErrorFrame",
    "   0.090000 CANFD   1 Rx        251  1 0 9 12 00 11 22 33 44 55 66 77 88 99 AA BB   0    0   3000 0 0 0 0 0",
    "   0.100000 Start of measurement",
    "   0.110000 1  Statistic: D 10 R 0 XD 0 XR 0 E 0 O 0 B 0.10%",
    "   0.120000 Sync",
    "   0.130000 1  211             Rx   d 8 ZZ",
    "",
    "// a comment",
    "Begin Triggerblock Tue Nov 24 10:00:00.000 2026",
    "211#00000103000000B1",
];

/// PEAK trc lines after a fixed 2.1 header: `;$COLUMNS=` and `;$FILEVERSION=` lines change the columns of the
/// lines after them; some lines read only with one layout.
const TRC_HEADER: &str = ";$FILEVERSION=2.1\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n";
const TRC_LINES: &[&str] = &[
    "      1        20.500 DT 1      0211 Rx -  8    00 00 01 03 00 00 00 B1",
    "      2        40.000 DT 1      0221 Rx 8    00 96 00 00 00 00 00 00",
    ";$COLUMNS=N,O,T,B,I,d,L,D",
    ";$COLUMNS=N,O,T,B,I,d,R,L,D\r",
    ";$FILEVERSION=1.1",
    "     9)      48937.6  Rx         0211  8  00 00 01 03 00 00 00 B2",
    "      3        45.000 ST 1         - Rx -  4    00 00 00 08",
    "      4        60.000 RR 1      0123 Rx -  4",
    "      5        70.000 BI 1  12345678 Rx -  9    00 11 22 33 44 55 66 77 88 99 AA BB",
    "      6        80.000 ER 1         - Rx -  5    00 00 08 01 00",
    "      7        90.000 DT 1      0211 Rx -  8    00 ZZ",
    "      8       100.000 EV              User event",
    "",
    "; a comment",
];

/// The modes whose events the main thread replays: the summary (text and JSON, filtered) and `-t d`.
const EVENT_MODES: &[&[&str]] = &[
    &["--summary"],
    &["--summary", "-f", "json"],
    &["--summary", "--id", "0x211", "--strict"],
    &["--delta-stamps"],
    &["--delta-stamps", "-f", "json"],
    &["--delta-stamps", "--summary", "-f", "json"],
];

/// The picked lines as a log file (in a directory that lives as long as the returned guard).
fn write_log(picks: &[usize], final_newline: bool) -> (tempfile::TempDir, std::path::PathBuf) {
    write_lines("", LINES, picks, final_newline)
}

/// `header`, then the picked `lines`.
fn write_lines(
    header: &str,
    lines: &[&str],
    picks: &[usize],
    final_newline: bool,
) -> (tempfile::TempDir, std::path::PathBuf) {
    let mut log = header.to_string();
    log.push_str(&picks.iter().map(|&i| lines[i % lines.len()]).collect::<Vec<_>>().join("\n"));
    if final_newline {
        log.push('\n');
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("random.log");
    std::fs::write(&path, &log).unwrap();
    (dir, path)
}

fn decode(path: &Path, threads: u16, chunk_bytes: Option<usize>, extra: &[&str]) -> Output {
    let mut command = Command::cargo_bin("tracerctl").unwrap();
    command.env_remove("NO_COLOR").arg("decode").arg(format!("-j{threads}")).args(extra).arg(path);
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    command.output().unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn any_chunking_writes_what_one_thread_writes(
        picks in prop::collection::vec(0..LINES.len(), 0..120),
        final_newline in any::<bool>(),
        chunk_bytes in 1usize..200,
        threads in 2u16..5,
        format in prop::sample::select(vec!["text", "json", "csv"]),
        strict in any::<bool>(),
    ) {
        let (_dir, path) = write_log(&picks, final_newline);
        let mut extra = vec!["-f", format];
        if strict {
            extra.push("--strict");
        }
        let single = decode(&path, 1, None, &extra);
        let parallel = decode(&path, threads, Some(chunk_bytes), &extra);
        prop_assert_eq!(String::from_utf8_lossy(&parallel.stdout), String::from_utf8_lossy(&single.stdout));
        prop_assert_eq!(String::from_utf8_lossy(&parallel.stderr), String::from_utf8_lossy(&single.stderr));
        prop_assert_eq!(parallel.status.code(), single.status.code());
    }

    #[test]
    fn any_chunking_summarises_what_one_thread_summarises(
        picks in prop::collection::vec(0..LINES.len(), 0..160),
        final_newline in any::<bool>(),
        chunk_bytes in 1usize..300,
        threads in 2u16..5,
        mode in prop::sample::select(EVENT_MODES.to_vec()),
    ) {
        let (_dir, path) = write_log(&picks, final_newline);
        let single = decode(&path, 1, None, mode);
        let parallel = decode(&path, threads, Some(chunk_bytes), mode);
        prop_assert_eq!(String::from_utf8_lossy(&parallel.stdout), String::from_utf8_lossy(&single.stdout));
        prop_assert_eq!(String::from_utf8_lossy(&parallel.stderr), String::from_utf8_lossy(&single.stderr));
        prop_assert_eq!(parallel.status.code(), single.status.code());
    }

    /// ASC and trc files, whose header lines change how the lines after them read.
    #[test]
    fn asc_and_trc_files_decode_the_same_over_any_chunking(
        trc in any::<bool>(),
        picks in prop::collection::vec(0..64usize, 0..160),
        final_newline in any::<bool>(),
        chunk_bytes in 1usize..300,
        threads in 2u16..5,
        mode in prop::sample::select([&[&["-f", "text"][..], &["-f", "json", "--strict"], &["-f", "csv"]], EVENT_MODES].concat()),
    ) {
        let (header, lines) = if trc { (TRC_HEADER, TRC_LINES) } else { (ASC_HEADER, ASC_LINES) };
        let (_dir, path) = write_lines(header, lines, &picks, final_newline);
        let single = decode(&path, 1, None, mode);
        let parallel = decode(&path, threads, Some(chunk_bytes), mode);
        prop_assert_eq!(String::from_utf8_lossy(&parallel.stdout), String::from_utf8_lossy(&single.stdout));
        prop_assert_eq!(String::from_utf8_lossy(&parallel.stderr), String::from_utf8_lossy(&single.stderr));
        prop_assert_eq!(parallel.status.code(), single.status.code());
    }
}
