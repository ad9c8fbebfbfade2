use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = tracerctl::cli::Cli::parse();
    match tracerctl::commands::run(cli) {
        Ok(code) => ExitCode::from(code),
        Err(error) => ExitCode::from(tracerctl::exit::report(&error)),
    }
}
