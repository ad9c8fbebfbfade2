//! The dependency direction of docs/architecture.md ("Layers"), checked on the sources: the crate's
//! top-level modules import each other without a circle, never upwards, nothing below `commands` imports it,
//! and clap stays in `src/cli.rs`. Test code (`#[cfg(test)]` items, `*_tests.rs`, `sim/tests.rs`) is left
//! out: a test may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use crate::source_scan::{code_only, is_test_file, rust_files, without_test_items};

/// Top layer first; a module may import its own layer (no circles, see below) and any layer below.
const LAYERS: &[&[&str]] = &[
    &["main", "cli", "fuzzing"],
    &["commands"],
    &["dashboard", "session"],
    &["link", "control", "sim", "recorder", "blackbox", "signals"],
    &["candump", "output", "exit", "config", "health"],
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

/// The module path of a file under src/: `a/b.rs` and `a/b/mod.rs` are `[a, b]`, `lib.rs` is `[]`.
fn module_path(relative: &Path) -> Vec<String> {
    let mut parts: Vec<String> =
        relative.with_extension("").iter().map(|part| part.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|last| last == "mod" || last == "lib") {
        parts.pop();
    }
    parts
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
    let files = rust_files(&src);
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

/// One module-root style: a folder module's root is its `mod.rs`, never a file named after the folder.
#[test]
fn every_folder_module_has_its_root_in_mod_rs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let files = rust_files(&root);
    let self_named: Vec<String> = files
        .iter()
        .filter(|file| file.with_extension("").is_dir())
        .map(|file| file.strip_prefix(&root).unwrap_or(file).display().to_string())
        .collect();
    assert!(self_named.is_empty(), "move these to <folder>/mod.rs: {self_named:?}");
    assert!(
        files.iter().any(|file| file.ends_with("commands/decode/parallel/mod.rs")),
        "the scan reads folders"
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

// Circles between the files of one folder.
//
// The module graph above is one node per top-level module. Inside a folder the same rule holds one level
// down: the folder's children (a file, or a subfolder taken whole) import each other without a circle, so
// each folder reads bottom-up from a leaf. The folder's root file (`mod.rs` or the self-named file) is the
// children's parent, not a sibling: it declares them and may hold the type they serve, so arrows between it
// and a child are not counted; an item it only re-exports is followed to the child that defines it.

/// One `use` leaf or path in the code: its segments as written and, for a `use` (not a `::*` one), the
/// name it binds.
#[derive(Debug, PartialEq)]
struct PathRef {
    segments: Vec<String>,
    binds: Option<String>,
    line: usize,
}

/// Skips spaces and newlines.
fn skip_blank(text: &str) -> &str {
    text.trim_start()
}

/// Parses a path or use tree at `text` (`a::b`, `a::{b, c::d as e}`, `a::*`), appending its leaves to `out`
/// after `prefix`. Returns what follows the tree.
fn parse_tree<'a>(text: &'a str, prefix: &[String], line: usize, out: &mut Vec<PathRef>) -> &'a str {
    let mut segments = prefix.to_vec();
    let mut rest = text;
    loop {
        rest = skip_blank(rest);
        if let Some(group) = rest.strip_prefix('{') {
            rest = group;
            loop {
                rest = skip_blank(rest);
                if let Some(after) = rest.strip_prefix('}') {
                    return after;
                }
                if rest.is_empty() {
                    return rest;
                }
                rest = parse_tree(rest, &segments, line, out);
                rest = skip_blank(rest);
                rest = rest.strip_prefix(',').unwrap_or(rest);
            }
        }
        if let Some(after) = rest.strip_prefix('*') {
            out.push(PathRef { segments, binds: None, line });
            return after;
        }
        let word = ident_at(rest);
        if word.is_empty() {
            // Not a path (`::<T>` turbofish, a stray token): what was read so far is the path.
            out.push(PathRef { segments, binds: None, line });
            return rest;
        }
        segments.push(word.to_string());
        rest = &rest[word.len()..];
        let after = skip_blank(rest);
        if let Some(next) = after.strip_prefix("::") {
            rest = next;
            continue;
        }
        let alias =
            after.strip_prefix("as").filter(|tail| tail.starts_with(char::is_whitespace)).map(|tail| {
                let name = ident_at(skip_blank(tail));
                rest = &skip_blank(tail)[name.len()..];
                name.to_string()
            });
        // What a `use` of this path binds: its alias, or its last segment (`a::{self}` binds `a`).
        let binds = alias.or_else(|| segments.iter().rev().find(|segment| *segment != "self").cloned());
        out.push(PathRef { segments, binds, line });
        return rest;
    }
}

/// Every path in `code` that starts at `crate` (or a name in `crate_names`), `self`, `super` or one of
/// `children` (the modules the file declares), and every `use` leaf (whatever it starts with).
fn paths_in(code: &str, crate_names: &[&str], children: &[String]) -> Vec<PathRef> {
    let line_of = |at: usize| code[..at].matches('\n').count() + 1;
    let mut found = Vec::new();
    let mut at = 0;
    while at < code.len() {
        let Some(offset) = code[at..].find(|c: char| c.is_alphabetic() || c == '_') else { break };
        let start = at + offset;
        let word = ident_at(&code[start..]);
        at = start + word.len().max(1);
        let before = code[..start].trim_end();
        if before.ends_with("::")
            || before.ends_with('$')
            || code[..start].ends_with(|c: char| c.is_alphanumeric() || c == '_')
        {
            continue;
        }
        let rest = &code[start + word.len()..];
        if word == "use" && rest.starts_with(char::is_whitespace) {
            let mut leaves = Vec::new();
            let tail =
                parse_tree(rest.trim_start().trim_start_matches("::"), &[], line_of(start), &mut leaves);
            found.extend(leaves);
            at = code.len() - tail.len();
            continue;
        }
        let starts_a_path = crate_names.contains(&word)
            || ["self", "super"].contains(&word)
            || children.iter().any(|child| child == word);
        if starts_a_path && rest.starts_with("::") {
            let mut paths = Vec::new();
            let tail = parse_tree(&code[start..], &[], line_of(start), &mut paths);
            // A path in code binds nothing.
            found.extend(paths.into_iter().map(|path| PathRef { binds: None, ..path }));
            at = code.len() - tail.len();
        }
    }
    found
}

/// The modules a file declares (`mod name;`), which it may name without `self::`.
fn declared_children(code: &str) -> Vec<String> {
    let mut children = Vec::new();
    for (at, _) in code.match_indices("mod ") {
        if code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let name = ident_at(&code[at + 4..]);
        if !name.is_empty() && code[at + 4 + name.len()..].trim_start().starts_with(';') {
            children.push(name.to_string());
        }
    }
    children
}

/// The inline modules (`mod name { ... }`) of a file: their byte range and name.
fn inline_modules(code: &str) -> Vec<(std::ops::Range<usize>, String)> {
    let mut modules = Vec::new();
    for (at, _) in code.match_indices("mod ") {
        if code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let name = ident_at(&code[at + 4..]);
        let after = &code[at + 4 + name.len()..];
        if name.is_empty() || !after.trim_start().starts_with('{') {
            continue;
        }
        let open = code.len() - after.trim_start().len();
        let mut depth = 0usize;
        let mut end = code.len();
        for (index, c) in code[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + index + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        modules.push((open..end, name.to_string()));
    }
    modules
}

/// Where a name imported by a file points: a path in the crate, or outside it (`None`).
type Imports = BTreeMap<String, Option<Vec<String>>>;

/// A non-test source file, as the file graph sees it.
struct SourceFile {
    relative: String,
    /// Its module path (`protocol/can.rs` is `[protocol, can]`).
    module: Vec<String>,
    /// The crate paths it names, absolute, with the line.
    paths: Vec<(Vec<String>, usize)>,
    imports: Imports,
}

/// `segments` as written in the module `module`, made absolute; `None` if it leaves the crate.
fn absolute(
    segments: &[String],
    module: &[String],
    crate_names: &[&str],
    children: &[String],
) -> Option<Vec<String>> {
    let (first, rest) = segments.split_first()?;
    let mut path = if crate_names.contains(&first.as_str()) {
        Vec::new()
    } else if first == "self" {
        module.to_vec()
    } else if first == "super" {
        let mut base = module.to_vec();
        base.pop();
        base
    } else if children.contains(first) {
        let mut base = module.to_vec();
        base.push(first.clone());
        base
    } else {
        return None;
    };
    for segment in rest {
        match segment.as_str() {
            "super" => {
                path.pop();
            }
            "self" => {}
            _ => path.push(segment.clone()),
        }
    }
    Some(path)
}

fn read_source_file(relative: &str, module: Vec<String>, source: &str) -> SourceFile {
    let code = without_test_items(&code_only(source));
    let children = declared_children(&code);
    let inline = inline_modules(&code);
    let mut paths = Vec::new();
    let mut imports = Imports::new();
    let mut add = |found: Vec<PathRef>, module: &[String], children: &[String], imports: &mut Imports| {
        for path in found {
            let resolved = absolute(&path.segments, module, &["crate"], children);
            if let Some(name) = &path.binds {
                imports.entry(name.clone()).or_insert(resolved.clone());
            }
            if let Some(resolved) = resolved {
                paths.push((resolved, path.line));
            }
        }
    };
    // The file outside its inline modules, then each inline module one level down.
    let mut outer = code.clone();
    for (range, _) in &inline {
        let blank: String = code[range.clone()].chars().map(|c| if c == '\n' { '\n' } else { ' ' }).collect();
        outer.replace_range(range.clone(), &blank);
    }
    add(paths_in(&outer, &["crate"], &children), &module, &children, &mut imports);
    for (range, name) in &inline {
        let mut padded: String =
            code[..range.start].chars().map(|c| if c == '\n' { '\n' } else { ' ' }).collect();
        padded.push_str(&code[range.clone()]);
        let mut inner = module.clone();
        inner.push(name.clone());
        add(paths_in(&padded, &["crate"], &[]), &inner, &[], &mut Imports::new());
    }
    SourceFile { relative: relative.to_string(), module, paths, imports }
}

/// The file a crate path lands in, following the imports of the files it passes through (a `pub use` in a
/// folder's root leads on to the child that defines the item).
fn resolve<'a>(path: &[String], files: &'a BTreeMap<Vec<String>, SourceFile>) -> Option<&'a SourceFile> {
    let mut path = path.to_vec();
    for _ in 0..8 {
        let file = (0..=path.len()).rev().find_map(|len| files.get(&path[..len]))?;
        let Some(name) = path.get(file.module.len()) else { return Some(file) };
        match file.imports.get(name) {
            Some(Some(target)) if target != &path[..=file.module.len()] => {
                path = target.iter().chain(&path[file.module.len() + 1..]).cloned().collect();
            }
            Some(None) => return None,
            _ => return Some(file),
        }
    }
    None
}

/// One arrow of a folder's graph: between two children of `folder` (a file, or a subfolder taken whole).
#[derive(Debug)]
struct FolderEdge {
    folder: String,
    edge: Edge,
}

/// The arrows between files of one folder, for every folder below the top level.
fn folder_edges(files: &BTreeMap<Vec<String>, SourceFile>) -> Vec<FolderEdge> {
    let mut edges = Vec::new();
    for file in files.values() {
        for (path, line) in &file.paths {
            let Some(target) = resolve(path, files) else { continue };
            let (from, to) = (&file.module, &target.module);
            let common = from.iter().zip(to).take_while(|(a, b)| a == b).count();
            // Within one file, between top-level modules (checked above), or to or from the folder's root.
            if common == 0 || from.len() == common || to.len() == common {
                continue;
            }
            let folder = from[..common].join("::");
            let node = |module: &[String]| format!("{folder}::{}", module[common]);
            let place = format!("src/{}:{line}", file.relative);
            edges.push(FolderEdge {
                folder: folder.clone(),
                edge: Edge { from: node(from), to: node(to), place },
            });
        }
    }
    edges
}

fn scan_files() -> BTreeMap<Vec<String>, SourceFile> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let paths = rust_files(&src);
    let mut files = BTreeMap::new();
    for path in paths {
        let relative = path.strip_prefix(&src).unwrap();
        let module = module_path(relative);
        // Test files may reach anywhere; main.rs is the binary, outside the library's folders.
        if is_test_file(relative) || module.is_empty() || module == ["main"] {
            continue;
        }
        let text = relative.to_string_lossy().replace('\\', "/");
        let source = std::fs::read_to_string(&path).unwrap();
        files.insert(module.clone(), read_source_file(&text, module, &source));
    }
    files
}

/// The circles of each folder's graph, one per folder, as readable arrows.
fn folder_cycles(edges: &[FolderEdge]) -> Vec<String> {
    let mut by_folder: BTreeMap<&str, Vec<&Edge>> = BTreeMap::new();
    for edge in edges {
        by_folder.entry(&edge.folder).or_default().push(&edge.edge);
    }
    let mut cycles = Vec::new();
    for (folder, folder_edges) in by_folder {
        let owned: Vec<Edge> = folder_edges
            .iter()
            .map(|edge| Edge { from: edge.from.clone(), to: edge.to.clone(), place: edge.place.clone() })
            .collect();
        if let Some(cycle) = find_cycle(&owned) {
            let arrows: Vec<String> =
                cycle.iter().map(|edge| format!("{} -> {} ({})", edge.from, edge.to, edge.place)).collect();
            cycles.push(format!("in {folder}:\n    {}", arrows.join("\n    ")));
        }
    }
    cycles
}

#[test]
fn the_cycle_finder_finds_a_circle_and_only_a_circle() {
    let edge = |from: &str, to: &str| Edge { from: from.into(), to: to.into(), place: format!("{from}.rs") };
    // a -> b -> c -> a, with d hanging off b: the circle is found, whichever node the search starts at.
    let edges = [edge("d", "b"), edge("a", "b"), edge("b", "c"), edge("b", "d2"), edge("c", "a")];
    let cycle = find_cycle(&edges).expect("a circle");
    let arrows: Vec<(&str, &str)> = cycle.iter().map(|edge| (edge.from.as_str(), edge.to.as_str())).collect();
    assert_eq!(arrows, [("a", "b"), ("b", "c"), ("c", "a")]);
    // A diamond (a -> b -> d, a -> c -> d) is not a circle; two arrows each way are.
    let diamond = [edge("a", "b"), edge("a", "c"), edge("b", "d"), edge("c", "d")];
    assert!(find_cycle(&diamond).is_none());
    let pair = [edge("x", "y"), edge("y", "x")];
    assert_eq!(find_cycle(&pair).map(|cycle| cycle.len()), Some(2));
}

#[test]
fn the_file_graph_follows_uses_through_the_folder_root() {
    let file = |relative: &str, source: &str| {
        let module = module_path(Path::new(relative));
        (module.clone(), read_source_file(relative, module, source))
    };
    // A fake folder `f`: its root re-exports `Item` from `leaf`; `user` takes it through the root, `leaf`
    // names `user` by its full path and the root's own `Helper` (a child using its parent: not counted).
    let files: BTreeMap<_, _> = [
        file(
            "f/mod.rs",
            "mod leaf;\nmod user;\npub use leaf::Item;\npub struct Helper;\nuse anyhow::Result;\n",
        ),
        file(
            "f/user.rs",
            "use super::{Item, Result};\n#[cfg(test)]\nmod tests { use super::super::Helper; }\n",
        ),
        file("f/leaf.rs", "pub struct Item;\nfn g() { crate::f::user::run(); super::Helper::new(); }\n"),
        file("other/mod.rs", "use crate::f::Item;\nmod inner { use super::super::f::leaf; }\n"),
    ]
    .into_iter()
    .collect();
    let arrows: Vec<(String, String)> =
        folder_edges(&files).into_iter().map(|edge| (edge.edge.from, edge.edge.to)).collect();
    let expected = [
        ("f::leaf", "f::user"),
        ("f::user", "f::leaf"), // Item, through the root; anyhow's Result is outside the crate
    ];
    let expected: Vec<(String, String)> =
        expected.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
    assert_eq!(arrows, expected);
    let cycles = folder_cycles(&folder_edges(&files));
    assert_eq!(cycles.len(), 1, "{cycles:?}");
    assert!(
        cycles[0].contains("f::leaf -> f::user") && cycles[0].contains("f::user -> f::leaf"),
        "{cycles:?}"
    );
}

#[test]
fn files_in_a_folder_import_each_other_without_circles() {
    let files = scan_files();
    let edges = folder_edges(&files);
    assert!(edges.len() > 200, "the scan found the imports inside folders ({})", edges.len());
    let cycles = folder_cycles(&edges);
    assert!(cycles.is_empty(), "import circles between the files of a folder:\n  {}", cycles.join("\n  "));
}
