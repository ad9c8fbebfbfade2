//! `decode -j N` of several inputs in one run: every file's lines are numbered from its own first line, as
//! one thread numbers them, in the rejected lines, `--summary`'s "first at" and `--strict`'s stop, for every
//! kind of input (plain, gzip, zstd, standard input, Vector ASC, PEAK trc) in every mode.

use std::io::Write;
use std::path::Path;
use std::process::Output;

use crate::parallel_logs::{asc_log, assert_same, awkward_log, session_log, trc_log};
use crate::util::{data, stderr, stdout, tracerctl};

/// Runs `decode -jN EXTRA INPUTS` with `stdin` on standard input (tiny chunks when `chunk_bytes` is given).
fn decode(
    inputs: &[&Path],
    stdin: &[u8],
    threads: u16,
    chunk_bytes: Option<usize>,
    extra: &[&str],
) -> Output {
    let mut command = tracerctl();
    command.arg("decode").arg(format!("-j{threads}")).args(extra).args(inputs).write_stdin(stdin.to_vec());
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    command.output().unwrap()
}

fn gzip(text: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(text).unwrap();
    encoder.finish().unwrap()
}

/// Every mode, `-j1` against two and three threads with the default and with tiny chunks, on inputs of
/// every kind one after the other; `--plot`'s SVG compared too.
#[test]
fn several_inputs_of_every_kind_decode_as_one_thread_decodes_them() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    let plain = write("awkward.log", awkward_log().as_bytes());
    let gz = write("session.log.gz", &gzip(session_log().as_bytes()));
    let zst = write("session.log.zst", &zstd::encode_all(session_log().as_bytes(), 3).unwrap());
    let asc = write("session.asc", asc_log().as_bytes());
    let trc = write("session.trc", trc_log().as_bytes());
    let bad15 = data("decode/bad_line15.log");
    let stdin = std::fs::read(&bad15).unwrap();
    let dash = Path::new("-");
    // A clean first file, so no reason is first seen in the first input and every later place shows.
    let good = data("decode/good14.log");
    let svg = dir.path().join("plot.svg");
    let plot = ["--plot", svg.to_str().unwrap()];
    let modes: &[&[&str]] = &[
        &["-f", "text"],
        &["-f", "json"],
        &["-f", "csv"],
        &["--summary"],
        &["--summary", "-f", "json"],
        &["--strict"],
        &["--delta-stamps", "-f", "json"],
        &plot,
        &[plot[0], plot[1], "--summary"],
    ];
    let orders: [&[&Path]; 2] = [
        &[&good, &plain, &gz, dash, &asc, &zst, &trc, &bad15],
        &[&good, &bad15, &trc, &asc, &zst, dash, &gz, &plain],
    ];
    for inputs in orders {
        let names: Vec<String> = inputs.iter().map(|path| path.display().to_string()).collect();
        for extra in modes {
            let _ = std::fs::remove_file(&svg);
            let single = decode(inputs, &stdin, 1, None, extra);
            let single_svg = std::fs::read(&svg).ok();
            for (threads, bytes) in [(2, None), (3, Some(97)), (2, Some(4096))] {
                let _ = std::fs::remove_file(&svg);
                let parallel = decode(inputs, &stdin, threads, bytes, extra);
                let what = format!("{names:?} {extra:?} -j{threads} TRACERCTL_CHUNK_BYTES={bytes:?}");
                assert_same(&single, &parallel, &what);
                assert_eq!(std::fs::read(&svg).ok(), single_svg, "the SVG of {what}");
            }
        }
    }
}

/// The example of the report: the second file's bad line is its line 15, in the messages, the summary's
/// "first at" and `--strict`'s stop, for a plain file, a compressed one and standard input.
#[test]
fn a_later_file_says_its_own_line_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let good = data("decode/good14.log");
    let bad = data("decode/bad_line15.log");
    let text = std::fs::read(&bad).unwrap();
    let gz = dir.path().join("bad.log.gz");
    std::fs::write(&gz, gzip(&text)).unwrap();
    for (second, stdin, name) in [
        (bad.as_path(), &[][..], bad.display().to_string()),
        (&gz, &[], gz.display().to_string()),
        (Path::new("-"), &text[..], "<stdin>".to_string()),
    ] {
        for threads in [1, 2, 3] {
            for bytes in [None, Some(7)] {
                let inputs = [good.as_path(), second];
                let what = format!("{name} -j{threads} {bytes:?}");
                let plain = decode(&inputs, stdin, threads, bytes, &[]);
                assert_eq!(plain.status.code(), Some(0), "{what}: {}", stderr(&plain));
                assert!(
                    stderr(&plain)
                        .starts_with(&format!("tracerctl: {name}:15: column 1: not a candump line\n")),
                    "{what}: {}",
                    stderr(&plain)
                );
                let summary = decode(&inputs, stdin, threads, bytes, &["--summary"]);
                assert!(
                    stdout(&summary).contains(&format!("(first at {name}:15)")),
                    "{what}: {}",
                    stdout(&summary)
                );
                let strict = decode(&inputs, stdin, threads, bytes, &["--strict"]);
                assert_eq!(strict.status.code(), Some(3), "{what}");
                assert_eq!(
                    stderr(&strict),
                    format!("tracerctl: {name}:15: column 1: not a candump line\n"),
                    "{what}"
                );
                assert_eq!(stdout(&strict).lines().count(), 28, "{what}: both files' good lines are written");
            }
        }
    }
}
