//! One small module per subcommand.

pub mod completions;
pub mod decode;

use crate::cli::{Cli, Command};

/// Runs the parsed command line and returns the exit status.
pub fn run(cli: Cli) -> anyhow::Result<u8> {
    match cli.command {
        Command::Decode(ref args) => decode::run(args, cli.protocol.into(), cli.color),
        Command::Completions(ref args) => completions::run(args),
    }
}
