//! The named fields of every message, in SI units: the one schema behind text, JSON and CSV output.

use super::faults::Flags;
use super::light::LightMode;
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
    pub name: FieldName,
    pub value: Value,
    pub unit: &'static str,
}

fn field(name: FieldName, value: Value, unit: &'static str) -> Field {
    Field { name, value, unit }
}
fn int(name: FieldName, value: impl Into<i64>, unit: &'static str) -> Field {
    field(name, Value::Int(value.into()), unit)
}
fn dec(name: FieldName, raw: impl Into<i64>, scale: u8, unit: &'static str) -> Field {
    field(name, Value::Decimal { raw: raw.into(), scale }, unit)
}
fn named(name: FieldName, raw: u8, text: Option<&'static str>) -> Field {
    field(name, Value::Name { raw, name: text }, "")
}

/// Calls `visit` with every field of `decoded`, in schema order.
#[expect(
    clippy::too_many_lines,
    reason = "the output schema, one arm per message in field order; split, it would no longer read as one table."
)]
pub fn for_each_field(decoded: &Decoded, mut visit: impl FnMut(Field)) {
    use FieldName::*;
    let wire = decoded.wire;
    match decoded.message {
        Message::MotionCommand(cmd) => {
            visit(dec(LinearVelocity, cmd.linear_mm_s, 3, "m/s"));
            visit(dec(AngularVelocity, cmd.angular_mrad_s, 3, "rad/s"));
        }
        Message::PercentMotionCommand(cmd) => {
            visit(dec(LinearVelocity, cmd.linear_mm_s(), 3, "m/s"));
            visit(dec(AngularVelocity, cmd.angular_1e5(), 5, "rad/s"));
            visit(named(ControlMode, cmd.control_mode, control_mode_name(wire, cmd.control_mode)));
            visit(named(FaultClear, cmd.fault_clear, fault_clear_v1_name(cmd.fault_clear)));
        }
        Message::LightCommand(lights) | Message::LightState(lights) => {
            visit(field(Enabled, Value::Bool(lights.enable != 0), ""));
            visit(named(
                FrontMode,
                lights.front_mode,
                LightMode::from_code(lights.front_mode).map(LightMode::name),
            ));
            visit(int(FrontBrightness, lights.front_brightness, "%"));
            visit(int(Count, lights.count, ""));
        }
        Message::ControlModeCommand(mode) => {
            visit(named(ControlMode, mode, control_mode_name(Wire::CanV2, mode)));
        }
        Message::FaultClear(code) => visit(named(Code, code, fault_clear_name(code))),
        Message::VersionRequest => {}
        Message::SystemState(state) => {
            let vehicle = state.vehicle_state;
            visit(named(VehicleState, vehicle, vehicle_state_name(vehicle)));
            let mode = state.control_mode;
            visit(named(ControlMode, mode, control_mode_name(wire, mode)));
            visit(dec(BatteryVoltage, state.battery_decivolts, 1, "V"));
            visit(field(FaultCode, Value::Code { value: state.fault_code, digits: 4 }, ""));
            visit(field(Faults, Value::Flags(state.faults(wire)), ""));
            visit(int(Count, state.count, ""));
        }
        Message::MotionState(state) => {
            visit(dec(LinearVelocity, state.linear_mm_s, 3, "m/s"));
            visit(dec(AngularVelocity, state.angular_mrad_s, 3, "rad/s"));
        }
        Message::RcState(rc) => {
            for (index, name) in [Swa, Swb, Swc, Swd].into_iter().enumerate() {
                let bits = (rc.switches >> (2 * index)) & 0b11;
                visit(named(name, bits, rc_switch_name(bits)));
            }
            visit(int(RightStickH, rc.right_stick_h, ""));
            visit(int(RightStickV, rc.right_stick_v, ""));
            visit(int(LeftStickV, rc.left_stick_v, ""));
            visit(int(LeftStickH, rc.left_stick_h, ""));
            visit(int(VarA, rc.var_a, ""));
            visit(int(Count, rc.count, ""));
        }
        Message::MotorHighSpeed(motor) => {
            visit(int(Motor, motor.motor, ""));
            visit(int(Rpm, motor.rpm, ""));
            visit(dec(Current, motor.current_deciamps, 1, "A"));
            visit(int(PulseCount, motor.pulse_count, ""));
        }
        Message::MotorDriverState(motor) => {
            visit(int(Motor, motor.motor, ""));
            visit(int(Rpm, motor.rpm, ""));
            visit(dec(Current, motor.current_deciamps, 1, "A"));
            visit(int(DriverTemperature, motor.driver_temperature, "°C"));
        }
        Message::MotorLowSpeed(motor) => {
            visit(int(Motor, motor.motor, ""));
            visit(dec(DriverVoltage, motor.driver_decivolts, 1, "V"));
            visit(int(DriverTemperature, motor.driver_temperature, "°C"));
            visit(int(MotorTemperature, motor.motor_temperature, "°C"));
            let state = u16::from(motor.driver_state);
            visit(field(DriverState, Value::Code { value: state, digits: 2 }, ""));
            visit(field(DriverFaults, Value::Flags(motor.driver_faults()), ""));
        }
        Message::Odometry(odo) => {
            visit(dec(LeftWheelOdometer, odo.left_mm, 3, "m"));
            visit(dec(RightWheelOdometer, odo.right_mm, 3, "m"));
        }
        Message::VersionResponse(version) => {
            visit(field(ControllerHw, Value::Version(version.controller_hw), ""));
            visit(field(DriverHw, Value::Version(version.driver_hw), ""));
            visit(field(ControllerSw, Value::Version(version.controller_sw), ""));
            visit(field(DriverSw, Value::Version(version.driver_sw), ""));
        }
    }
}

/// Declares [`FieldName`] and [`ALL_FIELD_NAMES`] from one list, so the two cannot drift apart.
macro_rules! field_names {
    ($($variant:ident = $name:literal,)*) => {
        /// The name of a field; its discriminant is its CSV column among the field columns.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum FieldName {
            $($variant,)*
        }

        /// Every field name any message can have, in a fixed order: the CSV columns.
        pub const ALL_FIELD_NAMES: &[&str] = &[$($name,)*];
    };
}

field_names! {
    VehicleState = "vehicle_state",
    ControlMode = "control_mode",
    BatteryVoltage = "battery_voltage",
    FaultCode = "fault_code",
    Faults = "faults",
    LinearVelocity = "linear_velocity",
    AngularVelocity = "angular_velocity",
    FaultClear = "fault_clear",
    Enabled = "enabled",
    FrontMode = "front_mode",
    FrontBrightness = "front_brightness",
    Motor = "motor",
    Rpm = "rpm",
    Current = "current",
    PulseCount = "pulse_count",
    DriverVoltage = "driver_voltage",
    DriverTemperature = "driver_temperature",
    MotorTemperature = "motor_temperature",
    DriverState = "driver_state",
    DriverFaults = "driver_faults",
    LeftWheelOdometer = "left_wheel_odometer",
    RightWheelOdometer = "right_wheel_odometer",
    Code = "code",
    Swa = "swa",
    Swb = "swb",
    Swc = "swc",
    Swd = "swd",
    RightStickH = "right_stick_h",
    RightStickV = "right_stick_v",
    LeftStickV = "left_stick_v",
    LeftStickH = "left_stick_h",
    VarA = "var_a",
    ControllerHw = "controller_hw",
    DriverHw = "driver_hw",
    ControllerSw = "controller_sw",
    DriverSw = "driver_sw",
    Count = "count",
}

impl FieldName {
    pub const fn as_str(self) -> &'static str {
        ALL_FIELD_NAMES[self as usize]
    }

    /// The field's index in [`ALL_FIELD_NAMES`] (its CSV column among the field columns).
    pub const fn column(self) -> usize {
        self as usize
    }
}

/// The most fields any one message has (RC state: ten); writers size their scratch space by it.
pub const MAX_FIELDS: usize = 10;

/// One message of every variant, each with a wire that decodes to it: the fields a kind can have.
pub fn one_of_each_message() -> Vec<Decoded> {
    let v2 = |message| Decoded { wire: Wire::CanV2, message };
    let v1 = |message| Decoded { wire: Wire::CanV1, message };
    vec![
        v2(Message::MotionCommand(MotionCommand::default())),
        v1(Message::PercentMotionCommand(PercentMotionCommand::default())),
        v2(Message::LightCommand(Lights::default())),
        v2(Message::ControlModeCommand(0)),
        v2(Message::FaultClear(0)),
        v2(Message::VersionRequest),
        v2(Message::SystemState(SystemState::default())),
        v2(Message::MotionState(MotionState::default())),
        v2(Message::LightState(Lights::default())),
        v2(Message::RcState(RcState::default())),
        v2(Message::MotorHighSpeed(MotorHighSpeed::default())),
        v1(Message::MotorDriverState(MotorDriverState::default())),
        v2(Message::MotorLowSpeed(MotorLowSpeed::default())),
        v2(Message::Odometry(Odometry::default())),
        v2(Message::VersionResponse(VersionResponse::default())),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;
    use strum::EnumCount;

    #[test]
    fn every_message_variant_has_a_sample() {
        let samples = one_of_each_message();
        assert_eq!(samples.len(), Message::COUNT);
        for (index, decoded) in samples.iter().enumerate() {
            let same = samples.iter().position(|other| {
                std::mem::discriminant(&other.message) == std::mem::discriminant(&decoded.message)
            });
            assert_eq!(same, Some(index), "one sample per variant");
        }
    }

    #[test]
    fn every_message_has_at_most_max_fields_each_named_once() {
        let mut most = 0;
        for decoded in one_of_each_message() {
            let mut names = Vec::new();
            for_each_field(&decoded, |field| names.push(field.name));
            let distinct: HashSet<_> = names.iter().map(|name| name.column()).collect();
            assert_eq!(distinct.len(), names.len(), "{names:?}");
            most = most.max(names.len());
        }
        assert_eq!(most, MAX_FIELDS);
    }

    #[test]
    fn field_names_are_their_columns() {
        assert_eq!(FieldName::VehicleState.as_str(), "vehicle_state");
        assert_eq!(FieldName::Count.as_str(), "count");
        assert_eq!(FieldName::Count.column(), ALL_FIELD_NAMES.len() - 1);
        assert_eq!(ALL_FIELD_NAMES[FieldName::LeftWheelOdometer.column()], "left_wheel_odometer");
    }
}
