//! The whole dashboard drawn into a `TestBackend`: insta snapshots of the main states and sizes, and what
//! every size must still show.

use std::time::{Duration, Instant};

use ratatui::backend::TestBackend;
use ratatui::buffer::Buffer;
use ratatui::style::Color;
use ratatui::Terminal;

use super::link::not_reported;
use super::text::{middle_ellipsis, names_within};
use super::*;
use crate::control::{Limits, SenderStats};
use crate::dashboard::app::{Arming, Prompt, Protocol, ReleaseView, Snapshot, TeleopView};
use crate::dashboard::keys;
use crate::dashboard::message::Message;
use crate::dashboard::teleop::Key;
use crate::protocol::catalog::{self, Direction};
use crate::protocol::detect::ProtocolDetector;
use crate::protocol::message::{
    Lights, MotionCommand, MotionState, MotorDriverState, MotorHighSpeed, MotorLowSpeed, Odometry,
    SystemState,
};
use crate::protocol::FrameId;
use crate::protocol::{ControlMode, Wire};
use crate::session::RobotStatus;

/// The buffer as text, one line per row, trailing spaces trimmed.
fn text(buffer: &Buffer) -> String {
    let area = buffer.area;
    let mut out = String::new();
    for y in area.top()..area.bottom() {
        let mut line = String::new();
        for x in area.left()..area.right() {
            line.push_str(buffer[(x, y)].symbol());
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

fn draw(app: &App, width: u16, height: u16) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).unwrap();
    terminal.draw(|frame| render(frame, app)).unwrap();
    terminal
}

fn screen(app: &App, width: u16, height: u16) -> String {
    text(draw(app, width, height).backend().buffer())
}

/// A V2 robot's status at `now`: 25.9 V, command mode, both motors at `rpm`.
fn v2_status(now: Instant, linear_mm_s: i16, rpm: i16) -> RobotStatus {
    let system =
        SystemState { vehicle_state: 0, control_mode: 1, battery_decivolts: 259, fault_code: 0, count: 7 };
    let mut status = RobotStatus {
        system: Some((now, system, Wire::CanV2)),
        motion: Some((now, MotionState { linear_mm_s, angular_mrad_s: 0, count: 0 })),
        lights: Some((now, Lights { enable: 1, front_mode: 1, ..Lights::default() })),
        odometry: Some(Odometry::default()),
        detector: ProtocolDetector { v1_frames: 0, v2_frames: 1 },
        ..RobotStatus::default()
    };
    for motor in 0..2 {
        status.motor_high[motor] = Some(MotorHighSpeed {
            motor: motor as u8 + 1,
            rpm,
            current_deciamps: if rpm == 0 { 0 } else { 6 },
            pulse_count: 0,
        });
        status.motor_low[motor] = Some(MotorLowSpeed {
            motor: motor as u8 + 1,
            driver_decivolts: 259,
            driver_temperature: 27,
            motor_temperature: 27,
            driver_state: 0,
        });
    }
    status
}

/// Feeds `seconds` of 50 ms updates: V2 feedback at its rates (0x261/0x262 at 10 Hz), the wheels at
/// `linear_mm_s`, the battery from `volts[second]`. `edit` changes the status before each update.
fn run(app: &mut App, base: Instant, seconds: u64, linear_mm_s: i16, edit: &dyn Fn(&mut RobotStatus, u64)) {
    let rpm = (f64::from(linear_mm_s) / 1000.0 / (std::f64::consts::PI * 0.15) * 60.0).round() as i16;
    let sent = MotionCommand { linear_mm_s, angular_mrad_s: 0 };
    for tick in 0..=seconds * 20 {
        let now = base + Duration::from_millis(50 * tick);
        let mut status = v2_status(now, linear_mm_s, rpm);
        let fast = tick * 5 / 2;
        let slow = tick / 2;
        status.id_counts = [0x211, 0x221, 0x231, 0x251, 0x252, 0x311]
            .iter()
            .map(|id| (FrameId::Standard(*id), fast))
            .chain([(FrameId::Standard(0x261), slow), (FrameId::Standard(0x262), slow)])
            .collect();
        status.id_counts.sort_unstable();
        status.frames = 6 * fast + 2 * slow;
        let travelled = (i64::from(linear_mm_s) * 50 * tick as i64 / 1000) as i32;
        status.odometry = Some(Odometry { left_mm: 120_000 + travelled, right_mm: 120_400 + travelled });
        edit(&mut status, tick);
        app.update(&Snapshot {
            status: &status,
            sender: SenderStats { sent, frames: tick, ..SenderStats::default() },
            link_name: "can0",
            now,
        });
    }
}

fn kitty(scale: f64, held: Vec<Key>, requested: (f64, f64)) -> TeleopView {
    TeleopView { release_mode: ReleaseView::Events, scale, held, requested }
}

/// Driving straight at 0.3 m/s for 30 s on 25.9 V (26.0 V for the first 10 s), no faults.
fn driving() -> App {
    let base = Instant::now();
    let mut app = App::new("can0", Limits::default(), false);
    run(&mut app, base, 30, 300, &|status, tick| {
        if tick < 200 {
            status.system.as_mut().unwrap().1.battery_decivolts = 260;
        }
    });
    app.set_teleop(kitty(0.6, vec![Key::Up], (0.3, 0.0)));
    app.set_arming(Arming::Armed);
    app
}

fn faulted() -> App {
    let base = Instant::now();
    let mut app = App::new("can0", Limits::default(), false);
    run(&mut app, base, 3, 0, &|status, _| {
        // CAN V1 system bits (latched driver over-temperature protection + its warning), with the
        // driver-state bytes of 0x261/0x262 as a V2 robot reports them.
        let system = &mut status.system.as_mut().unwrap();
        system.1.vehicle_state = 2;
        system.1.fault_code = 0x0040 | 0x0200;
        system.2 = Wire::CanV1;
        status.detector = ProtocolDetector { v1_frames: 1, v2_frames: 0 };
        status.motor_low[0].as_mut().unwrap().driver_state = 0x08 | 0x04;
        status.motor_low[0].as_mut().unwrap().driver_temperature = 68;
        status.motor_low[1].as_mut().unwrap().driver_state = 0x10;
    });
    app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
    app
}

fn assert_contains(screen: &str, needles: &[&str]) {
    for needle in needles {
        assert!(screen.contains(needle), "{needle:?} missing from:\n{screen}");
    }
}

/// No row wider than the terminal (the buffer guarantees it) and nothing drawn past the frame.
fn rows(screen: &str) -> Vec<&str> {
    screen.lines().collect()
}

#[test]
fn normal_driving_120x40() {
    let app = driving();
    let screen = screen(&app, 120, 40);
    assert_contains(
        &screen,
        &[
            "tracerctl · ARMED · can0 · CAN V2 · NORMAL · mode can · status <0.1 s",
            "ready to drive: command mode, no faults",
            "25.9 V  ok",
            "keys    +0.30   +0.00 ↑",
            "sent    +0.30   +0.00",
            "robot   +0.30   +0.00",
            "trip    9.00 m",
            "pose    x +9.00 y +0.00 m",
            "0x211 system    50/s",
            "0x261 driver 1  10/s",
            "stale: none",
            "key release: terminal events (kitty protocol)",
            "scale 60 %",
        ],
    );
    assert!(rows(&screen)[2..].iter().any(|row| row.contains("none")), "faults: none");
    insta::assert_snapshot!(screen);
}

#[test]
fn normal_driving_100x30() {
    let screen = screen(&driving(), 100, 30);
    assert_contains(&screen, &["NORMAL", "25.9 V  ok", "robot   +0.30", "Faults", "none", "0x311 odometry"]);
    insta::assert_snapshot!(screen);
}

#[test]
fn normal_driving_80x24_fits() {
    let screen = screen(&driving(), 80, 24);
    assert_contains(
        &screen,
        &[
            "NORMAL",
            "mode can",
            "25.9 V  ok",
            "keys    +0.30   +0.00 ↑",
            "robot   +0.30",
            "trip 9.00 m",
            "lights on",
            "none",
            "M1 +38",
            "stale: none",
            "211:50",
            "262:10",
            "key release: terminal events",
            "q quit",
        ],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn estop() {
    let base = Instant::now();
    let mut app = App::new("can0", Limits::default(), false);
    run(&mut app, base, 2, 0, &|status, _| {
        let system = &mut status.system.as_mut().unwrap().1;
        system.vehicle_state = 1;
        system.control_mode = 0;
        for motor in status.motor_low.iter_mut() {
            motor.as_mut().unwrap().driver_state = 0x40;
        }
    });
    app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "E-STOP · mode standby",
            "[fault] E-STOP: the E-stop is pressed: release both E-stop buttons",
            "[info]",
            "M1 driver_disabled",
            "0x40 disabled",
        ],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn active_faults() {
    let app = faulted();
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "CAN V1 · EXCEPTION",
            "[fault] CANNOT DRIVE, see Faults: driver_overheat_protection",
            "[protection] driver_overheat_protection: stop, let the drivers cool",
            "[warning]",
            "driver_overheat_warning",
            "[fault]      M2 can_disconnected",
            "M1 driver_overcurrent",
            "0x0C overcurrent,overheat",
            "Faults (5)",
        ],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn active_faults_80x24_fits() {
    let screen = screen(&faulted(), 80, 24);
    assert_contains(
        &screen,
        &["EXCEPTION", "[protection] driver_overheat_protection", "[fault]", "[warning]"],
    );
    // Every fault still has its line, with its severity spelled.
    for name in [
        "driver_overheat_protection",
        "M2 can_disconnected",
        "driver_overheat_warning",
        "M1 driver_overcurrent",
        "M1 driver_overheat",
    ] {
        assert!(screen.contains(name), "{name} missing:\n{screen}");
    }
    insta::assert_snapshot!(screen);
}

#[test]
fn low_battery() {
    let base = Instant::now();
    let mut app = App::new("can0", Limits::default(), false);
    run(&mut app, base, 20, 0, &|status, tick| {
        let system = &mut status.system.as_mut().unwrap().1;
        system.battery_decivolts = 223 - (tick / 200) as u16; // 22.3 V sagging to 22.1 V
        system.fault_code = 0x0200;
    });
    app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "22.1 V  [warning] <= 22.5 V",
            "WARNING",
            "[warning]    battery_undervoltage_warning: finish the task and charge soon",
            "last 21 s: 22.1-22.3 V",
        ],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn stale_link() {
    let base = Instant::now();
    let mut app = App::new("can0", Limits::default(), false);
    // 5 s of traffic, then nothing for 3 s.
    run(&mut app, base, 5, 0, &|_, _| {});
    let mut status = v2_status(base + Duration::from_secs(5), 0, 0);
    status.odometry = Some(Odometry { left_mm: 120_000, right_mm: 120_400 });
    status.id_counts = [0x211, 0x221, 0x231, 0x251, 0x252, 0x311]
        .iter()
        .map(|id| (FrameId::Standard(*id), 250))
        .chain([(FrameId::Standard(0x261), 50), (FrameId::Standard(0x262), 50)])
        .collect();
    status.id_counts.sort_unstable();
    for tick in 1..=60 {
        let now = base + Duration::from_secs(5) + Duration::from_millis(50 * tick);
        app.update(&Snapshot { status: &status, sender: SenderStats::default(), link_name: "can0", now });
    }
    app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "NO STATUS FOR 3.0 s",
            "[fault] STALE: no status for 3.0 s: every value on screen is old",
            "STALE: all 8 feedback IDs, >= 3.0 s",
            "0x211 system   STALE",
        ],
    );
    insta::assert_snapshot!(screen);
}

// The snapshot has the ^Z row, which Windows (no job control) does not.
#[cfg(unix)]
#[test]
fn help_overlay() {
    let mut app = driving();
    app.toggle_help();
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "Keys · ? closes",
            "drive forward / backward (linear speed)",
            "turn left / right (angular speed)",
            "held together: arcs (kitty protocol only)",
            "arcs ↖ ↗ ↙ ↘, also Home PgUp End PgDn",
            "Space  k  zero at once, no ramp",
            "speed scale up / down (now 60 %)",
            "cycle the lights",
            "clear faults (asks first)",
            "enable command mode",
            "q  ^C     stop the robot and quit",
        ],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn the_help_keeps_the_way_out_on_a_small_screen() {
    let mut app = driving();
    app.toggle_help();
    for (width, height) in [(60, 20), (80, 24), (60, 12)] {
        let screen = screen(&app, width, height);
        assert_contains(&screen, &["Keys · ? closes", "stop the robot and quit"]);
        if height < 20 {
            continue;
        }
        // The box's inside, as one text: every row's help is there whole (wrapped, never cut).
        let box_width = 70.min(width - 4);
        let left = usize::from((width - box_width) / 2) + 1;
        let inside: Vec<String> = screen
            .lines()
            .map(|line| line.chars().skip(left).take(usize::from(box_width) - 2).collect())
            .collect();
        let flat = inside.join(" ").split_whitespace().collect::<Vec<_>>().join(" ");
        for row in keys::BINDINGS {
            assert!(flat.contains(row.help), "{:?} at {width}x{height}:\n{screen}", row.help);
        }
    }
    assert_contains(
        &screen(&app, 60, 12),
        &["more: a taller terminal shows them", "q  ^C     stop the robot"],
    );
    assert_contains(&screen(&app, 80, 30), &["zero-velocity frames first."]);
}

#[test]
fn clear_confirmation_prompt() {
    let mut app = faulted();
    app.ask_clear_confirmation();
    assert_eq!(app.prompt(), Prompt::ConfirmClear);
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "Clear faults?",
            "Send a fault clear to the robot (all latched faults)?",
            "[protection] driver_overheat_protection",
            "[fault] M2 can_disconnected",
            "y send the clear",
            "any other key cancel",
        ],
    );
    insta::assert_snapshot!(screen);
    app.cancel_prompt();
    assert!(!self::screen(&app, 100, 30).contains("Send a fault clear"));
}

#[test]
fn recording_losses_stay_in_the_footer_beside_the_message() {
    let mut app = driving();
    let before = app.fingerprint();
    app.set_recording_loss(Some(crate::recorder::RecordLoss {
        frames: 1234,
        reason: "No space left on device (os error 28)".to_string(),
    }));
    assert_ne!(app.fingerprint(), before, "a loss redraws");
    app.set_message(Message::Lights("on"), Instant::now());
    let screen = screen(&app, 100, 30);
    let footer = rows(&screen).last().copied().unwrap_or_default().to_string();
    assert_eq!(
        footer.trim_end(),
        "[fault] RECORDING LOST 1234 frames: No space left on device (os error 28) · > lights: on"
    );
    assert!(screen_small(&app).contains("[fault] RECORDING LOST 1234 frames"));
    insta::assert_snapshot!(screen);
}

#[test]
fn message_and_nothing_received() {
    let base = Instant::now();
    let mut app = App::new("/dev/ttyUSB0", Limits::default(), false);
    app.update(&Snapshot {
        status: &RobotStatus::default(),
        sender: SenderStats::default(),
        link_name: "/dev/ttyUSB0",
        now: base,
    });
    app.set_message(Message::Lights("on"), base);
    let screen = screen(&app, 80, 24);
    assert_contains(
        &screen,
        &["no status yet", "[warning] nothing received on /dev/ttyUSB0 yet", "> lights: on", "no frames yet"],
    );
}

#[test]
fn no_color_means_no_colour_and_color_repeats_the_words() {
    let mut app = faulted();
    let terminal = draw(&app, 100, 30);
    for cell in terminal.backend().buffer().content() {
        assert_eq!((cell.fg, cell.bg), (Color::Reset, Color::Reset), "{cell:?}");
    }
    app.color = true;
    let terminal = draw(&app, 100, 30);
    let buffer = terminal.backend().buffer();
    let screen = text(buffer);
    let row = screen.lines().position(|line| line.contains("[protection]")).unwrap();
    let column = screen.lines().nth(row).unwrap().find("[protection]").unwrap();
    // `find` counts bytes; the row is ASCII up to there apart from the border.
    let x = screen.lines().nth(row).unwrap()[..column].chars().count() as u16;
    assert_eq!(buffer[(x + 1, row as u16)].fg, Color::Red);
    assert!(buffer.content().iter().any(|cell| cell.fg == Color::Yellow), "warnings in yellow");
}

#[test]
fn watching_arming_prompt_and_watch_only_are_shown() {
    let mut app = driving();
    app.set_arming(Arming::Watching);
    let shown = screen(&app, 100, 30);
    assert_contains(&shown, &["tracerctl · WATCHING · can0", "watching: nothing is sent", "a arm"]);
    app.ask_arm_confirmation();
    assert_eq!(app.prompt(), Prompt::ConfirmArm);
    let shown = screen(&app, 100, 30);
    assert_contains(&shown, &["Arm driving?", "y arm", "keep watching", "Until then nothing is sent."]);
    insta::assert_snapshot!(shown);
    let mut app = driving();
    app.set_arming(Arming::WatchOnly);
    let shown = screen(&app, 100, 30);
    assert_contains(&shown, &["WATCH ONLY", "watch only: nothing is sent to the robot"]);
    assert!(!shown.contains("a arm"), "no arming key when it cannot arm:\n{shown}");
    // The small layout keeps the state too.
    assert_contains(&screen_small(&app), &["WATCH ONLY"]);
}

#[test]
fn the_keys_that_answer_a_prompt_are_never_cut() {
    // At 60x20 the arm box used to lose its last line, the only one that says how to answer.
    let mut arm = driving();
    arm.set_arming(Arming::Watching);
    arm.ask_arm_confirmation();
    let mut clear = driving();
    clear.ask_clear_confirmation();
    for width in (24..=121).step_by(3) {
        for height in (6..=40).step_by(2) {
            let shown = screen(&arm, width, height);
            assert_contains(&shown, &["y arm", "any other", "watching"]);
            let shown = screen(&clear, width, height);
            assert_contains(&shown, &["y send", "stop", "cancel"]);
        }
    }
    // Where there is room, the explanation is whole too.
    assert_contains(&screen(&arm, 100, 30), &["Until then nothing is sent."]);
}

fn screen_small(app: &App) -> String {
    screen(app, 50, 16)
}

#[test]
fn every_size_draws_without_panicking() {
    let mut app = faulted();
    app.set_message(Message::ClearSent(Wire::CanV2), Instant::now());
    for (width, height) in
        [(1, 1), (20, 5), (59, 19), (60, 20), (79, 23), (80, 24), (99, 29), (100, 30), (120, 40), (250, 80)]
    {
        let screen = screen(&app, width, height);
        // The header gives way from its least needed part: the arming state stays.
        assert!(width < 20 || screen.contains("WATCHING"), "{width}x{height}:\n{screen}");
        app.toggle_help();
        let _ = self::screen(&app, width, height);
        app.toggle_help();
        app.ask_clear_confirmation();
        let _ = self::screen(&app, width, height);
        app.cancel_prompt();
    }
    let small = screen(&app, 50, 15);
    assert_contains(&small, &["60x20 or larger shows the panels", "EXCEPTION"]);
}

/// Driving as [`driving`] does, with 2 [info] driver bits (standby-like) and one [warning] bit.
fn driving_with_info_and_a_warning() -> App {
    let base = Instant::now();
    let mut app = App::new("can0", Limits::default(), false);
    run(&mut app, base, 3, 300, &|status, _| {
        status.system.as_mut().unwrap().1.fault_code = 0x0200;
        for motor in status.motor_low.iter_mut() {
            motor.as_mut().unwrap().driver_state = 0x40;
        }
    });
    app.set_teleop(kitty(0.6, vec![], (0.3, 0.0)));
    app.set_arming(Arming::Armed);
    app
}

/// The safety facts every size from the panels' minimum shows: arming, both speeds with units, the faults,
/// the battery, how to quit.
fn assert_safety_facts(screen: &str, size: (u16, u16)) {
    let (width, height) = size;
    let context = format!("{width}x{height}:\n{screen}");
    assert!(screen.contains("ARMED"), "arming state missing at {context}");
    assert!(screen.contains("m/s") && screen.contains("rad/s"), "speed units missing at {context}");
    // The speeds panel's row: what follows the label up to the panel's border.
    let row = |label: &str| {
        screen.lines().find_map(|line| {
            let after = line.split(&format!("│{label} ")).nth(1)?;
            Some(after.split('│').next().unwrap_or_default().split_whitespace().collect::<Vec<_>>())
        })
    };
    for label in ["sent", "robot"] {
        let values = row(label).unwrap_or_else(|| panic!("no {label} row at {context}"));
        assert_eq!(values, ["+0.30", "+0.00"], "{label} at {context}");
    }
    assert!(screen.contains("Faults (1)"), "the fault count (info not counted) at {context}");
    assert!(screen.contains("25.9 V"), "battery missing at {context}");
    let footer = screen.lines().rev().find(|line| line.contains("quit")).unwrap_or_default();
    assert!(footer.contains("q quit") && footer.contains("? help"), "keys at {context}");
    assert!(footer.trim_end().ends_with("q quit"), "the footer ends on a whole entry at {context}");
}

#[test]
fn every_size_from_the_minimum_shows_the_safety_facts() {
    let app = driving_with_info_and_a_warning();
    let mut sizes = 0;
    for width in (MIN_PANELS.0..=120).step_by(3).chain([120]) {
        for height in (MIN_PANELS.1..=40).step_by(2).chain([40]) {
            assert_safety_facts(&screen(&app, width, height), (width, height));
            sizes += 1;
        }
    }
    assert!(sizes > 200, "{sizes} sizes");
}

#[test]
fn safety_facts_60x20() {
    let screen = screen(&driving_with_info_and_a_warning(), 60, 20);
    assert_safety_facts(&screen, (60, 20));
    assert_contains(
        &screen,
        &["robot +0.30  +0.00", "ARMED · can0 · CAN V2 · NORMAL · mode can · status <0.1 s"],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn safety_facts_80x24() {
    let screen = screen(&driving_with_info_and_a_warning(), 80, 24);
    assert_safety_facts(&screen, (80, 24));
    assert_contains(&screen, &["robot   +0.30   +0.00", "[info]       M1 driver_disabled"]);
    insta::assert_snapshot!(screen);
}

#[test]
fn safety_facts_100x30() {
    let screen = screen(&driving_with_info_and_a_warning(), 100, 30);
    assert_safety_facts(&screen, (100, 30));
    assert_contains(
        &screen,
        &["[warning]    battery_undervoltage_warning", "[info]       M2 driver_disabled"],
    );
    insta::assert_snapshot!(screen);
}

#[test]
fn a_long_replay_path_loses_its_middle_never_the_status() {
    let mut app = driving();
    let path = format!("/home/operator/{}/field-test-2026-11-24/session.log", "logs/".repeat(20));
    app.shown.link_name.clone_from(&path);
    for width in [60, 80, 100, 120] {
        let screen = screen(&app, width, 30);
        let header = screen.lines().next().unwrap_or_default();
        assert!(header.ends_with("NORMAL · mode can · status <0.1 s"), "{width}: {header}");
        assert!(header.contains("ARMED"), "{width}: {header}");
        if width >= 80 {
            assert!(header.contains("…") && header.contains("session.log"), "{width}: {header}");
        }
    }
    assert_eq!(middle_ellipsis("/home/operator/session.log", 12), "/ho…sion.log");
    assert_eq!(middle_ellipsis("can0", 12), "can0");
    assert_eq!(fit_words("press e to enable it", 15), "press e to…");
    assert_eq!(fit_words("press e to enable it", 20), "press e to enable it");
    let names = ["a_fault".to_string(), "M2 b_fault".to_string(), "c_fault".to_string()];
    assert_eq!(names_within("see: ", &names, 80), "see: a_fault, M2 b_fault, c_fault");
    assert_eq!(names_within("see: ", &names, 26), "see: a_fault +2");
    assert_eq!(names_within("see: ", &names, 27), "see: a_fault, M2 b_fault +1");
}

#[test]
fn the_end_of_a_replay_is_info_and_keeps_the_last_values() {
    let base = Instant::now();
    let mut app = App::new("session.log", Limits::default(), false);
    run(&mut app, base, 3, 300, &|_, _| {});
    let end = base + Duration::from_secs(3);
    let mut status = v2_status(end, 300, 38);
    status.link_error = Some("end of the replayed log".to_string());
    status.link_ended = true;
    // Ten seconds after the end: nothing turns stale, the rates stay.
    for tick in 0..=200 {
        let now = end + Duration::from_millis(50 * tick);
        app.update(&Snapshot {
            status: &status,
            sender: SenderStats::default(),
            link_name: "session.log",
            now,
        });
    }
    app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "NORMAL · mode can · replay ended",
            "[info] replay ended: the log's last values stay on screen; q quits",
            "robot   +0.30   +0.00",
            "25.9 V",
            "stale: none",
            "0x211 system    50/s",
        ],
    );
    assert!(!screen.contains("[fault]") && !screen.contains("LINK FAILED"), "{screen}");
    // A link that fails is still a fault.
    status.link_ended = false;
    app.update(&Snapshot { status: &status, sender: SenderStats::default(), link_name: "x", now: end });
    assert!(self::screen(&app, 100, 30).contains("[fault] LINK FAILED: end of the replayed log"));
}

#[test]
fn info_lines_are_listed_but_not_counted() {
    let screen = screen(&driving_with_info_and_a_warning(), 100, 30);
    assert_contains(
        &screen,
        &["Faults (1)", "[info]       M1 driver_disabled", "[info]       M2 driver_disabled"],
    );
    let app = driving_with_info_and_a_warning();
    assert_eq!((app.faults().len(), app.fault_count()), (3, 1));
    assert_contains(&screen_small(&app), &["faults 1 (worst [warning])"]);
}

/// An RS232 robot: the serial feedback identifiers of the catalog at 50/s, no odometry, no driver state.
fn rs232() -> App {
    let base = Instant::now();
    let mut app = App::new("/dev/ttyUSB0", Limits::default(), false);
    let serial: Vec<FrameId> = catalog::CATALOG
        .iter()
        .filter(|entry| entry.wire == Wire::Serial && entry.direction == Direction::FromRobot)
        .map(|entry| entry.id)
        .collect();
    for tick in 0..=100u64 {
        let now = base + Duration::from_millis(50 * tick);
        let mut status = v2_status(now, 0, 0);
        let system = status.system.as_mut().unwrap();
        system.1.control_mode = ControlMode::Serial.code(Wire::Serial);
        system.2 = Wire::Serial;
        status.odometry = None;
        status.motor_low = [None, None];
        status.motor_high = [None, None];
        status.motor_driver = [1, 2].map(|motor| {
            Some(MotorDriverState { motor, current_deciamps: 3, rpm: 0, driver_temperature: 26, count: 0 })
        });
        status.detector = ProtocolDetector::default();
        status.id_counts = serial.iter().map(|id| (*id, tick * 5 / 2)).collect();
        status.frames = serial.len() as u64 * tick * 5 / 2;
        app.update(&Snapshot {
            status: &status,
            sender: SenderStats::default(),
            link_name: "/dev/ttyUSB0",
            now,
        });
    }
    app.set_teleop(kitty(0.6, vec![], (0.0, 0.0)));
    app
}

#[test]
fn rs232_link_panel_lists_its_identifiers_and_what_it_does_not_report() {
    assert_eq!(
        not_reported(Protocol::Serial),
        ["odometry", "motor_low_speed", "rc_state", "version_response"]
    );
    assert_eq!(not_reported(Protocol::CanV1), not_reported(Protocol::Serial));
    assert!(not_reported(Protocol::CanV2).is_empty());
    let app = rs232();
    let screen = screen(&app, 100, 30);
    assert_contains(
        &screen,
        &[
            "RS232 · NORMAL · mode serial",
            "0xAA01 system   50/s  0xAA02 motion   50/s",
            "rx 250 fps · checksum errors 0",
            "skipped bytes 0",
            "RS232 does not report: odometry,",
            "motor_low_speed, rc_state,",
            "RS232 reports no odometry",
            "not on RS232",
        ],
    );
    assert!(!screen.contains("0xAA01system") && !screen.contains("error frames"), "{screen}");
    insta::assert_snapshot!(screen);
    let compact = self::screen(&app, 80, 24);
    assert_contains(&compact, &["rx 250/s cksum 0 skip 0", "AA01:50", "not on RS232"]);
    assert!(!compact.contains("err 0"), "{compact}");
}
