//! The pure parts of the folders (limits and ramps, counts, staleness, text, the alert's choice, the line
//! loop and its limit) use no thread, clock or terminal: what they need of those comes in as values, so
//! each is tested alone with made-up inputs (issue 30).

use std::path::Path;

use crate::source_scan::{code_only, without_test_items};

const PURE: &[&str] = &[
    "src/control/limits.rs",
    "src/commands/monitor/counts.rs",
    "src/commands/monitor/staleness.rs",
    "src/commands/monitor/text.rs",
    "src/dashboard/alert.rs",
    "src/commands/decode/lines.rs",
    "src/candump/line_limit.rs",
    "src/blackbox/triggers.rs",
    "src/blackbox/onset.rs",
    "src/blackbox/expr.rs",
    "src/blackbox/state.rs",
    "src/blackbox/cause.rs",
];

/// Threads, channels, locks, clocks and terminals.
const IMPURE: &[&str] = &[
    "std::thread",
    "mpsc",
    "Mutex",
    "parking_lot",
    "Instant",
    "SystemTime",
    "crossterm",
    "ratatui",
    "stdout()",
    "stderr()",
];

/// The file's code without its test items, comments and literals.
fn code_before_tests(source: &str) -> String {
    code_only(&without_test_items(source))
}

fn impurities(code: &str) -> Vec<&'static str> {
    IMPURE.iter().copied().filter(|word| code.contains(word)).collect()
}

#[test]
fn the_pure_files_use_no_thread_clock_or_terminal() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for file in PURE {
        let source =
            std::fs::read_to_string(root.join(file)).unwrap_or_else(|error| panic!("{file}: {error}"));
        let found = impurities(&code_before_tests(&source));
        assert!(found.is_empty(), "{file} uses {found:?}: take them as values from the caller");
    }
}

#[test]
fn an_impure_line_is_found_and_comments_and_tests_are_not() {
    let source =
        "use std::time::Duration;\n// no Instant here\nfn f() { let _ = std::time::Instant::now(); }\n\
                  #[cfg(test)]\nmod tests { use std::thread; }\n";
    assert_eq!(impurities(&code_before_tests(source)), ["Instant"]);
    assert!(impurities(&code_before_tests("// std::thread\n#[cfg(test)]\nuse ratatui;")).is_empty());
}
