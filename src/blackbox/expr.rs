//! `--trigger EXPR`: one comparison on a decoded field, `FIELD OP VALUE`, read once at start-up and tested
//! against every message that carries the field.
//!
//! FIELD is a field of the JSON schema (`protocol::fields`, docs/json.md), optionally after its message's
//! name (`motor_low_speed.driver_temperature`), or `id`, the frame's identifier. OP is `<`, `<=`, `>`,
//! `>=`, `=` (or `==`) or `!=`. VALUE is a number (`23.0`, `-1.5`, `0x10`) for quantities and codes; a name
//! for named fields (`control_mode=rc`, `swb=middle`); a flag name for flag fields (`faults=rc_disconnected`
//! is true while that bit is set; `faults=none` while none is); `true`/`false` for `enabled`; `1.2` for
//! versions; an identifier for `id` (hex, as `--id` reads it: `0x441`, `0xAA01`). Names and flags compare
//! with `=` and `!=` only; a number compares a named or flag field's raw value. `motor_current` is accepted
//! for `current` (the spelling). Errors say at which byte and why, with the nearest field names.

use std::cmp::Ordering;
use std::str::FromStr;

use strum::IntoEnumIterator;

use crate::protocol::faults::FlagTable;
use crate::protocol::fields::{for_each_field, one_of_each_message, FieldName, Value, ALL_FIELD_NAMES};
use crate::protocol::id::ID_SYSTEM_STATE;
use crate::protocol::message::{
    control_mode_name, fault_clear_name, fault_clear_v1_name, rc_switch_name, vehicle_state_name,
};
use crate::protocol::{FrameId, LightMode, MessageKind, Wire};

/// Other spellings of field names.
const ALIASES: &[(&str, &str)] = &[("motor_current", "current")];

/// The pseudo-field of the frame's identifier.
const ID: &str = "id";

/// A comparison operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
}

impl Op {
    /// Longest first, so `<=` is not read as `<`.
    const SPELLINGS: [(&'static str, Op); 7] = [
        ("<=", Op::Le),
        (">=", Op::Ge),
        ("!=", Op::Ne),
        ("==", Op::Eq),
        ("<", Op::Lt),
        (">", Op::Gt),
        ("=", Op::Eq),
    ];

    pub fn symbol(self) -> &'static str {
        match self {
            Op::Lt => "<",
            Op::Le => "<=",
            Op::Gt => ">",
            Op::Ge => ">=",
            Op::Eq => "=",
            Op::Ne => "!=",
        }
    }

    /// Whether `value OP literal` holds, given how the value compares to the literal.
    #[inline]
    fn holds(self, ordering: Ordering) -> bool {
        match self {
            Op::Lt => ordering == Ordering::Less,
            Op::Le => ordering != Ordering::Greater,
            Op::Gt => ordering == Ordering::Greater,
            Op::Ge => ordering != Ordering::Less,
            Op::Eq => ordering == Ordering::Equal,
            Op::Ne => ordering != Ordering::Equal,
        }
    }

    fn is_equality(self) -> bool {
        matches!(self, Op::Eq | Op::Ne)
    }
}

/// What an expression looks at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The identifier of every frame.
    Id,
    /// A field; `kinds` has bit `kind_bit(k)` set for each message kind that may carry it.
    Field { name: FieldName, kinds: u16 },
}

/// A fixed-point number, `mantissa / 10^scale`, compared exactly (no float rounding at a threshold).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Fixed {
    mantissa: i128,
    scale: u8,
}

/// Enough for any literal we accept (at most 18 decimals, 19 digits) times any field's scale.
const MAX_SCALE: u8 = 18;

impl Fixed {
    fn compare(self, other: Fixed) -> Ordering {
        let scale = self.scale.max(other.scale);
        let widen = |n: Fixed| n.mantissa.saturating_mul(10i128.pow(u32::from(scale - n.scale)));
        widen(self).cmp(&widen(other))
    }

    /// A field value as a number: a name's or flag field's raw value, a version's u16.
    #[inline]
    fn of(value: &Value) -> Fixed {
        let (mantissa, scale) = match *value {
            Value::Int(v) => (i128::from(v), 0),
            Value::Decimal { raw, scale } => (i128::from(raw), scale.min(MAX_SCALE)),
            Value::Code { value, .. } => (i128::from(value), 0),
            Value::Name { raw, .. } => (i128::from(raw), 0),
            Value::Flags(flags) => (i128::from(flags.bits), 0),
            Value::Bool(value) => (i128::from(value), 0),
            Value::Version(version) => (i128::from(version), 0),
        };
        Fixed { mantissa, scale }
    }
}

/// The value side, checked against the field's kind when read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Literal {
    Number(Fixed),
    Id(FrameId),
    Bool(bool),
    Name(&'static str),
    /// A flag name: its bit in each table (system V2, system V1/RS232, driver state), 0 where absent.
    Flag([u16; 3]),
    Version(u16),
}

/// One `--trigger` expression, read and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct Expression {
    text: String,
    target: Target,
    op: Op,
    literal: Literal,
}

/// Why an expression was not understood: where (a byte offset into it, from 0) and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("trigger {text:?}, at byte {offset}: {reason}")]
pub struct ExpressionError {
    pub text: String,
    pub offset: usize,
    pub reason: String,
}

impl Expression {
    /// The expression as written.
    pub fn text(&self) -> &str {
        &self.text
    }

    pub fn target(&self) -> Target {
        self.target
    }

    /// For an `id` expression: whether a frame with this identifier satisfies it. Ordering compares
    /// identifiers of one kind only (standard, extended, RS232).
    #[inline]
    pub fn matches_id(&self, id: FrameId) -> bool {
        let Literal::Id(wanted) = self.literal else { return false };
        let same_kind = std::mem::discriminant(&id) == std::mem::discriminant(&wanted);
        match self.op {
            Op::Eq => id == wanted,
            Op::Ne => id != wanted,
            _ => same_kind && self.op.holds(id.value().cmp(&wanted.value())),
        }
    }

    /// For a field expression: whether this value of the field satisfies it.
    #[inline]
    pub fn holds(&self, value: &Value) -> bool {
        match self.literal {
            Literal::Number(number) => self.op.holds(Fixed::of(value).compare(number)),
            Literal::Bool(wanted) => match *value {
                Value::Bool(actual) => self.op.holds(actual.cmp(&wanted)),
                _ => false,
            },
            Literal::Name(wanted) => {
                let equal = matches!(*value, Value::Name { name: Some(name), .. } if name == wanted);
                equal == (self.op == Op::Eq)
            }
            Literal::Flag(masks) => match *value {
                Value::Flags(flags) => {
                    (flags.bits & masks[table_index(flags.table)] != 0) == (self.op == Op::Eq)
                }
                _ => false,
            },
            Literal::Version(wanted) => match *value {
                Value::Version(actual) => self.op.holds(actual.cmp(&wanted)),
                _ => false,
            },
            Literal::Id(_) => false,
        }
    }
}

impl FromStr for Expression {
    type Err = ExpressionError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        parse(text).map_err(|(offset, reason)| ExpressionError { text: text.to_string(), offset, reason })
    }
}

/// The bit of a message kind in [`Target::Field`]'s `kinds`.
#[inline]
pub fn kind_bit(kind: MessageKind) -> u16 {
    1 << (kind as u16)
}

fn table_index(table: FlagTable) -> usize {
    match table {
        FlagTable::SystemV2 => 0,
        FlagTable::SystemV1Serial => 1,
        FlagTable::DriverState => 2,
    }
}

/// How a field's values compare.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shape {
    Number,
    Bool,
    Name,
    Flags,
    Version,
}

fn shape_of(value: &Value) -> Shape {
    match value {
        Value::Int(_) | Value::Decimal { .. } | Value::Code { .. } => Shape::Number,
        Value::Bool(_) => Shape::Bool,
        Value::Name { .. } => Shape::Name,
        Value::Flags(_) => Shape::Flags,
        Value::Version(_) => Shape::Version,
    }
}

/// One field of the schema: its name, how it compares, the kinds of message that carry it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct SchemaField {
    name: FieldName,
    shape: Shape,
    kinds: u16,
}

/// The schema, read from the one field table (`protocol::fields`), so a new field is known here at once.
fn schema() -> Vec<SchemaField> {
    let mut fields: Vec<SchemaField> = Vec::new();
    for decoded in one_of_each_message() {
        let bit = kind_bit(decoded.message.kind());
        for_each_field(&decoded, |field| match fields.iter_mut().find(|known| known.name == field.name) {
            Some(known) => known.kinds |= bit,
            None => fields.push(SchemaField { name: field.name, shape: shape_of(&field.value), kinds: bit }),
        });
    }
    fields.sort_by_key(|field| field.name.column());
    fields
}

fn codes_named(name: impl Fn(u8) -> Option<&'static str>) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for code in 0..=u8::MAX {
        if let Some(name) = name(code).filter(|name| !names.contains(name)) {
            names.push(name);
        }
    }
    names
}

/// The names a named field can take, from the protocol's own name functions.
fn names_of(field: FieldName) -> Vec<&'static str> {
    match field {
        FieldName::VehicleState => codes_named(vehicle_state_name),
        FieldName::ControlMode => codes_named(|code| {
            [Wire::CanV2, Wire::CanV1, Wire::Serial]
                .into_iter()
                .find_map(|wire| control_mode_name(wire, code))
        }),
        FieldName::FaultClear => codes_named(fault_clear_v1_name),
        FieldName::Code => codes_named(fault_clear_name),
        FieldName::FrontMode => codes_named(|code| LightMode::from_code(code).map(LightMode::name)),
        FieldName::Swa | FieldName::Swb | FieldName::Swc | FieldName::Swd => codes_named(rc_switch_name),
        _ => Vec::new(),
    }
}

/// The flag tables a flag field is named by.
fn tables_of(field: FieldName) -> &'static [FlagTable] {
    match field {
        FieldName::Faults => &[FlagTable::SystemV2, FlagTable::SystemV1Serial],
        FieldName::DriverFaults => &[FlagTable::DriverState],
        _ => &[],
    }
}

/// Every flag name of a flag field (undefined bits by their `reserved_*` names), each once.
fn flag_names(field: FieldName) -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    for table in tables_of(field) {
        for bit in 0..table.width() {
            let name = table.info(bit).name;
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    names
}

fn flag_masks(field: FieldName, wanted: &str) -> [u16; 3] {
    let mut masks = [0u16; 3];
    for &table in tables_of(field) {
        for bit in 0..table.width() {
            let info = table.info(bit);
            if info.name == wanted {
                masks[table_index(table)] |= info.mask;
            }
        }
    }
    masks
}

type Failure = (usize, String);

/// The identifier examples name: the system state's.
fn example_id() -> FrameId {
    FrameId::standard(ID_SYSTEM_STATE)
}

fn parse(text: &str) -> Result<Expression, Failure> {
    let mut at = skip_spaces(text, 0);
    let field_end = token_end(text, at, |c| c.is_ascii_alphanumeric() || c == '_' || c == '.');
    if field_end == at {
        let reason = match text[at..].chars().next() {
            None => {
                format!(
                    "empty trigger: write FIELD OP VALUE, such as battery_voltage<23.0 or id={}",
                    example_id()
                )
            }
            Some(c) => format!("expected a field name, found {c:?}"),
        };
        return Err((at, reason));
    }
    let (target, shape) = resolve_field(&text[at..field_end], at)?;
    let field_text = &text[at..field_end];
    at = skip_spaces(text, field_end);
    let op_at = at;
    let Some(&(spelling, op)) = Op::SPELLINGS.iter().find(|(spelling, _)| text[at..].starts_with(spelling))
    else {
        let found = text[at..].chars().next().map_or_else(|| "nothing".to_string(), |c| format!("{c:?}"));
        return Err((
            at,
            format!("expected an operator (<, <=, >, >=, =, !=) after {field_text}, found {found}"),
        ));
    };
    at = skip_spaces(text, at + spelling.len());
    let value_at = at;
    let value_end = token_end(text, at, |c| !c.is_whitespace());
    if value_end == at {
        return Err((at, format!("expected a value after {spelling}")));
    }
    let rest = skip_spaces(text, value_end);
    if rest < text.len() {
        return Err((rest, format!("unexpected {:?} after the value", &text[rest..])));
    }
    let literal =
        read_literal(&text[value_at..value_end], target, shape).map_err(|reason| (value_at, reason))?;
    let by_name = matches!(literal, Literal::Name(_) | Literal::Flag(_) | Literal::Bool(_));
    if by_name && !op.is_equality() {
        return Err((op_at, format!("{field_text} compares with = or != only, not {spelling}")));
    }
    Ok(Expression { text: text.to_string(), target, op, literal })
}

fn skip_spaces(text: &str, from: usize) -> usize {
    token_end(text, from, char::is_whitespace)
}

fn token_end(text: &str, from: usize, keep: impl Fn(char) -> bool) -> usize {
    text[from..].char_indices().find(|&(_, c)| !keep(c)).map_or(text.len(), |(offset, _)| from + offset)
}

/// `id`, `field`, `message.field` or an alias, to what it targets.
fn resolve_field(written: &str, at: usize) -> Result<(Target, Shape), Failure> {
    let lower = written.to_ascii_lowercase();
    let (message, field) = match lower.split_once('.') {
        Some((message, field)) => (Some(message), field),
        None => (None, lower.as_str()),
    };
    let field_at = at + message.map_or(0, |message| message.len() + 1);
    let kind = match message {
        None => None,
        Some(message) => Some(MessageKind::iter().find(|kind| kind.name() == message).ok_or_else(|| {
            let known: Vec<&str> = MessageKind::iter().map(MessageKind::name).collect();
            (at, unknown("message", message, &known))
        })?),
    };
    if field == ID {
        return match kind {
            None => Ok((Target::Id, Shape::Number)),
            Some(_) => Err((
                at,
                format!("id is the frame's identifier, not a message's field: write id={}", example_id()),
            )),
        };
    }
    let field = ALIASES.iter().find(|(alias, _)| *alias == field).map_or(field, |(_, name)| name);
    let schema = schema();
    let Some(known) = schema.iter().find(|known| known.name.as_str() == field) else {
        let mut names: Vec<&str> = vec![ID];
        names.extend(ALL_FIELD_NAMES);
        names.extend(ALIASES.iter().map(|(alias, _)| *alias));
        return Err((field_at, unknown("field", field, &names)));
    };
    let kinds = match kind {
        None => known.kinds,
        Some(kind) if known.kinds & kind_bit(kind) != 0 => kind_bit(kind),
        Some(kind) => {
            let carried: Vec<&str> =
                schema.iter().filter(|f| f.kinds & kind_bit(kind) != 0).map(|f| f.name.as_str()).collect();
            let list = if carried.is_empty() { "none".to_string() } else { carried.join(", ") };
            return Err((field_at, format!("{} has no field {field}; its fields: {list}", kind.name())));
        }
    };
    Ok((Target::Field { name: known.name, kinds }, known.shape))
}

/// `unknown field "battery_voltag"; did you mean battery_voltage?`, or the whole list when nothing is near.
fn unknown(what: &str, written: &str, known: &[&str]) -> String {
    let near = nearest(written, known);
    if near.is_empty() {
        format!("unknown {what} {written:?}; known {what}s: {}", known.join(", "))
    } else {
        format!("unknown {what} {written:?}; did you mean {}?", or_list(&near))
    }
}

fn or_list(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [head @ .., last] => format!("{} or {last}", head.join(", ")),
    }
}

/// Up to three names near `written`: a small edit distance, or one containing the other.
fn nearest<'a>(written: &str, known: &[&'a str]) -> Vec<&'a str> {
    let limit = (written.len() / 3).max(2);
    let mut scored: Vec<(usize, &str)> = known
        .iter()
        .map(|name| (edit_distance(written, name), *name))
        .filter(|(distance, name)| {
            *distance <= limit || (written.len() >= 3 && (name.contains(written) || written.contains(name)))
        })
        .collect();
    scored.sort_by_key(|(distance, _)| *distance);
    scored.into_iter().take(3).map(|(_, name)| name).collect()
}

/// Levenshtein distance over bytes.
fn edit_distance(a: &str, b: &str) -> usize {
    let b = b.as_bytes();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.bytes().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(row[j + 1] + 1);
        }
    }
    row[b.len()]
}

fn read_literal(value: &str, target: Target, shape: Shape) -> Result<Literal, String> {
    let Target::Field { name, .. } = target else {
        return FrameId::parse(value)
            .map(Literal::Id)
            .map_err(|reason| format!("id takes an identifier: {reason}"));
    };
    let field = name.as_str();
    let starts_numeric = value.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+' || c == '.');
    match shape {
        Shape::Number => read_number(value).map(Literal::Number).ok_or_else(|| not_a_number(field, value)),
        Shape::Bool => match value.to_ascii_lowercase().as_str() {
            "true" | "1" => Ok(Literal::Bool(true)),
            "false" | "0" => Ok(Literal::Bool(false)),
            _ => Err(format!("{field} takes true or false, not {value:?}")),
        },
        Shape::Version => read_version(value)
            .map(Literal::Version)
            .ok_or_else(|| format!("{field} takes a version such as 1.2 (major.minor), not {value:?}")),
        Shape::Name | Shape::Flags if starts_numeric => {
            read_number(value).map(Literal::Number).ok_or_else(|| not_a_number(field, value))
        }
        Shape::Name => {
            let names = names_of(name);
            let lower = value.to_ascii_lowercase();
            match names.iter().find(|known| **known == lower) {
                Some(known) => Ok(Literal::Name(known)),
                None => Err(format!(
                    "{value:?} is not a {field} name; its names: {} (or a raw number)",
                    names.join(", ")
                )),
            }
        }
        Shape::Flags => {
            let lower = value.to_ascii_lowercase();
            if lower == "none" {
                return Ok(Literal::Number(Fixed { mantissa: 0, scale: 0 }));
            }
            let masks = flag_masks(name, &lower);
            if masks != [0; 3] {
                return Ok(Literal::Flag(masks));
            }
            let names = flag_names(name);
            let near = nearest(&lower, &names);
            let hint = if near.is_empty() {
                format!("its flags: {}", names.join(", "))
            } else {
                format!("did you mean {}?", or_list(&near))
            };
            Err(format!("{value:?} is not a {field} flag; {hint} (or none, or a raw number)"))
        }
    }
}

fn not_a_number(field: &str, value: &str) -> String {
    format!("{field} takes a number (such as 23.0, -1.5 or 0x10), not {value:?}")
}

/// `23`, `-1.5`, `+.5`, `0x1F`: at most 19 digits and 18 decimals.
fn read_number(text: &str) -> Option<Fixed> {
    let (negative, digits) = match text.as_bytes().first() {
        Some(b'-') => (true, &text[1..]),
        Some(b'+') => (false, &text[1..]),
        _ => (false, text),
    };
    let magnitude = if let Some(hex) = digits.strip_prefix("0x").or_else(|| digits.strip_prefix("0X")) {
        if hex.is_empty() || hex.len() > 16 {
            return None;
        }
        Fixed { mantissa: i128::from(u64::from_str_radix(hex, 16).ok()?), scale: 0 }
    } else {
        let (whole, fraction) = digits.split_once('.').unwrap_or((digits, ""));
        let all_digits = |part: &str| part.bytes().all(|b| b.is_ascii_digit());
        let count = whole.len() + fraction.len();
        if count == 0
            || count > 19
            || fraction.len() > usize::from(MAX_SCALE)
            || !all_digits(whole)
            || !all_digits(fraction)
        {
            return None;
        }
        let mantissa = format!("{whole}{fraction}").parse::<i128>().ok()?;
        Fixed { mantissa, scale: fraction.len() as u8 }
    };
    Some(if negative { Fixed { mantissa: -magnitude.mantissa, ..magnitude } } else { magnitude })
}

/// `1.2` or `1`: major and minor up to 255, as the u16 the message carries (major in the high byte).
fn read_version(text: &str) -> Option<u16> {
    let (major, minor) = text.split_once('.').unwrap_or((text, "0"));
    let byte = |part: &str| {
        (!part.is_empty() && part.bytes().all(|b| b.is_ascii_digit()))
            .then(|| part.parse::<u8>().ok())
            .flatten()
    };
    Some(u16::from_be_bytes([byte(major)?, byte(minor)?]))
}

#[cfg(test)]
#[path = "expr_tests.rs"]
mod tests;
