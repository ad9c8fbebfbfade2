//! The text of a log cut into runs of whole lines, for the line loop ([`super::lines`]): one thread's
//! reading (`-j1`), a stream's reader thread and a compressed file's chunks (`-jN`). A line longer than the
//! limit is kept only up to the bytes the [`LineLimit`] keeps, with its true length beside.

use std::io::{self, Read};
use std::ops::{Deref, Range};

use memchr::{memchr, memrchr};

use crate::candump::{LineLimit, LongLine};

/// Whole lines of the input as a reader cut them; the buffers are reused.
#[derive(Default)]
pub(super) struct Text {
    pub input: Buffer,
    /// Lines cut short because they exceeded the line limit: (offset in `input`, true length).
    pub long_lines: Vec<(usize, usize)>,
    /// Bytes of the input this text stands for (for the progress bar).
    pub bytes: u64,
    /// Reading failed after `input`.
    pub read_error: Option<io::Error>,
    /// With `read_error`: the bytes of the unfinished line read before it, not in `input`.
    pub unfinished: u64,
}

/// A byte buffer whose room after its contents stays initialized once written: reads go straight into it,
/// with no zeroing per read (std's `read_to_end` zeroed each chunk's room again: 9 M instructions of memset
/// per 9 MB decoded).
#[derive(Default)]
pub(super) struct Buffer {
    bytes: Vec<u8>,
    len: usize,
}

impl Buffer {
    pub fn clear(&mut self) {
        self.len = 0;
    }

    pub fn truncate(&mut self, len: usize) {
        self.len = self.len.min(len);
    }

    pub fn extend_from_slice(&mut self, more: &[u8]) {
        self.room(more.len()).copy_from_slice(more);
        self.len += more.len();
    }

    /// `bytes` of room after the contents, to read into; then [`Buffer::grow`] by what was read.
    pub fn room(&mut self, bytes: usize) -> &mut [u8] {
        let end = self.len + bytes;
        if self.bytes.len() < end {
            self.bytes.resize(end, 0);
        }
        &mut self.bytes[self.len..end]
    }

    /// The first `bytes` of the room hold new contents.
    pub fn grow(&mut self, bytes: usize) {
        self.len = (self.len + bytes).min(self.bytes.len());
    }

    /// Removes `range` of the contents, moving the rest down.
    pub fn drain(&mut self, range: Range<usize>) {
        self.bytes.copy_within(range.end..self.len, range.start);
        self.len -= range.len();
    }
}

impl Deref for Buffer {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        &self.bytes[..self.len]
    }
}

/// Where the reader cuts.
#[derive(Clone, Copy)]
pub(super) struct Cut {
    pub chunk_bytes: usize,
    /// After every read that ends a line, not only after `chunk_bytes` (a stream: its lines go out as they
    /// come).
    pub stream: bool,
}

/// Cuts the input into runs of about `chunk_bytes` ending after a `\n` (or at the end), numbered in order.
pub(super) struct Splitter<R> {
    reader: R,
    cut: Cut,
    /// The unfinished last line of the previous read, and its true length when it was cut short.
    carry: Vec<u8>,
    carry_long: Option<LongLine>,
    next_index: u64,
    ended: bool,
}

impl<R: Read> Splitter<R> {
    pub fn new(reader: R, cut: Cut) -> Self {
        Self { reader, cut, carry: Vec::new(), carry_long: None, next_index: 0, ended: false }
    }

    /// Whether the input ended (or failed).
    pub fn ended(&self) -> bool {
        self.ended
    }

    /// Fills `text` with the next run of lines, and returns its index in the input order when it holds
    /// anything to decode (lines, or a read error); past the end of the input, `None`.
    pub fn next_text(&mut self, text: &mut Text) -> Option<u64> {
        if self.ended {
            return None;
        }
        let index = self.next_index;
        self.next_index += 1;
        text.input.clear();
        text.long_lines.clear();
        text.input.extend_from_slice(&self.carry);
        let mut long = self.carry_long.take();
        let (last_newline, eof) = fill(&mut self.reader, text, self.cut, &mut long);
        self.carry.clear();
        if eof {
            self.ended = true;
            if let Some(long) = long.take() {
                text.long_lines.push((last_newline.map_or(0, |at| at + 1), long.length()));
            }
        } else if let Some(at) = last_newline {
            self.carry.extend_from_slice(&text.input[at + 1..]);
            text.input.truncate(at + 1);
            self.carry_long = long.take();
        }
        let kept = LineLimit::DEFAULT.kept();
        text.bytes = text.input.len() as u64
            + text.long_lines.iter().map(|&(_, length)| (length - kept) as u64).sum::<u64>();
        (!text.input.is_empty() || text.read_error.is_some()).then_some(index)
    }
}

/// Reads into `text.input` until it holds `chunk_bytes` and a `\n`, or the end. `long` is the open line
/// when it was cut short. Returns the last `\n`'s offset and whether the input ended.
pub(super) fn fill(
    reader: &mut impl Read,
    text: &mut Text,
    cut: Cut,
    long: &mut Option<LongLine>,
) -> (Option<usize>, bool) {
    let (limit, chunk_bytes) = (LineLimit::DEFAULT, cut.chunk_bytes);
    let mut last_newline: Option<usize> = None;
    let mut eof = false;
    while !(last_newline.is_some() && (cut.stream || text.input.len() >= chunk_bytes)) {
        let old = text.input.len();
        let read = if cut.stream {
            // Whatever one read returns: a live stream's lines go out as they come.
            let read = reader.read(text.input.room(chunk_bytes));
            text.input.grow(*read.as_ref().unwrap_or(&0));
            read
        } else {
            // A file: up to a chunk at once.
            read_up_to(reader, &mut text.input, chunk_bytes)
        };
        // Bytes read before an error are taken as a read of their own, then the error ends the input.
        let (read, error) = match read {
            Ok(_) => (text.input.len() - old, None),
            Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
            Err(error) => (text.input.len() - old, Some(error)),
        };
        if read == 0 {
            if let Some(error) = error {
                read_failed(text, last_newline, long, error);
            }
            eof = true;
            break;
        }
        let open = last_newline.map_or(0, |at| at + 1);
        if let Some(line) = long.as_mut() {
            // The open line is cut short: its further bytes are only counted, up to its newline.
            let cut = open + limit.kept();
            match memchr(b'\n', &text.input[old..]) {
                Some(at) => {
                    line.extend(at);
                    text.input.drain(cut..old + at);
                    text.long_lines.push((open, line.length()));
                    *long = None;
                }
                None => {
                    line.extend(read);
                    text.input.truncate(cut);
                    if let Some(error) = error {
                        read_failed(text, last_newline, long, error);
                        eof = true;
                        break;
                    }
                    continue;
                }
            }
        }
        let searched_from = old.min(text.input.len());
        if let Some(at) = memrchr(b'\n', &text.input[searched_from..]) {
            last_newline = Some(searched_from + at);
        }
        let open = last_newline.map_or(0, |at| at + 1);
        if let Some(line) = limit.cut(text.input.len() - open) {
            *long = Some(line);
            text.input.truncate(open + limit.kept());
        }
        if let Some(error) = error {
            read_failed(text, last_newline, long, error);
            eof = true;
            break;
        }
    }
    (last_newline, eof)
}

/// Reads into `buffer` until `bytes` were read or the input ended, as `take(bytes).read_to_end` would;
/// the bytes read before an error stay in `buffer`.
fn read_up_to(reader: &mut impl Read, buffer: &mut Buffer, bytes: usize) -> io::Result<usize> {
    let mut total = 0;
    while total < bytes {
        match reader.read(buffer.room(bytes - total)) {
            Ok(0) => break,
            Ok(read) => {
                buffer.grow(read);
                total += read;
            }
            Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
    Ok(total)
}

/// As the line reader: the lines read before the error count, the unfinished one does not (its length is
/// kept for the message).
fn read_failed(text: &mut Text, last_newline: Option<usize>, long: &mut Option<LongLine>, error: io::Error) {
    let open = last_newline.map_or(0, |at| at + 1);
    let unfinished = long.take().map_or(text.input.len().saturating_sub(open), LongLine::length);
    text.unfinished = unfinished as u64;
    text.input.truncate(open);
    text.read_error = Some(error);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gives its bytes `step` at a time, then fails (a disk that goes away mid-file).
    struct FailingAfter {
        data: &'static [u8],
        at: usize,
        step: usize,
    }

    impl Read for FailingAfter {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.at == self.data.len() {
                return Err(io::Error::other("the disk went away"));
            }
            let n = self.step.min(buf.len()).min(self.data.len() - self.at);
            buf[..n].copy_from_slice(&self.data[self.at..self.at + n]);
            self.at += n;
            Ok(n)
        }
    }

    /// As the line reader: whole lines read before an error count, the unfinished one does not, whether the
    /// bytes came in one read or many (files are read a chunk at a time, streams a read at a time).
    #[test]
    fn a_read_error_keeps_the_whole_lines_read_before_it() {
        for stream in [false, true] {
            for step in [1, 5, 64, 4096] {
                let mut reader = FailingAfter { data: b"a 1\nb 2\nc 3\npartial", at: 0, step };
                let mut text = Text::default();
                let mut long = None;
                let cut = Cut { chunk_bytes: 1 << 16, stream };
                let mut ended = false;
                let mut input: Vec<u8> = Vec::new();
                while !ended {
                    // As `split`: a chunk ends after its last newline, the rest opens the next one.
                    let (last_newline, eof) = fill(&mut reader, &mut text, cut, &mut long);
                    let end = if eof { text.input.len() } else { last_newline.map_or(0, |at| at + 1) };
                    input.extend_from_slice(&text.input[..end]);
                    text.input.drain(0..end);
                    ended = eof;
                }
                assert_eq!(input, b"a 1\nb 2\nc 3\n", "stream {stream}, step {step}");
                let error = text.read_error.as_ref().map(|error| error.to_string());
                assert_eq!(error.as_deref(), Some("the disk went away"), "stream {stream}, step {step}");
                assert_eq!(text.unfinished, 7, "the unfinished line's bytes, stream {stream}, step {step}");
            }
        }
    }
}
