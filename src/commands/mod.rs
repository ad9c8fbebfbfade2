//! One small module per subcommand.

pub mod clear_errors;
pub mod completions;
pub mod dashboard;
pub mod decode;
pub mod doctor;
pub mod drive;
pub mod lights;
pub mod live;
pub mod mode;
pub mod monitor;
pub mod send_raw;
pub mod sim;

use crate::cli::{Cli, Command};

/// Runs the parsed command line and returns the exit status.
pub fn run(cli: Cli) -> anyhow::Result<u8> {
    match cli.command {
        Command::Decode(ref args) => decode::run(args, &cli.link.serial, cli.protocol.into(), cli.color),
        Command::Completions(ref args) => completions::run(args),
        Command::Monitor(ref args) => monitor::run(&cli, args),
        Command::Drive(ref args) => drive::run(&cli, args),
        Command::Doctor(ref args) => doctor::run(&cli, args),
        Command::Mode(ref args) => mode::run(&cli, args),
        Command::ClearErrors(ref args) => clear_errors::run(&cli, args),
        Command::Lights(ref args) => lights::run(&cli, args),
        Command::SendRaw(ref args) => send_raw::run(&cli, args),
        Command::Sim(ref args) => sim::run(&cli, args),
        Command::Dashboard(ref args) => dashboard::run(&cli, args),
    }
}
