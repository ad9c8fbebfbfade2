//! One readable line per frame: `TS IFACE ID MSG field=value...`, units attached, faults by name and severity.
//! `monitor` adds [`Columns`]: candump's time modes and the raw bytes after the identifier.

use super::number::*;
use super::palette;
use super::short_text::{field_keys, push_short, ShortText};
use super::stamp::{Clock, TimeMode};
use super::{direction_name, Event, FrameRef, Shape};
use crate::protocol::fields::ALL_FIELD_NAMES;
use crate::protocol::{for_each_field, Field, Flags, Severity, Value};

const MESSAGE: &[u8] = palette::MESSAGE.as_bytes();
const FAULT: &[u8] = palette::FAULT.as_bytes();
const WARNING: &[u8] = palette::WARNING.as_bytes();
const RESET: &[u8] = palette::RESET.as_bytes();

/// Classic CAN's 8 data bytes as `00 11 22 33 44 55 66 77`: shorter payloads are padded to this width.
const CAN_BYTES_WIDTH: usize = 8 * 3 - 1;

/// What `monitor` adds to the text line of `decode` (which prints neither).
#[derive(Clone, Debug)]
pub struct Columns {
    /// The time column in one of candump's `-t` modes.
    pub clock: Clock,
    /// `[len] bytes` after the identifier, in hex with spaces, padded so the message names line up.
    pub data: bool,
    /// The widest identifier so far: narrower ones are padded to it, as candump indents standard
    /// identifiers once an extended one was seen.
    id_width: usize,
}

impl Columns {
    pub fn new(mode: TimeMode, data: bool) -> Self {
        Self { clock: Clock::new(mode), data, id_width: 0 }
    }
}

/// `decode`'s line.
pub fn write(out: &mut Vec<u8>, event: &Event, color: bool) {
    match &event.ts {
        Some(ts) => push_timestamp(out, ts),
        None => out.push(b'-'),
    }
    out.push(b' ');
    push_short(out, event.iface.as_bytes());
    out.push(b' ');
    event.push_id(out);
    out.push(b' ');
    write_rest(out, event, color, true);
}

/// `monitor`'s line: the time as `columns` says, and the data column if asked for.
pub fn write_with(out: &mut Vec<u8>, event: &Event, color: bool, columns: &mut Columns) {
    columns.clock.push(out, event.ts.as_ref());
    out.push(b' ');
    push_short(out, event.iface.as_bytes());
    out.push(b' ');
    if !columns.data {
        event.push_id(out);
        out.push(b' ');
        return write_rest(out, event, color, true);
    }
    let start = out.len();
    event.push_id(out);
    columns.id_width = columns.id_width.max(out.len() - start);
    pad_to(out, start, columns.id_width);
    out.push(b' ');
    push_data_column(out, event);
    push_short(out, b"  ");
    // The bytes are in their column already: no `data=` at the end.
    write_rest(out, event, color, false);
}

/// `[8] 00 00 01 03 00 00 00 B1`; CAN payloads under 8 bytes padded to that width (RS232 frames are all
/// 13 bytes, CAN FD ones longer than 8 stick out).
fn push_data_column(out: &mut Vec<u8>, event: &Event) {
    let serial;
    let bytes: &[u8] = match event.frame {
        FrameRef::Can(frame) => frame.data(),
        FrameRef::Serial(frame) => {
            serial = frame.to_bytes();
            &serial
        }
    };
    out.push(b'[');
    push_int(out, bytes.len());
    push_short(out, b"] ");
    let start = out.len();
    for (index, byte) in bytes.iter().enumerate() {
        if index > 0 {
            out.push(b' ');
        }
        push_hex(out, std::slice::from_ref(byte));
    }
    if let FrameRef::Can(_) = event.frame {
        pad_to(out, start, CAN_BYTES_WIDTH);
    }
}

/// Spaces after what was written since `start`, up to `width`.
fn pad_to(out: &mut Vec<u8>, start: usize, width: usize) {
    let written = out.len() - start;
    out.extend(std::iter::repeat_n(b' ', width.saturating_sub(written)));
}

/// The message name and its fields; `data=` for frames shown undecoded unless the data column has them.
fn write_rest(out: &mut Vec<u8>, event: &Event, color: bool, data_field: bool) {
    let shape = event.shape();
    let paint = |out: &mut Vec<u8>, code: &[u8], text: &[u8]| {
        if color {
            push_short(out, code);
            push_short(out, text);
            push_short(out, RESET);
        } else {
            push_short(out, text);
        }
    };
    let msg = event.msg_name().as_bytes();
    match shape {
        Shape::Invalid(_) => paint(out, FAULT, msg),
        _ => paint(out, MESSAGE, msg),
    }
    match shape {
        Shape::Message(decoded) => for_each_field(&decoded, |field| push_field(out, &field, color)),
        Shape::Invalid(error) => {
            push_short(out, b" error=\"");
            super::push_display(out, &error, |out, byte| out.push(byte));
            out.push(b'"');
            push_data_field(out, event, data_field);
        }
        Shape::ErrorFrame(error) => {
            push_short(out, b" classes=");
            push_names(out, error.class_names());
            if error.controller != 0 {
                push_short(out, b" controller=");
                push_names(out, error.controller_names());
            }
            if let Some((tx, rx)) = error.counters {
                push_short(out, b" tx_errors=");
                push_int(out, tx);
                push_short(out, b" rx_errors=");
                push_int(out, rx);
            }
            push_data_field(out, event, data_field);
        }
        Shape::Remote | Shape::Raw => {
            if let super::FrameRef::Can(frame) = event.frame {
                if frame.kind() == crate::protocol::FrameKind::Fd {
                    push_short(out, b" fd_flags=");
                    push_int(out, frame.fd_flags());
                }
                push_short(out, b" len=");
                push_int(out, frame.len());
            }
            if shape == Shape::Raw {
                push_data_field(out, event, data_field);
            }
        }
    }
    if let Some(dir) = event.dir {
        push_short(out, b" dir=");
        push_short(out, direction_name(dir).as_bytes());
    }
    out.push(b'\n');
}

fn push_data_field(out: &mut Vec<u8>, event: &Event, shown: bool) {
    if shown {
        push_short(out, b" data=");
        event.push_data(out);
    }
}

fn push_names<'a>(out: &mut Vec<u8>, names: impl Iterator<Item = &'a str>) {
    let mut first = true;
    for name in names {
        if !first {
            out.push(b',');
        }
        first = false;
        push_short(out, name.as_bytes());
    }
    if first {
        push_short(out, b"none");
    }
}

fn push_field(out: &mut Vec<u8>, field: &Field, color: bool) {
    static KEYS: [ShortText; ALL_FIELD_NAMES.len()] = field_keys(" ", "=");
    KEYS[field.name.column()].push_to(out);
    match field.value {
        Value::Int(value) => push_int(out, value),
        Value::Decimal { raw, scale } => push_decimal_trimmed(out, raw, scale),
        Value::Code { value, digits } => push_hex_value(out, u32::from(value), digits),
        Value::Bool(value) => push_short(out, if value { b"true" } else { b"false" }),
        Value::Name { raw, name } => push_name(out, raw, name),
        Value::Flags(flags) => push_flags(out, &flags, color),
        Value::Version(version) => push_version(out, version),
    }
    if !field.unit.is_empty() {
        push_short(out, field.unit.as_bytes());
    }
}

/// An enumerated value's name, or `unknown_0xNN`.
pub fn push_name(out: &mut Vec<u8>, raw: u8, name: Option<&'static str>) {
    match name {
        Some(name) => push_short(out, name.as_bytes()),
        None => {
            push_short(out, b"unknown_");
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
        push_short(out, b"none");
        return;
    }
    let code = match flags.worst() {
        Some(Severity::Fault | Severity::Protection | Severity::Unknown) => FAULT,
        Some(Severity::Warning) => WARNING,
        _ => b"".as_slice(),
    };
    if color {
        push_short(out, code);
    }
    for (index, info) in flags.iter().enumerate() {
        if index > 0 {
            out.push(b',');
        }
        push_short(out, info.name.as_bytes());
        out.push(b'[');
        push_short(out, info.severity.as_str().as_bytes());
        out.push(b']');
    }
    if color {
        push_short(out, RESET);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::serial::{self, SerialFrame};
    use crate::protocol::{decode, CanFrame, ProtocolHint};

    fn line(frame: FrameRef, columns: &mut Columns) -> String {
        let decoded = match frame {
            FrameRef::Can(frame) => decode(frame, ProtocolHint::Auto),
            FrameRef::Serial(frame) => Ok(serial::decode(frame)),
        };
        let event = Event { ts: None, iface: "link", dir: None, frame, decoded };
        let mut out = Vec::new();
        write_with(&mut out, &event, false, columns);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn the_data_column_for_rs232_error_remote_and_fd_frames() {
        let mut columns = Columns::new(TimeMode::Absolute, true);
        let motion = SerialFrame { frame_type: 0x55, command: 1, payload: [2, 0, 10, 0, 0, 0], frame_id: 0 };
        assert_eq!(
            line(FrameRef::Serial(&motion), &mut columns),
            "- link 0x5501 [13] 5A A5 0A 55 01 02 00 0A 00 00 00 00 6B  motion_command linear_velocity=0.15m/s \
             angular_velocity=0rad/s control_mode=serial fault_clear=none\n"
        );
        let mut columns = Columns::new(TimeMode::Absolute, true);
        let remote = CanFrame::new_remote(0x123, false, 5).unwrap();
        assert_eq!(
            line(FrameRef::Can(&remote), &mut columns),
            "- link 0x123 [0]                          remote_request len=5\n"
        );
        // An error frame's identifier is 8 digits wide: from then on standard ones are padded to it.
        let error = CanFrame::new_error(0x40, &[0; 8]).unwrap();
        assert_eq!(
            line(FrameRef::Can(&error), &mut columns),
            "- link 0x20000040 [8] 00 00 00 00 00 00 00 00  error_frame classes=bus_off\n"
        );
        let fd = CanFrame::new_fd(0x123, false, 5, &[0xAB; 12]).unwrap();
        assert_eq!(
            line(FrameRef::Can(&fd), &mut columns),
            "- link 0x123      [12] AB AB AB AB AB AB AB AB AB AB AB AB  raw fd_flags=5 len=12\n"
        );
        // Without the column: decode's line, data= included.
        let mut plain = Columns::new(TimeMode::Absolute, false);
        assert_eq!(
            line(FrameRef::Can(&error), &mut plain),
            "- link 0x20000040 error_frame classes=bus_off data=0000000000000000\n"
        );
    }
}
