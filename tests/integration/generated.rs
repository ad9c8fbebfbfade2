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

/// The man pages: `tracerctl.1` and one `tracerctl-<sub>.1` per subcommand. Generated here only: the
/// shipped binary does not carry a man-page renderer.
fn man_pages() -> std::io::Result<Vec<(String, Vec<u8>)>> {
    let root = command();
    let mut pages = Vec::new();
    let mut out = Vec::new();
    clap_mangen::Man::new(root.clone()).render(&mut out)?;
    pages.push(("tracerctl.1".to_string(), out));
    for sub in root.get_subcommands() {
        let name = format!("tracerctl-{}", sub.get_name());
        let mut out = Vec::new();
        let sub = sub.clone().name(name.clone()).version(root.get_version().unwrap_or_default().to_string());
        clap_mangen::Man::new(sub).render(&mut out)?;
        pages.push((format!("{name}.1"), out));
    }
    Ok(pages)
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

#[test]
fn completions_and_man_pages_are_fresh() {
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
