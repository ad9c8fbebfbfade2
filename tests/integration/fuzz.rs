//! Fuzzing in the test suite: every committed seed (and every regression input found by fuzzing) goes
//! through its target's invariant check, and a few hundred mutated logs go through every decode mode of
//! the real binary.

use std::path::{Path, PathBuf};
use std::process::Output;

use tracerctl::fuzzing::TARGETS;

use crate::util::{data, tracerctl};

fn fuzz_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fuzz")
}

/// The files of a directory, sorted (empty when it does not exist).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = match std::fs::read_dir(dir) {
        Ok(entries) => entries.map(|entry| entry.expect("readable directory").path()).collect(),
        Err(_) => Vec::new(),
    };
    files.retain(|path| path.is_file());
    files.sort();
    files
}

/// The seeds of fuzz/seeds/<target>/ and the findings of fuzz/regressions/<target>/, through the check
/// the afl target runs (a failing input is named, so it can be replayed alone).
#[test]
fn every_seed_and_regression_passes_its_check() {
    for target in TARGETS {
        let seeds = files(&fuzz_dir().join("seeds").join(target.name));
        assert!(seeds.len() >= 4, "{}: {} seeds", target.name, seeds.len());
        let regressions = files(&fuzz_dir().join("regressions").join(target.name));
        for path in seeds.iter().chain(&regressions) {
            let input = std::fs::read(path).unwrap();
            if let Err(panic) = std::panic::catch_unwind(|| (target.check)(&input)) {
                let message = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                panic!("{} fails {}: {message}", path.display(), target.name);
            }
        }
    }
}

/// Every seed directory belongs to a target (a renamed target would leave its seeds unused).
#[test]
fn seed_directories_match_the_targets() {
    let mut dirs: Vec<String> = std::fs::read_dir(fuzz_dir().join("seeds"))
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    dirs.sort();
    let mut names: Vec<String> = TARGETS.iter().map(|target| target.name.to_string()).collect();
    names.sort();
    assert_eq!(dirs, names);
    let bins: Vec<PathBuf> = files(&fuzz_dir().join("src/bin"));
    for name in &names {
        assert!(
            bins.iter().any(|bin| bin.file_stem().unwrap() == name.as_str()),
            "no fuzz/src/bin/{name}.rs"
        );
    }
}

/// splitmix64: a fixed seed makes the mutants the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Bytes and tokens that matter to the parsers.
const TOKENS: &[&[u8]] = &[
    b"(",
    b")",
    b"#",
    b"##",
    b" ",
    b"\t",
    b"\r",
    b"\n",
    b"R",
    b"_F",
    b"[8]",
    b"{F}",
    b"\x1b[1;31m",
    b".",
    b"99999999999999999999",
    b"(253402300800.0) ",
    b"FFFFFFFF",
    b"DROPCOUNT: ",
    b"\xEF\xBB\xBF",
    b"\x5A\xA5\x0A",
    b"  can0  ",
    b"ERRORFRAME",
    b"-",
];

fn mutate(rng: &mut Rng, base: &[u8], bases: &[Vec<u8>]) -> Vec<u8> {
    let mut out = base.to_vec();
    for _ in 0..1 + rng.below(8) {
        let at = rng.below(out.len() + 1);
        match rng.below(7) {
            0 if !out.is_empty() => {
                let at = at.min(out.len() - 1);
                out[at] ^= 1 << rng.below(8);
            }
            1 => out.insert(at, rng.next() as u8),
            2 => {
                let token = TOKENS[rng.below(TOKENS.len())];
                out.splice(at..at, token.iter().copied());
            }
            3 => {
                let end = (at + 1 + rng.below(40)).min(out.len());
                out.drain(at.min(end)..end);
            }
            4 => {
                // Duplicate the line around `at`.
                let start = out[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
                let end = out[at..].iter().position(|&b| b == b'\n').map_or(out.len(), |i| at + i + 1);
                let line = out[start..end].to_vec();
                out.splice(end..end, line);
            }
            5 => {
                let other = &bases[rng.below(bases.len())];
                let from = rng.below(other.len());
                let to = (from + rng.below(200)).min(other.len());
                out.splice(at..at, other[from..to].iter().copied());
            }
            _ => out.truncate(at),
        }
    }
    out
}

/// The fixtures to mutate: the project's candump fixtures, the other text formats it reads (ASC, trc,
/// candump -S/-i, Pengutronix, BOM, TAB lines) and the RS232 seeds.
fn bases() -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = files(&data("candump"));
    paths.retain(|path| path.extension().is_some_and(|ext| ext == "log" || ext == "txt"));
    let read_formats = files(&data("formats")).into_iter().filter(|path| {
        let name = path.file_name().unwrap().to_string_lossy();
        name.ends_with(".asc")
            || name.starts_with("peak_")
            || name.starts_with("candump_")
            || name == "pengutronix.log"
            || name == "bom.log"
            || name == "tab_indented.log"
    });
    paths.extend(read_formats);
    paths.push(data("tracer_session.log"));
    paths.push(data("monitor_gap.log"));
    let mut bases: Vec<Vec<u8>> = paths.iter().map(|path| std::fs::read(path).unwrap()).collect();
    for seed in files(&fuzz_dir().join("seeds/serial_stream")) {
        bases.push(std::fs::read(seed).unwrap()[1..].to_vec());
    }
    bases
}

/// Fields of every CSV record (quoted fields may hold commas, quotes and newlines).
fn csv_records(text: &str) -> Vec<usize> {
    let mut records = Vec::new();
    let (mut fields, mut quoted, mut at_start, mut chars) = (1, false, true, text.chars().peekable());
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
            }
            ('"', true) => quoted = false,
            ('"', false) => quoted = true,
            (',', false) => fields += 1,
            ('\n', false) => {
                records.push(fields);
                fields = 1;
                at_start = true;
                continue;
            }
            _ => {}
        }
        at_start = false;
    }
    if !at_start {
        records.push(fields);
    }
    records
}

/// The checks every run gets, whatever its mode: no panic, a documented exit status.
fn check_run(what: &str, output: &Output, allowed: &[i32]) -> String {
    let err = String::from_utf8_lossy(&output.stderr).into_owned();
    let code = output.status.code();
    assert_ne!(code, Some(101), "{what}: exit 101\n{err}");
    assert!(!err.contains("panicked"), "{what}: panicked\n{err}");
    // A mutant can turn into the start of a format tracerctl refuses: exit 3 in one line, in any mode.
    if code == Some(3) && err.contains("which tracerctl does not read") {
        return String::from_utf8_lossy(&output.stdout).into_owned();
    }
    assert!(
        code.is_some_and(|code| allowed.contains(&code)),
        "{what}: exit {code:?}, not one of {allowed:?}\n{err}"
    );
    String::from_utf8_lossy(&output.stdout).into_owned()
}

/// A few hundred mutated logs (byte flips, insertions, deletions, duplicated lines, splices of other
/// fixtures, truncations) through every decode mode: text, JSON, CSV, the summary as text and JSON,
/// `--serial`, `--strict` and standard input. Never a panic (exit 101); exit 0, or 2/3 for what the tool
/// may refuse (3 only means bad data with --strict, 2 a usage error); JSON lines and the summary JSON
/// parse; CSV rows have the header's column count. Mutants are decoded in batches of several files per
/// run to keep the test fast; a failure names the files, which are kept (target/tmp/fuzz_mutants).
#[test]
fn mutated_logs_through_every_decode_mode() {
    const MUTANTS: usize = 500;
    const BATCH: usize = 10;
    let bases = bases();
    let mut rng = Rng(0x7E57_F022_2026_0011);
    // Kept after a failure, for replaying a mutant alone.
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz_mutants");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mutants: Vec<PathBuf> = (0..MUTANTS)
        .map(|index| {
            let base = &bases[rng.below(bases.len())];
            let path = dir.join(format!("mutant{index:03}.log"));
            std::fs::write(&path, mutate(&mut rng, base, &bases)).unwrap();
            path
        })
        .collect();

    for (number, batch) in mutants.chunks(BATCH).enumerate() {
        let names: Vec<&str> = batch.iter().map(|path| path.to_str().unwrap()).collect();
        let what = |mode: &str| format!("decode {mode} on {}", names.join(" "));
        let run = |args: &[&str]| tracerctl().arg("decode").args(args).args(&names).output().unwrap();

        // Exit 3 without --strict: an input in a format tracerctl does not read (a mutant turned binary), or no
        // input of the batch held a single frame (issue 28), when nothing is written.
        let text = run(&[]);
        check_run(&what("(text)"), &text, &[0, 2, 3]);
        let refused = String::from_utf8_lossy(&text.stderr).contains("which tracerctl does not read");
        assert!(
            text.status.code() != Some(3) || text.stdout.is_empty() || refused,
            "{}: frames and exit 3",
            what("(text)")
        );

        let json = run(&["-f", "json"]);
        for line in check_run(&what("-f json"), &json, &[0, 2, 3]).lines() {
            serde_json::from_str::<serde_json::Value>(line)
                .unwrap_or_else(|error| panic!("{}: {error} in {line:?}", what("-f json")));
        }

        let csv = run(&["-f", "csv"]);
        let records = csv_records(&check_run(&what("-f csv"), &csv, &[0, 2, 3]));
        if let Some((&header, rows)) = records.split_first() {
            assert!(header > 8, "{}: header of {header} columns", what("-f csv"));
            for (row, &fields) in rows.iter().enumerate() {
                assert_eq!(fields, header, "{}: row {} has {fields} fields", what("-f csv"), row + 1);
            }
        }

        for args in [&["--summary"][..], &["--summary", "-f", "json"]] {
            let summary = run(args);
            let out = check_run(&what(&args.join(" ")), &summary, &[0, 2, 3]);
            if args.len() > 1 && summary.status.success() {
                serde_json::from_str::<serde_json::Value>(&out)
                    .unwrap_or_else(|error| panic!("{}: {error}", what("--summary -f json")));
            }
        }

        // --strict stops at the first bad line of the first file that has one.
        check_run(&what("--strict"), &run(&["--strict"]), &[0, 2, 3]);

        // Every mutant as an RS232 capture (raw bytes or hex text).
        let mut serial = tracerctl();
        serial.args(["decode", "-f", "json"]);
        for name in &names {
            serial.arg("--serial").arg(name);
        }
        for line in check_run(&what("--serial"), &serial.output().unwrap(), &[0, 2, 3]).lines() {
            serde_json::from_str::<serde_json::Value>(line).expect("JSON line from --serial");
        }

        // Standard input: this batch's mutants one after the other.
        let stdin: Vec<u8> = batch.iter().flat_map(|path| std::fs::read(path).unwrap()).collect();
        let piped = tracerctl().args(["decode", "-f", "json", "-"]).write_stdin(stdin).output().unwrap();
        let piped_frames = check_run(&format!("decode - (batch {number})"), &piped, &[0, 2, 3]);
        let refused = String::from_utf8_lossy(&piped.stderr).contains("which tracerctl does not read");
        assert!(
            piped.status.code() != Some(3) || piped_frames.is_empty() || refused,
            "batch {number}: exit 3"
        );
        for line in piped_frames.lines() {
            serde_json::from_str::<serde_json::Value>(line).expect("JSON line from standard input");
        }
    }
}
