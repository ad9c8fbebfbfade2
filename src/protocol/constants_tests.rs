use std::path::Path;

use super::*;
use crate::protocol::faults::{FlagInfo, SYSTEM_V1_SERIAL, SYSTEM_V2};
use crate::source_scan::{shipped_files, without_test_items};

#[test]
fn thresholds_are_the_manuals_and_descend() {
    assert_eq!(BATTERY_THRESHOLDS.map(|(dv, _)| volts(dv)), [22.5, 22.0, 21.5]);
    assert_eq!(BATTERY_THRESHOLDS.map(|(_, name)| name), ["warning", "fault", "cut-off"]);
    assert_eq!(format!("{}", volts(BATTERY_FAULT_DV)), "22", "texts print the protection voltage as 22 V");
}

/// The fault tables are `static` texts, so they quote the thresholds as literals (the one exception the
/// source scan below allows); this keeps those quotes equal to the constants.
#[test]
fn fault_texts_quote_the_thresholds() {
    let text = |table: &[FlagInfo], name: &str| {
        let info = table.iter().find(|info| info.name == name).unwrap();
        format!("{} {}", info.meaning, info.action)
    };
    let warning = format!("below the {} V alarm voltage", volts(BATTERY_WARNING_DV));
    let fault = format!("below the {} V protection voltage", volts(BATTERY_FAULT_DV));
    let cut_off = format!("motion is cut below {} V", volts(BATTERY_CUTOFF_DV));
    for table in [SYSTEM_V2, SYSTEM_V1_SERIAL] {
        assert!(text(table, "battery_undervoltage_warning").contains(&warning));
        assert!(text(table, "battery_undervoltage_fault").contains(&fault));
    }
    assert!(text(SYSTEM_V2, "battery_undervoltage_fault").contains(&cut_off));
}

/// Lines outside this file allowed to spell a threshold, each with why: (file, text on the line, reason).
const ALLOWED: &[(&str, &str, &str)] = &[
    ("src/protocol/faults.rs", "\"battery below the 22 V protection voltage\"", "static text; checked above"),
    ("src/protocol/faults.rs", "\"battery below the 22.5 V alarm voltage\"", "static text; checked above"),
    ("src/protocol/faults.rs", "motion is cut below 21.5 V\"", "static text; checked above"),
];

/// Does `line` hold `number` as a whole number (not part of 122.5, 22.55, 0x225 or `x220`)?
fn has_number(line: &str, number: &str) -> bool {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    line.match_indices(number).any(|(at, _)| {
        let before = line[..at].chars().next_back();
        let mut after = line[at + number.len()..].chars();
        let (next, second) = (after.next(), after.next());
        let starts = before.is_none_or(|c| !word(c) && c != '.');
        let decimal_point = |c: char| c == '.' && second.is_some_and(|c| c.is_ascii_digit());
        let ends = next.is_none_or(|c| !word(c) && !decimal_point(c));
        starts && ends
    })
}

/// Is this line a battery threshold written out: 22.5 / 22.0 / 21.5 (or "22 V") anywhere, or the same in
/// 0.1 V (225 / 220 / 215) on a line that speaks of volts or the battery (so RGB 220 is not flagged)?
fn spells_a_threshold(line: &str) -> bool {
    let lower = line.to_ascii_lowercase();
    let about_volts = ["volt", "battery", "dv", "decivolt"].iter().any(|word| lower.contains(word));
    let volts_literal = ["22.5", "22.0", "21.5"].iter().any(|n| has_number(line, n))
        || ["22 V", "22V"].iter().any(|n| has_number(line, n));
    let decivolts_literal = ["225", "220", "215"].iter().any(|n| has_number(line, n));
    volts_literal || (about_volts && decivolts_literal)
}

#[test]
fn battery_thresholds_are_written_only_here() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = shipped_files(&root.join("src"));
    assert!(files.len() > 20, "the scan found the sources");
    let mut strays = Vec::new();
    for path in &files {
        let relative = path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        if relative.starts_with("src/protocol/constants") {
            continue;
        }
        // Comments count too: a threshold quoted in a comment goes stale like one in code.
        let text = std::fs::read_to_string(path).unwrap();
        for (number, line) in without_test_items(&text).lines().enumerate() {
            let allowed = ALLOWED.iter().any(|&(file, text, _)| file == relative && line.contains(text));
            if spells_a_threshold(line) && !allowed {
                strays.push(format!("{relative}:{}: {}", number + 1, line.trim()));
            }
        }
    }
    assert!(
        strays.is_empty(),
        "battery thresholds belong in src/protocol/constants.rs:\n{}",
        strays.join("\n")
    );
}

#[test]
fn the_scan_flags_thresholds_and_nothing_else() {
    for line in [
        "const ALARM: f64 = 22.5;",
        "(22.0, \"fault\")",
        "\"motion is cut below 21.5 V\"",
        "below the 22 V protection",
        "pub const BATTERY_FAULT_DV: u16 = 220;",
        "if battery_decivolts <= 215 {",
    ] {
        assert!(spells_a_threshold(line), "{line}");
    }
    for line in [
        "const ESTOP_COLOR: RGBColor = RGBColor(220, 0, 0);",
        "close(rpm, 122.5, 1e-3);",
        "let x = 22.55;",
        "0x225 battery frame",
        "battery at 22.4 V",
        "(22, Reason::MissingFrame)",
    ] {
        assert!(!spells_a_threshold(line), "{line}");
    }
}
