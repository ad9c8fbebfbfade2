//! Decompression on its own thread, so that decoding a compressed log costs about what decoding the plain
//! file costs: one core inflates while the other decodes.
//!
//! The thread reads the decompressor into a few fixed blocks and sends them, in order, to a
//! [`ThreadedReader`] on the decoding side, which gives each block back once it is read: memory stays at
//! [`BLOCKS`] x [`BLOCK_LEN`] whatever the size of the log. Each block holds what one read of the
//! decompressor returned, so a slow (live) compressed stream is passed on as soon as it is inflated.
//! A read error is sent in its place, after every byte before it, and reaches the reader unchanged.
//!
//! Dropping the reader ends the thread: its next send (or its wait for a free block) fails. A thread
//! blocked reading a quiet pipe ends with the process.

use std::io::{self, Read};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender};
use std::time::Duration;

/// Bytes per block: as large as the line reader's own buffer, so one read usually fills it.
pub const BLOCK_LEN: usize = 256 * 1024;
/// Blocks in flight: one being filled, one being read, the rest queued.
pub const BLOCKS: usize = 4;
/// A reader waiting longer than this for a block returns `Interrupted`, so a caller that stops on a
/// signal (decode's Ctrl-C on a quiet stream) gets to look at its flag; every reader retries it.
const WAKE_EVERY: Duration = Duration::from_millis(50);

/// A filled block and the number of its bytes that count; 0 means the end of the stream.
type Filled = io::Result<(Vec<u8>, usize)>;

/// The decoding side: an ordinary [`Read`] over the blocks the thread sends.
pub struct ThreadedReader {
    filled: Receiver<Filled>,
    free: SyncSender<Vec<u8>>,
    block: Vec<u8>,
    start: usize,
    end: usize,
    finished: bool,
}

/// Starts a thread reading `inner` (a decompressor) and returns the reader of what it reads.
pub fn spawn(inner: impl Read + Send + 'static) -> io::Result<ThreadedReader> {
    let (filled_tx, filled) = sync_channel(BLOCKS);
    let (free, free_rx) = sync_channel(BLOCKS);
    for _ in 0..BLOCKS {
        // Cannot fail: the receiver is here and the channel holds every block.
        let _ = free.try_send(Vec::new());
    }
    std::thread::Builder::new()
        .name("decompress".into())
        .spawn(move || fill_blocks(inner, &filled_tx, &free_rx))?;
    Ok(ThreadedReader { filled, free, block: Vec::new(), start: 0, end: 0, finished: false })
}

/// The thread: fills free blocks until the end of the stream, an error, or the reader is gone.
fn fill_blocks(mut inner: impl Read, filled: &SyncSender<Filled>, free: &Receiver<Vec<u8>>) {
    while let Ok(mut block) = free.recv() {
        // Only the first use of a block allocates; its length stays BLOCK_LEN afterwards.
        block.resize(BLOCK_LEN, 0);
        let read = loop {
            match inner.read(&mut block) {
                Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
                result => break result,
            }
        };
        let last = !matches!(read, Ok(n) if n > 0);
        if filled.send(read.map(|n| (block, n))).is_err() || last {
            return;
        }
    }
}

impl Read for ThreadedReader {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        while self.start == self.end {
            if self.finished {
                return Ok(0);
            }
            if self.block.capacity() > 0 {
                // Never full: the channel holds every block there is.
                let _ = self.free.try_send(std::mem::take(&mut self.block));
            }
            match self.filled.recv_timeout(WAKE_EVERY) {
                Ok(Ok((block, len))) => {
                    self.finished = len == 0;
                    (self.block, self.start, self.end) = (block, 0, len);
                }
                Ok(Err(error)) => {
                    self.finished = true;
                    return Err(error);
                }
                Err(RecvTimeoutError::Timeout) => return Err(io::ErrorKind::Interrupted.into()),
                Err(RecvTimeoutError::Disconnected) => {
                    self.finished = true;
                    return Err(io::Error::other("the decompression thread stopped"));
                }
            }
        }
        let n = buf.len().min(self.end - self.start);
        buf[..n].copy_from_slice(&self.block[self.start..self.start + n]);
        self.start += n;
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Returns its bytes a few at a time, then an error.
    struct Dribble {
        data: Vec<u8>,
        at: usize,
        fail: bool,
    }

    impl Read for Dribble {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            if self.at == self.data.len() {
                return if self.fail {
                    Err(io::Error::new(io::ErrorKind::UnexpectedEof, "cut"))
                } else {
                    Ok(0)
                };
            }
            let n = buf.len().min(7).min(self.data.len() - self.at);
            buf[..n].copy_from_slice(&self.data[self.at..self.at + n]);
            self.at += n;
            Ok(n)
        }
    }

    fn read_all(reader: &mut ThreadedReader) -> (Vec<u8>, Option<io::Error>) {
        let mut out = Vec::new();
        let mut buf = [0u8; 5];
        loop {
            match reader.read(&mut buf) {
                Ok(0) => return (out, None),
                Ok(n) => out.extend_from_slice(&buf[..n]),
                Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
                Err(error) => return (out, Some(error)),
            }
        }
    }

    #[test]
    fn every_byte_comes_through_in_order_then_the_end_stays_the_end() {
        let data: Vec<u8> = (0..3 * BLOCK_LEN as u32 + 11).map(|i| (i % 251) as u8).collect();
        let mut reader = spawn(io::Cursor::new(data.clone())).unwrap();
        let (out, error) = read_all(&mut reader);
        assert!(error.is_none());
        assert_eq!(out, data);
        assert_eq!(reader.read(&mut [0u8; 4]).unwrap(), 0);
    }

    #[test]
    fn an_error_arrives_after_the_bytes_before_it_with_its_kind_and_message() {
        let mut reader = spawn(Dribble { data: b"abcdefghijklmnop".to_vec(), at: 0, fail: true }).unwrap();
        let (out, error) = read_all(&mut reader);
        assert_eq!(out, b"abcdefghijklmnop");
        let error = error.unwrap();
        assert_eq!((error.kind(), error.to_string()), (io::ErrorKind::UnexpectedEof, "cut".to_string()));
        assert_eq!(reader.read(&mut [0u8; 4]).unwrap(), 0);
    }

    #[test]
    fn dropping_the_reader_ends_the_thread() {
        struct Endless(std::sync::Arc<std::sync::atomic::AtomicBool>);
        impl Read for Endless {
            fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
                buf.fill(b'x');
                Ok(buf.len())
            }
        }
        impl Drop for Endless {
            fn drop(&mut self) {
                self.0.store(true, std::sync::atomic::Ordering::SeqCst);
            }
        }
        let dropped = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let mut reader = spawn(Endless(dropped.clone())).unwrap();
        assert_eq!(reader.read(&mut [0u8; 3]).unwrap(), 3);
        drop(reader);
        let deadline = std::time::Instant::now() + Duration::from_secs(10);
        while !dropped.load(std::sync::atomic::Ordering::SeqCst) {
            assert!(std::time::Instant::now() < deadline, "the thread still runs");
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}
