//! The one-line message under the keys: what the dashboard just did or saw, as a value. The glue says which
//! (`commands::dashboard`); the renderer words it (`render::message`), naming keys from the key table.

use std::time::Duration;

use crate::protocol::Wire;

/// What just happened, for the message line.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Message {
    /// Driving armed: command mode requested; an arrow key drives, the arm key disarms.
    Armed,
    AlreadyArmed,
    /// Arming refused: watch-only, and why (`--watch`, a replay).
    WatchOnlyCannotArm(&'static str),
    /// The key that asks to arm, while watch-only: nothing is sent.
    WatchOnly(&'static str),
    /// The sender did not start, with the error.
    ArmFailed(String),
    /// Disarmed: zero sent, nothing more.
    Disarmed,
    /// Disarmed, but the stop frames could not be sent, and why.
    DisarmedStopNotSent(String),
    /// The stop key: zero at once, held until a key is pressed again.
    Stopped,
    /// While armed, the robot began to block driving: zero sent; the reason.
    BlockedZeroSent(String),
    /// Not armed, the robot began to block driving; the reason.
    Blocked(String),
    /// What blocked driving cleared.
    Unblocked,
    /// A fresh press found the robot out of command mode: it was asked for, the keys drive once confirmed.
    CommandModeAsked,
    /// The robot confirmed command mode: the keys drive.
    CommandModeConfirmed,
    /// The robot did not enter command mode within this long: zero sent, the press forgotten.
    CommandModeTimedOut(Duration),
    /// The command mode key: requested.
    CommandModeRequested,
    /// The process was suspended this long: zero sent, every key released.
    Suspended(Duration),
    /// Input stalled longer than this watchdog: zero sent, every key released.
    InputStalled(Duration),
    /// A fault clear was sent on this wire.
    ClearSent(Wire),
    /// The fault clear could not be sent, with the error.
    ClearFailed(String),
    /// The lights were set to the setting of this name.
    Lights(&'static str),
    /// The lights could not be set, with the error.
    LightsFailed(String),
}
