//! The MCAP writer's pipeline: the thread that has the events formats each message body into a [`Batch`]
//! (one byte buffer and a header per message), and a writer thread owns the `mcap::Writer` and hands each
//! message to it. Most of an MCAP message's cost is the crate's (header serialisation, CRC, a compression
//! call per small write), so it runs beside the decoding instead of after it (docs/performance.md, "MCAP
//! output"). `BATCHES` batches circulate (filled, queued, being written) and come back for reuse: no
//! allocation per message, and memory bounded whatever the speed of either side.

use std::collections::BTreeMap;
use std::io::{self, Seek, Write};
use std::ops::Range;
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::thread::JoinHandle;

use mcap::records::{MessageHeader, Metadata};
use mcap::{McapError, McapResult};

use super::schema;

/// A batch is handed over once it holds this many bytes of bodies ...
const BATCH_BYTES: usize = 256 * 1024;
/// ... or this many messages.
const BATCH_MESSAGES: usize = 2048;
/// Batches in circulation: one being filled, the rest queued for or being written by the writer thread.
const BATCHES: usize = 3;

/// Message bodies end to end, and where each is.
#[derive(Default)]
struct Batch {
    bytes: Vec<u8>,
    messages: Vec<(MessageHeader, Range<usize>)>,
}

impl Batch {
    fn new() -> Self {
        Self {
            // Room for a last body past the threshold without growing.
            bytes: Vec::with_capacity(BATCH_BYTES + 16 * 1024),
            messages: Vec::with_capacity(BATCH_MESSAGES),
        }
    }

    fn full(&self) -> bool {
        self.bytes.len() >= BATCH_BYTES || self.messages.len() >= BATCH_MESSAGES
    }
}

/// What the writer thread is asked to do, in order.
enum Job {
    Batch(Batch),
    /// A channel registered after the start (a motor beyond the fixed ones); its id is sent back.
    AddChannel {
        schema_id: u16,
        topic: String,
    },
    Flush,
    Finish(Metadata),
}

/// The formatting side of the pipeline.
pub(super) struct Pipe<W: Write + Seek + Send + 'static> {
    current: Batch,
    /// Where the body being formatted starts in `current.bytes`.
    start: usize,
    /// `None` once the writer thread has stopped or been told to finish.
    jobs: Option<SyncSender<Job>>,
    spare: Receiver<Batch>,
    channel_ids: Receiver<u16>,
    thread: Option<JoinHandle<McapResult<Option<W>>>>,
}

impl<W: Write + Seek + Send + 'static> Pipe<W> {
    /// Starts the writer thread with `writer` (its header, schemas and channels already written).
    pub(super) fn start(writer: mcap::Writer<W>) -> McapResult<Self> {
        let (jobs, job_inbox) = mpsc::sync_channel(BATCHES - 1);
        let (spare_out, spare) = mpsc::sync_channel(BATCHES);
        let (channel_id_out, channel_ids) = mpsc::channel();
        for _ in 1..BATCHES {
            let _ = spare_out.send(Batch::new());
        }
        let thread = std::thread::Builder::new()
            .name("mcap-writer".into())
            .spawn(move || write_jobs(writer, &job_inbox, &spare_out, &channel_id_out))?;
        Ok(Self {
            current: Batch::new(),
            start: 0,
            jobs: Some(jobs),
            spare,
            channel_ids,
            thread: Some(thread),
        })
    }

    /// The buffer to append the next message's body to; [`Pipe::message`] ends it.
    pub(super) fn body(&mut self) -> &mut Vec<u8> {
        self.start = self.current.bytes.len();
        &mut self.current.bytes
    }

    /// The body appended since [`Pipe::body`] is a message with `header`.
    pub(super) fn message(&mut self, header: MessageHeader) -> McapResult<()> {
        let range = self.start..self.current.bytes.len();
        self.current.messages.push((header, range));
        if self.current.full() {
            self.hand_over()?;
        }
        Ok(())
    }

    /// Registers a channel on the writer thread, after what was formatted before it.
    pub(super) fn add_channel(&mut self, schema_id: u16, topic: String) -> McapResult<u16> {
        self.hand_over()?;
        self.send(Job::AddChannel { schema_id, topic })?;
        match self.channel_ids.recv() {
            Ok(id) => Ok(id),
            Err(_) => Err(self.stopped()),
        }
    }

    pub(super) fn flush(&mut self) -> McapResult<()> {
        self.hand_over()?;
        self.send(Job::Flush)
    }

    /// Writes what is left, `metadata`, the summary and the index; returns the output.
    pub(super) fn finish(mut self, metadata: Metadata) -> McapResult<W> {
        self.hand_over()?;
        self.send(Job::Finish(metadata))?;
        self.jobs = None;
        match self.join()? {
            Some(out) => Ok(out),
            None => Err(stopped_error()),
        }
    }

    /// Sends the current batch (if it holds anything) and takes a spare one, waiting for the writer thread
    /// when all are in use.
    fn hand_over(&mut self) -> McapResult<()> {
        if self.current.messages.is_empty() {
            return Ok(());
        }
        let Ok(next) = self.spare.recv() else { return Err(self.stopped()) };
        let full = std::mem::replace(&mut self.current, next);
        self.send(Job::Batch(full))
    }

    fn send(&mut self, job: Job) -> McapResult<()> {
        let sent = self.jobs.as_ref().is_some_and(|jobs| jobs.send(job).is_ok());
        if sent {
            Ok(())
        } else {
            Err(self.stopped())
        }
    }

    /// The writer thread's error, once it has stopped on one (a later call gets a generic error).
    fn stopped(&mut self) -> McapError {
        self.jobs = None;
        match self.join() {
            Err(error) => error,
            Ok(_) => stopped_error(),
        }
    }

    fn join(&mut self) -> McapResult<Option<W>> {
        match self.thread.take().map(JoinHandle::join) {
            Some(Ok(result)) => result,
            Some(Err(_)) | None => Err(stopped_error()),
        }
    }
}

impl<W: Write + Seek + Send + 'static> Drop for Pipe<W> {
    /// Unfinished (an error elsewhere, an early return): what was formatted is written, and the `mcap`
    /// crate's own drop finishes the file, on the writer thread, before this returns.
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.hand_over();
            self.jobs = None;
            let _ = self.join();
        }
    }
}

fn stopped_error() -> McapError {
    McapError::Io(io::Error::other("the MCAP writer stopped after an earlier error"))
}

/// The writer thread: does the jobs in order until told to finish or the formatting side is gone (its
/// drop). Stops at the first error, which the formatting side gets when it next hands something over.
fn write_jobs<W: Write + Seek>(
    mut writer: mcap::Writer<W>,
    jobs: &Receiver<Job>,
    spare: &SyncSender<Batch>,
    channel_ids: &mpsc::Sender<u16>,
) -> McapResult<Option<W>> {
    let result = do_jobs(&mut writer, jobs, spare, channel_ids);
    match result {
        Ok(true) => Ok(Some(writer.into_inner())),
        Ok(false) => Ok(None),
        Err(error) => {
            // The crate's drop tries to finish the file, which can panic after a failed write: the error
            // that stopped us is the one to report.
            let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || drop(writer)));
            Err(error)
        }
    }
}

/// Whether the file was finished.
fn do_jobs<W: Write + Seek>(
    writer: &mut mcap::Writer<W>,
    jobs: &Receiver<Job>,
    spare: &SyncSender<Batch>,
    channel_ids: &mpsc::Sender<u16>,
) -> McapResult<bool> {
    for job in jobs {
        match job {
            Job::Batch(mut batch) => {
                for (header, range) in &batch.messages {
                    let body = batch.bytes.get(range.clone()).unwrap_or_default();
                    writer.write_to_known_channel(header, body)?;
                }
                batch.bytes.clear();
                batch.messages.clear();
                let _ = spare.send(batch);
            }
            Job::AddChannel { schema_id, topic } => {
                let id = writer.add_channel(schema_id, &topic, schema::MESSAGE_ENCODING, &BTreeMap::new())?;
                let _ = channel_ids.send(id);
            }
            Job::Flush => writer.flush()?,
            Job::Finish(metadata) => {
                writer.write_metadata(&metadata)?;
                writer.finish()?;
                return Ok(true);
            }
        }
    }
    Ok(false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    fn writer<W: Write + Seek>(out: W, chunk_size: u64) -> (mcap::Writer<W>, u16) {
        let mut writer =
            mcap::WriteOptions::new().compression(None).chunk_size(Some(chunk_size)).create(out).unwrap();
        let schema = writer.add_schema("n", schema::SCHEMA_ENCODING, b"{}").unwrap();
        let channel =
            writer.add_channel(schema, "/first", schema::MESSAGE_ENCODING, &BTreeMap::new()).unwrap();
        (writer, channel)
    }

    fn header(channel_id: u16, n: u32) -> MessageHeader {
        MessageHeader { channel_id, sequence: n, log_time: u64::from(n), publish_time: u64::from(n) }
    }

    fn push(pipe: &mut Pipe<impl Write + Seek + Send + 'static>, channel: u16, n: u32) -> McapResult<()> {
        let out = pipe.body();
        out.extend_from_slice(n.to_string().as_bytes());
        pipe.message(header(channel, n))
    }

    #[test]
    fn every_message_arrives_in_order_across_batches_and_a_late_channel() {
        let (writer, first) = writer(Cursor::new(Vec::new()), 64 * 1024);
        let mut pipe = Pipe::start(writer).unwrap();
        let total = 5 * BATCH_MESSAGES as u32;
        for n in 0..total / 2 {
            push(&mut pipe, first, n).unwrap();
        }
        let late = pipe.add_channel(0, "/late".into()).unwrap();
        assert_ne!(late, first);
        for n in total / 2..total {
            push(&mut pipe, late, n).unwrap();
        }
        pipe.flush().unwrap();
        let metadata = Metadata { name: "end".into(), metadata: BTreeMap::new() };
        let bytes = pipe.finish(metadata).unwrap().into_inner();
        let messages: Vec<_> = mcap::MessageStream::new(&bytes).unwrap().map(Result::unwrap).collect();
        assert_eq!(messages.len(), total as usize);
        for (n, message) in (0..total).zip(&messages) {
            assert_eq!(message.sequence, n);
            assert_eq!(message.log_time, u64::from(n));
            assert_eq!(*message.data, *n.to_string().as_bytes());
            let topic = if n < total / 2 { "/first" } else { "/late" };
            assert_eq!(message.channel.topic, topic);
        }
        let summary = mcap::Summary::read(&bytes).unwrap().expect("finished: a summary");
        assert_eq!(summary.metadata_indexes[0].name, "end");
    }

    /// A file that takes `room` bytes, then fails like a full disk.
    struct Full {
        file: Cursor<Vec<u8>>,
        room: u64,
    }

    impl Write for Full {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.file.position() + buf.len() as u64 > self.room {
                return Err(io::Error::new(io::ErrorKind::StorageFull, "the disk is full"));
            }
            self.file.write(buf)
        }

        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    impl Seek for Full {
        fn seek(&mut self, to: io::SeekFrom) -> io::Result<u64> {
            self.file.seek(to)
        }
    }

    #[test]
    fn a_write_error_on_the_writer_thread_is_returned_by_a_later_call_and_every_call_after() {
        let (writer, channel) = writer(Full { file: Cursor::new(Vec::new()), room: 8192 }, 1024);
        let mut pipe = Pipe::start(writer).unwrap();
        let failed = (0..20 * BATCH_MESSAGES as u32).find_map(|n| push(&mut pipe, channel, n).err());
        let error = failed.expect("the error comes back within a few batches");
        assert!(
            matches!(&error, McapError::Io(error) if error.to_string().contains("the disk is full")),
            "{error:?}"
        );
        assert!(push(&mut pipe, channel, 0).is_err() || pipe.flush().is_err());
        let metadata = Metadata { name: "end".into(), metadata: BTreeMap::new() };
        let end = pipe.finish(metadata).err().expect("finish fails too");
        assert!(format!("{end:?}").contains("stopped after an earlier error"), "{end:?}");
    }

    #[test]
    fn dropped_unfinished_everything_formatted_is_written_and_the_file_finished() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("dropped.mcap");
        let (writer, channel) = writer(std::fs::File::create(&path).unwrap(), 64 * 1024);
        let mut pipe = Pipe::start(writer).unwrap();
        for n in 0..3000 {
            push(&mut pipe, channel, n).unwrap();
        }
        drop(pipe);
        let bytes = std::fs::read(&path).unwrap();
        assert!(mcap::Summary::read(&bytes).unwrap().is_some(), "finished by the crate's drop");
        assert_eq!(mcap::MessageStream::new(&bytes).unwrap().count(), 3000);
    }
}
