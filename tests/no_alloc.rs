//! The decode hot path (and monitor's text line) allocates nothing per line: decoding 20x more lines costs exactly as many heap
//! allocations (all of them set-up). Allocations are counted on the test's own thread only.

use tracerctl::candump::{Line, LineParser, LineReader, LogFormat, RawLine, TextFormat};
use tracerctl::commands::decode::summary::Summary;
use tracerctl::output::stamp::TimeMode;
use tracerctl::output::text::{self, Columns};
use tracerctl::output::{Event, EventWriter, Format, FrameRef};
use tracerctl::protocol::{decode, ProtocolHint};

#[path = "support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations_so_far;

/// A mix of log and console lines (coloured ones too), TRACER and other frames.
const SAMPLE: &[&str] = &[
    "(1700000000.000000) can0 211#00000103020000B1",
    "(1700000000.000100) can0 221#0096FE0C00000000 R",
    "(1700000000.000200)   can0 311#FFFFFFC100000012",
    "(1700000000.000300) can0 262#01070027D8400000",
    "(1700000000.000400) can0 130#01000A0000000045",
    "(1700000000.000500) can0 20000004#0008000000007800",
    "(1700000000.000600) can0 00000123#11",
    " (1700000000.000700)  can0  251   [8]  0B B8 00 32 00 00 00 00",
    " (1700000000.000800)  \x1b[31mcan0\x1b[0m  231   [8]  01 01 00 00 00 00 00 05",
    "  can0  121   [8]  01 03 1E 00 00 00 00 05   '........'",
    // candump -S and -i, Pengutronix canutils, a TAB-indented frame.
    "  can0  211   [8]  B1`00`00`00`03`01`00`00",
    "  can0  421   [1]  00000001",
    "<0x211> [8] 00 00 01 03 00 00 00 b1 ",
    "\t(1700000000.000900) can0 221#0096FE0C00000000",
];

enum Sink {
    Writer(EventWriter),
    /// monitor's text line: a time mode, with or without the data column.
    Columns(TimeMode, bool),
    Summary,
}

/// Allocations made while decoding `lines` lines into `sink`, set-up included.
fn allocations_for(lines: usize, sink: &Sink) -> usize {
    let text: String = SAMPLE.iter().cycle().take(lines).map(|line| format!("{line}\n")).collect();
    let before = allocations_so_far();
    let mut reader = LineReader::new(text.as_bytes());
    let mut parser = LineParser::new();
    let mut out = Vec::with_capacity(64 * 1024);
    let mut summary = Summary::default();
    let mut columns = match sink {
        Sink::Columns(mode, data) => Some(Columns::new(*mode, *data)),
        _ => None,
    };
    let mut frames = 0;
    while let Some(raw) = reader.next_line().unwrap() {
        let RawLine::Line { text, .. } = raw else { panic!("no line is too long") };
        let Ok(Line::Frame(record)) = parser.parse(text) else { panic!("every sample line parses") };
        let frame = record.frame;
        let event = Event {
            ts: record.ts,
            iface: record.iface,
            dir: record.dir,
            frame: FrameRef::Can(&frame),
            decoded: decode(&frame, ProtocolHint::Auto),
        };
        match sink {
            Sink::Writer(writer) => {
                writer.write(&mut out, &event);
                out.clear();
            }
            Sink::Columns(..) => {
                text::write_with(&mut out, &event, true, columns.as_mut().expect("made above"));
                out.clear();
            }
            Sink::Summary => summary.event(&event),
        }
        frames += 1;
    }
    assert_eq!(frames, lines);
    let used = allocations_so_far() - before;
    drop(summary);
    used
}

#[test]
fn decoding_allocates_nothing_per_line() {
    for (name, sink) in [
        ("json", Sink::Writer(EventWriter::new(Format::Json, false))),
        ("text", Sink::Writer(EventWriter::new(Format::Text, true))),
        ("csv", Sink::Writer(EventWriter::new(Format::Csv, false))),
        ("monitor text, absolute, data", Sink::Columns(TimeMode::Absolute, true)),
        ("monitor text, delta", Sink::Columns(TimeMode::Delta, true)),
        ("monitor text, zero, no data", Sink::Columns(TimeMode::Zero, false)),
        ("monitor text, date", Sink::Columns(TimeMode::Date, true)),
        ("summary", Sink::Summary),
    ] {
        // The sample text itself is built before counting starts, so only decoding is measured.
        let small = allocations_for(1_000, &sink);
        let large = allocations_for(20_000, &sink);
        assert_eq!(small, large, "{name}: {small} allocations for 1,000 lines, {large} for 20,000");
    }
}

/// Allocations made while parsing `lines` lines of `sample` with a parser for `format`.
fn parse_allocations(sample: &[&str], format: TextFormat, lines: usize) -> usize {
    let text: String = sample.iter().cycle().take(lines).map(|line| format!("{line}\n")).collect();
    let before = allocations_so_far();
    let mut reader = LineReader::new(text.as_bytes());
    let mut parser = LineParser::for_format(LogFormat { text: format, compression: None });
    let mut frames = 0;
    while let Some(raw) = reader.next_line().unwrap() {
        let RawLine::Line { text, .. } = raw else { panic!("no line is too long") };
        if let Ok(Line::Frame(_)) = parser.parse(text) {
            frames += 1;
        }
    }
    assert!(frames > 0);
    allocations_so_far() - before
}

#[test]
fn asc_and_trc_lines_allocate_nothing_per_line() {
    let asc = [
        "   0.020000 1  211             Rx   d 8 00 00 01 03 00 00 00 B1  Length = 230000",
        "   0.050000 2  18FF0001x       Tx   d 2 01 02",
        "   0.080000 1  ErrorFrame",
        "   0.090000 CANFD   3 Rx  221  Name  1 0 8  8 00 96 00 00 00 00 00 00   102203  133   303000",
    ];
    let trc = [
        "      1        20.500 DT 1      0211 Rx -  8    00 00 01 03 00 00 00 B1",
        "      2        40.000 DT 12     0111 Tx -  8    00 96 00 00 00 00 00 00",
        "      3        45.000 ST 1         - Rx -  4    00 00 00 08",
    ];
    for (name, sample, format) in
        [("asc", &asc[..], TextFormat::VectorAsc), ("trc", &trc[..], TextFormat::PeakTrc { version: 21 })]
    {
        let small = parse_allocations(sample, format, 1_000);
        let large = parse_allocations(sample, format, 20_000);
        assert_eq!(small, large, "{name}: {small} allocations for 1,000 lines, {large} for 20,000");
    }
}
