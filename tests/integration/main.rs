//! One integration-test binary (as ripgrep does): every test runs the real `tracerctl`.
// Test diagnostics may print; the closed-stream rule (clippy.toml) is for the tool itself.
#![allow(clippy::disallowed_macros)]

mod black_box;
mod commission;
mod compressed_input;
mod config;
mod dashboard;
mod dashboard_driver;
mod dashboard_keys;
mod dashboard_motion;
mod dashboard_screens;
mod decode;
mod decode_losses;
mod decode_outputs;
#[cfg(target_os = "linux")]
mod decode_shrinks;
#[cfg(target_os = "linux")]
mod decode_stops;
mod docs;
mod doctor;
mod doctor_interrupted;
mod drive;
mod drive_output;
mod drive_refusals;
mod file_sizes;
mod formats;
mod fuzz;
mod generated;
mod health_summary;
mod help_layout;
mod layers;
mod mcap;
mod monitor;
mod monitor_modes;
mod parallel_inputs;
#[path = "../parallel_decode/logs.rs"]
mod parallel_logs;
mod parallel_summary;
mod plot;
mod pty_robot;
mod pty_sim;
mod pure_files;
mod recording;
mod report;
mod robot_commands;
mod send_raw;
mod serial_peer;
mod serial_text;
mod service;
mod sim_command;
mod sim_params;
mod sim_training;
// The library's test-only source scanner, shared with its unit tests; this binary uses a part of it.
#[path = "../../src/source_scan.rs"]
#[allow(dead_code, reason = "the scanners in src use the rest")]
mod source_scan;
mod stress;
mod stress_commission;
mod truncated_input;
mod usage;
mod util;
mod variants;
