//! Every ```console example in README.md and docs/*.md is run against the real binary and must print
//! exactly what the document shows (standard error included unless the command redirects it). Every ```sh
//! block is run too, line by line, on the simulator, a replay or tests/data (exit status 0), unless the
//! line before it says why not (`<!-- sh: not run: REASON -->`, a reason this test checks against the block)
//! or how it runs (`<!-- sh: run in a new HOME ... -->`: the per-user install).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn documents() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut paths = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "md"))
        .collect();
    docs.sort();
    paths.extend(docs);
    paths
}

/// (command, expected output) pairs of one document's console blocks.
fn examples(text: &str) -> Vec<(String, String)> {
    let mut examples = Vec::new();
    for block in text.split("```console\n").skip(1) {
        let block = &block[..block.find("```").expect("closed console block")];
        let mut current: Option<(String, String)> = None;
        for line in block.lines() {
            if let Some(command) = line.strip_prefix("$ ") {
                examples.extend(current.take());
                current = Some((command.to_string(), String::new()));
            } else if let Some((_, expected)) = current.as_mut() {
                expected.push_str(line);
                expected.push('\n');
            } else {
                panic!("console block must start with '$ ': {line}");
            }
        }
        examples.extend(current);
    }
    examples
}

#[test]
fn documented_examples_print_what_the_documents_say() {
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    let bin_dir = binary.parent().unwrap();
    let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap_or_default());
    let mut checked = 0;
    let mut failures = Vec::new();
    for document in documents() {
        let text = std::fs::read_to_string(&document).unwrap();
        for (command, expected) in examples(&text) {
            let script = if command.contains("2>") { command.clone() } else { format!("{command} 2>&1") };
            let output = std::process::Command::new("bash")
                .arg("-c")
                .arg(&script)
                .current_dir(env!("CARGO_MANIFEST_DIR"))
                .env("PATH", &path)
                .env_remove("NO_COLOR")
                .output()
                .unwrap();
            let actual = String::from_utf8_lossy(&output.stdout);
            if actual != expected {
                failures.push(format!(
                    "{}: $ {command}\n--- documented\n{expected}--- actual\n{actual}",
                    document.display()
                ));
            }
            checked += 1;
        }
    }
    assert!(failures.is_empty(), "{} of {checked} examples differ:\n{}", failures.len(), failures.join("\n"));
    assert!(checked >= 20, "only {checked} examples found");
}

/// One ```sh block: the marker on the line before it (the text after `<!-- sh: `), its lines, and where.
struct ShBlock {
    marker: Option<String>,
    body: String,
    at: String,
}

fn sh_blocks(document: &Path) -> Vec<ShBlock> {
    let text = std::fs::read_to_string(document).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut blocks = Vec::new();
    for (index, line) in lines.iter().enumerate() {
        if *line != "```sh" {
            continue;
        }
        let marker = index
            .checked_sub(1)
            .and_then(|before| lines[before].strip_prefix("<!-- sh: "))
            .map(|marker| marker.trim_end_matches("-->").trim().to_string());
        let body: Vec<&str> = lines[index + 1..].iter().take_while(|line| **line != "```").copied().collect();
        blocks.push(ShBlock {
            marker,
            body: body.join("\n"),
            at: format!("{}:{}", document.display(), index + 1),
        });
    }
    blocks
}

/// Why a block is not run, and what the block must show for that reason to hold.
const NOT_RUN: &[(&str, &[&str])] = &[
    // A CAN interface or serial port of a real robot (can0 is also tracerctl's default link).
    ("robot", &["can0", "/dev/ttyUSB", "tracerctl monitor", "tracerctl doctor"]),
    // Loads kernel modules or creates interfaces.
    ("root", &["sudo "]),
    // Installs into the system or the user's home.
    ("install", &["cargo install", "dpkg -i"]),
    // Minutes of generated data, profilers, fuzzers.
    ("benchmark", &["bench", "gen_log", "valgrind", "afl", "/usr/bin/time"]),
    // The dashboard draws on a terminal until q.
    ("terminal", &["dashboard"]),
    // Runs cargo, which this suite cannot do inside its own run.
    ("cargo", &["cargo test"]),
];

/// The status a runnable line ends with when it is not 0: a simulator with an E-stop is not drivable.
const EXPECTED_STATUS: &[(&str, i32)] = &[("--fault estop@0s doctor", 4)];

/// The files the examples read, by the name the documents give them: a copy of a fixture.
fn placeholders(dir: &Path) {
    let data = |name: &str| {
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)).unwrap()
    };
    let session = data("tracer_session.log");
    for name in ["capture.log", "session.log", "candump-2024-05-01.log", "a.log", "old-robot.log"] {
        std::fs::write(dir.join(name), &session).unwrap();
    }
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    std::io::Write::write_all(&mut gz, &session).unwrap();
    std::fs::write(dir.join("b.log.gz"), gz.finish().unwrap()).unwrap();
    std::fs::write(dir.join("capture.log.zst"), zstd::encode_all(&session[..], 3).unwrap()).unwrap();
    std::fs::write(dir.join("trace.asc"), data("formats/vector.asc")).unwrap();
    for name in ["capture.bin", "uart.bin"] {
        std::fs::write(dir.join(name), data("decode/serial_xxd.txt")).unwrap();
    }
    for shared in ["tests", "docs", "completions"] {
        std::os::unix::fs::symlink(Path::new(env!("CARGO_MANIFEST_DIR")).join(shared), dir.join(shared))
            .unwrap();
    }
}

fn path_with_binary() -> String {
    let binary = assert_cmd::cargo::cargo_bin("tracerctl");
    format!("{}:{}", binary.parent().unwrap().display(), std::env::var("PATH").unwrap_or_default())
}

/// Runs `script` with bash in `dir`; (status, stdout and stderr), or a failure after `limit`. The output goes
/// to a file, so that a long one never blocks the command.
fn run_bash(
    script: &str,
    dir: &Path,
    envs: &[(&str, &str)],
    limit: Duration,
) -> Result<(i32, String), String> {
    let mut log = tempfile::tempfile().unwrap();
    let mut child = std::process::Command::new("bash")
        .arg("-c")
        .arg(script)
        .current_dir(dir)
        .env("PATH", path_with_binary())
        .envs(envs.iter().copied())
        .env_remove("NO_COLOR")
        .env_remove("TRACERCTL_IFACE")
        .stdin(std::process::Stdio::null())
        .stdout(log.try_clone().unwrap())
        .stderr(log.try_clone().unwrap())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + limit;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {limit:?}"));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut text = String::new();
    std::io::Seek::rewind(&mut log).unwrap();
    std::io::Read::read_to_string(&mut log, &mut text).unwrap();
    Ok((status.code().unwrap_or(-1), text))
}

#[cfg(unix)]
#[test]
fn every_sh_block_runs_or_says_why_not() {
    let dir = tempfile::tempdir().unwrap();
    placeholders(dir.path());
    let (mut ran, mut failures) = (0, Vec::new());
    for document in documents() {
        for block in sh_blocks(&document) {
            match block.marker.as_deref() {
                Some(marker) if marker.starts_with("not run: ") => {
                    let reason = marker["not run: ".len()..].split_whitespace().next().unwrap_or_default();
                    match NOT_RUN.iter().find(|(name, _)| *name == reason) {
                        Some((_, shows)) if shows.iter().any(|needle| block.body.contains(needle)) => {}
                        Some(_) => failures.push(format!(
                            "{}: not run for '{reason}', which the block does not show",
                            block.at
                        )),
                        None => failures.push(format!("{}: unknown reason '{reason}'", block.at)),
                    }
                }
                Some(marker) if marker.starts_with("run in a new HOME") => {}
                Some(marker) => failures.push(format!("{}: unknown marker '{marker}'", block.at)),
                None => {
                    for line in block.body.lines().filter(|line| !line.trim_start().starts_with('#')) {
                        let expected = EXPECTED_STATUS
                            .iter()
                            .find(|(text, _)| line.contains(text))
                            .map_or(0, |(_, status)| *status);
                        match run_bash(line, dir.path(), &[], Duration::from_secs(60)) {
                            Ok((status, _)) if status == expected => {}
                            Ok((status, output)) => failures.push(format!(
                                "{}: $ {line}\nexit status {status}, not {expected}:\n{output}",
                                block.at
                            )),
                            Err(why) => failures.push(format!("{}: $ {line}\n{why}", block.at)),
                        }
                        ran += 1;
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    assert!(ran >= 20, "only {ran} lines ran");
}

/// The README's per-user install, run in a new HOME: man-db finds the pages through PATH alone (no MANPATH,
/// nothing in ~/.local/bin), and a new bash completes tracerctl from ~/.bashrc without the bash-completion
/// package.
#[cfg(unix)]
#[test]
fn the_per_user_install_works_on_a_plain_system() {
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md");
    let block = sh_blocks(&readme)
        .into_iter()
        .find(|block| block.marker.as_deref().is_some_and(|marker| marker.starts_with("run in a new HOME")))
        .expect("the README's per-user install block");
    let home = tempfile::tempdir().unwrap();
    let home_text = home.path().to_str().unwrap();
    let repository = Path::new(env!("CARGO_MANIFEST_DIR"));
    let installed = run_bash(
        &format!("set -e\n{}", block.body),
        repository,
        &[("HOME", home_text)],
        Duration::from_secs(30),
    );
    assert_eq!(installed.as_ref().map(|(status, _)| *status), Ok(0), "{installed:?}");
    // `cargo install` made ~/.cargo/bin, which rustup puts on PATH.
    std::fs::create_dir_all(home.path().join(".cargo/bin")).unwrap();
    let man = std::process::Command::new("man")
        .args(["-w", "tracerctl-drive"])
        .env_clear()
        .env("HOME", home_text)
        .env("PATH", format!("{home_text}/.cargo/bin:/usr/bin:/bin"))
        .output()
        .expect("man-db is installed (apt-get install man-db)");
    let found = String::from_utf8_lossy(&man.stdout);
    assert_eq!(found.trim(), format!("{home_text}/.cargo/share/man/man1/tracerctl-drive.1"), "{man:?}");
    let completion =
        "source ~/.bashrc; COMP_WORDS=(tracerctl das); COMP_CWORD=1; _tracerctl tracerctl das tracerctl; \
                      complete -p tracerctl; echo \"${COMPREPLY[*]}\"";
    let completed = std::process::Command::new("bash")
        .args(["--norc", "-c", completion])
        .env_clear()
        .env("HOME", home_text)
        .env("PATH", "/usr/bin:/bin")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&completed.stdout);
    assert!(text.contains("-F _tracerctl tracerctl") && text.contains("dashboard dash"), "{completed:?}");
}

// docs/architecture.md is a map of src/: the checks below keep it true as files move, and short.

/// The map, read whole.
fn architecture() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/architecture.md")).unwrap()
}

/// Every `src/...` path a text names: from `src/` (at a word's start, or after `../`) up to the first
/// character no path holds, without a sentence's closing dot. A placeholder stops at its `<`:
/// `src/commands/<name>.rs` names `src/commands/`.
fn src_paths(text: &str) -> Vec<String> {
    let is_path_char = |c: char| c.is_ascii_alphanumeric() || "_./-".contains(c);
    let mut paths = Vec::new();
    for (at, _) in text.match_indices("src/") {
        let before = &text[..at];
        let starts_a_word = before.ends_with("../") || !before.ends_with(is_path_char);
        if !starts_a_word {
            continue;
        }
        let rest = &text[at..];
        let end = rest.find(|c: char| !is_path_char(c)).unwrap_or(rest.len());
        paths.push(rest[..end].trim_end_matches('.').to_string());
    }
    paths
}

/// The items of the "Map" section (a `- ` line and its indented continuation lines), each joined into one
/// line.
fn map_items(text: &str) -> Vec<String> {
    let section =
        text.split("\n## Map\n").nth(1).expect("a \"## Map\" section").split("\n## ").next().unwrap();
    let mut items: Vec<String> = Vec::new();
    let mut open = false;
    for line in section.lines() {
        if let Some(first) = line.strip_prefix("- ") {
            items.push(first.to_string());
            open = true;
        } else if open && line.starts_with("  ") {
            let item = items.last_mut().unwrap();
            item.push(' ');
            item.push_str(line.trim());
        } else {
            open = false;
        }
    }
    items
}

/// The paths an item of the map names that do not exist: its `src/...` paths, and, in an item whose first
/// path is a folder, the file and folder names in backticks (`lines.rs`, `overlays/`), taken in that folder.
fn missing_in_map_item(root: &Path, item: &str) -> Vec<String> {
    let paths = src_paths(item);
    let mut missing: Vec<String> = paths.iter().filter(|path| !root.join(path).exists()).cloned().collect();
    let Some(folder) = paths.first().filter(|path| path.ends_with('/')) else { return missing };
    let is_name_char = |c: char| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || c == '/';
    for name in item.split('`').skip(1).step_by(2) {
        let shaped = (name.ends_with(".rs") || name.ends_with('/'))
            && name.trim_end_matches(".rs").chars().all(is_name_char)
            && !name.starts_with("src/");
        if shaped && !root.join(folder).join(name).exists() {
            missing.push(format!("{folder}{name}"));
        }
    }
    missing
}

#[test]
fn the_architecture_map_names_only_paths_that_exist() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = architecture();
    let named = src_paths(&text);
    assert!(named.len() >= 30, "only {} src/ paths found in docs/architecture.md", named.len());
    let mut missing: Vec<String> = named.into_iter().filter(|path| !root.join(path).exists()).collect();
    let items = map_items(&text);
    assert!(items.len() >= 20, "only {} items found in the map", items.len());
    for item in &items {
        missing.extend(missing_in_map_item(root, item));
    }
    missing.sort();
    missing.dedup();
    assert!(
        missing.is_empty(),
        "docs/architecture.md names paths that do not exist:\n  {}",
        missing.join("\n  ")
    );
}

#[test]
fn the_architecture_map_names_every_folder_of_src_and_commands() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let named = src_paths(&architecture());
    let mut unnamed = Vec::new();
    for parent in ["src", "src/commands"] {
        for entry in std::fs::read_dir(root.join(parent)).unwrap() {
            let entry = entry.unwrap();
            if entry.file_type().unwrap().is_dir() {
                let folder = format!("{parent}/{}/", entry.file_name().to_string_lossy());
                if !named.contains(&folder) {
                    unnamed.push(folder);
                }
            }
        }
    }
    unnamed.sort();
    assert!(
        unnamed.is_empty(),
        "folders missing from docs/architecture.md (a line in its map):\n  {}",
        unnamed.join("\n  ")
    );
}

/// A map a newcomer reads in an hour: measurements go to docs/performance.md, history to CHANGELOG.md.
#[test]
fn the_architecture_map_stays_under_20_kb() {
    let size = architecture().len();
    assert!(size < 20_000, "docs/architecture.md is {size} bytes, over 20,000: move detail to module docs");
}

#[test]
fn src_paths_are_found_where_a_word_starts() {
    let text = "`src/cli.rs`, [x](../src/a/mod.rs). See src/b/. Not fuzz/src/c.rs nor mysrc/d, \
                `src/commands/<name>.rs`";
    assert_eq!(src_paths(text), ["src/cli.rs", "src/a/mod.rs", "src/b/", "src/commands/"]);
}
