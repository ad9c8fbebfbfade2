//! The words of the one-line message ([`Message`]); keys are named from the key table.

use crate::dashboard::keys::{key_name, Action};
use crate::dashboard::message::Message;
use crate::protocol::codec::clear_description;
use crate::protocol::message::COMMAND_TIMEOUT;
use crate::protocol::ClearTarget;

/// What the message line says for `message`.
pub(super) fn message_text(message: &Message) -> String {
    const AGAIN: &str = "zero sent, keys released; press again to drive";
    match message {
        Message::Armed => format!(
            "ARMED: command mode requested; press an arrow key to drive, {} to disarm",
            key_name(Action::Arm)
        ),
        Message::AlreadyArmed => "already armed".to_string(),
        Message::WatchOnlyCannotArm(why) => format!("watch-only ({why}): driving cannot be armed"),
        Message::WatchOnly(why) => format!("watch-only ({why}): nothing is sent to the robot"),
        Message::ArmFailed(error) => format!("cannot arm: {error}"),
        Message::Disarmed => "disarmed: zero sent; WATCHING (nothing is sent)".to_string(),
        Message::DisarmedStopNotSent(why) => format!(
            "disarmed, but the stop frames could not be sent ({why}): the robot's own {} ms command \
             timeout stops it",
            COMMAND_TIMEOUT.as_millis()
        ),
        Message::Stopped => format!("zero sent ({}): press a key again to drive", key_name(Action::Stop)),
        Message::BlockedZeroSent(reason) => {
            format!("zero sent: {reason}; press a key again once it is clear")
        }
        Message::Blocked(reason) => format!("driving blocked: {reason}"),
        Message::Unblocked => "clear again: press a key to drive".to_string(),
        Message::CommandModeAsked => {
            "not in command mode: command mode requested, driving once the robot confirms".to_string()
        }
        Message::CommandModeConfirmed => "command mode confirmed: driving".to_string(),
        Message::CommandModeTimedOut(wait) => format!(
            "the robot did not enter command mode within {} s: zero sent; press again to retry",
            wait.as_secs()
        ),
        Message::CommandModeRequested => "command mode requested".to_string(),
        Message::Suspended(gap) => format!("suspended for {:.2} s: {AGAIN}", gap.as_secs_f64()),
        Message::InputStalled(watchdog) => format!("input stalled over {} ms: {AGAIN}", watchdog.as_millis()),
        Message::ClearSent(wire) => format!(
            "fault clear sent ({}): watch the faults panel",
            clear_description(*wire, ClearTarget::All)
        ),
        Message::ClearFailed(error) => format!("cannot send the fault clear: {error}"),
        Message::Lights(name) => format!("lights: {name}"),
        Message::LightsFailed(error) => format!("cannot set the lights: {error}"),
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;
    use crate::protocol::Wire;

    #[test]
    fn messages_name_keys_from_the_table_and_keep_their_units() {
        assert_eq!(
            message_text(&Message::Armed),
            "ARMED: command mode requested; press an arrow key to drive, a to disarm"
        );
        assert_eq!(message_text(&Message::Stopped), "zero sent (Space): press a key again to drive");
        assert_eq!(
            message_text(&Message::Suspended(Duration::from_millis(1234))),
            "suspended for 1.23 s: zero sent, keys released; press again to drive"
        );
        assert_eq!(
            message_text(&Message::InputStalled(Duration::from_millis(250))),
            "input stalled over 250 ms: zero sent, keys released; press again to drive"
        );
        assert_eq!(
            message_text(&Message::CommandModeTimedOut(Duration::from_secs(2))),
            "the robot did not enter command mode within 2 s: zero sent; press again to retry"
        );
        assert_eq!(
            message_text(&Message::ClearSent(Wire::CanV2)),
            "fault clear sent (0x441 = 0x00): watch the faults panel"
        );
        assert_eq!(message_text(&Message::Lights("on")), "lights: on");
    }
}
