//! The live analysis: every frame the session's tap hands over (exactly the frames and stamps of a
//! `--record` recording, in its order) decoded as `decode` decodes a log and fed to the
//! [`health::Analyzer`](crate::health::Analyzer), so what `commission` and the dashboard show live is what
//! `decode --summary` of the recording reports. Runs on the session's analysis thread.

use super::Direction;
use crate::health::Analyzer;
use crate::link::{LinkFrame, Received};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::message::Message;
use crate::protocol::{serial, ProtocolHint};

/// The analysis of a live session's frames.
#[derive(Clone, Debug)]
pub struct LiveHealth {
    pub analyzer: Analyzer,
    detector: ProtocolDetector,
    hint: ProtocolHint,
    /// Frames seen, and those sent.
    pub frames: u64,
    pub sent: u64,
}

impl LiveHealth {
    pub fn new(hint: ProtocolHint) -> Self {
        Self { analyzer: Analyzer::new(), detector: ProtocolDetector::default(), hint, frames: 0, sent: 0 }
    }

    /// One frame of the recording; its message and stamp (µs) when it is one, for callers that keep more.
    pub fn observe(&mut self, received: &Received, direction: Direction) -> Option<(i64, Message)> {
        self.frames += 1;
        if direction == Direction::Sent {
            self.sent += 1;
        }
        let decoded = match &received.frame {
            LinkFrame::Can(frame) => self.detector.observe_and_decode(frame, self.hint).ok().flatten(),
            LinkFrame::Serial(frame) => serial::decode(frame),
        }?;
        let at_us = received.ts.as_micros_i64();
        self.analyzer.observe(at_us, &decoded.message);
        Some((at_us, decoded.message))
    }
}
