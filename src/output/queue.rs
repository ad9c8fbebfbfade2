//! Standard output written on a thread of its own, behind a bounded queue of blocks: whoever produces the
//! output (the monitor's receive loop) never waits for the reader of the pipe. A `monitor | less` that is not
//! scrolling blocks only the writer thread; frames are still received, stamped and checked for silence as
//! they arrive. When the queue is full a block is dropped, and its lines counted, rather than waited for.

use std::io::{self, Write};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use parking_lot::Mutex;

/// Bytes the queue holds before blocks are dropped: tens of seconds of the robot's feedback as JSON.
pub const QUEUE_BYTES: usize = 4 * 1024 * 1024;
/// Blocks it holds (a quiet bus makes small ones: a block per burst of frames).
pub const QUEUE_BLOCKS: usize = 4096;

struct Block {
    bytes: Vec<u8>,
    lines: u64,
}

#[derive(Default)]
struct Shared {
    /// When the write in progress began, in microseconds after `origin`, plus one; 0 when idle.
    writing_since: AtomicU64,
    /// Lines and bytes queued or being written.
    pending_lines: AtomicU64,
    pending_bytes: AtomicU64,
    error: Mutex<Option<io::Error>>,
}

/// What became of a block handed over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pushed {
    Queued,
    /// The queue was full: the block's lines were dropped (and counted).
    Dropped,
}

/// The producer's end: hand blocks over with [`OutputQueue::push`], end with [`OutputQueue::finish`].
pub struct OutputQueue {
    blocks: Option<SyncSender<Block>>,
    spares: Receiver<Vec<u8>>,
    shared: Arc<Shared>,
    origin: Instant,
    max_bytes: u64,
    writer: Option<JoinHandle<()>>,
    /// Lines dropped because the queue was full, or still unwritten when `finish` gave up.
    pub dropped_lines: u64,
}

impl OutputQueue {
    /// A queue to standard output.
    pub fn stdout() -> io::Result<Self> {
        Self::start(QUEUE_BLOCKS, QUEUE_BYTES, || io::stdout().lock())
    }

    /// A queue of up to `capacity` blocks and `max_bytes` to the writer `open` returns (called on the writer
    /// thread).
    pub fn start<W: Write>(
        capacity: usize,
        max_bytes: usize,
        open: impl FnOnce() -> W + Send + 'static,
    ) -> io::Result<Self> {
        let (blocks, inbox) = mpsc::sync_channel::<Block>(capacity);
        // Every buffer in circulation fits: the queue, the one being written, the producer's.
        let (spare, spares) = mpsc::sync_channel(capacity + 2);
        let shared = Arc::new(Shared::default());
        let origin = Instant::now();
        let writer = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new().name("tracerctl-output".into()).spawn(move || {
                let mut out = open();
                for mut block in inbox {
                    let began = origin.elapsed().as_micros() as u64 + 1;
                    shared.writing_since.store(began, Ordering::SeqCst);
                    let result = out.write_all(&block.bytes).and_then(|()| out.flush());
                    shared.writing_since.store(0, Ordering::SeqCst);
                    shared.pending_lines.fetch_sub(block.lines, Ordering::SeqCst);
                    shared.pending_bytes.fetch_sub(block.bytes.len() as u64, Ordering::SeqCst);
                    if let Err(error) = result {
                        *shared.error.lock() = Some(error);
                        return;
                    }
                    block.bytes.clear();
                    let _ = spare.try_send(block.bytes);
                }
            })?
        };
        Ok(Self {
            blocks: Some(blocks),
            spares,
            shared,
            origin,
            max_bytes: max_bytes as u64,
            writer: Some(writer),
            dropped_lines: 0,
        })
    }

    /// Hands over the bytes in `buffer` (holding `lines` lines), leaving `buffer` empty; never waits. An
    /// error means the writer has stopped on one (a closed pipe: `BrokenPipe`).
    pub fn push(&mut self, buffer: &mut Vec<u8>, lines: u64) -> io::Result<Pushed> {
        let Some(blocks) = &self.blocks else { return Err(self.error()) };
        let len = buffer.len() as u64;
        let drop = |buffer: &mut Vec<u8>, dropped: &mut u64| {
            *dropped += lines;
            buffer.clear();
            Ok(Pushed::Dropped)
        };
        if self.shared.pending_bytes.load(Ordering::SeqCst) + len > self.max_bytes {
            return drop(buffer, &mut self.dropped_lines);
        }
        let bytes = std::mem::replace(buffer, self.spares.try_recv().unwrap_or_default());
        self.shared.pending_lines.fetch_add(lines, Ordering::SeqCst);
        self.shared.pending_bytes.fetch_add(len, Ordering::SeqCst);
        match blocks.try_send(Block { bytes, lines }) {
            Ok(()) => Ok(Pushed::Queued),
            Err(TrySendError::Full(block)) => {
                self.shared.pending_lines.fetch_sub(lines, Ordering::SeqCst);
                self.shared.pending_bytes.fetch_sub(len, Ordering::SeqCst);
                // Keep the bigger buffer.
                *buffer = block.bytes;
                drop(buffer, &mut self.dropped_lines)
            }
            Err(TrySendError::Disconnected(_)) => {
                self.shared.pending_lines.fetch_sub(lines, Ordering::SeqCst);
                self.shared.pending_bytes.fetch_sub(len, Ordering::SeqCst);
                self.blocks = None;
                Err(self.error())
            }
        }
    }

    /// How long the write in progress has been waiting for the reader, if one is.
    pub fn stalled(&self) -> Option<Duration> {
        let since = self.shared.writing_since.load(Ordering::SeqCst);
        let since = Duration::from_micros(since.checked_sub(1)?);
        Some(self.origin.elapsed().saturating_sub(since))
    }

    /// Lets the writer write out everything queued, unless `give_up` says stop first (checked every 10 ms);
    /// what was still unwritten then is added to `dropped_lines`. An error if the writer stopped on one.
    pub fn finish(&mut self, mut give_up: impl FnMut() -> bool) -> io::Result<()> {
        self.blocks = None;
        let Some(writer) = self.writer.take() else { return Ok(()) };
        while !writer.is_finished() {
            if give_up() {
                // The writer stays blocked in its write; the process exits without it.
                self.dropped_lines += self.shared.pending_lines.swap(0, Ordering::SeqCst);
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        let _ = writer.join();
        match self.shared.error.lock().take() {
            Some(error) => Err(error),
            None => Ok(()),
        }
    }

    fn error(&self) -> io::Error {
        self.shared
            .error
            .lock()
            .take()
            .unwrap_or_else(|| io::Error::new(io::ErrorKind::BrokenPipe, "the output thread has stopped"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::Sender;
    use std::sync::Mutex;

    /// A writer that blocks until the test lets it go, then collects what it was given.
    struct Gate {
        open: Arc<(Mutex<bool>, std::sync::Condvar)>,
        out: Sender<Vec<u8>>,
    }

    impl Write for Gate {
        fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
            let (lock, opened) = &*self.open;
            let mut open = lock.lock().unwrap();
            while !*open {
                open = opened.wait(open).unwrap();
            }
            self.out.send(bytes.to_vec()).unwrap();
            Ok(bytes.len())
        }

        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_blocked_reader_never_blocks_the_producer_and_overflow_is_counted() {
        let open = Arc::new((Mutex::new(false), std::sync::Condvar::new()));
        let (out, written) = mpsc::channel();
        let gate = Gate { open: Arc::clone(&open), out };
        let mut queue = OutputQueue::start(4, QUEUE_BYTES, move || gate).unwrap();
        let start = Instant::now();
        let mut dropped_blocks = 0;
        for n in 0..20u8 {
            let mut buffer = vec![b'a' + n, b'\n'];
            if queue.push(&mut buffer, 1).unwrap() == Pushed::Dropped {
                dropped_blocks += 1;
            }
            assert!(buffer.is_empty());
            // The writer takes the first block and stays in its write.
            while n == 0 && queue.stalled().is_none() {
                std::thread::sleep(Duration::from_millis(1));
            }
        }
        assert!(start.elapsed() < Duration::from_secs(1), "pushing never waits");
        // One block is in the blocked write, four are queued: the other fifteen were dropped.
        assert_eq!((dropped_blocks, queue.dropped_lines), (15, 15));
        std::thread::sleep(Duration::from_millis(30));
        assert!(queue.stalled().is_some_and(|stall| stall >= Duration::from_millis(20)));
        *open.0.lock().unwrap() = true;
        open.1.notify_all();
        queue.finish(|| false).unwrap();
        let text: Vec<u8> = written.try_iter().flatten().collect();
        assert_eq!(text, b"a\nb\nc\nd\ne\n");
        assert_eq!(queue.stalled(), None);
    }

    #[test]
    fn the_byte_limit_drops_too() {
        let open = Arc::new((Mutex::new(false), std::sync::Condvar::new()));
        let (out, written) = mpsc::channel();
        let gate = Gate { open: Arc::clone(&open), out };
        let mut queue = OutputQueue::start(100, 10, move || gate).unwrap();
        let pushed: Vec<Pushed> = (0..4).map(|_| queue.push(&mut b"1234\n".to_vec(), 1).unwrap()).collect();
        assert_eq!(pushed, [Pushed::Queued, Pushed::Queued, Pushed::Dropped, Pushed::Dropped]);
        *open.0.lock().unwrap() = true;
        open.1.notify_all();
        queue.finish(|| false).unwrap();
        assert_eq!(written.try_iter().flatten().count(), 10);
        assert_eq!(queue.dropped_lines, 2);
    }

    #[test]
    fn finish_gives_up_on_a_reader_that_never_reads_and_counts_what_was_left() {
        let open = Arc::new((Mutex::new(false), std::sync::Condvar::new()));
        let (out, _written) = mpsc::channel();
        let gate = Gate { open: Arc::clone(&open), out };
        let mut queue = OutputQueue::start(4, QUEUE_BYTES, move || gate).unwrap();
        for _ in 0..3 {
            queue.push(&mut b"x\ny\n".to_vec(), 2).unwrap();
        }
        queue.finish(|| true).unwrap();
        assert_eq!(queue.dropped_lines, 6);
        // Let the stuck writer go, so the test leaves no thread behind.
        *open.0.lock().unwrap() = true;
        open.1.notify_all();
    }

    #[test]
    fn a_closed_pipe_is_an_error_for_the_producer() {
        struct Closed;
        impl Write for Closed {
            fn write(&mut self, _: &[u8]) -> io::Result<usize> {
                Err(io::Error::new(io::ErrorKind::BrokenPipe, "closed"))
            }
            fn flush(&mut self) -> io::Result<()> {
                Ok(())
            }
        }
        let mut queue = OutputQueue::start(4, QUEUE_BYTES, || Closed).unwrap();
        queue.push(&mut b"x\n".to_vec(), 1).unwrap();
        let deadline = Instant::now() + Duration::from_secs(5);
        let error = loop {
            match queue.push(&mut b"x\n".to_vec(), 1) {
                Err(error) => break error,
                Ok(_) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(5)),
                Ok(_) => panic!("the error never came"),
            }
        };
        assert_eq!(error.kind(), io::ErrorKind::BrokenPipe);
    }
}
