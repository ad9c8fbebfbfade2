//! The summary as one set of values, built once at the end: what the text and the JSON report both print.
//! Each renderer only formats these values; neither computes anything of its own.

use super::{nanos, At, Extreme, IdStats, RowKey, Summary};
use crate::candump::Timestamp;
use crate::commands::decode::InputStats;
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::error_frame::ERROR_CLASSES;
use crate::protocol::faults::{FlagInfo, FlagTable};

/// The whole report: the input's totals, then one field per section.
pub(super) struct Report<'a> {
    /// Lines, frames, rejected and skipped input, RS232 stream statistics.
    pub input: &'a InputStats,
    pub interfaces: InterfaceList<'a>,
    pub protocol: String,
    pub first: Option<Timestamp>,
    pub last: Option<Timestamp>,
    /// In the table's order (see `RowKey`).
    pub ids: Vec<IdRow>,
    /// Control-mode and vehicle-state changes.
    pub events: &'a [(At, String)],
    pub events_not_listed: u64,
    pub faults: Vec<FaultRow>,
    /// `None` without system-state frames.
    pub battery: Option<BatteryRange>,
    pub wheels: [WheelRow; 2],
    pub speeds: [SpeedRow; 4],
    pub motors: [MotorRow; 2],
    /// Only the error classes seen.
    pub error_frames: Vec<ErrorClassCount>,
    /// Response and health (issue 32).
    pub health: crate::health::Report,
}

pub(super) struct InterfaceList<'a> {
    pub listed: &'a [String],
    pub not_listed: usize,
    /// More names than could be counted: `not_listed` is a lower bound.
    pub more_than: bool,
}

/// One identifier's row.
pub(super) struct IdRow {
    pub key: RowKey,
    /// The message name of the latest frame.
    pub msg: &'static str,
    pub frames: u64,
    pub first: Option<Timestamp>,
    pub last: Option<Timestamp>,
    /// Frames per second between the first and the last frame; `None` for a single frame or no time.
    pub rate: Option<f64>,
    pub worst_gap: Option<Gap>,
    /// What the rolling count byte says; `None` for messages without one.
    pub counter: Option<CounterLosses>,
    pub invalid: u64,
}

/// The longest interval between consecutive frames of one identifier, and the frame that ended it.
pub(super) struct Gap {
    pub seconds: f64,
    pub at: Timestamp,
}

pub(super) struct CounterLosses {
    pub frames_lost: u64,
    pub skips: u64,
    pub repeats: u64,
}

/// Where a fault bit was read.
#[derive(Clone, Copy)]
pub(super) enum FaultSource {
    System,
    /// The driver state of motor 1, 2, or another motor number (0-based index 0..=2).
    Motor(usize),
}

/// One fault or status bit seen.
pub(super) struct FaultRow {
    pub source: FaultSource,
    pub info: FlagInfo,
    pub frames: u64,
    pub first: At,
    pub last: At,
}

/// A unit the report shows values in, and how many raw steps make one of it.
#[derive(Clone, Copy)]
pub(super) enum Unit {
    Volts,
    MetresPerSecond,
    RadiansPerSecond,
    Rpm,
    Amps,
}

impl Unit {
    fn steps(self) -> f64 {
        match self {
            Unit::Volts | Unit::Amps => 10.0,
            Unit::MetresPerSecond | Unit::RadiansPerSecond => 1000.0,
            Unit::Rpm => 1.0,
        }
    }
}

/// A value as the robot sent it (in the unit's raw steps), and when.
#[derive(Clone, Copy)]
pub(super) struct Reading {
    pub raw: i64,
    pub unit: Unit,
    pub at: At,
}

impl Reading {
    fn of(extreme: Option<Extreme>, unit: Unit) -> Option<Self> {
        extreme.map(|e| Self { raw: e.value, unit, at: e.at })
    }

    /// The value in the unit.
    pub fn value(&self) -> f64 {
        self.raw as f64 / self.unit.steps()
    }
}

pub(super) struct BatteryRange {
    pub min: Reading,
    pub max: Reading,
    pub last: Reading,
}

pub(super) struct WheelRow {
    pub name: &'static str,
    /// The sum of the absolute steps between consecutive odometer readings, resets left out.
    pub travelled_mm: i64,
    /// The first and last odometer readings; `None` without odometry frames.
    pub odometer_mm: Option<(i64, i64)>,
    pub resets: u64,
}

/// A top speed; `name` is the JSON key (the text shows it with spaces).
pub(super) struct SpeedRow {
    pub name: &'static str,
    pub reading: Option<Reading>,
}

pub(super) struct MotorRow {
    pub number: usize,
    pub rpm: Option<Reading>,
    pub current: Option<Reading>,
}

pub(super) struct ErrorClassCount {
    pub class: &'static str,
    pub frames: u64,
}

impl Summary {
    pub(super) fn build_report<'a>(
        &'a self,
        input: &'a InputStats,
        detector: &ProtocolDetector,
    ) -> Report<'a> {
        let mut ids: Vec<&IdStats> = self.ids.iter().collect();
        ids.sort_by_key(|stats| stats.key);
        Report {
            input,
            interfaces: InterfaceList {
                listed: &self.interfaces.names,
                not_listed: self.interfaces.not_listed(),
                more_than: self.interfaces.extra_overflow,
            },
            protocol: detector.describe(),
            first: self.first,
            last: self.last,
            ids: ids.into_iter().map(id_row).collect(),
            events: &self.events,
            events_not_listed: self.events_not_listed,
            faults: self.fault_rows(),
            battery: self.battery_range(),
            wheels: [0, 1].map(|index| self.wheel_row(index)),
            speeds: [
                ("measured_linear", self.measured_linear, Unit::MetresPerSecond),
                ("measured_angular", self.measured_angular, Unit::RadiansPerSecond),
                ("commanded_linear", self.commanded_linear, Unit::MetresPerSecond),
                ("commanded_angular", self.commanded_angular, Unit::RadiansPerSecond),
            ]
            .map(|(name, extreme, unit)| SpeedRow { name, reading: Reading::of(extreme, unit) }),
            motors: [0, 1].map(|index| MotorRow {
                number: index + 1,
                rpm: Reading::of(self.rpm[index], Unit::Rpm),
                current: Reading::of(self.current[index], Unit::Amps),
            }),
            error_frames: ERROR_CLASSES
                .iter()
                .zip(self.error_classes)
                .filter(|(_, frames)| *frames > 0)
                .map(|((_, class), frames)| ErrorClassCount { class, frames })
                .collect(),
            health: self.health.report(),
        }
    }

    /// System bits (the V2 table, then the V1/RS232 one), then each motor's driver bits.
    fn fault_rows(&self) -> Vec<FaultRow> {
        let system = [FlagTable::SystemV2, FlagTable::SystemV1Serial]
            .into_iter()
            .zip(&self.system_faults)
            .flat_map(|(table, bits)| {
                bits.iter().enumerate().map(move |(bit, seen)| (FaultSource::System, table, bit, seen))
            });
        let drivers = self.driver_faults.iter().enumerate().flat_map(|(motor, bits)| {
            bits.iter()
                .enumerate()
                .map(move |(bit, seen)| (FaultSource::Motor(motor), FlagTable::DriverState, bit, seen))
        });
        system
            .chain(drivers)
            .filter_map(|(source, table, bit, seen)| {
                let (first, last) = seen.first.zip(seen.last)?;
                Some(FaultRow { source, info: table.info(bit as u32), frames: seen.frames, first, last })
            })
            .collect()
    }

    fn battery_range(&self) -> Option<BatteryRange> {
        let reading = |extreme| Reading::of(extreme, Unit::Volts);
        Some(BatteryRange {
            min: reading(self.battery_min)?,
            max: reading(self.battery_max)?,
            last: reading(self.battery_last)?,
        })
    }

    fn wheel_row(&self, index: usize) -> WheelRow {
        let wheel = &self.wheels[index];
        WheelRow {
            name: ["left", "right"][index],
            travelled_mm: wheel.travelled_mm,
            odometer_mm: wheel.first.zip(wheel.last),
            resets: wheel.resets,
        }
    }
}

fn id_row(stats: &IdStats) -> IdRow {
    let rate = match (stats.first, stats.last) {
        (Some(first), Some(last)) if stats.count > 1 && nanos(&last) > nanos(&first) => {
            Some((stats.count - 1) as f64 / ((nanos(&last) - nanos(&first)) as f64 / 1e9))
        }
        _ => None,
    };
    IdRow {
        key: stats.key,
        msg: stats.name,
        frames: stats.count,
        first: stats.first,
        last: stats.last,
        rate,
        worst_gap: stats
            .worst_gap_at
            .filter(|_| stats.worst_gap_ns > 0)
            .map(|at| Gap { seconds: stats.worst_gap_ns as f64 / 1e9, at }),
        counter: stats.last_counter.map(|_| CounterLosses {
            frames_lost: stats.frames_lost,
            skips: stats.counter_skips,
            repeats: stats.counter_repeats,
        }),
        invalid: stats.invalid,
    }
}
