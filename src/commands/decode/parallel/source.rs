//! Where the workers of `decode -j` get their chunks: a stream's reader thread, a compressed file read one
//! worker at a time, or a plain file's ranges.

use std::io::{self, Read};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;

use parking_lot::Mutex;

use super::super::interrupt::StopReading;
use super::super::ranges::Ranges;
use super::super::splitter::Splitter;
use super::super::Interrupted;
use super::settings::Start;
use super::worker::Chunk;
use super::WAKE;

/// The reader thread of a stream: chunks from the pool, filled, to the workers' queue.
pub(super) fn split(
    mut splitter: Splitter<impl Read>,
    pool: mpsc::Receiver<Chunk>,
    work: mpsc::Sender<Chunk>,
    finished: &AtomicBool,
) {
    while !splitter.ended() {
        let Ok(mut chunk) = pool.recv() else { return };
        if finished.load(Ordering::Relaxed) {
            return;
        }
        if let Some(index) = splitter.next_text(&mut chunk.text) {
            chunk.index = index;
            if work.send(chunk).is_err() {
                return;
            }
        }
    }
}

/// Where the workers get their chunks.
pub(super) enum Source<R> {
    /// A stream: from the reader thread, whose reads may block for as long as the stream is quiet.
    Queue(Mutex<mpsc::Receiver<Chunk>>),
    /// A file through its decompressor (or a plain one whose handle could not be shared): each worker reads
    /// its next chunk itself, one worker at a time (no reader thread to hand chunks over: 2-7 % less time,
    /// measured in docs/performance.md).
    File { splitter: Mutex<Splitter<R>>, pool: Mutex<mpsc::Receiver<Chunk>> },
    /// A plain file: each worker claims the next range and reads it itself, as it decodes it.
    Ranges { ranges: Arc<Ranges>, pool: Mutex<mpsc::Receiver<Chunk>> },
}

/// Why a worker got no chunk.
pub(super) enum Idle {
    /// Nothing yet: look again (unless decoding ended).
    NotYet,
    /// The input ended or the others stopped.
    Ended,
}

impl<R: Read> Source<R> {
    /// The next chunk, with the start its first line is guessed to be decoded from.
    pub fn take(&self, guess: &Mutex<Start>) -> Result<(Chunk, Start), Idle> {
        let received = match self {
            Source::Queue(work) => work.lock().recv_timeout(WAKE),
            Source::File { pool, .. } | Source::Ranges { pool, .. } => pool.lock().recv_timeout(WAKE),
        };
        let mut chunk = match received {
            Ok(chunk) => chunk,
            Err(RecvTimeoutError::Timeout) => return Err(Idle::NotYet),
            Err(RecvTimeoutError::Disconnected) => return Err(Idle::Ended),
        };
        if let Source::Ranges { ranges, .. } = self {
            // Guessed before the range is let go: only ranges before this one can have published their verdict.
            let Some(range) = ranges.claim_with(|| guess.lock().clone()) else { return Err(Idle::Ended) };
            chunk.index = range.0.index;
            chunk.range = Some(range.0);
            return Ok((chunk, range.1));
        }
        if let Source::File { splitter, .. } = self {
            let mut splitter = splitter.lock();
            let Some(index) = splitter.next_text(&mut chunk.text) else { return Err(Idle::Ended) };
            chunk.index = index;
            // Guessed while the file is held: only chunks before this one can have published their verdict.
            return Ok((chunk, guess.lock().clone()));
        }
        Ok((chunk, guess.lock().clone()))
    }
}

/// The input as the workers read it: every read looks at the stop first, so a worker inside an endless line
/// (a decompression bomb of zeros, which it reads on to its `\n`) lets go at a signal.
pub(super) struct Stopping<R> {
    pub inner: R,
    pub stop: StopReading,
}

impl<R: Read> Read for Stopping<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.stop.now() {
            return Err(io::Error::other(Interrupted));
        }
        self.inner.read(buf)
    }
}

#[cfg(test)]
mod tests {
    use super::super::super::splitter::Cut;
    use super::*;
    use crate::candump::DEFAULT_MAX_LINE_LEN;

    fn split_all(text: &[u8], chunk_bytes: usize) -> Vec<Chunk> {
        let (pool_tx, pool_rx) = mpsc::channel();
        let (work_tx, work_rx) = mpsc::channel();
        for _ in 0..10_000 {
            pool_tx.send(Chunk::default()).unwrap();
        }
        let cut = Cut { chunk_bytes, stream: false };
        split(Splitter::new(text, cut), pool_rx, work_tx, &AtomicBool::new(false));
        work_rx.iter().collect()
    }

    #[test]
    fn chunks_end_after_a_newline_and_hold_every_byte() {
        let text = b"a\r\nbb\n\nccc\nlast";
        for chunk_bytes in 1..20 {
            let chunks = split_all(text, chunk_bytes);
            let joined: Vec<u8> = chunks.iter().flat_map(|chunk| chunk.text.input.to_vec()).collect();
            assert_eq!(joined, text, "chunk size {chunk_bytes}");
            for chunk in &chunks[..chunks.len() - 1] {
                assert_eq!(chunk.text.input.last(), Some(&b'\n'), "chunk size {chunk_bytes}");
            }
            assert_eq!(chunks.iter().map(|c| c.text.bytes).sum::<u64>(), text.len() as u64);
        }
        assert!(split_all(b"", 4).is_empty());
    }

    #[test]
    fn an_overlong_line_is_cut_short_with_its_length() {
        let long = DEFAULT_MAX_LINE_LEN * 3 + 5;
        let mut text = b"ok\n".to_vec();
        text.extend(std::iter::repeat_n(b'x', long));
        text.extend_from_slice(b"\nfine\n");
        text.extend(std::iter::repeat_n(b'y', long));
        for chunk_bytes in [1000, 70_000, 1 << 20] {
            let chunks = split_all(&text, chunk_bytes);
            let longs: Vec<usize> =
                chunks.iter().flat_map(|c| c.text.long_lines.iter().map(|&(_, len)| len)).collect();
            // Only the line still open when a read ends is cut; one read of all holds the first whole.
            let expected = if chunk_bytes > text.len() { vec![long] } else { vec![long, long] };
            assert_eq!(longs, expected, "chunk size {chunk_bytes}");
            assert!(chunks.iter().all(|c| c.text.input.len() <= chunk_bytes.max(DEFAULT_MAX_LINE_LEN) * 3));
            assert_eq!(chunks.iter().map(|c| c.text.bytes).sum::<u64>(), text.len() as u64);
        }
    }
}
