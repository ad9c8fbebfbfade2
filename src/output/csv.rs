//! CSV with a fixed header: the event columns, then one column per field name of any message.

use super::number::*;
use super::short_text::push_short;
use super::text::{push_name, push_version};
use super::{direction_name, Event, Shape};
use crate::protocol::fields::{ALL_FIELD_NAMES, MAX_FIELDS};
use crate::protocol::{for_each_field, Value};

/// The columns before the field columns.
pub const EVENT_COLUMNS: &[&str] = &["ts", "iface", "dir", "id", "wire", "msg", "data", "error"];

pub fn header(out: &mut Vec<u8>) {
    for (index, name) in EVENT_COLUMNS.iter().chain(ALL_FIELD_NAMES).enumerate() {
        if index > 0 {
            out.push(b',');
        }
        push_short(out, name.as_bytes());
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
        push_short(out, direction_name(dir).as_bytes());
    }
    out.push(b',');
    event.push_id(out);
    out.push(b',');
    if let Some(wire) = event.wire_name() {
        push_short(out, wire.as_bytes());
    }
    out.push(b',');
    push_short(out, event.msg_name().as_bytes());
    out.push(b',');
    event.push_data(out);
    out.push(b',');
    // Only the message's own cells are kept (a few, not one per column); the empty columns
    // between them are runs of commas.
    let mut cells = [(0, Value::Int(0)); MAX_FIELDS];
    let mut count = 0;
    match event.shape() {
        Shape::Message(decoded) => for_each_field(&decoded, |field| {
            // Cannot be full: no message has more than MAX_FIELDS fields (tested in protocol::fields).
            if let Some(cell) = cells.get_mut(count) {
                *cell = (field.name.column(), field.value);
                count += 1;
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
    let cells = &mut cells[..count];
    // Fields come in schema order, which is column order for all but the V1 motion command.
    cells.sort_unstable_by_key(|&(column, _)| column);
    let mut next_column = 0;
    for (column, value) in cells.iter() {
        // Each column is preceded by its comma.
        push_commas(out, (column + 1).saturating_sub(next_column));
        push_value(out, value);
        next_column = column + 1;
    }
    push_commas(out, ALL_FIELD_NAMES.len().saturating_sub(next_column));
    out.push(b'\n');
}

fn push_commas(out: &mut Vec<u8>, count: usize) {
    const COMMAS: [u8; ALL_FIELD_NAMES.len()] = [b','; ALL_FIELD_NAMES.len()];
    push_short(out, &COMMAS[..count]);
}

fn push_value(out: &mut Vec<u8>, value: &Value) {
    match *value {
        Value::Int(value) => push_int(out, value),
        Value::Decimal { raw, scale } => push_decimal(out, raw, scale),
        Value::Code { value, .. } => push_int(out, value),
        Value::Bool(value) => push_short(out, if value { b"true" } else { b"false" }),
        Value::Name { raw, name } => push_name(out, raw, name),
        // Flag names never contain commas; ';' keeps them in one cell.
        Value::Flags(flags) => {
            for (index, info) in flags.iter().enumerate() {
                if index > 0 {
                    out.push(b';');
                }
                push_short(out, info.name.as_bytes());
            }
        }
        Value::Version(version) => push_version(out, version),
    }
}

/// A text cell, quoted when it contains a separator, quote or line break (RFC 4180).
fn push_cell(out: &mut Vec<u8>, text: &str) {
    if !text.bytes().any(|b| matches!(b, b',' | b'"' | b'\n' | b'\r')) {
        push_short(out, text.as_bytes());
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::fields::one_of_each_message;
    use crate::protocol::message::{Message, PercentMotionCommand};

    /// Each field's cell, placed by looking its name up among the columns: the plain way.
    fn expected_row(decoded: &crate::protocol::Decoded) -> Vec<String> {
        let mut cells = vec![String::new(); ALL_FIELD_NAMES.len()];
        for_each_field(decoded, |field| {
            let column = ALL_FIELD_NAMES.iter().position(|name| *name == field.name.as_str()).unwrap();
            let mut cell = Vec::new();
            push_value(&mut cell, &field.value);
            cells[column] = String::from_utf8(cell).unwrap();
        });
        cells
    }

    #[test]
    fn every_field_lands_in_the_column_of_its_name() {
        let mut samples = one_of_each_message();
        // The V1 motion command lists control_mode (column 1) after the velocities (5, 6).
        let command = PercentMotionCommand {
            control_mode: 1,
            fault_clear: 2,
            linear_percent: 30,
            angular_percent: -5,
            ..Default::default()
        };
        samples.push(crate::protocol::Decoded {
            wire: crate::protocol::Wire::CanV1,
            message: Message::PercentMotionCommand(command),
        });
        for decoded in samples {
            let row = crate::output::written(write, decoded);
            let cells: Vec<&str> = row.trim_end_matches('\n').split(',').collect();
            assert_eq!(cells.len(), EVENT_COLUMNS.len() + ALL_FIELD_NAMES.len(), "{row}");
            assert_eq!(cells[EVENT_COLUMNS.len()..], expected_row(&decoded), "{row}");
            assert!(row.ends_with('\n'));
        }
    }

    /// A reader that types columns from the first rows (DuckDB, Spark) must see a float in a stationary log.
    #[test]
    fn a_zero_current_or_speed_is_written_as_a_float() {
        use crate::protocol::message::{MotionState, MotorHighSpeed};
        let cells_of = |message| {
            let decoded = crate::protocol::Decoded { wire: crate::protocol::Wire::CanV2, message };
            let row = crate::output::written(write, decoded);
            let cells: Vec<String> = row.trim_end().split(',').map(str::to_string).collect();
            let cell = |name: &str| {
                cells[EVENT_COLUMNS.len() + ALL_FIELD_NAMES.iter().position(|n| *n == name).unwrap()].clone()
            };
            (cell("linear_velocity"), cell("angular_velocity"), cell("current"), cell("rpm"))
        };
        let motor = MotorHighSpeed { motor: 1, rpm: 0, current_deciamps: 0, pulse_count: 0 };
        assert_eq!(
            cells_of(Message::MotorHighSpeed(motor)),
            ("".into(), "".into(), "0.0".into(), "0".into())
        );
        let standing = MotionState { linear_mm_s: 0, angular_mrad_s: -1000, count: 0 };
        assert_eq!(
            cells_of(Message::MotionState(standing)),
            ("0.0".into(), "-1.0".into(), "".into(), "".into())
        );
    }
}
