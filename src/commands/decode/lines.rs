//! The one line loop of `decode`: whole lines of text in, each line's outcome out to a [`LineSink`]. One
//! thread's [`super::Decoder`] (`-j1`) and the workers' chunk recorder (`-jN`, see [`super::parallel`]) are
//! its two sinks; the readers around it ([`super::splitter`], the positioned reads of
//! [`super::ranges`]) only cut the input into whole lines.

use std::ops::ControlFlow;

use memchr::memchr;

use crate::candump::{Direction, Line, LineError, LineLimit, LineParser, Timestamp};
use crate::protocol::CanFrame;

/// A frame line as the loop hands it over.
#[derive(Clone, Copy)]
pub(super) struct FrameLine<'a> {
    pub ts: Option<Timestamp>,
    /// `-t d`: the stamp is the parser's sum of the deltas so far (not the line's own).
    pub summed: bool,
    pub iface: &'a str,
    pub dir: Option<Direction>,
    pub frame: &'a CanFrame,
}

/// What becomes of each line. `number` counts from the `first` given to [`decode_lines`]. `Break` stops the
/// loop after the line (`--strict`, a failed write).
pub(super) trait LineSink {
    fn frame(&mut self, number: u64, line: FrameLine<'_>) -> ControlFlow<()>;
    /// A line that is no frame and no error (blank, comment, DROPCOUNT, error-frame text, CAN XL).
    fn skipped(&mut self, number: u64, line: Line<'_>) -> ControlFlow<()>;
    /// A line the log format does not read (it may still be a bare cansend frame).
    fn unparsed(&mut self, number: u64, text: &[u8], error: LineError) -> ControlFlow<()>;
    /// A line over the line limit, `length` bytes without its `\n`: rejected whole, never parsed.
    fn too_long(&mut self, number: u64, length: usize) -> ControlFlow<()>;
}

/// How far [`decode_lines`] went.
pub(super) struct Scanned {
    /// Lines looked at, the one that stopped the loop included.
    pub lines: u64,
    pub flow: ControlFlow<()>,
}

/// Decodes the whole lines of `input` (`long_lines`: those a reader cut short, by offset, with their true
/// length) until its end or a `Break`; the first line is number `first`.
#[inline(always)]
pub(super) fn decode_lines(
    sink: &mut impl LineSink,
    parser: &mut LineParser,
    (input, long_lines): (&[u8], &[(usize, usize)]),
    first: u64,
) -> Scanned {
    let (limit, sums_deltas) = (LineLimit::DEFAULT, parser.sums_deltas());
    let mut long_lines = long_lines.iter().peekable();
    // `-t d`: the interface name of a summed line, copied out of the parser while its sum is asked.
    let mut iface = String::new();
    let (mut at, mut number) = (0, first);
    while at < input.len() {
        // Nearly every line: the common log line, whose end parsing it finds (no search for the `\n` first).
        // A line the reader cut short is never one (it is longer than the limit).
        if long_lines.peek().is_none_or(|&&(offset, _)| offset != at) {
            if let Some((record, length)) = parser.parse_log_line_at(&input[at..]) {
                at += length + 1;
                let (ts, iface, dir, frame) = (record.ts, record.iface, record.dir, record.frame);
                let flow = sink.frame(number, FrameLine { ts, summed: false, iface, dir, frame });
                number += 1;
                if flow.is_break() {
                    return Scanned { lines: number - first, flow };
                }
                continue;
            }
        }
        let end = memchr(b'\n', &input[at..]).map_or(input.len(), |offset| at + offset);
        let text = &input[at..end];
        let line_start = at;
        at = end + 1;
        let too_long = match long_lines.next_if(|&&(offset, _)| offset == line_start) {
            Some(&(_, length)) => Some(length),
            None => limit.is_over(text.len()).then_some(text.len()),
        };
        let flow = match too_long {
            Some(length) => sink.too_long(number, length),
            None => {
                let deltas_before = parser.delta_sum().added();
                match parser.parse(text) {
                    Ok(Line::Frame(record)) if sums_deltas => {
                        let (ts, dir, frame) = (record.ts, record.dir, record.frame);
                        iface.clear();
                        iface.push_str(record.iface);
                        let summed = parser.delta_sum().added() != deltas_before;
                        sink.frame(number, FrameLine { ts, summed, iface: &iface, dir, frame: &frame })
                    }
                    Ok(Line::Frame(record)) => {
                        let (ts, iface, dir) = (record.ts, record.iface, record.dir);
                        sink.frame(number, FrameLine { ts, summed: false, iface, dir, frame: &record.frame })
                    }
                    Ok(other) => sink.skipped(number, other),
                    Err(error) => sink.unparsed(number, text, error),
                }
            }
        };
        number += 1;
        if flow.is_break() {
            return Scanned { lines: number - first, flow };
        }
    }
    Scanned { lines: number - first, flow: ControlFlow::Continue(()) }
}
