//! What the source scanners share (the layering test, the catalog identifiers, the battery thresholds, the
//! keys named on screen): the .rs files under src/, which of them are test code, and a file's text with its
//! comments, literals or test items blanked. Blanking keeps every newline and every byte offset, so line
//! numbers and positions found in one view hold in the others and in the file.
//!
//! Test-only: the library declares it under `#[cfg(test)]` and the integration tests include it by path.

use std::ops::Range;
use std::path::{Path, PathBuf};

/// Every .rs file under `dir`, sorted by path.
pub(crate) fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    collect_rust_files(dir, &mut found);
    found.sort();
    found
}

fn collect_rust_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|error| panic!("{}: {error}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            collect_rust_files(&path, found);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            found.push(path);
        }
    }
}

/// A test-only file, by the project's naming: `*_tests.rs` or `tests.rs`.
pub(crate) fn is_test_file(path: &Path) -> bool {
    let name = path.file_name().and_then(|name| name.to_str()).unwrap_or_default();
    name.ends_with("_tests.rs") || name == "tests.rs"
}

/// The .rs files under `dir` that ship: [`rust_files`] without the test files.
pub(crate) fn shipped_files(dir: &Path) -> Vec<PathBuf> {
    rust_files(dir).into_iter().filter(|path| !is_test_file(path)).collect()
}

/// `source` with its comments, string and character literals blanked.
pub(crate) fn code_only(source: &str) -> String {
    blanked(source, pieces(source).iter().map(|piece| piece.whole.clone()))
}

/// `source` with its comments blanked and its literals as written.
pub(crate) fn without_comments(source: &str) -> String {
    let comments = pieces(source).into_iter().filter(|piece| piece.kind == Kind::Comment);
    blanked(source, comments.map(|piece| piece.whole))
}

/// The string literals of `source` (raw and byte strings too): each one's line and its text between the
/// quotes, escapes as written.
pub(crate) fn string_literals(source: &str) -> Vec<(usize, &str)> {
    pieces(source)
        .into_iter()
        .filter(|piece| piece.kind == Kind::Str)
        .map(|piece| (line_at(source, piece.body.start), &source[piece.body]))
        .collect()
}

/// `source` without the items marked `#[cfg(test)]` or `#[cfg(all(test, ...))]` (a test module, a
/// test-only function or import); its comments and literals stay.
pub(crate) fn without_test_items(source: &str) -> String {
    blanked(source, test_items(&code_only(source)))
}

/// The 1-based line of byte `at`.
fn line_at(source: &str, at: usize) -> usize {
    source[..at].matches('\n').count() + 1
}

/// `source` with every byte of `ranges` but its newlines made a space.
fn blanked(source: &str, ranges: impl IntoIterator<Item = Range<usize>>) -> String {
    let mut bytes = source.as_bytes().to_vec();
    for range in ranges {
        for byte in &mut bytes[range] {
            if *byte != b'\n' {
                *byte = b' ';
            }
        }
    }
    // Each range covers whole characters, so blanking leaves valid UTF-8.
    String::from_utf8(bytes).expect("blanked whole characters")
}

/// The byte ranges of the test items in `code` (comments and literals already blanked, so a brace or a
/// semicolon is the code's own). An item ends at its first `;` outside braces, or where its first brace
/// block closes.
fn test_items(code: &str) -> Vec<Range<usize>> {
    let mut items = Vec::new();
    let mut from = 0;
    while let Some(start) =
        ["#[cfg(test)]", "#[cfg(all(test"].iter().filter_map(|mark| code[from..].find(mark)).min()
    {
        let start = from + start;
        let mut depth = 0usize;
        let mut end = code.len();
        for (index, byte) in code.bytes().enumerate().skip(start) {
            match byte {
                b'{' => depth += 1,
                b'}' => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        end = index + 1;
                        break;
                    }
                }
                b';' if depth == 0 => {
                    end = index + 1;
                    break;
                }
                _ => {}
            }
        }
        items.push(start..end);
        from = end;
    }
    items
}

/// What a comment or literal is, to a scanner.
#[derive(PartialEq)]
enum Kind {
    Comment,
    Str,
    Char,
}

/// One comment or literal of a source: its whole extent and, for a string, the text between its quotes.
struct Piece {
    kind: Kind,
    whole: Range<usize>,
    body: Range<usize>,
}

/// The comments and literals of `source`, in order. Everything between them is code.
fn pieces(source: &str) -> Vec<Piece> {
    let bytes = source.as_bytes();
    let mut found = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let piece = match (bytes[at], bytes.get(at + 1)) {
            (b'/', Some(b'/')) => Some(line_comment(bytes, at)),
            (b'/', Some(b'*')) => Some(block_comment(bytes, at)),
            (b'r', _) => raw_string(bytes, at),
            (b'"', _) => Some(string(bytes, at)),
            (b'\'', _) => char_literal(source, at),
            _ => None,
        };
        // Every delimiter is ASCII, so stepping one byte never lands a match inside a character.
        match piece {
            Some(piece) => {
                at = piece.whole.end;
                found.push(piece);
            }
            None => at += 1,
        }
    }
    found
}

/// `// ...` up to its newline (the newline is code).
fn line_comment(bytes: &[u8], start: usize) -> Piece {
    let end = bytes[start..].iter().position(|&byte| byte == b'\n').map_or(bytes.len(), |at| start + at);
    Piece { kind: Kind::Comment, whole: start..end, body: start..end }
}

/// `/* ... */`, nested ones included.
fn block_comment(bytes: &[u8], start: usize) -> Piece {
    let mut depth = 0;
    let mut at = start;
    while at < bytes.len() {
        match &bytes[at..] {
            [b'/', b'*', ..] => {
                depth += 1;
                at += 2;
            }
            [b'*', b'/', ..] => {
                depth -= 1;
                at += 2;
                if depth == 0 {
                    break;
                }
            }
            _ => at += 1,
        }
    }
    let end = at.min(bytes.len());
    Piece { kind: Kind::Comment, whole: start..end, body: start..end }
}

/// `"..."`, with its escapes (`\"` does not close it).
fn string(bytes: &[u8], start: usize) -> Piece {
    let mut at = start + 1;
    while at < bytes.len() && bytes[at] != b'"' {
        at += if bytes[at] == b'\\' { 2 } else { 1 };
    }
    let body_end = at.min(bytes.len());
    let end = (at + 1).min(bytes.len());
    Piece { kind: Kind::Str, whole: start..end, body: start + 1..body_end }
}

/// `r"..."` or `r#"..."#` (also after `b` or `c`); `None` for an `r` that starts no raw string (`r#type`, a
/// name ending in r).
fn raw_string(bytes: &[u8], start: usize) -> Option<Piece> {
    let ident = |at: Option<usize>| {
        at.and_then(|at| bytes.get(at)).is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_')
    };
    let before = start.checked_sub(1);
    let prefixed = before.is_some_and(|at| matches!(bytes[at], b'b' | b'c'))
        && !ident(before.and_then(|at| at.checked_sub(1)));
    if ident(before) && !prefixed {
        return None;
    }
    let hashes = bytes[start + 1..].iter().take_while(|&&byte| byte == b'#').count();
    let open = start + 1 + hashes;
    if bytes.get(open) != Some(&b'"') {
        return None;
    }
    let body_start = open + 1;
    let closes = |at: usize| {
        bytes[at] == b'"'
            && bytes.get(at + 1..at + 1 + hashes).is_some_and(|tail| tail.iter().all(|&byte| byte == b'#'))
    };
    let body_end = (body_start..bytes.len()).find(|&at| closes(at)).unwrap_or(bytes.len());
    let end = (body_end + 1 + hashes).min(bytes.len());
    Some(Piece { kind: Kind::Str, whole: start..end, body: body_start..body_end })
}

/// `'x'`, `'\n'`, `'\''`, `'\u{2191}'`, `'↑'`; `None` for a lifetime (`'a`).
fn char_literal(source: &str, start: usize) -> Option<Piece> {
    let bytes = source.as_bytes();
    let first = source[start + 1..].chars().next()?;
    let end = if first == '\\' {
        // The escaped character, then up to the closing quote (`\u{...}` is longer).
        let after = start + 3;
        after + bytes.get(after..)?.iter().position(|&byte| byte == b'\'')? + 1
    } else if bytes.get(start + 1 + first.len_utf8()) == Some(&b'\'') {
        start + 2 + first.len_utf8()
    } else {
        return None;
    };
    Some(Piece { kind: Kind::Char, whole: start..end, body: start + 1..end - 1 })
}
