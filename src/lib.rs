//! tracerctl: a command-line tool for the AgileX TRACER.
//!
//! The library holds everything; `main.rs` only parses the command line, runs it and maps errors to an
//! exit code. `protocol` is pure (no I/O) and shared by every subcommand.

pub mod candump;
pub mod cli;
pub mod commands;
pub mod control;
pub mod exit;
pub mod link;
pub mod output;
pub mod protocol;
pub mod session;
pub mod signals;

pub mod dashboard;
pub mod sim;
