//! The command-line definition: the single source for parsing, `--help`, shell completions and man pages.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::output::Format;
use crate::protocol::ProtocolHint;

const ABOUT: &str = "Decode, monitor, drive and diagnose the AgileX TRACER robot";

const AFTER_HELP: &str = "\
Examples:
  tracerctl decode capture.log                 decode a candump log, one line per frame
  tracerctl decode --summary capture.log       the technician's report: rates, lost frames, faults, battery
  tracerctl decode --format json capture.log   one JSON object per frame (docs/json.md)
  tracerctl decode 211#00000103000000B1        decode one frame given in cansend syntax
  tracerctl decode --serial uart.bin           decode an RS232 capture (raw bytes or hex text)";

#[derive(Debug, Parser)]
#[command(name = "tracerctl", version, about = ABOUT, after_help = AFTER_HELP, propagate_version = true)]
pub struct Cli {
    /// Protocol version: auto detects from the identifiers on the bus
    #[arg(long, global = true, value_enum, default_value_t = ProtocolArg::Auto, value_name = "VERSION")]
    pub protocol: ProtocolArg,

    /// When to colour output (colour is never used with NO_COLOR set)
    #[arg(long, global = true, value_enum, default_value_t = ColorChoice::Auto, value_name = "WHEN")]
    pub color: ColorChoice,

    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Decode candump logs, single frames or RS232 captures
    #[command(after_help = DECODE_AFTER_HELP)]
    Decode(DecodeArgs),
    /// Print a shell completion script to standard output
    Completions(CompletionsArgs),
}

const DECODE_AFTER_HELP: &str = "\
Inputs are candump logs in any variant (candump -l/-L files, console output with or without
timestamps, -x, -a, -e, colour), '-' for standard input, or frames in cansend syntax (211#00000103000000B1).
Bad lines are reported with file:line and the reason, counted, and skipped (--strict stops at the first).

Exit status: 0 success, 1 error, 2 usage error, 3 bad input with --strict.";

#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// candump logs, '-' for standard input, or frames in cansend syntax (e.g. 211#00000103000000B1)
    #[arg(value_name = "INPUT")]
    pub inputs: Vec<String>,

    /// RS232 capture to decode: raw bytes, or hex text such as "5A A5 0A 55 ..."
    #[arg(long = "serial", value_name = "FILE")]
    pub serial: Vec<PathBuf>,

    /// Output format
    #[arg(long, short = 'f', value_enum, default_value_t = Format::Text)]
    pub format: Format,

    /// Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance
    #[arg(long, short = 's')]
    pub summary: bool,

    /// Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)
    #[arg(long)]
    pub strict: bool,

    /// Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)
    #[arg(long = "id", value_name = "IDS", value_delimiter = ',', value_parser = parse_id)]
    pub ids: Vec<u32>,

    /// Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame
    #[arg(long = "msg", value_name = "NAMES", value_delimiter = ',', value_parser = parse_msg_name)]
    pub messages: Vec<&'static str>,

    /// Console timestamps are deltas between frames (candump -t d): add them up.
    /// Such stamps look exactly like -t z ones, so this cannot be detected.
    #[arg(long)]
    pub delta_stamps: bool,

    /// Never show a progress bar (it is shown only on a terminal, for large files)
    #[arg(long)]
    pub no_progress: bool,
}

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// Shell to generate completions for
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProtocolArg {
    /// Decide from the traffic
    Auto,
    /// CAN protocol V1 (older firmware, checksummed frames)
    V1,
    /// CAN protocol V2 (current firmware)
    V2,
}

impl From<ProtocolArg> for ProtocolHint {
    fn from(value: ProtocolArg) -> Self {
        match value {
            ProtocolArg::Auto => ProtocolHint::Auto,
            ProtocolArg::V1 => ProtocolHint::V1,
            ProtocolArg::V2 => ProtocolHint::V2,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColorChoice {
    Auto,
    Always,
    Never,
}

impl ColorChoice {
    /// Whether to colour a stream that is (or is not) a terminal; NO_COLOR always wins.
    pub fn enabled(self, is_terminal: bool) -> bool {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|value| !value.is_empty());
        match self {
            _ if no_color => false,
            ColorChoice::Always => true,
            ColorChoice::Never => false,
            ColorChoice::Auto => is_terminal,
        }
    }
}

/// Message names accepted by `--msg`: every TRACER message plus the shapes of other frames.
pub const FILTER_NAMES: &[&str] = &["raw", "invalid", "error_frame", "remote_request"];

fn parse_msg_name(text: &str) -> Result<&'static str, String> {
    crate::protocol::message::MESSAGE_NAMES
        .iter()
        .chain(FILTER_NAMES)
        .find(|name| **name == text)
        .copied()
        .ok_or_else(|| {
            let known: Vec<_> =
                crate::protocol::message::MESSAGE_NAMES.iter().chain(FILTER_NAMES).copied().collect();
            format!("unknown message name '{text}'; known: {}", known.join(", "))
        })
}

fn parse_id(text: &str) -> Result<u32, String> {
    let digits = text.trim().trim_start_matches("0x").trim_start_matches("0X");
    if digits.is_empty() || digits.len() > 8 {
        return Err(format!("'{text}' is not a hex identifier such as 0x211"));
    }
    u32::from_str_radix(digits, 16).map_err(|_| format!("'{text}' is not a hex identifier such as 0x211"))
}

/// The clap command, for completions, man pages and tests.
pub fn command() -> clap::Command {
    <Cli as clap::CommandFactory>::command()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn definition_is_consistent() {
        command().debug_assert();
    }

    #[test]
    fn ids_and_names_parse() {
        assert_eq!(parse_id("0x211"), Ok(0x211));
        assert_eq!(parse_id("aa01"), Ok(0xAA01));
        assert!(parse_id("0x").is_err());
        assert!(parse_id("zz").is_err());
        assert_eq!(parse_msg_name("odometry"), Ok("odometry"));
        assert!(parse_msg_name("odometer").unwrap_err().contains("known: motion_command"));
    }
}
