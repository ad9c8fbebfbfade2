//! `tracerctl record`: the black box. Records the bus unattended into a ring of compressed segments,
//! watches the decoded traffic for triggers and keeps the window around each as an incident; never sends.
//! Also `--status`, `--list` and `--mark` for a recorder directory. The pieces are in `crate::blackbox`;
//! here are the loop (`recording.rs`), the writer thread (`writer.rs`), the incident files (`incident.rs`)
//! and the reports (`inspect.rs`).

mod incident;
mod inspect;
mod recording;
mod writer;

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Result;

use super::Global;
use crate::blackbox::triggers::TriggerSettings;
use crate::commands::decode::ReportFormat;

/// `tracerctl record`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// The recorder directory.
    pub dir: PathBuf,
    pub action: Action,
}

/// What `record` is asked to do.
#[derive(Clone, Debug)]
pub enum Action {
    /// Record until a signal (or the end of a replay).
    Record(Settings),
    /// Print the settings and the link `Record` would use, then stop.
    DryRun(Settings),
    Status(ReportFormat),
    List(ReportFormat),
    /// Leave a mark for the running recorder.
    Mark(String),
}

/// How the recorder records.
#[derive(Clone, Debug)]
pub struct Settings {
    /// A new segment this often (frame time).
    pub segment: Duration,
    /// The ring's bounds.
    pub max_total: u64,
    pub max_age: Duration,
    /// An incident's window around its trigger.
    pub before: Duration,
    pub after: Duration,
    /// Incidents kept, oldest removed first.
    pub max_incidents: u32,
    pub triggers: TriggerSettings,
    /// `--instance`: the systemd instance the link came from (said at the start).
    pub instance: Option<String>,
}

impl Settings {
    /// The built-in defaults (issue 31): 1 min segments, 1 GiB and 7 days of ring, 60 s before and 30 s
    /// after a trigger, 100 incidents.
    pub fn defaults() -> Self {
        Self {
            segment: Duration::from_secs(60),
            max_total: 1 << 30,
            max_age: Duration::from_secs(7 * 24 * 3600),
            before: Duration::from_secs(60),
            after: Duration::from_secs(30),
            max_incidents: 100,
            triggers: TriggerSettings::default(),
            instance: None,
        }
    }
}

pub fn run(global: &Global, options: &Options) -> Result<u8> {
    match &options.action {
        Action::Record(settings) => recording::run(global, &options.dir, settings),
        Action::DryRun(settings) => inspect::dry_run(global, &options.dir, settings),
        Action::Status(format) => inspect::status(&options.dir, *format),
        Action::List(format) => inspect::list(&options.dir, *format),
        Action::Mark(note) => inspect::mark(&options.dir, note),
    }
}
