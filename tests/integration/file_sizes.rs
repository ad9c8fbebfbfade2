//! No file under src/ is longer than 800 lines before its tests (issue 30): a folder's worth of code gets a
//! folder. cli.rs, the declarative clap definition, is the exception; test files (`*_tests.rs`, `tests.rs`)
//! are not counted.

use std::path::Path;

use crate::source_scan::shipped_files;

const MAX_LINES: usize = 800;

/// Lines before the first `#[cfg(test)]` at the start of a line (all of them when there is none).
fn lines_before_tests(source: &str) -> usize {
    source.lines().take_while(|line| !line.starts_with("#[cfg(test)]")).count()
}

#[test]
fn no_source_file_is_longer_than_800_lines_before_its_tests() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let files = shipped_files(&src);
    let mut long: Vec<String> = files
        .iter()
        .filter(|path| !path.ends_with("src/cli.rs"))
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
