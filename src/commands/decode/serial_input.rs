//! RS232 captures: raw bytes, or hex text ("5A A5 0A 55 ...", with optional 0x prefixes, commas, '#' comments).

use std::fmt::Write as _;
use std::io::Read;

use anyhow::Result;

use super::written::read_error;
use super::Decoder;
use crate::candump::{Line, LineParser};
use crate::exit::{Failure, USAGE};
use crate::output::{Event, FrameRef};
use crate::protocol::serial::{self, StreamDecoder, StreamEvent, StreamStats};

const CHUNK: usize = 64 * 1024;

/// Turns hex text into bytes incrementally; anything that is not hex, a separator or a comment is reported.
#[derive(Debug, Default)]
struct HexText {
    high_nibble: Option<u8>,
    /// The pending nibble came from a '0' that may turn out to be a `0x` prefix.
    pending_zero: bool,
    in_comment: bool,
}

#[derive(Clone, Copy, Debug)]
enum HexError {
    Unexpected(u8),
    OddDigit,
}

impl HexText {
    /// Appends the bytes of `text` to `out`; calls `bad` with the offset (within `text`) of each bad character.
    fn convert(&mut self, text: &[u8], out: &mut Vec<u8>, mut bad: impl FnMut(usize, HexError)) {
        for (offset, &ch) in text.iter().enumerate() {
            if self.in_comment {
                self.in_comment = ch != b'\n';
                continue;
            }
            let nibble = match ch {
                b'0'..=b'9' => ch - b'0',
                b'a'..=b'f' => ch - b'a' + 10,
                b'A'..=b'F' => ch - b'A' + 10,
                b'x' | b'X' if self.pending_zero => {
                    self.high_nibble = None;
                    self.pending_zero = false;
                    continue;
                }
                b' ' | b'\t' | b'\r' | b'\n' | b',' | b';' | b':' | b'#' => {
                    if self.high_nibble.take().is_some() {
                        bad(offset, HexError::OddDigit);
                    }
                    self.pending_zero = false;
                    self.in_comment = ch == b'#';
                    continue;
                }
                _ => {
                    bad(offset, HexError::Unexpected(ch));
                    continue;
                }
            };
            match self.high_nibble.take() {
                None => {
                    self.high_nibble = Some(nibble);
                    self.pending_zero = ch == b'0';
                }
                Some(high) => {
                    out.push(high << 4 | nibble);
                    self.pending_zero = false;
                }
            }
        }
    }
}

/// How much of the start of a capture is looked at to tell hex text from raw bytes (and a candump log).
const SAMPLE: usize = 4096;
/// A live input (a read returned less than asked) is classified once this much has arrived.
const LIVE_SAMPLE: usize = 512;
/// A line of hex text longer than this is converted in pieces (only its first piece can have labels).
const MAX_CARRY: usize = 4096;
const BOM: &[u8] = b"\xEF\xBB\xBF";

/// A capture is hex text when its start reads as text: at most 1% of its bytes are control characters or
/// invalid UTF-8 (a raw capture has 0xA5, invalid UTF-8, in every frame), and it holds hex digits. Labels,
/// timestamps, offsets and ASCII columns are text too; [`HexLines`] takes them apart line by line.
fn looks_like_hex_text(start: &[u8]) -> bool {
    let start = start.strip_prefix(BOM).unwrap_or(start);
    let mut binary = 0usize;
    let mut chunks = start.utf8_chunks().peekable();
    while let Some(chunk) = chunks.next() {
        binary += chunk
            .valid()
            .chars()
            .filter(|ch| ch.is_control() && !matches!(ch, '\t' | '\n' | '\r' | '\x0C'))
            .count();
        let invalid = chunk.invalid().len();
        // A character cut off by the end of the sample is not evidence of binary data.
        let cut_at_end =
            chunks.peek().is_none() && chunk.valid().is_empty() && invalid < 4 && start.len() >= SAMPLE;
        if !cut_at_end {
            binary += invalid;
        }
    }
    let digits = start.iter().filter(|b| b.is_ascii_hexdigit()).count();
    digits >= 2 && binary * 100 <= start.len()
}

/// Whether the start of a capture is candump text (a log given to `--serial` by mistake): most of its first
/// complete lines, comments and blank lines aside, parse as candump frames.
fn looks_like_candump(start: &[u8]) -> bool {
    let mut parser = LineParser::new();
    let (mut frames, mut other) = (0, 0);
    for line in start.split(|&b| b == b'\n').take(32) {
        match parser.parse(line) {
            Ok(Line::Frame(_)) => frames += 1,
            Ok(Line::Blank | Line::Comment) => {}
            _ => other += 1,
        }
    }
    frames > 0 && frames >= other * 2
}

/// The column layout of a hex dump, decided on its first line with data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Layout {
    /// Bytes, optionally after labels and timestamps (`RX: 5A A5 ...`, `[12:34:56.789] 5a a5 ...`).
    Plain,
    /// An offset column first, an ASCII column last: `hexdump -C`, `od -A x -t x1z`, CoolTerm, PuTTY.
    Offsets,
    /// `xxd`: `00000000: 5aa5 0a55 ...  Z..U`, byte pairs grouped, the ASCII column after two spaces.
    Xxd,
}

/// Hex text, line by line: a BOM, leading labels (`RX:`, `TX:`, `<-`, `->`, `[RX]`), timestamps
/// (`[12:34:56.789]`, `12:34:56.789`), offset columns and ASCII columns are left out; what remains goes to
/// [`HexText`], which reports anything that is not hex.
struct HexLines {
    hex: HexText,
    layout: Option<Layout>,
    /// The start of a line not yet complete, and its offset in the input.
    carry: Vec<u8>,
    carry_offset: u64,
    /// The next piece continues a line whose start was already converted.
    mid_line: bool,
    first_line: bool,
    /// Lines of text that gave no byte and held nothing wrong (a banner, a tool's header, `#` comments):
    /// skipped, and counted as comments.
    text_lines: u64,
}

impl HexLines {
    fn new() -> Self {
        Self {
            hex: HexText::default(),
            layout: None,
            carry: Vec::with_capacity(MAX_CARRY),
            carry_offset: 0,
            mid_line: false,
            first_line: true,
            text_lines: 0,
        }
    }

    /// The start of the line not yet complete (its offset in the input, its bytes), taken out.
    fn take_carry(&mut self) -> (u64, Vec<u8>) {
        (self.carry_offset, std::mem::take(&mut self.carry))
    }

    /// Converts `data` (at input offset `offset`), appending bytes to `out` and reporting bad characters.
    fn feed(&mut self, data: &[u8], offset: u64, out: &mut Vec<u8>, bad: &mut impl FnMut(u64, HexError)) {
        let mut rest = data;
        let mut at = offset;
        while let Some(newline) = memchr::memchr(b'\n', rest) {
            let (piece, tail) = rest.split_at(newline + 1);
            if self.carry.is_empty() {
                self.line(piece, at, out, bad);
            } else {
                let mut line = std::mem::take(&mut self.carry);
                line.extend_from_slice(piece);
                self.line(&line, self.carry_offset, out, bad);
                line.clear();
                self.carry = line;
            }
            at += piece.len() as u64;
            rest = tail;
        }
        if rest.is_empty() {
            return;
        }
        if self.carry.is_empty() {
            self.carry_offset = at;
        }
        if self.carry.len() + rest.len() <= MAX_CARRY {
            self.carry.extend_from_slice(rest);
        } else {
            // A very long line (a capture without newlines): convert what there is, go on mid-line.
            let mut line = std::mem::take(&mut self.carry);
            line.extend_from_slice(rest);
            self.line(&line, self.carry_offset, out, bad);
            line.clear();
            self.carry = line;
            self.mid_line = true;
        }
    }

    fn finish(&mut self, out: &mut Vec<u8>, bad: &mut impl FnMut(u64, HexError)) {
        let line = std::mem::take(&mut self.carry);
        if !line.is_empty() {
            self.line(&line, self.carry_offset, out, bad);
            self.hex.convert(b"\n", out, |_, error| bad(self.carry_offset + line.len() as u64, error));
        }
    }

    /// One line (with its `\n`, unless it is the last or a piece of a long one); a line of words that gives no
    /// byte and nothing wrong is counted as text.
    fn line(&mut self, text: &[u8], offset: u64, out: &mut Vec<u8>, bad: &mut impl FnMut(u64, HexError)) {
        let continues = self.mid_line;
        let (before, mut wrong) = (out.len(), false);
        self.convert_line(text, offset, out, &mut |at, error| {
            wrong = true;
            bad(at, error);
        });
        let words =
            text.iter().any(|b| !(b.is_ascii_hexdigit() || b.is_ascii_whitespace() || b",;:xX".contains(b)));
        if !continues && out.len() == before && !wrong && words {
            self.text_lines += 1;
        }
    }

    fn convert_line(
        &mut self,
        text: &[u8],
        offset: u64,
        out: &mut Vec<u8>,
        bad: &mut impl FnMut(u64, HexError),
    ) {
        let continues = std::mem::replace(&mut self.mid_line, false);
        let mut start = 0;
        if !continues {
            if std::mem::replace(&mut self.first_line, false) && text.starts_with(BOM) {
                start = BOM.len();
            }
            let data = self.skip_labels(text, start);
            // Labels with nothing after them were not labels: the line is converted whole, so its
            // characters are reported (an offset alone ends a dump, though).
            let nothing_after = matches!(text.get(data), None | Some(b'\n' | b'\r' | b'#'));
            if !(nothing_after && self.layout == Some(Layout::Plain)) {
                start = data;
            }
        }
        let end = match self.layout {
            Some(Layout::Offsets | Layout::Xxd) if !continues => self.data_end(text, start),
            _ => text.len(),
        };
        self.hex.convert(&text[start..end], out, |at, error| bad(offset + (start + at) as u64, error));
        if end < text.len() {
            // The ASCII column is left out; the line still ends here.
            self.hex.convert(b"\n", out, |_, error| bad(offset + end as u64, error));
        }
    }

    /// Skips what precedes the bytes of a line: labels, timestamps, an offset column.
    fn skip_labels(&mut self, text: &[u8], mut pos: usize) -> usize {
        let mut first_token = true;
        loop {
            while text.get(pos).is_some_and(|b| matches!(b, b' ' | b'\t' | b'\r')) {
                pos += 1;
            }
            let Some(&byte) = text.get(pos) else { return pos };
            if matches!(byte, b'[' | b'(') {
                let close = if byte == b'[' { b']' } else { b')' };
                match memchr::memchr(close, &text[pos..]) {
                    Some(length) => {
                        pos += length + 1;
                        first_token = false;
                        continue;
                    }
                    None => return pos,
                }
            }
            if matches!(byte, b'#' | b'\n') {
                return pos;
            }
            let end = text[pos..]
                .iter()
                .position(|b| b.is_ascii_whitespace())
                .map_or(text.len(), |length| pos + length);
            let token = &text[pos..end];
            let bare = token.strip_suffix(b":").unwrap_or(token);
            let all_hex = !bare.is_empty() && bare.iter().all(u8::is_ascii_hexdigit);
            if self.layout.is_none() && all_hex {
                // Decided on the first line that starts with hex, so a header line (PuTTY's) is no guide.
                self.layout = Some(layout_of(token, &text[end..]));
            }
            let offset_column = first_token && self.layout != Some(Layout::Plain) && all_hex;
            let more_follows = text[end..].iter().any(|b| !b.is_ascii_whitespace());
            let label = !token.iter().all(|b| b.is_ascii_hexdigit() || b"xX,;:".contains(b))
                || (token.ends_with(b":") && all_hex && token.len() > 1 && bare.len() != 2)
                || (is_clock(token) && more_follows);
            if !(offset_column || label) {
                return pos;
            }
            pos = end;
            first_token = false;
        }
    }

    /// Where the bytes of an offset-layout line end: at the ASCII column (`|...|`, `>...<`, or after a
    /// wide gap), or at a group that is not one or two bytes.
    fn data_end(&self, text: &[u8], start: usize) -> usize {
        let gap = if self.layout == Some(Layout::Xxd) { 2 } else { 3 };
        let mut pos = start;
        let mut spaces = 0;
        let mut token_start = start;
        while let Some(&byte) = text.get(pos) {
            match byte {
                b' ' | b'\t' => {
                    spaces += 1;
                    if spaces >= gap && pos + 1 > start + spaces {
                        return pos + 1 - spaces;
                    }
                }
                b'\r' | b'\n' => return pos,
                b'|' | b'>' if spaces > 0 || pos == start => return pos,
                _ => {
                    if spaces > 0 || pos == start {
                        token_start = pos;
                    }
                    spaces = 0;
                    let length = pos + 1 - token_start;
                    if !byte.is_ascii_hexdigit() || length > 4 {
                        return token_start;
                    }
                }
            }
            pos += 1;
        }
        pos
    }
}

/// A time of day without brackets before the bytes: `12:34:56` or CuteCom's `12:34:56:789`.
fn is_clock(token: &[u8]) -> bool {
    let mut parts = 0;
    for (index, part) in token.split(|&b| b == b':').enumerate() {
        let width_ok = match index {
            0 => (1..=2).contains(&part.len()),
            1 | 2 => part.len() == 2,
            3 => (1..=6).contains(&part.len()),
            _ => false,
        };
        if !width_ok || !part.iter().all(u8::is_ascii_digit) {
            return false;
        }
        parts += 1;
    }
    parts >= 3
}

/// Decides the layout from the first token of the first line with data: an offset of zeros (dumps start
/// at offset 0) means a dump with offset and ASCII columns; `xxd` adds a colon and groups byte pairs.
fn layout_of(token: &[u8], rest: &[u8]) -> Layout {
    let bare = token.strip_suffix(b":").unwrap_or(token);
    if !(4..=8).contains(&bare.len()) || !bare.iter().all(|&b| b == b'0') {
        return Layout::Plain;
    }
    let next = rest.trim_ascii_start();
    let group = next.iter().take_while(|b| b.is_ascii_hexdigit()).count();
    if token.ends_with(b":") && group == 4 {
        Layout::Xxd
    } else {
        Layout::Offsets
    }
}

pub fn decode(decoder: &mut Decoder, name: &str, input: impl Read) -> Result<()> {
    let mut input = decoder.live(input);
    let mut chunk = vec![0u8; CHUNK];
    let rejected_before = decoder.stats.rejected_total();

    let filled = read_sample(&mut input, &mut chunk, name)?;
    let hex = hex_converter(&chunk[..filled], name)?;
    let mut capture =
        Capture { name, stream: StreamDecoder::new(), hex, events: Vec::new(), problems: Vec::new() };
    let mut bytes = Vec::with_capacity(CHUNK);
    // Text before binary frames (a terminal program's banner): skipped, and its bytes counted as such.
    let mut text_before: Option<(u64, StreamStats)> = None;

    let (mut offset, mut read) = (0u64, filled);
    while read > 0 {
        let data = &chunk[..read];
        match capture.hex.as_ref().and_then(|_| binary_start(data)) {
            Some(at) => {
                // The line holding the first binary byte starts the raw capture: the text before it is done.
                let line_start = memchr::memrchr(b'\n', &data[..at]).map_or(0, |newline| newline + 1);
                capture.feed(decoder, &data[..line_start], offset, &mut bytes)?;
                let mut converter = capture.hex.take().expect("hex text before");
                let (carry_offset, mut raw) = converter.take_carry();
                let raw_from = if raw.is_empty() { offset + line_start as u64 } else { carry_offset };
                // Its bytes are counted as skipped bytes of the capture, not as text lines too.
                converter.text_lines = 0;
                capture.end_of_text(decoder, &mut converter, &mut bytes)?;
                let text = std::mem::take(&mut capture.stream).finish();
                text_before = Some((raw_from, text));
                raw.extend_from_slice(&data[line_start..]);
                capture.feed(decoder, &raw, raw_from, &mut bytes)?;
            }
            None => capture.feed(decoder, data, offset, &mut bytes)?,
        }
        offset += read as u64;
        read = input.read(&mut chunk).map_err(|error| read_error(error, name))?;
    }
    if let Some(mut converter) = capture.hex.take() {
        capture.end_of_text(decoder, &mut converter, &mut bytes)?;
        capture.hex = Some(converter);
    }
    let mut stats = capture.stream.finish();
    if let Some((text_bytes, text)) = text_before {
        stats = with_text_before(stats, text_bytes, &text);
    }
    let rejected = decoder.stats.rejected_total() - rejected_before;
    decoder.stats.serial.push((name.to_string(), stats));
    let hex_text = capture.hex.is_some().then_some(offset);
    if stats.frames == 0 {
        let message = match (stats.bytes, rejected, hex_text) {
            (0, 0, None | Some(0)) => format!("no TRACER frames in {name}: empty"),
            _ => no_frames_message(name, &stats, rejected, hex_text),
        };
        if decoder.strict {
            return Err(Failure::data(message).into());
        }
        decoder.note_frameless(message);
    }
    Ok(())
}

/// A capture being decoded: its stream decoder, and while it reads as hex text, the converter.
struct Capture<'a> {
    name: &'a str,
    stream: StreamDecoder,
    hex: Option<HexLines>,
    events: Vec<StreamEvent>,
    problems: Vec<(u64, HexError)>,
}

impl Capture<'_> {
    /// Decodes `data` (at input offset `offset`): converted first while the capture is hex text.
    fn feed(&mut self, decoder: &mut Decoder, data: &[u8], offset: u64, bytes: &mut Vec<u8>) -> Result<()> {
        let input_bytes: &[u8] = match &mut self.hex {
            Some(converter) => {
                bytes.clear();
                let problems = &mut self.problems;
                converter.feed(data, offset, bytes, &mut |at, error| problems.push((at, error)));
                report_hex_problems(decoder, self.name, problems)?;
                bytes
            }
            None => data,
        };
        self.decode(decoder, input_bytes)
    }

    /// The end of the hex text: its unfinished last line converted, its text lines counted.
    fn end_of_text(
        &mut self,
        decoder: &mut Decoder,
        converter: &mut HexLines,
        bytes: &mut Vec<u8>,
    ) -> Result<()> {
        bytes.clear();
        let problems = &mut self.problems;
        converter.finish(bytes, &mut |at, error| problems.push((at, error)));
        report_hex_problems(decoder, self.name, problems)?;
        decoder.stats.skipped.comment += std::mem::take(&mut converter.text_lines);
        self.decode(decoder, bytes)
    }

    fn decode(&mut self, decoder: &mut Decoder, bytes: &[u8]) -> Result<()> {
        let events = &mut self.events;
        self.stream.feed(bytes, |event| events.push(event));
        for event in self.events.drain(..) {
            emit(decoder, self.name, event)?;
        }
        Ok(())
    }
}

/// Where binary data starts in what was read of a capture that began as text: the first control character
/// (but TAB, CR, LF, form feed, and ESC of a terminal's colours) or invalid UTF-8 with another within the
/// next 64 bytes (a raw frame has several: its A5 and low bytes), so one stray byte in a hex dump is not.
fn binary_start(data: &[u8]) -> Option<usize> {
    let binary = |at: usize| {
        let byte = data[at];
        match byte {
            b'\t' | b'\n' | b'\r' | 0x0C | 0x1B => false,
            0..0x20 | 0x7F => true,
            0..0x80 => false,
            // Not part of valid UTF-8 (a character cut off by the end of the read is not evidence).
            _ => {
                let lead = (0..4).filter_map(|back| at.checked_sub(back)).find(|&i| data[i] & 0xC0 != 0x80);
                let from = lead.unwrap_or(at);
                match std::str::from_utf8(&data[from..(from + 4).min(data.len())]) {
                    Ok(_) => false,
                    Err(error) if error.valid_up_to() > at - from => false,
                    Err(error) => error.error_len().is_some(),
                }
            }
        }
    };
    let first = (0..data.len()).find(|&at| binary(at))?;
    let more = (first + 1..(first + 64).min(data.len())).filter(|&at| binary(at)).count();
    (more >= 1).then_some(first)
}

/// The stats of a capture whose first `text_bytes` bytes were text: those are counted as skipped bytes of the
/// capture (so its bytes are the file's), with what the text itself gave.
fn with_text_before(raw: StreamStats, text_bytes: u64, text: &StreamStats) -> StreamStats {
    StreamStats {
        bytes: raw.bytes + text_bytes,
        frames: raw.frames + text.frames,
        bad_checksum: raw.bad_checksum + text.bad_checksum,
        bad_length: raw.bad_length + text.bad_length,
        bad_type: raw.bad_type + text.bad_type,
        skipped_bytes: raw.skipped_bytes + text_bytes,
        sync_losses: raw.sync_losses + text.sync_losses,
    }
}

/// Reads the start of the input, which decides what the capture is; a live port is decided on less, so it
/// is not held up. Returns how many bytes of `chunk` were filled.
fn read_sample(input: &mut impl Read, chunk: &mut [u8], name: &str) -> Result<usize> {
    let mut filled = 0;
    while filled < SAMPLE {
        let read = input.read(&mut chunk[filled..SAMPLE]).map_err(|error| read_error(error, name))?;
        filled += read;
        if read == 0 || (read < SAMPLE - (filled - read) && filled >= LIVE_SAMPLE) {
            break;
        }
    }
    Ok(filled)
}

/// A hex-text converter when the sample is hex text; a candump log given to --serial is refused.
fn hex_converter(sample: &[u8], name: &str) -> Result<Option<HexLines>> {
    if !looks_like_hex_text(sample) {
        return Ok(None);
    }
    if looks_like_candump(sample) {
        return Err(Failure {
            code: USAGE,
            message: format!(
                "{name} looks like a candump log, not an RS232 capture: decode it without --serial"
            ),
        }
        .into());
    }
    Ok(Some(HexLines::new()))
}

/// `no TRACER frames in NAME: N bytes, none part of a valid 5A A5 frame; 3 bad checksums`; `hex_text` is
/// the length of the hex text the bytes came from, if they did.
fn no_frames_message(name: &str, stats: &StreamStats, rejected: u64, hex_text: Option<u64>) -> String {
    let mut message = format!("no TRACER frames in {name}: ");
    if let Some(text_bytes) = hex_text {
        let _ = write!(message, "{text_bytes} bytes of hex text gave {} bytes", stats.bytes);
    } else {
        let _ = write!(message, "{} bytes", stats.bytes);
    }
    let _ = write!(message, ", none part of a valid 5A A5 frame");
    for (count, what) in [
        (stats.bad_checksum, "bad checksums"),
        (stats.bad_length, "bad length bytes"),
        (stats.bad_type, "bad frame types"),
        (rejected, "characters that are not hex"),
    ] {
        if count > 0 {
            let _ = write!(message, "; {count} {what}");
        }
    }
    message
}

fn report_hex_problems(decoder: &mut Decoder, name: &str, problems: &mut Vec<(u64, HexError)>) -> Result<()> {
    for (at, error) in problems.drain(..) {
        let message = match error {
            HexError::Unexpected(ch) => format!("unexpected character 0x{ch:02X} in hex text"),
            HexError::OddDigit => "odd number of hex digits in a byte".to_string(),
        };
        let reason = match error {
            HexError::Unexpected(_) => "unexpected character in hex text",
            HexError::OddDigit => "odd number of hex digits in a byte",
        };
        decoder.reject_common(name, &format!("byte {at}"), &message, reason)?;
    }
    Ok(())
}

fn emit(decoder: &mut Decoder, name: &str, event: StreamEvent) -> Result<()> {
    match event {
        StreamEvent::Frame { frame, .. } => {
            decoder.stats.frames += 1;
            let decoded = Ok(serial::decode(&frame));
            let event =
                Event { ts: None, iface: "serial", dir: None, frame: FrameRef::Serial(&frame), decoded };
            decoder.event(&event)
        }
        StreamEvent::BadChecksum { offset, computed, found } => {
            let message =
                format!("serial checksum mismatch: computed 0x{computed:02X}, frame carries 0x{found:02X}");
            decoder.reject_common(name, &format!("byte {offset}"), &message, "serial frame checksum mismatch")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn convert(text: &str) -> (Vec<u8>, usize) {
        let mut out = Vec::new();
        let mut errors = 0;
        HexText::default().convert(text.as_bytes(), &mut out, |_, _| errors += 1);
        (out, errors)
    }

    #[test]
    fn hex_text_variants() {
        assert_eq!(convert("5A A5 0a\n55"), (vec![0x5A, 0xA5, 0x0A, 0x55], 0));
        assert_eq!(convert("0x5A,0xA5, 0x0A"), (vec![0x5A, 0xA5, 0x0A], 0));
        assert_eq!(convert("5AA50A # comment 12 34\n55"), (vec![0x5A, 0xA5, 0x0A, 0x55], 0));
        assert_eq!(convert("5A 0 A5"), (vec![0x5A, 0xA5], 1));
        assert_eq!(convert("5A zz A5"), (vec![0x5A, 0xA5], 2));
    }

    /// Converts `text` in chunks of `chunk` bytes; returns the bytes and the offsets of bad characters.
    fn lines(text: &[u8], chunk: usize) -> (Vec<u8>, Vec<u64>) {
        let mut converter = HexLines::new();
        let (mut out, mut bad) = (Vec::new(), Vec::new());
        let mut offset = 0;
        for piece in text.chunks(chunk) {
            converter.feed(piece, offset, &mut out, &mut |at, _| bad.push(at));
            offset += piece.len() as u64;
        }
        converter.finish(&mut out, &mut |at, _| bad.push(at));
        (out, bad)
    }

    const FRAME: [u8; 13] = [0x5A, 0xA5, 0x0A, 0x55, 0x01, 0x02, 0x00, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x6B];

    #[test]
    fn labels_timestamps_offsets_and_ascii_columns_are_left_out() {
        let shapes: [&[u8]; 12] = [
            b"12:34:56:789 5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n",
            b"1700000000.123, 5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n",
            b"=~=~=~=~ PuTTY log 2024.01.01 12:00:00 =~=~=~=~\n  00000000  5a a5 0a 55 01 02 00 0a  00 00 00 00 6b   Z..U........k\n",
            b"\xEF\xBB\xBF5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n",
            b"RX: 5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n",
            b"[RX] 5a a5 0a 55 01 02 00 0a 00 00 00 00 6b\r\n",
            b"[12:34:56.789] <- 5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n",
            b"12:34:56.789 -> 5AA50A550102000A000000006B\n",
            b"0000: 5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n",
            b"00000000  5a a5 0a 55 01 02 00 0a  00 00 00 00 6b        |Z..U........k|\n0000000d\n",
            b"00000000: 5aa5 0a55 0102 000a 0000 0000 6b         Z..U........k\n",
            b"000000 5a a5 0a 55 01 02 00 0a 00 00 00 00 6b  >Z..U........k<\n00000d\n",
        ];
        for shape in shapes {
            for chunk in [1, 3, 7, 4096] {
                assert_eq!(
                    lines(shape, chunk),
                    (FRAME.to_vec(), vec![]),
                    "{} in {chunk}",
                    shape.escape_ascii()
                );
            }
        }
    }

    #[test]
    fn an_xxd_ascii_column_that_looks_like_hex_is_not_read() {
        // Two data bytes 0x61 0x62 show as "ab" in the ASCII column, after the padding.
        let dump = b"00000000: 5aa5 0a55 0102 000a 0000 0000 6b5a a50a  Z..U........kZ..\n00000010: 6162                                     ab\n";
        let (bytes, bad) = lines(dump, 4096);
        assert_eq!(bytes.len(), 18);
        assert_eq!(&bytes[16..], b"ab");
        assert!(bad.is_empty());
    }

    #[test]
    fn words_are_reported_at_their_offsets() {
        let (bytes, bad) = lines(b"5A A5\nnope\n", 4096);
        assert_eq!(bytes, [0x5A, 0xA5]);
        // 'n' at 6, 'o' at 7, 'p' at 8 are not hex; 'e' is a lone digit, ended by the newline at 10.
        assert_eq!(bad, [6, 7, 8, 10]);
    }

    #[test]
    fn a_line_longer_than_the_carry_is_converted_in_pieces() {
        let text: Vec<u8> =
            FRAME.iter().cycle().take(13 * 1000).flat_map(|b| format!("{b:02X} ").into_bytes()).collect();
        let (bytes, bad) = lines(&text, 1000);
        assert_eq!(bytes.len(), 13 * 1000);
        assert!(bad.is_empty());
    }

    #[test]
    fn candump_text_is_recognised() {
        assert!(looks_like_candump(
            b"(1700000000.000000) can0 211#00000103000000B1\n# c\n(1.0) can0 421#01\n"
        ));
        assert!(looks_like_candump(b"  can0  211   [8]  00 00 01 03 00 00 00 B1\n"));
        assert!(!looks_like_candump(b"5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n"));
        assert!(!looks_like_candump(b"RX: 5A A5 0A 55\n"));
    }

    #[test]
    fn binary_starts_at_the_first_of_several_binary_bytes() {
        assert_eq!(binary_start(b"Welcome\r\n\x1b[0m\n\x5A\xA5\x0A\x55\x01\x02"), Some(15));
        assert_eq!(binary_start("[12:34:56] \u{2190} 5A A5\n".as_bytes()), None, "UTF-8 is text");
        assert_eq!(binary_start(b"5A A5\x00 0A 55\n"), None, "one stray byte is not binary data");
        let cut = "5A A5 \u{2190}".as_bytes();
        assert_eq!(binary_start(&cut[..cut.len() - 1]), None, "a character cut by the read is not either");
    }

    #[test]
    fn detection_of_hex_text() {
        assert!(looks_like_hex_text(b"\xEF\xBB\xBF5A A5"));
        assert!(looks_like_hex_text(b"RX: 5A A5 0A 55\n"));
        assert!(looks_like_hex_text("[12:34:56] \u{2190} 5A A5".as_bytes()));
        let raw: Vec<u8> = FRAME.iter().cycle().take(4096).copied().collect();
        assert!(!looks_like_hex_text(&raw));
        assert!(looks_like_hex_text(b"5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n"));
        assert!(!looks_like_hex_text(&[0x5A, 0xA5, 0x0A, 0x55, 0x01]));
        assert!(!looks_like_hex_text(b""));
        assert!(looks_like_hex_text(b"# captured with minicom\n0x5A, 0xA5"));
        assert!(!looks_like_hex_text(b"Z\xa5"));
    }
}
