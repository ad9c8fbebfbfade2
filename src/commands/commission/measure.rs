//! The plot's samples beside the live analysis ([`LiveHealth`]), fed by the session's tap with exactly the
//! frames and stamps of the `--record` recording. Runs on the session's analysis thread.

use crate::health::Analyzer;
use crate::link::Received;
use crate::protocol::message::Message;
use crate::protocol::ProtocolHint;
use crate::session::health::LiveHealth;
use crate::session::Direction;

/// At most this many plot samples are kept (a default run has about 6 000).
const MAX_SAMPLES: usize = 500_000;

/// One point of the plot, µs of the recording's clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sample {
    /// A motion command sent (m/s, rad/s).
    Command { at_us: i64, linear: f64, angular: f64 },
    /// The robot's measured motion (0x221).
    Motion { at_us: i64, linear: f64, angular: f64 },
    /// The wheel odometers (m).
    Odometer { at_us: i64, left: f64, right: f64 },
}

/// The analysis and the plot's samples, fed by the session's tap.
pub struct Measurement {
    pub live: LiveHealth,
    pub samples: Vec<Sample>,
}

impl Measurement {
    pub fn new(hint: ProtocolHint) -> Self {
        Self { live: LiveHealth::new(hint), samples: Vec::new() }
    }

    pub fn analyzer(&self) -> &Analyzer {
        &self.live.analyzer
    }

    /// One frame of the recording.
    pub fn observe(&mut self, received: &Received, direction: Direction) {
        let Some((at_us, message)) = self.live.observe(received, direction) else { return };
        let sample = match message {
            Message::MotionCommand(command) => {
                Sample::Command { at_us, linear: command.linear(), angular: command.angular() }
            }
            Message::MotionState(motion) => {
                Sample::Motion { at_us, linear: motion.linear(), angular: motion.angular() }
            }
            Message::Odometry(odometry) => Sample::Odometer {
                at_us,
                left: f64::from(odometry.left_mm) / 1000.0,
                right: f64::from(odometry.right_mm) / 1000.0,
            },
            _ => return,
        };
        if self.samples.len() < MAX_SAMPLES {
            self.samples.push(sample);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::{Timestamp, TimestampKind};
    use crate::link::LinkFrame;
    use crate::protocol::CanFrame;

    fn at(micros: u64, frame: CanFrame) -> Received {
        let ts = Timestamp {
            secs: micros / 1_000_000,
            nanos: (micros % 1_000_000) as u32 * 1000 + 7,
            kind: TimestampKind::Absolute,
        };
        Received { ts, frame: LinkFrame::Can(frame) }
    }

    #[test]
    fn commands_motion_and_odometers_become_samples_at_the_recordings_microsecond() {
        let mut measurement = Measurement::new(ProtocolHint::Auto);
        let command = CanFrame::new(0x111, &[0x01, 0x2C, 0, 0, 0, 0, 0, 0]).unwrap();
        let motion = CanFrame::new(0x221, &[0x00, 0x96, 0xFF, 0xCE, 0, 0, 0, 0]).unwrap();
        let odometer = CanFrame::new(0x311, &[0, 0, 0x03, 0xE8, 0, 0, 0x03, 0xE9]).unwrap();
        measurement.observe(&at(1_700_000_000_000_020, command), Direction::Sent);
        measurement.observe(&at(1_700_000_000_000_040, motion), Direction::Received);
        measurement.observe(&at(1_700_000_000_000_060, odometer), Direction::Received);
        assert_eq!((measurement.live.frames, measurement.live.sent), (3, 1));
        assert_eq!(
            measurement.samples,
            vec![
                Sample::Command { at_us: 1_700_000_000_000_020, linear: 0.3, angular: 0.0 },
                Sample::Motion { at_us: 1_700_000_000_000_040, linear: 0.15, angular: -0.05 },
                Sample::Odometer { at_us: 1_700_000_000_000_060, left: 1.0, right: 1.001 },
            ]
        );
    }
}
