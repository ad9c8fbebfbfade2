//! Send and confirm: the robot commands that are answered in the status (mode, lights, fault clear, doctor's
//! probe) send, wait for the status to show the change, and send again if it does not.

use std::time::{Duration, Instant};

use anyhow::Result;

use super::{RobotStatus, Session};
use crate::link::LinkFrame;

/// What `send_until` saw.
#[derive(Debug)]
pub struct Attempt<T> {
    /// The confirmation, if it came in time.
    pub found: Option<T>,
    /// How many times the frames were sent.
    pub sends: u32,
    /// Just before the first send: status received after this is a reply.
    pub first_sent: Instant,
}

/// Sends the frames `frames` builds, then waits for `confirmed` (given the status and the time of the
/// first send); if it does not come, sends again, up to `resends` more times spread evenly over `timeout`.
pub fn send_until<T>(
    session: &Session,
    timeout: Duration,
    resends: u32,
    mut frames: impl FnMut() -> Vec<LinkFrame>,
    mut confirmed: impl FnMut(&RobotStatus, Instant) -> Option<T>,
) -> Result<Attempt<T>> {
    let first_sent = Instant::now();
    let deadline = first_sent + timeout;
    let slice = timeout / (resends + 1);
    let mut sends = 0;
    for attempt in 0..=resends {
        for frame in frames() {
            session.send(&frame)?;
        }
        sends += 1;
        let until =
            if attempt == resends { deadline } else { (first_sent + slice * (attempt + 1)).min(deadline) };
        let wait = until.saturating_duration_since(Instant::now());
        if let Some(found) = session.wait_for(wait, |status| confirmed(status, first_sent)) {
            return Ok(Attempt { found: Some(found), sends, first_sent });
        }
        if session.status().link_error.is_some() {
            break;
        }
    }
    Ok(Attempt { found: None, sends, first_sent })
}
