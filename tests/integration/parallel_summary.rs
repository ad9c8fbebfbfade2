//! `decode -j N --summary` merges per-chunk partial summaries (issue 14); a chunk whose partial cannot be
//! merged exactly (more interface names or identifiers than the report lists) is replayed instead. Either
//! way the report is `-j1`'s, byte for byte.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Output;

use crate::util::{stderr, stdout, tracerctl};

fn decode(path: &Path, threads: u16, chunk_bytes: Option<usize>, extra: &[&str]) -> Output {
    let mut command = tracerctl();
    command.arg("decode").arg(format!("-j{threads}")).arg("--summary").args(extra).arg(path);
    if let Some(bytes) = chunk_bytes {
        command.env("TRACERCTL_CHUNK_BYTES", bytes.to_string());
    }
    command.output().unwrap()
}

/// 15,000 lines: system states changing mode and E-stop, and from line 3000 on 400 names used once, then
/// names from 100 interfaces; 4500 distinct extended identifiers, then seven more taking turns (past the 64
/// names and 4096 rows the report lists one by one).
fn crowded_log() -> String {
    let mut log = String::new();
    for n in 0..15_000u32 {
        let stamp = format!("({}.{:06})", 1_700_000_000 + n / 100, (n % 100) * 10_000);
        let iface = match n {
            ..3000 => format!("can{}", n % 3),
            // Each its own name: a chunk of these lists more names than fit.
            3000..3400 => format!("v{n}"),
            _ => format!("can{}", (n * 37) % 100),
        };
        if n % 2 == 0 {
            let (mode, state) = ((n / 500) % 3, u32::from(n % 1700 < 20));
            // The count byte steps by one, skipping one value every 700 frames.
            let count = (n / 2 + n / 1400) % 256;
            writeln!(log, "{stamp} {iface} 211#{state:02X}{mode:02X}0103000000{count:02X}").unwrap();
        } else {
            let id = match n {
                ..3000 => 0x1000 + n % 40,
                3000..12_000 => 0x10_0000 + (n / 2 * 7919) % 9000,
                // Past the rows: seven identifiers taking turns, all counted in the overflow row.
                _ => 0x20_0000 + n % 7,
            };
            writeln!(log, "{stamp} {iface} {id:08X}#{:02X}", n % 256).unwrap();
        }
    }
    log
}

#[test]
fn partial_summaries_and_replayed_chunks_give_the_single_pass_report() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("crowded.log");
    std::fs::write(&path, crowded_log()).unwrap();
    for extra in [&[][..], &["-f", "json"]] {
        let single = decode(&path, 1, None, extra);
        let report = stdout(&single);
        assert!(single.status.success(), "{}", stderr(&single));
        if extra.is_empty() {
            assert!(report.contains("decoded 15000 frames from 15000 lines"), "{report}");
            assert!(report.contains("other ids (beyond 4096)"), "{report}");
        }
        for bytes in [97, 4000, 65_536, 1 << 20] {
            let parallel = decode(&path, 2, Some(bytes), extra);
            let what = format!("{extra:?} TRACERCTL_CHUNK_BYTES={bytes}");
            assert_eq!(stdout(&parallel), report, "stdout of {what}");
            assert_eq!(stderr(&parallel), stderr(&single), "stderr of {what}");
            assert_eq!(parallel.status.code(), single.status.code(), "exit status of {what}");
        }
    }
}
