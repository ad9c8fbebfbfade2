//! The 50 Hz motion sender: its own clock, caps, ramps, a watchdog, and zero-velocity frames on every way out.
//!
//! The sender thread wakes on an absolute 20 ms grid (late wake-ups skip ticks rather than burst). Each tick it
//! takes the latest target, clamps it to the caps, moves the sent command towards it within the acceleration
//! limits (braking has its own, stronger, deceleration), and sends it.
//!
//! The stop rules (docs/architecture.md, "Stop rules"):
//! - **Hold.** Some events make the sender *hold* zero and ignore targets until its owner calls
//!   [`MotionSender::resume`] on a fresh operator command: a halt (Space, an E-stop or fault the owner saw,
//!   SIGTSTP), a gap in its own clock longer than [`GAP_LIMIT`] (the process was suspended or the machine
//!   stalled: the robot has stopped by itself, or is about to, so the ramp state becomes zero), and a
//!   watchdog trip (the owner stopped refreshing the target: input stalled).
//! - **Stop first.** Before the stop frames, what the link still holds for output is discarded, so the
//!   zeros are not queued behind stale motion; a motion frame is held back while the link's output is not
//!   draining. Stopping, by [`MotionSender::stop`], by dropping the sender (errors, panics that unwind), by
//!   the panic hook (panics on any thread), or by a signal, sends zero-velocity frames at once.
//! - **Truth.** How many stop frames actually left is counted, so callers never say "stopped" when none did.
//!
//! The folder: [`limits`] (pure: the caps, their checks and the ramp step), [`sender`] (the 50 Hz thread
//! and its holds), [`stop`] (the stop sequence, the emergency stop and the panic hook).

pub mod limits;
pub mod sender;
pub mod stop;

// The paths callers have always used (`crate::control::MotionSender`, ...), and the library's API.
pub use limits::{ramp_step, LimitError, LimitName, Limits};
pub use sender::{Hold, MotionSender, SenderStats, Stopper, GAP_LIMIT, PERIOD};
pub use stop::{emergency_stop, install_panic_hook, panicked, send_stop_frames, STOP_FRAMES};
