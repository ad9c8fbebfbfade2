//! One JSON object per line; the schema is documented in docs/json.md and must stay stable.

use super::number::*;
use super::short_text::{field_keys, push_short, ShortText};
use super::text::{push_name, push_version};
use super::{direction_name, Event, Shape};
use crate::protocol::fields::ALL_FIELD_NAMES;
use crate::protocol::{for_each_field, Decoded, Value};

/// `"iface":"can0","id":"0x211","data":"00000103000000B1"`: where a frame came from and its bytes, as the
/// per-frame object and MCAP's `/tracer/raw` messages both write them.
#[inline]
pub fn push_frame_keys(out: &mut Vec<u8>, event: &Event) {
    push_short(out, b"\"iface\":");
    push_string(out, event.iface);
    push_short(out, b",\"id\":\"");
    event.push_id(out);
    push_short(out, b"\",\"data\":\"");
    event.push_data(out);
    out.push(b'"');
}

pub fn write(out: &mut Vec<u8>, event: &Event) {
    push_header(out, event);
    push_short(out, b",\"fields\":{");
    push_fields(out, event);
    push_short(out, b"}\n");
}

/// `{"ts":...,"ts_ns":...,"iface":...,"id":...,"data":...,"msg":...,"wire":...,"dir":...`: what every line
/// has. `ts_ns` is the same stamp as an integer: a 64-bit float (jq, JavaScript) keeps only about 7 of
/// `ts`'s decimals.
#[inline]
fn push_header(out: &mut Vec<u8>, event: &Event) {
    push_short(out, b"{\"ts\":");
    match &event.ts {
        Some(ts) => push_timestamp_and_nanos(out, ts, b",\"ts_ns\":"),
        None => push_short(out, b"null,\"ts_ns\":null"),
    }
    out.push(b',');
    push_frame_keys(out, event);
    push_short(out, b",\"msg\":\"");
    push_short(out, event.msg_name().as_bytes());
    push_short(out, b"\",\"wire\":");
    push_name_or_null(out, event.wire_name());
    push_short(out, b",\"dir\":");
    push_name_or_null(out, event.dir.map(direction_name));
}

/// A name known not to need escaping, quoted, or `null`.
#[inline]
fn push_name_or_null(out: &mut Vec<u8>, name: Option<&str>) {
    match name {
        Some(name) => {
            out.push(b'"');
            push_short(out, name.as_bytes());
            out.push(b'"');
        }
        None => push_short(out, b"null"),
    }
}

/// The inside of `"fields":{...}` and its closing brace (an undecodable frame closes it early and adds
/// `"error"`).
#[inline]
fn push_fields(out: &mut Vec<u8>, event: &Event) {
    match event.shape() {
        Shape::Message(decoded) => {
            push_message_fields(out, &decoded);
            out.push(b'}');
        }
        Shape::Invalid(error) => {
            push_short(out, b"},\"error\":\"");
            super::push_display(out, &error, push_escaped);
            out.push(b'"');
        }
        Shape::ErrorFrame(error) => {
            push_short(out, b"\"classes\":");
            push_string_array(out, error.class_names());
            push_short(out, b",\"controller\":");
            push_string_array(out, error.controller_names());
            if let Some((tx, rx)) = error.counters {
                push_short(out, b",\"tx_errors\":");
                push_int(out, tx);
                push_short(out, b",\"rx_errors\":");
                push_int(out, rx);
            }
            out.push(b'}');
        }
        Shape::Remote => {
            if let super::FrameRef::Can(frame) = event.frame {
                push_short(out, b"\"len\":");
                push_int(out, frame.len());
            }
            out.push(b'}');
        }
        Shape::Raw => {
            if let super::FrameRef::Can(frame) = event.frame {
                if frame.kind() == crate::protocol::FrameKind::Fd {
                    push_short(out, b"\"fd\":true,\"fd_flags\":");
                    push_int(out, frame.fd_flags());
                }
            }
            out.push(b'}');
        }
    }
}

/// `"name":value,...` for every field of a message, without braces (also the MCAP message channels' body).
#[inline]
pub fn push_message_fields(out: &mut Vec<u8>, decoded: &Decoded) {
    static FIRST_KEYS: [ShortText; ALL_FIELD_NAMES.len()] = field_keys("\"", "\":");
    static NEXT_KEYS: [ShortText; ALL_FIELD_NAMES.len()] = field_keys(",\"", "\":");
    let mut keys = &FIRST_KEYS;
    for_each_field(decoded, |field| {
        keys[field.name.column()].push_to(out);
        keys = &NEXT_KEYS;
        push_value(out, &field.value);
    });
}

/// A field value as JSON: numbers for quantities and codes, strings for names, arrays for flags.
pub fn push_value(out: &mut Vec<u8>, value: &Value) {
    match *value {
        Value::Int(value) => push_int(out, value),
        Value::Decimal { raw, scale } => push_decimal(out, raw, scale),
        Value::Code { value, .. } => push_int(out, value),
        Value::Bool(value) => push_short(out, if value { b"true" } else { b"false" }),
        Value::Name { raw, name } => {
            out.push(b'"');
            push_name(out, raw, name);
            out.push(b'"');
        }
        Value::Flags(flags) => push_string_array(out, flags.iter().map(|info| info.name)),
        Value::Version(version) => {
            out.push(b'"');
            push_version(out, version);
            out.push(b'"');
        }
    }
}

fn push_string_array<'a>(out: &mut Vec<u8>, names: impl Iterator<Item = &'a str>) {
    out.push(b'[');
    for (index, name) in names.enumerate() {
        if index > 0 {
            out.push(b',');
        }
        push_string(out, name);
    }
    out.push(b']');
}

/// A JSON string with the required escapes.
pub fn push_string(out: &mut Vec<u8>, text: &str) {
    // Interface names almost never need an escape: then one copy instead of a test per byte.
    if !text.bytes().any(|byte| matches!(byte, b'"' | b'\\' | 0..=0x1F)) {
        out.push(b'"');
        push_short(out, text.as_bytes());
        out.push(b'"');
        return;
    }
    out.push(b'"');
    for byte in text.bytes() {
        push_escaped(out, byte);
    }
    out.push(b'"');
}

/// One byte of a JSON string body, escaped where JSON requires it.
fn push_escaped(out: &mut Vec<u8>, byte: u8) {
    match byte {
        b'"' => push_short(out, b"\\\""),
        b'\\' => push_short(out, b"\\\\"),
        0..=0x1F => {
            push_short(out, b"\\u00");
            push_hex(out, &[byte]);
        }
        _ => out.push(byte),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::{Message, MotionState, Odometry};
    use crate::protocol::Wire;

    fn line_of(message: Message) -> String {
        crate::output::written(write, Decoded { wire: Wire::CanV2, message })
    }

    /// A reader that types columns from the first rows (DuckDB, Spark) must see a float in a stationary log.
    #[test]
    fn a_zero_or_whole_speed_is_written_as_a_float() {
        let standing =
            line_of(Message::MotionState(MotionState { linear_mm_s: 0, angular_mrad_s: 2000, count: 0 }));
        assert!(
            standing.contains(r#""fields":{"linear_velocity":0.0,"angular_velocity":2.0}"#),
            "{standing}"
        );
        let odometry = line_of(Message::Odometry(Odometry { left_mm: 0, right_mm: -1000 }));
        assert!(
            odometry.contains(r#""fields":{"left_wheel_odometer":0.0,"right_wheel_odometer":-1.0}"#),
            "{odometry}"
        );
    }
}
