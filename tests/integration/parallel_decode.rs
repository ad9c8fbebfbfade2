//! `decode -j N`: the parallel path writes exactly what one thread writes (stdout, stderr, exit status, and
//! the `--plot` SVG) on every fixture and on logs whose chunk boundaries are forced everywhere
//! (`TRACERCTL_CHUNK_BYTES`), in every mode: text, JSON, CSV, `--summary` (text and JSON), `--plot`,
//! `--delta-stamps`, `--strict`.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::util::{data, stderr, stdout, tracerctl};

/// Runs `decode` with `threads` (and tiny chunks when given) on `path`.
fn decode(path: &Path, threads: u16, chunk_bytes: Option<usize>, extra: &[&str]) -> Output {
    let mut command = tracerctl();
    command.arg("decode").arg(format!("-j{threads}")).args(extra).arg(path);
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    command.output().unwrap()
}

pub(super) fn assert_same(single: &Output, parallel: &Output, what: &str) {
    assert_eq!(stdout(parallel), stdout(single), "stdout of {what}");
    assert_eq!(stderr(parallel), stderr(single), "stderr of {what}");
    assert_eq!(parallel.status.code(), single.status.code(), "exit status of {what}");
}

/// Compares `-j1` with several threads and chunk sizes, in every output format, with and without --strict.
fn assert_parallel_same(path: &Path, chunk_sizes: &[usize]) {
    for extra in [&["-f", "text"][..], &["-f", "json"], &["-f", "csv"], &["-f", "json", "--strict"]] {
        let single = decode(path, 1, None, extra);
        for &bytes in chunk_sizes {
            for threads in [2, 3] {
                let parallel = decode(path, threads, Some(bytes), extra);
                let what = format!("{} {extra:?} -j{threads} TRACERCTL_CHUNK_BYTES={bytes}", path.display());
                assert_same(&single, &parallel, &what);
            }
        }
        let default = decode(path, 2, None, extra);
        assert_same(&single, &default, &format!("{} {extra:?} -j2", path.display()));
    }
}

/// The modes whose events are replayed in order by the main thread (see parallel.rs).
const EVENT_MODES: &[&[&str]] = &[
    &["--summary"],
    &["--summary", "-f", "json"],
    &["--summary", "--strict"],
    &["--summary", "-f", "json", "--id", "0x211"],
    &["--delta-stamps"],
    &["--delta-stamps", "-f", "json", "--strict"],
    &["--delta-stamps", "--summary", "-f", "json"],
];

/// [`assert_parallel_same`] for the summary, `-t d` sums and the plot (whose SVG is compared too).
fn assert_events_same(path: &Path, chunk_sizes: &[usize]) {
    for extra in EVENT_MODES {
        let single = decode(path, 1, None, extra);
        for &bytes in chunk_sizes {
            let parallel = decode(path, 2, Some(bytes), extra);
            let what = format!("{} {extra:?} -j2 TRACERCTL_CHUNK_BYTES={bytes}", path.display());
            assert_same(&single, &parallel, &what);
        }
    }
    // The SVG's path is in the messages: both runs write the same one, read after each.
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("plot.svg");
    // Beside the lines the workers write, beside the summary, and with the -t d lines this thread writes.
    for mode in [&[][..], &["--summary"], &["--delta-stamps"]] {
        let plot = [&["--plot", svg.to_str().unwrap()][..], mode].concat();
        let _ = std::fs::remove_file(&svg);
        let single = decode(path, 1, None, &plot);
        let single_svg = std::fs::read(&svg).ok();
        for &bytes in chunk_sizes {
            let _ = std::fs::remove_file(&svg);
            let parallel = decode(path, 3, Some(bytes), &plot);
            let what = format!("{} {plot:?} -j3 TRACERCTL_CHUNK_BYTES={bytes}", path.display());
            assert_same(&single, &parallel, &what);
            assert_eq!(std::fs::read(&svg).ok(), single_svg, "the SVG of {what}");
        }
    }
}

fn files_under(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files_under(&path, found);
        } else {
            found.push(path);
        }
    }
}

#[test]
fn every_fixture_decodes_the_same_with_threads() {
    let mut files = Vec::new();
    files_under(&data(""), &mut files);
    files.sort();
    assert!(files.len() > 40, "fixtures found: {}", files.len());
    for path in files {
        assert_parallel_same(&path, &[1, 29, 200]);
        assert_events_same(&path, &[1, 200]);
    }
}

/// Every awkward line kind, with chunk boundaries falling before, inside and after each: CRLF endings,
/// bad lines, an error frame's continuation text, a count-byte wrap of 0x211, DROPCOUNT, a Pengutronix
/// header, over-long lines (one a log line padded with spaces, after an error frame), blank lines, and a
/// last line without a newline.
pub(super) fn awkward_log() -> String {
    let mut log = String::new();
    for count in 250..=262u32 {
        let count = count % 256;
        log.push_str(&format!("(1700000000.{count:06}) can0 211#00000103000000{count:02X}\n"));
        match count % 6 {
            0 => log.push_str("(1700000000.500000) can0 221#0096000000000000\r\n"),
            1 => log.push_str("this line is not candump\n\n   \n"),
            2 => log.push_str(
                " (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n\
                 \tcontroller-problem{}\n\tbus-off\n",
            ),
            3 => {
                log.push_str("DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 3)\n# comment\n")
            }
            4 => log.push_str(
                "interface = can1, family = 29, type = 3, proto = 1\n<0x211> [8] 00 00 01 03 00 00 00 b1 \n",
            ),
            _ => log.push_str("(1700000000.1) can0 211#ZZ\r\n211#00000103000000B1\n\tstray text\n"),
        }
    }
    log.push_str(&"x".repeat(70_000));
    log.push('\n');
    // A log line past the line limit (spaces after its stamp) right after an error frame: rejected whole as
    // too long, never parsed, so the TAB line after it is still the error frame's text.
    log.push_str(" (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n");
    log.push_str(&format!("(1700000000.777777){}can0 211#00000103000000B1\n", " ".repeat(70_000)));
    log.push_str("\tbus-off\n");
    log.push_str("(1700000000.999999) can0 311#0000000A00000014");
    log
}

#[test]
fn chunk_boundaries_anywhere_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("awkward.log");
    std::fs::write(&path, awkward_log()).unwrap();
    let sizes: Vec<usize> = (1..=200).step_by(7).chain([64 * 1024, 70_001]).collect();
    assert_parallel_same(&path, &sizes);
    assert_events_same(&path, &sizes);
}

/// A Vector ASC log whose header changes how the lines after it read halfway (`base dec`, then `base hex`
/// again), with the lines every ASC writer leaves: measurement events, statistics, error frames, remote and
/// CAN FD frames, CRLF endings, a bad line and an unknown event.
pub(super) fn asc_log() -> String {
    let mut log = String::from(
        "date Tue Nov 24 10:00:00.000 2026\nbase hex  timestamps absolute\ninternal events logged\n\
         Begin Triggerblock Tue Nov 24 10:00:00.000 2026\n   0.000000 Start of measurement\n",
    );
    for tick in 0..300u32 {
        let at = format!("{:4}.{:06}", tick / 50, (tick % 50) * 20_000);
        match tick {
            100 => log.push_str("base dec  timestamps absolute\n"),
            200 => log.push_str("base hex  timestamps absolute\r\n"),
            _ => {}
        }
        // Identifiers and bytes as the header in force says: hex, or decimal between ticks 100 and 200.
        let decimal = (100..200).contains(&tick);
        let number = |value: u32| if decimal { value.to_string() } else { format!("{value:02X}") };
        let bytes = |data: &[u32]| data.iter().map(|&byte| number(byte)).collect::<Vec<_>>().join(" ");
        let frame =
            |id: u32, data: &[u32]| format!("{at} 1  {}  Rx   d {} {}", number(id), data.len(), bytes(data));
        log.push_str(&frame(0x211, &[0, 0, 1, 3, 0, 0, 0, (tick + 250) % 256]));
        log.push('\n');
        log.push_str(&frame(0x221, &[0, tick % 256, 0, 0, 0, 0, 0, 1]));
        log.push_str("\r\n");
        match tick % 23 {
            0 => log.push_str(&format!("{at} 1  ErrorFrame\n")),
            5 => log.push_str(&format!(
                "{at} 2  {}x  Rx   d 2 01 02\n{at} 1  {}   Tx   r 4\n",
                number(0x18FF_0001),
                number(0x7FF)
            )),
            9 => log.push_str(&format!("{at} 1  211             Rx   d 8 ZZ 00\n")),
            13 => log.push_str(&format!(
                "{at} CANFD   1 Rx        {}  1 0 9 12 {}   0    0   3000 0 0 0 0 0\n",
                number(0x251),
                bytes(&[0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99, 0xAA, 0xBB])
            )),
            17 => {
                log.push_str(&format!("{at} 1  Statistic: D 10 R 0 XD 0 XR 0 E 0 O 0 B 0.10%\n{at} Sync\n"))
            }
            _ => {}
        }
    }
    log.push_str("End TriggerBlock\n");
    log
}

/// A PEAK trc 2.1 trace whose `;$COLUMNS=` header changes the columns halfway (the reserved column left out,
/// then back), with status and error lines, events, remote and FD frames, CRLF endings and a bad line.
pub(super) fn trc_log() -> String {
    let mut log = String::from(
        ";$FILEVERSION=2.1\n;$STARTTIME=46350.4166666667\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n;\n\
         ;   Start time: 24.11.2026 10:00:00.000.0\n",
    );
    let mut number = 0;
    for tick in 0..300u32 {
        let at = format!("{:9}.{:03}", tick * 20, tick % 7);
        let count = (tick + 250) % 256;
        match tick {
            100 => log.push_str(";$COLUMNS=N,O,T,B,I,d,L,D\n"),
            200 => log.push_str(";$COLUMNS=N,O,T,B,I,d,R,L,D\r\n"),
            _ => {}
        }
        let reserved = if (100..200).contains(&tick) { "" } else { "-  " };
        let mut line = |kind: &str, id: &str, rest: &str| {
            number += 1;
            log.push_str(&format!("{number:7} {at} {kind} 1      {id} Rx {reserved}{rest}\n"));
        };
        line("DT", "0211", &format!("8    00 00 01 03 00 00 00 {count:02X}"));
        line("DT", "0221", &format!("8    00 {:02X} 00 00 00 00 00 01\r", tick % 256));
        match tick % 19 {
            0 => line("ER", "   -", "5    00 00 08 01 00"),
            4 => line("ST", "   -", "4    00 00 00 08"),
            8 => line("RR", "0123", "4"),
            11 => line("FB", "0251", "9    00 11 22 33 44 55 66 77 88 99 AA BB"),
            14 => line("DT", "0211", "8    00 ZZ"),
            16 => log.push_str(&format!("{:7} {at} EV              User event\n", number + 1)),
            _ => {}
        }
    }
    log
}

#[test]
fn asc_and_trc_logs_decode_the_same_with_threads() {
    let dir = tempfile::tempdir().unwrap();
    let files = [
        ("session.asc", asc_log(), "decoded 639 frames from 700 lines; rejected 26 lines"),
        ("session.trc", trc_log(), "decoded 632 frames from 702 lines; rejected 16 lines"),
    ];
    for (name, log, totals) in files {
        let path = dir.path().join(name);
        std::fs::write(&path, &log).unwrap();
        let single = decode(&path, 1, None, &["--summary"]);
        let report = stdout(&single);
        // Every frame line reads, those after the changed header too: 0x211's count bytes run on unbroken.
        assert!(report.contains(totals), "{name}: {report}");
        let row = report.lines().find(|line| line.trim_start().starts_with("0x211")).unwrap();
        assert!(row.contains(" 300 ") && row.ends_with("0 in 0 skips"), "{name}: {row}");
        let sizes = [1, 29, 200, 4096, 7777];
        assert_parallel_same(&path, &sizes);
        assert_events_same(&path, &[1, 61, 1000, 8192]);
    }
}

/// A session for the summary and the plot: 0x211 whose count byte wraps 0xFF -> 0x00 and then skips, a
/// 3-second gap, mode and vehicle-state changes, faults coming and going, an E-stop, motion and motor frames,
/// an invalid frame (a V1 0x151 after V1 traffic), bad lines, error frames with their text, CRLF endings.
pub(super) fn session_log() -> String {
    let mut log = String::new();
    let mut at = 1_700_000_000_000_000u64;
    for tick in 0..400u32 {
        at += if tick == 200 { 3_000_000 } else { 20_000 };
        let stamp = format!("({}.{:06})", at / 1_000_000, at % 1_000_000);
        // Count 250 .. 255, 0, 1, ... wraps; tick 300 skips two counts.
        let count = (tick + 250 + u32::from(tick >= 300) * 2) % 256;
        let (mode, state, fault) = (u32::from(tick >= 100), u32::from(tick % 150 > 140) * 2, (tick / 50) % 3);
        log.push_str(&format!("{stamp} can0 211#{state:02X}{mode:02X}0103{fault:02X}0000{count:02X}\n"));
        log.push_str(&format!("{stamp} can0 221#{:04X}0000000000{:02X}\r\n", tick * 3, tick % 256));
        log.push_str(&format!("{stamp} can0 251#{:04X}{:04X}00000000\n", tick * 7, tick));
        match tick % 37 {
            0 => log.push_str(&format!("{stamp} can0 211#ZZ\n")),
            5 => log.push_str(
                " (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n\
                 \tcontroller-problem{}\n\tbus-off\n",
            ),
            9 => log
                .push_str(&format!("{stamp} can1 131#0000000000000000\n{stamp} can1 151#0000000000000000\n")),
            _ => {}
        }
    }
    log
}

#[test]
fn the_summary_and_the_plot_are_one_pass_over_any_chunking() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("session.log");
    let log = session_log();
    std::fs::write(&path, &log).unwrap();
    let single = decode(&path, 1, None, &["--summary"]);
    let report = stdout(&single);
    // The count-byte wrap 0xFF -> 0x00 is no skip, the jump by three is one (2 lost), the gap is 3 s.
    let row = report.lines().find(|line| line.trim_start().starts_with("0x211")).unwrap();
    assert!(row.ends_with("36.4    3.000 s  2 in 1 skips"), "{row}");
    assert!(report.contains("decoded 1233 frames from 1266 lines; rejected 11 lines"), "{report}");
    // Boundaries at every offset of the first kilobytes, then spread over the file.
    let sizes: Vec<usize> = (1..=120).chain((150..log.len()).step_by(997)).collect();
    for &bytes in &sizes {
        let parallel = decode(&path, 2, Some(bytes), &["--summary"]);
        assert_same(&single, &parallel, &format!("--summary TRACERCTL_CHUNK_BYTES={bytes}"));
    }
    assert_events_same(&path, &[1, 13, 64, 333, 4096]);
}

/// `-t d`: every stamp is the sum of all deltas before it, those of rejected lines too; a log line's own
/// small stamp is not a delta.
fn delta_log() -> String {
    let mut log = String::new();
    for n in 0..300u32 {
        let delta = format!("({:03}.{:06})", n % 3, (n * 7919) % 1_000_000);
        log.push_str(&format!(" {delta}  can0  211   [8]  00 00 01 03 00 00 00 {:02X}\n", n % 256));
        match n % 11 {
            0 => log.push_str(&format!(" {delta}  can0  221   [8]  00 ZZ 00 00 00 00 00 01\n")),
            3 => log.push_str("(0.500000) can1 221#01F4000000000001\r\n"),
            6 => log.push_str(
                " (000.000100)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME\n\tbus-off\n",
            ),
            _ => {}
        }
    }
    log
}

#[test]
fn delta_stamps_sum_across_chunks() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("td.txt");
    std::fs::write(&path, delta_log()).unwrap();
    let single = decode(&path, 1, None, &["--delta-stamps"]);
    let last = stdout(&single).lines().last().unwrap().to_string();
    // 300 deltas of n % 3 seconds plus fractions, the 28 rejected lines' included: far past 300 s.
    let secs: f64 = last.split_whitespace().next().unwrap().parse().unwrap();
    assert!(secs > 300.0, "{last}");
    for bytes in [1, 2, 50, 51, 52, 200, 1000, 9999] {
        for threads in [2, 4] {
            let parallel = decode(&path, threads, Some(bytes), &["--delta-stamps"]);
            assert_same(&single, &parallel, &format!("-t d -j{threads} TRACERCTL_CHUNK_BYTES={bytes}"));
        }
    }
    assert_events_same(&path, &[1, 77, 4096]);
}

/// 0x151 is decoded by what the traffic before it says: after a V1-only frame, as V1, so a checksum that does
/// not match makes it invalid (with no traffic seen it would be a V2 system state). Chunks of one line each
/// are decoded from a guess of the traffic before; without the check of that guess some would say V2.
#[test]
fn the_protocol_verdict_crosses_chunk_boundaries() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("v1.log");
    let mut log = String::from("(1700000000.000000) can0 131#0000000000000000\n");
    for n in 1..300 {
        log.push_str(&format!("(1700000000.{n:06}) can0 151#0000000000000000\n"));
    }
    std::fs::write(&path, log).unwrap();
    let single = decode(&path, 1, None, &["-f", "json"]);
    let lines = crate::util::json_lines(&single);
    assert_eq!(lines.len(), 300);
    assert!(lines[1..].iter().all(|line| line["msg"] == "invalid"), "{}", lines[1]);
    for bytes in [1, 45, 46, 47, 100] {
        let parallel = decode(&path, 4, Some(bytes), &["-f", "json"]);
        assert_same(&single, &parallel, &format!("TRACERCTL_CHUNK_BYTES={bytes}"));
    }
}

/// Without `TRACERCTL_CHUNK_BYTES` a plain file is cut into ranges the workers read themselves (a share of
/// what is left each, the first ones small; reads of 128 KiB inside them): a 4 MiB log whose first frame
/// makes every 0x151 after it a V1 frame (so the ranges claimed before that verdict is known are decoded
/// again), with lines over the 64 KiB limit across the first cuts, decodes as one thread decodes it.
#[test]
fn a_large_plain_log_decodes_the_same_over_the_default_ranges() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("large.log");
    let mut log = String::from("(1700000000.000000) can0 131#0000000000000000\n");
    let session = session_log();
    let long = format!("(1700000000.000000) can0 211#{}\n", "0".repeat(70_000));
    let mut tick = 0u64;
    while log.len() < 4 << 20 {
        tick += 1;
        log.push_str(&format!(
            "(1700000001.{:06}) can0 151#00000000000000{:02X}\n",
            tick % 1_000_000,
            tick % 256
        ));
        // Only V1 traffic in the first megabyte: the session's V2 frames would make the verdict mixed, which
        // decodes 0x151 as the unguessed start does, and a range decoded from the wrong guess would not show.
        if tick % 5000 == 0 && tick > 25_000 {
            log.push_str(&session);
        }
        if matches!(tick, 5_000 | 5_600 | 25_000) {
            log.push_str(&long);
        }
    }
    std::fs::write(&path, &log).unwrap();
    let single = decode(&path, 1, None, &["--summary"]);
    let report = stdout(&single);
    assert!(report.contains("line too long"), "{}", stderr(&single));
    assert!(report.contains("0x151"), "{report}");
    for extra in [&["--summary"][..], &["--summary", "-f", "json"], &["-f", "json"], &["-f", "csv"]] {
        let single = decode(&path, 1, None, extra);
        for threads in [2, 3] {
            let parallel = decode(&path, threads, None, extra);
            assert_same(&single, &parallel, &format!("{extra:?} -j{threads}"));
        }
    }
}

/// A compressed file is read through its decompressor and chunked like a plain one; a truncated one writes
/// the same lines before the same error.
#[test]
fn compressed_files_decode_the_same_with_threads() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let log = awkward_log();
    let gz = dir.path().join("awkward.log.gz");
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(log.as_bytes()).unwrap();
    let gzipped = encoder.finish().unwrap();
    std::fs::write(&gz, &gzipped).unwrap();
    let zst = dir.path().join("awkward.log.zst");
    std::fs::write(&zst, zstd::encode_all(log.as_bytes(), 3).unwrap()).unwrap();
    let truncated = dir.path().join("truncated.log.gz");
    std::fs::write(&truncated, &gzipped[..gzipped.len() / 2]).unwrap();
    for path in [&gz, &zst, &truncated] {
        assert_parallel_same(path, &[1, 97, 4096]);
    }
    let cut = decode(&truncated, 2, Some(97), &[]);
    assert_eq!(cut.status.code(), Some(1));
    assert!(stderr(&cut).contains("truncated gzip data"), "{}", stderr(&cut));
}

#[test]
fn strict_stops_at_the_same_line_with_the_same_message() {
    let path = data("decode/bad_line15.log");
    for bytes in [1, 10, 100, 1000] {
        let parallel = decode(&path, 2, Some(bytes), &["--strict"]);
        assert_eq!(parallel.status.code(), Some(3));
        assert!(stderr(&parallel).contains("bad_line15.log:15: "), "{}", stderr(&parallel));
        assert_eq!(stdout(&parallel).lines().count(), 14, "the 14 lines before it are written");
        assert_same(&decode(&path, 1, None, &["--strict"]), &parallel, "--strict");
    }
}

#[test]
fn zero_threads_is_a_usage_error() {
    let output = tracerctl().args(["decode", "-j0"]).arg(data("decode/good14.log")).output().unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
}

/// Standard input (a pipe) is chunked at whatever each read returns (at most the chunk size), and written
/// exactly as one thread writes it, in every mode; compressed input on a pipe too.
#[test]
fn standard_input_decodes_the_same_with_threads() {
    let modes: &[&[&str]] = &[
        &["-f", "text"],
        &["-f", "json"],
        &["-f", "csv", "--strict"],
        EVENT_MODES[0],
        EVENT_MODES[1],
        EVENT_MODES[5],
    ];
    let piped = |input: &[u8], threads: u16, bytes: Option<usize>, extra: &[&str]| {
        let mut command = tracerctl();
        command.arg("decode").arg(format!("-j{threads}")).args(extra).arg("-").write_stdin(input.to_vec());
        if let Some(bytes) = bytes {
            command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
        }
        command.output().unwrap()
    };
    let zst = zstd::encode_all(session_log().as_bytes(), 3).unwrap();
    for input in [awkward_log().into_bytes(), session_log().into_bytes(), delta_log().into_bytes(), zst] {
        for extra in modes {
            let single = piped(&input, 1, None, extra);
            for bytes in [1, 61, 4096, 1 << 20] {
                let parallel = piped(&input, 2, Some(bytes), extra);
                assert_same(&single, &parallel, &format!("stdin {extra:?} TRACERCTL_CHUNK_BYTES={bytes}"));
            }
        }
    }
    let strict = piped(&std::fs::read(data("decode/bad_line15.log")).unwrap(), 3, Some(10), &["--strict"]);
    assert_eq!(strict.status.code(), Some(3));
    assert!(stderr(&strict).contains("<stdin>:15: "), "{}", stderr(&strict));
}

/// `candump | tracerctl decode -j2 -`: each line is written soon after it arrives, while the writer still
/// runs (in `-t d` mode too, where the main thread writes the text).
#[test]
fn a_live_stream_is_written_line_by_line_with_threads() {
    use std::io::{BufRead, Write};
    use std::process::{Command, Stdio};
    use std::time::Duration;
    for (extra, line) in [
        (&["-f", "json"][..], "(1700000000.000000) can0 211#00000103000000B1\n"),
        (&["--delta-stamps"][..], " (000.250000)  can0  211   [8]  00 00 01 03 00 00 00 B1\n"),
    ] {
        let mut child = Command::new(assert_cmd::cargo::cargo_bin("tracerctl"))
            .args(["decode", "-j2", "--no-progress"])
            .args(extra)
            .arg("-")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut stdin = child.stdin.take().unwrap();
        let stdout = child.stdout.take().unwrap();
        let (lines_tx, lines_rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            for line in std::io::BufReader::new(stdout).lines() {
                let _ = lines_tx.send(line.unwrap());
            }
        });
        for n in 1..=3 {
            stdin.write_all(line.as_bytes()).unwrap();
            stdin.flush().unwrap();
            // The pipe stays open: the line must come out before the next is written.
            let out = lines_rx.recv_timeout(Duration::from_secs(20)).expect("a line while the writer runs");
            assert!(out.contains("0x211"), "{out}");
            if extra == ["--delta-stamps"] {
                assert!(out.starts_with(&format!("{:.6}", 0.25 * f64::from(n))), "{out}");
            }
        }
        drop(stdin);
        assert!(child.wait().unwrap().success());
    }
}
