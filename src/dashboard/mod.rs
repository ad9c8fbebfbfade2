//! `tracerctl dashboard`: live state of the robot, and arrow-key driving that stops every time.
//!
//! Pure parts: [`teleop`] (keys to a velocity request, with or without key-release events), [`app`] (the
//! state shown, built from the session's status and the sender's stats), [`render`] (a pure function of the
//! app state). The terminal glue in [`terminal`] owns raw mode, the keyboard flags and the input thread.

pub mod app;
pub mod render;
pub mod teleop;
pub mod terminal;
