//! One integration-test binary (as ripgrep does): every test runs the real `tracerctl`.
// Test diagnostics may print; the closed-stream rule (clippy.toml) is for the tool itself.
#![allow(clippy::disallowed_macros)]

mod compressed_input;
mod dashboard;
mod dashboard_keys;
mod dashboard_screens;
mod decode;
mod decode_losses;
mod decode_outputs;
mod docs;
mod doctor;
mod drive;
mod drive_output;
#[cfg(target_os = "linux")]
mod fault_peer;
#[cfg(target_os = "linux")]
mod faults;
mod formats;
mod fuzz;
mod generated;
mod help_layout;
mod layers;
mod long_functions;
mod mcap;
mod monitor;
mod monitor_modes;
mod parallel_decode;
mod parallel_inputs;
mod parallel_summary;
mod plot;
mod recording;
mod robot_commands;
mod send_raw;
mod serial_peer;
mod sim_command;
mod sim_training;
mod usage;
mod util;
mod variants;
