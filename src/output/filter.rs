//! The `--id` / `--msg` frame filter shared by `decode` and `monitor`.

use super::{Event, FrameRef};
use crate::protocol::FrameId;

/// What `--msg` calls frames that are not TRACER messages (`raw`, `invalid`, `error_frame`,
/// `remote_request`), as JSON `msg` names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::IntoStaticStr, strum::VariantNames)]
#[strum(serialize_all = "snake_case")]
pub enum FrameShape {
    /// A frame that is no TRACER message.
    Raw,
    /// A TRACER identifier that cannot be a valid message (bad checksum, too short).
    Invalid,
    /// A SocketCAN error frame.
    ErrorFrame,
    /// A CAN remote request.
    RemoteRequest,
}

impl FrameShape {
    /// Every shape's name, in a fixed order (for `--msg` and its help).
    pub const NAMES: &'static [&'static str] = <Self as strum::VariantNames>::VARIANTS;

    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// Frames pass when they match every filter given (an empty list matches everything).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Filter {
    /// Identifiers (CAN, or RS232 `0xAA01`), compared with their kind: `--id 211` is not extended 0x211.
    pub ids: Vec<FrameId>,
    /// Message names (`system_state`) or frame shapes ([`FrameShape`]).
    pub messages: Vec<&'static str>,
}

impl Filter {
    pub fn new(ids: &[FrameId], messages: &[&'static str]) -> Self {
        Self { ids: ids.to_vec(), messages: messages.to_vec() }
    }

    /// True when nothing is filtered out.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty() && self.messages.is_empty()
    }

    #[inline]
    pub fn passes(&self, event: &Event) -> bool {
        // Without a filter (nearly every decode) no identifier is built: this runs for every frame.
        if self.ids.is_empty() && self.messages.is_empty() {
            return true;
        }
        let id = match event.frame {
            FrameRef::Can(frame) => frame.frame_id(),
            FrameRef::Serial(frame) => frame.frame_id(),
        };
        (self.ids.is_empty() || self.ids.contains(&id))
            && (self.messages.is_empty() || self.messages.contains(&event.msg_name()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::id::TYPE_FEEDBACK;
    use crate::protocol::serial::SerialFrame;
    use crate::protocol::{self, CanFrame, ProtocolHint};

    fn can_event(frame: &CanFrame) -> Event<'_> {
        Event {
            ts: None,
            iface: "-",
            dir: None,
            frame: FrameRef::Can(frame),
            decoded: protocol::decode(frame, ProtocolHint::Auto),
        }
    }

    #[test]
    fn ids_and_names_must_all_match() {
        let state = CanFrame::new(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]).unwrap();
        let other = CanFrame::new(0x123, &[1]).unwrap();
        assert!(Filter::default().passes(&can_event(&state)));
        let by_id = Filter::new(&[FrameId::Standard(0x211)], &[]);
        assert!(by_id.passes(&can_event(&state)) && !by_id.passes(&can_event(&other)));
        let by_name = Filter::new(&[], &["raw"]);
        assert!(!by_name.passes(&can_event(&state)) && by_name.passes(&can_event(&other)));
        assert!(
            !Filter::new(&[FrameId::Standard(0x211)], &["raw"]).passes(&can_event(&state)),
            "both must match"
        );

        let serial = SerialFrame { frame_type: TYPE_FEEDBACK, command: 1, payload: [0; 6], frame_id: 0 };
        let event = Event {
            ts: None,
            iface: "serial",
            dir: None,
            frame: FrameRef::Serial(&serial),
            decoded: Ok(protocol::serial::decode(&serial)),
        };
        assert!(Filter::new(&[FrameId::Serial(0xAA01)], &["system_state"]).passes(&event));
        assert!(!Filter::new(&[FrameId::Standard(0x211)], &[]).passes(&event));
    }

    #[test]
    fn an_identifier_matches_only_its_own_kind() {
        let extended = CanFrame::new_extended(0x211, &[0; 8]).unwrap();
        assert!(!Filter::new(&[FrameId::Standard(0x211)], &[]).passes(&can_event(&extended)));
        assert!(Filter::new(&[FrameId::Extended(0x211)], &[]).passes(&can_event(&extended)));
    }

    #[test]
    fn shape_names_are_the_json_names() {
        assert_eq!(FrameShape::NAMES, ["raw", "invalid", "error_frame", "remote_request"]);
        assert_eq!(FrameShape::RemoteRequest.name(), "remote_request");
    }
}
