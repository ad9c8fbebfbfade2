//! Every fixture in `tests/data/candump/` read through `LineReader` + `LineParser`: exact frame, error and
//! other-line counts, plus spot checks of decoded values.

use std::fs::File;

use super::{Direction, Line, LineParser, LineReader, RawLine, Reason, Timestamp, TimestampKind};
use crate::protocol::{CanFrame, FrameKind};

const ABS: TimestampKind = TimestampKind::Absolute;
const REL: TimestampKind = TimestampKind::Relative;

#[derive(Debug)]
struct Frame {
    line: u64,
    ts: Option<Timestamp>,
    iface: String,
    frame: CanFrame,
    dir: Option<Direction>,
}

#[derive(Debug, Default)]
struct Scan {
    lines: u64,
    frames: Vec<Frame>,
    errors: Vec<(u64, Reason)>,
    blank: usize,
    comments: usize,
    drops: Vec<u64>,
    error_text: usize,
    xl: usize,
}

fn scan_with(name: &str, mut parser: LineParser, capacity: usize, max_line_len: usize) -> Scan {
    let path = format!("{}/tests/data/candump/{name}", env!("CARGO_MANIFEST_DIR"));
    let file = File::open(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let mut reader = LineReader::with_capacity(capacity, file).with_max_line_len(max_line_len);
    let mut scan = Scan::default();
    while let Some(raw) = reader.next_line().unwrap() {
        let (number, text) = match raw {
            RawLine::Line { number, text } => (number, text),
            RawLine::TooLong { number, .. } => {
                scan.lines = number;
                scan.errors.push((number, Reason::LineTooLong));
                continue;
            }
        };
        scan.lines = number;
        match parser.parse(text) {
            Ok(Line::Frame(r)) => scan.frames.push(Frame {
                line: number,
                ts: r.ts,
                iface: r.iface.to_owned(),
                frame: r.frame,
                dir: r.dir,
            }),
            Ok(Line::Blank) => scan.blank += 1,
            Ok(Line::Comment) => scan.comments += 1,
            Ok(Line::DropCount { dropped }) => scan.drops.push(dropped),
            Ok(Line::ErrorText) => scan.error_text += 1,
            Ok(Line::CanXl) => scan.xl += 1,
            Err(e) => scan.errors.push((number, e.reason)),
        }
    }
    scan
}

fn scan(name: &str) -> Scan {
    scan_with(name, LineParser::new(), 64 * 1024, 64 * 1024)
}

fn ts(secs: u64, nanos: u32, kind: TimestampKind) -> Option<Timestamp> {
    Some(Timestamp { secs, nanos, kind })
}

fn ids(scan: &Scan) -> Vec<u32> {
    scan.frames.iter().map(|f| f.frame.id()).collect()
}

/// Only frames, no errors or other lines.
fn assert_only_frames(scan: &Scan, count: usize) {
    assert_eq!(scan.frames.len(), count, "{scan:#?}");
    assert_eq!(scan.errors, vec![], "{scan:#?}");
    assert_eq!((scan.blank, scan.comments, scan.drops.len(), scan.error_text, scan.xl), (0, 0, 0, 0, 0));
}

#[test]
fn log_basic() {
    let s = scan("log_basic.log");
    assert_only_frames(&s, 10);
    assert_eq!(ids(&s), [0x211, 0x221, 0x231, 0x251, 0x252, 0x261, 0x262, 0x311, 0x111, 0x421]);
    let first = &s.frames[0];
    assert_eq!(
        (first.line, first.ts, first.iface.as_str(), first.dir),
        (1, ts(1_700_000_000, 0, ABS), "can0", None)
    );
    assert_eq!(first.frame.data(), &[0x00, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00, 0xB1]);
    assert_eq!(s.frames[7].frame.data(), &[0xFF, 0xFF, 0xFF, 0xC1, 0x00, 0x00, 0x00, 0x12]);
    assert_eq!(s.frames[8].ts, ts(1_700_000_000, 20_000_000, ABS));
    assert_eq!(s.frames[9].frame.data(), &[0x01]);
    assert!(s
        .frames
        .iter()
        .all(|f| f.frame.is_standard_data() && f.frame.len() == if f.frame.id() == 0x421 { 1 } else { 8 }));
}

#[test]
fn log_padded_dir() {
    let s = scan("log_padded_dir.log");
    assert_only_frames(&s, 6);
    let ifaces: Vec<&str> = s.frames.iter().map(|f| f.iface.as_str()).collect();
    assert_eq!(ifaces, ["can0", "vcan10", "can0", "can0", "vcan10", "can0"]);
    let dirs: Vec<_> = s.frames.iter().map(|f| f.dir).collect();
    let (rx, tx) = (Some(Direction::Rx), Some(Direction::Tx));
    assert_eq!(dirs, [rx, tx, rx, tx, rx, None]);
    assert_eq!(s.frames[3].frame.data(), &[0x01]);
    assert_eq!(s.frames[1].ts, ts(1_700_000_001, 100_000, ABS));
}

#[test]
fn log_ns_relative() {
    let s = scan("log_ns_relative.log");
    assert_only_frames(&s, 8);
    let stamps: Vec<_> = s.frames.iter().map(|f| f.ts).collect();
    assert_eq!(
        stamps,
        [
            ts(1_700_000_002, 123_456_789, ABS),
            ts(1_700_000_002, 123_706_789, ABS),
            ts(0, 0, REL),
            ts(0, 20_113_000, REL),
            ts(1, 0, REL),
            ts(0, 0, REL),
            ts(1_614_188_635, 100_000_000, ABS),
            ts(0, 123_456_789, REL),
        ]
    );
    assert_eq!(s.frames[5].dir, Some(Direction::Rx));
}

#[test]
fn log_rtr_dlc_dots() {
    let s = scan("log_rtr_dlc_dots.log");
    assert_only_frames(&s, 10);
    let summary: Vec<_> = s
        .frames
        .iter()
        .map(|f| (f.frame.kind(), f.frame.is_extended(), f.frame.len(), f.frame.raw_dlc()))
        .collect();
    use FrameKind::{Data, Remote};
    assert_eq!(
        summary,
        [
            (Remote, false, 0, None),
            (Remote, false, 1, None),
            (Remote, false, 8, Some(0xE)),
            (Remote, true, 3, None),
            (Data, false, 8, Some(9)),
            (Data, false, 8, Some(0xF)),
            (Data, false, 8, None),
            (Data, false, 8, None),
            (Data, false, 1, None),
            (Remote, false, 0, None),
        ]
    );
    assert_eq!(s.frames[4].frame.data(), &[0x00, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00, 0xB1]);
    assert_eq!(s.frames[6].frame.data(), &[0xFF, 0xFF, 0xFF, 0xC1, 0x00, 0x00, 0x00, 0x12]);
    assert_eq!(s.frames[7].frame.data(), &[0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88]);
}

#[test]
fn log_fd_error_eff() {
    let s = scan("log_fd_error_eff.log");
    assert_eq!((s.frames.len(), s.xl, s.errors.len()), (12, 1, 0));
    let f = &s.frames;
    assert_eq!(
        (f[0].frame.kind(), f[0].frame.fd_flags(), f[0].frame.data()),
        (FrameKind::Fd, 5, &[0, 0x11, 0x22][..])
    );
    assert_eq!((f[1].frame.kind(), f[1].frame.fd_flags(), f[1].frame.len()), (FrameKind::Fd, 4, 0));
    assert_eq!(
        (f[2].frame.id(), f[2].frame.is_extended(), f[2].frame.fd_flags(), f[2].frame.len()),
        (0x18FF_0001, true, 7, 12)
    );
    assert_eq!((f[3].iface.as_str(), f[3].frame.fd_flags(), f[3].frame.len()), ("can1", 0, 64));
    assert_eq!(f[3].frame.data()[63], 63);
    assert_eq!((f[4].frame.kind(), f[4].frame.id()), (FrameKind::Error, 0x4));
    assert_eq!(f[4].frame.data(), &[0x00, 0x08, 0x00, 0x00, 0x00, 0x00, 0x78, 0x00]);
    assert_eq!((f[5].frame.kind(), f[5].frame.id(), f[5].frame.len()), (FrameKind::Error, 0x80, 0));
    assert_eq!((f[6].frame.kind(), f[6].dir), (FrameKind::Error, Some(Direction::Rx)));
    assert_eq!((f[7].frame.id(), f[7].frame.is_extended(), f[7].frame.data()), (0x123, true, &[0x11][..]));
    assert_eq!((f[8].frame.id(), f[8].frame.kind()), (0x18FE_F100, FrameKind::Data));
    assert_eq!((f[9].frame.id(), f[9].frame.is_extended(), f[9].frame.len()), (0x1FFF_FFFF, true, 0));
    assert_eq!((f[10].frame.id(), f[10].frame.len()), (0x211, 0));
    assert_eq!(f[11].frame.data(), &[0xAB, 0xCD, 0xEF, 0x01, 0x23, 0x45, 0x67, 0x89]);
}

#[test]
fn log_dropcount_comments() {
    let s = scan("log_dropcount_comments.log");
    assert_eq!(s.frames.len(), 3);
    assert_eq!(s.errors, vec![]);
    assert_eq!((s.comments, s.blank, s.drops.clone()), (2, 3, vec![3, 1]));
    let lines: Vec<u64> = s.frames.iter().map(|f| f.line).collect();
    assert_eq!(lines, [4, 6, 9]);
    assert_eq!(s.frames[2].dir, Some(Direction::Rx));
    assert_eq!(s.frames[0].frame.data(), &[0x00, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00, 0xB1]);
}

#[test]
fn console_plain() {
    let s = scan("console_plain.txt");
    assert_only_frames(&s, 8);
    assert_eq!(ids(&s), [0x211, 0x221, 0x231, 0x251, 0x252, 0x261, 0x311, 0x421]);
    assert!(s.frames.iter().all(|f| f.ts.is_none() && f.iface == "can0" && f.dir.is_none()));
    assert_eq!(s.frames[3].frame.data(), &[0x00, 0x00, 0x00, 0x0F, 0x00, 0x00, 0x00, 0x54]);
    assert_eq!(s.frames[7].frame.data(), &[0x01]);
}

#[test]
fn console_rtr_fd_dlc() {
    let s = scan("console_rtr_fd_dlc.txt");
    assert_eq!((s.frames.len(), s.xl, s.errors.len()), (8, 1, 0));
    let summary: Vec<_> = s
        .frames
        .iter()
        .map(|f| (f.frame.kind(), f.frame.len(), f.frame.raw_dlc(), f.frame.fd_flags()))
        .collect();
    use FrameKind::{Data, Fd, Remote};
    assert_eq!(
        summary,
        [
            (Remote, 0, None, 0),
            (Remote, 5, None, 0),
            (Fd, 8, None, 4),
            (Fd, 12, None, 4),
            (Data, 8, Some(9), 0),
            (Data, 8, None, 0),
            (Data, 1, None, 0),
            (Remote, 8, Some(0xF), 0),
        ]
    );
    assert_eq!(s.frames[3].frame.data()[11], 0xBB);
}

#[test]
fn console_ta() {
    let s = scan("console_ta.txt");
    assert_only_frames(&s, 4);
    let stamps: Vec<_> = s.frames.iter().map(|f| f.ts).collect();
    assert_eq!(
        stamps,
        [
            ts(1_700_000_006, 0, ABS),
            ts(1_700_000_006, 250_000, ABS),
            ts(1_700_000_006, 500_000, ABS),
            ts(1_700_000_006, 20_000_000, ABS)
        ]
    );
    assert_eq!(s.frames[3].frame.data(), &[0x01, 0xF4, 0, 0, 0, 0, 0, 0]);
}

#[test]
fn console_t_capital_a() {
    let s = scan("console_tA.txt");
    assert_only_frames(&s, 3);
    let stamps: Vec<_> = s.frames.iter().map(|f| f.ts).collect();
    // 2023-11-14 22:13:20 UTC is 1700000000; 2024-02-29 23:59:59 UTC is 1709251199.
    assert_eq!(
        stamps,
        [ts(1_700_000_000, 0, ABS), ts(1_700_000_000, 250_000, ABS), ts(1_709_251_199, 999_999_000, ABS)]
    );
}

#[test]
fn console_td_accumulates_deltas() {
    let s = scan_with("console_td.txt", LineParser::new().with_delta_timestamps(), 64 * 1024, 64 * 1024);
    assert_only_frames(&s, 5);
    let stamps: Vec<_> = s.frames.iter().map(|f| f.ts).collect();
    assert_eq!(
        stamps,
        [
            ts(0, 0, REL),
            ts(0, 250_000, REL),
            ts(0, 500_000, REL),
            ts(0, 20_000_000, REL),
            ts(1, 20_000_000, REL)
        ]
    );
    // Without the option the same file reads as -t z stamps.
    let plain = scan("console_td.txt");
    assert_eq!(plain.frames[4].ts, ts(1, 0, REL));
}

#[test]
fn console_tz() {
    let s = scan("console_tz.txt");
    assert_only_frames(&s, 5);
    let stamps: Vec<_> = s.frames.iter().map(|f| f.ts).collect();
    assert_eq!(
        stamps,
        [
            ts(0, 0, REL),
            ts(0, 250_000, REL),
            ts(0, 500_000, REL),
            ts(0, 20_000_000, REL),
            ts(123, 456_789_000, REL)
        ]
    );
}

#[test]
fn console_x() {
    let s = scan("console_x.txt");
    assert_eq!((s.frames.len(), s.errors.len(), s.drops.clone()), (7, 0, vec![2]));
    let (rx, tx) = (Some(Direction::Rx), Some(Direction::Tx));
    let summary: Vec<_> =
        s.frames.iter().map(|f| (f.dir, f.frame.kind(), f.frame.fd_flags(), f.frame.len())).collect();
    use FrameKind::{Data, Fd};
    assert_eq!(
        summary,
        [
            (rx, Data, 0, 8),
            (tx, Data, 0, 8),
            (rx, Fd, 5, 12),
            (rx, Fd, 6, 16),
            (tx, Fd, 7, 64),
            (rx, Data, 0, 1),
            (rx, Fd, 4, 8)
        ]
    );
    assert_eq!(s.frames[5].iface, "vcan10");
    assert_eq!(s.frames[4].frame.data()[63], 0x3F);
}

#[test]
fn console_color() {
    let s = scan("console_color.txt");
    assert_only_frames(&s, 5);
    assert_eq!(ids(&s), [0x211, 0x221, 0x311, 0x421, 0x111]);
    let ifaces: Vec<&str> = s.frames.iter().map(|f| f.iface.as_str()).collect();
    assert_eq!(ifaces, ["can0", "can1", "can0", "can0", "can0"]);
    assert_eq!(s.frames[2].frame.data(), &[0xFF, 0xFF, 0xFF, 0xC1, 0x00, 0x00, 0x00, 0x12]);
    assert_eq!((s.frames[4].dir, s.frames[4].ts), (Some(Direction::Tx), ts(1_700_000_008, 400_000, ABS)));
}

#[test]
fn console_eff_indent() {
    let s = scan("console_eff_indent.txt");
    assert_only_frames(&s, 6);
    assert_eq!(ids(&s), [0x211, 0x18FE_F100, 0x211, 0x221, 0x123, 0x311]);
    let ext: Vec<bool> = s.frames.iter().map(|f| f.frame.is_extended()).collect();
    assert_eq!(ext, [false, true, false, false, true, false]);
}

#[test]
fn console_ascii() {
    let s = scan("console_ascii.txt");
    assert_only_frames(&s, 6);
    assert_eq!(s.frames[1].frame.data(), b"TRACER V");
    assert_eq!(s.frames[2].frame.data(), b"1.2.8'\0\0");
    assert_eq!(s.frames[3].frame.data(), &[0x01]);
    assert!(s.frames[4].frame.is_empty());
    assert_eq!(s.frames[5].frame.data(), b"''");
}

#[test]
fn console_errorframe() {
    let s = scan("console_errorframe.txt");
    assert_eq!((s.frames.len(), s.error_text, s.errors.len()), (4, 6, 0));
    let kinds: Vec<_> = s.frames.iter().map(|f| (f.line, f.frame.kind(), f.frame.id())).collect();
    use FrameKind::{Data, Error};
    assert_eq!(kinds, [(1, Error, 0x4), (4, Data, 0x211), (5, Error, 0x80), (7, Error, 0x44)]);
    assert_eq!(s.frames[0].frame.data(), &[0x00, 0x08, 0x00, 0x00, 0x00, 0x00, 0x78, 0x00]);
    // 2023-02-06 16:15:05 UTC is 1675700105.
    assert_eq!(s.frames[0].ts, ts(1_675_700_105, 259_679_000, ABS));
}

#[test]
fn mixed() {
    let s = scan("mixed.log");
    assert_eq!(s.lines, 27);
    assert_eq!(s.errors, vec![]);
    assert_eq!(s.frames.len(), 20);
    assert_eq!((s.comments, s.blank, s.error_text, s.xl, s.drops.clone()), (1, 1, 2, 1, vec![3, 2]));
    let lines: Vec<u64> = s.frames.iter().map(|f| f.line).collect();
    assert_eq!(lines, [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 14, 15, 16, 20, 21, 22, 24, 25, 27]);
    let kinds: Vec<FrameKind> = s.frames.iter().map(|f| f.frame.kind()).collect();
    use FrameKind::{Data, Error, Fd, Remote};
    assert_eq!(
        kinds,
        [
            Data, Data, Data, Data, Data, Data, Remote, Fd, Error, Data, Data, Data, Data, Error, Remote,
            Data, Data, Data, Fd, Data
        ]
    );
    assert_eq!(s.frames[2].dir, Some(Direction::Rx));
    assert_eq!(s.frames[4].ts, ts(0, 0, REL));
    assert_eq!(s.frames[5].ts, ts(1_700_000_000, 0, ABS));
    assert_eq!(s.frames[15].frame.raw_dlc(), Some(9));
    assert_eq!(s.frames[18].frame.len(), 64);
    assert_eq!(s.frames[19].frame.data(), &[0x01]);
}

#[test]
fn mixed_with_a_tiny_buffer_gives_the_same_result() {
    let big = scan("mixed.log");
    let tiny = scan_with("mixed.log", LineParser::new(), 3, 64 * 1024);
    assert_eq!(format!("{big:?}"), format!("{tiny:?}"));
}

#[test]
fn bad_lines_one_per_reason() {
    let s = scan_with("bad_lines.log", LineParser::new(), 1024, 4096);
    let expected = [
        (2, Reason::NotCandump),
        (4, Reason::UnterminatedTimestamp),
        (6, Reason::BadTimestamp),
        (8, Reason::TimestampFraction),
        (10, Reason::TimestampTooLarge),
        (12, Reason::BadDateTime),
        (14, Reason::ExpectedSpace),
        (16, Reason::MissingInterface),
        (18, Reason::InterfaceTooLong),
        (20, Reason::BadInterface),
        (22, Reason::MissingFrame),
        (24, Reason::MissingHash),
        (26, Reason::NotHex),
        (28, Reason::IdLength),
        (30, Reason::SffIdTooLarge),
        (32, Reason::IdTooLarge),
        (34, Reason::OddHexDigits),
        (36, Reason::BadSeparator),
        (38, Reason::TooManyBytes),
        (40, Reason::FdTooManyBytes),
        (42, Reason::BadFdLength),
        (44, Reason::BadFdFlags),
        (46, Reason::BadRemoteLength),
        (48, Reason::BadRawDlc),
        (50, Reason::ErrorFrameNotData),
        (52, Reason::BadMessageInfo),
        (54, Reason::BadLength),
        (56, Reason::LengthMismatch),
        (58, Reason::ConsoleByte),
        (60, Reason::BadXlFrame),
        (62, Reason::TrailingGarbage),
        (64, Reason::BadDropCount),
        (66, Reason::LineTooLong),
    ];
    assert_eq!(s.errors, expected);
    assert_eq!(s.lines, 67);
    assert_eq!(s.frames.len(), 34);
    assert!(s.frames.iter().all(|f| f.line % 2 == 1));
    assert_eq!(ids(&s)[..3], [0x211, 0x221, 0x311]);
    // Every reason a line can produce appears; the rest only come from parse_cansend.
    let cansend_only = [Reason::XlUnsupported, Reason::UnexpectedWhitespace, Reason::EmptyFrame];
    // The ASC and trc parsers' reasons, and the TAB rule that needs line context (formats_tests.rs).
    let elsewhere =
        [Reason::NotAsc, Reason::AscEvent, Reason::AscFrame, Reason::TrcFrame, Reason::StrayErrorText];
    for reason in Reason::ALL {
        let seen = s.errors.iter().filter(|(_, r)| r == reason).count();
        let expected = !cansend_only.contains(reason) && !elsewhere.contains(reason);
        assert_eq!(seen, usize::from(expected), "{reason:?}");
    }
}
