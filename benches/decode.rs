//! Per-line costs of the decode hot path: parse a candump line, decode the frame, render it.
//! Run: cargo bench --bench decode   (whole-binary throughput: python3 benches/bench.py)

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;

use tracerctl::candump::{Line, LineParser};
use tracerctl::output::{Event, EventWriter, Format, FrameRef};
use tracerctl::protocol::{decode, ProtocolHint};

const LOG_LINE: &[u8] = b"(1700000000.002500) can0 211#00000103000000B1";
const CONSOLE_LINE: &[u8] = b" (1700000000.002500)  can0  211   [8]  00 00 01 03 00 00 00 B1";

fn parse(c: &mut Criterion) {
    let mut group = c.benchmark_group("candump_line");
    group.throughput(Throughput::Elements(1));
    let mut parser = LineParser::new();
    group.bench_function("log_format", |b| {
        b.iter(|| matches!(parser.parse(black_box(LOG_LINE)), Ok(Line::Frame(_))))
    });
    group.bench_function("console_format", |b| {
        b.iter(|| matches!(parser.parse(black_box(CONSOLE_LINE)), Ok(Line::Frame(_))))
    });
    group.finish();
}

fn decode_and_render(c: &mut Criterion) {
    let mut parser = LineParser::new();
    let Ok(Line::Frame(record)) = parser.parse(LOG_LINE) else { panic!("fixture parses") };
    let frame = record.frame;
    let mut group = c.benchmark_group("frame");
    group.throughput(Throughput::Elements(1));
    group.bench_function("decode_0x211", |b| b.iter(|| decode(black_box(&frame), ProtocolHint::Auto)));
    let event = Event {
        ts: record.ts,
        iface: "can0",
        dir: None,
        frame: FrameRef::Can(&frame),
        decoded: decode(&frame, ProtocolHint::Auto),
    };
    let mut out = Vec::with_capacity(1 << 16);
    for format in [Format::Json, Format::Text, Format::Csv] {
        let writer = EventWriter::new(format, false);
        group.bench_function(format!("render_{format:?}").to_lowercase(), |b| {
            b.iter(|| {
                out.clear();
                writer.write(&mut out, black_box(&event));
                out.len()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, parse, decode_and_render);
criterion_main!(benches);
