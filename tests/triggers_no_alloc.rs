//! The black box's trigger watcher allocates nothing per frame when nothing fires: watching 20x more frames
//! costs exactly as many heap allocations (all of them set-up). Counted on the test's own thread only.

use tracerctl::blackbox::triggers::{TriggerSettings, Watcher};
use tracerctl::candump::{Timestamp, TimestampKind};
use tracerctl::protocol::can::{encode_v1, encode_v2};
use tracerctl::protocol::message::*;
use tracerctl::protocol::{serial, LinkFrame};

#[path = "support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::allocations_so_far;

/// One 20 ms period of a healthy robot on each wire: V2 with every feedback frame, V1, RS232.
fn period() -> Vec<LinkFrame> {
    let status = SystemState { control_mode: MODE_CAN, battery_decivolts: 259, ..SystemState::default() };
    let v2 = [
        Message::MotionCommand(MotionCommand { linear_mm_s: 500, angular_mrad_s: 100 }),
        Message::SystemState(status),
        Message::MotionState(MotionState { linear_mm_s: 500, angular_mrad_s: 100, count: 0 }),
        Message::LightState(Lights { front_mode: LIGHT_ON, ..Lights::default() }),
        Message::MotorHighSpeed(MotorHighSpeed { motor: 1, rpm: 1200, current_deciamps: 21, pulse_count: 9 }),
        Message::MotorHighSpeed(MotorHighSpeed {
            motor: 2,
            rpm: -1200,
            current_deciamps: 23,
            pulse_count: 9,
        }),
        Message::Odometry(Odometry { left_mm: 1000, right_mm: 1001 }),
        Message::MotorLowSpeed(MotorLowSpeed {
            motor: 1,
            driver_decivolts: 259,
            driver_temperature: 30,
            ..Default::default()
        }),
    ];
    let mut frames: Vec<LinkFrame> = v2.iter().map(|m| LinkFrame::Can(encode_v2(m).unwrap())).collect();
    let v1 = Message::SystemState(status);
    frames.push(LinkFrame::Can(encode_v1(&v1).unwrap()));
    let rs232 = SystemState { control_mode: MODE_SERIAL, ..status };
    frames.push(LinkFrame::Serial(serial::encode(&Message::SystemState(rs232), 1).unwrap()));
    frames
}

/// Allocations made while watching `periods` periods of frames (the watcher made before counting).
fn allocations_for(periods: u64) -> usize {
    let frames = period();
    let expressions = ["current>15", "id=0x441", "control_mode=rc", "faults=rc_disconnected"];
    let settings = TriggerSettings {
        expressions: expressions.iter().map(|text| text.parse().unwrap()).collect(),
        ..TriggerSettings::default()
    };
    let mut watcher = Watcher::new(settings);
    let mut out = Vec::with_capacity(16);
    let before = allocations_so_far();
    for index in 0..periods {
        let micros = 1_700_000_000_000_000 + index * 20_000;
        for (offset, frame) in frames.iter().enumerate() {
            let micros = micros + offset as u64 * 100;
            let at = Timestamp {
                secs: micros / 1_000_000,
                nanos: (micros % 1_000_000) as u32 * 1000,
                kind: TimestampKind::Absolute,
            };
            watcher.frame(at, frame, &mut out);
        }
        if index % 5 == 0 {
            let at = Timestamp { secs: micros / 1_000_000, nanos: 0, kind: TimestampKind::Absolute };
            watcher.tick(at, &mut out);
        }
    }
    let used = allocations_so_far() - before;
    assert!(out.is_empty(), "a healthy robot fires nothing: {out:?}");
    used
}

#[test]
fn watching_allocates_nothing_per_frame() {
    let small = allocations_for(100);
    let large = allocations_for(2_000);
    assert_eq!(small, large, "{small} allocations for 1,000 frames, {large} for 20,000");
    assert_eq!(large, 0, "the watcher's tables are made by Watcher::new");
}
