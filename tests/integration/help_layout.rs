//! The layout of `--help`, the man pages and the completions (issue 13), and who wins between `--color`
//! and NO_COLOR: checked on the real binary and on the committed generated files.

use std::path::Path;

use crate::util::{stderr, stdout, tracerctl};

/// Every subcommand's name, from the CLI definition (the help subcommand aside).
fn subcommands() -> Vec<String> {
    tracerctl::cli::command().get_subcommands().map(|sub| sub.get_name().to_string()).collect()
}

/// `tracerctl [SUB] FLAG` at `COLUMNS=columns` (standard output is a pipe, so clap reads COLUMNS).
fn help(sub: Option<&str>, flag: &str, columns: usize) -> String {
    let output = tracerctl().env("COLUMNS", columns.to_string()).args(sub).arg(flag).output().unwrap();
    assert!(output.status.success(), "{sub:?} {flag}: {}", stderr(&output));
    stdout(&output)
}

/// Every help text: the top level and each subcommand, `-h` and `--help`, at `columns`.
fn every_help(columns: usize) -> Vec<(String, String)> {
    let mut subs: Vec<Option<String>> = vec![None];
    subs.extend(subcommands().into_iter().map(Some));
    subs.iter()
        .flat_map(|sub| ["-h", "--help"].map(|flag| (sub.clone(), flag)))
        .map(|(sub, flag)| {
            let label = format!("tracerctl {} {flag}", sub.as_deref().unwrap_or(""));
            (label, help(sub.as_deref(), flag, columns))
        })
        .collect()
}

fn indent(line: &str) -> usize {
    line.len() - line.trim_start().len()
}

/// Lines holding one word that continue the line before (not after a heading): what a paragraph wrapped
/// twice, or wrapped badly once, leaves behind.
fn orphans(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    lines
        .windows(2)
        .filter(|pair| {
            let (previous, line) = (pair[0], pair[1]);
            let one_word = !line.trim().is_empty() && !line.trim().contains(' ');
            // The same indentation, or deeper: the second column of `-h` (`--iface <NAME>   SocketCAN ...`).
            let continues = !previous.trim().is_empty()
                && indent(previous) <= indent(line)
                && !previous.trim_end().ends_with(':');
            one_word && continues
        })
        .map(|pair| format!("{}\n{}", pair[0], pair[1]))
        .collect()
}

#[test]
fn the_orphan_check_finds_a_paragraph_wrapped_twice() {
    // What `decode --help` printed at 80 columns: a line wrapped by hand, then by clap.
    let twice = "Bad lines are reported with file:line and the reason, counted, and skipped\n(--strict \
                 stops at the first).\nsyntax up.\nthe\nnext line\n";
    assert_eq!(orphans(twice), ["syntax up.\nthe"]);
    assert!(orphans("Options:\n      --sim\n          Talk to the simulator\n").is_empty());
    let two_columns = "      --iface <NAME>   SocketCAN interface [default: $TRACERCTL_IFACE, else\n                       can0]";
    assert_eq!(orphans(two_columns).len(), 1);
}

#[test]
fn every_help_fits_80_columns_without_orphan_words() {
    // Prose is wrapped once, by clap, to the terminal; examples and key tables are written to fit 80.
    for (label, text) in every_help(80) {
        for line in text.lines() {
            let width = line.chars().count();
            assert!(width <= 80, "{label} at 80 columns: a line of {width} characters:\n{line}");
        }
        let orphans = orphans(&text);
        assert!(orphans.is_empty(), "{label} at 80 columns: orphan words:\n{}", orphans.join("\n--\n"));
    }
    // On a wide terminal prose stops at 100 columns (max_term_width), for the top level and below.
    for sub in [None, Some("doctor")] {
        let widest = help(sub, "--help", 200).lines().map(|line| line.chars().count()).max().unwrap_or(0);
        assert!((90..=100).contains(&widest), "{sub:?} at 200 columns: {widest} wide");
    }
}

#[test]
fn global_and_link_options_come_under_their_headings_after_the_commands_own() {
    let root = tracerctl::cli::command();
    for sub in root.get_subcommands() {
        let text = help(Some(sub.get_name()), "--help", 80);
        let lines: Vec<&str> = text.lines().collect();
        let heading = |name: &str| {
            lines
                .iter()
                .position(|line| *line == name)
                .unwrap_or_else(|| panic!("{}: no {name}\n{text}", sub.get_name()))
        };
        let option = |long: &str| {
            lines
                .iter()
                .position(|line| {
                    // An option's own line (indented 2 or 6), not a description mentioning it.
                    let own_line = (2..=6).contains(&indent(line)) && line.trim_start().starts_with('-');
                    own_line && line.trim_start().split([',', ' ']).any(|word| word == format!("--{long}"))
                })
                .unwrap_or_else(|| panic!("{}: --{long} missing\n{text}", sub.get_name()))
        };
        let (own, global, link) = (heading("Options:"), heading("Global options:"), heading("Link options:"));
        assert!(own < global && global < link, "{}: headings out of order\n{text}", sub.get_name());
        for long in ["protocol", "color"] {
            assert!(
                (global..link).contains(&option(long)),
                "{}: --{long} not under Global options",
                sub.get_name()
            );
        }
        for long in ["iface", "serial", "baud", "sim", "replay", "speed"] {
            assert!(option(long) > link, "{}: --{long} not under Link options", sub.get_name());
        }
        // The command's own options (unbuilt: without the global ones) all come before the global ones.
        for arg in sub.get_arguments().filter(|arg| !arg.is_hide_set()) {
            if let Some(long) = arg.get_long() {
                assert!(
                    option(long) < global,
                    "{}: its own --{long} after the global options",
                    sub.get_name()
                );
            }
        }
    }
}

#[test]
fn top_level_examples_show_the_main_tasks() {
    let text = help(None, "--help", 80);
    let examples = text.split("Examples:\n").nth(1).expect("an Examples section");
    for task in
        ["--sim dashboard", "tracerctl doctor", " drive --linear", "tracerctl monitor", "decode --summary"]
    {
        assert!(examples.contains(task), "no example of {task}:\n{examples}");
    }
    assert!(examples.contains(&format!("tracerctl decode {}", tracerctl::protocol::can::EXAMPLE_FRAME)));
    // The top-level description is the tool's, not the doc of a flattened group of options.
    assert!(
        text.starts_with("Decode, monitor, drive and diagnose the AgileX TRACER robot\n\nUsage:"),
        "{text}"
    );
}

fn man_page(name: &str) -> String {
    let _files = crate::generated::GENERATED_FILES.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/man").join(name)).unwrap()
}

#[test]
fn man_pages_have_examples_real_synopses_and_the_link_options() {
    let top = man_page("tracerctl.1");
    assert!(top.contains("\n.SH EXAMPLES\n"), "{top}");
    assert!(top.contains("tracerctl \\-\\-sim dashboard"), "{top}");
    let mut pages = vec!["tracerctl.1".to_string()];
    pages.extend(subcommands().iter().map(|sub| format!("tracerctl-{sub}.1")));
    for page in &pages {
        let text = man_page(page);
        assert!(!text.contains("EXTRA"), "{page} has an EXTRA section");
        assert!(text.contains("\n.SH \"GLOBAL OPTIONS\"\n"), "{page}: no GLOBAL OPTIONS section");
        assert!(text.contains("\n.SH \"LINK OPTIONS\"\n.TP\n\\fB\\-\\-iface\\fR"), "{page}: no LINK OPTIONS");
    }
    let drive = man_page("tracerctl-drive.1");
    assert!(drive.contains(".SH SYNOPSIS\n\\fBtracerctl drive\\fR [OPTIONS]\n"), "{drive}");
    assert!(!drive.contains("tracerctl\\-drive\\fR"), "the synopsis names the command as typed");
    for link_option in ["\\-\\-iface", "\\-\\-serial", "\\-\\-sim", "\\-\\-replay"] {
        assert!(drive.contains(&format!("\\fB{link_option}")), "tracerctl-drive.1 lacks {link_option}");
    }
    let decode = man_page("tracerctl-decode.1");
    assert!(decode.contains("\n.SH \"EXIT STATUS\"\n.PP\n0 success, 1 error"), "{decode}");
    let dashboard = man_page("tracerctl-dashboard.1");
    assert!(dashboard.contains("\n.SH KEYS\n"), "{dashboard}");
}

#[test]
fn completions_offer_the_message_names_for_msg() {
    let names = tracerctl::protocol::message::MESSAGE_NAMES.iter().chain(tracerctl::cli::FILTER_NAMES);
    let expected =
        format!("$(compgen -W \"{}\" -- \"${{cur}}\")", names.copied().collect::<Vec<_>>().join(" "));
    let bash = stdout(&tracerctl().args(["completions", "bash"]).output().unwrap());
    // decode's and monitor's --msg.
    let msg_cases: Vec<&str> = bash.split("                --msg)\n").skip(1).collect();
    assert_eq!(msg_cases.len(), 2, "{bash}");
    for case in msg_cases {
        let reply = case.lines().next().unwrap().trim();
        assert_eq!(reply, format!("COMPREPLY=({expected})"));
    }
    let fish = stdout(&tracerctl().args(["completions", "fish"]).output().unwrap());
    let msg_line = fish.lines().find(|line| line.contains("decode\" -l msg")).unwrap();
    assert!(msg_line.contains("system_state") && msg_line.contains("error_frame"), "{msg_line}");
    // --id takes identifiers, not file names.
    let id_case = bash.split("                --id)\n").nth(1).unwrap();
    assert!(!id_case.lines().next().unwrap().contains("compgen -f"), "{id_case}");
    // The names are offered, and a wrong one still gets the error that lists them.
    let output = tracerctl().args(["decode", "--msg", "odometry,odometer", "x.log"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("unknown message name 'odometer'; known: motion_command, light_command"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn an_explicit_color_always_wins_over_no_color() {
    let frame = tracerctl::protocol::can::EXAMPLE_FRAME;
    let run = |args: &[&str], no_color: Option<&str>| {
        let mut command = tracerctl();
        if let Some(value) = no_color {
            command.env("NO_COLOR", value);
        }
        stdout(&command.args(args).output().unwrap())
    };
    let always = run(&["--color", "always", "decode", frame], Some("1"));
    assert!(always.contains("\x1b["), "--color always with NO_COLOR=1: {always:?}");
    let doctor = run(&["--sim", "--color", "always", "doctor", "--listen", "300ms"], Some("1"));
    assert!(doctor.contains("\x1b["), "doctor --color always with NO_COLOR=1: {doctor:?}");
    // NO_COLOR still turns the default off (here a pipe is no terminal either), and never means never.
    assert!(!run(&["decode", frame], Some("1")).contains('\x1b'));
    assert!(!run(&["--color", "never", "decode", frame], None).contains('\x1b'));
    let help = help(None, "--help", 100);
    assert!(help.contains("an explicit always or never overrides NO_COLOR"), "{help}");
}
