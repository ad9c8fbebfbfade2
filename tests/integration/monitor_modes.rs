//! `monitor`'s candump conventions (issue 13): the `-t` time modes, `-n COUNT`, the raw bytes in text lines,
//! and JSON's integer `ts_ns`, on a replay of `tests/data/monitor_modes.log` and on the simulator.

use std::process::Output;

use predicates::prelude::*;

use super::util::{data, json_lines, stderr, stdout, tracerctl};

/// The fixture's stamps as written, in nanoseconds since the epoch.
const STAMPS: [&str; 8] = [
    "1700000000.000000",
    "1700000000.020000",
    "1700000000.040250",
    "1700000001.440250",
    "1700000001.478500",
    "1700000001.500000",
    "1700000001.520000",
    "1700000002.123456789",
];

fn fixture() -> String {
    data("monitor_modes.log").to_str().unwrap().to_string()
}

/// `monitor` on the fixture replayed as fast as possible, with `args` after `monitor`.
fn replay(args: &[&str]) -> Output {
    let log = fixture();
    tracerctl().args(["--replay", &log, "--speed", "0", "monitor"]).args(args).output().unwrap()
}

/// A decimal stamp `S.F` (6 or 9 decimals) in nanoseconds, exactly.
fn nanos(text: &str) -> u128 {
    let (secs, fraction) = text.split_once('.').expect("a decimal point");
    let scale = 10u128.pow(9 - fraction.len() as u32);
    secs.parse::<u128>().unwrap() * 1_000_000_000 + fraction.parse::<u128>().unwrap() * scale
}

/// The time column of every text line (the first word; `-t A` stamps are the first two).
fn time_column(output: &Output, words: usize) -> Vec<String> {
    stdout(output).lines().map(|line| line.split(' ').take(words).collect::<Vec<_>>().join(" ")).collect()
}

/// `SSS.ffffff` (or 9 decimals) as candump -t d/z prints `span` nanoseconds.
fn span(span: u128, nine: bool) -> String {
    let (secs, nanos) = (span / 1_000_000_000, span % 1_000_000_000);
    if nine {
        format!("{secs:03}.{nanos:09}")
    } else {
        format!("{secs:03}.{:06}", nanos / 1000)
    }
}

#[test]
fn absolute_is_the_default_and_matches_the_replayed_stamps() {
    let default = replay(&[]);
    assert_eq!(default.status.code(), Some(0), "{}", stderr(&default));
    assert_eq!(time_column(&default, 1), STAMPS);
    for flag in [&["-t", "a"][..], &["--timestamp", "absolute"], &["-ta"]] {
        let output = replay(flag);
        assert_eq!(stdout(&output), stdout(&default), "{flag:?}");
    }
}

#[test]
fn zero_starts_at_zero_and_counts_from_the_first_frame() {
    let output = replay(&["-t", "z"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let first = nanos(STAMPS[0]);
    // Six decimals until the stamp with nanoseconds; from then on nine.
    let expected: Vec<String> =
        STAMPS.iter().map(|stamp| span(nanos(stamp) - first, stamp.len() > 17)).collect();
    assert_eq!(time_column(&output, 1), expected);
    assert_eq!(expected[0], "000.000000");
    assert_eq!(expected[3], "001.440250");
    assert_eq!(expected[7], "002.123456789");
    assert_eq!(stdout(&replay(&["--timestamp", "zero"])), stdout(&output));
}

#[test]
fn delta_is_zero_first_then_the_gap_to_the_previous_frame() {
    let output = replay(&["-t", "d"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let mut previous = nanos(STAMPS[0]);
    let expected: Vec<String> = STAMPS
        .iter()
        .map(|stamp| {
            let now = nanos(stamp);
            let gap = span(now - previous, stamp.len() > 17);
            previous = now;
            gap
        })
        .collect();
    assert_eq!(time_column(&output, 1), expected);
    assert_eq!(&expected[..5], ["000.000000", "000.020000", "000.020250", "001.400000", "000.038250"]);
    assert_eq!(stdout(&replay(&["--timestamp", "delta"])), stdout(&output));

    // Delta and zero count the lines shown: with a filter, from the first and previous 0x211.
    let output = replay(&["-t", "d", "--id", "0x211"]);
    assert_eq!(time_column(&output, 1), ["000.000000", "000.040250", "001.459750"]);
}

#[test]
fn date_is_local_date_and_time_with_microseconds() {
    let shape = predicate::str::is_match(r"^\d{4}-\d\d-\d\d \d\d:\d\d:\d\d\.\d{6}(\d{3})?$").unwrap();
    let log = fixture();
    let run = |tz: &str, mode: &str| {
        let output = tracerctl()
            .env("TZ", tz)
            .args(["--replay", &log, "--speed", "0", "monitor", "-t", mode])
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
        time_column(&output, 2)
    };
    let utc = run("UTC", "A");
    for stamp in &utc {
        assert!(shape.eval(stamp), "{stamp}");
    }
    // 1700000000 is 2023-11-14 22:13:20 UTC; the stamp with nanoseconds keeps all nine.
    assert_eq!(utc[0], "2023-11-14 22:13:20.000000");
    assert_eq!(utc[3], "2023-11-14 22:13:21.440250");
    assert_eq!(utc[7], "2023-11-14 22:13:22.123456789");
    // Local time: POSIX "UTC-2" is two hours east of Greenwich, past midnight.
    let east = run("UTC-2", "date");
    assert_eq!(east[0], "2023-11-15 00:13:20.000000");
    assert!(east.iter().all(|stamp| shape.eval(stamp.as_str())), "{east:?}");
}

#[test]
fn count_prints_exactly_that_many_frames_exits_0_and_still_summarises() {
    let output = replay(&["-n", "5"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(time_column(&output, 1), STAMPS[..5]);
    let errors = stderr(&output);
    assert!(errors.contains("(frame count reached): 5 frames, 5 shown"), "{errors}");
    assert!(errors.contains("  total: 5 frames,"), "{errors}");

    // Frames shown, not received: a filter lets two 0x211 through after skipping others.
    let output = replay(&["--count", "2", "--id", "0x211", "--format", "json"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let ids: Vec<String> = json_lines(&output).iter().map(|line| line["id"].to_string()).collect();
    assert_eq!(ids, ["\"0x211\"", "\"0x211\""]);

    // Live: the simulator's 150 frames a second, stopped at 5 however fast they come.
    let output = tracerctl().args(["--sim", "monitor", "-n", "5", "--duration", "10s"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(stdout(&output).lines().count(), 5, "{}", stdout(&output));
    assert!(stderr(&output).contains("(frame count reached)"), "{}", stderr(&output));
    let raw = tracerctl().args(["--sim", "monitor", "--raw", "-n", "3"]).output().unwrap();
    assert_eq!((raw.status.code(), stdout(&raw).lines().count()), (Some(0), 3), "{}", stderr(&raw));
}

#[test]
fn text_lines_show_the_raw_bytes_in_an_aligned_column() {
    let output = replay(&[]);
    let text = stdout(&output);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "1700000000.000000 replay 0x211 [8] 00 00 01 03 00 00 00 B1  system_state vehicle_state=normal \
         control_mode=standby battery_voltage=25.9V fault_code=0x0000 faults=none count=177"
    );
    // A two-byte frame is padded; the bytes are in their column, so no data= at the end.
    assert_eq!(lines[3], "1700000001.440250 replay 0x123 [2] 01 02                    raw len=2");
    // Every message name starts in one column until the extended identifier widens it, as candump does.
    let msg_column = |line: &str, msg: &str| line.find(&format!("  {msg}")).unwrap();
    let names = ["system_state", "motion_state", "system_state", "raw", "odometry", "system_state"];
    for (line, msg) in lines.iter().zip(names) {
        assert_eq!(msg_column(line, msg), msg_column(lines[0], "system_state"), "{line}");
    }
    assert_eq!(lines[6], "1700000001.520000 replay 0x18FF0001 [2] AA BB                    raw len=2");
    assert!(lines[7]
        .starts_with("1700000002.123456789 replay 0x221      [8] FF 38 FE 0C 00 00 00 00  motion_state"));
}

#[test]
fn no_data_gives_the_line_decode_prints() {
    let output = replay(&["--no-data"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let decode = tracerctl().args(["decode", &fixture()]).output().unwrap();
    assert!(decode.status.success(), "{}", stderr(&decode));
    assert_eq!(stdout(&output), stdout(&decode).replace(" can0 ", " replay "));
    assert!(stdout(&output).contains(" 0x123 raw len=2 data=0102\n"), "{}", stdout(&output));
}

#[test]
fn json_ts_ns_is_the_stamp_in_integer_nanoseconds() {
    let output = replay(&["--format", "json"]);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    for (line, stamp) in text.lines().zip(STAMPS) {
        // `ts` as written (a float would lose the last digits), then `ts_ns` right after it.
        let prefix = format!("{{\"ts\":{stamp},\"ts_ns\":{},\"iface\":\"replay\"", nanos(stamp));
        assert!(line.starts_with(&prefix), "{line}\nexpected {prefix}");
    }
    let objects = json_lines(&output);
    assert_eq!(objects[7]["ts_ns"].as_u64(), Some(1_700_000_002_123_456_789));

    // Live stamps with nanoseconds: ts and ts_ns agree to the nanosecond on every line.
    let output = tracerctl().args(["--sim", "monitor", "--format", "json", "-n", "20"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    assert_eq!(text.lines().count(), 20);
    for line in text.lines() {
        let ts = line.strip_prefix("{\"ts\":").unwrap().split(',').next().unwrap();
        let ts_ns = line.split("\"ts_ns\":").nth(1).unwrap().split(',').next().unwrap();
        assert_eq!(ts_ns.parse::<u128>().unwrap(), nanos(ts), "{line}");
    }

    // decode writes the same object: `null` for both without a stamp.
    let decode = tracerctl().args(["decode", "--format", "json", "211#00000103000000B1"]).output().unwrap();
    assert!(
        stdout(&decode).starts_with("{\"ts\":null,\"ts_ns\":null,\"iface\":\"-\""),
        "{}",
        stdout(&decode)
    );
}

#[test]
fn text_column_options_with_json_csv_or_raw_and_a_zero_count_are_usage_errors() {
    for args in [
        &["--format", "json", "-t", "z"][..],
        &["--format", "csv", "--timestamp", "date"],
        &["--raw", "-t", "d"],
        &["--format", "json", "--no-data"],
    ] {
        let output = replay(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
        assert!(stderr(&output).contains("is for text lines"), "{args:?}: {}", stderr(&output));
        assert!(output.stdout.is_empty());
    }
    for args in [&["-n", "0"][..], &["-t", "x"], &["-t", "Z"]] {
        let output = replay(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", stderr(&output));
    }
}
