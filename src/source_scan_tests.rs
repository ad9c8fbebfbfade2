//! The source scanners' shared helper on small texts and a scratch tree.

use std::path::Path;

use crate::source_scan::{
    code_only, is_test_file, rust_files, shipped_files, string_literals, without_comments, without_test_items,
};

/// Every view keeps the file's length and lines, so positions found in one hold in the others.
fn assert_same_shape(view: &str, source: &str) {
    assert_eq!(view.len(), source.len(), "{view:?}");
    let newlines = |text: &str| text.match_indices('\n').map(|(at, _)| at).collect::<Vec<_>>();
    assert_eq!(newlines(view), newlines(source), "{view:?}");
}

#[test]
fn code_only_blanks_comments_strings_and_chars() {
    let source = "let a = 1; // one\n/* two /* nested */ still */ let b = \"s\\\"t\";\n\
                  let c = '\"'; let d = '\\''; let e = '\\u{2191}'; let f = '↑'; /// doc\n";
    let code = code_only(source);
    assert_same_shape(&code, source);
    let words: Vec<&str> = code.split_whitespace().collect();
    assert_eq!(
        words,
        [
            "let", "a", "=", "1;", "let", "b", "=", ";", "let", "c", "=", ";", "let", "d", "=", ";", "let",
            "e", "=", ";", "let", "f", "=", ";"
        ]
    );
}

#[test]
fn code_only_blanks_raw_strings_and_keeps_raw_names_and_lifetimes() {
    let source = "let a = r#\"say \"hi\" // no comment\"#; let b = br\"x\"; let c = r\"y\";\n\
                  fn f<'a>(r#type: &'a str, bar: u8) -> &'a str { r#type }\n";
    let code = code_only(source);
    assert_same_shape(&code, source);
    assert_eq!(
        code.lines().map(|line| line.split_whitespace().collect::<Vec<_>>().join(" ")).collect::<Vec<_>>(),
        ["let a = ; let b = b ; let c = ;", "fn f<'a>(r#type: &'a str, bar: u8) -> &'a str { r#type }"]
    );
}

#[test]
fn without_comments_keeps_the_literals_as_written() {
    let source = "let a = \"// not a comment\"; // a comment\nlet b = '\"'; /* gone */ let c = r\"\\d\";\n";
    let text = without_comments(source);
    assert_same_shape(&text, source);
    assert_eq!(
        text.lines().map(str::trim_end).collect::<Vec<_>>(),
        ["let a = \"// not a comment\";", "let b = '\"';            let c = r\"\\d\";"]
    );
}

#[test]
fn string_literals_give_each_body_and_its_line() {
    let source = "let a = \"one\"; // \"not\"\nlet b = '\"';\nlet c = r#\"two\n\"lines\"\"#;\n\
                  let d = b\"\\x00\"; let e = \"esc\\\"aped\";\n";
    assert_eq!(
        string_literals(source),
        [(1, "one"), (3, "two\n\"lines\""), (5, "\\x00"), (5, "esc\\\"aped")]
    );
}

#[test]
fn without_test_items_blanks_test_modules_functions_and_imports() {
    let source = "use a;\n#[cfg(test)]\nuse b;\nfn shipped() {}\n#[cfg(test)]\nmod tests {\n    \
                  fn t() { let s = \"}\"; } // }\n}\n#[cfg(all(test, unix))]\nfn helper() {}\nfn after() {}\n\
                  // a comment stays\n";
    let text = without_test_items(source);
    assert_same_shape(&text, source);
    let kept: Vec<&str> = text.lines().map(str::trim).filter(|line| !line.is_empty()).collect();
    assert_eq!(kept, ["use a;", "fn shipped() {}", "fn after() {}", "// a comment stays"]);
}

#[test]
fn the_walk_finds_rust_files_sorted_and_knows_test_files() {
    let dir = tempfile::tempdir().unwrap();
    for file in ["b.rs", "a/mod.rs", "a/x_tests.rs", "a/tests.rs", "a/z.rs", "notes.md", "a.rs"] {
        let path = dir.path().join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, "").unwrap();
    }
    let relative = |files: Vec<std::path::PathBuf>| -> Vec<String> {
        let relative =
            |path: &Path| path.strip_prefix(dir.path()).unwrap().to_string_lossy().replace('\\', "/");
        files.iter().map(|path| relative(path)).collect()
    };
    // A folder's files come before the file named after it (paths sort by component).
    assert_eq!(
        relative(rust_files(dir.path())),
        ["a/mod.rs", "a/tests.rs", "a/x_tests.rs", "a/z.rs", "a.rs", "b.rs"]
    );
    assert_eq!(relative(shipped_files(dir.path())), ["a/mod.rs", "a/z.rs", "a.rs", "b.rs"]);
    assert!(is_test_file(Path::new("src/sim/tests.rs")) && is_test_file(Path::new("catalog_tests.rs")));
    assert!(!is_test_file(Path::new("src/tests_helper.rs")) && !is_test_file(Path::new("src/contests.rs")));
}
