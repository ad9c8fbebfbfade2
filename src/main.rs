use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = tracerctl::cli::parse();
    match tracerctl::cli::run(cli) {
        Ok(code) => ExitCode::from(code),
        Err(error) => ExitCode::from(tracerctl::exit::report(&error)),
    }
}
