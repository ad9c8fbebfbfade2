//! Telling protocol V1 from V2 by the identifiers on the bus.
//!
//! Unlike AgileX's detector, seeing both is not an error: the verdict says what was seen and decoding goes on.

use super::can::{self, ProtocolHint};
use super::catalog::StandardIds;
use super::frame::CanFrame;
use super::message::{MessageKind, Wire};

/// What the traffic so far says about the protocol version.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// No TRACER-specific identifier seen yet.
    Unknown,
    V1,
    V2,
    /// Both V1-only and V2-only identifiers seen (two robots, or a replay of mixed logs).
    Mixed,
}

/// Counts V1-only and V2-only frames.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ProtocolDetector {
    pub v1_frames: u64,
    pub v2_frames: u64,
}

/// The catalog's V2 identifiers that V1 does not use, without the version query: it comes from other AgileX
/// bases (the Scout V2 manual), so it says nothing about which TRACER firmware is on the bus.
static V2_ONLY: StandardIds =
    StandardIds::only_on(Wire::CanV2, &[MessageKind::VersionRequest, MessageKind::VersionResponse]);

/// Identifiers only V2 firmware sends (feedback), or a V2 host sends.
pub fn is_v2_only_id(id: u32) -> bool {
    V2_ONLY.contains(id)
}

impl ProtocolDetector {
    pub fn observe(&mut self, frame: &CanFrame) {
        if !frame.is_standard_data() {
            return;
        }
        if can::is_v1_only_id(frame.id()) {
            self.v1_frames += 1;
        } else if is_v2_only_id(frame.id()) {
            self.v2_frames += 1;
        }
    }

    pub fn verdict(&self) -> Verdict {
        match (self.v1_frames > 0, self.v2_frames > 0) {
            (false, false) => Verdict::Unknown,
            (true, false) => Verdict::V1,
            (false, true) => Verdict::V2,
            (true, true) => Verdict::Mixed,
        }
    }

    /// What the traffic showed, in words: never an error, a mixed or unknown bus is said as such.
    /// `V2 (96 V2-only frames, 0 V1-only frames)`.
    pub fn describe(&self) -> String {
        let verdict = match self.verdict() {
            Verdict::Unknown => "not determined (no version-specific IDs)",
            Verdict::V1 => "V1",
            Verdict::V2 => "V2",
            Verdict::Mixed => "mixed V1 and V2 traffic",
        };
        format!("{verdict} ({} V2-only frames, {} V1-only frames)", self.v2_frames, self.v1_frames)
    }

    /// The hint to decode ambiguous frames with (0x151): the bus's version once it is clear.
    /// Observes `frame`, then decodes it as `protocol` says: as given, or for `Auto` as the traffic seen so far
    /// says (what decides an ambiguous 0x151).
    #[inline]
    pub fn observe_and_decode(
        &mut self,
        frame: &CanFrame,
        protocol: ProtocolHint,
    ) -> Result<Option<super::Decoded>, can::DecodeError> {
        self.observe(frame);
        let hint = match protocol {
            ProtocolHint::Auto => self.hint(),
            forced => forced,
        };
        can::decode(frame, hint)
    }

    pub fn hint(&self) -> ProtocolHint {
        match self.verdict() {
            Verdict::V1 => ProtocolHint::V1,
            Verdict::V2 => ProtocolHint::V2,
            Verdict::Unknown | Verdict::Mixed => ProtocolHint::Auto,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(id: u32) -> CanFrame {
        CanFrame::new(id, &[0; 8]).unwrap()
    }

    #[test]
    fn verdict_follows_the_traffic_and_never_fails() {
        let mut detector = ProtocolDetector::default();
        assert_eq!(detector.verdict(), Verdict::Unknown);
        detector.observe(&frame(0x151)); // shared ID: no evidence either way
        assert_eq!(detector.verdict(), Verdict::Unknown);
        detector.observe(&frame(0x221));
        assert_eq!((detector.verdict(), detector.hint()), (Verdict::V2, ProtocolHint::V2));
        detector.observe(&frame(0x131));
        assert_eq!((detector.verdict(), detector.hint()), (Verdict::Mixed, ProtocolHint::Auto));
        assert_eq!((detector.v1_frames, detector.v2_frames), (1, 1));
        assert_eq!(detector.describe(), "mixed V1 and V2 traffic (1 V2-only frames, 1 V1-only frames)");
    }

    /// The sets derived from the catalog are the ones detection used before the catalog existed.
    #[test]
    fn version_specific_identifiers_are_todays() {
        let v2: Vec<u32> = (0..0x800).filter(|&id| is_v2_only_id(id)).collect();
        let v2_before =
            [0x111, 0x121, 0x211, 0x221, 0x231, 0x241, 0x251, 0x252, 0x261, 0x262, 0x311, 0x421, 0x441];
        assert_eq!(v2, v2_before);
        let v1: Vec<u32> = (0..0x800).filter(|&id| can::is_v1_only_id(id)).collect();
        assert_eq!(v1, [0x130, 0x131, 0x140, 0x141, 0x201, 0x202]);
        assert!(!is_v2_only_id(0x151) && !can::is_v1_only_id(0x151), "0x151 is shared");
        assert!(!is_v2_only_id(0x1000) && !can::is_v1_only_id(u32::MAX));
    }
}
