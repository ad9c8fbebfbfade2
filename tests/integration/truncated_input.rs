//! Compressed logs cut short or corrupt (issue 31: the black box's open segment after a crash), and
//! directories of the recorder given to `decode`. Logs are compressed by the real `gzip`, `zstd`, `xz` and
//! `bzip2` tools (the crates when a tool is missing); every whole line before the damage is decoded exactly
//! as in the whole file's output, the message names the byte and the line reached, exit 3, and `-j1`,
//! `-j2` and `--summary` agree.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use crate::util::{stderr, stdout, tracerctl};

/// A TRACER session of `lines` lines starting at line `from` (stamps and values run on across parts).
fn session(from: usize, lines: usize) -> String {
    let mut log = String::new();
    for i in from..from + lines {
        let micros = 1_700_000_000_000_000u64 + i as u64 * 10_000;
        let stamp = format!("({}.{:06})", micros / 1_000_000, micros % 1_000_000);
        let line = match i % 4 {
            0 => format!("{stamp} can0 211#00000103000000{:02X}\n", i % 256),
            1 => format!("{stamp} can0 221#{:04X}{:04X}00000000\n", i % 3000, (i * 7) % 900),
            2 => format!("{stamp} can0 311#{:08X}{:08X}\n", i * 13, i * 17),
            _ => format!("{stamp} can0 231#00{:02X}000000000000\n", i % 200),
        };
        log.push_str(&line);
    }
    log
}

/// `data` compressed by the command-line `tool` (with its defaults: zstd and xz write checksums), or by
/// the crate when the tool is not installed.
fn compress(tool: &str, data: &[u8]) -> Vec<u8> {
    match Command::new(tool).arg("-c").stdin(Stdio::piped()).stdout(Stdio::piped()).spawn() {
        Ok(mut child) => {
            let mut stdin = child.stdin.take().unwrap();
            let data = data.to_vec();
            let feeder = std::thread::spawn(move || stdin.write_all(&data).unwrap());
            let output = child.wait_with_output().unwrap();
            feeder.join().unwrap();
            assert!(output.status.success(), "{tool} failed");
            output.stdout
        }
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => by_crate(tool, data),
        Err(error) => panic!("cannot run {tool}: {error}"),
    }
}

fn by_crate(tool: &str, data: &[u8]) -> Vec<u8> {
    eprintln!("{tool} is not installed: compressed with the crate instead");
    match tool {
        "gzip" => {
            let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        "zstd" => {
            let mut encoder = zstd::stream::write::Encoder::new(Vec::new(), 3).unwrap();
            encoder.include_checksum(true).unwrap();
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        "xz" => {
            let mut encoder = liblzma::write::XzEncoder::new(Vec::new(), 6);
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        "bzip2" => {
            let mut encoder = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::default());
            encoder.write_all(data).unwrap();
            encoder.finish().unwrap()
        }
        _ => unreachable!("{tool}"),
    }
}

/// Several parts, each compressed on its own and written one after the other, as the recorder writes its
/// segments (a zstd frame a second, each ending at a line's end). The parts' ends in the compressed bytes.
fn in_parts(tool: &str, parts: &[String]) -> (Vec<u8>, Vec<usize>) {
    let mut bytes = Vec::new();
    let mut ends = Vec::new();
    for part in parts {
        bytes.extend(compress(tool, part.as_bytes()));
        ends.push(bytes.len());
    }
    (bytes, ends)
}

fn run(args: &[&str], path: &Path, chunk_bytes: Option<usize>) -> Output {
    let mut command = tracerctl();
    command.args(["decode", "--no-progress"]).args(args).arg(path);
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    command.output().unwrap()
}

/// What a run said of a cut: the lines it read (from `lines 1-K read`), after checking the words around.
fn lines_read(errors: &str, name: &Path, cut: usize) -> usize {
    let said = format!(
        "tracerctl: {}: the {{}} data ends early, at byte {cut} (the end of the file), inside a ",
        name.display()
    );
    let (start, rest) = said.split_once("{}").unwrap();
    let line = errors.lines().last().unwrap_or_default();
    assert!(line.starts_with(start) && line.contains(rest), "cut at {cut}: {errors}");
    assert!(
        line.contains(": a recording stopped by a crash or a power cut, or a copy not finished; "),
        "{line}"
    );
    if line.contains("; no whole line before it") {
        0
    } else if line.contains("; line 1 read") {
        1
    } else {
        let after = line.split_once("; lines 1-").unwrap_or_else(|| panic!("{line}")).1;
        after[..after.find(' ').unwrap()].parse().unwrap()
    }
}

/// `output` is the start of `whole` (the whole file's output lines), cut at a line's end: its line count.
fn assert_prefix(output: &Output, whole: &[String], what: &str) -> usize {
    let text = stdout(output);
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() <= whole.len(), "{what}: more lines than the whole file");
    for (number, (line, expected)) in lines.iter().zip(whole).enumerate() {
        assert_eq!(line, expected, "{what}: line {}", number + 1);
    }
    assert!(text.is_empty() || text.ends_with('\n'), "{what}: a line cut in the output");
    assert!(!stderr(output).contains("panicked"), "{what}: {}", stderr(output));
    lines.len()
}

/// One cut of one file through `-j1`, `-j2` and (with `summary`) `--summary`: the same lines, the same
/// message, exit 3 (0 when `clean`: cut where a part ends). Returns the lines decoded.
fn check_cut(
    path: &Path,
    whole: &[String],
    cut: usize,
    clean: bool,
    (chunk_bytes, summary): (Option<usize>, bool),
) -> usize {
    let what = format!("{} cut at {cut}", path.display());
    let single = run(&["-j1"], path, None);
    let lines = assert_prefix(&single, whole, &what);
    let errors = stderr(&single);
    if clean {
        assert_eq!((single.status.code(), errors.as_str()), (Some(0), ""), "{what}");
    } else {
        assert_eq!(single.status.code(), Some(3), "{what}: {errors}");
        assert_eq!(lines_read(&errors, path, cut), lines, "{what}: the lines said are the lines written");
    }
    let parallel = run(&["-j2"], path, chunk_bytes);
    assert_eq!(stdout(&parallel), stdout(&single), "{what} -j2");
    assert_eq!(
        (parallel.status.code(), stderr(&parallel)),
        (single.status.code(), errors.clone()),
        "{what} -j2"
    );
    for threads in if summary { &["-j1", "-j2"][..] } else { &[] } {
        let summary = run(&["--summary", threads], path, chunk_bytes);
        assert_eq!(summary.status.code(), single.status.code(), "{what} --summary {threads}");
        if lines > 0 {
            let decoded = format!("  decoded {lines} frames from {lines} lines\n");
            assert!(stdout(&summary).contains(&decoded), "{what} --summary {threads}: {}", stdout(&summary));
        }
        assert_eq!(stderr(&summary), errors, "{what} --summary {threads}");
    }
    lines
}

fn whole_output(text: &str, dir: &Path) -> Vec<String> {
    let plain = dir.join("plain.log");
    std::fs::write(&plain, text).unwrap();
    let output = run(&["-j1"], &plain, None);
    assert!(output.status.success(), "{}", stderr(&output));
    stdout(&output).lines().map(str::to_string).collect()
}

/// Every offset of a small log compressed by each tool: whatever was decoded is the whole file's first
/// lines, the message names the offset and the lines reached, and no mode panics or differs.
#[test]
fn every_cut_of_a_small_compressed_log_decodes_the_lines_before_it_and_names_the_byte() {
    let dir = tempfile::tempdir().unwrap();
    // Two parts, so that the decompressors have lines to give before most cuts.
    let parts = [session(0, 4), session(4, 4)];
    let whole = whole_output(&parts.concat(), dir.path());
    std::thread::scope(|scope| {
        for tool in ["gzip", "zstd", "xz", "bzip2"] {
            let (dir, parts, whole) = (dir.path(), &parts, &whole);
            scope.spawn(move || {
                let (bytes, ends) = in_parts(tool, parts);
                let full = run(&["-j1"], &write(dir, &format!("whole.{tool}"), &bytes), None);
                assert_eq!(
                    assert_prefix(&full, whole, tool),
                    whole.len(),
                    "{tool}: the two parts read whole"
                );
                // Below 2 bytes (4 for bzip2's printable `BZh9`) no compression can be told.
                let least = if tool == "bzip2" { 4 } else { 2 };
                for cut in least..bytes.len() {
                    let path = write(dir, &format!("cut.{tool}"), &bytes[..cut]);
                    // The summaries at every third cut only: the suite's time.
                    let lines = check_cut(&path, whole, cut, cut == ends[0], (None, cut % 3 == 0));
                    if cut >= ends[0] {
                        assert!(lines >= 4, "{tool} cut at {cut}: the first part's lines are all there");
                    }
                }
            });
        }
    });
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A segment as the recorder writes it: zstd frames of whole lines, one after the other. It reads whole,
/// and cut anywhere gives every line of the frames before the cut (and what the cut frame's complete
/// blocks hold), in every mode, with chunks of the parallel path cut small.
#[test]
fn a_segment_of_many_zstd_frames_reads_whole_and_cut_keeps_every_frame_before_the_cut() {
    let dir = tempfile::tempdir().unwrap();
    let parts: Vec<String> = (0..6).map(|part| session(part * 50, 50)).collect();
    let whole = whole_output(&parts.concat(), dir.path());
    let (bytes, ends) = in_parts("zstd", &parts);
    let full = write(dir.path(), "segment.log.zst", &bytes);
    assert_eq!(check_cut(&full, &whole, bytes.len(), true, (Some(97), true)), 300, "every frame read");
    let mut cuts = vec![1 + 3, bytes.len() - 1];
    for (frame, &end) in ends[..ends.len() - 1].iter().enumerate() {
        let next = ends[frame + 1];
        cuts.extend([end, end + 1, end + 3, end + 6, (end + next) / 2, next - 1]);
    }
    for cut in cuts {
        let path = write(dir.path(), "cut.log.zst", &bytes[..cut]);
        let frames_before = ends.iter().filter(|&&end| end <= cut).count();
        let clean = ends.contains(&cut);
        let lines = check_cut(&path, &whole, cut, clean, (Some(97), true));
        assert!(
            lines >= frames_before * 50,
            "cut at {cut}: {lines} lines, {frames_before} whole frames before"
        );
        assert!(lines <= (frames_before + 1) * 50, "cut at {cut}");
    }
}

/// A wrong checksum is corruption, not a cut: the place it was found and the size, the lines before it,
/// nothing of the part after it; exit 3 in every mode.
#[test]
fn a_corrupt_part_is_said_as_corruption_and_the_parts_after_it_are_not_decoded() {
    let dir = tempfile::tempdir().unwrap();
    let parts = [session(0, 40), session(40, 40)];
    let whole = whole_output(&parts.concat(), dir.path());
    for tool in ["gzip", "zstd", "xz", "bzip2"] {
        let (mut bytes, ends) = in_parts(tool, &parts);
        // The first part's checksum (bzip2's stream CRC ends a few bits before its last byte).
        let flipped = if tool == "bzip2" { ends[0] - 2 } else { ends[0] - 1 };
        bytes[flipped] ^= 0x55;
        let path = write(dir.path(), &format!("bad.{tool}"), &bytes);
        let single = run(&["-j1"], &path, None);
        let lines = assert_prefix(&single, &whole, tool);
        assert!(lines <= 40, "{tool}: nothing of the second part");
        let errors = stderr(&single);
        assert_eq!(single.status.code(), Some(3), "{tool}: {errors}");
        let said = format!("tracerctl: {}: the {tool} data is corrupt, found at byte ", path.display());
        assert!(errors.starts_with(&said) && errors.lines().count() == 1, "{tool}: {errors}");
        let at: usize = errors[said.len()..].split(' ').next().unwrap().parse().unwrap();
        assert!(at > flipped && at <= bytes.len(), "{tool}: found at {at}, flipped {flipped}");
        assert!(errors.contains(&format!(" of {} (", bytes.len())), "{errors}");
        assert!(errors.contains("): a damaged disk or a bad copy; "), "{errors}");
        for args in [&["-j2"][..], &["--summary", "-j2"]] {
            let other = run(args, &path, Some(97));
            assert_eq!((other.status.code(), stderr(&other)), (Some(3), errors.clone()), "{tool} {args:?}");
        }
    }
}

#[test]
fn a_cut_stream_on_standard_input_names_the_end_of_the_input_and_strict_stops_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let parts = [session(0, 30), session(30, 30)];
    let whole = whole_output(&parts.concat(), dir.path());
    let (bytes, ends) = in_parts("zstd", &parts);
    let cut = ends[0] + 10;
    for threads in ["-j1", "-j2"] {
        let output = tracerctl().args(["decode", threads, "-"]).write_stdin(&bytes[..cut]).output().unwrap();
        assert_eq!(assert_prefix(&output, &whole, threads), 30, "{threads}");
        assert_eq!(output.status.code(), Some(3));
        assert_eq!(
            stderr(&output),
            format!(
                "tracerctl: <stdin>: the zstd data ends early, at byte {cut} (the end of the input), inside a \
                 frame: a recording stopped by a crash or a power cut, or a copy not finished; lines 1-30 read\n"
            ),
            "{threads}"
        );
    }
    // --strict stops there too, with the same words.
    let path = write(dir.path(), "cut.log.zst", &bytes[..cut]);
    let strict = run(&["--strict"], &path, None);
    assert_eq!((strict.status.code(), stdout(&strict).lines().count()), (Some(3), 30));
    assert!(stderr(&strict).contains("the zstd data ends early, at byte "), "{}", stderr(&strict));
}

/// A recorder's directory: `DIR/ring/` with segments, one cut by a crash, and an incident.
struct Recorder {
    dir: tempfile::TempDir,
    /// Each segment's text, in time order.
    texts: Vec<String>,
}

impl Recorder {
    const SEGMENTS: [&'static str; 3] =
        ["20261128T134500.000Z.log.zst", "20261128T134600.000Z.log.zst", "20261128T134700.000Z.log.zst"];

    /// Three segments of two frames each; `cut` cuts the second one 10 bytes into its second frame.
    fn new(cut: bool) -> Self {
        let dir = tempfile::tempdir().unwrap();
        let ring = dir.path().join("ring");
        std::fs::create_dir(&ring).unwrap();
        let mut texts = Vec::new();
        // Written out of name order: the names decide.
        for (index, name) in Self::SEGMENTS.iter().enumerate().rev() {
            let parts = [session(index * 40, 20), session(index * 40 + 20, 20)];
            let (mut bytes, ends) = in_parts("zstd", &parts);
            if cut && index == 1 {
                bytes.truncate(ends[0] + 10);
            }
            std::fs::write(ring.join(name), bytes).unwrap();
            texts.insert(0, parts.concat());
        }
        std::fs::write(ring.join(".20261128T134800.000Z.log.zst.tmp"), b"not a segment").unwrap();
        let incident = dir.path().join("incidents/20261128T134612Z-estop");
        std::fs::create_dir_all(&incident).unwrap();
        std::fs::write(incident.join("frames.log"), session(55, 10)).unwrap();
        std::fs::write(incident.join("summary.txt"), "not decoded\n").unwrap();
        Self { dir, texts }
    }

    fn path(&self, under: &str) -> std::path::PathBuf {
        self.dir.path().join(under)
    }
}

#[test]
fn a_ring_decodes_as_its_segments_given_in_name_order() {
    let recorder = Recorder::new(false);
    let ring = recorder.path("ring");
    let segments: Vec<std::path::PathBuf> = Recorder::SEGMENTS.iter().map(|name| ring.join(name)).collect();
    let mut given = tracerctl();
    let expected = given.args(["decode", "-j1"]).args(&segments).output().unwrap();
    assert!(expected.status.success() && stdout(&expected).lines().count() == 120, "{}", stderr(&expected));
    for dir in [recorder.path("ring"), recorder.dir.path().to_path_buf()] {
        for args in [&["-j1"][..], &["-j2"], &["-f", "json"]] {
            let output = run(args, &dir, None);
            let reference = if args == ["-f", "json"] {
                tracerctl().args(["decode", "-f", "json"]).args(&segments).output().unwrap()
            } else {
                expected.clone()
            };
            assert_eq!(
                (output.status.code(), stderr(&output)),
                (Some(0), String::new()),
                "{args:?}: nothing extra"
            );
            assert!(output.stdout == reference.stdout, "{} {args:?}", dir.display());
        }
    }
    // The summary sees the three segments as one run.
    let summary = run(&["--summary"], &ring, None);
    assert!(stdout(&summary).contains("  decoded 120 frames from 120 lines\n"), "{}", stdout(&summary));
}

#[test]
fn a_segment_cut_by_a_crash_is_said_at_the_end_and_the_segments_after_it_are_decoded() {
    let recorder = Recorder::new(true);
    let ring = recorder.path("ring");
    let cut = ring.join(Recorder::SEGMENTS[1]);
    let cut_len = std::fs::metadata(&cut).unwrap().len();
    // The cut segment's first frame (20 lines) is whole; its second is cut 10 bytes in.
    let expected = [recorder.texts[0].clone(), session(40, 20), recorder.texts[2].clone()].concat();
    let dir = tempfile::tempdir().unwrap();
    let whole = whole_output(&expected, dir.path());
    for args in [&["-j1"][..], &["-j2"]] {
        let output = run(args, &ring, Some(97));
        assert_eq!(assert_prefix(&output, &whole, "ring"), 100, "{args:?}: 40 + 20 + 40 lines");
        assert_eq!(output.status.code(), Some(3), "{args:?}");
        assert_eq!(
            stderr(&output),
            format!(
                "tracerctl: {}: the zstd data ends early, at byte {cut_len} (the end of the file), inside a frame: \
                 a recording stopped by a crash or a power cut, or a copy not finished; lines 1-20 read\n",
                cut.display()
            ),
            "{args:?}"
        );
    }
    let summary = run(&["--summary"], &ring, None);
    assert_eq!(summary.status.code(), Some(3));
    assert!(stdout(&summary).contains("  decoded 100 frames from 100 lines\n"), "{}", stdout(&summary));
    // --strict stops at the damaged segment.
    let strict = run(&["--strict"], &ring, None);
    assert_eq!((strict.status.code(), stdout(&strict).lines().count()), (Some(3), 60));
}

#[test]
fn an_incident_directory_decodes_its_frames_log_and_names_it_in_messages() {
    let recorder = Recorder::new(false);
    let incident = recorder.path("incidents/20261128T134612Z-estop");
    let frames = incident.join("frames.log");
    let mut log = session(55, 10);
    log.insert_str(0, "not a candump line\n");
    std::fs::write(&frames, &log).unwrap();
    let output = run(&[], &incident, None);
    let direct = run(&[], &frames, None);
    assert_eq!(output.status.code(), Some(0));
    assert_eq!((stdout(&output), stderr(&output)), (stdout(&direct), stderr(&direct)));
    assert_eq!(stdout(&output).lines().count(), 10);
    assert!(
        stderr(&output).starts_with(&format!("tracerctl: {}:1: ", frames.display())),
        "{}",
        stderr(&output)
    );
}

#[test]
fn a_directory_with_no_log_is_an_error_like_a_missing_input_and_an_output_in_it_is_not_read() {
    let recorder = Recorder::new(false);
    let incidents = recorder.path("incidents");
    let output = run(&[], &incidents, None);
    assert_eq!(output.status.code(), Some(1), "as for a missing input");
    assert_eq!(
        stderr(&output),
        format!(
            "tracerctl: {} is a directory with no frames.log and no *.log.zst segments (it holds incidents: give \
             one, such as the latest, {}): give a log file, an incident directory (DIR/incidents/TIME-CAUSE) or a \
             recorder's ring (DIR/ring)\n",
            incidents.display(),
            incidents.join("20261128T134612Z-estop").display()
        )
    );
    assert!(output.stdout.is_empty());
    // An output named like a segment, in the ring: created after the listing, never read back.
    let ring = recorder.path("ring");
    let inside = ring.join("20261128T134900.000Z.log.zst");
    let written = tracerctl().args(["decode", "-o"]).arg(&inside).arg(&ring).output().unwrap();
    assert_eq!((written.status.code(), stderr(&written)), (Some(0), String::new()));
    assert_eq!(std::fs::read_to_string(&inside).unwrap().lines().count(), 120);
}

#[test]
fn a_cut_file_then_a_missing_one_says_both_the_cut_first() {
    let dir = tempfile::tempdir().unwrap();
    let (bytes, ends) = in_parts("gzip", &[session(0, 10), session(10, 10)]);
    let cut = write(dir.path(), "cut.log.gz", &bytes[..ends[0] + 5]);
    let missing = dir.path().join("missing.log");
    let output = tracerctl().args(["decode", "-j1"]).arg(&cut).arg(&missing).output().unwrap();
    assert_eq!((output.status.code(), stdout(&output).lines().count()), (Some(1), 10));
    let errors = stderr(&output);
    let lines: Vec<&str> = errors.lines().collect();
    assert_eq!(lines.len(), 2, "{errors}");
    assert!(lines[0].starts_with(&format!("tracerctl: {}: the gzip data ends early, ", cut.display())));
    assert!(lines[1].starts_with(&format!("tracerctl: {}: no such file", missing.display())));
}
