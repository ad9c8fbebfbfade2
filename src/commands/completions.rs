//! `tracerctl completions <shell>`: prints the completion script, which the command line generates from its
//! own definition (the committed copies in completions/ are checked against it by a test).

use std::io::Write;

use super::Global;

/// `tracerctl completions`' settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// The script for the shell that was asked for.
    pub script: Vec<u8>,
}

pub fn run(_global: &Global, args: &Options) -> anyhow::Result<u8> {
    std::io::stdout().lock().write_all(&args.script)?;
    Ok(crate::exit::SUCCESS)
}
