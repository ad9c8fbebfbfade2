//! The typed vocabulary both codecs (CAN and RS232) map to.
//!
//! Values are kept as the integers on the wire (mm/s, 0.1 V, ...) so that decoding and re-encoding is exact;
//! accessors give SI units. Constructors from SI values round to nearest (AgileX's code truncates) and reject
//! values outside the documented ranges.

use super::faults::{FlagTable, Flags};
use super::light::LightMode;
use super::mode::ControlMode;
// Messages are read from and written to a wire: `message::Wire` is the usual way to name it, defined in a
// leaf of its own so that the control mode's codes can read it too.
pub use super::wire::Wire;

/// Linear speed limit for commands built from SI values, m/s: AgileX's own clamp (SDK 2020) and the
/// RS232 full scale (100 % = 1.5 m/s). The spec's 2.3 m/s no-load top speed is not a safe command limit.
pub const LINEAR_LIMIT: f64 = 1.5;
/// Angular speed limit for commands built from SI values, rad/s: the manual's RS232 full scale.
/// (The manual's 0.7853 is a rounded pi/4; the firmware spec is the rounded number, so it stays.)
#[allow(clippy::approx_constant)]
pub const ANGULAR_LIMIT: f64 = 0.7853;
/// The chassis stops by itself when no motion command has arrived for this long (manual: communication
/// protection, 500 ms).
pub const COMMAND_TIMEOUT: std::time::Duration = std::time::Duration::from_millis(500);
/// Highest brightness of the custom light mode, percent.
pub const BRIGHTNESS_MAX: u8 = 100;

/// A value outside what the protocol documents.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum RangeError {
    #[error("{what} {value} is not a finite number")]
    NotFinite { what: &'static str, value: f64 },
    #[error("{what} {value} {unit} is outside the allowed range -{limit}..={limit} {unit}")]
    OutOfRange { what: &'static str, value: f64, limit: f64, unit: &'static str },
    #[error("brightness {0} % is above 100 %")]
    Brightness(u8),
}

fn check(what: &'static str, value: f64, limit: f64, unit: &'static str) -> Result<f64, RangeError> {
    if !value.is_finite() {
        return Err(RangeError::NotFinite { what, value });
    }
    if value.abs() > limit + 1e-9 {
        return Err(RangeError::OutOfRange { what, value, limit, unit });
    }
    Ok(value)
}

fn clamp_finite(value: f64, limit: f64) -> (f64, bool) {
    if value.is_nan() {
        return (0.0, true);
    }
    let clamped = value.clamp(-limit, limit);
    (clamped, clamped != value)
}

/// V2 motion command (0x111): mm/s and 0.001 rad/s, +x forward, +angular counter-clockwise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotionCommand {
    pub linear_mm_s: i16,
    pub angular_mrad_s: i16,
}

impl MotionCommand {
    pub const STOP: Self = Self { linear_mm_s: 0, angular_mrad_s: 0 };

    /// From m/s and rad/s, rounded to nearest; values beyond `LINEAR_LIMIT`/`ANGULAR_LIMIT` are rejected.
    pub fn from_si(linear: f64, angular: f64) -> Result<Self, RangeError> {
        let linear = check("linear speed", linear, LINEAR_LIMIT, "m/s")?;
        let angular = check("angular speed", angular, ANGULAR_LIMIT, "rad/s")?;
        Ok(Self::from_si_unchecked(linear, angular))
    }

    /// From m/s and rad/s, clamped to the limits (NaN becomes 0); also says whether anything was clamped.
    pub fn clamped_from_si(linear: f64, angular: f64) -> (Self, bool) {
        let (linear, a) = clamp_finite(linear, LINEAR_LIMIT);
        let (angular, b) = clamp_finite(angular, ANGULAR_LIMIT);
        (Self::from_si_unchecked(linear, angular), a || b)
    }

    fn from_si_unchecked(linear: f64, angular: f64) -> Self {
        Self {
            linear_mm_s: (linear * 1000.0).round() as i16,
            angular_mrad_s: (angular * 1000.0).round() as i16,
        }
    }

    pub fn linear(&self) -> f64 {
        f64::from(self.linear_mm_s) / 1000.0
    }
    pub fn angular(&self) -> f64 {
        f64::from(self.angular_mrad_s) / 1000.0
    }
}

/// Full scale of percentage speeds (CAN V1 0x130 and RS232 motion control): 100 % = 1.5 m/s.
pub const PERCENT_LINEAR_FULL_SCALE_MM_S: i64 = 1500;
/// 100 % = 0.7853 rad/s (manual); in units of 1e-5 rad/s so 1 % = 785.3e-5 is exact: 7853 per 10 %.
pub const PERCENT_ANGULAR_FULL_SCALE_1E5: i64 = 78530;

/// Motion command in percent of full scale: CAN V1 0x130 and RS232 0x55/0x01.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PercentMotionCommand {
    /// 0x01 CAN command mode (V1), 0x02 serial mode (RS232).
    pub control_mode: u8,
    /// Fault-clear code carried in the command (0 = none); see `FAULT_CLEAR_V1_NAMES`.
    pub fault_clear: u8,
    pub linear_percent: i8,
    pub angular_percent: i8,
    /// Scout Mini omni only; 0 on TRACER.
    pub lateral_percent: i8,
    /// V1 count byte or RS232 frame id.
    pub count: u8,
}

impl PercentMotionCommand {
    /// From m/s and rad/s, rounded to the nearest percent; outside the full scale is rejected.
    pub fn from_si(control_mode: u8, linear: f64, angular: f64) -> Result<Self, RangeError> {
        let linear = check("linear speed", linear, LINEAR_LIMIT, "m/s")?;
        let angular = check("angular speed", angular, ANGULAR_LIMIT, "rad/s")?;
        Ok(Self {
            control_mode,
            linear_percent: (linear / LINEAR_LIMIT * 100.0).round() as i8,
            angular_percent: (angular / ANGULAR_LIMIT * 100.0).round() as i8,
            ..Self::default()
        })
    }

    /// Linear speed in mm/s (exact: 1 % = 15 mm/s).
    pub fn linear_mm_s(&self) -> i64 {
        i64::from(self.linear_percent) * PERCENT_LINEAR_FULL_SCALE_MM_S / 100
    }
    /// Angular speed in units of 1e-5 rad/s (exact).
    pub fn angular_1e5(&self) -> i64 {
        i64::from(self.angular_percent) * PERCENT_ANGULAR_FULL_SCALE_1E5 / 100
    }
    pub fn linear(&self) -> f64 {
        self.linear_mm_s() as f64 / 1000.0
    }
    pub fn angular(&self) -> f64 {
        self.angular_1e5() as f64 / 100_000.0
    }
}

/// Light command (0x121, V1 0x140, RS232 0x55/0x02) and light state (0x231, V1 0x141, RS232 0xAA/0x07).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Lights {
    /// 0 = firmware controls the lights, 1 = the host does.
    pub enable: u8,
    /// 0 off, 1 on, 2 breathing, 3 custom brightness ([`LightMode::from_code`]).
    pub front_mode: u8,
    /// 0-100 %, used in mode 3.
    pub front_brightness: u8,
    /// Reserved on TRACER (SDK: rear mode); sent as 0.
    pub rear_mode: u8,
    /// Reserved on TRACER (SDK: rear brightness); sent as 0.
    pub rear_brightness: u8,
    /// Count byte (V2 byte 7, V1 byte 6) or RS232 frame id.
    pub count: u8,
}

/// Light-mode bytes of byte 1, from [`LightMode::code`], for matching on a raw byte; prefer [`LightMode`].
pub const LIGHT_OFF: u8 = LightMode::Off.code();
pub const LIGHT_ON: u8 = LightMode::On.code();
pub const LIGHT_BREATH: u8 = LightMode::Breath.code();
pub const LIGHT_CUSTOM: u8 = LightMode::Custom.code();

impl Lights {
    /// Host-controlled front lights; `brightness` only matters for [`LightMode::Custom`].
    pub fn front(mode: LightMode, brightness: u8) -> Result<Self, RangeError> {
        if brightness > BRIGHTNESS_MAX {
            return Err(RangeError::Brightness(brightness));
        }
        Ok(Self { enable: 1, front_mode: mode.code(), front_brightness: brightness, ..Self::default() })
    }
    /// Hand the lights back to the firmware.
    pub fn release() -> Self {
        Self::default()
    }
}

/// System state: 0x211 (V2), 0x151 (V1, or V2 as the manual names it), RS232 0xAA/0x01.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SystemState {
    /// 0 normal, 1 E-stop, 2 system exception.
    pub vehicle_state: u8,
    /// See [`ControlMode::from_code`] (`SystemState::mode`).
    pub control_mode: u8,
    /// Battery voltage in 0.1 V.
    pub battery_decivolts: u16,
    /// byte4 << 8 | byte5.
    pub fault_code: u16,
    pub count: u8,
}

impl SystemState {
    pub fn battery_voltage(&self) -> f64 {
        super::constants::volts(self.battery_decivolts)
    }
    /// The fault bits, named by the table of the wire they came from.
    pub fn faults(&self, wire: Wire) -> Flags {
        let table = match wire {
            Wire::CanV2 => FlagTable::SystemV2,
            Wire::CanV1 | Wire::Serial => FlagTable::SystemV1Serial,
        };
        Flags::new(table, self.fault_code)
    }
    pub fn is_estop(&self) -> bool {
        self.vehicle_state == VEHICLE_ESTOP
    }
    /// The vehicle state "exception": a latched fault, battery cut-off or the RC link lost.
    pub fn is_exception(&self) -> bool {
        self.vehicle_state == VEHICLE_EXCEPTION
    }

    /// The reported control mode, if the byte is defined on `wire`.
    pub fn mode(&self, wire: Wire) -> Option<ControlMode> {
        ControlMode::from_code(wire, self.control_mode)
    }

    /// Whether the RC transmitter has control, as far as the status can tell: mode 3 on V2; on V1/RS232 the
    /// shared 0 (RC, or not yet in command mode).
    pub fn rc_has_control(&self, wire: Wire) -> bool {
        self.mode(wire) == Some(ControlMode::Rc)
    }

    /// Why the robot cannot be driven now, if it cannot: E-stop, the vehicle state "exception", a bit that blocks driving (a fault or a
    /// latched protection), or the RC transmitter in control (V2, where the status says so unambiguously).
    pub fn why_not_drivable(&self, wire: Wire) -> Option<String> {
        if self.is_estop() {
            return Some("the E-stop is pressed: release both E-stop buttons".to_string());
        }
        let blocking: Vec<String> = self
            .faults(wire)
            .iter()
            .filter(|f| f.severity.blocks_driving())
            .map(|f| format!("{} [{}]: {}", f.name, f.severity, f.action))
            .collect();
        if !blocking.is_empty() {
            return Some(format!("fault set: {}", blocking.join("; ")));
        }
        // The robot ignores motion commands in this state, whatever its fault bits show (a motor driver's
        // lost link, for one, is reported only in that driver's own frame).
        if self.is_exception() {
            return Some(EXCEPTION_REASON.to_string());
        }
        if wire == Wire::CanV2 && self.rc_has_control(wire) {
            return Some(
                "the RC transmitter has control: put switch SWB at the top (command mode)".to_string(),
            );
        }
        None
    }
}

/// Why a robot in the vehicle state "exception" cannot be driven, and what to do.
pub const EXCEPTION_REASON: &str =
    "the robot reports a system exception (a latched fault, battery cut-off or \
     the RC link lost): see `tracerctl doctor`, then `tracerctl clear-errors`";

pub const VEHICLE_NORMAL: u8 = 0;
pub const VEHICLE_ESTOP: u8 = 1;
pub const VEHICLE_EXCEPTION: u8 = 2;

/// Control-mode bytes of 0x421 and 0x211 byte 1 (V2), from [`ControlMode::code`], for matching on a raw
/// byte; prefer [`ControlMode`].
pub const MODE_STANDBY: u8 = ControlMode::Standby.code(Wire::CanV2);
pub const MODE_CAN: u8 = ControlMode::Can.code(Wire::CanV2);
pub const MODE_SERIAL: u8 = ControlMode::Serial.code(Wire::CanV2);
pub const MODE_RC: u8 = ControlMode::Rc.code(Wire::CanV2);

pub fn vehicle_state_name(value: u8) -> Option<&'static str> {
    match value {
        VEHICLE_NORMAL => Some("normal"),
        VEHICLE_ESTOP => Some("estop"),
        VEHICLE_EXCEPTION => Some("exception"),
        _ => None,
    }
}

/// The name of a reported control-mode byte ([`ControlMode::from_code`]).
pub fn control_mode_name(wire: Wire, value: u8) -> Option<&'static str> {
    ControlMode::from_code(wire, value).map(ControlMode::name)
}

/// 0x441 codes (V2).
pub const CLEAR_ALL: u8 = 0;
pub const CLEAR_MOTOR1: u8 = 1;
pub const CLEAR_MOTOR2: u8 = 2;

pub fn fault_clear_name(value: u8) -> Option<&'static str> {
    match value {
        CLEAR_ALL => Some("all"),
        CLEAR_MOTOR1 => Some("motor1"),
        CLEAR_MOTOR2 => Some("motor2"),
        _ => None,
    }
}

/// Fault-clear codes carried in V1 0x130 byte 1 and RS232 motion control d1.
pub fn fault_clear_v1_name(value: u8) -> Option<&'static str> {
    Some(match value {
        0 => "none",
        1 => "battery_undervoltage",
        2 => "battery_overvoltage",
        3 => "motor1_comm",
        4 => "motor2_comm",
        5 => "motor3_comm",
        6 => "motor4_comm",
        7 => "driver_overheat",
        8 => "motor_overcurrent",
        _ => return None,
    })
}

/// Motion state: 0x221 (V2), 0x131 (V1), RS232 0xAA/0x02.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotionState {
    pub linear_mm_s: i16,
    pub angular_mrad_s: i16,
    /// V1 count byte or RS232 frame id; 0 for V2, which carries none.
    pub count: u8,
}

impl MotionState {
    pub fn linear(&self) -> f64 {
        f64::from(self.linear_mm_s) / 1000.0
    }
    pub fn angular(&self) -> f64 {
        f64::from(self.angular_mrad_s) / 1000.0
    }
}

/// RC transmitter state, 0x241 (SDK layout; not in the TRACER manuals).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RcState {
    /// SWA bits 1:0, SWB 3:2, SWC 5:4, SWD 7:6.
    pub switches: u8,
    pub right_stick_h: i8,
    pub right_stick_v: i8,
    pub left_stick_v: i8,
    pub left_stick_h: i8,
    pub var_a: i8,
    pub count: u8,
}

/// Position of an RC switch from its two bits.
pub fn rc_switch_name(bits: u8) -> Option<&'static str> {
    match bits & 0b11 {
        0b10 => Some("up"),
        0b01 => Some("middle"),
        0b11 => Some("down"),
        _ => None,
    }
}

/// Motor high-speed feedback, 0x251/0x252.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotorHighSpeed {
    /// 1 or 2.
    pub motor: u8,
    pub rpm: i16,
    /// 0.1 A, signed.
    pub current_deciamps: i16,
    pub pulse_count: i32,
}

/// Motor driver feedback of CAN V1 (0x201/0x202) and RS232 (0xAA/0x03, 0x04).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotorDriverState {
    pub motor: u8,
    /// 0.1 A, unsigned.
    pub current_deciamps: u16,
    pub rpm: i16,
    pub driver_temperature: i8,
    /// V1 count byte or RS232 frame id.
    pub count: u8,
}

/// Motor low-speed feedback, 0x261/0x262.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MotorLowSpeed {
    pub motor: u8,
    /// 0.1 V.
    pub driver_decivolts: u16,
    /// °C.
    pub driver_temperature: i16,
    /// °C; -40 means no sensor.
    pub motor_temperature: i8,
    pub driver_state: u8,
}

impl MotorLowSpeed {
    pub fn driver_faults(&self) -> Flags {
        Flags::new(FlagTable::DriverState, u16::from(self.driver_state))
    }
}

/// Wheel odometers, 0x311, in mm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Odometry {
    pub left_mm: i32,
    pub right_mm: i32,
}

/// Version response, 0x41A: each a u16 with major in the high byte.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VersionResponse {
    pub controller_hw: u16,
    pub driver_hw: u16,
    pub controller_sw: u16,
    pub driver_sw: u16,
}

/// Everything the TRACER speaks, in both directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, strum::EnumCount)]
pub enum Message {
    MotionCommand(MotionCommand),
    PercentMotionCommand(PercentMotionCommand),
    LightCommand(Lights),
    ControlModeCommand(u8),
    FaultClear(u8),
    VersionRequest,
    SystemState(SystemState),
    MotionState(MotionState),
    LightState(Lights),
    RcState(RcState),
    MotorHighSpeed(MotorHighSpeed),
    MotorDriverState(MotorDriverState),
    MotorLowSpeed(MotorLowSpeed),
    Odometry(Odometry),
    VersionResponse(VersionResponse),
}

impl Message {
    /// What kind of message this is: encodings of the same thing share one kind.
    pub fn kind(&self) -> MessageKind {
        match self {
            Message::MotionCommand(_) | Message::PercentMotionCommand(_) => MessageKind::MotionCommand,
            Message::LightCommand(_) => MessageKind::LightCommand,
            Message::ControlModeCommand(_) => MessageKind::ControlModeCommand,
            Message::FaultClear(_) => MessageKind::FaultClear,
            Message::VersionRequest => MessageKind::VersionRequest,
            Message::SystemState(_) => MessageKind::SystemState,
            Message::MotionState(_) => MessageKind::MotionState,
            Message::LightState(_) => MessageKind::LightState,
            Message::RcState(_) => MessageKind::RcState,
            Message::MotorHighSpeed(_) | Message::MotorDriverState(_) => MessageKind::MotorHighSpeed,
            Message::MotorLowSpeed(_) => MessageKind::MotorLowSpeed,
            Message::Odometry(_) => MessageKind::Odometry,
            Message::VersionResponse(_) => MessageKind::VersionResponse,
        }
    }

    /// The stable message name of JSON `msg`. Encodings of the same thing share one name.
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// True for messages that can make the robot move.
    pub fn moves_robot(&self) -> bool {
        match self {
            Message::MotionCommand(cmd) => *cmd != MotionCommand::STOP,
            Message::PercentMotionCommand(cmd) => cmd.linear_percent != 0 || cmd.angular_percent != 0,
            Message::ControlModeCommand(_) => true,
            _ => false,
        }
    }
}

/// The kinds of message, named as JSON `msg` names them (`system_state`); the order is the order of
/// [`MESSAGE_NAMES`].
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, strum::IntoStaticStr, strum::VariantNames, strum::EnumIter,
)]
#[strum(serialize_all = "snake_case")]
pub enum MessageKind {
    MotionCommand,
    LightCommand,
    ControlModeCommand,
    FaultClear,
    VersionRequest,
    SystemState,
    MotionState,
    LightState,
    RcState,
    MotorHighSpeed,
    MotorLowSpeed,
    Odometry,
    VersionResponse,
}

impl MessageKind {
    /// The stable name (`system_state`).
    pub fn name(self) -> &'static str {
        self.into()
    }
}

/// Every message name, in a fixed order (for filters and help text).
pub const MESSAGE_NAMES: &[&str] = <MessageKind as strum::VariantNames>::VARIANTS;

/// A message together with the encoding it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decoded {
    pub wire: Wire,
    pub message: Message,
}

#[cfg(test)]
mod tests {
    use strum::{EnumCount, IntoEnumIterator};

    use super::*;

    /// One message of every variant (the count below fails when a variant is added without one here).
    fn one_of_each() -> [Message; Message::COUNT] {
        [
            Message::MotionCommand(MotionCommand::default()),
            Message::PercentMotionCommand(PercentMotionCommand::default()),
            Message::LightCommand(Lights::default()),
            Message::ControlModeCommand(0),
            Message::FaultClear(0),
            Message::VersionRequest,
            Message::SystemState(SystemState::default()),
            Message::MotionState(MotionState::default()),
            Message::LightState(Lights::default()),
            Message::RcState(RcState::default()),
            Message::MotorHighSpeed(MotorHighSpeed::default()),
            Message::MotorDriverState(MotorDriverState::default()),
            Message::MotorLowSpeed(MotorLowSpeed::default()),
            Message::Odometry(Odometry::default()),
            Message::VersionResponse(VersionResponse::default()),
        ]
    }

    #[test]
    fn message_names_are_the_names_messages_have() {
        let names: Vec<&str> = one_of_each().iter().map(Message::name).collect();
        for name in &names {
            assert!(MESSAGE_NAMES.contains(name), "{name} missing from MESSAGE_NAMES");
        }
        for name in MESSAGE_NAMES {
            assert!(names.contains(name), "no message is named {name}");
        }
        assert_eq!(MessageKind::iter().map(MessageKind::name).collect::<Vec<_>>(), MESSAGE_NAMES);
    }

    #[test]
    fn names_are_the_stable_json_names() {
        assert_eq!(
            MESSAGE_NAMES,
            [
                "motion_command",
                "light_command",
                "control_mode_command",
                "fault_clear",
                "version_request",
                "system_state",
                "motion_state",
                "light_state",
                "rc_state",
                "motor_high_speed",
                "motor_low_speed",
                "odometry",
                "version_response",
            ]
        );
        assert_eq!(Message::PercentMotionCommand(Default::default()).name(), "motion_command");
        assert_eq!(Message::MotorDriverState(Default::default()).name(), "motor_high_speed");
    }

    fn state(vehicle_state: u8, control_mode: u8, fault_code: u16) -> SystemState {
        SystemState { vehicle_state, control_mode, battery_decivolts: 259, fault_code, count: 0 }
    }

    #[test]
    fn drivability_from_the_status() {
        assert_eq!(state(0, 1, 0).why_not_drivable(Wire::CanV2), None);
        assert!(state(1, 1, 0).why_not_drivable(Wire::CanV2).is_some_and(|r| r.contains("E-stop")));
        assert!(state(0, 3, 0).why_not_drivable(Wire::CanV2).is_some_and(|r| r.contains("RC transmitter")));
        // V1/RS232 0 also means "not in command mode yet": not a reason by itself.
        assert_eq!(state(0, 0, 0).why_not_drivable(Wire::Serial), None);
        let fault = state(0, 1, 0x0100).why_not_drivable(Wire::CanV2);
        assert!(fault.is_some_and(|r| r.starts_with("fault set: battery_undervoltage_fault [fault]")));
    }

    #[test]
    fn an_undocumented_bit_does_not_block_driving() {
        // 0x0080: byte 5 bit 7, defined by no TRACER document (a Bunker Mini sets it in E-stop).
        assert_eq!(state(0, 1, 0x0080).why_not_drivable(Wire::CanV2), None);
    }
}
