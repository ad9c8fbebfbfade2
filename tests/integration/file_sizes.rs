//! No file under src/ is longer than 800 lines before its tests (issue 30): a folder's worth of code gets a
//! folder. cli.rs, the declarative clap definition, is the exception; test files (`*_tests.rs`, `tests.rs`)
//! are not counted.

use std::path::{Path, PathBuf};

const MAX_LINES: usize = 800;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            out.push(path);
        }
    }
}

/// Lines before the first `#[cfg(test)]` at the start of a line (all of them when there is none).
fn lines_before_tests(source: &str) -> usize {
    source.lines().take_while(|line| !line.starts_with("#[cfg(test)]")).count()
}

#[test]
fn no_source_file_is_longer_than_800_lines_before_its_tests() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut long: Vec<String> = files
        .iter()
        .filter(|path| {
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            name != "tests.rs" && !name.ends_with("_tests.rs") && !path.ends_with("src/cli.rs")
        })
        .filter_map(|path| {
            let lines = lines_before_tests(&std::fs::read_to_string(path).unwrap());
            (lines > MAX_LINES)
                .then(|| format!("{} ({lines} lines)", path.strip_prefix(&src).unwrap().display()))
        })
        .collect();
    long.sort();
    assert!(long.is_empty(), "split these into a folder of smaller files: {long:?}");
    assert!(files.len() > 100, "the scan reads src/: {} files", files.len());
}

#[test]
fn the_count_stops_at_the_tests() {
    assert_eq!(lines_before_tests("a\nb\n#[cfg(test)]\nmod tests {}\n"), 2);
    assert_eq!(lines_before_tests("a\nb\n    #[cfg(test)]\nc\n"), 4, "only a test module at the top level");
}
