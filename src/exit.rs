//! Exit statuses, the same for every command (documented in docs/troubleshooting.md).

use std::io::{self, Write};

/// Everything worked.
pub const SUCCESS: u8 = 0;
/// An error: I/O, a missing file, a failed link.
pub const FAILURE: u8 = 1;
/// The command line was wrong (clap's own status).
pub const USAGE: u8 = 2;
/// Bad input data with `--strict`.
pub const DATA_ERROR: u8 = 3;
/// The robot is not ready or did not do what was asked (E-stop, latched fault, mode not switched,
/// faults that did not clear, lights not confirmed, no status from the robot).
pub const NOT_DONE: u8 = 4;
/// `commission`: the drive ran to its end and a measured figure failed its threshold.
pub const MEASURED_FAIL: u8 = 5;
/// After a termination signal: 128 + the signal number (130 SIGINT, 143 SIGTERM, 129 SIGHUP).
pub const SIGNAL_BASE: u8 = 128;

/// An error that carries its own exit status.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct Failure {
    pub code: u8,
    pub message: String,
}

impl Failure {
    pub fn data(message: impl Into<String>) -> Self {
        Self { code: DATA_ERROR, message: message.into() }
    }

    /// The robot is not ready or did not do it.
    pub fn not_done(message: impl Into<String>) -> Self {
        Self { code: NOT_DONE, message: message.into() }
    }
}

/// True when the error is a closed output pipe (`tracerctl decode big.log | head`): not a failure.
pub fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|cause| {
        cause.downcast_ref::<io::Error>().is_some_and(|io_error| io_error.kind() == io::ErrorKind::BrokenPipe)
    })
}

/// Prints the error as one line on stderr and gives the exit status.
pub fn report(error: &anyhow::Error) -> u8 {
    if is_broken_pipe(error) {
        return SUCCESS;
    }
    // Not eprintln!: a closed stderr must not turn an error into a panic (exit 101).
    let _ = writeln!(io::stderr(), "tracerctl: {error:#}");
    error.downcast_ref::<Failure>().map_or(FAILURE, |failure| failure.code)
}
