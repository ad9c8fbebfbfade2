//! Writes a realistic TRACER CAN session in candump `-L` format, for benchmarks and manual testing.
//!
//! Usage: cargo run --release --example gen_log -- LINES [OUT]   (OUT defaults to standard output)
//!
//! Every 20 ms: 0x111 (host), 0x211, 0x221, 0x231, 0x251, 0x252, 0x311; every 100 ms: 0x261, 0x262.
//! The robot accelerates and turns, the battery drains, a warning comes and goes, an E-stop is pressed
//! and released, and now and then a 0x211 frame is dropped (a count-byte skip). Deterministic.

use std::io::{self, BufWriter, Write};

use tracerctl::candump::{write_log_line, Timestamp, TimestampKind};
use tracerctl::protocol::can::encode_v2;
use tracerctl::protocol::message::*;

#[expect(
    clippy::too_many_lines,
    reason = "one log writer: each message and fault in the order the log holds them"
)]
fn main() -> io::Result<()> {
    let mut args = std::env::args().skip(1);
    let lines: u64 = args.next().and_then(|n| n.parse().ok()).unwrap_or(1_000_000);
    let out: Box<dyn Write> = match args.next() {
        Some(path) => Box::new(std::fs::File::create(path)?),
        None => Box::new(io::stdout().lock()),
    };
    let mut out = BufWriter::with_capacity(1 << 20, out);
    let mut buffer = Vec::with_capacity(256);
    let mut written = 0u64;
    let mut tick = 0u64;
    let (mut left_mm, mut right_mm) = (0i64, 0i64);
    let mut status_count = 0u8;
    let mut light_count = 0u8;
    'session: loop {
        let micros = 1_700_000_000_000_000u64 + tick * 20_000;
        let ts = Timestamp {
            secs: micros / 1_000_000,
            nanos: (micros % 1_000_000) as u32 * 1000,
            kind: TimestampKind::Absolute,
        };
        let phase = (tick % 3000) as f64 / 3000.0 * std::f64::consts::TAU;
        let estop = tick % 5000 >= 4000 && tick % 5000 < 4100;
        let linear = if estop { 0.0 } else { 1.2 * phase.sin() };
        let angular = if estop { 0.0 } else { 0.5 * (phase * 2.0).sin() };
        let command = MotionCommand::from_si(linear, angular).expect("within limits");
        let battery = 259 - (tick / 2000).min(45) as u16;
        let mut fault_code = 0u16;
        if battery <= 225 {
            fault_code |= 0x0200;
        }
        if tick % 7000 > 6900 {
            fault_code |= 0x0400;
        }
        let state = SystemState {
            vehicle_state: if estop { VEHICLE_ESTOP } else { VEHICLE_NORMAL },
            control_mode: if tick < 10 { MODE_STANDBY } else { MODE_CAN },
            battery_decivolts: battery,
            fault_code,
            count: status_count,
        };
        status_count = status_count.wrapping_add(1);
        // Simulated loss: skip one status frame in every 997 ticks.
        if tick % 997 == 996 {
            status_count = status_count.wrapping_add(1);
        }
        left_mm += ((linear - angular * 0.18) * 20.0) as i64;
        right_mm += ((linear + angular * 0.18) * 20.0) as i64;
        let rpm = (linear * 1000.0) as i16;
        let mut messages = vec![
            Message::MotionCommand(command),
            Message::SystemState(state),
            Message::MotionState(MotionState {
                linear_mm_s: command.linear_mm_s,
                angular_mrad_s: command.angular_mrad_s,
                count: 0,
            }),
            Message::LightState(Lights {
                enable: 1,
                front_mode: LIGHT_ON,
                count: light_count,
                ..Default::default()
            }),
            Message::MotorHighSpeed(MotorHighSpeed {
                motor: 1,
                rpm,
                current_deciamps: 12 + (rpm.abs() / 100),
                pulse_count: left_mm as i32 * 10,
            }),
            Message::MotorHighSpeed(MotorHighSpeed {
                motor: 2,
                rpm: -rpm,
                current_deciamps: 12 + (rpm.abs() / 100),
                pulse_count: right_mm as i32 * 10,
            }),
            Message::Odometry(Odometry { left_mm: left_mm as i32, right_mm: right_mm as i32 }),
        ];
        light_count = light_count.wrapping_add(1);
        if tick % 5 == 0 {
            for motor in 1..=2 {
                messages.push(Message::MotorLowSpeed(MotorLowSpeed {
                    motor,
                    driver_decivolts: battery,
                    driver_temperature: 35 + (tick / 10_000 % 20) as i16,
                    motor_temperature: 30,
                    driver_state: 0,
                }));
            }
        }
        if tick % 997 == 996 {
            messages.remove(1);
        }
        for message in &messages {
            if written == lines {
                break 'session;
            }
            let frame = encode_v2(message).expect("V2 message");
            buffer.clear();
            write_log_line(&mut buffer, Some(ts), "can0", &frame);
            out.write_all(&buffer)?;
            written += 1;
        }
        tick += 1;
    }
    out.flush()
}
