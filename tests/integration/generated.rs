//! The committed completions and man pages must match what the CLI definition generates.
//! Regenerate with: TRACERCTL_BLESS=1 cargo test --test integration generated

use std::path::Path;

use clap_complete::Shell;
use tracerctl::cli::{command, completion_script};

use crate::util::{stdout, tracerctl};

/// The committed completion files: (file name, contents), as `tracerctl completions SHELL` prints them.
fn completion_files() -> Vec<(String, Vec<u8>)> {
    [
        (Shell::Bash, "tracerctl.bash"),
        (Shell::Zsh, "_tracerctl"),
        (Shell::Fish, "tracerctl.fish"),
        (Shell::PowerShell, "_tracerctl.ps1"),
        (Shell::Elvish, "tracerctl.elv"),
    ]
    .into_iter()
    .map(|(shell, name)| (name.to_string(), completion_script(shell)))
    .collect()
}

/// The man pages: `tracerctl.1` and one `tracerctl-<sub>.1` per subcommand, named as git names its pages
/// (page `tracerctl-drive`, synopsis `tracerctl drive`). Generated here only: the shipped binary does not
/// carry a man-page renderer.
fn man_pages() -> std::io::Result<Vec<(String, Vec<u8>)>> {
    // `help` is a page of its own nowhere: each page is the help.
    let mut root = command().disable_help_subcommand(true);
    // Built, each subcommand carries the global and link options and its full name (`tracerctl drive`).
    root.build();
    let mut pages = vec![("tracerctl.1".to_string(), man_page(root.clone())?)];
    for sub in root.get_subcommands() {
        let name = sub.get_display_name().unwrap_or(sub.get_name()).to_string();
        pages.push((format!("{name}.1"), man_page(sub.clone())?));
    }
    Ok(pages)
}

/// One page: clap_mangen's sections, with the after-help text (see [`AfterHelp`]) in sections of its own
/// instead of clap_mangen's `EXTRA`.
fn man_page(mut cmd: clap::Command) -> std::io::Result<Vec<u8>> {
    let after = AfterHelp::parse(&cmd.get_after_help().map(ToString::to_string).unwrap_or_default());
    let has_options = cmd.get_arguments().any(|arg| !arg.is_hide_set());
    let has_subcommands = cmd.get_subcommands().any(|sub| !sub.is_hide_set());
    // The synopsis as `--help` gives it (`tracerctl drive [OPTIONS]`), as ripgrep's page does, rather than
    // every option's name in clap_mangen's order.
    let name = cmd.get_bin_name().unwrap_or(cmd.get_name()).to_string();
    let usage = cmd.render_usage().to_string();
    let usage = usage.trim_start_matches("Usage: ").trim_start_matches(name.as_str()).to_string();
    let version = cmd.get_version().unwrap_or_default().to_string();
    let man = clap_mangen::Man::new(cmd).source(format!("tracerctl {version}"));
    let mut out = Vec::new();
    man.render_title(&mut out)?;
    man.render_name_section(&mut out)?;
    let mut roff = roff::Roff::new();
    roff.control("SH", ["SYNOPSIS"]);
    roff.text([roff::bold(name), roff::roman(usage)]);
    roff.to_writer(&mut out)?;
    man.render_description_section(&mut out)?;
    let mut roff = roff::Roff::new();
    render_blocks(&mut roff, &after.description);
    roff.to_writer(&mut out)?;
    if has_options {
        man.render_options_section(&mut out)?;
    }
    if has_subcommands {
        man.render_subcommands_section(&mut out)?;
    }
    let mut roff = roff::Roff::new();
    for (title, blocks) in &after.sections {
        roff.control("SH", [title.as_str()]);
        render_blocks(&mut roff, blocks);
    }
    roff.to_writer(&mut out)?;
    man.render_version_section(&mut out)?;
    Ok(out)
}

/// A command's after-help text in man-page sections. Its blocks are separated by blank lines; a block
/// opening with a line `Title:` starts the section TITLE (`Examples:` -> EXAMPLES) and one opening with
/// `Exit status: ...` the section EXIT STATUS; the blocks before any section extend the DESCRIPTION, those
/// after one belong to it.
#[derive(Debug, Default)]
struct AfterHelp {
    description: Vec<Vec<String>>,
    sections: Vec<(String, Vec<Vec<String>>)>,
}

impl AfterHelp {
    fn parse(text: &str) -> Self {
        let mut after = AfterHelp::default();
        let blocks = text.split("\n\n").map(|block| block.lines().map(str::to_string).collect::<Vec<_>>());
        for mut block in blocks.filter(|block| !block.is_empty()) {
            let first = block[0].clone();
            let title = if first.ends_with(':') && !first.starts_with(' ') {
                block.remove(0);
                Some(first.trim_end_matches(':').to_uppercase())
            } else if let Some(rest) = first.strip_prefix("Exit status: ") {
                block[0] = rest.to_string();
                Some("EXIT STATUS".to_string())
            } else {
                None
            };
            match (title, after.sections.last_mut()) {
                (Some(title), _) => after.sections.push((title, vec![block])),
                (None, Some((_, blocks))) => blocks.push(block),
                (None, None) => after.description.push(block),
            }
        }
        after
    }
}

/// Blocks as roff: a prose line as a filled paragraph, indented lines (examples, key tables) as written.
fn render_blocks(roff: &mut roff::Roff, blocks: &[Vec<String>]) {
    for block in blocks {
        roff.control("PP", []);
        let mut preformatted = false;
        for line in block {
            let indented = line.starts_with(' ');
            if indented != preformatted {
                roff.control(if indented { "nf" } else { "fi" }, []);
                preformatted = indented;
            }
            roff.text([roff::roman(if indented { line.strip_prefix("  ").unwrap_or(line) } else { line })]);
        }
        if preformatted {
            roff.control("fi", []);
        }
    }
}

/// Writes completions to `completions/` and man pages to `docs/man/` under `root`.
fn write_generated(root: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(root.join("completions"))?;
    std::fs::create_dir_all(root.join("docs/man"))?;
    for (name, contents) in completion_files() {
        std::fs::write(root.join("completions").join(name), contents)?;
    }
    for (name, contents) in man_pages()? {
        std::fs::write(root.join("docs/man").join(name), contents)?;
    }
    Ok(())
}

/// Held while the generated files are written or read: with TRACERCTL_BLESS the writer would otherwise race
/// the tests that read the committed files.
pub static GENERATED_FILES: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
fn completions_and_man_pages_are_fresh() {
    let _files = GENERATED_FILES.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    if std::env::var_os("TRACERCTL_BLESS").is_some() {
        write_generated(root).unwrap();
    }
    let expected = completion_files()
        .into_iter()
        .map(|(name, contents)| (root.join("completions").join(name), contents))
        .chain(
            man_pages()
                .unwrap()
                .into_iter()
                .map(|(name, contents)| (root.join("docs/man").join(name), contents)),
        );
    let mut count = 0;
    for (path, contents) in expected {
        let committed = std::fs::read(&path).unwrap_or_default();
        assert!(
            committed == contents,
            "{} is stale or missing: run `TRACERCTL_BLESS=1 cargo test --test integration generated` and commit",
            path.display()
        );
        count += 1;
    }
    assert!(count >= 5 + 3, "five shells and at least three man pages");
}

#[test]
fn completions_subcommand_prints_the_committed_script() {
    let _files = GENERATED_FILES.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (shell, file) in [("bash", "tracerctl.bash"), ("zsh", "_tracerctl"), ("fish", "tracerctl.fish")] {
        let output = tracerctl().args(["completions", shell]).output().unwrap();
        assert!(output.status.success());
        let committed = std::fs::read_to_string(root.join("completions").join(file)).unwrap();
        assert!(
            stdout(&output) == committed,
            "completions/{file} differs from `tracerctl completions {shell}`"
        );
        assert!(committed.contains("decode"), "{shell} completion knows the decode subcommand");
    }
}

/// One markdown row of docs/protocol.md §5 for a fault bit.
fn fault_row(table: tracerctl::protocol::FlagTable, info: &tracerctl::protocol::FlagInfo) -> String {
    let bit = info.mask.trailing_zeros();
    let (place, mask) = match table {
        tracerctl::protocol::FlagTable::DriverState => {
            (format!("byte 5 bit {bit}"), format!("0x{:02X}", info.mask))
        }
        _ if bit >= 8 => (format!("byte 4 bit {}", bit - 8), format!("0x{:04X}", info.mask)),
        _ => (format!("byte 5 bit {bit}"), format!("0x{:04X}", info.mask)),
    };
    format!(
        "| {place} | `{mask}` | `{}` | {} | {} | {} |",
        info.name, info.severity, info.meaning, info.action
    )
}

#[test]
fn protocol_doc_lists_every_fault_bit_as_the_code_defines_it() {
    use tracerctl::protocol::FlagTable;
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/protocol.md")).unwrap();
    for table in [FlagTable::SystemV2, FlagTable::SystemV1Serial, FlagTable::DriverState] {
        for info in table.entries() {
            let row = fault_row(table, info);
            assert!(doc.contains(&row), "docs/protocol.md lacks or has a stale row; expected:\n{row}");
        }
    }
}
