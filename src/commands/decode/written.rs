//! Where decoded text goes: a buffer written out in blocks, or at once on a terminal, and before every read
//! of the input ([`LiveInput`]), so a live stream leaves line by line; and the errors of both ends.

use std::io::{self, Read, Write};
use std::{cell::RefCell, rc::Rc};

use crate::exit::Failure;
use crate::signals::SignalFlag;

/// The decoded text not yet written. Shared with [`LiveInput`], which writes it out before each read of
/// the input, so a live stream leaves line by line while bulk input still goes out in large blocks.
pub(super) struct Written {
    pub buffer: Vec<u8>,
    pub out: Box<dyn Write>,
    /// Every event is written at once (standard output is a terminal).
    pub line_buffered: bool,
    /// The file's path, or `standard output`, for messages.
    pub name: String,
    /// A write failed (a full disk): the error was returned once, and nothing more is written.
    pub failed: bool,
}

impl Written {
    pub fn flush(&mut self) -> io::Result<()> {
        if self.failed {
            return Ok(());
        }
        self.write_through(&[])?;
        self.out.flush().map_err(|error| self.failure(error))
    }

    /// Writes what is buffered, then `bytes` straight through (a decoded chunk: no copy into the buffer).
    pub fn write_through(&mut self, bytes: &[u8]) -> io::Result<()> {
        if self.failed {
            return Ok(());
        }
        if !self.buffer.is_empty() {
            let result = self.out.write_all(&self.buffer);
            self.buffer.clear();
            result.map_err(|error| self.failure(error))?;
        }
        self.out.write_all(bytes).map_err(|error| self.failure(error))?;
        if self.line_buffered {
            self.out.flush().map_err(|error| self.failure(error))?;
        }
        Ok(())
    }

    /// `error` with the output's name; the output is given up.
    fn failure(&mut self, error: io::Error) -> io::Error {
        self.failed = true;
        io::Error::new(error.kind(), OutputFailed { name: self.name.clone(), error })
    }
}

/// A failed write of the output, naming it: `cannot write out.csv: No space left on device (os error 28)`.
/// Inside an `io::Error` of the same kind, so a closed pipe is still told apart (and stays quiet).
#[derive(Debug, thiserror::Error)]
#[error("cannot write {name}: {error}")]
pub(super) struct OutputFailed {
    pub name: String,
    pub error: io::Error,
}

/// A write of the output failed inside a read of the input (see [`LiveInput`]).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub(super) struct WriteFailed(io::Error);

/// A termination signal arrived while reading.
#[derive(Debug, thiserror::Error)]
#[error("interrupted")]
pub(super) struct Interrupted;

/// The input as the decoder reads it: before every read (which may block on a pipe, a terminal or a serial
/// port) the decoded output is written out, and a termination signal ends the reading. On a regular file
/// this costs one write per read buffer (256 KiB of input), the same blocks as before.
pub(super) struct LiveInput<R> {
    pub inner: R,
    pub output: Option<Rc<RefCell<Written>>>,
    pub signals: SignalFlag,
}

impl<R: Read> Read for LiveInput<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            if self.signals.received().is_some() {
                return Err(io::Error::other(Interrupted));
            }
            if let Some(output) = &self.output {
                output
                    .borrow_mut()
                    .flush()
                    .map_err(|error| io::Error::new(error.kind(), WriteFailed(error)))?;
            }
            match self.inner.read(buf) {
                // A signal interrupts a blocked read (see interrupt.rs); the loop looks at the flag.
                Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
                result => return result,
            }
        }
    }
}

/// A failure while decoding line `number` of `name`, with that place in its message.
pub(super) fn in_line(error: anyhow::Error, name: &str, number: u64) -> anyhow::Error {
    match error.downcast::<Failure>() {
        Ok(failure) => Failure::data(format!("{name}:{number}: {}", failure.message)).into(),
        Err(other) => other,
    }
}

/// A read error of `name`, unless it was really a failed write of the output (or a signal).
pub(super) fn read_error(error: io::Error, name: &str) -> anyhow::Error {
    let inner = error.get_ref();
    if inner.is_some_and(|inner| inner.is::<WriteFailed>() || inner.is::<Interrupted>()) {
        anyhow::Error::new(error)
    } else {
        anyhow::Error::new(error).context(format!("cannot read {name}"))
    }
}
