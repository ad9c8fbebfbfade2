//! The dashboard's screens at the sizes operators use (60x20 and 80x24 in tmux, over SSH): the real binary
//! against `--sim`, captured with tmux. Every size shows the safety-relevant facts (arming, speeds with
//! units, faults, battery, how to quit), the footer keeps whole entries, and the end of a replay is news,
//! not a fault.

use std::time::Duration;

use crate::dashboard::Session;

/// The speeds panel's row after `label` (`sent`, `robot`): its two values, m/s and rad/s.
fn speeds_row(screen: &str, label: &str) -> Option<Vec<String>> {
    screen.lines().find_map(|line| {
        let after = line.split(&format!("│{label} ")).nth(1)?;
        Some(after.split('│').next()?.split_whitespace().map(str::to_string).collect())
    })
}

/// The facts an operator needs at any size, and the footer ending on a whole entry.
fn assert_safety_facts(screen: &str, arming: &str, size: &str) {
    let context = format!("{size}:\n{screen}");
    assert!(
        screen.lines().next().unwrap_or_default().contains(arming),
        "{arming} in the header at {context}"
    );
    assert!(screen.contains("m/s") && screen.contains("rad/s"), "speed units at {context}");
    for label in ["sent", "robot"] {
        let values = speeds_row(screen, label).unwrap_or_else(|| panic!("no {label} row at {context}"));
        assert_eq!(values.len(), 2, "{label}: linear and angular at {context}");
        for value in &values {
            let decimals = value.split_once('.').map(|(_, decimals)| decimals.len());
            assert!(
                value.parse::<f64>().is_ok() && decimals == Some(2),
                "{label} {value:?} whole at {context}"
            );
        }
    }
    assert!(screen.contains("┌ Faults"), "the faults panel at {context}");
    assert!(screen.contains("driver_disabled"), "the standby driver state is listed at {context}");
    assert!(!screen.contains("Faults (2)"), "info lines are not counted as faults at {context}");
    assert!(
        screen.lines().any(|line| line.starts_with("│2") && line.contains(" V ")),
        "battery at {context}"
    );
    let footer = screen.lines().rev().find(|line| !line.trim().is_empty()).unwrap_or_default();
    assert!(footer.contains("? help"), "help in the footer at {context}");
    assert!(footer.trim_end().ends_with("q quit"), "the footer ends on q quit at {context}");
}

#[test]
fn sim_at_60x20_and_80x24_shows_the_safety_facts_and_whole_footer_entries() {
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command = format!("{} --sim dashboard; echo \"exit status $?\"; sleep 30", binary.display());
    let session = Session::start(&format!("tracerctl-screens-{}", std::process::id()), &command);
    for (width, height, arming) in [(60, 20, "WATCHING"), (80, 24, "WATCHING")] {
        session.resize(width, height);
        let size = format!("{width}x{height}");
        let (drawn, screen) = session.wait_for(Duration::from_secs(10), |s| {
            s.lines().count() == usize::from(height) && s.contains("driver_disabled") && s.contains("q quit")
        });
        assert!(drawn, "the dashboard drew at {size}:\n{screen}");
        assert!(screen.lines().all(|line| line.chars().count() <= usize::from(width)), "{size}:\n{screen}");
        assert_safety_facts(&screen, arming, &size);
    }
    // The help at the smallest size keeps the way out.
    session.resize(60, 20);
    session.keys(&["?"]);
    // tmux may be caught mid-redraw (the overlay's top drawn, its bottom not yet): wait for the whole overlay.
    let (help, screen) = session.wait_for(Duration::from_secs(5), |s| {
        s.contains("Keys · ? closes") && s.contains("stop the robot and quit")
    });
    assert!(help, "? opens the help, and it says how to quit at 60x20:\n{screen}");
    session.keys(&["?"]);
    let (closed, screen) = session.wait_for(Duration::from_secs(5), |s| !s.contains("Keys · ? closes"));
    assert!(closed, "? closes the help:\n{screen}");
    // Armed, at the smallest size: the state changes in the header.
    session.keys(&["a"]);
    let (asked, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("Arm driving?"));
    assert!(asked, "a asks before arming:\n{screen}");
    session.keys(&["y"]);
    let (armed, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("ARMED ·"));
    assert!(armed, "y arms:\n{screen}");
    let (settled, screen) = session.wait_for(Duration::from_secs(5), |s| s.contains("mode can"));
    assert!(settled, "command mode:\n{screen}");
    assert!(screen.contains("ARMED"), "{screen}");
    session.keys(&["q"]);
    let (quit, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("exit status 0"));
    assert!(quit, "q quits with status 0:\n{screen}");
}

#[test]
fn a_replay_that_ends_is_info_and_a_long_path_leaves_the_status_in_the_header() {
    let dir = tempfile::tempdir().unwrap();
    let deep = dir.path().join("field-tests/2026-11-24/site-north/robot-07/afternoon-run/candump");
    std::fs::create_dir_all(&deep).unwrap();
    let log = deep.join("session.log");
    std::fs::copy(crate::util::data("tracer_session.log"), &log).unwrap();
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command = format!(
        "{} --replay {} --speed 0 dashboard; echo \"exit status $?\"; sleep 30",
        binary.display(),
        log.display()
    );
    let session = Session::start(&format!("tracerctl-replay-end-{}", std::process::id()), &command);
    session.resize(80, 24);
    let (ended, screen) = session
        .wait_for(Duration::from_secs(10), |s| s.lines().count() == 24 && s.contains("[info] replay ended"));
    assert!(ended, "the end of the replay is info:\n{screen}");
    assert!(!screen.contains("LINK FAILED") && !screen.contains("[fault]"), "not a fault:\n{screen}");
    let header = screen.lines().next().unwrap_or_default();
    assert!(header.trim_end().ends_with("replay ended"), "the status stays in the header: {header}");
    assert!(header.contains('…') && header.contains("session.log"), "the path loses its middle: {header}");
    // The last values stay: the log's battery (0x211 ... B1/B2: 25.9 V) and no stale alarm.
    std::thread::sleep(Duration::from_millis(1500));
    let screen = session.screen();
    assert!(screen.contains("stale: none") && !screen.contains("NO STATUS"), "{screen}");
    session.keys(&["q"]);
    let (quit, screen) = session.wait_for(Duration::from_secs(10), |s| s.contains("exit status 0"));
    assert!(quit, "q quits with status 0:\n{screen}");
}

/// Issue 32: the dashboard shows the live analysis' dead time and battery estimate once it has them. A
/// commissioning run of a simulator with a 60 ms dead time and a 0.3 Ω battery, replayed as fast as
/// possible: the Speeds panel gives the dead time (the analysis finds it within one 20 ms period), the
/// Battery panel the internal resistance (within 15 %). Before the replay has a step, neither shows.
#[test]
fn the_live_dead_time_and_battery_estimate_show_once_measured() {
    use std::time::Duration;
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("commissioning.log");
    let text = crate::parallel_summary::commissioning_log_with(1, false, |_| tracerctl::sim::SimConfig {
        dead_time: Duration::from_millis(60),
        battery_resistance_ohm: 0.3,
        ..tracerctl::sim::SimConfig::default()
    });
    std::fs::write(&log, text).unwrap();
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let command = format!("{} --replay {} --speed 0 dashboard; sleep 30", binary.display(), log.display());
    let session = crate::dashboard_driver::Session::start(
        &format!("tracerctl-health-{}", std::process::id()),
        &command,
    );
    let (shown, screen) =
        session.wait_for(Duration::from_secs(20), |s| s.contains("dead time") && s.contains(" Ω · OCV "));
    assert!(shown, "{screen}");
    let after = |marker: &str| {
        let at = screen.find(marker).unwrap() + marker.len();
        screen[at..].split_whitespace().next().unwrap().parse::<f64>().unwrap()
    };
    let dead_time = after("dead time ");
    assert!((60.0..=80.0).contains(&dead_time), "dead time {dead_time} ms:\n{screen}");
    let resistance = after("R ");
    assert!((0.255..=0.345).contains(&resistance), "R {resistance} Ω:\n{screen}");
    session.keys(&["q"]);
}
