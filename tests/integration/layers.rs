//! The dependency direction of docs/architecture.md ("Layers"), checked on the sources: the crate's
//! top-level modules import each other without a circle, never upwards, nothing below `commands` imports it,
//! and clap stays in `src/cli.rs`. Test code (`#[cfg(test)]` items, `*_tests.rs`, `sim/tests.rs`) is left
//! out: a test may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Top layer first; a module may import its own layer (no circles, see below) and any layer below.
const LAYERS: &[&[&str]] = &[
    &["main", "cli", "fuzzing"],
    &["commands"],
    &["dashboard", "session"],
    &["link", "control", "sim", "recorder", "signals"],
    &["candump", "output", "exit"],
    &["protocol"],
];

/// Modules that may import `crate::commands` (the command line's dispatch, the doc-hidden fuzz harness).
const COMMANDS_USERS: &[&str] = &["main", "cli", "fuzzing", "commands"];

/// One `crate::` reference: from which top-level module to which, and where.
#[derive(Debug)]
struct Edge {
    from: String,
    to: String,
    place: String,
}

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|layer| layer.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|entry| entry.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            out.push(path);
        }
    }
}

/// Test-only files, by the project's naming.
fn is_test_file(relative: &Path) -> bool {
    let name = relative.file_name().and_then(|name| name.to_str()).unwrap_or_default();
    name.ends_with("_tests.rs") || name == "tests.rs"
}

/// The module path of a file under src/: `a/b.rs` and `a/b/mod.rs` are `[a, b]`, `lib.rs` is `[]`.
fn module_path(relative: &Path) -> Vec<String> {
    let mut parts: Vec<String> =
        relative.with_extension("").iter().map(|part| part.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|last| last == "mod" || last == "lib") {
        parts.pop();
    }
    parts
}

/// The source with comments, string and char literals blanked (newlines kept, so lines still count).
#[expect(clippy::too_many_lines, reason = "one scanner: each literal and comment kind is one arm")]
fn code_only(source: &str) -> String {
    let chars: Vec<char> = source.chars().collect();
    let mut out = String::with_capacity(source.len());
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    let mut i = 0;
    while i < chars.len() {
        let at = |j: usize| chars.get(j).copied().unwrap_or('\0');
        match chars[i] {
            '/' if at(i + 1) == '/' => {
                while i < chars.len() && chars[i] != '\n' {
                    out.push(' ');
                    i += 1;
                }
            }
            '/' if at(i + 1) == '*' => {
                let mut depth = 0;
                while i < chars.len() {
                    if chars[i] == '/' && at(i + 1) == '*' {
                        depth += 1;
                        out.push_str("  ");
                        i += 2;
                    } else if chars[i] == '*' && at(i + 1) == '/' {
                        depth -= 1;
                        out.push_str("  ");
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        out.push(blank(chars[i]));
                        i += 1;
                    }
                }
            }
            'r' if (at(i + 1) == '"' || at(i + 1) == '#')
                && !chars.get(i.wrapping_sub(1)).is_some_and(|c| c.is_alphanumeric() || *c == '_') =>
            {
                // A raw string r"..." or r#"..."#.
                let mut hashes = 0;
                let mut j = i + 1;
                while chars.get(j) == Some(&'#') {
                    hashes += 1;
                    j += 1;
                }
                if chars.get(j) != Some(&'"') {
                    out.push(chars[i]);
                    i += 1;
                    continue;
                }
                let closing: String = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
                let body_start = j + 1;
                let text: String = chars[body_start..].iter().collect();
                let end =
                    text.find(&closing).map_or(chars.len(), |at| body_start + text[..at].chars().count());
                let stop = (end + closing.chars().count()).min(chars.len());
                for &c in &chars[i..stop] {
                    out.push(blank(c));
                }
                i = stop;
            }
            '"' => {
                out.push(' ');
                i += 1;
                while i < chars.len() && chars[i] != '"' {
                    if chars[i] == '\\' {
                        out.push(' ');
                        i += 1;
                    }
                    if i < chars.len() {
                        out.push(blank(chars[i]));
                        i += 1;
                    }
                }
                out.push(' ');
                i += 1;
            }
            // A char literal ('x', '\n', '\''), not a lifetime ('a).
            '\'' if at(i + 1) == '\\' || at(i + 2) == '\'' => {
                out.push(' ');
                i += 1;
                if chars.get(i) == Some(&'\\') {
                    out.push_str("  ");
                    i += 2;
                }
                while i < chars.len() && chars[i] != '\'' {
                    out.push(' ');
                    i += 1;
                }
                out.push(' ');
                i += 1;
            }
            c => {
                out.push(c);
                i += 1;
            }
        }
    }
    out
}

/// `code` without the items marked `#[cfg(test)]` (a test module, a test-only function or import).
fn without_test_items(code: &str) -> String {
    let mut out = String::with_capacity(code.len());
    let mut rest = code;
    while let Some(at) = ["#[cfg(test)]", "#[cfg(all(test"].iter().filter_map(|mark| rest.find(mark)).min() {
        out.push_str(&rest[..at]);
        let item = &rest[at..];
        // The item ends at its first `;` outside braces, or where its first brace block closes.
        let mut depth = 0usize;
        let mut end = item.len();
        for (index, c) in item.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        end = index + 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    end = index + 1;
                    break;
                }
                _ => {}
            }
        }
        out.extend(item[..end].chars().map(|c| if c == '\n' { '\n' } else { ' ' }));
        rest = &item[end..];
    }
    out.push_str(rest);
    out
}

fn ident_at(text: &str) -> &str {
    let end = text.find(|c: char| !(c.is_alphanumeric() || c == '_')).unwrap_or(text.len());
    &text[..end]
}

/// The first segment of each path in a `{a, b::c, d::{e, f}}` group starting at `text` (after the `{`).
fn group_heads(text: &str) -> Vec<String> {
    let mut heads = Vec::new();
    let mut depth = 0;
    let mut expect_head = true;
    let mut rest = text;
    while let Some(c) = rest.chars().next() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => break,
            '}' => depth -= 1,
            ',' if depth == 0 => expect_head = true,
            c if c.is_alphabetic() || c == '_' => {
                let word = ident_at(rest);
                if expect_head && depth == 0 {
                    heads.push(word.to_string());
                    expect_head = false;
                }
                rest = &rest[word.len()..];
                continue;
            }
            _ => {}
        }
        rest = &rest[c.len_utf8()..];
    }
    heads
}

/// Which top-level modules `code` (of the file at `path`, a module path) refers to, with the line.
fn references(code: &str, path: &[String], crate_names: &[&str]) -> Vec<(String, usize)> {
    let mut found = Vec::new();
    let bytes = code.as_bytes();
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    let mut at = 0;
    while at < code.len() {
        let Some(next) = code[at..].find("::").map(|offset| at + offset) else { break };
        // The word before `::`, and what follows it.
        let start = code[..next].rfind(|c: char| !(c.is_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
        let word = &code[start..next];
        let preceded_by_path = start >= 2 && &code[start - 2..start] == "::";
        at = next + 2;
        if preceded_by_path || start > 0 && bytes[start - 1] == b'$' {
            continue;
        }
        // Resolve the base: `crate` (or the library's name, in main.rs) is the root; each `super` one up.
        let mut base: Vec<String> = if crate_names.contains(&word) {
            Vec::new()
        } else if word == "super" {
            let mut base = path.to_vec();
            base.pop();
            let mut tail = &code[at..];
            while let Some(after) = tail.strip_prefix("super::") {
                base.pop();
                tail = after;
                at += "super::".len();
            }
            base
        } else {
            continue;
        };
        let tail = code[at..].trim_start();
        let heads: Vec<String> = if let Some(group) = tail.strip_prefix('{') {
            group_heads(group)
        } else {
            vec![ident_at(tail).to_string()]
        };
        for head in heads {
            let mut target = base.clone();
            target.push(head);
            if let Some(top) = target.first() {
                found.push((top.clone(), line_of(next)));
            }
        }
        base.clear();
    }
    found
}

struct Sources {
    edges: Vec<Edge>,
    /// Non-test code per file (relative path), for the clap check.
    code: BTreeMap<String, String>,
}

fn scan() -> Sources {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let modules: BTreeSet<String> = files
        .iter()
        .filter_map(|file| module_path(file.strip_prefix(&src).unwrap()).first().cloned())
        .collect();
    let mut edges = Vec::new();
    let mut code_by_file = BTreeMap::new();
    for file in &files {
        let relative = file.strip_prefix(&src).unwrap();
        if is_test_file(relative) {
            continue;
        }
        let path = module_path(relative);
        let Some(from) = path.first().cloned() else { continue }; // lib.rs only declares the modules
        let code = without_test_items(&code_only(&std::fs::read_to_string(file).unwrap()));
        // main.rs is the binary: it reaches the library by its name.
        let crate_names: &[&str] = if from == "main" { &["tracerctl"] } else { &["crate"] };
        let path = if from == "main" { Vec::new() } else { path };
        for (to, line) in references(&code, &path, crate_names) {
            if to != from && modules.contains(&to) {
                let place = format!("src/{}:{line}", relative.display());
                edges.push(Edge { from: from.clone(), to, place });
            }
        }
        code_by_file.insert(relative.display().to_string(), code);
    }
    Sources { edges, code: code_by_file }
}

/// A circle in the module graph, as `a -> b -> a` with where each arrow comes from.
fn find_cycle(edges: &[Edge]) -> Option<Vec<&Edge>> {
    let mut graph: BTreeMap<&str, Vec<&Edge>> = BTreeMap::new();
    for edge in edges {
        graph.entry(edge.from.as_str()).or_default().push(edge);
    }
    fn visit<'a>(
        node: &'a str,
        graph: &BTreeMap<&'a str, Vec<&'a Edge>>,
        stack: &mut Vec<&'a Edge>,
        done: &mut BTreeSet<&'a str>,
    ) -> Option<Vec<&'a Edge>> {
        if let Some(start) = stack.iter().position(|edge| edge.from == node) {
            return Some(stack[start..].to_vec());
        }
        if !done.insert(node) {
            return None;
        }
        for edge in graph.get(node).into_iter().flatten() {
            stack.push(edge);
            let cycle = visit(&edge.to, graph, stack, done);
            stack.pop();
            if cycle.is_some() {
                return cycle;
            }
        }
        None
    }
    let nodes: Vec<&str> = graph.keys().copied().collect();
    nodes.into_iter().find_map(|node| visit(node, &graph, &mut Vec::new(), &mut BTreeSet::new()))
}

#[test]
fn the_scanner_sees_uses_groups_and_super() {
    let code = code_only(
        "use crate::{\n    a::X,\n    b::{c, d},\n};\nuse super::e;\nfn f() { crate::g::h(); let s = \"crate::x::\"; }\n\
         // crate::comment\nuse super::super::k;\n",
    );
    let path = vec!["m".to_string(), "n".to_string()];
    let found = references(&code, &path, &["crate"]);
    let tops: Vec<(&str, usize)> = found.iter().map(|(top, line)| (top.as_str(), *line)).collect();
    // super::e is m::e (module m); super::super::k is the root's k.
    assert_eq!(tops, [("a", 1), ("b", 1), ("m", 5), ("g", 6), ("k", 8)]);
    let code =
        without_test_items("use crate::a;\n#[cfg(test)]\nmod tests {\n use crate::b;\n}\nuse crate::c;\n");
    let tops: Vec<String> = references(&code, &path, &["crate"]).into_iter().map(|(top, _)| top).collect();
    assert_eq!(tops, ["a", "c"]);
}

#[test]
fn modules_import_each_other_without_circles() {
    let sources = scan();
    assert!(sources.edges.len() > 50, "the scan found the crate's imports ({})", sources.edges.len());
    if let Some(cycle) = find_cycle(&sources.edges) {
        let arrows: Vec<String> =
            cycle.iter().map(|edge| format!("{} -> {} ({})", edge.from, edge.to, edge.place)).collect();
        panic!("an import circle between modules:\n  {}", arrows.join("\n  "));
    }
}

#[test]
fn no_module_imports_a_higher_layer() {
    let sources = scan();
    let mut offenders = Vec::new();
    for edge in &sources.edges {
        match (layer_of(&edge.from), layer_of(&edge.to)) {
            (Some(from), Some(to)) if to < from => {
                offenders.push(format!("{}: {} imports {}, a higher layer", edge.place, edge.from, edge.to))
            }
            (Some(_), Some(_)) => {}
            _ => offenders.push(format!(
                "{}: {} -> {}: add the new module to LAYERS here and to docs/architecture.md",
                edge.place, edge.from, edge.to
            )),
        }
    }
    assert!(
        offenders.is_empty(),
        "imports against the layers (docs/architecture.md):\n  {}",
        offenders.join("\n  ")
    );
}

#[test]
fn nothing_below_commands_imports_it() {
    let sources = scan();
    let offenders: Vec<String> = sources
        .edges
        .iter()
        .filter(|edge| edge.to == "commands" && !COMMANDS_USERS.contains(&edge.from.as_str()))
        .map(|edge| format!("{}: {} imports commands", edge.place, edge.from))
        .collect();
    assert!(
        offenders.is_empty(),
        "only the command line dispatches to commands:\n  {}",
        offenders.join("\n  ")
    );
}

#[test]
fn clap_stays_in_the_command_line() {
    let sources = scan();
    let mut offenders = Vec::new();
    for (file, code) in &sources.code {
        if file == "cli.rs" {
            continue;
        }
        for (number, line) in code.lines().enumerate() {
            let mentions = line
                .match_indices("clap::")
                .any(|(at, _)| !line[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_'))
                || line
                    .trim_start()
                    .strip_prefix("use clap")
                    .is_some_and(|rest| !rest.starts_with(|c: char| c.is_alphanumeric() || c == '_'));
            if mentions {
                offenders.push(format!("src/{file}:{}: {}", number + 1, line.trim()));
            }
        }
    }
    assert!(offenders.is_empty(), "clap outside src/cli.rs:\n  {}", offenders.join("\n  "));
}
