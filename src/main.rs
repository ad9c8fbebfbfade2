use std::process::ExitCode;

fn main() -> ExitCode {
    tracerctl::output::console::enable_escape_codes();
    let cli = tracerctl::cli::parse();
    match tracerctl::cli::run(cli) {
        Ok(code) => ExitCode::from(code),
        Err(error) => ExitCode::from(tracerctl::exit::report(&error)),
    }
}
