//! The channels of an MCAP file and their JSON Schemas (draft 2020-12).
//!
//! The TRACER message schemas are derived from `protocol::fields` (every message variant's fields, with
//! their value kinds and units), so they follow the JSON output and cannot drift from it. The Foxglove
//! schemas follow Foxglove's well-known JSON schemas (foxglove/schemas, `schemas/jsonschema/`).

use serde_json::{json, Map, Value as Json};
use strum::IntoEnumIterator;

use crate::protocol::fields::one_of_each_message;
use crate::protocol::message::*;
use crate::protocol::{for_each_field, Value};

/// Schema (and message) encodings.
pub const SCHEMA_ENCODING: &str = "jsonschema";
pub const MESSAGE_ENCODING: &str = "json";
const DRAFT: &str = "https://json-schema.org/draft/2020-12/schema";

pub const RAW_TOPIC: &str = "/tracer/raw";
pub const EVENTS_TOPIC: &str = "/tracer/events";
pub const POSE_TOPIC: &str = "/tracer/pose";
pub const TF_TOPIC: &str = "/tf";
pub const LOG_SCHEMA: &str = "foxglove.Log";
pub const POSE_SCHEMA: &str = "foxglove.PoseInFrame";
pub const TRANSFORM_SCHEMA: &str = "foxglove.FrameTransform";
pub const RAW_SCHEMA: &str = "tracer.raw";
/// The motor numbers that get a channel from the start (TRACER has two); others get one when seen.
pub const MOTORS: [u8; 2] = [1, 2];

/// The topic of a message kind, for kinds other than the two motor kinds (which have one per motor).
pub fn message_topic(kind: MessageKind) -> Option<String> {
    match kind {
        MessageKind::MotorHighSpeed | MessageKind::MotorLowSpeed => None,
        kind => Some(format!("/tracer/{}", kind.name())),
    }
}

/// `/tracer/motor/N` (high-speed feedback) or `/tracer/motor/N/low_speed`.
pub fn motor_topic(kind: MessageKind, motor: u8) -> String {
    match kind {
        MessageKind::MotorLowSpeed => format!("/tracer/motor/{motor}/low_speed"),
        _ => format!("/tracer/motor/{motor}"),
    }
}

/// `tracer.system_state`: the schema name of a message kind's channels.
pub fn message_schema_name(kind: MessageKind) -> String {
    format!("tracer.{}", kind.name())
}

/// Every topic a file starts with (motors beyond [`MOTORS`] are added when seen), with its schema name.
pub fn fixed_topics() -> Vec<(String, String)> {
    let mut topics = Vec::new();
    for kind in MessageKind::iter() {
        match message_topic(kind) {
            Some(topic) => topics.push((topic, message_schema_name(kind))),
            None => topics
                .extend(MOTORS.iter().map(|&motor| (motor_topic(kind, motor), message_schema_name(kind)))),
        }
    }
    for (topic, schema) in [
        (RAW_TOPIC, RAW_SCHEMA),
        (EVENTS_TOPIC, LOG_SCHEMA),
        (POSE_TOPIC, POSE_SCHEMA),
        (TF_TOPIC, TRANSFORM_SCHEMA),
    ] {
        topics.push((topic.to_string(), schema.to_string()));
    }
    topics
}

fn value_schema(value: &Value, unit: &str) -> Json {
    let unit = if unit.is_empty() { String::new() } else { format!(" Unit: {unit}.") };
    match value {
        Value::Int(_) => json!({"type": "integer", "description": format!("Integer.{unit}")}),
        Value::Decimal { .. } => {
            json!({"type": "number", "description": format!("Decimal, exact as decoded.{unit}")})
        }
        Value::Code { .. } => {
            json!({"type": "integer", "minimum": 0, "description": "Raw bit field or code."})
        }
        Value::Bool(_) => json!({"type": "boolean"}),
        Value::Name { .. } => {
            json!({"type": "string", "description": "A name, or unknown_0xNN for an undefined byte."})
        }
        Value::Flags(_) => json!({
            "type": "array",
            "items": {"type": "string"},
            "description": "Names of the set bits, lowest first (docs/protocol.md section 5)."
        }),
        Value::Version(_) => json!({"type": "string", "description": "major.minor"}),
    }
}

/// The schema of a TRACER message channel: the JSON output's `fields` at top level, plus `iface` and `wire`.
/// `required` lists the keys every frame of the kind has; wire-specific keys (V1/RS232 only) are optional.
pub fn message_schema(kind: MessageKind) -> Json {
    let samples: Vec<Decoded> =
        one_of_each_message().into_iter().filter(|decoded| decoded.message.kind() == kind).collect();
    let mut properties = Map::new();
    let mut per_sample: Vec<Vec<&'static str>> = Vec::new();
    for decoded in &samples {
        let mut names = Vec::new();
        for_each_field(decoded, |field| {
            properties.entry(field.name.as_str()).or_insert_with(|| value_schema(&field.value, field.unit));
            names.push(field.name.as_str());
        });
        per_sample.push(names);
    }
    let mut required: Vec<&str> = properties
        .keys()
        .filter(|name| per_sample.iter().all(|names| names.contains(&name.as_str())))
        .map(String::as_str)
        .collect();
    required.extend(["iface", "wire"]);
    let required: Vec<String> = required.into_iter().map(str::to_string).collect();
    properties.insert(
        "iface".into(),
        json!({"type": "string", "description": "Interface (can0, a file's, serial)."}),
    );
    properties.insert(
        "wire".into(),
        json!({"type": "string", "enum": ["can-v2", "can-v1", "serial"], "description": "Encoding it came in."}),
    );
    json!({
        "$schema": DRAFT,
        "title": message_schema_name(kind),
        "description": format!("TRACER {} (docs/json.md section 2)", kind.name()),
        "type": "object",
        "properties": properties,
        "required": required,
        "additionalProperties": false
    })
}

/// Every frame, as decode's JSON header without the decoded fields. A frame without a stamp, direction or
/// wire leaves that key out (decode's JSON writes `null`): Foxglove's parser takes one `type` per property
/// and no `null`, and drops a channel whose schema has one.
pub fn raw_schema() -> Json {
    json!({
        "$schema": DRAFT,
        "title": RAW_SCHEMA,
        "description": "Every frame as captured (docs/json.md section 1)",
        "type": "object",
        "properties": {
            "ts_ns": {"type": "integer", "minimum": 0, "description": "The stamp as captured, ns; absent without one."},
            "iface": {"type": "string"},
            "id": {"type": "string", "description": "Identifier as printed (docs/json.md section 1: standard, extended, error and RS232 forms)."},
            "data": {"type": "string", "description": "Payload bytes in hex (a whole 13-byte RS232 frame)."},
            "dir": {"type": "string", "enum": ["rx", "tx"], "description": "candump -x direction; absent without it."},
            "msg": {"type": "string", "description": "Message name, or raw, invalid, error_frame, remote_request."},
            "wire": {"type": "string", "enum": ["can-v2", "can-v1", "serial"], "description": "Encoding of a TRACER message; absent for other frames."}
        },
        "required": ["iface", "id", "data", "msg"],
        "additionalProperties": false
    })
}

fn time_schema(description: &str) -> Json {
    json!({
        "type": "object",
        "title": "time",
        "properties": {
            "sec": {"type": "integer", "minimum": 0},
            "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}
        },
        "description": description
    })
}

fn vector3(title: &str, description: &str) -> Json {
    let axis = |name: &str| json!({"type": "number", "description": format!("{name} coordinate length")});
    json!({
        "title": title,
        "description": description,
        "type": "object",
        "properties": {"x": axis("x"), "y": axis("y"), "z": axis("z")}
    })
}

fn quaternion(description: &str) -> Json {
    let part = |name: &str| json!({"type": "number", "description": format!("{name} value")});
    json!({
        "title": "foxglove.Quaternion",
        "description": description,
        "type": "object",
        "properties": {"x": part("x"), "y": part("y"), "z": part("z"), "w": part("w")}
    })
}

/// foxglove.Log: levels 0 UNKNOWN, 1 DEBUG, 2 INFO, 3 WARNING, 4 ERROR, 5 FATAL.
pub fn log_schema() -> Json {
    let levels: Vec<Json> = ["UNKNOWN", "DEBUG", "INFO", "WARNING", "ERROR", "FATAL"]
        .iter()
        .enumerate()
        .map(|(value, title)| json!({"title": title, "const": value}))
        .collect();
    json!({
        "$schema": DRAFT,
        "title": LOG_SCHEMA,
        "description": "A log message",
        "type": "object",
        "properties": {
            "timestamp": time_schema("Timestamp of log message"),
            "level": {"title": "foxglove.LogLevel", "description": "Log level", "oneOf": levels},
            "message": {"type": "string", "description": "Log message"},
            "name": {"type": "string", "description": "Process or node name"},
            "file": {"type": "string", "description": "Filename"},
            "line": {"type": "integer", "minimum": 0, "description": "Line number in the file"}
        }
    })
}

pub fn pose_schema() -> Json {
    json!({
        "$schema": DRAFT,
        "title": POSE_SCHEMA,
        "description": "A timestamped pose for an object or reference frame in 3D space",
        "type": "object",
        "properties": {
            "timestamp": time_schema("Timestamp of pose"),
            "frame_id": {"type": "string", "description": "Frame of reference for pose position and orientation"},
            "pose": {
                "title": "foxglove.Pose",
                "description": "Pose in 3D space",
                "type": "object",
                "properties": {
                    "position": vector3("foxglove.Vector3", "Point denoting position in 3D space"),
                    "orientation": quaternion("Quaternion denoting orientation in 3D space")
                }
            }
        }
    })
}

pub fn transform_schema() -> Json {
    json!({
        "$schema": DRAFT,
        "title": TRANSFORM_SCHEMA,
        "description": "A transform between two reference frames in 3D space",
        "type": "object",
        "properties": {
            "timestamp": time_schema("Timestamp of transform"),
            "parent_frame_id": {"type": "string", "description": "Name of the parent frame"},
            "child_frame_id": {"type": "string", "description": "Name of the child frame"},
            "translation": vector3("foxglove.Vector3", "Translation component of the transform"),
            "rotation": quaternion("Rotation component of the transform")
        }
    })
}

/// The schema of a schema name from [`fixed_topics`].
pub fn schema_named(name: &str) -> Option<Json> {
    match name {
        RAW_SCHEMA => Some(raw_schema()),
        LOG_SCHEMA => Some(log_schema()),
        POSE_SCHEMA => Some(pose_schema()),
        TRANSFORM_SCHEMA => Some(transform_schema()),
        _ => MessageKind::iter().find(|kind| message_schema_name(*kind) == name).map(message_schema),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wire_specific_keys_are_optional() {
        let schema = message_schema(MessageKind::MotionCommand);
        let required = schema["required"].as_array().unwrap();
        let names: Vec<&str> = required.iter().filter_map(Json::as_str).collect();
        assert_eq!(names, ["angular_velocity", "linear_velocity", "iface", "wire"]);
        assert_eq!(schema["properties"]["control_mode"]["type"], "string");
        let system = message_schema(MessageKind::SystemState);
        assert_eq!(system["properties"]["battery_voltage"]["type"], "number");
        assert!(system["properties"]["battery_voltage"]["description"]
            .as_str()
            .unwrap()
            .contains("Unit: V."));
        assert_eq!(system["properties"]["faults"]["items"]["type"], "string");
    }

    #[test]
    fn every_topic_and_schema_is_in_the_table_of_docs_foxglove_md() {
        let doc = include_str!("../../../docs/foxglove.md");
        for (topic, schema) in fixed_topics() {
            let row = format!("| `{topic}` | `{schema}` |");
            assert!(doc.contains(&row), "docs/foxglove.md lacks the row {row}");
        }
    }

    /// Foxglove's `parseJsonSchema` (mcap-support) as a predicate: an object with properties that each have
    /// one `type` it knows (arrays of such items, nested objects alike), or a `oneOf` of numeric `const`s.
    /// tests/mcap/foxglove_subset.py applies the same rules to the files in CI.
    fn foxglove_rejects(schema: &Json, path: &str) -> Vec<String> {
        if schema["type"] != "object" {
            return vec![format!("{path}: type {} is not \"object\"", schema["type"])];
        }
        let mut problems = Vec::new();
        for (name, property) in schema["properties"].as_object().into_iter().flatten() {
            let path = format!("{path}.{name}");
            if let Some(alternatives) = property["oneOf"].as_array() {
                if !alternatives.iter().all(|alternative| alternative["const"].is_number()) {
                    problems.push(format!("{path}: oneOf without numeric consts"));
                }
                continue;
            }
            let mut kind = &property["type"];
            if kind == "array" {
                kind = &property["items"]["type"];
            }
            match kind.as_str() {
                Some("boolean" | "string" | "number" | "integer") => {}
                Some("object") if property["type"] == "object" => {
                    problems.extend(foxglove_rejects(property, &path))
                }
                Some("object") => problems.extend(foxglove_rejects(&property["items"], &path)),
                _ => problems.push(format!("{path}: unsupported type {kind}")),
            }
        }
        problems
    }

    #[test]
    fn every_schema_fits_foxglove_json_schema_parser() {
        let mut problems = Vec::new();
        for (_, name) in fixed_topics() {
            problems.extend(foxglove_rejects(&schema_named(&name).unwrap(), &name));
        }
        assert_eq!(problems, Vec::<String>::new());
        // The rules catch what Foxglove 1.48 and Lichtblick threw on ("Unsupported type undefined for dir").
        let old_raw = json!({"type": "object", "properties": {
            "ts_ns": {"type": ["integer", "null"]}, "dir": {"enum": ["rx", "tx", null]}, "level": {"type": "null"}}});
        assert_eq!(
            foxglove_rejects(&old_raw, "raw"),
            [
                "raw.dir: unsupported type null",
                "raw.level: unsupported type \"null\"",
                "raw.ts_ns: unsupported type [\"integer\",\"null\"]",
            ]
        );
    }

    #[test]
    fn every_fixed_topic_has_a_schema() {
        let topics = fixed_topics();
        assert!(topics.iter().any(|(topic, _)| topic == "/tracer/motor/2/low_speed"));
        assert!(topics.iter().any(|(topic, _)| topic == "/tracer/system_state"));
        assert!(!topics.iter().any(|(topic, _)| topic == "/tracer/motor_high_speed"));
        for (topic, schema) in topics {
            assert!(schema_named(&schema).is_some(), "{topic}: {schema}");
        }
    }
}
