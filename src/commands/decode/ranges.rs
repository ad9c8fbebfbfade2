//! A plain file cut into byte ranges that the workers of `decode -j` read themselves: each maps its range
//! into memory a window at a time and decodes the lines where they stand ([`Window`]), or, where a window
//! does not serve (the last range, which may grow; a line longer than a window; a file cut short since), reads
//! them with positioned reads (`pread`) into a small buffer of its own that stays in the cache. Reading the
//! whole chunk into a pool buffer first cost the parallel summary a third of its time: the kernel's copy into
//! cold memory, the first touch of the pool's pages, and the hand-overs; the mapping saves the copy
//! `pread` still makes (docs/performance.md).
//!
//! Ranges are whole lines: the claim of a range looks (one small read) for the first line start at or after
//! its nominal end, and the next range starts there. A worker thus reads whole lines from its range's start
//! to its end, as the single thread reads them: a line longer than the line limit is only counted (its true
//! length), the unfinished line before a read error is dropped, and the last range reads on to wherever the
//! file ends when it gets there.

use std::cell::RefCell;
use std::fs::File;
use std::io;

use memchr::{memchr, memrchr};
use parking_lot::Mutex;

use super::interrupt::StopReading;
use super::mapped::{FaultHandler, Window};
use super::Interrupted;
use crate::candump::{self, LineLimit, LongLine};

/// Bytes a read asks for: a slice this size and the line it carries over stay in a core's L2 cache.
pub const SLICE_BYTES: usize = 128 * 1024;
/// Bytes mapped at once: the page faults of larger windows cost no less, and two threads' windows are what
/// the mapping adds to the resident memory (measured on 10 M lines, `--summary -j2`: 1 MiB windows 5 %
/// slower, 32 MiB no faster).
pub const WINDOW_BYTES: usize = 4 << 20;
/// Guided range sizes (`--summary`): each range is a share of what is left, between these bounds, so the
/// workers finish together without a hand-over per slice.
const MIN_GUIDED_BYTES: u64 = 1 << 20;
const MAX_GUIDED_BYTES: u64 = 32 << 20;
/// Bytes a read asks for when looking for where a range ends.
const SCAN_BYTES: usize = 1024;
/// The size of the first range of each worker (`--summary`).
const FIRST_GUIDED_BYTES: u64 = 256 << 10;

/// One range of the file: its place in the input order, its first byte and the byte after it (`None`: on to
/// the end of the file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Range {
    pub index: u64,
    pub start: u64,
    pub end: Option<u64>,
}

/// How large the ranges are.
#[derive(Clone, Copy, Debug)]
pub enum Sizing {
    /// Every range this many bytes (output modes, whose output per range is held until written; tests).
    Fixed(u64),
    /// A share of what is left for this many workers (`--summary`, which holds nothing per range).
    Guided { threads: u64 },
}

/// What a range's reading hands the decoder, in order.
pub enum Piece<'a> {
    /// Whole lines: each ends with its `\n` but the file's last, which may not.
    Lines(&'a [u8]),
    /// A line longer than the line limit: its length without the `\n`.
    TooLong(usize),
}

/// How the mapped windows of a range ended.
enum Mapped {
    /// The range's lines from here on are read.
    ReadOn,
    /// The decoder stopped.
    Stopped,
    /// A window's page could not be read after its lines were handed over.
    Faulted,
}

/// How a range's reading ended.
pub struct RangeEnd {
    /// Bytes of the lines handed over (for the progress bar).
    pub bytes: u64,
    pub error: Option<io::Error>,
    /// A page of a mapped window vanished while its lines were handed over (the file was cut short, or its
    /// disk failed): they may hold zeros that were never in the file, so the range must be decoded again
    /// from its start, read without mapping ([`Ranges::read`] with `mapped` false), which finds the file's
    /// true end or the disk's error.
    pub reread: bool,
}

/// A plain file and the ranges not yet claimed.
pub struct Ranges {
    file: File,
    /// The file's size when decoding began: the range reaching it reads on to the end.
    size: u64,
    sizing: Sizing,
    slice_bytes: usize,
    /// Bytes mapped at once, with the fault handler mapping needs; `None`: read only.
    windows: Option<(FaultHandler, usize)>,
    next: Mutex<(u64, Option<u64>)>,
    /// Looked at before every read and window: a line of gigabytes is let go at a signal.
    stop: Option<StopReading>,
}

thread_local! {
    /// Each thread's read buffer, kept between ranges.
    static BUFFER: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
}

impl Ranges {
    /// `slice_bytes` is what a read asks for, `windows` how much is mapped at once (tests make them tiny to
    /// cut lines everywhere).
    pub fn new(
        file: File,
        text_start: u64,
        size: u64,
        sizing: Sizing,
        (slice_bytes, windows): (usize, Option<(FaultHandler, usize)>),
    ) -> Self {
        let windows = windows.map(|(handler, bytes)| (handler, bytes.max(1)));
        let next = Mutex::new((0, Some(text_start)));
        Self { file, size, sizing, slice_bytes: slice_bytes.max(1), windows, next, stop: None }
    }

    /// These ranges, whose reading ends (with an [`Interrupted`] error) once `stop` says so.
    pub fn stopping(self, stop: StopReading) -> Self {
        Self { stop: Some(stop), ..self }
    }

    /// The error a reading ends with when decoding stopped.
    fn stopped(&self) -> Option<io::Error> {
        self.stop.as_ref().filter(|stop| stop.now()).map(|_| io::Error::other(Interrupted))
    }

    /// The next range in input order; `None` once the range reaching the end was claimed.
    #[cfg(test)]
    pub fn claim(&self) -> Option<Range> {
        self.claim_with(|| ()).map(|(range, ())| range)
    }

    /// [`Self::claim`], with what `also` returns while no other range can be claimed.
    pub fn claim_with<T>(&self, also: impl FnOnce() -> T) -> Option<(Range, T)> {
        let mut next = self.next.lock();
        let (index, start) = (next.0, next.1?);
        let left = self.size.saturating_sub(start);
        let bytes = match self.sizing {
            Sizing::Fixed(bytes) => bytes.max(1),
            // The first ranges start before any verdict of the protocol detector is known: small, so the one
            // decoded again from the true start (see `settle`) costs little.
            Sizing::Guided { threads } if index < threads => FIRST_GUIDED_BYTES,
            Sizing::Guided { threads } => {
                (left / (threads.max(1) * 2)).clamp(MIN_GUIDED_BYTES, MAX_GUIDED_BYTES)
            }
        };
        // Up to the first line start at or after `start + bytes`: the next range starts with a whole line.
        let end = match bytes < left {
            true => self.line_start_from(start + bytes),
            false => None,
        };
        *next = (index + 1, end);
        Some((Range { index, start, end }, also()))
    }

    /// The first line start at or after `at` (after the first `\n` at or after `at - 1`); `None` at the end of
    /// the file or at a read error (the range then reads on to the end, and meets the error itself).
    fn line_start_from(&self, at: u64) -> Option<u64> {
        let mut scan = [0u8; SCAN_BYTES];
        let mut pos = at - 1;
        loop {
            if self.stopped().is_some() {
                return None;
            }
            match self.read_at(&mut scan, pos) {
                Ok(0) | Err(_) => return None,
                Ok(read) => match memchr(b'\n', &scan[..read]) {
                    Some(newline) => return Some(pos + newline as u64 + 1),
                    None => pos += read as u64,
                },
            }
        }
    }

    /// Reads the lines of `range`, handing them to `take` in order until it returns `false` (a stop); from
    /// mapped windows where they serve, if `mapped`.
    pub fn read(&self, range: Range, mapped: bool, mut take: impl FnMut(Piece<'_>) -> bool) -> RangeEnd {
        let mut pos = range.start;
        let windows = self.windows.filter(|_| mapped);
        if let (Some(end), Some(windows)) = (range.end, windows) {
            let mapped = self.read_mapped(&mut pos, end, windows, &mut take);
            let bytes = pos - range.start;
            match mapped {
                Mapped::ReadOn => {}
                Mapped::Stopped => return RangeEnd { bytes, error: None, reread: false },
                Mapped::Faulted => return RangeEnd { bytes, error: None, reread: true },
            }
        }
        let mut end = self.read_rest(Range { start: pos, ..range }, take);
        end.bytes += pos - range.start;
        end
    }

    /// Reads the lines of `range` with positioned reads.
    fn read_rest(&self, range: Range, take: impl FnMut(Piece<'_>) -> bool) -> RangeEnd {
        BUFFER.with(|buffer| {
            let mut buffer = buffer.borrow_mut();
            // Room for the longest line kept whole plus one read.
            let capacity = LineLimit::DEFAULT.kept() + self.slice_bytes;
            if buffer.len() != capacity {
                *buffer = vec![0; capacity];
            }
            self.read_into(&mut buffer, range, take)
        })
    }

    fn read_into(&self, buf: &mut [u8], range: Range, mut take: impl FnMut(Piece<'_>) -> bool) -> RangeEnd {
        let limit = LineLimit::DEFAULT;
        // `buf[..filled]` holds the file from `pos`, always a line's start; `buf[..searched]` has no `\n`
        // (each byte is looked at once: a long line read in small slices costs no rescan).
        let (mut pos, mut filled, mut searched) = (range.start, 0, 0);
        let first = pos;
        let end_of = |pos: u64| RangeEnd { bytes: pos - first, error: None, reread: false };
        let failed = |pos: u64, error| RangeEnd { bytes: pos - first, error: Some(error), reread: false };
        loop {
            if range.end.is_some_and(|end| pos >= end) {
                return end_of(pos);
            }
            if let Some(error) = self.stopped() {
                return failed(pos, error);
            }
            let newline = memrchr(b'\n', &buf[searched..filled]).map(|at| searched + at);
            searched = filled;
            if let Some(last) = newline {
                let mut lines = last + 1;
                if let Some(end) = range.end.filter(|&end| pos + lines as u64 > end) {
                    // Lines starting at `end` or after are the next range's (`end` is a line start unless the
                    // file changed since: then the line holding `end - 1` is this range's last).
                    let inside = (end - pos) as usize - 1;
                    lines = inside + memchr(b'\n', &buf[inside..filled]).map_or(lines - inside, |at| at + 1);
                }
                if !take(Piece::Lines(&buf[..lines])) {
                    return end_of(pos + lines as u64);
                }
                buf.copy_within(lines..filled, 0);
                (pos, filled, searched) = (pos + lines as u64, filled - lines, filled - lines);
                if range.end.is_some_and(|end| pos >= end) {
                    return end_of(pos);
                }
            }
            // No `\n` in the bytes of a line the limit keeps: too long, counted on to its end.
            if let Some(long) = limit.cut(filled) {
                match self.skip_long(buf, pos, long, &mut take) {
                    Ok(next) => (pos, filled, searched) = (next.0, next.1, 0),
                    Err((at, None)) => return end_of(at),
                    Err((at, Some(error))) => return failed(at, error),
                }
                continue;
            }
            let room = (buf.len() - filled).min(self.slice_bytes);
            match self.read_at(&mut buf[filled..filled + room], pos + filled as u64) {
                Err(error) => return failed(pos, error),
                // The file ends before its size when decoding began: the cut line's start is dropped.
                Ok(0) if pos + (filled as u64) < self.size => return failed(pos, self.shrank()),
                Ok(0) => {
                    // The end of the file: its last line may have no `\n`.
                    if filled > 0 {
                        take(Piece::Lines(&buf[..filled]));
                    }
                    return end_of(pos + filled as u64);
                }
                Ok(read) => filled += read,
            }
        }
    }

    /// The rest of a line longer than the limit at `pos`, whose first `length` bytes were read: only its
    /// length is handed over, counted up to its `\n`. Returns where the next line starts and how many of its
    /// bytes `buf` holds; or where the reading ended, with the error if it failed (the unfinished line
    /// before a read error is dropped, as the single thread drops it).
    fn skip_long(
        &self,
        buf: &mut [u8],
        pos: u64,
        mut line: LongLine,
        take: &mut impl FnMut(Piece<'_>) -> bool,
    ) -> Result<(u64, usize), (u64, Option<io::Error>)> {
        loop {
            if let Some(error) = self.stopped() {
                return Err((pos, Some(error)));
            }
            let length = line.length();
            match self.read_at(&mut buf[..self.slice_bytes], pos + length as u64) {
                Err(error) => return Err((pos, Some(error))),
                Ok(0) if pos + (length as u64) < self.size => return Err((pos, Some(self.shrank()))),
                Ok(0) => {
                    let next = pos + length as u64;
                    return if take(Piece::TooLong(length)) { Ok((next, 0)) } else { Err((next, None)) };
                }
                Ok(read) => {
                    let Some(at) = memchr(b'\n', &buf[..read]) else {
                        line.extend(read);
                        continue;
                    };
                    line.extend(at);
                    let length = line.length();
                    let next = pos + length as u64 + 1;
                    if !take(Piece::TooLong(length)) {
                        return Err((next, None));
                    }
                    buf.copy_within(at + 1..read, 0);
                    return Ok((next, read - at - 1));
                }
            }
        }
    }

    /// Hands the lines of `[*pos, end)` over from mapped windows, each up to its last `\n`, for as long as the
    /// windows serve; `*pos` is then the first line not handed over.
    fn read_mapped(
        &self,
        pos: &mut u64,
        end: u64,
        (handler, window_bytes): (FaultHandler, usize),
        take: &mut impl FnMut(Piece<'_>) -> bool,
    ) -> Mapped {
        while *pos < end {
            if self.stopped().is_some() {
                // The reads say it.
                return Mapped::ReadOn;
            }
            // A file cut short since is read instead: its missing pages would only fault.
            if self.file.metadata().map_or(true, |metadata| metadata.len() < end) {
                return Mapped::ReadOn;
            }
            let len = (end - *pos).min(window_bytes as u64) as usize;
            // SAFETY: the window's bytes are only handed to the decoder, which parses any bytes; lines from a
            // window that faulted or whose file shrank are decoded again from reads (`Mapped::Faulted`).
            let Some(window) = (unsafe { Window::map(handler, &self.file, *pos, len) }) else {
                return Mapped::ReadOn;
            };
            // No `\n`: a line longer than the window, whose end the reads find.
            let Some(last) = memrchr(b'\n', window.bytes()) else { return Mapped::ReadOn };
            if window.faulted() {
                return Mapped::ReadOn;
            }
            let handed = *pos + last as u64 + 1;
            let more = take(Piece::Lines(&window.bytes()[..=last]));
            // A file cut short inside the window's last page reads zeros there without a fault: its size tells.
            let cut_short = self.file.metadata().is_ok_and(|metadata| metadata.len() < handed);
            if window.faulted() || cut_short {
                return Mapped::Faulted;
            }
            *pos = handed;
            if !more {
                return Mapped::Stopped;
            }
        }
        Mapped::ReadOn
    }

    /// The error of a file found shorter than when decoding began.
    fn shrank(&self) -> io::Error {
        let now = self.file.metadata().map_or(0, |metadata| metadata.len());
        candump::shrank(self.size, now)
    }

    /// One positioned read (retried when a signal interrupts it).
    fn read_at(&self, buf: &mut [u8], offset: u64) -> io::Result<usize> {
        loop {
            match super::positioned::read_at(&self.file, buf, offset) {
                Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
                other => return other,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// Windows of `bytes`, mapped where the fault handler installs.
    fn windows(bytes: Option<usize>) -> Option<(FaultHandler, usize)> {
        Some((super::super::mapped::install_fault_handler()?, bytes?))
    }

    fn file_of(text: &[u8]) -> File {
        let mut file = tempfile::tempfile().unwrap();
        file.write_all(text).unwrap();
        file
    }

    /// Every range's lines, in order, as text or `<long N>`, read in slices of `cuts.0` bytes and mapped in
    /// windows of `cuts.1`.
    fn pieces(text: &[u8], text_start: u64, sizing: Sizing, cuts: (usize, Option<usize>)) -> Vec<Vec<u8>> {
        let cuts = (cuts.0, windows(cuts.1));
        let ranges = Ranges::new(file_of(text), text_start, text.len() as u64, sizing, cuts);
        let mut lines = Vec::new();
        while let Some(range) = ranges.claim() {
            let end = ranges.read(range, true, |piece| {
                match piece {
                    // A whole line over the limit is the decoder's to find (as in a chunk read at once).
                    Piece::Lines(text) => lines.extend(text.split_inclusive(|&b| b == b'\n').map(|line| {
                        let length = line.strip_suffix(b"\n").unwrap_or(line).len();
                        match LineLimit::DEFAULT.is_over(length) {
                            true => format!("<long {length}>").into_bytes(),
                            false => line.to_vec(),
                        }
                    })),
                    Piece::TooLong(length) => lines.push(format!("<long {length}>").into_bytes()),
                }
                true
            });
            assert!(end.error.is_none());
        }
        lines
    }

    #[test]
    fn every_line_is_read_once_whatever_the_cuts() {
        let text = b"a\n\nbb\r\nccc\n(1.0) can0 211#00\ndddd";
        let expected: Vec<Vec<u8>> = text.split_inclusive(|&b| b == b'\n').map(<[u8]>::to_vec).collect();
        for range_bytes in 1..=text.len() as u64 + 1 {
            for slice_bytes in 1..=text.len() + 1 {
                let got = pieces(text, 0, Sizing::Fixed(range_bytes), (slice_bytes, None));
                assert_eq!(got, expected, "ranges of {range_bytes}, slices of {slice_bytes}");
            }
            for window_bytes in 1..=text.len() + 1 {
                let got = pieces(text, 0, Sizing::Fixed(range_bytes), (3, Some(window_bytes)));
                assert_eq!(got, expected, "ranges of {range_bytes}, windows of {window_bytes}");
            }
        }
    }

    #[test]
    fn the_text_starts_after_the_byte_order_mark() {
        let text = b"\xEF\xBB\xBFa\nb\n";
        for range_bytes in 1..=8 {
            for window in [None, Some(1), Some(2), Some(4096)] {
                let got = pieces(text, 3, Sizing::Fixed(range_bytes), (2, window));
                assert_eq!(got, [b"a\n".to_vec(), b"b\n".to_vec()]);
            }
        }
    }

    #[test]
    fn a_line_over_the_limit_is_counted_with_its_true_length() {
        let long = LineLimit::DEFAULT.max() + 10;
        let mut text = b"a\n".to_vec();
        text.extend(std::iter::repeat_n(b'x', long));
        text.extend_from_slice(b"\nb\n");
        text.extend(std::iter::repeat_n(b'y', long + 1));
        let want = |last: usize| {
            vec![
                b"a\n".to_vec(),
                format!("<long {long}>").into_bytes(),
                b"b\n".to_vec(),
                format!("<long {last}>").into_bytes(),
            ]
        };
        // Tiny ranges: each holds at least one whole line, so a long line is scanned once to find its end.
        for range_bytes in [7, 1000, 70_000, 1 << 20] {
            for cuts in
                [(4096, None), (SLICE_BYTES, None), (4096, Some(4096)), (SLICE_BYTES, Some(WINDOW_BYTES))]
            {
                let got = pieces(&text, 0, Sizing::Fixed(range_bytes), cuts);
                assert_eq!(got, want(long + 1), "ranges of {range_bytes}, cuts {cuts:?}");
            }
        }
    }

    #[test]
    fn guided_ranges_shrink_towards_the_end_and_cover_the_file() {
        let text = b"0123456789abcde\n".repeat(1 << 19);
        let size = text.len() as u64;
        let ranges = Ranges::new(file_of(&text), 0, size, Sizing::Guided { threads: 2 }, (SLICE_BYTES, None));
        let mut claimed = Vec::new();
        while let Some(range) = ranges.claim() {
            claimed.push(range);
        }
        let first = FIRST_GUIDED_BYTES;
        assert_eq!(claimed[0], Range { index: 0, start: 0, end: Some(first) });
        assert_eq!(claimed[1], Range { index: 1, start: first, end: Some(2 * first) });
        let left = size - 2 * first;
        assert_eq!(claimed[2], Range { index: 2, start: 2 * first, end: Some(2 * first + left / 4) });
        assert!(claimed.windows(2).all(|pair| pair[0].end == Some(pair[1].start)));
        assert!(claimed.windows(2).all(|pair| pair[1].index == pair[0].index + 1));
        let last = claimed.last().unwrap();
        assert_eq!(last.end, None);
        assert!(size - last.start <= MIN_GUIDED_BYTES, "last range from {}", last.start);
        assert!(claimed.iter().all(|range| range.start % 16 == 0), "ranges start with a line");
    }

    // Windows opens no directory as a file (File::open fails before any read).
    #[cfg(unix)]
    #[test]
    fn a_read_error_keeps_the_lines_before_it() {
        // A directory cannot be read: the error is reported with nothing taken.
        for window in [None, Some(4)] {
            let dir = File::open(std::env::temp_dir()).unwrap();
            let ranges = Ranges::new(dir, 0, 10, Sizing::Fixed(4), (4, windows(window)));
            let range = ranges.claim().unwrap();
            let mut taken = 0;
            let end = ranges.read(range, true, |_| {
                taken += 1;
                true
            });
            assert_eq!((taken, end.bytes), (0, 0));
            assert!(end.error.is_some());
        }
    }

    /// A file of `lines` lines of 16 bytes, its ranges (of two pages) claimed while it was whole.
    fn claimed_then(lines: usize) -> (Ranges, File, Vec<Range>) {
        let text = b"0123456789abcde\n".repeat(lines);
        let file = file_of(&text);
        let handle = file.try_clone().unwrap();
        let ranges = Ranges::new(
            file,
            0,
            text.len() as u64,
            Sizing::Fixed(8192),
            (SLICE_BYTES, windows(Some(WINDOW_BYTES))),
        );
        let claimed = std::iter::from_fn(|| ranges.claim()).collect();
        (ranges, handle, claimed)
    }

    #[test]
    fn a_file_cut_short_before_a_range_is_read_gives_the_whole_lines_left_and_says_so() {
        let (ranges, handle, claimed) = claimed_then(1024);
        // Into the range's first page, mid-line: its second page is gone.
        handle.set_len(8192 + 168).unwrap();
        let mut lines = 0;
        let end = ranges.read(claimed[1], true, |piece| {
            let Piece::Lines(text) = piece else { panic!("no line is long") };
            lines += text.iter().filter(|&&b| b == b'\n').count();
            assert!(!text.contains(&0), "nothing of the missing page");
            assert!(text.ends_with(b"\n"), "the cut line is not handed over");
            true
        });
        assert_eq!((lines, end.bytes), (10, 160));
        let error = end.error.expect("the shorter file is reported");
        assert_eq!(error.to_string(), "it shrank while being read (16384 bytes, now 8360)");
    }

    /// Reads the first range of a file that another program cuts to `length` bytes while the range's window
    /// is being decoded (Unix only: elsewhere nothing is mapped), as a worker does (again without mapping when a window's pages vanished): the lines
    /// the decoder was handed in the end, whether the first reading had handed over zeros, how it ended.
    #[cfg(unix)]
    fn read_while_cut_to(length: u64) -> (Vec<u8>, bool, RangeEnd) {
        let (ranges, handle, claimed) = claimed_then(1024);
        let mut zeros = false;
        let mut first = ranges.read(claimed[0], true, |piece| {
            let Piece::Lines(text) = piece else { panic!("no line is long") };
            handle.set_len(length).unwrap();
            zeros |= text.ends_with(&[0; 4]);
            true
        });
        assert!(first.reread, "the mapped lines are not trusted");
        let mut lines = Vec::new();
        first = ranges.read(claimed[0], false, |piece| {
            let Piece::Lines(text) = piece else { panic!("no line is long") };
            lines.extend_from_slice(text);
            true
        });
        (lines, zeros, first)
    }

    #[cfg(unix)]
    #[test]
    fn a_file_cut_short_inside_the_last_page_of_its_window_gives_the_whole_lines_left() {
        // Into the window's last page, mid-line: its end reads as zeros, and no page faults.
        let (lines, zeros, end) = read_while_cut_to(8192 - 100);
        assert!(zeros, "the mapping read zeros past the new end");
        assert_eq!(lines, b"0123456789abcde\n".repeat(505), "the whole lines before the cut, no zero");
        assert_eq!(end.bytes, 505 * 16);
        let error = end.error.expect("the shorter file is reported");
        assert_eq!(error.to_string(), "it shrank while being read (16384 bytes, now 8092)");
    }

    #[cfg(unix)]
    #[test]
    fn a_file_cut_short_while_its_window_is_decoded_counts_no_zero_and_does_not_crash() {
        // Every page of the mapping goes.
        let (lines, zeros, end) = read_while_cut_to(0);
        assert!(zeros, "the vanished page reads as zeros");
        assert_eq!((lines.len(), end.bytes), (0, 0), "nothing of the faulted window is counted");
        let error = end.error.expect("the shorter file is reported");
        assert_eq!(error.to_string(), "it shrank while being read (16384 bytes, now 0)");
    }
}
