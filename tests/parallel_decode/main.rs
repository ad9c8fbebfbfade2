//! `decode -j N`: the parallel path writes exactly what one thread writes (stdout, stderr, exit status, and
//! the `--plot` SVG) on every fixture and on logs whose chunk boundaries are forced everywhere
//! (`TRACERCTL_CHUNK_BYTES`), in every mode: text, JSON, CSV, `--summary` (text and JSON), `--plot`,
//! `--delta-stamps`, `--strict`.
//!
//! The sweeps run decode thousands of times: in forks of this process (the command line through
//! `cli::try_parse_from` and `cli::run`, as src/main.rs runs it), not as processes of the debug binary, whose
//! every start loads 80 MB; standard input, a live pipe and `-j0` still run the real binary. Its own test
//! binary without libtest's harness: a fork is safe only while this process has no other thread.
// Test diagnostics may print; the closed-stream rule (clippy.toml) is for the tool itself.
#![allow(clippy::disallowed_macros)]

mod logs;
#[path = "../integration/util.rs"]
mod util;

use logs::{asc_log, assert_same, awkward_log, session_log, trc_log};

use std::ffi::OsString;
use std::io::{Read, Seek, Write};
use std::os::fd::AsRawFd;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{ExitStatus, Output};

use crate::util::{data, stderr, stdout, tracerctl};

/// Runs `decode` with `threads` (and tiny chunks when given) on `path`.
fn decode(path: &Path, threads: u16, chunk_bytes: Option<usize>, extra: &[&str]) -> Output {
    let mut args: Vec<OsString> = vec!["tracerctl".into(), "decode".into(), format!("-j{threads}").into()];
    args.extend(extra.iter().map(OsString::from));
    args.push(path.into());
    in_a_fork(&args, chunk_bytes)
}

/// Runs the command line as src/main.rs does, in a fork of this process (no exec: no loading of the debug
/// binary), its descriptors 1 and 2 sent to files; what it wrote and its exit status. A fork, not a call
/// here: decode's signal listener is made for one run per process, and a failing run must not take the
/// sweep's own output with it.
fn in_a_fork(args: &[OsString], chunk_bytes: Option<usize>) -> Output {
    let (mut out, mut err) = (tempfile::tempfile().unwrap(), tempfile::tempfile().unwrap());
    let _ = std::io::stdout().flush();
    // SAFETY: this process has one thread (no libtest harness), so the child inherits no lock held by
    // another thread; the child only runs tracerctl's own code and leaves with _exit.
    let pid = unsafe { libc::fork() };
    assert!(pid >= 0, "fork: {}", std::io::Error::last_os_error());
    if pid == 0 {
        match chunk_bytes {
            Some(bytes) => std::env::set_var("TRACERCTL_CHUNK_BYTES", bytes.to_string()),
            None => std::env::remove_var("TRACERCTL_CHUNK_BYTES"),
        }
        // SAFETY: dup2 onto this child's own descriptors 1 and 2 from two open files.
        unsafe {
            libc::dup2(out.as_raw_fd(), 1);
            libc::dup2(err.as_raw_fd(), 2);
        }
        let code = std::panic::catch_unwind(|| match tracerctl::cli::try_parse_from(args) {
            Ok(cli) => tracerctl::cli::run(cli).unwrap_or_else(|error| tracerctl::exit::report(&error)),
            Err(error) => {
                let _ = error.print();
                u8::try_from(error.exit_code()).unwrap_or(1)
            }
        })
        .unwrap_or(101);
        let _ = std::io::stdout().flush();
        // SAFETY: ends the child at once, as the process would end after main; no destructors of the
        // parent's state run twice.
        unsafe { libc::_exit(i32::from(code)) };
    }
    let mut status = 0;
    // SAFETY: waits for the child just forked, with a valid status pointer.
    let waited = unsafe { libc::waitpid(pid, &mut status, 0) };
    assert_eq!(waited, pid, "waitpid: {}", std::io::Error::last_os_error());
    let read = |file: &mut std::fs::File| {
        let mut bytes = Vec::new();
        file.rewind().unwrap();
        file.read_to_end(&mut bytes).unwrap();
        bytes
    };
    Output { status: ExitStatus::from_raw(status), stdout: read(&mut out), stderr: read(&mut err) }
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

/// The modes whose events are replayed in order by the main thread (see src/commands/decode/parallel/mod.rs).
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

fn chunk_boundaries_anywhere_change_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("awkward.log");
    std::fs::write(&path, awkward_log()).unwrap();
    let sizes: Vec<usize> = (1..=200).step_by(7).chain([64 * 1024, 70_001]).collect();
    assert_parallel_same(&path, &sizes);
    assert_events_same(&path, &sizes);
}

fn asc_and_trc_logs_decode_the_same_with_threads() {
    let dir = tempfile::tempdir().unwrap();
    let files = [
        ("session.asc", asc_log(), "decoded 653 frames from 700 lines; rejected 26 lines"),
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
    assert_eq!(cut.status.code(), Some(3));
    assert!(stderr(&cut).contains("the gzip data ends early"), "{}", stderr(&cut));
}

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

fn zero_threads_is_a_usage_error() {
    let output = tracerctl().args(["decode", "-j0"]).arg(data("decode/good14.log")).output().unwrap();
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
}

/// Standard input (a pipe) is chunked at whatever each read returns (at most the chunk size), and written
/// exactly as one thread writes it, in every mode; compressed input on a pipe too.
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

/// Every test of this file, in order.
/// Mapping plain files is only a way of reading them: `--no-mmap` and `TRACERCTL_NO_MMAP` (positioned reads
/// only) write the same bytes as the mapped default, with windows and reads cut everywhere.
fn reading_without_mapping_changes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let awkward = dir.path().join("awkward.log");
    std::fs::write(&awkward, awkward_log()).unwrap();
    let session = dir.path().join("session.log");
    std::fs::write(&session, session_log()).unwrap();
    let mut files = vec![awkward, session];
    files_under(&data("candump"), &mut files);
    for path in &files {
        for extra in [&["-f", "json"][..], &["--summary"], &["--delta-stamps", "--strict"]] {
            for bytes in [None, Some(61), Some(4096)] {
                let mapped = decode(path, 2, bytes, extra);
                let unmapped = decode(path, 2, bytes, &[extra, &["--no-mmap"]].concat());
                let what = format!("{} {extra:?} --no-mmap TRACERCTL_CHUNK_BYTES={bytes:?}", path.display());
                assert_same(&mapped, &unmapped, &what);
                std::env::set_var("TRACERCTL_NO_MMAP", "1");
                let unmapped = decode(path, 2, bytes, extra);
                std::env::remove_var("TRACERCTL_NO_MMAP");
                assert_same(&mapped, &unmapped, &format!("{what} (the environment variable)"));
            }
        }
    }
}

const TESTS: &[(&str, fn())] = &[
    ("reading_without_mapping_changes_nothing", reading_without_mapping_changes_nothing),
    ("every_fixture_decodes_the_same_with_threads", every_fixture_decodes_the_same_with_threads),
    ("chunk_boundaries_anywhere_change_nothing", chunk_boundaries_anywhere_change_nothing),
    ("asc_and_trc_logs_decode_the_same_with_threads", asc_and_trc_logs_decode_the_same_with_threads),
    (
        "the_summary_and_the_plot_are_one_pass_over_any_chunking",
        the_summary_and_the_plot_are_one_pass_over_any_chunking,
    ),
    ("delta_stamps_sum_across_chunks", delta_stamps_sum_across_chunks),
    ("the_protocol_verdict_crosses_chunk_boundaries", the_protocol_verdict_crosses_chunk_boundaries),
    (
        "a_large_plain_log_decodes_the_same_over_the_default_ranges",
        a_large_plain_log_decodes_the_same_over_the_default_ranges,
    ),
    ("compressed_files_decode_the_same_with_threads", compressed_files_decode_the_same_with_threads),
    (
        "strict_stops_at_the_same_line_with_the_same_message",
        strict_stops_at_the_same_line_with_the_same_message,
    ),
    ("zero_threads_is_a_usage_error", zero_threads_is_a_usage_error),
    ("standard_input_decodes_the_same_with_threads", standard_input_decodes_the_same_with_threads),
    (
        "a_live_stream_is_written_line_by_line_with_threads",
        a_live_stream_is_written_line_by_line_with_threads,
    ),
];

/// libtest's interface as far as cargo and nextest use it: `--list`, and a name filter (`--exact` too).
fn main() {
    std::env::remove_var("NO_COLOR");
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|arg| arg == "--list") {
        for (name, _) in TESTS {
            println!("{name}: test");
        }
        return;
    }
    let exact = args.iter().any(|arg| arg == "--exact");
    let mut skip_value = false;
    let filter = args.iter().find(|arg| {
        let value = !arg.starts_with('-') && !skip_value;
        skip_value = matches!(arg.as_str(), "--format" | "--test-threads" | "--skip" | "--color" | "-Z");
        value
    });
    let chosen = |name: &str| {
        filter.is_none_or(|filter| if exact { name == filter } else { name.contains(filter.as_str()) })
    };
    let chosen: Vec<(&str, fn())> = TESTS.iter().copied().filter(|(name, _)| chosen(name)).collect();
    let passed = run_on_two_workers(&chosen);
    println!("\ntest result: ok. {passed} passed; 0 failed");
}

/// Runs the tests on two workers, this process and a fork of it, each taking the next test from a shared
/// queue (a pipe of test numbers, one byte each): a sweep runs one decode at a time, 1.3 cores of two, so
/// two sweeps at once fill the machine (73 s -> 41 s, measured alone). A fork, not a thread: each worker
/// forks its decodes, which is safe only in a process of one thread. Returns the number run, all of them:
/// a failure in either worker fails the whole (exit status 101, the panic printed by its worker).
fn run_on_two_workers(tests: &[(&str, fn())]) -> usize {
    let mut fds = [0; 2];
    // SAFETY: pipe fills the two-element array it is given.
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0, "pipe: {}", std::io::Error::last_os_error());
    let [queue, feeder] = fds;
    let numbers: Vec<u8> = (0..tests.len()).map(|index| u8::try_from(index).unwrap()).collect();
    // SAFETY: writes the whole (small: one byte per test, far below the pipe's buffer) slice from valid memory.
    let wrote = unsafe { libc::write(feeder, numbers.as_ptr().cast(), numbers.len()) };
    assert_eq!(wrote, numbers.len() as isize, "write to the queue: {}", std::io::Error::last_os_error());
    // SAFETY: closes this process's write end, which it no longer uses: the queue ends when it is empty.
    unsafe { libc::close(feeder) };
    let _ = std::io::stdout().flush();
    // SAFETY: this process has one thread (no libtest harness, no test started), so the child inherits no
    // lock held by another thread.
    let pid = unsafe { libc::fork() };
    assert!(pid >= 0, "fork: {}", std::io::Error::last_os_error());
    if pid == 0 {
        // SAFETY: asks the kernel to end this worker if the other one dies first (a failed test there).
        unsafe { libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) };
    }
    loop {
        let mut number = 0u8;
        // SAFETY: reads at most one byte into a valid u8; a read of one byte from a pipe is atomic, so each
        // test number goes to one worker.
        let read = unsafe { libc::read(queue, (&raw mut number).cast(), 1) };
        if read != 1 {
            break;
        }
        let (name, test) = tests[usize::from(number)];
        let started = std::time::Instant::now();
        println!("test {name} ...");
        test();
        println!("test {name} ... ok ({:.1} s)", started.elapsed().as_secs_f64());
    }
    if pid == 0 {
        let _ = std::io::stdout().flush();
        // SAFETY: ends the worker without running this process's exit handlers twice; its tests passed.
        unsafe { libc::_exit(0) };
    }
    let mut status = 0;
    // SAFETY: waits for the worker forked above, with a valid status pointer.
    let waited = unsafe { libc::waitpid(pid, &mut status, 0) };
    assert_eq!(waited, pid, "waitpid: {}", std::io::Error::last_os_error());
    if !(libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0) {
        eprintln!("the second worker failed (wait status {status}): its output above names the test");
        std::process::exit(101);
    }
    tests.len()
}
