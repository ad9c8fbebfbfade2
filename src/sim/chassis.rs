//! The chassis model: modes, commands, faults, physics on a 1 ms grid, and the feedback it sends.

use std::time::Duration;

use super::battery::{to_decivolts, Battery, EMPTY_EVENT_V, LOW_EVENT_V, WARNING_EVENT_V};
use super::drive::{Drive, Thermal};
use super::faults::{ClearRequest, FaultKind, Latches, ScheduledFault, OTHER_HOST_HOLD};
use super::feedback::Ticker;
use super::noise::Noise;
use super::{ControlMode, MotionBlock, MotorSnapshot, RcSwitch, SimConfig, SimState, SimWire};
use crate::protocol::message::*;

/// The physics grid. Commands act from the last whole millisecond, scheduled faults from the next one.
const TICK_US: u64 = 1_000;
const DT: f64 = TICK_US as f64 / 1e6;
/// Feedback periods (TRACER manual, CN12 table 3.1 and the RS232 command table).
const FAST_PERIOD_US: u64 = 20_000;
const SLOW_PERIOD_US: u64 = 100_000;
/// Gaps this long at rest are computed in one go, so a huge jump in time cannot hang the caller.
const FAST_FORWARD_MIN_TICKS: u64 = 10_000;

/// Driver limits of the manual's V1/serial fault table: warnings at 55 °C / 15 A, protections at
/// 65 °C / 20 A.
pub(super) const OVERHEAT_WARNING_C: f64 = 55.0;
pub(super) const OVERHEAT_PROTECTION_C: f64 = 65.0;
pub(super) const OVERCURRENT_WARNING_A: f64 = 15.0;
pub(super) const OVERCURRENT_PROTECTION_A: f64 = 20.0;
/// Temperature an injected overheat sets.
pub(super) const OVERHEAT_EVENT_C: f64 = 70.0;

/// System-state fault bits, V2 (0x211 byte 4 = high byte); cross-checked with `protocol::faults`.
pub(super) const V2_BATTERY_FAULT: u16 = 0x0100;
pub(super) const V2_BATTERY_WARNING: u16 = 0x0200;
pub(super) const V2_RC_DISCONNECTED: u16 = 0x0400;
/// System-state fault bits, V1/serial layout.
pub(super) const SERIAL_DRIVER_OVERHEAT_WARNING: u16 = 0x0200;
pub(super) const SERIAL_OVERCURRENT_WARNING: u16 = 0x0400;
pub(super) const SERIAL_BATTERY_WARNING: u16 = 0x0800;
pub(super) const SERIAL_BATTERY_FAULT: u16 = 0x0001;
pub(super) const SERIAL_MOTOR_COMM: [u16; 2] = [0x0004, 0x0008];
pub(super) const SERIAL_OVERHEAT_PROTECTION: u16 = 0x0040;
pub(super) const SERIAL_OVERCURRENT_PROTECTION: u16 = 0x0080;
/// 0x261/0x262 driver-state bits: 0x10 is the TRACER manual's; the others follow the SDK masks.
pub(super) const DRIVER_OVERCURRENT: u8 = 0x04;
pub(super) const DRIVER_OVERHEAT: u8 = 0x08;
pub(super) const DRIVER_CAN_DISCONNECTED: u8 = 0x10;
pub(super) const DRIVER_DISABLED: u8 = 0x40;

/// What the virtual robot answers to a version request: 1.0 everywhere.
pub(super) const SIM_VERSION: VersionResponse =
    VersionResponse { controller_hw: 0x0100, driver_hw: 0x0100, controller_sw: 0x0100, driver_sw: 0x0100 };

/// The virtual TRACER. Pure and deterministic: every method takes the time since the start.
#[derive(Clone, Debug)]
pub struct Chassis {
    config: SimConfig,
    /// Physics time in whole milliseconds.
    tick: u64,
    /// The latest time any call has given.
    latest: Duration,
    drive: Drive,
    thermal: [Thermal; 2],
    battery: Battery,
    latches: [Latches; 2],
    estop: bool,
    /// The mode the host chose: standby, CAN or serial (RC override is on top, see `control_mode`).
    host_mode: ControlMode,
    rc_present: bool,
    rc_swb: RcSwitch,
    rc_lost: bool,
    /// After `other-host`: until then this link cannot select its command mode.
    other_host_until: Option<Duration>,
    /// The last accepted motion command (limited), and when it came.
    commanded: (f64, f64),
    command_at: Option<Duration>,
    /// Lights set by the host; `None` = the firmware's default.
    host_lights: Option<Lights>,
    schedule: Vec<ScheduledFault>,
    next_event: usize,
    fast: Ticker,
    slow: Ticker,
    system_count: u8,
    light_count: u8,
    motion_count: u8,
    motor_counts: [u8; 2],
    version_requested: bool,
    accepted: u64,
    ignored: u64,
    /// Noise on reported values (none by default).
    noise: Noise,
}

impl Chassis {
    /// A robot just switched on, in standby. Invalid settings fall back to their defaults (see
    /// `SimConfig::validate` to report them instead); faults scheduled at 0 are already active.
    pub fn new(config: SimConfig) -> Self {
        let config = config.sanitized();
        let mut schedule = config.faults.clone();
        schedule.sort_by_key(|fault| fault.at);
        let mut chassis = Self {
            tick: 0,
            latest: Duration::ZERO,
            drive: Drive::new(&config, DT),
            thermal: [Thermal::new(&config, DT), Thermal::new(&config, DT)],
            battery: Battery::new(&config),
            latches: [Latches::default(); 2],
            estop: false,
            host_mode: ControlMode::Standby,
            rc_present: config.rc_present,
            rc_swb: config.rc_swb,
            rc_lost: false,
            other_host_until: None,
            commanded: (0.0, 0.0),
            command_at: None,
            host_lights: None,
            schedule,
            next_event: 0,
            fast: Ticker::new(FAST_PERIOD_US),
            slow: Ticker::new(SLOW_PERIOD_US),
            system_count: 0,
            light_count: 0,
            motion_count: 0,
            motor_counts: [0; 2],
            version_requested: false,
            accepted: 0,
            ignored: 0,
            noise: Noise::new(config.noise, config.seed),
            config,
        };
        chassis.apply_due_events();
        chassis
    }

    /// The configuration in use (after `SimConfig::sanitized`).
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// A message from the host (already decoded by the transport), received at `now`. Messages of the
    /// other link, feedback messages and invalid values are ignored (and counted).
    pub fn receive(&mut self, now: Duration, message: &Message) {
        self.step(now);
        let obeyed = match (self.config.wire, *message) {
            (SimWire::CanV2, Message::MotionCommand(cmd)) => self.motion(cmd.linear(), cmd.angular()),
            (SimWire::CanV2, Message::ControlModeCommand(mode)) => self.set_mode(mode),
            (SimWire::CanV2, Message::FaultClear(code)) => match ClearRequest::from_can(code) {
                Some(request) => {
                    self.clear(request);
                    true
                }
                None => false,
            },
            (SimWire::CanV2, Message::VersionRequest) => {
                self.version_requested = true;
                true
            }
            (SimWire::Serial, Message::PercentMotionCommand(cmd)) => self.serial_motion(&cmd),
            (_, Message::LightCommand(lights)) => self.set_lights(lights),
            _ => false,
        };
        if obeyed {
            self.accepted += 1;
        } else {
            self.ignored += 1;
        }
    }

    /// Advances the physics to `now` (to its last whole millisecond). Any step pattern gives the same
    /// state; a time earlier than the last one is ignored.
    pub fn step(&mut self, now: Duration) {
        self.latest = self.latest.max(now);
        let goal = micros(now) / TICK_US;
        while self.tick < goal {
            let rest_until = goal.min(self.next_event_tick());
            if rest_until - self.tick >= FAST_FORWARD_MIN_TICKS && self.at_rest() {
                self.rest_for(rest_until - self.tick);
            } else {
                self.tick_once();
            }
        }
    }

    /// Appends the feedback due at `now` (stepping the physics there first): per 20 ms slot, CAN V2
    /// 0x211, 0x221, 0x231, 0x251, 0x252, 0x311, plus 0x261, 0x262 per 100 ms slot; RS232 system, motion,
    /// motor 1, motor 2 and light status per 20 ms slot. A version response follows a version request.
    pub fn due_feedback(&mut self, now: Duration, out: &mut Vec<Message>) {
        self.step(now);
        let now_us = micros(now);
        if std::mem::take(&mut self.version_requested) {
            out.push(Message::VersionResponse(SIM_VERSION));
        }
        if self.fast.due(now_us) {
            match self.config.wire {
                SimWire::CanV2 => self.push_can_fast(out),
                SimWire::Serial => self.push_serial(out),
            }
        }
        if self.slow.due(now_us) && self.config.wire == SimWire::CanV2 {
            for motor in 0..2 {
                out.push(Message::MotorLowSpeed(MotorLowSpeed {
                    motor: motor as u8 + 1,
                    driver_decivolts: self.reported_decivolts(),
                    driver_temperature: self.thermal[motor].celsius.round() as i16,
                    // One thermal mass per side: the motor reads what its driver reads.
                    motor_temperature: self.thermal[motor].celsius.round() as i8,
                    driver_state: self.driver_state(motor),
                }));
            }
        }
    }

    /// Injects a fault or operator action at `now` (after stepping there).
    pub fn inject(&mut self, now: Duration, fault: FaultKind) {
        self.step(now);
        self.apply(fault);
    }

    /// A read-only view of everything the model knows.
    pub fn state(&self) -> SimState {
        let (linear, angular) = self.drive.speeds();
        let (target_linear, target_angular) = self.target();
        let (odometry_left_mm, odometry_right_mm) = self.drive.odometry_mm();
        let motor = |m: usize| MotorSnapshot {
            wheel_speed: self.drive.motor_wheel_speed(m),
            rpm: self.drive.rpm(m),
            current: self.drive.current(m),
            driver_temperature: self.thermal[m].celsius,
            driver_state: self.driver_state(m),
        };
        SimState {
            time: Duration::from_millis(self.tick),
            wire: self.config.wire,
            control_mode: self.control_mode(),
            control_mode_code: self.control_mode().code(self.config.wire.into()),
            vehicle_state: self.vehicle_state(),
            motion_block: self.motion_block(),
            commanded_linear: self.commanded.0,
            commanded_angular: self.commanded.1,
            target_linear,
            target_angular,
            linear,
            angular,
            motors: [motor(0), motor(1)],
            battery_voltage: self.battery.voltage(),
            battery_current: self.battery.current(),
            state_of_charge: self.battery.state_of_charge(),
            fault_code: self.fault_code(),
            odometry_left_mm,
            odometry_right_mm,
            lights: self.lights(),
            commands_accepted: self.accepted,
            commands_ignored: self.ignored,
        }
    }

    /// (left, right) odometers in m, unrounded (for tests).
    pub fn odometry_m(&self) -> (f64, f64) {
        self.drive.odometry_m()
    }

    // ---- physics ----

    fn tick_once(&mut self) {
        self.drive.advance(self.target());
        for (motor, thermal) in self.thermal.iter_mut().enumerate() {
            thermal.advance(self.drive.current(motor));
        }
        self.battery.draw(self.config.idle_current_a + self.drive.total_motor_current(), DT);
        self.tick += 1;
        self.evaluate();
        self.apply_due_events();
    }

    /// `ticks` steps at rest in one go (only the battery and the driver temperatures change).
    fn rest_for(&mut self, ticks: u64) {
        self.drive.rest();
        for thermal in &mut self.thermal {
            thermal.cool(ticks);
        }
        self.battery.draw(self.config.idle_current_a, ticks as f64 * DT);
        self.tick += ticks;
        self.evaluate();
        self.apply_due_events();
    }

    fn at_rest(&self) -> bool {
        self.drive.at_rest() && self.target() == (0.0, 0.0)
    }

    /// Where the ramp heads: the command, unless it timed out or motion is blocked.
    fn target(&self) -> (f64, f64) {
        if self.motion_block().is_some() || self.command_expired() {
            (0.0, 0.0)
        } else {
            self.commanded
        }
    }

    /// Communication protection: no motion command for `command_timeout`.
    fn command_expired(&self) -> bool {
        match self.command_at {
            Some(at) => Duration::from_millis(self.tick) >= at.saturating_add(self.config.command_timeout),
            None => true,
        }
    }

    /// Conditions that latch or cut power, checked after every change.
    fn evaluate(&mut self) {
        for (motor, latches) in self.latches.iter_mut().enumerate() {
            latches.overheat |= self.thermal[motor].celsius >= OVERHEAT_PROTECTION_C;
            latches.overcurrent |= self.drive.current(motor) >= OVERCURRENT_PROTECTION_A;
        }
        if self.battery.levels().cut_off {
            self.drive.stop_now();
        }
    }

    fn next_event_tick(&self) -> u64 {
        self.schedule.get(self.next_event).map_or(u64::MAX, |fault| event_tick(fault.at))
    }

    /// Scheduled faults act at the first whole millisecond at or after their time.
    fn apply_due_events(&mut self) {
        while let Some(&fault) = self.schedule.get(self.next_event) {
            if event_tick(fault.at) > self.tick {
                break;
            }
            self.next_event += 1;
            self.apply(fault.fault);
        }
    }

    // ---- modes, commands and faults ----

    fn rc_override(&self) -> bool {
        self.rc_present && self.rc_swb == RcSwitch::Middle
    }

    fn control_mode(&self) -> ControlMode {
        if self.rc_override() {
            ControlMode::Rc
        } else {
            self.host_mode
        }
    }

    /// The host mode in which this link's motion commands are obeyed.
    fn command_mode(&self) -> ControlMode {
        match self.config.wire {
            SimWire::CanV2 => ControlMode::Can,
            SimWire::Serial => ControlMode::Serial,
        }
    }

    fn latched(&self) -> bool {
        self.latches.iter().any(|latches| latches.any())
    }

    fn motion_block(&self) -> Option<MotionBlock> {
        if self.estop {
            Some(MotionBlock::EStop)
        } else if self.battery.levels().cut_off {
            Some(MotionBlock::BatteryCutOff)
        } else if self.latched() {
            Some(MotionBlock::LatchedFault)
        } else if self.rc_lost {
            Some(MotionBlock::RcLost)
        } else if self.rc_override() {
            Some(MotionBlock::RcOverride)
        } else if self.host_mode != self.command_mode() {
            Some(MotionBlock::NotInCommandMode)
        } else {
            None
        }
    }

    fn vehicle_state(&self) -> u8 {
        if self.estop {
            VEHICLE_ESTOP
        } else if self.battery.levels().cut_off || self.latched() || self.rc_lost {
            VEHICLE_EXCEPTION
        } else {
            VEHICLE_NORMAL
        }
    }

    /// Obeys a motion command (m/s, rad/s) unless motion is blocked.
    fn motion(&mut self, linear: f64, angular: f64) -> bool {
        if self.motion_block().is_some() {
            return false;
        }
        self.commanded = self.drive.limit(linear, angular);
        self.command_at = Some(self.latest);
        true
    }

    /// RS232 motion control: carries a fault-clear code, and mode 0x02 both selects and keeps serial mode.
    fn serial_motion(&mut self, cmd: &PercentMotionCommand) -> bool {
        if let Some(request) = ClearRequest::from_serial(cmd.fault_clear) {
            self.clear(request);
        }
        if cmd.control_mode != ControlMode::Serial.code(Wire::Serial)
            || self.estop
            || self.rc_override()
            || self.other_host_holds()
        {
            return false;
        }
        self.host_mode = ControlMode::Serial;
        self.motion(cmd.linear(), cmd.angular())
    }

    /// 0x421. Ignored during E-stop and RC override (the transmitter has priority).
    fn set_mode(&mut self, mode: u8) -> bool {
        if self.estop || self.rc_override() || self.other_host_holds() {
            return false;
        }
        match ControlMode::from_code(Wire::CanV2, mode) {
            Some(ControlMode::Standby) => self.enter_standby(),
            Some(ControlMode::Can) => self.host_mode = ControlMode::Can,
            Some(ControlMode::Serial) => {
                self.enter_standby();
                self.host_mode = ControlMode::Serial;
            }
            Some(ControlMode::Rc) | None => return false,
        }
        true
    }

    /// Within [`OTHER_HOST_HOLD`] of `other-host`.
    fn other_host_holds(&self) -> bool {
        self.other_host_until.is_some_and(|until| self.latest < until)
    }

    fn enter_standby(&mut self) {
        self.host_mode = ControlMode::Standby;
        self.commanded = (0.0, 0.0);
        self.command_at = None;
    }

    /// Enable 0 hands the lights back to the firmware; enable 1 with a known mode is echoed (brightness
    /// clamped to 100 %). Anything else is ignored.
    fn set_lights(&mut self, lights: Lights) -> bool {
        match lights.enable {
            0 => self.host_lights = None,
            1 if lights.front_mode <= LIGHT_CUSTOM => {
                self.host_lights = Some(Lights {
                    enable: 1,
                    front_mode: lights.front_mode,
                    front_brightness: lights.front_brightness.min(BRIGHTNESS_MAX),
                    ..Lights::default()
                })
            }
            _ => return false,
        }
        true
    }

    /// The lights as reported; the firmware default is the front light constantly on.
    fn lights(&self) -> Lights {
        let lights =
            self.host_lights.unwrap_or(Lights { enable: 0, front_mode: LIGHT_ON, ..Lights::default() });
        Lights { count: self.light_count, ..lights }
    }

    /// Clears the requested latches whose cause has gone (a driver still at 65 °C stays latched).
    fn clear(&mut self, request: ClearRequest) {
        for motor in 0..2 {
            if !request.motors[motor] {
                continue;
            }
            let latches = &mut self.latches[motor];
            if request.overheat && self.thermal[motor].celsius < OVERHEAT_PROTECTION_C {
                latches.overheat = false;
            }
            if request.overcurrent && self.drive.current(motor) < OVERCURRENT_PROTECTION_A {
                latches.overcurrent = false;
            }
            if request.comm {
                latches.comm = false;
            }
        }
    }

    fn apply(&mut self, fault: FaultKind) {
        match fault {
            FaultKind::EStop => {
                self.estop = true;
                self.drive.stop_now();
                // A real robot needs 0x421 again after an E-stop: it comes back in standby.
                self.enter_standby();
            }
            FaultKind::EStopRelease => self.estop = false,
            FaultKind::Motor1Overheat => self.overheat(0),
            FaultKind::Motor2Overheat => self.overheat(1),
            FaultKind::Overcurrent => self.latches.iter_mut().for_each(|latches| latches.overcurrent = true),
            FaultKind::Motor1Overcurrent => self.latches[0].overcurrent = true,
            FaultKind::Motor2Overcurrent => self.latches[1].overcurrent = true,
            FaultKind::Motor1Comm => self.latches[0].comm = true,
            FaultKind::Motor2Comm => self.latches[1].comm = true,
            FaultKind::BatteryWarning => self.battery.set_open_circuit_voltage(WARNING_EVENT_V),
            FaultKind::BatteryLow => self.battery.set_open_circuit_voltage(LOW_EVENT_V),
            FaultKind::BatteryEmpty => self.battery.set_open_circuit_voltage(EMPTY_EVENT_V),
            FaultKind::BatteryOk => self.battery.set_open_circuit_voltage(self.config.battery_start_v),
            FaultKind::RcLost => self.rc_lost = true,
            FaultKind::RcRestore => self.rc_lost = false,
            FaultKind::SwbMiddle => self.set_rc_switch(RcSwitch::Middle),
            FaultKind::SwbTop => self.set_rc_switch(RcSwitch::Top),
            FaultKind::OtherHost => {
                self.enter_standby();
                self.host_mode = match self.config.wire {
                    SimWire::CanV2 => ControlMode::Serial,
                    SimWire::Serial => ControlMode::Can,
                };
                self.other_host_until = Some(Duration::from_millis(self.tick) + OTHER_HOST_HOLD);
            }
        }
        self.evaluate();
    }

    fn overheat(&mut self, motor: usize) {
        let thermal = &mut self.thermal[motor];
        thermal.celsius = thermal.celsius.max(OVERHEAT_EVENT_C);
    }

    /// Moving SWB implies the transmitter is on. Entering RC override drops the host's mode, as the
    /// robot reports RC and wants 0x421 again afterwards.
    fn set_rc_switch(&mut self, swb: RcSwitch) {
        let was_override = self.rc_override();
        self.rc_present = true;
        self.rc_swb = swb;
        if self.rc_override() && !was_override {
            self.enter_standby();
        }
    }

    // ---- reported values ----

    fn fault_code(&self) -> u16 {
        let levels = self.battery.levels();
        let bit = |condition: bool, mask: u16| if condition { mask } else { 0 };
        match self.config.wire {
            SimWire::CanV2 => {
                bit(levels.fault, V2_BATTERY_FAULT)
                    | bit(levels.warning, V2_BATTERY_WARNING)
                    | bit(self.rc_lost, V2_RC_DISCONNECTED)
            }
            SimWire::Serial => {
                let hot = self.thermal.iter().any(|t| t.celsius >= OVERHEAT_WARNING_C);
                let high_current = (0..2).any(|m| self.drive.current(m) >= OVERCURRENT_WARNING_A);
                let mut code = bit(hot, SERIAL_DRIVER_OVERHEAT_WARNING)
                    | bit(high_current, SERIAL_OVERCURRENT_WARNING)
                    | bit(levels.warning, SERIAL_BATTERY_WARNING)
                    | bit(levels.fault, SERIAL_BATTERY_FAULT);
                for (motor, latches) in self.latches.iter().enumerate() {
                    code |= bit(latches.comm, SERIAL_MOTOR_COMM[motor])
                        | bit(latches.overheat, SERIAL_OVERHEAT_PROTECTION)
                        | bit(latches.overcurrent, SERIAL_OVERCURRENT_PROTECTION);
                }
                code
            }
        }
    }

    fn driver_state(&self, motor: usize) -> u8 {
        let latches = self.latches[motor];
        let bit = |condition: bool, mask: u8| if condition { mask } else { 0 };
        let disabled =
            self.estop || self.battery.levels().cut_off || self.control_mode() == ControlMode::Standby;
        bit(latches.comm, DRIVER_CAN_DISCONNECTED)
            | bit(latches.overheat || self.thermal[motor].celsius >= OVERHEAT_WARNING_C, DRIVER_OVERHEAT)
            | bit(
                latches.overcurrent || self.drive.current(motor) >= OVERCURRENT_WARNING_A,
                DRIVER_OVERCURRENT,
            )
            | bit(disabled, DRIVER_DISABLED)
    }

    fn system_state(&mut self) -> SystemState {
        let state = SystemState {
            vehicle_state: self.vehicle_state(),
            control_mode: self.control_mode().code(self.config.wire.into()),
            battery_decivolts: self.reported_decivolts(),
            fault_code: self.fault_code(),
            count: self.system_count,
        };
        self.system_count = self.system_count.wrapping_add(1);
        state
    }

    /// The actual body speeds, with the noise (1 mm/s and 1 mrad/s resolution).
    fn motion_state(&mut self, count: u8) -> MotionState {
        let (linear, angular) = self.drive.speeds();
        let linear = self.noise.add(linear, 0.001);
        let angular = self.noise.add(angular, 0.001);
        MotionState { linear_mm_s: milli_i16(linear), angular_mrad_s: milli_i16(angular), count }
    }

    /// The battery voltage as reported, with the noise (0.1 V resolution); the levels judge it without.
    fn reported_decivolts(&mut self) -> u16 {
        to_decivolts(self.noise.add(self.battery.voltage(), 0.1))
    }

    /// A motor's RPM as reported, with the noise (1 RPM resolution).
    fn reported_rpm(&mut self, motor: usize) -> i16 {
        self.noise.add(self.drive.rpm(motor), 1.0).round() as i16
    }

    /// A motor's current as reported, 0.1 A, with the noise while it draws current (a motor at rest
    /// reads 0); never negative.
    fn reported_deciamps(&mut self, motor: usize) -> f64 {
        let current = self.drive.current(motor);
        let current = if current > 0.0 { self.noise.add(current, 0.1).max(0.0) } else { current };
        (current * 10.0).round()
    }

    fn next_lights(&mut self) -> Lights {
        let lights = self.lights();
        self.light_count = self.light_count.wrapping_add(1);
        lights
    }

    fn push_can_fast(&mut self, out: &mut Vec<Message>) {
        out.push(Message::SystemState(self.system_state()));
        out.push(Message::MotionState(self.motion_state(0)));
        out.push(Message::LightState(self.next_lights()));
        for motor in 0..2 {
            out.push(Message::MotorHighSpeed(MotorHighSpeed {
                motor: motor as u8 + 1,
                rpm: self.reported_rpm(motor),
                current_deciamps: self.reported_deciamps(motor) as i16,
                pulse_count: 0,
            }));
        }
        let (left_mm, right_mm) = self.drive.odometry_mm();
        out.push(Message::Odometry(Odometry { left_mm, right_mm }));
    }

    /// RS232 counts follow what `SerialEncoder` assigns as frame ids: one counter per feedback kind.
    fn push_serial(&mut self, out: &mut Vec<Message>) {
        out.push(Message::SystemState(self.system_state()));
        out.push(Message::MotionState(self.motion_state(self.motion_count)));
        self.motion_count = self.motion_count.wrapping_add(1);
        for motor in 0..2 {
            out.push(Message::MotorDriverState(MotorDriverState {
                motor: motor as u8 + 1,
                current_deciamps: self.reported_deciamps(motor) as u16,
                rpm: self.reported_rpm(motor),
                driver_temperature: self.thermal[motor].celsius.round() as i8,
                count: self.motor_counts[motor],
            }));
            self.motor_counts[motor] = self.motor_counts[motor].wrapping_add(1);
        }
        out.push(Message::LightState(self.next_lights()));
    }
}

/// Microseconds since the start, saturating (585,000 years).
fn micros(time: Duration) -> u64 {
    u64::try_from(time.as_micros()).unwrap_or(u64::MAX)
}

fn event_tick(at: Duration) -> u64 {
    micros(at).div_ceil(TICK_US)
}

/// m/s -> mm/s (rad/s -> mrad/s), rounded; `as` saturates at the i16 range.
fn milli_i16(value: f64) -> i16 {
    (value * 1000.0).round() as i16
}
