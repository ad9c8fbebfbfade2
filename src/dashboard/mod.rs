//! `tracerctl dashboard`: live state of the robot, and arrow-key driving that stops every time.
//!
//! Pure parts: [`teleop`] (keys to a velocity request, with or without key-release events), [`app`] (the
//! state shown, built from the session's status and the sender's stats), [`alert`] (which alert wins),
//! [`render`] (a pure function of the app state, one file per panel), and [`keys`] (every key binding,
//! once: the dispatcher, the footer, the help and `--help` read it). The terminal glue in [`terminal`] owns
//! raw mode, the keyboard flags and the input thread.

pub mod alert;
pub mod app;
pub mod health;
pub mod keys;
pub mod lights;
pub mod message;
pub mod render;
pub mod teleop;
pub mod terminal;

#[cfg(test)]
mod key_mentions_tests;
