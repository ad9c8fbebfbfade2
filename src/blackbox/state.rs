//! The latest decoded message of each identifier, kept in a table filled once per identifier (so a frame
//! allocates nothing), and written as JSON for incident.json with decode's own field writer, so the names
//! and values are those of `decode --format json`. Pure.

use crate::candump::{Timestamp, TimestampKind};
use crate::protocol::{Decoded, FrameId, Value};

/// More than the catalog's identifiers (the only ones that decode): the table never fills in practice.
pub const MAX_SLOTS: usize = 64;

/// One identifier's latest message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Slot {
    pub id: FrameId,
    pub at: Timestamp,
    pub decoded: Decoded,
}

/// The latest message of each identifier (and wire: 0x151 decodes as V1 or as V2), in order of first sight.
#[derive(Clone, Debug)]
pub struct Latest {
    slots: Vec<Slot>,
}

impl Default for Latest {
    fn default() -> Self {
        Self { slots: Vec::with_capacity(MAX_SLOTS) }
    }
}

impl Latest {
    /// Keeps `decoded` as the latest of `id`; its slot's index, or `None` once [`MAX_SLOTS`] identifiers are
    /// kept (then it is not kept).
    #[inline]
    pub fn store(&mut self, id: FrameId, at: Timestamp, decoded: Decoded) -> Option<usize> {
        let slot = Slot { id, at, decoded };
        if let Some(index) =
            self.slots.iter().position(|kept| kept.id == id && kept.decoded.wire == decoded.wire)
        {
            self.slots[index] = slot;
            return Some(index);
        }
        if self.slots.len() == MAX_SLOTS {
            return None;
        }
        self.slots.push(slot);
        Some(self.slots.len() - 1)
    }

    pub fn get(&self, index: usize) -> Option<&Slot> {
        self.slots.get(index)
    }

    /// `{"0x211": {"msg": "system_state", "wire": "can-v2", "ts": ..., "ts_ns": ..., "fields": {...}}, ...}`;
    /// a V1 0x151 beside a V2 one is keyed `0x151 can-v1`.
    pub fn to_json(&self) -> serde_json::Value {
        let mut messages = serde_json::Map::new();
        for slot in &self.slots {
            let shared = self.slots.iter().filter(|other| other.id == slot.id).count() > 1;
            let key = if shared {
                format!("{} {}", slot.id, slot.decoded.wire.as_str())
            } else {
                slot.id.to_string()
            };
            let mut message = serde_json::Map::new();
            message.insert("msg".into(), slot.decoded.message.name().into());
            message.insert("wire".into(), slot.decoded.wire.as_str().into());
            insert_stamp(&mut message, "ts", slot.at);
            message.insert("fields".into(), fields_json(&slot.decoded));
            messages.insert(key, message.into());
        }
        messages.into()
    }
}

/// The fields object exactly as decode's JSON writes it.
fn fields_json(decoded: &Decoded) -> serde_json::Value {
    let mut text = vec![b'{'];
    crate::output::json::push_message_fields(&mut text, decoded);
    text.push(b'}');
    serde_json::from_slice(&text).unwrap_or(serde_json::Value::Null)
}

/// A value as decode's JSON writes it (`22.4`, `"rc"`, `["rc_disconnected"]`), without a string's quotes.
pub fn value_text(value: &Value) -> String {
    let mut text = Vec::new();
    crate::output::json::push_value(&mut text, value);
    let text = String::from_utf8_lossy(&text).into_owned();
    match text.strip_prefix('"').and_then(|inner| inner.strip_suffix('"')) {
        Some(inner) => inner.to_string(),
        None => text,
    }
}

/// `"ts"` as seconds and `"ts_ns"` as an integer (a float keeps only about 7 decimals of a Unix stamp), and
/// `"ts_kind"` when the stamp counts from the start of a capture rather than the epoch.
pub fn insert_stamp(object: &mut serde_json::Map<String, serde_json::Value>, key: &str, at: Timestamp) {
    object.insert(key.into(), at.as_secs_f64().into());
    let nanos = u64::try_from(at.as_nanos()).unwrap_or(u64::MAX);
    object.insert(format!("{key}_ns"), nanos.into());
    if at.kind == TimestampKind::Relative {
        object.insert(format!("{key}_kind"), "relative".into());
    }
}

/// A stamp in nanoseconds, the watcher's clock (saturating in the year 2554).
#[inline]
pub fn nanos_of(at: Timestamp) -> u64 {
    at.secs.saturating_mul(1_000_000_000).saturating_add(u64::from(at.nanos))
}

/// The stamp of a time in nanoseconds, of the given kind.
pub fn stamp_at(nanos: u64, kind: TimestampKind) -> Timestamp {
    Timestamp { secs: nanos / 1_000_000_000, nanos: (nanos % 1_000_000_000) as u32, kind }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::{Message, Odometry, SystemState};
    use crate::protocol::Wire;

    fn at(secs: u64) -> Timestamp {
        Timestamp { secs, nanos: 5, kind: TimestampKind::Absolute }
    }

    fn system(wire: Wire, battery_decivolts: u16) -> Decoded {
        let state = SystemState { control_mode: 1, battery_decivolts, ..SystemState::default() };
        Decoded { wire, message: Message::SystemState(state) }
    }

    #[test]
    fn the_latest_of_each_identifier_is_kept_with_decodes_field_names() {
        let mut latest = Latest::default();
        let id = FrameId::Standard(0x211);
        assert_eq!(latest.store(id, at(1_700_000_000), system(Wire::CanV2, 259)), Some(0));
        let odometry = Decoded { wire: Wire::CanV2, message: Message::Odometry(Odometry::default()) };
        assert_eq!(latest.store(FrameId::Standard(0x311), at(1_700_000_000), odometry), Some(1));
        assert_eq!(latest.store(id, at(1_700_000_001), system(Wire::CanV2, 224)), Some(0));
        let json = latest.to_json();
        assert_eq!(json["0x211"]["msg"], "system_state");
        assert_eq!(json["0x211"]["wire"], "can-v2");
        assert_eq!(json["0x211"]["fields"]["battery_voltage"], 22.4);
        assert_eq!(json["0x211"]["fields"]["control_mode"], "can");
        assert_eq!(json["0x211"]["ts_ns"], 1_700_000_001_000_000_005u64);
        assert_eq!(json["0x311"]["fields"]["left_wheel_odometer"], 0.0);
    }

    #[test]
    fn the_table_is_bounded_and_0x151_of_both_wires_is_told_apart() {
        let mut latest = Latest::default();
        for id in 0..MAX_SLOTS as u16 {
            assert_eq!(latest.store(FrameId::Standard(id), at(1), system(Wire::CanV2, 1)), Some(id.into()));
        }
        assert_eq!(latest.store(FrameId::Standard(0x7FF), at(1), system(Wire::CanV2, 1)), None);
        let mut latest = Latest::default();
        latest.store(FrameId::Standard(0x151), at(1), system(Wire::CanV1, 250));
        latest.store(FrameId::Standard(0x151), at(2), system(Wire::CanV2, 251));
        let json = latest.to_json();
        assert_eq!(json["0x151 can-v1"]["fields"]["battery_voltage"], 25.0);
        assert_eq!(json["0x151 can-v2"]["fields"]["battery_voltage"], 25.1);
    }

    #[test]
    fn stamps_round_trip_through_nanoseconds() {
        let stamp = Timestamp { secs: 1_700_000_000, nanos: 123_456_789, kind: TimestampKind::Relative };
        assert_eq!(stamp_at(nanos_of(stamp), TimestampKind::Relative), stamp);
        assert_eq!(nanos_of(Timestamp { secs: u64::MAX, ..stamp }), u64::MAX);
        assert_eq!(value_text(&Value::Name { raw: 3, name: Some("rc") }), "rc");
        assert_eq!(value_text(&Value::Decimal { raw: 162, scale: 1 }), "16.2");
    }
}
