//! The `--id` / `--msg` frame filter shared by `decode` and `monitor`.

use super::{Event, FrameRef};

/// Frames pass when they match every filter given (an empty list matches everything).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Filter {
    /// Identifiers: CAN identifiers, or `type << 8 | command` for RS232 frames (`0xAA01`).
    pub ids: Vec<u32>,
    /// Message names (`system_state`) or frame shapes (`raw`, `invalid`, `error_frame`, `remote_request`).
    pub messages: Vec<&'static str>,
}

impl Filter {
    pub fn new(ids: &[u32], messages: &[&'static str]) -> Self {
        Self { ids: ids.to_vec(), messages: messages.to_vec() }
    }

    /// True when nothing is filtered out.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty() && self.messages.is_empty()
    }

    pub fn passes(&self, event: &Event) -> bool {
        let id = match event.frame {
            FrameRef::Can(frame) => frame.id(),
            FrameRef::Serial(frame) => u32::from(frame.id()),
        };
        (self.ids.is_empty() || self.ids.contains(&id))
            && (self.messages.is_empty() || self.messages.contains(&event.msg_name()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::serial::{SerialFrame, TYPE_FEEDBACK};
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
        let by_id = Filter::new(&[0x211], &[]);
        assert!(by_id.passes(&can_event(&state)) && !by_id.passes(&can_event(&other)));
        let by_name = Filter::new(&[], &["raw"]);
        assert!(!by_name.passes(&can_event(&state)) && by_name.passes(&can_event(&other)));
        assert!(!Filter::new(&[0x211], &["raw"]).passes(&can_event(&state)), "both must match");

        let serial = SerialFrame { frame_type: TYPE_FEEDBACK, command: 1, payload: [0; 6], frame_id: 0 };
        let event = Event {
            ts: None,
            iface: "serial",
            dir: None,
            frame: FrameRef::Serial(&serial),
            decoded: Ok(protocol::serial::decode(&serial)),
        };
        assert!(Filter::new(&[0xAA01], &["system_state"]).passes(&event));
        assert!(!Filter::new(&[0x211], &[]).passes(&event));
    }
}
