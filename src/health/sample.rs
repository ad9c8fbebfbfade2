//! What the analysis keeps of a message: the few integers it measures with, in the units of the wire
//! (mm/s, mrad/s, 0.1 A, 0.1 V, mm), so sums over them are exact whatever order they are added in.

use crate::protocol::message::Message;

/// Commands keep angular speed in 1e-5 rad/s: exact for both the V2 command (mrad/s) and the RS232
/// percent command (785.3e-5 rad/s per %).
pub(super) const ANGULAR_COMMAND_PER_MRAD: i32 = 100;

/// One relevant observation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Sample {
    /// A motion command: mm/s and 1e-5 rad/s.
    Command { linear: i32, angular: i32 },
    /// The robot's measured motion (0x221, RS232 motion state): mm/s and mrad/s.
    Motion { linear: i32, angular: i32 },
    /// A motor's current, 0.1 A; `motor` 0 (motor 1) or 1 (motor 2).
    Current { motor: u8, deciamps: i32 },
    /// Wheel odometers (0x311), mm.
    Odometry { left: i32, right: i32 },
    /// Battery voltage (system state), 0.1 V.
    Voltage { decivolts: u16 },
}

impl Sample {
    /// The sample of a message, or `None` for the messages the analysis does not use (one match, no
    /// allocation).
    #[inline]
    pub fn of(message: &Message) -> Option<Self> {
        Some(match message {
            Message::MotionCommand(cmd) => Sample::Command {
                linear: cmd.linear_mm_s.into(),
                angular: i32::from(cmd.angular_mrad_s) * ANGULAR_COMMAND_PER_MRAD,
            },
            Message::PercentMotionCommand(cmd) => {
                Sample::Command { linear: cmd.linear_mm_s() as i32, angular: cmd.angular_1e5() as i32 }
            }
            Message::MotionState(state) => {
                Sample::Motion { linear: state.linear_mm_s.into(), angular: state.angular_mrad_s.into() }
            }
            Message::MotorHighSpeed(motor) if matches!(motor.motor, 1 | 2) => {
                Sample::Current { motor: motor.motor - 1, deciamps: motor.current_deciamps.into() }
            }
            Message::MotorDriverState(motor) if matches!(motor.motor, 1 | 2) => {
                Sample::Current { motor: motor.motor - 1, deciamps: motor.current_deciamps.into() }
            }
            Message::Odometry(odo) => Sample::Odometry { left: odo.left_mm, right: odo.right_mm },
            Message::SystemState(state) => Sample::Voltage { decivolts: state.battery_decivolts },
            _ => return None,
        })
    }
}

/// A command in SI units: m/s, rad/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Command {
    pub t: i64,
    pub linear: i32,
    pub angular: i32,
}

impl Command {
    pub fn linear_si(&self) -> f64 {
        f64::from(self.linear) / 1000.0
    }
    pub fn angular_si(&self) -> f64 {
        f64::from(self.angular) / 100_000.0
    }
    pub fn is_zero(&self) -> bool {
        self.linear == 0 && self.angular == 0
    }
    pub fn same_value(&self, other: &Command) -> bool {
        self.linear == other.linear && self.angular == other.angular
    }
}

/// A measured motion sample: mm/s, mrad/s.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Motion {
    pub t: i64,
    pub linear: i32,
    pub angular: i32,
}

/// A timed integer reading (current in 0.1 A, voltage in 0.1 V).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Reading {
    pub t: i64,
    pub value: i32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Odometer {
    pub t: i64,
    pub left: i64,
    pub right: i64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::*;

    #[test]
    fn commands_of_both_links_share_exact_units() {
        let v2 = Message::MotionCommand(MotionCommand { linear_mm_s: 300, angular_mrad_s: -500 });
        assert_eq!(Sample::of(&v2), Some(Sample::Command { linear: 300, angular: -50_000 }));
        let serial = Message::PercentMotionCommand(PercentMotionCommand {
            linear_percent: 20,
            angular_percent: -10,
            ..PercentMotionCommand::default()
        });
        assert_eq!(Sample::of(&serial), Some(Sample::Command { linear: 300, angular: -7853 }));
    }

    #[test]
    fn feedback_becomes_samples_and_the_rest_is_ignored() {
        let motor = Message::MotorHighSpeed(MotorHighSpeed {
            motor: 2,
            rpm: 10,
            current_deciamps: -12,
            pulse_count: 0,
        });
        assert_eq!(Sample::of(&motor), Some(Sample::Current { motor: 1, deciamps: -12 }));
        let other = Message::MotorHighSpeed(MotorHighSpeed { motor: 3, ..MotorHighSpeed::default() });
        assert_eq!(Sample::of(&other), None);
        let state = Message::SystemState(SystemState { battery_decivolts: 259, ..SystemState::default() });
        assert_eq!(Sample::of(&state), Some(Sample::Voltage { decivolts: 259 }));
        assert_eq!(Sample::of(&Message::VersionRequest), None);
        assert_eq!(Sample::of(&Message::LightState(Lights::default())), None);
    }
}
