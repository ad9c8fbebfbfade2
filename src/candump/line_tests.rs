//! `LineParser` on every log and console variant, and on bad lines.

use super::{Direction, Line, LineError, LineParser, Reason, Timestamp, TimestampKind};
use crate::protocol::{CanFrame, FrameKind};

const ABS: TimestampKind = TimestampKind::Absolute;
const REL: TimestampKind = TimestampKind::Relative;

/// A parsed frame line with an owned interface name.
#[derive(Debug)]
struct Owned {
    ts: Option<Timestamp>,
    iface: String,
    frame: CanFrame,
    dir: Option<Direction>,
}

fn frame_with(parser: &mut LineParser, line: &str) -> Owned {
    match parser.parse(line.as_bytes()) {
        Ok(Line::Frame(r)) => Owned { ts: r.ts, iface: r.iface.to_owned(), frame: r.frame, dir: r.dir },
        other => panic!("{line:?}: expected a frame, got {other:?}"),
    }
}

fn frame(line: &str) -> Owned {
    frame_with(&mut LineParser::new(), line)
}

fn kind_of(line: &str) -> Line<'static> {
    match LineParser::new().parse(line.as_bytes()) {
        Ok(Line::Frame(r)) => panic!("{line:?}: unexpected frame {r:?}"),
        Ok(Line::Blank) => Line::Blank,
        Ok(Line::Comment) => Line::Comment,
        Ok(Line::DropCount { dropped }) => Line::DropCount { dropped },
        Ok(Line::ErrorText) => Line::ErrorText,
        Ok(Line::CanXl) => Line::CanXl,
        Err(e) => panic!("{line:?}: {e}"),
    }
}

fn error(line: &str) -> (usize, Reason) {
    match LineParser::new().parse(line.as_bytes()) {
        Err(LineError { column, reason }) => (column, reason),
        Ok(other) => panic!("{line:?}: accepted as {other:?}"),
    }
}

/// 1-based column of the first occurrence of `needle` in `line`.
fn col(line: &str, needle: &str) -> usize {
    line.find(needle).unwrap_or_else(|| panic!("{needle:?} not in {line:?}")) + 1
}

fn ts(secs: u64, nanos: u32, kind: TimestampKind) -> Option<Timestamp> {
    Some(Timestamp { secs, nanos, kind })
}

fn assert_frame(f: &CanFrame, id: u32, extended: bool, kind: FrameKind, data: &[u8]) {
    assert_eq!((f.id(), f.is_extended(), f.kind(), f.data()), (id, extended, kind, data), "{f}");
}

const TRACER_211: [u8; 8] = [0x00, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00, 0xB1];
const COUNTING: [u8; 8] = [0, 1, 2, 3, 4, 5, 6, 7];

// ---- log format ----

#[test]
fn log_basic_line() {
    let r = frame("(1700000000.002500) can0 211#00000103000000B1");
    assert_eq!(r.ts, ts(1_700_000_000, 2_500_000, ABS));
    assert_eq!(r.iface, "can0");
    assert_frame(&r.frame, 0x211, false, FrameKind::Data, &TRACER_211);
    assert_eq!((r.frame.len(), r.frame.raw_dlc(), r.frame.fd_flags()), (8, None, 0));
    assert_eq!(r.dir, None);
}

#[test]
fn log_padded_interface_and_direction_suffix() {
    let r = frame("(1600000000.000000)   can0 123#00");
    assert_eq!((r.iface.as_str(), r.ts), ("can0", ts(1_600_000_000, 0, ABS)));
    assert_frame(&r.frame, 0x123, false, FrameKind::Data, &[0]);
    let r = frame("(1600000000.000001) vcan10 311#FFFFFFC100000012 R");
    assert_eq!((r.iface.as_str(), r.dir), ("vcan10", Some(Direction::Rx)));
    assert_frame(&r.frame, 0x311, false, FrameKind::Data, &[0xFF, 0xFF, 0xFF, 0xC1, 0, 0, 0, 0x12]);
    let r = frame("(1600000000.000002)  slcan0 111#0000000000000000 T");
    assert_eq!((r.iface.as_str(), r.dir), ("slcan0", Some(Direction::Tx)));
    // Extra spaces around the suffix and a CR are tolerated.
    assert_eq!(frame("(1600000000.000002) can0 111#00  T \r").dir, Some(Direction::Tx));
}

#[test]
fn log_fractions_of_every_width_scale_to_nanoseconds() {
    assert_eq!(frame("(1700000000.123456789) can0 221#00").ts, ts(1_700_000_000, 123_456_789, ABS));
    assert_eq!(frame("(1614188635.1000000) can0 221#00").ts, ts(1_614_188_635, 100_000_000, ABS));
    assert_eq!(frame("(1700000000.5) can0 221#00").ts, ts(1_700_000_000, 500_000_000, ABS));
    // python-can writes `(%f)` without padding; small values read as relative.
    assert_eq!(frame("(0.000000) can0 221#00 R").ts, ts(0, 0, REL));
}

#[test]
fn log_relative_stamps_from_t_z() {
    let r = frame("(000.123456) can0 231#0001000000000000");
    assert_eq!(r.ts, ts(0, 123_456_000, REL));
    assert_eq!(frame("(99999999.999999) can0 231#00").ts, ts(99_999_999, 999_999_000, REL));
    assert_eq!(frame("(100000000.000000) can0 231#00").ts, ts(100_000_000, 0, ABS));
}

#[test]
fn log_remote_requests() {
    let r = frame("(1700000000.000000) can0 123#R");
    assert_frame(&r.frame, 0x123, false, FrameKind::Remote, &[]);
    assert_eq!(r.frame.len(), 0);
    assert_eq!(frame("(1700000000.000000) can0 123#R5").frame.len(), 5);
    let f = frame("(1700000000.000000) can0 123#R8_E").frame;
    assert_eq!((f.kind(), f.len(), f.raw_dlc()), (FrameKind::Remote, 8, Some(0xE)));
    let f = frame("(1700000000.000000) can0 00000123#r3 R").frame;
    assert_eq!((f.kind(), f.is_extended(), f.len()), (FrameKind::Remote, true, 3));
}

#[test]
fn log_raw_dlc_and_dot_separators() {
    let f = frame("(1700000000.000000) can0 123#1122334455667788_E").frame;
    assert_eq!((f.len(), f.raw_dlc()), (8, Some(14)));
    assert_eq!(f.data(), &[0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88]);
    let f = frame("(1700000000.000000) can0 5A1#11.2233.44556677.88").frame;
    assert_frame(&f, 0x5A1, false, FrameKind::Data, &[0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88]);
}

#[test]
fn log_can_fd_frames_keep_any_flags_nibble() {
    let f = frame("(1700000000.000000) can0 123##5001122").frame;
    assert_frame(&f, 0x123, false, FrameKind::Fd, &[0x00, 0x11, 0x22]);
    assert_eq!(f.fd_flags(), 5);
    for (nibble, flags) in [('0', 0), ('3', 3), ('7', 7), ('F', 15), ('b', 11)] {
        let line = format!("(1700000000.000000) can0 123##{nibble}");
        assert_eq!(frame(&line).frame.fd_flags(), flags);
    }
    let line = format!("(1700000000.000000) can0 1FFFFFFF##4{}", "AB".repeat(64));
    let f = frame(&line).frame;
    assert_eq!((f.id(), f.is_extended(), f.len()), (0x1FFF_FFFF, true, 64));
}

#[test]
fn log_error_frames_and_extended_ids() {
    let f = frame("(1700000000.000000) can0 20000004#0008000000007800").frame;
    assert_frame(&f, 0x4, true, FrameKind::Error, &[0, 8, 0, 0, 0, 0, 0x78, 0]);
    // python-can's error frame without data.
    let f = frame("(1700000000.000000) can0 20000080# R").frame;
    assert_frame(&f, 0x80, true, FrameKind::Error, &[]);
    let f = frame("(1700000000.000000) can0 00000123#11").frame;
    assert_frame(&f, 0x123, true, FrameKind::Data, &[0x11]);
    let f = frame("(1700000000.000000) can0 1FFFFFFF#").frame;
    assert_frame(&f, 0x1FFF_FFFF, true, FrameKind::Data, &[]);
}

#[test]
fn log_empty_payload_and_lowercase_hex() {
    assert_frame(&frame("(1700000000.000000) can0 421#").frame, 0x421, false, FrameKind::Data, &[]);
    let f = frame("(1700000000.000000) can0 2a1#abcdef").frame;
    assert_frame(&f, 0x2A1, false, FrameKind::Data, &[0xAB, 0xCD, 0xEF]);
}

#[test]
fn log_crlf_line_endings() {
    let r = frame("(1700000000.002500) can0 211#00000103000000B1\r");
    assert_frame(&r.frame, 0x211, false, FrameKind::Data, &TRACER_211);
    assert_eq!(frame("(1700000000.002500) can0 211#00 R\r").dir, Some(Direction::Rx));
    assert_eq!(frame("(1700000000.002500) can0 20000080#\r").frame.kind(), FrameKind::Error);
}

#[test]
fn log_without_timestamp() {
    let r = frame("can0 211#00000103000000B1");
    assert_eq!((r.ts, r.iface.as_str()), (None, "can0"));
}

#[test]
fn can_xl_lines_are_recognised() {
    assert_eq!(kind_of("(1700000000.000000) can0 45123#81:00:12345678#112233"), Line::CanXl);
    assert_eq!(kind_of("(1700000000.000000) can0 45123#81:00:12345678# R"), Line::CanXl);
    assert_eq!(kind_of(" (000.000000)  xl0  123 [0003] (45|81:00:12345678) 11 22 33"), Line::CanXl);
    let line = "(1700000000.000000) can0 45123#81:00:1234567Z#11";
    assert_eq!(error(line), (col(line, "Z"), Reason::BadXlFrame));
}

// ---- non-frame lines ----

#[test]
fn blank_comment_dropcount_and_error_text_lines() {
    for line in ["", "   ", "\r", "  \r"] {
        assert_eq!(kind_of(line), Line::Blank, "{line:?}");
    }
    for line in ["# recorded on the bench", "  ; notes", ";", "#"] {
        assert_eq!(kind_of(line), Line::Comment, "{line:?}");
    }
    assert_eq!(
        kind_of("DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 7)"),
        Line::DropCount { dropped: 3 }
    );
    assert_eq!(
        kind_of("DROPCOUNT: dropped 1 CAN frame on 'any' socket (total drops 1)\r"),
        Line::DropCount { dropped: 1 }
    );
    // candump prints the u32 count with %d.
    assert_eq!(
        kind_of("DROPCOUNT: dropped -1 CAN frames on 'can0' socket (total drops -1)"),
        Line::DropCount { dropped: u64::from(u32::MAX) }
    );
    // TAB-indented error text is only text after an error frame (see console_error_frames_and_their_text).
    assert_eq!(error("\tcontroller-problem{tx-error-warning}"), (1, Reason::StrayErrorText));
    assert_eq!(error("DROPCOUNT: lost some"), (1, Reason::BadDropCount));
    assert_eq!(error("DROPCOUNT: dropped many CAN frames"), (20, Reason::BadDropCount));
}

// ---- console format ----

#[test]
fn console_with_absolute_stamp() {
    let r = frame(" (1600000000.123456)  can0  151   [8]  00 01 02 03 04 05 06 07");
    assert_eq!((r.ts, r.iface.as_str(), r.dir), (ts(1_600_000_000, 123_456_000, ABS), "can0", None));
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, &COUNTING);
}

#[test]
fn console_without_stamp() {
    let r = frame("  can0  151   [8]  00 01 02 03 04 05 06 07");
    assert_eq!((r.ts, r.iface.as_str()), (None, "can0"));
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, &COUNTING);
    let r = frame("  can0  421   [1]  01");
    assert_frame(&r.frame, 0x421, false, FrameKind::Data, &[1]);
    assert_frame(&frame("  can0  421   [0]").frame, 0x421, false, FrameKind::Data, &[]);
    // Any run of spaces between columns is tolerated.
    assert_frame(&frame("can0 421 [2] 01    02").frame, 0x421, false, FrameKind::Data, &[1, 2]);
}

#[test]
fn console_date_time_stamp_is_taken_as_utc() {
    let r = frame(" (2020-12-19 12:04:45.485261)  can0  211   [8]  00 00 01 03 00 00 00 B1");
    assert_eq!(r.ts, ts(1_608_379_485, 485_261_000, ABS));
    assert_frame(&r.frame, 0x211, false, FrameKind::Data, &TRACER_211);
}

#[test]
fn console_relative_stamps_since_start() {
    let mut parser = LineParser::new();
    let first = frame_with(&mut parser, " (000.000000)  can0  221   [8]  00 00 00 00 00 00 00 01");
    let later = frame_with(&mut parser, " (000.020000)  can0  221   [8]  00 00 00 00 00 00 00 02");
    assert_eq!((first.ts, later.ts), (ts(0, 0, REL), ts(0, 20_000_000, REL)));
}

#[test]
fn console_deltas_accumulate_when_asked() {
    let mut parser = LineParser::new().with_delta_timestamps();
    let stamps: Vec<_> = [
        " (000.000000)  can0  221   [8]  00 00 00 00 00 00 00 01",
        " (000.600000)  can0  221   [8]  00 00 00 00 00 00 00 02",
        "\tnot a frame",
        " (000.600000)  can0  221   [8]  00 00 00 00 00 00 00 03",
        " (001.000001)  can0  221   [8]  00 00 00 00 00 00 00 04",
    ]
    .iter()
    .filter_map(|line| match parser.parse(line.as_bytes()) {
        Ok(Line::Frame(r)) => r.ts,
        _ => None,
    })
    .collect();
    let expected = [(0, 0), (0, 600_000_000), (1, 200_000_000), (2, 200_001_000)]
        .map(|(secs, nanos)| Timestamp { secs, nanos, kind: REL });
    assert_eq!(stamps, expected);
    // Absolute console stamps and log lines are not deltas.
    assert_eq!(
        frame_with(&mut parser, " (1600000000.000000)  can0  221   [0]").ts,
        ts(1_600_000_000, 0, ABS)
    );
    assert_eq!(frame_with(&mut parser, "(000.500000) can0 221#").ts, ts(0, 500_000_000, REL));
    parser.reset();
    assert_eq!(frame_with(&mut parser, " (000.100000)  can0  221   [0]").ts, ts(0, 100_000_000, REL));
}

#[test]
fn console_extra_message_info() {
    let r = frame("  can0  RX - -  151   [8]  00 01 02 03 04 05 06 07");
    assert_eq!(r.dir, Some(Direction::Rx));
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, &COUNTING);
    let r = frame(" (1600000000.000000)  can0  TX - -  111   [8]  00 00 00 00 00 00 00 00");
    assert_eq!((r.dir, r.ts), (Some(Direction::Tx), ts(1_600_000_000, 0, ABS)));
    // B/E are BRS/ESI; FDF is always reported for FD frames.
    for (info, flags) in [("- -", 4), ("B -", 5), ("- E", 6), ("B E", 7)] {
        let r = frame(&format!("  can0  RX {info}  151  [12]  00 01 02 03 04 05 06 07 08 09 0A 0B"));
        assert_eq!((r.frame.kind(), r.frame.fd_flags(), r.frame.len()), (FrameKind::Fd, flags, 12), "{info}");
    }
    // On classic frames the flag columns carry no information.
    assert_eq!(frame("  can0  RX B E  151   [1]  00").frame.kind(), FrameKind::Data);
    let line = "  can0  RX X -  151   [1]  00";
    assert_eq!(error(line), (col(line, "X -"), Reason::BadMessageInfo));
    let line = "  can0  RX -  151   [1]  00";
    assert_eq!(error(line), (col(line, "151"), Reason::BadMessageInfo));
}

#[test]
fn console_colour_codes_are_stripped() {
    let line =
        " \x1b[1;31m(1600000000.123456) \x1b[1;31mcan0\x1b[0m  151   [8]  00 01 02 03 04 05 06 07\x1b[0m";
    let r = frame(line);
    assert_eq!((r.ts, r.iface.as_str()), (ts(1_600_000_000, 123_456_000, ABS), "can0"));
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, &COUNTING);
    let r = frame("  \x1b[32mcan1\x1b[0m  RX - -  \x1b[1m251\x1b[m   [8]  00 00 00 0F 00 00 00 54");
    assert_eq!((r.iface.as_str(), r.dir), ("can1", Some(Direction::Rx)));
    assert_frame(&r.frame, 0x251, false, FrameKind::Data, &[0, 0, 0, 0x0F, 0, 0, 0, 0x54]);
    // The scratch buffer is reused: a second coloured line parses independently.
    let mut parser = LineParser::new();
    let a = frame_with(&mut parser, "\x1b[31m  can0  111   [1]  01\x1b[0m");
    let b = frame_with(&mut parser, "\x1b[31m  can9  112   [1]  02\x1b[0m");
    assert_eq!(
        (a.iface.as_str(), a.frame.id(), b.iface.as_str(), b.frame.id()),
        ("can0", 0x111, "can9", 0x112)
    );
}

#[test]
fn console_sff_indent_after_eff() {
    let r = frame("  can0  12345678   [8]  00 01 02 03 04 05 06 07");
    assert_frame(&r.frame, 0x1234_5678, true, FrameKind::Data, &COUNTING);
    let r = frame("  can0       151   [8]  00 01 02 03 04 05 06 07");
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, &COUNTING);
}

#[test]
fn console_ascii_column() {
    let r = frame("  can0  151   [8]  41 42 43 44 45 46 47 48   'ABCDEFGH'");
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, b"ABCDEFGH");
    // Whatever is between the quotes, including quotes and spaces.
    let r = frame("  can0  151   [3]  27 20 41                  '' A'");
    assert_frame(&r.frame, 0x151, false, FrameKind::Data, &[0x27, 0x20, 0x41]);
    assert_frame(
        &frame("  can0  151   [0]                            ''").frame,
        0x151,
        false,
        FrameKind::Data,
        &[],
    );
    let line = "  can0  151   [8]  41 42 43 44 45 46 47 48   'ABCDEFGH";
    assert_eq!(error(line), (col(line, "'"), Reason::TrailingGarbage));
}

#[test]
fn console_remote_requests() {
    let f = frame("  can0  151   [0]  remote request").frame;
    assert_eq!((f.kind(), f.len(), f.is_extended()), (FrameKind::Remote, 0, false));
    let f = frame("  can0  12345678   [5]  remote request").frame;
    assert_eq!((f.kind(), f.len(), f.is_extended()), (FrameKind::Remote, 5, true));
    let f = frame("  can0  151   {E}  remote request").frame;
    assert_eq!((f.kind(), f.len(), f.raw_dlc()), (FrameKind::Remote, 8, Some(0xE)));
}

#[test]
fn console_raw_dlc_in_braces() {
    let f = frame("  can0  151   {9}  00 01 02 03 04 05 06 07").frame;
    assert_eq!((f.len(), f.raw_dlc()), (8, Some(9)));
    assert_eq!(f.data(), &COUNTING);
    assert_eq!(frame("  can0  151   {F}  00 01 02 03 04 05 06 07").frame.raw_dlc(), Some(15));
    let f = frame("  can0  151   {8}  00 01 02 03 04 05 06 07").frame;
    assert_eq!((f.len(), f.raw_dlc()), (8, None));
    let f = frame("  can0  151   {3}  00 01 02").frame;
    assert_eq!((f.len(), f.raw_dlc(), f.data()), (3, None, &[0, 1, 2][..]));
    let line = "  can0  151   {G}  00";
    assert_eq!(error(line), (col(line, "{"), Reason::BadLength));
}

#[test]
fn console_fd_two_digit_lengths() {
    let f = frame("  can0  151  [08]  00 01 02 03 04 05 06 07").frame;
    assert_eq!((f.kind(), f.len(), f.fd_flags(), f.data()), (FrameKind::Fd, 8, 4, &COUNTING[..]));
    let twelve = frame("  can0  151  [12]  00 01 02 03 04 05 06 07 08 09 0A 0B").frame;
    assert_eq!((twelve.kind(), twelve.len()), (FrameKind::Fd, 12));
    let bytes: Vec<String> = (0..64).map(|i| format!("{i:02X}")).collect();
    let f = frame(&format!("  can0  1FFFFFFF  [64]  {}", bytes.join(" "))).frame;
    assert_eq!((f.len(), f.is_extended(), f.data()[63]), (64, true, 63));
    let line = "  can0  151  [09]  00 01 02 03 04 05 06 07 08";
    assert_eq!(error(line), (col(line, "["), Reason::BadFdLength));
}

#[test]
fn console_error_frames_and_their_text() {
    let line =
        " (2023-02-06 16:15:05.259679)  can0  RX - -  20000004   [8]  00 08 00 00 00 00 78 00   ERRORFRAME";
    let r = frame(line);
    assert_frame(&r.frame, 0x4, true, FrameKind::Error, &[0, 8, 0, 0, 0, 0, 0x78, 0]);
    assert_eq!((r.dir, r.ts.map(|t| t.kind)), (Some(Direction::Rx), Some(ABS)));
    let r = frame("  can0  20000080   [0]                                ERRORFRAME");
    assert_frame(&r.frame, 0x80, true, FrameKind::Error, &[]);
    let mut parser = LineParser::new();
    frame_with(&mut parser, "  can0  20000080   [0]                                ERRORFRAME");
    for text in ["\tcontroller-problem{tx-error-warning}", "\terror-counter-tx-rx{{120}{0}}"] {
        assert_eq!(parser.parse(text.as_bytes()), Ok(Line::ErrorText), "{text}");
    }
    let line = "  can0  00000004   [1]  00   ERRORFRAME";
    assert_eq!(error(line), (col(line, "ERR"), Reason::TrailingGarbage));
}

#[test]
fn console_dropcount() {
    assert_eq!(
        kind_of("DROPCOUNT: dropped 12 CAN frames on 'can0' socket (total drops 12)"),
        Line::DropCount { dropped: 12 }
    );
}

// ---- fast path ----

#[test]
fn fast_path_and_general_path_agree() {
    let lines = [
        "(1700000000.002500) can0 211#00000103000000B1",
        "(1700000000.002500)    can0 211#00000103000000B1 R",
        "(000.100000) vcan12 00000123#1122 T",
        "(1.5) can0 421#\r",
        "(1700000000.002500) abcdefghijklmno 7FF#FF",
    ];
    for line in lines {
        let fast = super::line::parse_log_fast_for_tests(line.as_bytes());
        let general = super::line::parse_general_for_tests(line.as_bytes());
        assert!(fast.is_some(), "{line:?} should take the fast path");
        assert_eq!(fast, general, "{line:?}");
    }
    // Lines the fast path leaves to the general one.
    for line in [
        "(1700000000.002500) can0 20000004#00",
        "(1700000000.002500) can0 211#00.01",
        "(1700000000.002500) can0 211#R",
        "(1700000000.002500) can0 211##100",
        "(1700000000.002500) can0 211#0011 ",
        "(1700000000.002500) can0 FFF#00",
        "(1700000000.002500) can0 211#001",
        "(1700000000.002500) can0 211#001122334455667788",
    ] {
        assert_eq!(super::line::parse_log_fast_for_tests(line.as_bytes()), None, "{line:?}");
    }
}

// ---- bad lines ----

#[test]
fn bad_log_lines_report_column_and_reason() {
    let cases: &[(&str, &str, Reason)] = &[
        ("(1700000000.002500) can0 211#0000010300000B1", "1", Reason::OddHexDigits),
        ("(1700000000.002500) can0 211#00000103000000B1FF", "FF", Reason::TooManyBytes),
        ("(1700000000.002500) can0 211#0000010300000XB1", "XB1", Reason::NotHex),
        ("(1700000000.002500) can0 21#00", "21#", Reason::IdLength),
        ("(1700000000.002500) can0 2111#00", "2111", Reason::IdLength),
        ("(1700000000.002500) can0 211000000#00", "211000000", Reason::IdLength),
        ("(1700000000.002500) can0 G11#00", "G11", Reason::NotHex),
        ("(1700000000.002500) can0 21100000103000000B1", "", Reason::MissingHash),
        ("(1700000000.002500 can0 211#00", "(", Reason::UnterminatedTimestamp),
        ("(1700000000.0025x0) can0 211#00", "x", Reason::BadTimestamp),
        ("(1700000000) can0 211#00", ")", Reason::BadTimestamp),
        ("(1700000000.0000000000) can0 211#00", "0000000000)", Reason::TimestampFraction),
        ("(123456789012345678901.0) can0 211#00", "1", Reason::TimestampTooLarge),
        ("(1700000000.002500)can0 211#00", "can0", Reason::ExpectedSpace),
        ("(1700000000.002500) 211#00", "211", Reason::MissingInterface),
        ("(1700000000.002500)", "", Reason::MissingInterface),
        ("(1700000000.002500) can0", "", Reason::MissingFrame),
        ("(1700000000.002500) averyveryverylongname 211#00", "avery", Reason::InterfaceTooLong),
        ("(1700000000.002500) can\u{7f} 211#00", "\u{7f}", Reason::BadInterface),
        ("(1700000000.002500) can0 800#00", "800", Reason::SffIdTooLarge),
        ("(1700000000.002500) can0 40000000#00", "4000", Reason::IdTooLarge),
        ("(1700000000.002500) can0 211#00..11", ".11", Reason::BadSeparator),
        ("(1700000000.002500) can0 123##4000102030405060708", "000102", Reason::BadFdLength),
        ("(1700000000.002500) can0 123##", "", Reason::BadFdFlags),
        ("(1700000000.002500) can0 123#R9", "9", Reason::BadRemoteLength),
        ("(1700000000.002500) can0 123#11_E", "_", Reason::BadRawDlc),
        ("(1700000000.002500) can0 20000004#R", "R", Reason::ErrorFrameNotData),
        ("(1700000000.002500) can0 211#00 X", "X", Reason::TrailingGarbage),
        ("(1700000000.002500) can0 211#00 R T", "R T", Reason::TrailingGarbage),
        ("(1700000000.002500) can0 211#00 RX", "RX", Reason::TrailingGarbage),
    ];
    for &(line, at, reason) in cases {
        let expected_col = if at.is_empty() { line.len() + 1 } else { col(line, at) };
        let expected_col = match reason {
            Reason::OddHexDigits => line.len(),
            Reason::MissingFrame | Reason::BadFdFlags if at.is_empty() => line.len() + 1,
            _ => expected_col,
        };
        assert_eq!(error(line), (expected_col, reason), "{line:?}");
    }
}

#[test]
fn bad_console_lines_report_column_and_reason() {
    let cases: &[(&str, &str, Reason)] = &[
        ("  can0  151   [8]  00 01 02 03 04 05 06", "", Reason::LengthMismatch),
        ("  can0  151   [2]  00 01 02", "02", Reason::LengthMismatch),
        ("  can0  151   [8]  00 01   'AB'", "'AB'", Reason::LengthMismatch),
        ("  can0  151   [9]  00", "[", Reason::BadLength),
        ("  can0  151   [8  00", "[", Reason::BadLength),
        ("  can0  151   [123]  00", "[", Reason::BadLength),
        ("  can0  151   [1]  0G", "0G", Reason::ConsoleByte),
        ("  can0  151   [1]  001", "001", Reason::ConsoleByte),
        ("  can0  15    [1]  00", "15", Reason::IdLength),
        ("  can0  1G1   [1]  00", "G", Reason::NotHex),
        ("  can0  951   [1]  00", "951", Reason::SffIdTooLarge),
        ("  can0  151   [1]  00 zz", "zz", Reason::TrailingGarbage),
        ("  can0  151   [0]  remote request now", "now", Reason::TrailingGarbage),
        ("  can0  20000001   [0]  remote request", "remote", Reason::ErrorFrameNotData),
        ("  can0  20000001  [12]  00 00 00 00 00 00 00 00 00 00 00 00", "[", Reason::ErrorFrameNotData),
        ("  can0  151   [1]00", "]00", Reason::ExpectedSpace),
        (" (1600000000.1234567890)  can0  151   [0]", "1234567890", Reason::TimestampFraction),
        (" (2020-02-30 00:00:00.000000)  can0  151   [0]", "2020", Reason::BadDateTime),
        ("  averyveryverylongname  151   [0]", "avery", Reason::InterfaceTooLong),
        ("hello world", "hello", Reason::NotCandump),
        ("  hello brave new world", "hello", Reason::NotCandump),
        ("ERROR: something went wrong", "ERROR", Reason::NotCandump),
        ("  words", "words", Reason::NotCandump),
        ("211#00000103000000B1", "211", Reason::MissingInterface),
    ];
    for &(line, at, reason) in cases {
        let expected_col = match at {
            "" => line.len() + 1,
            "]00" => col(line, at) + 1,
            _ => col(line, at),
        };
        assert_eq!(error(line), (expected_col, reason), "{line:?}");
    }
}

#[test]
fn columns_of_coloured_lines_refer_to_the_text_without_colour_codes() {
    assert_eq!(error("\x1b[31m  can0  151   [1]  0G\x1b[0m"), (20, Reason::ConsoleByte));
}

#[test]
fn never_panics_on_awkward_input() {
    let awkward: &[&[u8]] = &[
        b"(",
        b"()",
        b"(.",
        b"(1.",
        b"(1.1",
        b"(1.1)",
        b"(1.1) ",
        b"(1.1) c",
        b"(1.1) c 1",
        b"(1.1) c 123#",
        b"(1.1) c 123##",
        b"(1.1) c 12345678#",
        b"(1.1) c 45123#",
        b"(1.1) c 45123#11:",
        b"(1.1) c 45123#11:22:33333333#1",
        b"(2020-",
        b"(2020-01-01 00:00:00.",
        b"\x1b",
        b"\x1b[",
        b"\x1b[1;",
        b"  can0  RX",
        b"  can0  RX -",
        b"  can0  RX - -",
        b"  can0  151 [",
        b"  can0  151 {",
        b"  can0  151 {9",
        b"  can0  151 [8] ",
        b"DROPCOUNT:",
        b"DROPCOUNT: dropped -",
        b"DROPCOUNT: dropped -99999999999999999999 CAN frames",
        b"\xff\xfe\x00",
        b"(1700000000.002500) \xc3\xa9 211#00",
    ];
    let mut parser = LineParser::new().with_delta_timestamps();
    for line in awkward {
        let _ = parser.parse(line);
    }
    assert_eq!(error("(1700000000.002500) \u{e9} 211#00"), (21, Reason::BadInterface));
}

mod fast_path_props {
    use proptest::collection::vec;
    use proptest::prelude::*;

    use super::super::line::{parse_general_for_tests, parse_log_fast_for_tests};

    proptest! {
        /// Every line the fast path accepts reads the same through the general path.
        #[test]
        fn fast_path_agrees_with_general_path(
            secs in "[0-9]{1,12}",
            frac in "[0-9]{1,9}",
            pad in " {0,3}",
            iface in "[!-~]{1,15}",
            id in prop_oneof!["[0-9A-Fa-f]{3}", "[0-9A-Fa-f]{8}"],
            data in vec(any::<u8>(), 0..=9),
            lower in any::<bool>(),
            suffix in prop_oneof![Just(""), Just(" R"), Just(" T"), Just(" X"), Just("  R"), Just("\r"), Just(" T\r")],
        ) {
            let hex: String = data.iter().map(|b| format!("{b:02X}")).collect();
            let hex = if lower { hex.to_lowercase() } else { hex };
            let line = format!("({secs}.{frac}) {pad}{iface} {id}#{hex}{suffix}");
            let fast = parse_log_fast_for_tests(line.as_bytes());
            let general = parse_general_for_tests(line.as_bytes());
            if fast.is_some() {
                prop_assert_eq!(fast, general, "{:?}", line);
            }
        }

        /// Lines read where they stand in a buffer (`\n` or `\r\n` after each) end at their newline and read
        /// as `parse` reads each line alone; lines not taken there are left whole to `parse`.
        #[test]
        fn lines_parsed_in_a_buffer_agree_with_lines_parsed_alone(
            lines in vec(prop_oneof![
                "\\([0-9]{1,10}\\.[0-9]{1,6}\\) {1,2}(can0|vcan1|c) ([0-9A-F]{3}|[0-9A-F]{8})#([0-9A-Fa-f]{2}){0,9}( R| T| X)?\r?",
                "[ -~\t\r]{0,40}",
            ], 1..12),
            crlf in any::<bool>(),
        ) {
            let newline = if crlf { "\r\n" } else { "\n" };
            let text = lines.join(newline);
            let mut in_buffer = super::LineParser::new();
            let mut alone = super::LineParser::new();
            let mut at = 0;
            while at < text.len() {
                let rest = &text.as_bytes()[at..];
                let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
                let expected = match alone.parse(&rest[..end]) {
                    Ok(super::Line::Frame(record)) => Some(format!("{record:?}")),
                    _ => None,
                };
                if let Some((record, length)) = in_buffer.parse_log_line_at(rest) {
                    prop_assert_eq!(length, end, "{:?}", text);
                    prop_assert_eq!(Some(format!("{:?}", record.to_record())), expected, "{:?}", text);
                } else {
                    let _ = in_buffer.parse(&rest[..end]);
                }
                at += end + 1;
            }
        }
    }
}

/// A buffer of lines read where each line stands: the line's length is found by parsing it, and the record
/// is the one `parse` gives for that line alone, whatever follows it (the next line, `\r\n`, the end).
#[test]
fn log_lines_parsed_where_they_stand_end_where_their_newline_is() {
    let lines = [
        "(1700000000.002500) can0 211#00000103000000B1",
        "(1700000000.002500) can0 211#00000103000000B1 R",
        "(1700000000.002500) can0 211#00000103000000B1\r",
        "(1700000000.002500) can0 211#00000103000000B1 T\r",
        "(000.100000) vcan12 00000123#1122 T",
        "(1.5) can0 421#",
        "(1.5) can0 421#\r",
        "(1.5) can0 421#00",
        "(1.5) can0 421#00 R",
    ];
    for line in lines {
        for after in ["", "\n", "\n(1700000000.002500) can0 211#00", "\n\n", "\n0000000000000000 R"] {
            let text = format!("{line}{after}");
            let mut parser = LineParser::new();
            let (record, length) = parser.parse_log_line_at(text.as_bytes()).expect(&text);
            let (ts, iface, frame, dir) = (record.ts, record.iface.to_owned(), *record.frame, record.dir);
            assert_eq!(length, line.len(), "{text:?}");
            let alone = frame_with(&mut LineParser::new(), line);
            assert_eq!((ts, iface, frame, dir), (alone.ts, alone.iface, alone.frame, alone.dir), "{text:?}");
        }
    }
    // A line of this shape past the reader's limit (spaces after the stamp) is left to the caller, who
    // rejects it whole, and leaves the parser as it was (an error frame's text may follow).
    let long = format!("(1700000000.002500){}can0 211#00\n", " ".repeat(super::DEFAULT_MAX_LINE_LEN));
    let mut parser = LineParser::new();
    let error_frame = " (000.000000)  can0  20000080   [8]  00 00 00 00 00 00 00 00   ERRORFRAME";
    assert!(matches!(parser.parse(error_frame.as_bytes()), Ok(Line::Frame(_))));
    assert!(parser.parse_log_line_at(long.as_bytes()).is_none());
    assert_eq!(parser.parse(b"\tbus-off"), Ok(Line::ErrorText));
    // Lines the general path reads (or rejects): not taken, whatever follows.
    for line in [
        "(1700000000.002500) can0 211#00 X",
        "(1700000000.002500) can0 211#00\r\r",
        "(1700000000.002500) can0 211#00\r R",
        "(1700000000.002500) can0 211#0",
        "(1700000000.002500) can0 211#00.11",
        "can0  211   [2]  00 11",
        "# comment",
    ] {
        for after in ["", "\n", "\n(1700000000.002500) can0 211#00"] {
            let text = format!("{line}{after}");
            assert!(LineParser::new().parse_log_line_at(text.as_bytes()).is_none(), "{text:?}");
        }
    }
}

/// The fast path takes the last line's interface when the same name and a space follow the stamp; every
/// other name (longer, shorter, a prefix, one byte changed, not printable) is scanned as before.
#[test]
fn log_interface_names_change_from_line_to_line() {
    let mut parser = LineParser::new();
    let line = |iface: &str| format!("(1700000000.002500) {iface} 211#00000103000000B1");
    for iface in [
        "can0",
        "can0",
        "can01",
        "can0",
        "can1",
        "vcan0",
        "c",
        "c",
        "abcdefghijklmno",
        "abcdefghijklmno",
        "can0",
    ] {
        assert_eq!(frame_with(&mut parser, &line(iface)).iface, iface);
    }
    // A name of 16 bytes, or with a byte that is not printable ASCII, is not an interface.
    assert!(parser.parse(line("abcdefghijklmnop").as_bytes()).is_err());
    assert!(parser.parse(line("can\u{7f}").as_bytes()).is_err());
    assert_eq!(frame_with(&mut parser, &line("can0")).iface, "can0");
    // The last name followed by more name is another name.
    assert_eq!(frame_with(&mut parser, &line("can0x")).iface, "can0x");
    assert_eq!(frame_with(&mut parser, "(1700000000.002500) can0x  211#00").iface, "can0x");
}
