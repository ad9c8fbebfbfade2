//! `tracerctl completions <shell>`, plus the generators behind the committed completions and man pages.

use std::io::Write;
use std::path::Path;

use crate::cli::{command, CompletionsArgs};

pub fn run(args: &CompletionsArgs) -> anyhow::Result<u8> {
    let mut out = Vec::new();
    clap_complete::generate(args.shell, &mut command(), "tracerctl", &mut out);
    std::io::stdout().lock().write_all(&out)?;
    Ok(crate::exit::SUCCESS)
}

/// The committed completion files: (file name, contents).
pub fn completion_files() -> Vec<(String, Vec<u8>)> {
    use clap_complete::Shell;
    [Shell::Bash, Shell::Zsh, Shell::Fish, Shell::PowerShell, Shell::Elvish]
        .into_iter()
        .map(|shell| {
            let mut out = Vec::new();
            clap_complete::generate(shell, &mut command(), "tracerctl", &mut out);
            let name = match shell {
                Shell::Bash => "tracerctl.bash",
                Shell::Zsh => "_tracerctl",
                Shell::Fish => "tracerctl.fish",
                Shell::PowerShell => "_tracerctl.ps1",
                _ => "tracerctl.elv",
            };
            (name.to_string(), out)
        })
        .collect()
}

/// The man pages: `tracerctl.1` and one `tracerctl-<sub>.1` per subcommand.
pub fn man_pages() -> anyhow::Result<Vec<(String, Vec<u8>)>> {
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

/// Writes completions to `completions/` and man pages to `docs/man/` under `root` (used by the freshness test).
pub fn write_generated(root: &Path) -> anyhow::Result<()> {
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
