//! The other line formats: candump's -S and -i views, Pengutronix canutils, TAB-indented lines, Vector
//! ASC and PEAK trc lines.

use super::{
    Direction, Line, LineError, LineParser, LogFormat, Reason, TextFormat, Timestamp, TimestampKind,
};
use crate::protocol::{CanFrame, FrameKind};

#[derive(Debug, PartialEq)]
enum Parsed {
    Frame { ts: Option<Timestamp>, iface: String, frame: CanFrame, dir: Option<Direction> },
    Other(String),
    Rejected(LineError),
}

fn parse_all(parser: &mut LineParser, lines: &[&str]) -> Vec<Parsed> {
    lines
        .iter()
        .map(|line| match parser.parse(line.as_bytes()) {
            Ok(Line::Frame(r)) => {
                Parsed::Frame { ts: r.ts, iface: r.iface.into(), frame: r.frame, dir: r.dir }
            }
            Ok(other) => Parsed::Other(format!("{other:?}")),
            Err(error) => Parsed::Rejected(error),
        })
        .collect()
}

fn parser(text: TextFormat) -> LineParser {
    LineParser::for_format(LogFormat { text, compression: None })
}

fn rel(secs: u64, nanos: u32) -> Option<Timestamp> {
    Some(Timestamp { secs, nanos, kind: TimestampKind::Relative })
}

fn abs(secs: u64, nanos: u32) -> Option<Timestamp> {
    Some(Timestamp { secs, nanos, kind: TimestampKind::Absolute })
}

#[test]
fn asc_dates_in_every_shape_start_the_clock() {
    let local = |civil| super::timestamp::local_to_epoch(civil).unwrap();
    let cases = [
        ("date Sam Sep 30 15:06:13.191 2017", local([2017, 9, 30, 15, 6, 13]), 191_000_000),
        ("date Thu Mar 5 03:06:13 pm 2020", local([2020, 3, 5, 15, 6, 13]), 0),
        ("date Do Okt 1 12:00:00.5 am 2020", local([2020, 10, 1, 0, 0, 0]), 500_000_000),
        ("Begin Triggerblock Di Dez 1 08:00:00.000 2020", local([2020, 12, 1, 8, 0, 0]), 0),
    ];
    for (header, secs, nanos) in cases {
        let parsed = parse_all(&mut parser(TextFormat::VectorAsc), &[header, "   1.250000 1  211 Rx d 1 00"]);
        let nanos = nanos + 250_000_000;
        let ts = abs(secs + 1 + u64::from(nanos / 1_000_000_000), nanos % 1_000_000_000);
        assert_eq!(
            parsed[1],
            Parsed::Frame { ts, iface: "can1".into(), frame: data(0x211, &[0]), dir: Some(Direction::Rx) },
            "{header}"
        );
    }
    // A date that does not read leaves the stamps relative.
    let parsed =
        parse_all(&mut parser(TextFormat::VectorAsc), &["date soon", "   1.250000 1  211 Rx d 1 00"]);
    assert!(matches!(&parsed[1], Parsed::Frame { ts, .. } if *ts == rel(1, 250_000_000)));
}

#[test]
fn trc_start_time_puts_the_stamps_on_the_clock() {
    // 46350.5 days after 1899-12-30 is 2026-11-24 12:00:00 UTC (python-can: 1795521600.0).
    for version in ["1.1", "1.3", "2.0", "2.1"] {
        let line = match version {
            "1.1" => "     1)        20.0  Rx         0211  2  00 B1 ",
            "1.3" => "     1)        20.000 1  Rx        0211 -   2    00 B1",
            "2.0" => "      1        20.000 DT     0211 Rx 2 00 B1",
            _ => "      1        20.000 DT 1      0211 Rx -  2    00 B1",
        };
        let version_line = format!(";$FILEVERSION={version}");
        let lines = [";$STARTTIME=46350.5", &version_line, line];
        let parsed = parse_all(&mut parser(TextFormat::PeakTrc { version: 10 }), &lines);
        assert!(
            matches!(&parsed[2], Parsed::Frame { ts, .. } if *ts == abs(1_795_521_600, 20_000_000)),
            "{version}: {:?}",
            parsed[2]
        );
    }
    assert_eq!(
        super::trc::start_time(b"45000.123456789"),
        Some((1_678_849_066, 666_569_000)),
        "as python-can"
    );
}

fn data(id: u32, bytes: &[u8]) -> CanFrame {
    CanFrame::new(id, bytes).unwrap()
}

fn frame_of(parsed: &Parsed) -> CanFrame {
    match parsed {
        Parsed::Frame { frame, .. } => *frame,
        other => panic!("expected a frame, got {other:?}"),
    }
}

#[test]
fn candump_swapped_view_is_read_in_wire_order() {
    let mut p = LineParser::new();
    let parsed = parse_all(
        &mut p,
        &[
            "  can0  211   [8]  B1`00`00`00`03`01`00`00",
            "  can0  421   [1]  01",
            "  vcan10  18FF0001   [2]  02`01   `..`",
            "    can0       123  [12]  BB`AA`99`88`77`66`55`44`33`22`11`00",
            "    can0  20000004   [8]  00`78`00`00`00`00`08`00   ERRORFRAME",
        ],
    );
    assert_eq!(frame_of(&parsed[0]), data(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]));
    assert_eq!(frame_of(&parsed[1]), data(0x421, &[1]));
    assert_eq!(frame_of(&parsed[2]), CanFrame::new_extended(0x18FF0001, &[1, 2]).unwrap());
    let fd = frame_of(&parsed[3]);
    assert_eq!(
        (fd.kind(), fd.data()),
        (FrameKind::Fd, &[0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99, 0xAA, 0xBB][..])
    );
    assert_eq!(frame_of(&parsed[4]).data(), &[0, 8, 0, 0, 0, 0, 0x78, 0]);
    // One byte too few or a broken separator is still an error.
    let bad = parse_all(&mut p, &["  can0  211   [3]  B1`00", "  can0  211   [2]  B1'00"]);
    assert!(matches!(bad[0], Parsed::Rejected(LineError { reason: Reason::LengthMismatch, .. })), "{bad:?}");
    assert!(matches!(bad[1], Parsed::Rejected(_)), "{bad:?}");
}

#[test]
fn candump_binary_view_is_read() {
    let parsed = parse_all(
        &mut LineParser::new(),
        &[
            "  can0  211   [8]  00000000 00000000 00000001 00000011 00000000 00000000 00000000 10110001",
            "  can0  421   [1]  00000001",
            "  vcan10  123   [0] ",
            "  can0  221   [2]  00000001 0000001",
        ],
    );
    assert_eq!(frame_of(&parsed[0]), data(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]));
    assert_eq!(frame_of(&parsed[1]), data(0x421, &[1]));
    assert_eq!(frame_of(&parsed[2]), data(0x123, &[]));
    assert!(
        matches!(parsed[3], Parsed::Rejected(LineError { reason: Reason::LengthMismatch, .. })),
        "{parsed:?}"
    );
}

#[test]
fn pengutronix_candump_lines_take_the_interface_from_the_header() {
    let mut p = LineParser::new();
    let before = parse_all(&mut p, &["<0x211> [1] 01 "]);
    assert_eq!(before[0], Parsed::Frame { ts: None, iface: "-".into(), frame: data(0x211, &[1]), dir: None });
    let parsed = parse_all(
        &mut p,
        &[
            "interface = can1, family = 29, type = 3, proto = 1",
            "<0x18eeff01> [8] 05 a0 be 1c 00 a0 a0 c0 ",
            "<0x123> [2] remote request",
            "<0x123> [2] 01 ",
            "<0x123> [1] 01 02 ",
        ],
    );
    assert_eq!(parsed[0], Parsed::Other("Comment".into()));
    let frame = CanFrame::new_extended(0x18EEFF01, &[5, 0xA0, 0xBE, 0x1C, 0, 0xA0, 0xA0, 0xC0]).unwrap();
    assert_eq!(parsed[1], Parsed::Frame { ts: None, iface: "can1".into(), frame, dir: None });
    assert_eq!(frame_of(&parsed[2]), CanFrame::new_remote(0x123, false, 2).unwrap());
    assert!(matches!(parsed[3], Parsed::Rejected(LineError { reason: Reason::LengthMismatch, .. })));
    assert!(matches!(parsed[4], Parsed::Rejected(LineError { reason: Reason::LengthMismatch, .. })));
}

#[test]
fn tab_lines_are_error_text_only_after_an_error_frame() {
    let mut p = LineParser::new();
    let parsed = parse_all(
        &mut p,
        &[
            "\t(1700000000.000000) can0 211#00000103000000B1",
            "\t  can0  421   [1]  01",
            "\tcontroller-problem{tx-error-warning}",
            "    can0  20000004   [8]  00 08 00 00 00 00 78 00   ERRORFRAME",
            "\tcontroller-problem{tx-error-warning}",
            "\terror-counter-tx-rx{{120}{0}}",
            "(1700000000.000000) can0 211#00000103000000B1",
            "\tbus-off",
            "\t(1700000000.000000) can0 211#0G",
        ],
    );
    assert_eq!(frame_of(&parsed[0]), data(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]));
    assert_eq!(frame_of(&parsed[1]), data(0x421, &[1]));
    assert_eq!(parsed[2], Parsed::Rejected(LineError { column: 1, reason: Reason::StrayErrorText }));
    assert_eq!(frame_of(&parsed[3]).kind(), FrameKind::Error);
    assert_eq!(parsed[4], Parsed::Other("ErrorText".into()));
    assert_eq!(parsed[5], Parsed::Other("ErrorText".into()));
    assert_eq!(frame_of(&parsed[6]).id(), 0x211);
    assert_eq!(parsed[7], Parsed::Rejected(LineError { column: 1, reason: Reason::StrayErrorText }));
    // A malformed indented frame keeps its own reason and a column counting the TAB.
    assert_eq!(parsed[8], Parsed::Rejected(LineError { column: 32, reason: Reason::NotHex }));
}

#[test]
fn vector_asc_lines() {
    let mut p = parser(TextFormat::VectorAsc);
    let parsed = parse_all(
        &mut p,
        &[
            "date Tue Nov 24 10:00:00.000 2026",
            "base hex  timestamps absolute",
            "// version 13.0.0",
            "Begin Triggerblock Tue Nov 24 10:00:00.000 2026",
            "   0.000000 Start of measurement",
            "   0.010000 CAN 1 Status:chip status error active",
            "   0.020000 1  211             Rx   d 8 00 00 01 03 00 00 00 B1  Length = 230000 BitCount = 118",
            "   0.050000 2  18FF0001x       Tx   d 2 01 02\r",
            "   0.060000 1  7FF             Tx   r",
            "   0.070000 1  123             Rx   r 4",
            "   0.080000 1  ErrorFrame ECC: 10100010",
            "   0.090000 CANFD   1 Rx        221  Motion_State    1 0 8  8 00 96 00 00 00 00 00 00   102203  133   303000 0 0",
            "   0.100000 CANFD   3 Tx   12345678x        0 1 9 12 00 11 22 33 44 55 66 77 88 99 AA BB   1 2 5000",
            "   0.110000 CANFD   1 Tx        300         0 0 2  2 01 02   140000 73 200000",
            "   1.000000 1  Statistic: D 4 R 2 XD 0 XR 0 E 1 O 0 B 0.04%",
            "   1.100000 1  J1939TP FEE3p        6    0  0   -   Rx   d 23 A0 0F",
            "   1.200000 LIN 1 Rx 12 2 00 00",
            "   1.300000 1  211             Rx   d 8 00 00 01",
            "End TriggerBlock",
        ],
    );
    for (index, kind) in [
        (0, "Comment"),
        (1, "Comment"),
        (2, "Comment"),
        (3, "Comment"),
        (4, "Comment"),
        (5, "Comment"),
        (14, "Comment"),
        (15, "Comment"),
        (18, "Comment"),
    ] {
        assert_eq!(parsed[index], Parsed::Other(kind.into()), "line {index}");
    }
    // The date, local time, puts the stamps on the clock.
    let start = super::timestamp::local_to_epoch([2026, 11, 24, 10, 0, 0]).unwrap();
    let frame = data(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]);
    assert_eq!(
        parsed[6],
        Parsed::Frame { ts: abs(start, 20_000_000), iface: "can1".into(), frame, dir: Some(Direction::Rx) }
    );
    let frame = CanFrame::new_extended(0x18FF0001, &[1, 2]).unwrap();
    assert_eq!(
        parsed[7],
        Parsed::Frame { ts: abs(start, 50_000_000), iface: "can2".into(), frame, dir: Some(Direction::Tx) }
    );
    // An error frame, as python-can writes an ASC ErrorFrame to a candump log.
    let frame = CanFrame::new_error(0x80, &[0; 8]).unwrap();
    assert_eq!(
        parsed[10],
        Parsed::Frame { ts: abs(start, 80_000_000), iface: "can1".into(), frame, dir: None }
    );
    assert_eq!(frame_of(&parsed[8]), CanFrame::new_remote(0x7FF, false, 0).unwrap());
    assert_eq!(frame_of(&parsed[9]), CanFrame::new_remote(0x123, false, 4).unwrap());
    // EDL + BRS flags (0x3000): FD with BRS; the symbolic name is skipped.
    assert_eq!(
        frame_of(&parsed[11]),
        CanFrame::new_fd(0x221, false, 0x5, &[0, 0x96, 0, 0, 0, 0, 0, 0]).unwrap()
    );
    let fd = frame_of(&parsed[12]);
    assert_eq!((fd.id(), fd.is_extended(), fd.fd_flags(), fd.len()), (0x12345678, true, 0x6, 12));
    // A CANFD line without the EDL flag is a classic frame.
    assert_eq!(frame_of(&parsed[13]), data(0x300, &[1, 2]));
    assert!(
        matches!(parsed[16], Parsed::Rejected(LineError { reason: Reason::AscEvent, .. })),
        "{:?}",
        parsed[16]
    );
    assert!(
        matches!(parsed[17], Parsed::Rejected(LineError { reason: Reason::LengthMismatch, .. })),
        "{:?}",
        parsed[17]
    );
}

#[test]
fn vector_asc_decimal_base() {
    let mut p = parser(TextFormat::VectorAsc);
    let parsed = parse_all(&mut p, &["base dec  timestamps absolute", "   0.5 1  529  Rx   d 2 255 16"]);
    assert_eq!(frame_of(&parsed[1]), data(529, &[255, 16]));
}

#[test]
fn peak_trc_lines_of_every_version() {
    let cases: &[(u8, &[&str])] = &[
        (10, &["     1)        20  0211  2  00 B1"]),
        (11, &["     1)        20.0  Rx         0211  2  00 B1 "]),
        (12, &["     1)        20.000 1  Rx        0211  2  00 B1"]),
        (13, &["     1)        20.000 1  Rx        0211 -   2    00 B1"]),
        (20, &["      1        20.000 DT     0211 Rx 2 00 B1"]),
        (21, &[";$COLUMNS=N,O,T,B,I,d,R,L,D", "      1        20.000 DT 1      0211 Rx -  2    00 B1"]),
    ];
    for (version, lines) in cases {
        let parsed = parse_all(&mut parser(TextFormat::PeakTrc { version: *version }), lines);
        let dir = if *version == 10 { None } else { Some(Direction::Rx) };
        let expected = Parsed::Frame {
            ts: rel(0, 20_000_000),
            iface: "can1".into(),
            frame: data(0x211, &[0, 0xB1]),
            dir,
        };
        assert_eq!(parsed.last(), Some(&expected), "version {version}");
    }
}

#[test]
fn peak_trc_kinds_and_header_lines() {
    let mut p = parser(TextFormat::PeakTrc { version: 21 });
    let parsed = parse_all(
        &mut p,
        &[
            ";$FILEVERSION=2.1",
            ";$COLUMNS=N,O,T,B,I,d,R,L,D",
            "      1     17535.400 DT 2  00000100 Tx -  8    00 00 00 00 00 00 00 01",
            "      2     17540.300 ST 1         - Rx -  4    00 00 00 08",
            "      3     48937.600 RR 1      0704 Rx -  1",
            "      4     48938.000 FB 1      0123 Rx -  9    00 11 22 33 44 55 66 77 88 99 AA BB",
            "      5     48939.000 ER 1         - Rx -  5    00 02 01 10 00",
            "      6     48940.000 EV 1         - Rx -  0    some event",
            "      7     48941.000 DT 1      0123 Rx -  2    00",
            "      8     48942.000 XX 1      0123 Rx -  1    00",
        ],
    );
    assert_eq!(parsed[0], Parsed::Other("Comment".into()));
    let frame = CanFrame::new_extended(0x100, &[0, 0, 0, 0, 0, 0, 0, 1]).unwrap();
    assert_eq!(
        parsed[2],
        Parsed::Frame {
            ts: Some(Timestamp { secs: 17, nanos: 535_400_000, kind: TimestampKind::Relative }),
            iface: "can2".into(),
            frame,
            dir: Some(Direction::Tx)
        }
    );
    assert_eq!(parsed[3], Parsed::Other("ErrorText".into()));
    assert_eq!(frame_of(&parsed[4]), CanFrame::new_remote(0x704, false, 1).unwrap());
    let fd = frame_of(&parsed[5]);
    assert_eq!((fd.kind(), fd.fd_flags(), fd.len()), (FrameKind::Fd, 0x5, 12));
    assert_eq!(parsed[6], Parsed::Other("ErrorText".into()));
    assert_eq!(parsed[7], Parsed::Other("Comment".into()));
    assert!(
        matches!(parsed[8], Parsed::Rejected(LineError { reason: Reason::LengthMismatch, .. })),
        "{:?}",
        parsed[8]
    );
    assert!(
        matches!(parsed[9], Parsed::Rejected(LineError { reason: Reason::TrcFrame, .. })),
        "{:?}",
        parsed[9]
    );
}

#[test]
fn peak_trc_1_1_remote_and_warning_lines() {
    let mut p = parser(TextFormat::PeakTrc { version: 11 });
    let parsed = parse_all(
        &mut p,
        &[
            "     2)     17540.3  Warng  FFFFFFFF  4  00 00 00 08  BUSHEAVY ",
            "    12)     48937.6  Rx         0704  1  RTR",
        ],
    );
    assert_eq!(parsed[0], Parsed::Other("ErrorText".into()));
    assert_eq!(frame_of(&parsed[1]), CanFrame::new_remote(0x704, false, 1).unwrap());
}

mod never_panic {
    use proptest::prelude::*;

    use super::super::open_log;
    use super::*;

    const SEEDS: &[&str] = &[
        "   0.090000 CANFD   1 Rx        221  Motion_State    1 0 8  8 00 96 00 00 00 00 00 00   102203  133   303000",
        "   0.020000 1  18EBFF00x       Rx   d 8 00 00 01 03 00 00 00 B1  Length = 230000",
        "      5        70.000 BI 1  12345678 Rx -  9    00 11 22 33 44 55 66 77 88 99 AA BB",
        "     5)        70.1  Rx         0123  4  RTR",
        "  can0  211   [8]  B1`00`00`00`03`01`00`00",
        "  can0  211   [8]  00000000 00000000 00000001 00000011 00000000 00000000 00000000 10110001",
        "<0x18eeff01> [8] 05 a0 be 1c 00 a0 a0 c0 ",
        "\tcontroller-problem{tx-error-warning}",
        ";$COLUMNS=N,O,T,B,I,d,R,L,D",
    ];

    fn mutated() -> impl Strategy<Value = Vec<u8>> {
        (0..SEEDS.len(), proptest::collection::vec((any::<usize>(), any::<u8>()), 0..6), any::<usize>())
            .prop_map(|(seed, edits, cut)| {
                let mut line = SEEDS[seed].as_bytes().to_vec();
                for (at, byte) in edits {
                    let at = at % (line.len() + 1);
                    match byte % 3 {
                        0 => line.insert(at, byte),
                        1 if at < line.len() => line[at] = b" 0189AFx`[]-;."[usize::from(byte) % 14],
                        _ if at < line.len() => {
                            line.remove(at);
                        }
                        _ => {}
                    }
                }
                line.truncate(cut % (line.len() + 1) + line.len() / 2);
                line
            })
    }

    proptest! {
        #[test]
        fn no_line_parser_panics_on_mutated_lines(lines in proptest::collection::vec(mutated(), 1..8)) {
            for format in [TextFormat::Candump, TextFormat::VectorAsc, TextFormat::PeakTrc { version: 10 },
                TextFormat::PeakTrc { version: 11 }, TextFormat::PeakTrc { version: 20 }, TextFormat::PeakTrc { version: 21 }] {
                let mut p = parser(format);
                for line in &lines {
                    let _ = p.parse(line);
                }
            }
        }

        #[test]
        fn open_log_never_panics_and_keeps_every_byte(bytes in proptest::collection::vec(any::<u8>(), 0..300),
                                                      text in proptest::collection::vec(mutated(), 0..4)) {
            use std::io::Read;
            for input in [bytes, text.join(&b'\n')] {
                if let Ok((mut reader, _)) = open_log(std::io::Cursor::new(input.clone()), "x") {
                    let mut out = Vec::new();
                    if reader.read_to_end(&mut out).is_ok() && !input.starts_with(b"\x1f\x8b") {
                        // Plain text comes back whole, less a leading BOM.
                        let expected = input.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&input);
                        if !matches!(input.first(), Some(0x28 | 0xFD | b'B')) {
                            prop_assert_eq!(&out[..], expected);
                        }
                    }
                }
            }
        }
    }
}
