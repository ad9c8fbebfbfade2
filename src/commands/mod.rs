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

/// A usage error (exit status 2) with this message.
pub fn usage(message: impl Into<String>) -> anyhow::Error {
    crate::exit::Failure { code: crate::exit::USAGE, message: message.into() }.into()
}

/// Runs the parsed command line and returns the exit status.
pub fn run(cli: Cli) -> anyhow::Result<u8> {
    match cli.command {
        Command::Decode(ref args) => {
            let link = &cli.link;
            let live = [
                (link.sim, "--sim"),
                (link.replay.is_some(), "--replay"),
                (link.iface.is_some(), "--iface"),
                (link.baud.is_some(), "--baud"),
                (link.speed.is_some(), "--speed"),
            ];
            if let Some((_, option)) = live.iter().find(|(given, _)| *given) {
                return Err(usage(format!(
                    "{option} is for live links; decode reads files (candump logs, or RS232 captures with --serial)"
                )));
            }
            decode::run(args, &cli.link.serial, cli.protocol.into(), cli.color)
        }
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
