//! One readable line per frame: `TS IFACE ID MSG field=value...`, units attached, faults by name and severity.

use super::number::*;
use super::{direction_name, Event, Shape};
use crate::protocol::{for_each_field, Field, Flags, Severity, Value};

const BOLD_CYAN: &[u8] = b"\x1b[1;36m";
const RED: &[u8] = b"\x1b[31m";
const YELLOW: &[u8] = b"\x1b[33m";
const RESET: &[u8] = b"\x1b[0m";

pub fn write(out: &mut Vec<u8>, event: &Event, color: bool) {
    match &event.ts {
        Some(ts) => push_timestamp(out, ts),
        None => out.push(b'-'),
    }
    out.push(b' ');
    out.extend_from_slice(event.iface.as_bytes());
    out.push(b' ');
    event.push_id(out);
    out.push(b' ');
    let shape = event.shape();
    let paint = |out: &mut Vec<u8>, code: &[u8], text: &[u8]| {
        if color {
            out.extend_from_slice(code);
            out.extend_from_slice(text);
            out.extend_from_slice(RESET);
        } else {
            out.extend_from_slice(text);
        }
    };
    let msg = event.msg_name().as_bytes();
    match shape {
        Shape::Invalid(_) => paint(out, RED, msg),
        _ => paint(out, BOLD_CYAN, msg),
    }
    match shape {
        Shape::Message(decoded) => for_each_field(&decoded, |field| push_field(out, &field, color)),
        Shape::Invalid(error) => {
            out.extend_from_slice(b" error=\"");
            super::push_display(out, &error, |out, byte| out.push(byte));
            out.extend_from_slice(b"\" data=");
            event.push_data(out);
        }
        Shape::ErrorFrame(error) => {
            out.extend_from_slice(b" classes=");
            push_names(out, error.class_names());
            if error.controller != 0 {
                out.extend_from_slice(b" controller=");
                push_names(out, error.controller_names());
            }
            if let Some((tx, rx)) = error.counters {
                out.extend_from_slice(b" tx_errors=");
                push_int(out, tx);
                out.extend_from_slice(b" rx_errors=");
                push_int(out, rx);
            }
            out.extend_from_slice(b" data=");
            event.push_data(out);
        }
        Shape::Remote | Shape::Raw => {
            if let super::FrameRef::Can(frame) = event.frame {
                if frame.kind() == crate::protocol::FrameKind::Fd {
                    out.extend_from_slice(b" fd_flags=");
                    push_int(out, frame.fd_flags());
                }
                out.extend_from_slice(b" len=");
                push_int(out, frame.len());
            }
            if shape == Shape::Raw {
                out.extend_from_slice(b" data=");
                event.push_data(out);
            }
        }
    }
    if let Some(dir) = event.dir {
        out.extend_from_slice(b" dir=");
        out.extend_from_slice(direction_name(dir).as_bytes());
    }
    out.push(b'\n');
}

fn push_names<'a>(out: &mut Vec<u8>, names: impl Iterator<Item = &'a str>) {
    let mut first = true;
    for name in names {
        if !first {
            out.push(b',');
        }
        first = false;
        out.extend_from_slice(name.as_bytes());
    }
    if first {
        out.extend_from_slice(b"none");
    }
}

fn push_field(out: &mut Vec<u8>, field: &Field, color: bool) {
    out.push(b' ');
    out.extend_from_slice(field.name.as_bytes());
    out.push(b'=');
    match field.value {
        Value::Int(value) => push_int(out, value),
        Value::Decimal { raw, scale } => push_decimal(out, raw, scale),
        Value::Code { value, digits } => push_hex_value(out, u32::from(value), digits),
        Value::Bool(value) => out.extend_from_slice(if value { b"true" } else { b"false" }),
        Value::Name { raw, name } => push_name(out, raw, name),
        Value::Flags(flags) => push_flags(out, &flags, color),
        Value::Version(version) => push_version(out, version),
    }
    out.extend_from_slice(field.unit.as_bytes());
}

/// An enumerated value's name, or `unknown_0xNN`.
pub fn push_name(out: &mut Vec<u8>, raw: u8, name: Option<&'static str>) {
    match name {
        Some(name) => out.extend_from_slice(name.as_bytes()),
        None => {
            out.extend_from_slice(b"unknown_");
            push_hex_value(out, u32::from(raw), 2);
        }
    }
}

pub fn push_version(out: &mut Vec<u8>, version: u16) {
    push_int(out, version >> 8);
    out.push(b'.');
    push_int(out, version & 0xFF);
}

/// `none`, or `name[severity],...`: the severity is always spelled out, colour only adds to it.
fn push_flags(out: &mut Vec<u8>, flags: &Flags, color: bool) {
    if flags.is_empty() {
        out.extend_from_slice(b"none");
        return;
    }
    let code = match flags.worst() {
        Some(Severity::Fault | Severity::Protection | Severity::Unknown) => RED,
        Some(Severity::Warning) => YELLOW,
        _ => b"".as_slice(),
    };
    if color {
        out.extend_from_slice(code);
    }
    for (index, info) in flags.iter().enumerate() {
        if index > 0 {
            out.push(b',');
        }
        out.extend_from_slice(info.name.as_bytes());
        out.push(b'[');
        out.extend_from_slice(info.severity.as_str().as_bytes());
        out.push(b']');
    }
    if color {
        out.extend_from_slice(RESET);
    }
}
