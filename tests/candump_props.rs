//! Property tests for the candump reader and writer.

use proptest::collection::vec;
use proptest::prelude::*;

use tracerctl::candump::{
    parse_cansend, write_log_line, write_log_record, Direction, Line, LineParser, LineReader, RawLine,
    Record, Timestamp, TimestampKind, RELATIVE_LIMIT_SECS,
};
use tracerctl::protocol::frame::{EFF_MAX, FD_LENGTHS, SFF_MAX};
use tracerctl::protocol::CanFrame;

/// One valid line of every variant the parser knows, to mutate.
const SAMPLES: &[&str] = &[
    "(1700000000.002500) can0 211#00000103000000B1",
    "(1600000000.000000)   can0 123#00 R",
    "(1700000000.123456789) vcan10 311#FFFFFFC100000012 T",
    "(000.123456) can0 251#0000000F00000054",
    "(0.000000) can0 20000080# R",
    "(1700000000.000000) can0 123#R8_E",
    "(1700000000.000000) can0 123#1122334455667788_E",
    "(1700000000.000000) can0 5A1#11.2233.44556677.88",
    "(1700000000.000000) can0 123##5001122",
    "(1700000000.000000) can0 20000004#0008000000007800",
    "(1700000000.000000) can0 00000123#11",
    "(1700000000.000000) can0 45123#81:00:12345678#112233",
    "DROPCOUNT: dropped 3 CAN frames on 'can0' socket (total drops 7)",
    "# comment",
    " (1600000000.123456)  can0  151   [8]  00 01 02 03 04 05 06 07",
    "  can0  151   [8]  00 01 02 03 04 05 06 07",
    " (2020-12-19 12:04:45.485261)  can0  151   [8]  00 01 02 03 04 05 06 07",
    " (000.000250)  can0  RX B E  123  [12]  00 01 02 03 04 05 06 07 08 09 0A 0B",
    " \x1b[1;31m(1600000000.123456) \x1b[1;31mcan0\x1b[0m  151   [8]  00 01 02 03 04 05 06 07\x1b[0m",
    "  can0       151   [8]  41 42 43 44 45 46 47 48   'ABCDEFGH'",
    "  can0  151   [5]  remote request",
    "  can0  151   {9}  00 01 02 03 04 05 06 07",
    "  can0  20000004   [8]  00 08 00 00 00 00 78 00   ERRORFRAME",
    "\tcontroller-problem{tx-error-warning}",
    "   xl0  123 [0003] (45|81:00:12345678) 11 22 33",
];

#[derive(Clone, Debug)]
enum Edit {
    Flip(usize, u8),
    Insert(usize, u8),
    Delete(usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let interesting = prop_oneof![
        any::<u8>(),
        Just(b' '),
        Just(b'#'),
        Just(b'.'),
        Just(b'('),
        Just(b')'),
        Just(b'['),
        Just(b']'),
        Just(b'_'),
        Just(b'R'),
        Just(b'\t'),
        Just(0x1B),
        Just(b'0'),
        Just(b'F'),
    ];
    prop_oneof![
        (any::<usize>(), interesting.clone()).prop_map(|(at, b)| Edit::Flip(at, b)),
        (any::<usize>(), interesting).prop_map(|(at, b)| Edit::Insert(at, b)),
        any::<usize>().prop_map(Edit::Delete),
    ]
}

fn apply(line: &mut Vec<u8>, edit: &Edit) {
    match *edit {
        Edit::Flip(at, b) if !line.is_empty() => {
            let at = at % line.len();
            line[at] = b;
        }
        Edit::Insert(at, b) => {
            let at = at % (line.len() + 1);
            line.insert(at, b);
        }
        Edit::Delete(at) if !line.is_empty() => {
            let at = at % line.len();
            line.remove(at);
        }
        _ => {}
    }
}

/// Parses with both parser modes and checks what can be checked of any result.
fn parse_anything(line: &[u8]) {
    for mut parser in [LineParser::new(), LineParser::new().with_delta_timestamps()] {
        match parser.parse(line) {
            Err(err) => {
                assert!(err.column >= 1 && err.column <= line.len() + 1, "column {} of {line:?}", err.column)
            }
            Ok(Line::Frame(record)) => {
                assert!(!record.iface.is_empty() && record.iface.len() <= 15);
                if let Some(ts) = record.ts {
                    assert!(ts.nanos < 1_000_000_000);
                }
            }
            Ok(_) => {}
        }
    }
}

fn id_and_ext() -> impl Strategy<Value = (u32, bool)> {
    prop_oneof![(0..=SFF_MAX).prop_map(|id| (id, false)), (0..=EFF_MAX).prop_map(|id| (id, true))]
}

/// Valid frames of every kind.
fn frame() -> impl Strategy<Value = CanFrame> {
    prop_oneof![
        (id_and_ext(), vec(any::<u8>(), 0..=8)).prop_map(|((id, ext), data)| match ext {
            false => CanFrame::new(id, &data).unwrap(),
            true => CanFrame::new_extended(id, &data).unwrap(),
        }),
        (id_and_ext(), any::<[u8; 8]>(), 9..=15u8).prop_map(|((id, ext), data, dlc)| {
            let frame = if ext { CanFrame::new_extended(id, &data) } else { CanFrame::new(id, &data) };
            frame.unwrap().with_raw_dlc(dlc).unwrap()
        }),
        (id_and_ext(), 0..=8u8).prop_map(|((id, ext), len)| CanFrame::new_remote(id, ext, len).unwrap()),
        (id_and_ext(), 9..=15u8).prop_map(|((id, ext), dlc)| CanFrame::new_remote(id, ext, 8)
            .unwrap()
            .with_raw_dlc(dlc)
            .unwrap()),
        (0..=EFF_MAX, vec(any::<u8>(), 0..=8))
            .prop_map(|(class, data)| CanFrame::new_error(class, &data).unwrap()),
        (id_and_ext(), 0..16u8, prop::sample::select(&FD_LENGTHS[..]), any::<[u8; 64]>()).prop_map(
            |((id, ext), flags, len, data)| CanFrame::new_fd(id, ext, flags, &data[..usize::from(len)])
                .unwrap()
        ),
    ]
}

/// Timestamps the log format can carry unchanged: whole microseconds, the kind implied by the value.
fn timestamp() -> impl Strategy<Value = Option<Timestamp>> {
    let micros = 0..1_000_000u32;
    prop_oneof![
        1 => Just(None),
        3 => (RELATIVE_LIMIT_SECS..=9_999_999_999_999_999_999u64, micros.clone())
            .prop_map(|(secs, us)| Some(Timestamp { secs, nanos: us * 1000, kind: TimestampKind::Absolute })),
        3 => (0..RELATIVE_LIMIT_SECS, micros)
            .prop_map(|(secs, us)| Some(Timestamp { secs, nanos: us * 1000, kind: TimestampKind::Relative })),
    ]
}

/// Interface names: any printable ASCII with a timestamp; without one, a name that cannot be read as a
/// comment, a timestamp or a DROPCOUNT line.
fn iface_for(ts: Option<Timestamp>) -> BoxedStrategy<String> {
    match ts {
        Some(_) => "[!-~]{1,15}".boxed(),
        None => "[a-z][a-z0-9_.-]{0,14}".boxed(),
    }
}

fn direction() -> impl Strategy<Value = Option<Direction>> {
    prop_oneof![Just(None), Just(Some(Direction::Rx)), Just(Some(Direction::Tx))]
}

/// A frame as candump's console shows it (`-x` columns when `dir` is given).
fn console_line(frame: &CanFrame, dir: Option<Direction>) -> String {
    use tracerctl::protocol::FrameKind;
    let id = match frame.kind() {
        FrameKind::Error => format!("{:08X}", frame.id() | 0x2000_0000),
        _ if frame.is_extended() => format!("{:08X}", frame.id()),
        _ => format!("{:03X}", frame.id()),
    };
    let info = match dir {
        None => String::new(),
        Some(d) => {
            let brs = if frame.fd_flags() & 1 != 0 { 'B' } else { '-' };
            let esi = if frame.fd_flags() & 2 != 0 { 'E' } else { '-' };
            format!("  {} {brs} {esi}", if d == Direction::Rx { "RX" } else { "TX" })
        }
    };
    let len = match (frame.kind(), frame.raw_dlc()) {
        (FrameKind::Fd, _) => format!("[{:02}]", frame.len()),
        (_, Some(dlc)) => format!("{{{dlc:X}}}"),
        _ => format!(" [{}]", frame.len()),
    };
    let body = match frame.kind() {
        FrameKind::Remote => " remote request".to_owned(),
        _ => frame.data().iter().map(|b| format!(" {b:02X}")).collect(),
    };
    let tag = if frame.kind() == FrameKind::Error { "   ERRORFRAME" } else { "" };
    format!("  can0{info}  {id}  {len} {body}{tag}")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn never_panics_on_random_bytes(line in vec(any::<u8>(), 0..160)) {
        parse_anything(&line);
    }

    #[test]
    fn never_panics_on_random_printable_text(line in "[ -~\t\x1b]{0,120}") {
        parse_anything(line.as_bytes());
    }

    #[test]
    fn never_panics_on_mutated_valid_lines(sample in prop::sample::select(SAMPLES), edits in vec(edit(), 1..6)) {
        let mut line = sample.as_bytes().to_vec();
        for edit in &edits {
            apply(&mut line, edit);
        }
        parse_anything(&line);
        let _ = parse_cansend(&line);
    }

    #[test]
    fn cansend_never_panics(text in vec(any::<u8>(), 0..100)) {
        if let Err(err) = parse_cansend(&text) {
            prop_assert!(err.column >= 1 && err.column <= text.len() + 1);
        }
    }

    #[test]
    fn log_lines_round_trip(
        frame in frame(),
        (ts, iface) in timestamp().prop_flat_map(|ts| (Just(ts), iface_for(ts))),
        dir in direction(),
        crlf in any::<bool>(),
    ) {
        let mut out = Vec::new();
        write_log_record(&mut out, &Record { ts, iface: &iface, frame, dir });
        prop_assert_eq!(out.pop(), Some(b'\n'));
        if crlf {
            out.push(b'\r');
        }
        let mut parser = LineParser::new();
        match parser.parse(&out) {
            Ok(Line::Frame(record)) => {
                prop_assert_eq!(record.frame, frame);
                prop_assert_eq!(record.iface, iface.as_str());
                prop_assert_eq!(record.ts, ts);
                prop_assert_eq!(record.dir, dir);
            }
            other => prop_assert!(false, "{:?} parsed as {:?}", String::from_utf8_lossy(&out), other),
        }
    }

    #[test]
    fn write_log_line_matches_write_log_record_without_direction(frame in frame(), ts in timestamp()) {
        let mut a = Vec::new();
        write_log_line(&mut a, ts, "can0", &frame);
        let mut b = Vec::new();
        write_log_record(&mut b, &Record { ts, iface: "can0", frame, dir: None });
        prop_assert_eq!(a, b);
    }

    #[test]
    fn cansend_round_trips_display(frame in frame()) {
        prop_assert_eq!(parse_cansend(frame.to_string().as_bytes()), Ok(frame));
        prop_assert_eq!(parse_cansend(frame.to_string().to_lowercase().as_bytes()), Ok(frame));
    }

    #[test]
    fn console_lines_round_trip(frame in frame(), dir in direction()) {
        use tracerctl::protocol::FrameKind;
        // The console shows FD flags only through -x, and always implies FDF.
        let expected_flags = match (frame.kind(), dir) {
            (FrameKind::Fd, Some(_)) => 4 | (frame.fd_flags() & 3),
            (FrameKind::Fd, None) => 4,
            _ => 0,
        };
        let line = console_line(&frame, dir);
        match LineParser::new().parse(line.as_bytes()) {
            Ok(Line::Frame(record)) => {
                prop_assert_eq!(record.frame.kind(), frame.kind());
                prop_assert_eq!(record.frame.id(), frame.id());
                prop_assert_eq!(record.frame.is_extended(), frame.is_extended());
                prop_assert_eq!(record.frame.len(), frame.len());
                prop_assert_eq!(record.frame.data(), frame.data());
                prop_assert_eq!(record.frame.raw_dlc(), frame.raw_dlc());
                prop_assert_eq!(record.frame.fd_flags(), expected_flags);
                prop_assert_eq!(record.dir, dir);
            }
            other => prop_assert!(false, "{:?} parsed as {:?}", line, other),
        }
    }

    #[test]
    fn line_reader_yields_exactly_the_lines(
        lines in vec(vec(any::<u8>().prop_filter("no newline", |b| *b != b'\n'), 0..40), 0..20),
        final_newline in any::<bool>(),
        capacity in 1..24usize,
    ) {
        let mut content = lines.join(&b'\n');
        if final_newline && !lines.is_empty() {
            content.push(b'\n');
        }
        let mut expected: Vec<&[u8]> = content.split(|&b| b == b'\n').collect();
        if content.is_empty() || content.ends_with(b"\n") {
            expected.pop();
        }
        let mut reader = LineReader::with_capacity(capacity, &content[..]);
        let mut got = Vec::new();
        while let Some(line) = reader.next_line().unwrap() {
            match line {
                RawLine::Line { number, text } => {
                    prop_assert_eq!(number, got.len() as u64 + 1);
                    got.push(text.to_vec());
                }
                RawLine::TooLong { .. } => prop_assert!(false, "no line is near the default limit"),
            }
        }
        prop_assert_eq!(got, expected);
        prop_assert_eq!(reader.bytes_read(), content.len() as u64);
    }

    #[test]
    fn line_reader_reports_long_lines_exactly(
        lengths in vec(0..60usize, 0..20),
        final_newline in any::<bool>(),
        capacity in 1..24usize,
        max in 1..40usize,
    ) {
        let mut content = Vec::new();
        for (i, len) in lengths.iter().enumerate() {
            if i > 0 {
                content.push(b'\n');
            }
            content.extend((0..*len).map(|j| b'a' + (j % 26) as u8));
        }
        if final_newline && !lengths.is_empty() {
            content.push(b'\n');
        }
        let mut expected: Vec<usize> = content.split(|&b| b == b'\n').map(<[u8]>::len).collect();
        if content.is_empty() || content.ends_with(b"\n") {
            expected.pop();
        }
        let mut reader = LineReader::with_capacity(capacity, &content[..]).with_max_line_len(max);
        let mut got = Vec::new();
        while let Some(line) = reader.next_line().unwrap() {
            let (number, len) = match line {
                RawLine::Line { number, text } => {
                    prop_assert!(text.len() <= max);
                    (number, text.len())
                }
                RawLine::TooLong { number, len } => {
                    prop_assert!(len > max);
                    (number, len)
                }
            };
            prop_assert_eq!(number, got.len() as u64 + 1);
            got.push(len);
        }
        prop_assert_eq!(got, expected);
    }
}
