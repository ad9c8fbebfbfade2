//! CSV with a fixed header: the event columns, then one column per field name of any message.

use super::number::*;
use super::text::{push_name, push_version};
use super::{direction_name, Event, Shape};
use crate::protocol::fields::{column_of, ALL_FIELD_NAMES};
use crate::protocol::{for_each_field, Value};

/// The columns before the field columns.
pub const EVENT_COLUMNS: &[&str] = &["ts", "iface", "dir", "id", "wire", "msg", "data", "error"];

pub fn header(out: &mut Vec<u8>) {
    for (index, name) in EVENT_COLUMNS.iter().chain(ALL_FIELD_NAMES).enumerate() {
        if index > 0 {
            out.push(b',');
        }
        out.extend_from_slice(name.as_bytes());
    }
    out.push(b'\n');
}

pub fn write(out: &mut Vec<u8>, event: &Event) {
    if let Some(ts) = &event.ts {
        push_timestamp(out, ts);
    }
    out.push(b',');
    push_cell(out, event.iface);
    out.push(b',');
    if let Some(dir) = event.dir {
        out.extend_from_slice(direction_name(dir).as_bytes());
    }
    out.push(b',');
    event.push_id(out);
    out.push(b',');
    if let Some(wire) = event.wire_name() {
        out.extend_from_slice(wire.as_bytes());
    }
    out.push(b',');
    out.extend_from_slice(event.msg_name().as_bytes());
    out.push(b',');
    event.push_data(out);
    out.push(b',');
    let mut cells: [Option<Value>; ALL_FIELD_NAMES.len()] = [None; ALL_FIELD_NAMES.len()];
    match event.shape() {
        Shape::Message(decoded) => for_each_field(&decoded, |field| {
            if let Some(column) = column_of(field.name) {
                cells[column] = Some(field.value);
            }
        }),
        // Error texts contain commas: always quoted (RFC 4180).
        Shape::Invalid(error) => {
            out.push(b'"');
            super::push_display(out, &error, |out, byte| {
                if byte == b'"' {
                    out.push(b'"');
                }
                out.push(byte);
            });
            out.push(b'"');
        }
        _ => {}
    }
    for cell in &cells {
        out.push(b',');
        if let Some(value) = cell {
            push_value(out, value);
        }
    }
    out.push(b'\n');
}

fn push_value(out: &mut Vec<u8>, value: &Value) {
    match *value {
        Value::Int(value) => push_int(out, value),
        Value::Decimal { raw, scale } => push_decimal(out, raw, scale),
        Value::Code { value, .. } => push_int(out, value),
        Value::Bool(value) => out.extend_from_slice(if value { b"true" } else { b"false" }),
        Value::Name { raw, name } => push_name(out, raw, name),
        // Flag names never contain commas; ';' keeps them in one cell.
        Value::Flags(flags) => {
            for (index, info) in flags.iter().enumerate() {
                if index > 0 {
                    out.push(b';');
                }
                out.extend_from_slice(info.name.as_bytes());
            }
        }
        Value::Version(version) => push_version(out, version),
    }
}

/// A text cell, quoted when it contains a separator, quote or line break (RFC 4180).
fn push_cell(out: &mut Vec<u8>, text: &str) {
    if !text.bytes().any(|b| matches!(b, b',' | b'"' | b'\n' | b'\r')) {
        out.extend_from_slice(text.as_bytes());
        return;
    }
    out.push(b'"');
    for byte in text.bytes() {
        if byte == b'"' {
            out.push(b'"');
        }
        out.push(byte);
    }
    out.push(b'"');
}
