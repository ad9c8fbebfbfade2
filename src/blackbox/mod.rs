//! `tracerctl record`, the black box: the bus recorded unattended into a bounded ring of compressed candump
//! segments, decoded events watched for triggers, and the window around each trigger kept as an incident.
//! The parts here are the recorder's pieces; the loop that runs them is `commands/record/`.
//!
//! Layout of a recorder directory (docs/json.md has the files' fields):
//!
//! ```text
//! DIR/ring/YYYYMMDDTHHMMSS.mmmZ.log.zst       segments, oldest first by name; zstd frames of candump -L lines
//! DIR/incidents/YYYYMMDDTHHMMSSZ-CAUSE/       frames.log, frames.mcap, summary.txt, summary.json, incident.json
//! DIR/marks/                                  `record --mark` drops a note here for the running recorder
//! DIR/status.json                             the running recorder's state, rewritten every few seconds
//! DIR/recorder.lock                           held (flock) by the running recorder: one per directory
//! ```

mod cause;
pub mod expr;
pub mod lock;
pub mod marks;
pub mod names;
mod onset;
pub mod ring;
pub mod segment;
pub mod state;
pub mod status;
pub mod triggers;
pub mod window;

/// The ring's folder in a recorder directory.
pub fn ring_dir(dir: &std::path::Path) -> std::path::PathBuf {
    dir.join("ring")
}

/// The incidents' folder in a recorder directory.
pub fn incidents_dir(dir: &std::path::Path) -> std::path::PathBuf {
    dir.join("incidents")
}
