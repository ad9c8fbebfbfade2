//! No function in `src/` is longer than 80 lines (issue 12), unless the line directly above it (above its
//! attributes and doc comments) is a comment `// Long: <why>`. Test code is left out: `#[cfg(test)] mod`
//! blocks, `*_tests.rs` files and `src/sim/tests.rs`.
//!
//! A function's length is counted from the line of `fn` to the line of the brace that closes its body,
//! both included. Braces are matched on the source with comments and the contents of string and
//! character literals (raw strings too) blanked out, so a `"{"` or a `'}'` does not count.

use std::path::{Path, PathBuf};

/// The longest a function may be without a `// Long:` comment.
const MAX_LINES: usize = 80;

/// A function longer than `MAX_LINES` without a reason.
#[derive(Debug, PartialEq)]
struct LongFunction {
    /// 1-based line of `fn`.
    line: usize,
    name: String,
    lines: usize,
}

#[test]
fn no_function_in_src_is_longer_than_80_lines_without_a_reason() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut offenders = Vec::new();
    for path in rust_files(&root.join("src")) {
        let relative = path.strip_prefix(root).unwrap_or(&path).to_string_lossy().replace('\\', "/");
        if is_test_file(&relative) {
            continue;
        }
        let source = std::fs::read_to_string(&path).unwrap();
        for long in long_functions(&source) {
            offenders.push(format!("{relative}:{} {} {} lines", long.line, long.name, long.lines));
        }
    }
    assert!(
        offenders.is_empty(),
        "{} functions are longer than {MAX_LINES} lines; split them, or put a `// Long: <why>` comment \
         directly above one that must stay long:\n{}",
        offenders.len(),
        offenders.join("\n")
    );
}

fn is_test_file(relative: &str) -> bool {
    relative.ends_with("_tests.rs") || relative == "src/sim/tests.rs"
}

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|entry| entry.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            files.push(path);
        }
    }
    files
}

/// The functions of one file longer than `MAX_LINES` without a `// Long:` comment, outside test modules.
fn long_functions(source: &str) -> Vec<LongFunction> {
    let code = blank_comments_and_literals(source);
    let lines: Vec<&str> = source.lines().collect();
    let test_modules = test_module_spans(&code);
    let mut found = Vec::new();
    for (start, name) in fn_items(&code) {
        if test_modules.iter().any(|span| span.contains(&start)) {
            continue;
        }
        let Some(end) = body_end(&code, start) else { continue };
        let first_line = line_of(&code, start);
        let length = line_of(&code, end) - first_line + 1;
        if length > MAX_LINES && !has_long_reason(&lines, first_line) {
            found.push(LongFunction { line: first_line, name, lines: length });
        }
    }
    found
}

/// The source with every comment and the contents of every string and character literal replaced by
/// spaces (line breaks kept), so that only code remains and byte offsets and line numbers are unchanged.
fn blank_comments_and_literals(source: &str) -> Vec<u8> {
    let bytes = source.as_bytes();
    let mut code = bytes.to_vec();
    let mut i = 0;
    while i < bytes.len() {
        let rest = &bytes[i..];
        let after_ident = i > 0 && is_ident(bytes[i - 1]);
        let end = if rest.starts_with(b"//") {
            rest.iter().position(|&b| b == b'\n').map_or(bytes.len(), |n| i + n)
        } else if rest.starts_with(b"/*") {
            block_comment_end(bytes, i)
        } else if let Some(end) = raw_string_end(bytes, i).filter(|_| !after_ident) {
            end
        } else if rest[0] == b'"' {
            string_end(bytes, i)
        } else if rest[0] == b'\'' {
            match char_literal_end(bytes, i) {
                Some(end) => end,
                None => {
                    i += 1; // A lifetime or a label.
                    continue;
                }
            }
        } else {
            i += 1;
            continue;
        };
        for byte in &mut code[i..end] {
            if *byte != b'\n' {
                *byte = b' ';
            }
        }
        i = end.max(i + 1);
    }
    code
}

fn is_ident(byte: u8) -> bool {
    byte.is_ascii_alphanumeric() || byte == b'_' || byte >= 0x80
}

/// The end (exclusive) of a block comment starting at `start`; block comments nest.
fn block_comment_end(bytes: &[u8], start: usize) -> usize {
    let (mut depth, mut i) = (0usize, start);
    while i < bytes.len() {
        if bytes[i..].starts_with(b"/*") {
            depth += 1;
            i += 2;
        } else if bytes[i..].starts_with(b"*/") {
            depth -= 1;
            i += 2;
            if depth == 0 {
                return i;
            }
        } else {
            i += 1;
        }
    }
    bytes.len()
}

/// The end (exclusive) of a string literal whose opening quote is at `start`.
fn string_end(bytes: &[u8], start: usize) -> usize {
    let mut i = start + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    bytes.len()
}

/// A raw string (`r"…"`, `r#"…"#`, `br##"…"##`, `cr"…"`) starting at `start`: its end (exclusive).
fn raw_string_end(bytes: &[u8], start: usize) -> Option<usize> {
    let mut i = start;
    if matches!(bytes[i], b'b' | b'c') {
        i += 1;
    }
    if bytes.get(i) != Some(&b'r') {
        return None;
    }
    i += 1;
    let hashes = bytes[i..].iter().take_while(|&&b| b == b'#').count();
    i += hashes;
    if bytes.get(i) != Some(&b'"') {
        return None;
    }
    let closing: Vec<u8> = std::iter::once(b'"').chain(std::iter::repeat_n(b'#', hashes)).collect();
    let body = i + 1;
    Some(
        bytes[body..]
            .windows(closing.len())
            .position(|w| w == closing)
            .map_or(bytes.len(), |n| body + n + closing.len()),
    )
}

/// A character literal (`'x'`, `'\n'`, `'\u{7FF}'`, `'é'`) whose quote is at `start`: its end (exclusive);
/// `None` for a lifetime or a label (`'a`, `'static`, `'outer:`).
fn char_literal_end(bytes: &[u8], start: usize) -> Option<usize> {
    let next = *bytes.get(start + 1)?;
    if next == b'\\' {
        // The escaped character is skipped: `'\''` ends at the second quote after the backslash.
        let close = bytes.get(start + 3..)?.iter().position(|&b| b == b'\'')?;
        return Some(start + 3 + close + 1);
    }
    // One character, possibly several bytes of UTF-8, then the closing quote.
    let width = match next {
        0x00..=0x7F => 1,
        0xC0..=0xDF => 2,
        0xE0..=0xEF => 3,
        _ => 4,
    };
    (bytes.get(start + 1 + width) == Some(&b'\'')).then_some(start + 2 + width)
}

/// Every `fn NAME` item in the code: the offset of `fn` and the name. Function-pointer types (`fn(u8)`)
/// have no name and are left out.
fn fn_items(code: &[u8]) -> Vec<(usize, String)> {
    let mut items = Vec::new();
    for start in keyword_offsets(code, b"fn") {
        let mut i = start + 2;
        while i < code.len() && code[i].is_ascii_whitespace() {
            i += 1;
        }
        let name_end = i + code[i..].iter().take_while(|&&b| is_ident(b)).count();
        if name_end > i && !code[i].is_ascii_digit() {
            items.push((start, String::from_utf8_lossy(&code[i..name_end]).into_owned()));
        }
    }
    items
}

/// Offsets of a keyword standing alone (not part of a longer identifier).
fn keyword_offsets(code: &[u8], keyword: &[u8]) -> Vec<usize> {
    (0..code.len().saturating_sub(keyword.len() - 1))
        .filter(|&i| {
            code[i..].starts_with(keyword)
                && (i == 0 || !is_ident(code[i - 1]))
                && code.get(i + keyword.len()).is_none_or(|&b| !is_ident(b))
        })
        .collect()
}

/// The offset of the brace closing the body of the item that starts at `start`; `None` for an item with
/// no body (a trait method's declaration ends at `;`).
fn body_end(code: &[u8], start: usize) -> Option<usize> {
    let mut nesting = 0i32; // Parentheses and brackets of the signature: `[u8; 4]` holds a `;`.
    let mut i = start;
    while i < code.len() {
        match code[i] {
            b'(' | b'[' => nesting += 1,
            b')' | b']' => nesting -= 1,
            b';' if nesting == 0 => return None,
            b'{' if nesting == 0 => return matching_brace(code, i),
            _ => {}
        }
        i += 1;
    }
    None
}

/// The offset of the `}` matching the `{` at `open`.
fn matching_brace(code: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (i, &byte) in code.iter().enumerate().skip(open) {
        match byte {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(i);
                }
            }
            _ => {}
        }
    }
    None
}

/// The byte ranges of `#[cfg(test)] mod NAME { … }` blocks (other attributes may stand between).
fn test_module_spans(code: &[u8]) -> Vec<std::ops::Range<usize>> {
    let mut spans = Vec::new();
    let text = String::from_utf8_lossy(code);
    for (at, _) in text.match_indices("#[cfg(test)]") {
        let mut i = at + "#[cfg(test)]".len();
        loop {
            while i < code.len() && code[i].is_ascii_whitespace() {
                i += 1;
            }
            // Skip further attributes.
            if code[i..].starts_with(b"#[") {
                let Some(close) = code[i..].iter().position(|&b| b == b']') else { break };
                i += close + 1;
                continue;
            }
            break;
        }
        let rest = &text[i..];
        let item = rest.strip_prefix("pub(crate) ").or_else(|| rest.strip_prefix("pub ")).unwrap_or(rest);
        if !item.starts_with("mod ") {
            continue;
        }
        let head_end = i + rest.find(['{', ';']).unwrap_or(rest.len());
        if code.get(head_end) == Some(&b'{') {
            if let Some(close) = matching_brace(code, head_end) {
                spans.push(at..close + 1);
            }
        }
    }
    spans
}

/// 1-based line of a byte offset.
fn line_of(code: &[u8], offset: usize) -> usize {
    code[..offset].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Whether the line directly above the function's attributes and doc comments is `// Long: <reason>`.
fn has_long_reason(lines: &[&str], fn_line: usize) -> bool {
    let mut index = fn_line - 1; // 0-based index of the fn line
    while index > 0 {
        let above = lines[index - 1].trim();
        if above.starts_with("///") || above.starts_with("#[") {
            index -= 1;
        } else if above.ends_with(']') {
            // The last line of an attribute written over several lines: go to its `#[`.
            match lines[..index - 1].iter().rposition(|line| line.trim().starts_with("#[")) {
                Some(opening) => index = opening,
                None => return false,
            }
        } else {
            return above.strip_prefix("// Long:").is_some_and(|reason| !reason.trim().is_empty());
        }
    }
    false
}

/// A function named `name` with `body_lines` copies of `body_line` as its body.
fn function(name: &str, body_lines: usize, body_line: &str) -> String {
    format!("fn {name}() {{\n{}}}\n", format!("    {body_line}\n").repeat(body_lines))
}

#[test]
fn counts_from_fn_to_the_closing_brace() {
    // 79 body lines + the two brace lines = 81: too long; 78 + 2 = 80: allowed.
    let source = format!("{}{}", function("long", 79, "x();"), function("fits", 78, "x();"));
    assert_eq!(long_functions(&source), [LongFunction { line: 1, name: "long".into(), lines: 81 }]);
}

#[test]
fn braces_in_literals_and_comments_do_not_count() {
    let tricky = [
        r#"let s = "}}}";"#,
        r##"let r = r#"}" }"#;"##,
        r"let c = '}';",
        r"let e = '\'';",
        r"let u = '\u{7D}';",
        r"// }",
        r"/* } /* nested } */ } */",
        r#"let b = b"}";"#,
        r"fn inner<'a>(x: &'a str) -> &'a str { x }",
    ];
    let body: String = tricky.iter().map(|line| format!("    {line}\n")).collect::<String>().repeat(10);
    let source = format!("fn tricky() {{\n{body}}}\nfn after() {{\n}}\n");
    let found = long_functions(&source);
    assert_eq!(found, [LongFunction { line: 1, name: "tricky".into(), lines: 92 }]);
}

#[test]
fn a_long_comment_above_the_attributes_and_docs_allows_it() {
    let body = function("dispatch", 90, "x();");
    let allowed = format!("// Long: one arm per command, each a call\n/// Docs.\n#[inline]\n#[allow(\n    dead_code\n)]\n{body}");
    assert_eq!(long_functions(&allowed), []);
    let no_reason = format!("// Long:\n{body}");
    assert_eq!(long_functions(&no_reason).len(), 1);
    let between = format!("// Long: why\n// something else\n{body}");
    assert_eq!(long_functions(&between).len(), 1);
}

#[test]
fn test_modules_and_declarations_are_left_out() {
    let source = format!(
        "trait T {{\n    fn declared(&self, x: [u8; 4]);\n}}\n#[cfg(test)]\n#[allow(unused)]\nmod tests {{\n{}}}\n{}",
        function("in_tests", 100, "x();"),
        function("outside", 100, "x();")
    );
    let found = long_functions(&source);
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].name, "outside");
    assert!(is_test_file("src/candump/line_tests.rs") && is_test_file("src/sim/tests.rs"));
    assert!(!is_test_file("src/commands/drive.rs"));
}
