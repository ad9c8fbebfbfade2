//! `tracerctl config show` (every effective setting and its source) and `tracerctl config path` (the files
//! looked for). The command line resolves the settings; this prints what it found.

use std::io::Write;

use super::Global;
use crate::config::{show, FileState, Report};

/// What `tracerctl config` prints.
#[derive(Clone, Debug)]
pub enum Options {
    Show { report: Report, json: bool },
    Path { files: Vec<FileState>, note: Option<String> },
}

pub fn run(_global: &Global, options: &Options) -> anyhow::Result<u8> {
    let text = match options {
        Options::Show { report, json: true } => show::json(report),
        Options::Show { report, json: false } => show::text(report),
        Options::Path { files, note } => show::paths_text(files, note.as_deref()),
    };
    std::io::stdout().lock().write_all(text.as_bytes())?;
    Ok(crate::exit::SUCCESS)
}
