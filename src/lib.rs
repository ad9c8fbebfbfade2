//! tracerctl: a command-line tool for the AgileX TRACER.
//!
//! The library holds everything; `main.rs` only parses the command line, runs it and maps errors to an
//! exit code. `protocol` is pure (no I/O) and shared by every subcommand.

/// `eprintln!` that cannot panic: a closed stderr (`tracerctl ... 2>&1 | head -1`) loses the message, not
/// the run; the command goes on, and a moving robot is still stopped.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `eprint!` that cannot panic (see [`say!`]).
#[macro_export]
macro_rules! say_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

pub mod blackbox;
pub mod candump;
pub mod cli;
pub mod commands;
pub mod config;
pub mod control;
pub mod exit;
#[doc(hidden)]
pub mod fuzzing;
pub mod health;
pub mod link;
pub mod output;
pub mod protocol;
pub mod recorder;
pub mod session;
pub mod signals;
/// The source scanners' walk of src/ and blanking (tests/integration includes the same file by path).
#[cfg(test)]
pub(crate) mod source_scan;
// Its tests sit here, not in the file, so that the integration binary does not run them again.
#[cfg(test)]
mod source_scan_tests;

pub mod dashboard;
pub mod sim;
