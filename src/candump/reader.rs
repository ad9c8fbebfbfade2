//! Streams lines out of any reader with flat memory.

use std::io::{self, Read};

use super::line_limit::{LineLimit, LongLine};

/// Finds the newline ending each line. On x86-64 a searcher built once (SSE2 is always there), which
/// skips the per-call CPU dispatch of `memchr::memchr` (measured: about a third of its cost on 46-byte
/// lines); elsewhere `memchr` itself.
#[derive(Clone, Copy)]
struct Newline {
    #[cfg(target_arch = "x86_64")]
    sse2: Option<memchr::arch::x86_64::sse2::memchr::One>,
}

impl Newline {
    fn new() -> Self {
        Self {
            #[cfg(target_arch = "x86_64")]
            sse2: memchr::arch::x86_64::sse2::memchr::One::new(b'\n'),
        }
    }

    #[inline(always)]
    fn find(&self, haystack: &[u8]) -> Option<usize> {
        #[cfg(target_arch = "x86_64")]
        if let Some(sse2) = &self.sse2 {
            return sse2.find(haystack);
        }
        memchr::memchr(b'\n', haystack)
    }
}

/// Default size of the read buffer.
pub const DEFAULT_BUFFER_CAPACITY: usize = 256 * 1024;

/// One line, without its `\n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RawLine<'a> {
    /// `number` is 1-based.
    Line { number: u64, text: &'a [u8] },
    /// A line longer than the limit: skipped up to its newline. `len` excludes the `\n`.
    TooLong { number: u64, len: usize },
}

/// Splits a reader into lines using one reusable buffer and `memchr`; nothing is allocated per line.
///
/// The buffer starts at the given capacity and grows (rarely, by doubling) only when a single line does
/// not fit, up to the line-length limit; lines above the limit are reported as [`RawLine::TooLong`] and
/// skipped without being buffered, and reading continues with the next line.
pub struct LineReader<R: Read> {
    inner: R,
    newline: Newline,
    buf: Vec<u8>,
    /// Unconsumed data is `buf[start..end]`.
    start: usize,
    end: usize,
    /// Where to resume the newline search (everything in `start..searched` has no '\n').
    searched: usize,
    limit: LineLimit,
    line_number: u64,
    bytes_read: u64,
    eof: bool,
    /// An over-long line being skipped: its bytes discarded so far.
    skipped: Option<LongLine>,
    /// Where the buffer's last whole line ends (after its `\n`), once [`LineReader::whole_lines`] looked
    /// since the last read.
    whole_end: Option<usize>,
}

impl<R: Read> LineReader<R> {
    pub fn new(inner: R) -> Self {
        Self::with_capacity(DEFAULT_BUFFER_CAPACITY, inner)
    }

    /// A reader whose buffer starts at `cap` bytes (at least 1).
    pub fn with_capacity(cap: usize, inner: R) -> Self {
        Self {
            inner,
            newline: Newline::new(),
            buf: vec![0; cap.max(1)],
            start: 0,
            end: 0,
            searched: 0,
            limit: LineLimit::DEFAULT,
            line_number: 0,
            bytes_read: 0,
            eof: false,
            skipped: None,
            whole_end: None,
        }
    }

    /// Sets the length above which lines are reported as [`RawLine::TooLong`].
    pub fn with_max_line_len(mut self, max: usize) -> Self {
        self.limit = LineLimit::new(max);
        self
    }

    /// Total bytes read from the inner reader so far (for a progress bar).
    pub fn bytes_read(&self) -> u64 {
        self.bytes_read
    }

    /// The whole lines buffered after the last one returned, each with its `\n`, and the number of the
    /// first: for a caller that finds where lines end while parsing them, which then says how far it got
    /// with [`LineReader::consume`]. Empty when no whole line is buffered (or while an over-long line is
    /// skipped): [`LineReader::next_line`] then reads on, as it does for any line the caller leaves, which
    /// must include every line over the length limit (this does not look at lengths).
    pub fn whole_lines(&mut self) -> (u64, &[u8]) {
        let first = self.line_number + 1;
        if self.skipped.is_some() {
            return (first, &[]);
        }
        // Looked for once per read: the last newline is near the end, bar a long partial line.
        let (start, end) = (self.start, self.end);
        let whole_end = *self.whole_end.get_or_insert_with(|| {
            memchr::memrchr(b'\n', &self.buf[start..end]).map_or(start, |last| start + last + 1)
        });
        (first, self.buf.get(self.start..whole_end).unwrap_or_default())
    }

    /// Marks `lines` lines of [`LineReader::whole_lines`], `bytes` bytes with their newlines, as read.
    pub fn consume(&mut self, lines: u64, bytes: usize) {
        self.start += bytes.min(self.end - self.start);
        self.searched = self.searched.max(self.start);
        self.line_number += lines;
    }

    /// The next line without its `\n`, or `None` at the end. A final line without `\n` is returned too.
    pub fn next_line(&mut self) -> io::Result<Option<RawLine<'_>>> {
        loop {
            if let Some(offset) = self.newline.find(&self.buf[self.searched..self.end]) {
                let newline = self.searched + offset;
                let (start, len) = (self.start, newline - self.start);
                self.start = newline + 1;
                self.searched = self.start;
                self.line_number += 1;
                let number = self.line_number;
                if let Some(mut skipped) = self.skipped.take() {
                    skipped.extend(len);
                    return Ok(Some(RawLine::TooLong { number, len: skipped.length() }));
                }
                if self.limit.is_over(len) {
                    return Ok(Some(RawLine::TooLong { number, len }));
                }
                return Ok(Some(RawLine::Line { number, text: &self.buf[start..newline] }));
            }
            self.searched = self.end;

            let pending = self.end - self.start;
            if let Some(skipped) = self.skipped.as_mut() {
                skipped.extend(pending);
                self.discard_pending();
            } else if let Some(long) = self.limit.cut(pending) {
                self.skipped = Some(long);
                self.discard_pending();
            }

            if self.eof {
                return Ok(self.final_line());
            }
            self.make_room();
            self.fill()?;
        }
    }

    /// At the end of input: the last line if it had no newline.
    fn final_line(&mut self) -> Option<RawLine<'_>> {
        let number = self.line_number + 1;
        if let Some(long) = self.skipped.take() {
            self.line_number = number;
            return Some(RawLine::TooLong { number, len: long.length() });
        }
        if self.start == self.end {
            return None;
        }
        let start = self.start;
        self.start = self.end;
        self.line_number = number;
        Some(RawLine::Line { number, text: &self.buf[start..self.end] })
    }

    fn discard_pending(&mut self) {
        self.whole_end = None;
        self.start = 0;
        self.end = 0;
        self.searched = 0;
    }

    /// Moves the partial line to the front, and doubles the buffer if the line fills all of it.
    fn make_room(&mut self) {
        // Every read comes after this: the last whole line is looked for again.
        self.whole_end = None;
        if self.start > 0 {
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.searched -= self.start;
            self.start = 0;
        }
        if self.end == self.buf.len() {
            // Only reached while the partial line is within the limit; the bytes the limit keeps are
            // enough to see that a line is too long.
            let target = (self.buf.len() * 2).min(self.limit.kept()).max(self.buf.len() + 1);
            self.buf.resize(target, 0);
        }
    }

    fn fill(&mut self) -> io::Result<()> {
        loop {
            match self.inner.read(&mut self.buf[self.end..]) {
                Ok(0) => {
                    self.eof = true;
                    return Ok(());
                }
                Ok(n) => {
                    self.end += n;
                    self.bytes_read += n as u64;
                    return Ok(());
                }
                Err(err) if err.kind() == io::ErrorKind::Interrupted => continue,
                Err(err) => return Err(err),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collect(input: &[u8], cap: usize, max: usize) -> Vec<(u64, Result<Vec<u8>, usize>)> {
        let mut reader = LineReader::with_capacity(cap, input).with_max_line_len(max);
        let mut lines = Vec::new();
        while let Some(line) = reader.next_line().unwrap() {
            lines.push(match line {
                RawLine::Line { number, text } => (number, Ok(text.to_vec())),
                RawLine::TooLong { number, len } => (number, Err(len)),
            });
        }
        assert_eq!(reader.bytes_read(), input.len() as u64);
        lines
    }

    #[test]
    fn splits_lines_and_keeps_a_final_line_without_newline() {
        for cap in [1, 2, 3, 7, 64, 1 << 16] {
            let lines = collect(b"a\n\nbc\r\nlast", cap, 100);
            let expected: Vec<(u64, Result<Vec<u8>, usize>)> = vec![
                (1, Ok(b"a".to_vec())),
                (2, Ok(b"".to_vec())),
                (3, Ok(b"bc\r".to_vec())),
                (4, Ok(b"last".to_vec())),
            ];
            assert_eq!(lines, expected, "cap {cap}");
        }
    }

    #[test]
    fn no_phantom_line_after_a_final_newline_or_for_empty_input() {
        assert_eq!(collect(b"x\n", 4, 10), vec![(1, Ok(b"x".to_vec()))]);
        assert!(collect(b"", 4, 10).is_empty());
        assert_eq!(collect(b"\n", 4, 10), vec![(1, Ok(Vec::new()))]);
    }

    #[test]
    fn long_lines_are_reported_and_skipped() {
        for cap in [1, 4, 16, 1024] {
            let input = b"ok\n0123456789abcdef\nfine\n0123456789";
            let lines = collect(input, cap, 8);
            let expected: Vec<(u64, Result<Vec<u8>, usize>)> =
                vec![(1, Ok(b"ok".to_vec())), (2, Err(16)), (3, Ok(b"fine".to_vec())), (4, Err(10))];
            assert_eq!(lines, expected, "cap {cap}");
        }
        // Exactly at the limit is still a line.
        assert_eq!(collect(b"12345678\n", 2, 8), vec![(1, Ok(b"12345678".to_vec()))]);
    }

    #[test]
    fn buffer_never_grows_past_the_limit() {
        let input = vec![b'x'; 10_000];
        let mut reader = LineReader::with_capacity(4, &input[..]).with_max_line_len(100);
        assert_eq!(reader.next_line().unwrap(), Some(RawLine::TooLong { number: 1, len: 10_000 }));
        assert!(reader.buf.len() <= 101);
        assert_eq!(reader.next_line().unwrap(), None);
    }

    #[test]
    fn whole_lines_taken_in_part_then_line_by_line_read_every_line_once() {
        // Short lines after the odd ones, so that reads end inside lines of a buffer read many times.
        let mut input = b"a\nbb\n\nccc\r\n0123456789abcdef\ndd\n".to_vec();
        for number in 7..100 {
            input.extend_from_slice(format!("l{number}\n").as_bytes());
        }
        input.extend_from_slice(b"last");
        for cap in [1, 2, 3, 5, 8, 64] {
            for take in 0..4 {
                let mut reader = LineReader::with_capacity(cap, &input[..]).with_max_line_len(8);
                let mut lines = Vec::new();
                loop {
                    // Take up to `take` whole lines from the buffer, then one line from next_line.
                    let (first, text) = reader.whole_lines();
                    let (mut count, mut at) = (0, 0);
                    while count < take {
                        let Some(end) = text[at..].iter().position(|&byte| byte == b'\n') else { break };
                        // As the decoder's parser does, a line over the limit is left to next_line.
                        if end > 8 {
                            break;
                        }
                        lines.push((first + count, Ok(text[at..at + end].to_vec())));
                        count += 1;
                        at += end + 1;
                    }
                    assert!(text.is_empty() || text.ends_with(b"\n"), "{text:?}");
                    reader.consume(count, at);
                    match reader.next_line().unwrap() {
                        Some(RawLine::Line { number, text }) => lines.push((number, Ok(text.to_vec()))),
                        Some(RawLine::TooLong { number, len }) => lines.push((number, Err(len))),
                        None => break,
                    }
                }
                let mut expected: Vec<(u64, Result<Vec<u8>, usize>)> = vec![
                    (1, Ok(b"a".to_vec())),
                    (2, Ok(b"bb".to_vec())),
                    (3, Ok(b"".to_vec())),
                    (4, Ok(b"ccc\r".to_vec())),
                    (5, Err(16)),
                    (6, Ok(b"dd".to_vec())),
                ];
                expected.extend((7..100).map(|number| (number, Ok(format!("l{number}").into_bytes()))));
                expected.push((100, Ok(b"last".to_vec())));
                assert_eq!(lines, expected, "cap {cap} take {take}");
            }
        }
    }

    #[test]
    fn read_errors_are_returned() {
        struct Failing;
        impl Read for Failing {
            fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
                Err(io::Error::other("boom"))
            }
        }
        assert!(LineReader::new(Failing).next_line().is_err());
    }
}
