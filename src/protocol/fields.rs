//! The named fields of every message, in SI units: the one schema behind text, JSON and CSV output.

use super::faults::Flags;
use super::message::*;

/// One field value, kept exact (fixed-point) so printing never needs float formatting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value {
    Int(i64),
    /// `raw / 10^scale`, e.g. battery 259 with scale 1 = 25.9.
    Decimal {
        raw: i64,
        scale: u8,
    },
    /// A bit field or code: an integer in JSON/CSV, hex with `digits` digits in text.
    Code {
        value: u16,
        digits: u8,
    },
    Bool(bool),
    /// An enumerated byte: its name, or the raw value when undefined.
    Name {
        raw: u8,
        name: Option<&'static str>,
    },
    /// Named flags (fault bits).
    Flags(Flags),
    /// `major.minor` from a u16 with major in the high byte.
    Version(u16),
}

impl Value {
    /// The value as a float where that makes sense (for summaries and plots).
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Value::Int(v) => Some(v as f64),
            Value::Decimal { raw, scale } => Some(raw as f64 / 10f64.powi(i32::from(scale))),
            Value::Code { value, .. } => Some(f64::from(value)),
            _ => None,
        }
    }
}

/// A named field with its unit (empty when unitless).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    pub name: &'static str,
    pub value: Value,
    pub unit: &'static str,
}

fn field(name: &'static str, value: Value, unit: &'static str) -> Field {
    Field { name, value, unit }
}
fn int(name: &'static str, value: impl Into<i64>, unit: &'static str) -> Field {
    field(name, Value::Int(value.into()), unit)
}
fn dec(name: &'static str, raw: impl Into<i64>, scale: u8, unit: &'static str) -> Field {
    field(name, Value::Decimal { raw: raw.into(), scale }, unit)
}
fn named(name: &'static str, raw: u8, text: Option<&'static str>) -> Field {
    field(name, Value::Name { raw, name: text }, "")
}

// Long: the output schema, one arm per message in field order; split, it would no longer read as one table.
/// Calls `visit` with every field of `decoded`, in schema order.
pub fn for_each_field(decoded: &Decoded, mut visit: impl FnMut(Field)) {
    let wire = decoded.wire;
    match decoded.message {
        Message::MotionCommand(cmd) => {
            visit(dec("linear_velocity", cmd.linear_mm_s, 3, "m/s"));
            visit(dec("angular_velocity", cmd.angular_mrad_s, 3, "rad/s"));
        }
        Message::PercentMotionCommand(cmd) => {
            visit(dec("linear_velocity", cmd.linear_mm_s(), 3, "m/s"));
            visit(dec("angular_velocity", cmd.angular_1e5(), 5, "rad/s"));
            visit(named("control_mode", cmd.control_mode, control_mode_name(wire, cmd.control_mode)));
            visit(named("fault_clear", cmd.fault_clear, fault_clear_v1_name(cmd.fault_clear)));
        }
        Message::LightCommand(lights) | Message::LightState(lights) => {
            visit(field("enabled", Value::Bool(lights.enable != 0), ""));
            visit(named("front_mode", lights.front_mode, light_mode_name(lights.front_mode)));
            visit(int("front_brightness", lights.front_brightness, "%"));
            visit(int("count", lights.count, ""));
        }
        Message::ControlModeCommand(mode) => {
            visit(named("control_mode", mode, control_mode_name(Wire::CanV2, mode)));
        }
        Message::FaultClear(code) => visit(named("code", code, fault_clear_name(code))),
        Message::VersionRequest => {}
        Message::SystemState(state) => {
            let vehicle = state.vehicle_state;
            visit(named("vehicle_state", vehicle, vehicle_state_name(vehicle)));
            let mode = state.control_mode;
            visit(named("control_mode", mode, control_mode_name(wire, mode)));
            visit(dec("battery_voltage", state.battery_decivolts, 1, "V"));
            visit(field("fault_code", Value::Code { value: state.fault_code, digits: 4 }, ""));
            visit(field("faults", Value::Flags(state.faults(wire)), ""));
            visit(int("count", state.count, ""));
        }
        Message::MotionState(state) => {
            visit(dec("linear_velocity", state.linear_mm_s, 3, "m/s"));
            visit(dec("angular_velocity", state.angular_mrad_s, 3, "rad/s"));
        }
        Message::RcState(rc) => {
            for (index, name) in ["swa", "swb", "swc", "swd"].into_iter().enumerate() {
                let bits = (rc.switches >> (2 * index)) & 0b11;
                visit(named(name, bits, rc_switch_name(bits)));
            }
            visit(int("right_stick_h", rc.right_stick_h, ""));
            visit(int("right_stick_v", rc.right_stick_v, ""));
            visit(int("left_stick_v", rc.left_stick_v, ""));
            visit(int("left_stick_h", rc.left_stick_h, ""));
            visit(int("var_a", rc.var_a, ""));
            visit(int("count", rc.count, ""));
        }
        Message::MotorHighSpeed(motor) => {
            visit(int("motor", motor.motor, ""));
            visit(int("rpm", motor.rpm, ""));
            visit(dec("current", motor.current_deciamps, 1, "A"));
            visit(int("pulse_count", motor.pulse_count, ""));
        }
        Message::MotorDriverState(motor) => {
            visit(int("motor", motor.motor, ""));
            visit(int("rpm", motor.rpm, ""));
            visit(dec("current", motor.current_deciamps, 1, "A"));
            visit(int("driver_temperature", motor.driver_temperature, "°C"));
        }
        Message::MotorLowSpeed(motor) => {
            visit(int("motor", motor.motor, ""));
            visit(dec("driver_voltage", motor.driver_decivolts, 1, "V"));
            visit(int("driver_temperature", motor.driver_temperature, "°C"));
            visit(int("motor_temperature", motor.motor_temperature, "°C"));
            let state = u16::from(motor.driver_state);
            visit(field("driver_state", Value::Code { value: state, digits: 2 }, ""));
            visit(field("driver_faults", Value::Flags(motor.driver_faults()), ""));
        }
        Message::Odometry(odo) => {
            visit(dec("left_wheel_odometer", odo.left_mm, 3, "m"));
            visit(dec("right_wheel_odometer", odo.right_mm, 3, "m"));
        }
        Message::VersionResponse(version) => {
            visit(field("controller_hw", Value::Version(version.controller_hw), ""));
            visit(field("driver_hw", Value::Version(version.driver_hw), ""));
            visit(field("controller_sw", Value::Version(version.controller_sw), ""));
            visit(field("driver_sw", Value::Version(version.driver_sw), ""));
        }
    }
}

/// Every field name any message can have, in a fixed order: the CSV columns.
pub const ALL_FIELD_NAMES: &[&str] = &[
    "vehicle_state",
    "control_mode",
    "battery_voltage",
    "fault_code",
    "faults",
    "linear_velocity",
    "angular_velocity",
    "fault_clear",
    "enabled",
    "front_mode",
    "front_brightness",
    "motor",
    "rpm",
    "current",
    "pulse_count",
    "driver_voltage",
    "driver_temperature",
    "motor_temperature",
    "driver_state",
    "driver_faults",
    "left_wheel_odometer",
    "right_wheel_odometer",
    "code",
    "swa",
    "swb",
    "swc",
    "swd",
    "right_stick_h",
    "right_stick_v",
    "left_stick_v",
    "left_stick_h",
    "var_a",
    "controller_hw",
    "driver_hw",
    "controller_sw",
    "driver_sw",
    "count",
];

/// Index of a field name in `ALL_FIELD_NAMES`.
pub fn column_of(name: &str) -> Option<usize> {
    ALL_FIELD_NAMES.iter().position(|candidate| *candidate == name)
}
