//! RS232 captures: raw bytes, or hex text ("5A A5 0A 55 ...", with optional 0x prefixes, commas, '#' comments).

use std::io::Read;

use anyhow::{Context, Result};

use super::Decoder;
use crate::output::{Event, FrameRef};
use crate::protocol::serial::{self, StreamDecoder, StreamEvent};

const CHUNK: usize = 64 * 1024;

/// Turns hex text into bytes incrementally; anything that is not hex, a separator or a comment is reported.
#[derive(Default)]
struct HexText {
    high_nibble: Option<u8>,
    /// The pending nibble came from a '0' that may turn out to be a `0x` prefix.
    pending_zero: bool,
    in_comment: bool,
}

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

/// A capture is hex text when its start (comments aside) holds only hex digits, separators and `0x` prefixes.
fn looks_like_hex_text(start: &[u8]) -> bool {
    let mut in_comment = false;
    let mut digits = 0;
    for &byte in start {
        if in_comment {
            in_comment = byte != b'\n';
            continue;
        }
        match byte {
            b'#' => in_comment = true,
            b'0'..=b'9' | b'a'..=b'f' | b'A'..=b'F' => digits += 1,
            b' ' | b'\t' | b'\r' | b'\n' | b',' | b';' | b':' | b'x' | b'X' => {}
            _ => return false,
        }
    }
    digits >= 2
}

pub fn decode(decoder: &mut Decoder, name: &str, mut input: impl Read) -> Result<()> {
    let mut stream = StreamDecoder::new();
    let mut chunk = vec![0u8; CHUNK];
    let mut bytes = Vec::with_capacity(CHUNK);
    let mut hex: Option<HexText> = None;
    let mut first = true;
    let mut text_offset = 0u64;
    let mut events = Vec::new();
    loop {
        let read = input.read(&mut chunk).with_context(|| format!("cannot read {name}"))?;
        if read == 0 {
            break;
        }
        let data = &chunk[..read];
        if first {
            first = false;
            if looks_like_hex_text(&data[..data.len().min(4096)]) {
                hex = Some(HexText::default());
            }
        }
        let input_bytes: &[u8] = match &mut hex {
            Some(converter) => {
                bytes.clear();
                let mut problems = Vec::new();
                converter.convert(data, &mut bytes, |offset, error| problems.push((offset, error)));
                for (offset, error) in problems {
                    let at = text_offset + offset as u64;
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
                &bytes
            }
            None => data,
        };
        text_offset += read as u64;
        stream.feed(input_bytes, |event| events.push(event));
        for event in events.drain(..) {
            emit(decoder, name, event)?;
        }
    }
    let stats = stream.finish();
    decoder.stats.serial.push((name.to_string(), stats));
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

    #[test]
    fn detection_of_hex_text() {
        assert!(looks_like_hex_text(b"5A A5 0A 55 01 02 00 0A 00 00 00 00 6B\n"));
        assert!(!looks_like_hex_text(&[0x5A, 0xA5, 0x0A, 0x55, 0x01]));
        assert!(!looks_like_hex_text(b""));
        assert!(looks_like_hex_text(b"# captured with minicom\n0x5A, 0xA5"));
        assert!(!looks_like_hex_text(b"Z\xa5"));
    }
}
