//! `tracerctl record`, the black box: the bus recorded unattended into a bounded ring of compressed candump
//! segments, decoded events watched for triggers, and the window around each trigger kept as an incident.
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
mod onset;
pub mod state;
pub mod triggers;
