//! What the dashboard shows, folded in from the session's status and the sender's stats.
//!
//! Pure: no clock and no I/O. Every time comes in as an `Instant` (the snapshot's `now`, a message's `at`),
//! so tests drive it with fixed instants. Everything the screen shows is kept in [`Shown`], already rounded
//! to the resolution it is printed at, so that [`App::fingerprint`] changes exactly when the picture does
//! (a count byte going up, or 49 fps becoming 50 fps inside one rate window, does not redraw).
//!
//! Inputs beyond the snapshot: none. Per-identifier frame rates and stale identifiers come from
//! `RobotStatus::id_counts` (cumulative frames per CAN ID / RS232 frame id), compared between updates.

use std::collections::{BTreeMap, VecDeque};
use std::hash::{DefaultHasher, Hash, Hasher};
use std::time::{Duration, Instant};

use super::message::Message;
use super::teleop::Key;
use crate::control::{Limits, SenderStats};
use crate::protocol::catalog;
use crate::protocol::constants::{BATTERY_CUTOFF_DV, BATTERY_FAULT_DV, BATTERY_WARNING_DV};
use crate::protocol::detect::Verdict;
use crate::protocol::faults::{FlagInfo, Severity};
use crate::protocol::message::{Odometry, SystemState};
use crate::protocol::pose::DeadReckoning;
use crate::protocol::{ControlMode, FrameId, Wire};
use crate::recorder::RecordLoss;
use crate::session::RobotStatus;

pub use crate::protocol::constants::TRACK_M;
/// Battery samples kept for the sparkline, one per [`BATTERY_SAMPLE`].
pub const BATTERY_HISTORY: usize = 120;
pub const BATTERY_SAMPLE: Duration = Duration::from_secs(1);
/// Top of the gauge's scale, 0.1 V (a display scale from the cut-off up, not a state of charge).
pub const BATTERY_GAUGE_TOP_DV: u16 = 265;
/// Per-identifier rates are counted over windows this long (so they change at most once a second).
pub const RATE_WINDOW: Duration = Duration::from_secs(1);
/// The system state (0x211) is stale when older than this (the robot sends one every 20 ms).
pub const STATUS_STALE: Duration = Duration::from_millis(100);
/// How long a one-line message stays on screen.
pub const MESSAGE_TTL: Duration = Duration::from_secs(10);

/// What the terminal glue hands over at each update.
pub struct Snapshot<'a> {
    pub status: &'a RobotStatus,
    pub sender: SenderStats,
    pub link_name: &'a str,
    pub now: Instant,
}

/// Teleop display values, set by the glue each loop.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TeleopView {
    /// How key releases are detected, or why nothing drives.
    pub release_mode: ReleaseView,
    /// Fraction of the caps the arrow keys ask for (shown as a percentage).
    pub scale: f64,
    /// The drive keys held.
    pub held: Vec<Key>,
    /// m/s and rad/s, after the scale and the caps.
    pub requested: (f64, f64),
}

/// How the keys are read, as the footer says it; in milliseconds, the resolution shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ReleaseView {
    /// Not set by the glue yet.
    #[default]
    Unset,
    /// Nothing drives (watch-only), and why.
    DrivingOff(&'static str),
    /// The terminal reports key releases (kitty protocol).
    Events,
    /// A key counts as released when no repeat arrives in time: the learned repeat delay and interval
    /// (`None`: not learned yet), the timeout, and whether `--key-timeout` set it.
    Deadline { delay_ms: Option<u128>, interval_ms: Option<u128>, timeout_ms: u128, from_flag: bool },
}

/// A question on screen that takes the next key.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Prompt {
    #[default]
    None,
    /// "Clear faults? y / any other key cancels".
    ConfirmClear,
    /// "Arm driving? y / any other key keeps watching".
    ConfirmArm,
}

/// Whether the dashboard may send: it opens watching and sends nothing until the operator arms it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Arming {
    /// Nothing is sent; a drive key asks to arm.
    #[default]
    Watching,
    /// Nothing is sent, and arming is not possible (--watch, a replay).
    WatchOnly,
    /// Command mode requested and motion commands sent at 50 Hz.
    Armed,
}

/// Where the battery voltage stands against the manual's thresholds (each applies at or below).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BatteryZone {
    Ok,
    /// At or below the warning voltage ([`BATTERY_WARNING_DV`] unless configured).
    Warning,
    /// At or below [`BATTERY_FAULT_DV`] (still drives; the robot beeps).
    Fault,
    /// At or below [`BATTERY_CUTOFF_DV`]: drive power is cut.
    CutOff,
}

impl BatteryZone {
    pub fn of(decivolts: u16, warning_dv: u16) -> Self {
        match decivolts {
            v if v <= BATTERY_CUTOFF_DV => BatteryZone::CutOff,
            v if v <= BATTERY_FAULT_DV => BatteryZone::Fault,
            v if v <= warning_dv => BatteryZone::Warning,
            _ => BatteryZone::Ok,
        }
    }

    pub fn severity(self) -> Option<Severity> {
        match self {
            BatteryZone::Ok => None,
            BatteryZone::Warning => Some(Severity::Warning),
            BatteryZone::Fault | BatteryZone::CutOff => Some(Severity::Fault),
        }
    }
}

/// The protocol the traffic showed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Protocol {
    #[default]
    Unknown,
    CanV1,
    CanV2,
    /// Both V1-only and V2-only identifiers seen.
    Mixed,
    Serial,
}

impl Protocol {
    /// The wire this protocol is, when it is one.
    pub fn wire(self) -> Option<Wire> {
        match self {
            Protocol::CanV1 => Some(Wire::CanV1),
            Protocol::CanV2 => Some(Wire::CanV2),
            Protocol::Serial => Some(Wire::Serial),
            Protocol::Unknown | Protocol::Mixed => None,
        }
    }

    pub fn label(self) -> &'static str {
        match self {
            Protocol::Unknown => "protocol ?",
            Protocol::CanV1 => "CAN V1",
            Protocol::CanV2 => "CAN V2",
            Protocol::Mixed => "CAN V1+V2 mixed",
            Protocol::Serial => "RS232",
        }
    }
}

/// How old the latest system state is, at the resolution shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StatusAge {
    /// No system state yet.
    #[default]
    Never,
    /// No older than [`STATUS_STALE`].
    Fresh,
    /// Older, in tenths of a second.
    Stale { deciseconds: u64 },
}

/// The system state fields shown (not its count byte, which changes with every frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SystemView {
    pub vehicle_state: u8,
    pub control_mode: u8,
    pub decivolts: u16,
    pub fault_code: u16,
    pub wire: Wire,
}

impl SystemView {
    pub fn state(&self) -> SystemState {
        SystemState {
            vehicle_state: self.vehicle_state,
            control_mode: self.control_mode,
            battery_decivolts: self.decivolts,
            fault_code: self.fault_code,
            count: 0,
        }
    }

    /// Whether the robot is in the command mode of its wire (the one this link drives in).
    pub fn in_command_mode(&self) -> bool {
        ControlMode::from_code(self.wire, self.control_mode) == Some(ControlMode::command_mode_of(self.wire))
    }
}

/// One motor's row. Fields come from 0x251/0x252 and 0x261/0x262 on V2, the motor driver frames on V1 and
/// RS232; `None` when nothing reported them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct MotorView {
    pub rpm: Option<i16>,
    /// 0.1 A.
    pub current_deciamps: Option<i32>,
    /// °C.
    pub driver_temperature: Option<i16>,
    /// °C; -40 means no sensor.
    pub motor_temperature: Option<i8>,
    /// 0x261/0x262 byte 5 (V2 only).
    pub driver_state: Option<u8>,
}

/// The dead-reckoned pose, at the resolution shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PoseView {
    pub x_cm: i64,
    pub y_cm: i64,
    /// -1800..1800, tenths of a degree, counter-clockwise positive.
    pub heading_decideg: i64,
}

/// One identifier of the link-health table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct IdView {
    pub id: FrameId,
    /// Frames per second over the last full window; `None` before the first window ends.
    pub fps: Option<u32>,
    /// For a known feedback message not seen for too long: for how long, in tenths of a second.
    pub stale_deciseconds: Option<u64>,
}

/// Receive and send counters shown.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Counters {
    pub error_frames: u64,
    pub socket_drops: u64,
    pub serial_bad_checksum: u64,
    pub serial_skipped_bytes: u64,
    pub send_errors: u64,
    pub watchdog_trips: u64,
}

/// A set fault or status bit, with where it came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FaultLine {
    /// `None` for the system state, `Some(1 | 2)` for a motor driver's state byte.
    pub motor: Option<u8>,
    pub info: FlagInfo,
}

/// Everything the screen shows from the robot and the sender, rounded as printed.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Shown {
    pub link_name: String,
    pub protocol: Protocol,
    pub system: Option<SystemView>,
    pub status_age: StatusAge,
    /// Any frame at all received.
    pub received_any: bool,
    pub link_error: Option<String>,
    /// The source ended on its own (a replay's last frame): not a failure; the last values stay shown.
    pub link_ended: bool,
    /// Battery voltage, 0.1 V, oldest first; one sample per second of fresh status.
    pub battery_history: VecDeque<u16>,
    /// Reported by the robot (0x221): mm/s, mrad/s.
    pub measured: Option<(i16, i16)>,
    /// The last motion command sent: mm/s, mrad/s.
    pub sent: (i16, i16),
    /// enable, front mode, front brightness.
    pub lights: Option<(u8, u8, u8)>,
    pub motors: [MotorView; 2],
    /// Wheel odometers as reported (since the robot powered on), mm.
    pub odometer_mm: Option<(i32, i32)>,
    /// Distance driven since the dashboard started, cm.
    pub trip_cm: u64,
    pub pose: Option<PoseView>,
    pub counters: Counters,
    /// All received frames per second (last full window).
    pub total_fps: Option<u32>,
    pub ids: Vec<IdView>,
    /// The live analysis' dead time and battery estimate, once measured.
    pub health: super::health::HealthView,
}

/// Pose from odometer deltas ([`DeadReckoning`]), timed by the clock of the updates.
#[derive(Clone, Copy, Debug, Default)]
struct Odometer {
    pose: DeadReckoning,
    at: Option<Instant>,
}

impl Odometer {
    fn step(&mut self, odometry: Odometry, now: Instant) {
        let elapsed = self.at.replace(now).map_or(0.0, |at| now.saturating_duration_since(at).as_secs_f64());
        self.pose.step(odometry, elapsed);
    }

    fn view(&self) -> Option<PoseView> {
        let pose = &self.pose;
        pose.started().then(|| PoseView {
            x_cm: (pose.x * 100.0).round() as i64,
            y_cm: (pose.y * 100.0).round() as i64,
            heading_decideg: (pose.heading.to_degrees() * 10.0).round() as i64,
        })
    }
}

/// Frame rates per identifier from cumulative counts, and when each count last went up.
#[derive(Clone, Debug, Default)]
struct Rates {
    /// Start of the current window: when, total frames, counts per ID.
    window: Option<(Instant, u64, BTreeMap<FrameId, u64>)>,
    fps: BTreeMap<FrameId, u32>,
    total_fps: Option<u32>,
    /// Per ID: the last count seen and the update at which it last went up.
    last_rise: BTreeMap<FrameId, (u64, Instant)>,
}

impl Rates {
    fn update(&mut self, counts: &[(FrameId, u64)], frames: u64, now: Instant) {
        for &(id, count) in counts {
            let entry = self.last_rise.entry(id).or_insert((count, now));
            if count > entry.0 {
                *entry = (count, now);
            }
        }
        let current: BTreeMap<FrameId, u64> = counts.iter().copied().collect();
        match &self.window {
            None => self.window = Some((now, frames, current)),
            Some((start, start_frames, start_counts)) => {
                let elapsed = now.saturating_duration_since(*start);
                if elapsed >= RATE_WINDOW {
                    let seconds = elapsed.as_secs_f64();
                    let rate = |delta: u64| (delta as f64 / seconds).round() as u32;
                    self.fps = current
                        .iter()
                        .map(|(id, count)| {
                            (*id, rate(count.saturating_sub(start_counts.get(id).copied().unwrap_or(0))))
                        })
                        .collect();
                    self.total_fps = Some(rate(frames.saturating_sub(*start_frames)));
                    self.window = Some((now, frames, current));
                }
            }
        }
    }

    fn views(&self, now: Instant) -> Vec<IdView> {
        self.last_rise
            .iter()
            .map(|(&id, &(_, rose))| {
                let silent = now.saturating_duration_since(rose);
                let stale = stale_after(id).filter(|limit| silent > *limit);
                IdView {
                    id,
                    fps: self.fps.get(&id).copied(),
                    stale_deciseconds: stale.map(|_| deciseconds(silent)),
                }
            })
            .collect()
    }
}

/// How often the robot sends a feedback identifier, for the ones whose period is known.
pub fn feedback_period(id: FrameId) -> Option<Duration> {
    catalog::periodic_frame(id).and_then(|entry| entry.period)
}

/// How long a feedback identifier may be silent before it is stale (the catalog's limit, never under
/// [`STATUS_STALE`]); `None` for identifiers that are not periodic robot feedback (commands from another
/// host, other devices, version replies).
pub fn stale_after(id: FrameId) -> Option<Duration> {
    catalog::periodic_frame(id).and_then(|entry| entry.stale_after()).map(|limit| limit.max(STATUS_STALE))
}

/// What an identifier carries, for the link-health table: the catalog's label.
pub fn id_name(id: FrameId) -> &'static str {
    catalog::label(id).unwrap_or("")
}

fn deciseconds(duration: Duration) -> u64 {
    (duration.as_millis() / 100) as u64
}

/// The dashboard's state.
pub struct App {
    pub(super) limits: Limits,
    pub(super) color: bool,
    pub(super) shown: Shown,
    pub(super) teleop: TeleopView,
    pub(super) help: bool,
    pub(super) prompt: Prompt,
    pub(super) arming: Arming,
    pub(super) message: Option<(Message, Instant)>,
    /// Frames the `--record` recording lost, and why: shown until the end.
    pub(super) recording_loss: Option<RecordLoss>,
    battery_sampled: Option<Instant>,
    odometry: Odometer,
    rates: Rates,
    /// When the source was first seen ended: the robot's values are aged up to then, never beyond.
    ended_at: Option<Instant>,
    /// The warning voltage, decivolts: the manual's, or the configuration's `battery.warning_volts`.
    pub(super) battery_warning_dv: u16,
}

impl App {
    pub fn new(link_name: &str, limits: Limits, color: bool) -> Self {
        Self {
            limits,
            color,
            shown: Shown { link_name: link_name.to_string(), ..Shown::default() },
            teleop: TeleopView::default(),
            help: false,
            prompt: Prompt::None,
            arming: Arming::Watching,
            message: None,
            recording_loss: None,
            battery_sampled: None,
            odometry: Odometer::default(),
            rates: Rates::default(),
            ended_at: None,
            battery_warning_dv: BATTERY_WARNING_DV,
        }
    }

    /// The live analysis' figures (the glue refreshes them about once a second).
    pub fn set_health(&mut self, health: super::health::HealthView) {
        self.shown.health = health;
    }

    /// The battery's warning voltage (`battery.warning_volts` of the configuration file).
    pub fn set_battery_warning(&mut self, volts: f64) {
        self.battery_warning_dv = crate::protocol::constants::decivolts(volts);
    }

    /// Folds in the latest status (called about every 50 ms): battery history (one sample a second of fresh
    /// status, at most [`BATTERY_HISTORY`]), per-ID frame rates and stale IDs from `status.id_counts`, trip
    /// distance and dead-reckoned pose from odometer deltas, the age of the latest system state, and the
    /// expiry of the one-line message.
    pub fn update(&mut self, snapshot: &Snapshot) {
        let status = snapshot.status;
        let clock = snapshot.now;
        // After a replay's end its last values stay as they were: no stale alarms, no rates decaying.
        let now = if status.link_ended { *self.ended_at.get_or_insert(clock) } else { clock };
        let snapshot = &Snapshot { status, sender: snapshot.sender, link_name: snapshot.link_name, now };
        self.update_system(snapshot);
        self.sample_battery(status, now);
        let shown = &mut self.shown;
        shown.measured = status.motion.map(|(_, motion)| (motion.linear_mm_s, motion.angular_mrad_s));
        shown.sent = (snapshot.sender.sent.linear_mm_s, snapshot.sender.sent.angular_mrad_s);
        shown.lights =
            status.lights.map(|(_, lights)| (lights.enable, lights.front_mode, lights.front_brightness));
        self.update_motors(status);
        self.update_odometry(status, now);
        self.update_link(snapshot);
        if self.message.as_ref().is_some_and(|(_, at)| clock.saturating_duration_since(*at) >= MESSAGE_TTL) {
            self.message = None;
        }
    }

    /// The link's name, the latest system state and its age, and the protocol in use.
    fn update_system(&mut self, snapshot: &Snapshot) {
        let status = snapshot.status;
        let shown = &mut self.shown;
        shown.link_name.clear();
        shown.link_name.push_str(snapshot.link_name);
        shown.received_any = status.frames > 0;
        shown.link_error.clone_from(&status.link_error);
        shown.link_ended = status.link_ended;
        let system_age = status.system.map(|(at, ..)| snapshot.now.saturating_duration_since(at));
        shown.system = status.system.map(|(_, state, wire)| SystemView {
            vehicle_state: state.vehicle_state,
            control_mode: state.control_mode,
            decivolts: state.battery_decivolts,
            fault_code: state.fault_code,
            wire,
        });
        shown.status_age = match system_age {
            None => StatusAge::Never,
            Some(age) if age <= STATUS_STALE => StatusAge::Fresh,
            Some(age) => StatusAge::Stale { deciseconds: deciseconds(age) },
        };
        shown.protocol = match (status.system, status.detector.verdict()) {
            (Some((_, _, Wire::Serial)), _) => Protocol::Serial,
            (_, Verdict::V1) => Protocol::CanV1,
            (_, Verdict::V2) => Protocol::CanV2,
            (_, Verdict::Mixed) => Protocol::Mixed,
            (_, Verdict::Unknown) => Protocol::Unknown,
        };
    }

    /// Battery history: a sample a second, only of a status that is still coming in.
    fn sample_battery(&mut self, status: &RobotStatus, now: Instant) {
        let Some((at, state, _)) = status.system else { return };
        let age = now.saturating_duration_since(at);
        let due = self.battery_sampled.is_none_or(|at| now.saturating_duration_since(at) >= BATTERY_SAMPLE);
        if !due || age > BATTERY_SAMPLE {
            return;
        }
        let history = &mut self.shown.battery_history;
        history.push_back(state.battery_decivolts);
        while history.len() > BATTERY_HISTORY {
            history.pop_front();
        }
        // Stay on a one-second grid unless updates fell behind.
        self.battery_sampled = Some(match self.battery_sampled {
            Some(at) if now.saturating_duration_since(at) < BATTERY_SAMPLE * 2 => at + BATTERY_SAMPLE,
            _ => now,
        });
    }

    /// Trip distance and dead-reckoned pose from odometer deltas.
    fn update_odometry(&mut self, status: &RobotStatus, now: Instant) {
        if let Some(odometry) = status.odometry {
            self.odometry.step(odometry, now);
        }
        let shown = &mut self.shown;
        shown.odometer_mm = status.odometry.map(|o| (o.left_mm, o.right_mm));
        shown.trip_cm = (self.odometry.pose.trip_m * 100.0).round() as u64;
        shown.pose = self.odometry.view();
    }

    /// Each motor's speed, current, temperatures and driver state, from whichever frames the robot sends.
    fn update_motors(&mut self, status: &RobotStatus) {
        for (index, motor) in self.shown.motors.iter_mut().enumerate() {
            let high = status.motor_high[index];
            let driver = status.motor_driver[index];
            let low = status.motor_low[index];
            *motor = MotorView {
                rpm: high.map(|m| m.rpm).or(driver.map(|m| m.rpm)),
                current_deciamps: high
                    .map(|m| i32::from(m.current_deciamps))
                    .or(driver.map(|m| i32::from(m.current_deciamps))),
                driver_temperature: low
                    .map(|m| m.driver_temperature)
                    .or(driver.map(|m| i16::from(m.driver_temperature))),
                motor_temperature: low.map(|m| m.motor_temperature),
                driver_state: low.map(|m| m.driver_state),
            };
        }
    }

    /// Per-ID frame rates, stale IDs and the link's error counters.
    fn update_link(&mut self, snapshot: &Snapshot) {
        let status = snapshot.status;
        self.rates.update(&status.id_counts, status.frames, snapshot.now);
        let shown = &mut self.shown;
        shown.ids = self.rates.views(snapshot.now);
        shown.total_fps = self.rates.total_fps;
        shown.counters = Counters {
            error_frames: status.rx.error_frames,
            socket_drops: status.rx.socket_drops,
            serial_bad_checksum: status.rx.serial_bad_checksum,
            serial_skipped_bytes: status.rx.serial_skipped_bytes,
            send_errors: snapshot.sender.send_errors,
            watchdog_trips: snapshot.sender.watchdog_trips,
        };
    }

    /// Teleop display values, set by the glue each loop.
    pub fn set_teleop(&mut self, view: TeleopView) {
        self.teleop = view;
    }

    pub fn toggle_help(&mut self) {
        self.help = !self.help;
    }

    pub fn hide_help(&mut self) {
        self.help = false;
    }

    pub fn help_shown(&self) -> bool {
        self.help
    }

    pub fn set_arming(&mut self, arming: Arming) {
        self.arming = arming;
    }

    pub fn arming(&self) -> Arming {
        self.arming
    }

    pub fn ask_arm_confirmation(&mut self) {
        self.help = false;
        self.prompt = Prompt::ConfirmArm;
    }

    pub fn ask_clear_confirmation(&mut self) {
        self.help = false;
        self.prompt = Prompt::ConfirmClear;
    }

    pub fn cancel_prompt(&mut self) {
        self.prompt = Prompt::None;
    }

    pub fn prompt(&self) -> Prompt {
        self.prompt
    }

    /// One-line feedback ("lights: on"); it goes away [`MESSAGE_TTL`] after `at` (checked by `update`).
    pub fn set_message(&mut self, message: Message, at: Instant) {
        self.message = Some((message, at));
    }

    /// What the recording has lost so far (set by the glue each update).
    pub fn set_recording_loss(&mut self, loss: Option<RecordLoss>) {
        self.recording_loss = loss;
    }

    /// A hash of everything shown: the glue redraws only when it changes.
    pub fn fingerprint(&self) -> u64 {
        let mut hasher = DefaultHasher::new();
        self.shown.hash(&mut hasher);
        self.help.hash(&mut hasher);
        self.prompt.hash(&mut hasher);
        self.arming.hash(&mut hasher);
        self.message.as_ref().map(|(message, _)| message).hash(&mut hasher);
        self.recording_loss.hash(&mut hasher);
        self.color.hash(&mut hasher);
        let teleop = &self.teleop;
        teleop.release_mode.hash(&mut hasher);
        teleop.held.hash(&mut hasher);
        // At the resolution printed.
        scale_percent(teleop.scale).hash(&mut hasher);
        speed_text(teleop.requested.0).hash(&mut hasher);
        speed_text(teleop.requested.1).hash(&mut hasher);
        hasher.finish()
    }

    /// Every set fault and status bit (system state, then each motor driver's state byte), the most serious
    /// first.
    pub fn faults(&self) -> Vec<FaultLine> {
        let mut lines: Vec<FaultLine> = Vec::new();
        if let Some(system) = self.shown.system {
            lines.extend(
                system.state().faults(system.wire).iter().map(|info| FaultLine { motor: None, info }),
            );
        }
        for (index, motor) in self.shown.motors.iter().enumerate() {
            if let Some(bits) = motor.driver_state {
                let flags =
                    crate::protocol::Flags::new(crate::protocol::FlagTable::DriverState, u16::from(bits));
                lines.extend(flags.iter().map(|info| FaultLine { motor: Some(index as u8 + 1), info }));
            }
        }
        // `Severity`'s own order, the worst first (stable: bit order within a severity).
        lines.sort_by_key(|line| std::cmp::Reverse(line.info.severity));
        lines
    }

    /// How many of [`App::faults`] count as faults, the way `doctor` counts them: warnings and worse
    /// ([`Severity::is_problem`]); info lines (a driver disabled in standby) are states, listed but not counted.
    pub fn fault_count(&self) -> usize {
        self.faults().iter().filter(|line| line.info.severity.is_problem()).count()
    }

    /// The dead-reckoned pose in m, m, rad (full precision), once odometry has been seen.
    pub fn pose(&self) -> Option<(f64, f64, f64)> {
        let pose = &self.odometry.pose;
        pose.started().then_some((pose.x, pose.y, pose.heading))
    }

    /// Distance driven since the start, m.
    pub fn trip_m(&self) -> f64 {
        self.odometry.pose.trip_m
    }

    /// Everything shown from the robot and the sender.
    pub fn shown(&self) -> &Shown {
        &self.shown
    }

    /// The identifiers of known feedback messages that stopped arriving.
    pub fn stale_ids(&self) -> Vec<FrameId> {
        self.shown.ids.iter().filter(|id| id.stale_deciseconds.is_some()).map(|id| id.id).collect()
    }
}

/// A speed as printed: `+0.30`.
pub fn speed_text(value: f64) -> String {
    let value = if value.abs() < 0.005 { 0.0 } else { value };
    format!("{value:+.2}")
}

/// The speed scale as printed, percent.
pub fn scale_percent(scale: f64) -> i64 {
    if scale.is_finite() {
        (scale * 100.0).round() as i64
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::{MotionCommand, SystemState};

    fn standard(id: u16) -> FrameId {
        FrameId::Standard(id)
    }

    fn status_at(at: Instant) -> RobotStatus {
        RobotStatus {
            system: Some((
                at,
                SystemState {
                    vehicle_state: 0,
                    control_mode: 1,
                    battery_decivolts: 259,
                    fault_code: 0,
                    count: 1,
                },
                Wire::CanV2,
            )),
            frames: 1,
            ..RobotStatus::default()
        }
    }

    fn update(app: &mut App, status: &RobotStatus, now: Instant) {
        app.update(&Snapshot { status, sender: SenderStats::default(), link_name: "can0", now });
    }

    fn at(base: Instant, ms: u64) -> Instant {
        base + Duration::from_millis(ms)
    }

    fn odometry_run(steps: &[(i32, i32)]) -> App {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        let mut status = status_at(base);
        for (index, &(left_mm, right_mm)) in steps.iter().enumerate() {
            status.odometry = Some(Odometry { left_mm, right_mm });
            update(&mut app, &status, at(base, 50 * index as u64));
        }
        app
    }

    #[test]
    fn driving_straight_one_metre_moves_along_x() {
        // 1 m in 20 steps of 50 mm on both wheels, starting from arbitrary odometer readings.
        let steps: Vec<_> = (0..=20).map(|i| (5000 + 50 * i, 7000 + 50 * i)).collect();
        let app = odometry_run(&steps);
        let (x, y, heading) = app.pose().unwrap();
        assert!((x - 1.0).abs() < 1e-9, "{x}");
        assert!(y.abs() < 1e-9 && heading.abs() < 1e-9);
        assert!((app.trip_m() - 1.0).abs() < 1e-9);
        assert_eq!(app.shown().trip_cm, 100);
        assert_eq!(app.shown().pose, Some(PoseView { x_cm: 100, y_cm: 0, heading_decideg: 0 }));
        assert_eq!(app.shown().odometer_mm, Some((6000, 8000)));
    }

    #[test]
    fn turning_on_the_spot_changes_only_the_heading() {
        // Wheels 180 mm each way: (dr - dl) / track = 0.36 / 0.36 = 1 rad, counter-clockwise.
        let app = odometry_run(&[(0, 0), (-90, 90), (-180, 180)]);
        let (x, y, heading) = app.pose().unwrap();
        assert!(x.abs() < 1e-9 && y.abs() < 1e-9, "{x} {y}");
        assert!((heading - 1.0).abs() < 1e-9, "{heading}");
        assert_eq!(app.shown().pose.unwrap().heading_decideg, 573);
        assert_eq!(app.trip_m(), 0.0, "turning on the spot is no trip distance");
        // And back the other way past zero.
        let app = odometry_run(&[(0, 0), (360, -360)]);
        assert!((app.pose().unwrap().2 + 2.0).abs() < 1e-9);
    }

    #[test]
    fn a_quarter_circle_ends_where_geometry_says() {
        // Radius 1 m arc to the left: the right wheel runs (1 + 0.18) / 1 as far as the centre.
        let arc = std::f64::consts::FRAC_PI_2;
        let steps: Vec<_> = (0..=1000)
            .map(|i| {
                let s = arc * f64::from(i) / 1000.0;
                (
                    ((1.0 - TRACK_M / 2.0) * s * 1000.0).round() as i32,
                    ((1.0 + TRACK_M / 2.0) * s * 1000.0).round() as i32,
                )
            })
            .collect();
        let app = odometry_run(&steps);
        let (x, y, heading) = app.pose().unwrap();
        assert!((x - 1.0).abs() < 0.01 && (y - 1.0).abs() < 0.01, "{x} {y}");
        assert!((heading - arc).abs() < 0.01);
        assert!((app.trip_m() - arc).abs() < 0.01);
    }

    #[test]
    fn odometers_wrap_and_resets_are_skipped() {
        let app = odometry_run(&[(i32::MAX - 100, i32::MAX - 100), (i32::MIN + 99, i32::MIN + 99)]);
        assert!((app.pose().unwrap().0 - 0.2).abs() < 1e-9, "wrapped step is 200 mm");
        // A jump of 100 m in 50 ms is a reset, not driving.
        let app = odometry_run(&[(0, 0), (100_000, 100_000), (100_050, 100_050)]);
        assert!((app.pose().unwrap().0 - 0.05).abs() < 1e-9);
        assert_eq!(app.odometry.pose.jumps, 1);
    }

    #[test]
    fn rates_per_id_and_stale_ids() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        let mut status = status_at(base);
        // 0x211 at 50 Hz and 0x261 at 10 Hz for two seconds, then 0x211 stops while 0x261 goes on.
        for tick in 0..=60u64 {
            let now = at(base, tick * 50);
            let (fast, slow) = if tick <= 40 { (tick * 5 / 2, tick / 2) } else { (100, tick / 2) };
            status.id_counts = vec![(standard(0x211), fast), (standard(0x261), slow), (standard(0x111), 3)];
            status.frames = fast + slow + 3;
            if tick <= 40 {
                status.system.as_mut().unwrap().0 = now;
            }
            update(&mut app, &status, now);
            if tick == 40 {
                let ids = &app.shown().ids;
                assert_eq!(
                    ids.iter().map(|i| (i.id, i.fps)).collect::<Vec<_>>(),
                    [(standard(0x111), Some(0)), (standard(0x211), Some(50)), (standard(0x261), Some(10))]
                );
                assert_eq!(app.shown().total_fps, Some(60));
                assert!(app.stale_ids().is_empty());
                assert_eq!(app.shown().status_age, StatusAge::Fresh);
            }
        }
        // 1 s after the last 0x211 (which rose at tick 40): stale, with its age; 0x111 is not feedback.
        assert_eq!(app.stale_ids(), [standard(0x211)]);
        assert_eq!(app.shown().ids[1].stale_deciseconds, Some(10));
        assert_eq!(app.shown().status_age, StatusAge::Stale { deciseconds: 10 });
        assert_eq!(app.shown().ids[2].fps, Some(10));
    }

    #[test]
    fn battery_history_is_one_sample_a_second_and_bounded() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        let mut status = status_at(base);
        for tick in 0..(200 * 20) {
            let now = at(base, tick * 50);
            let state = &mut status.system.as_mut().unwrap();
            state.0 = now;
            state.1.battery_decivolts = 260 - (tick / 20 / 10) as u16;
            update(&mut app, &status, now);
            if tick == 20 * 10 {
                assert_eq!(app.shown().battery_history.len(), 11, "t = 0 s .. 10 s");
            }
        }
        let history = &app.shown().battery_history;
        assert_eq!(history.len(), BATTERY_HISTORY);
        assert_eq!(history.back(), Some(&241), "the newest last");
        assert_eq!(history.front(), Some(&252), "the oldest dropped");
        // A stale status adds nothing.
        let before = app.shown().battery_history.clone();
        update(&mut app, &status, at(base, 200 * 1000 + 5000));
        assert_eq!(app.shown().battery_history, before);
    }

    #[test]
    fn fingerprint_follows_what_is_shown() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        let mut status = status_at(base);
        status.id_counts = vec![(standard(0x211), 1)];
        update(&mut app, &status, base);
        let first = app.fingerprint();
        // A count byte and a few ms of age are not shown.
        status.system.as_mut().unwrap().1.count = 2;
        status.system.as_mut().unwrap().0 = at(base, 20);
        status.id_counts = vec![(standard(0x211), 2)];
        status.frames = 2;
        update(&mut app, &status, at(base, 50));
        assert_eq!(app.fingerprint(), first);
        app.set_teleop(TeleopView { requested: (0.0001, -0.0001), ..TeleopView::default() });
        assert_eq!(app.fingerprint(), first, "below the printed resolution");

        // Each of these is shown.
        let mut seen = vec![first];
        let mut changed = |app: &App, what: &str| {
            let now = app.fingerprint();
            assert!(!seen.contains(&now), "{what} did not change the fingerprint");
            seen.push(now);
        };
        status.system.as_mut().unwrap().1.battery_decivolts = 258;
        update(&mut app, &status, at(base, 60));
        changed(&app, "battery");
        status.system.as_mut().unwrap().1.fault_code = 0x0200;
        update(&mut app, &status, at(base, 70));
        changed(&app, "fault bits");
        app.set_teleop(TeleopView { scale: 0.5, ..TeleopView::default() });
        changed(&app, "scale");
        app.set_teleop(TeleopView {
            scale: 0.5,
            held: vec![Key::Up],
            requested: (0.25, 0.0),
            ..Default::default()
        });
        changed(&app, "held key");
        let sender =
            SenderStats { sent: MotionCommand { linear_mm_s: 100, angular_mrad_s: 0 }, ..Default::default() };
        app.update(&Snapshot { status: &status, sender, link_name: "can0", now: at(base, 80) });
        changed(&app, "sent command");
        app.update(&Snapshot { status: &status, sender, link_name: "can0", now: at(base, 500) });
        changed(&app, "stale status");
        app.toggle_help();
        changed(&app, "help");
        app.toggle_help();
        app.ask_clear_confirmation();
        changed(&app, "prompt");
        app.set_message(Message::Lights("on"), at(base, 500));
        changed(&app, "message");
        let before = app.fingerprint();
        app.update(&Snapshot {
            status: &status,
            sender,
            link_name: "can0",
            now: at(base, 500) + MESSAGE_TTL,
        });
        assert!(app.message.is_none(), "the message expired");
        assert_ne!(app.fingerprint(), before);
    }

    #[test]
    fn faults_list_the_worst_first_with_motor_bits() {
        let base = Instant::now();
        let mut app = App::new("ttyUSB0", Limits::default(), false);
        let mut status = status_at(base);
        status.system = Some((
            base,
            SystemState {
                vehicle_state: 2,
                control_mode: 2,
                battery_decivolts: 240,
                fault_code: 0x0240,
                count: 0,
            },
            Wire::Serial,
        ));
        status.motor_low[1] = Some(crate::protocol::message::MotorLowSpeed {
            motor: 2,
            driver_state: 0x48,
            ..Default::default()
        });
        update(&mut app, &status, base);
        let faults: Vec<_> = app.faults().iter().map(|f| (f.motor, f.info.name, f.info.severity)).collect();
        assert_eq!(
            faults,
            [
                (None, "driver_overheat_protection", Severity::Protection),
                (None, "driver_overheat_warning", Severity::Warning),
                (Some(2), "driver_overheat", Severity::Warning),
                (Some(2), "driver_disabled", Severity::Info),
            ]
        );
        assert_eq!(app.shown().protocol, Protocol::Serial);
    }

    /// `Severity`'s order: a bit no document defines comes after a fault and before a warning.
    #[test]
    fn an_undocumented_bit_is_listed_between_faults_and_warnings() {
        let base = Instant::now();
        let mut app = App::new("can0", Limits::default(), false);
        let mut status = status_at(base);
        let state =
            SystemState { control_mode: 1, battery_decivolts: 259, fault_code: 0x0380, ..Default::default() };
        status.system = Some((base, state, Wire::CanV2));
        update(&mut app, &status, base);
        let faults: Vec<_> = app.faults().iter().map(|f| (f.info.name, f.info.severity)).collect();
        assert_eq!(
            faults,
            [
                ("battery_undervoltage_fault", Severity::Fault),
                ("reserved_byte5_bit7", Severity::Unknown),
                ("battery_undervoltage_warning", Severity::Warning),
            ]
        );
    }

    #[test]
    fn battery_zones_follow_the_manual() {
        let of = |decivolts| BatteryZone::of(decivolts, BATTERY_WARNING_DV);
        assert_eq!(of(259), BatteryZone::Ok);
        assert_eq!(of(226), BatteryZone::Ok);
        assert_eq!(of(225), BatteryZone::Warning);
        assert_eq!(of(221), BatteryZone::Warning);
        assert_eq!(of(220), BatteryZone::Fault);
        assert_eq!(of(215), BatteryZone::CutOff);
        // A configured warning voltage moves only the warning zone.
        let mut app = App::new("can0", Limits::default(), false);
        app.set_battery_warning(26.0);
        assert_eq!(app.battery_warning_dv, 260);
        assert_eq!(BatteryZone::of(259, app.battery_warning_dv), BatteryZone::Warning);
        assert_eq!(BatteryZone::of(261, app.battery_warning_dv), BatteryZone::Ok);
        assert_eq!(BatteryZone::of(220, app.battery_warning_dv), BatteryZone::Fault);
    }
}
