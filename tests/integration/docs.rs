//! Every ```console example in README.md and docs/*.md is run against the real binary and must print
//! exactly what the document shows (standard error included unless the command redirects it).

use std::path::{Path, PathBuf};

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
