//! Keys named by hand (issue 28): "press m to enable it" named the back-left arc key as command mode, and
//! an operator who did as told drove backwards. Shipped code names keys only through the key table
//! (`keys::key_name`, the footer, the help): a string literal that names a key fails here. The docs may
//! name keys, but what they say a key does must be what the table says it does.

use std::path::Path;

use super::keys::{Action, BINDINGS};
use crate::source_scan::{self, shipped_files, without_test_items};

/// Verbs that say what a key does when they follow it: `a disarms`, `q quits`.
const VERBS: [&str; 12] = [
    "arms", "disarms", "quits", "asks", "enables", "clears", "stops", "drives", "cycles", "toggles",
    "closes", "suspends",
];

/// Words before a key that make it a key: `press m`.
const PRESS: [&str; 6] = ["press", "presses", "pressed", "pressing", "hit", "type"];

/// A key named in prose, and the words that say what it does (empty when nothing does).
#[derive(Debug, PartialEq)]
struct Mention {
    key: String,
    does: Vec<String>,
}

/// The keys as the table shows them (`e`, `Space`, `?`), the ones that could be named in prose.
fn key_tokens() -> Vec<&'static str> {
    let mut tokens: Vec<&str> = BINDINGS
        .iter()
        .flat_map(|row| row.shown.split_whitespace())
        .filter(|token| *token != "..." && token.chars().all(|c| c.is_ascii_graphic()))
        .collect();
    tokens.extend(["Enter", "Tab", "Esc", "Space", "Home", "PgUp", "End", "PgDn"]);
    tokens.sort_unstable();
    tokens.dedup();
    tokens
}

/// A word of prose: without backticks and, beyond its first character, trailing punctuation.
#[derive(Debug)]
struct Word<'a> {
    text: &'a str,
    /// The text as written (`` `m`, `` or `(command`).
    raw: &'a str,
}

fn words(text: &str) -> Vec<Word<'_>> {
    text.split_whitespace()
        .filter(|raw| *raw != "\\")
        .map(|raw| {
            let mut text = raw.trim_start_matches(['(', '"', '`', '*']);
            while text.chars().count() > 1 && text.ends_with([',', ';', ':', '.', ')', '"', '`', '*', '!']) {
                text = &text[..text.len() - 1];
            }
            Word { text: text.trim_end_matches('`'), raw }
        })
        .collect()
}

/// Every key named in `text`: after "press", before "to VERB" or a verb of [`VERBS`], in a list sharing
/// one verb (`e, c or l asks`), backticked before a parenthesis (`` `m` (command mode) ``) or after "is"
/// (``command mode is `e` ``). "press a key" is the article, not the key.
fn mentions(text: &str, tokens: &[&str]) -> Vec<Mention> {
    let words = words(text);
    // A key's name (`Space`, `Esc`) in any case; a one-character key exactly.
    let is_key = |at: usize| {
        words.get(at).is_some_and(|word| {
            tokens.iter().any(|token| {
                *token == word.text || (token.len() > 1 && token.eq_ignore_ascii_case(word.text))
            })
        })
    };
    let lower = |at: usize| words.get(at).map(|word| word.text.to_ascii_lowercase()).unwrap_or_default();
    let mut found = Vec::new();
    let mut at = 0;
    while at < words.len() {
        if !is_key(at) {
            at += 1;
            continue;
        }
        // A list of keys sharing what follows it: `e, c or l asks`, `a, y arm`.
        let mut keys = vec![at];
        let mut next = at + 1;
        while words[next - 1].raw.ends_with(',') || matches!(lower(next).as_str(), "or" | "and") {
            let candidate = if matches!(lower(next).as_str(), "or" | "and") { next + 1 } else { next };
            if !is_key(candidate) {
                break;
            }
            keys.push(candidate);
            next = candidate + 1;
        }
        let pressed = at > 0 && PRESS.contains(&lower(at - 1).as_str());
        let article =
            words[at].text == "a" && matches!(lower(next).as_str(), "key" | "fresh" | "new" | "drive");
        let backticked = words[at].raw.trim_start_matches('(').starts_with('`');
        // `the m key enables`: the word "key" between the key and its verb.
        if lower(next) == "key" && VERBS.contains(&lower(next + 1).as_str()) {
            next += 1;
        }
        let to_verb = lower(next) == "to" && !matches!(lower(next + 1).as_str(), "" | "the" | "a" | "an");
        let does: Option<Vec<String>> = if to_verb {
            Some(vec![lower(next + 1)])
        } else if VERBS.contains(&lower(next).as_str()) || (keys.len() > 1 && lower(next) == "arm") {
            Some(vec![lower(next)])
        } else if backticked && words.get(next).is_some_and(|word| word.raw.starts_with('(')) {
            let inside = words[next..].iter().position(|word| word.raw.ends_with(')')).unwrap_or(0);
            Some((next..=next + inside).map(lower).collect())
        } else if backticked && at >= 2 && lower(at - 1) == "is" {
            Some(vec![lower(at - 2)])
        } else if (pressed && !article) || parenthesized(words[at].raw) {
            // `press e`; a key's own name in parentheses: `zero sent (Space)`.
            Some(Vec::new())
        } else {
            None
        };
        match does {
            Some(does) if !article => found.extend(
                keys.iter().map(|&key| Mention { key: words[key].text.to_string(), does: does.clone() }),
            ),
            _ => {}
        }
        at = next.max(at + 1);
    }
    found
}

/// A key alone in parentheses: `(Space)`, `(e)`, `` (`e`) ``.
fn parenthesized(raw: &str) -> bool {
    raw.starts_with('(') && raw.trim_end_matches([',', ';', ':', '.']).ends_with(')')
}

/// Words that say nothing of what a key does.
const STOP_WORDS: [&str; 14] =
    ["to", "the", "a", "an", "key", "keys", "and", "or", "of", "it", "then", "at", "is", "once"];

/// What the table says a key does, in lower-case words: its rows' help and footer labels, its actions'
/// names (`command mode` for CommandMode), and "asks to arm" where it asks while watching.
fn vocabulary(key: &str) -> Vec<String> {
    let mut words = Vec::new();
    for row in BINDINGS.iter().filter(|row| row.shown.split_whitespace().any(|shown| shown == key)) {
        let mut text = row.help.to_string();
        if let Some(footer) = row.footer {
            text.push_str(&format!(" {} {} {}", footer.label, footer.short, footer.armed.unwrap_or("")));
        }
        if row.watching == super::keys::Watching::AsksToArm {
            text.push_str(" asks to arm");
        }
        for bind in row.keys {
            text.push(' ');
            text.push_str(&action_words(bind.action));
        }
        words.extend(
            text.split(|c: char| !c.is_alphanumeric())
                .filter(|w| !w.is_empty() && !STOP_WORDS.contains(w))
                .map(str::to_lowercase),
        );
    }
    words
}

/// `ClearFaults` -> `clear faults`; `Drive(BackLeft)` -> `drive`.
fn action_words(action: Action) -> String {
    let name = format!("{action:?}");
    let name = name.split('(').next().unwrap_or_default();
    let mut words = String::new();
    for c in name.chars() {
        if c.is_uppercase() && !words.is_empty() {
            words.push(' ');
        }
        words.push(c.to_ascii_lowercase());
    }
    words
}

/// Whether the table agrees with what a mention says the key does: its first word that says something
/// ("enables" as "enable") is a word the table uses for the key. A mention that says nothing agrees if the
/// key exists.
fn agrees(mention: &Mention) -> bool {
    let vocabulary = vocabulary(&mention.key);
    let Some(word) = mention.does.iter().find(|word| !STOP_WORDS.contains(&word.as_str())) else {
        return !vocabulary.is_empty();
    };
    let stem = word.strip_suffix('s').filter(|stem| stem.len() > 2).unwrap_or(word);
    vocabulary.iter().any(|known| known.starts_with(stem))
}

/// The string literals of shipped code, as `(file, line, text)`.
fn string_literals(root: &Path) -> Vec<(String, usize, String)> {
    let mut literals = Vec::new();
    for path in shipped_files(&root.join("src")) {
        let relative = path.strip_prefix(root).unwrap_or(&path).to_string_lossy().replace('\\', "/");
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let shipped = without_test_items(&text);
        literals.extend(
            source_scan::string_literals(&shipped)
                .into_iter()
                .map(|(line, text)| (relative.clone(), line, text.to_string())),
        );
    }
    literals
}

#[test]
fn the_scan_finds_keys_named_in_prose_and_nothing_else() {
    let tokens = key_tokens();
    let found = |text: &str| mentions(text, &tokens);
    let one = |key: &str, does: &[&str]| Mention {
        key: key.into(),
        does: does.iter().map(|w| w.to_string()).collect(),
    };
    assert_eq!(found("not in command mode (mode standby): press m to enable it"), [one("m", &["enable"])]);
    assert_eq!(found("an arrow key or a asks to arm driving"), [one("a", &["asks"])]);
    assert_eq!(
        found("The first drive key, e, c or l asks"),
        [one("e", &["asks"]), one("c", &["asks"]), one("l", &["asks"])]
    );
    assert_eq!(
        found("the whole product: a, y arm; arrows drive; q quits"),
        [one("a", &["arm"]), one("y", &["arm"]), one("q", &["quits"])]
    );
    assert_eq!(
        found("nothing to fix; `m` (command mode) enables the drivers"),
        [one("m", &["command", "mode"])]
    );
    assert_eq!(found("| command mode is `e` |"), [one("e", &["mode"])]);
    assert_eq!(found("press Space"), [one("Space", &[])]);
    assert_eq!(found("zero sent (Space): press a key"), [one("Space", &[])]);
    assert!(found("`-t a` (absolute, the default)").is_empty(), "a code span, not a key");
    assert_eq!(found("enable it (e)"), [one("e", &[])]);
    assert_eq!(found("press space"), [one("space", &[])]);
    assert_eq!(found("the `m` key enables it"), [one("m", &["enables"])]);
    assert!(found("| Space to the first zero frame |").is_empty());
    for prose in
        ["press a key again to drive", "press a fresh key", "a to b", "up to 2 m", "press again to drive"]
    {
        let mentioned = found(prose);
        assert!(
            mentioned.iter().all(|m| m.key != "a" || !m.does.is_empty() && m.does[0] != "key"),
            "{prose}: {mentioned:?}"
        );
    }
    assert!(found("press a key again to drive").is_empty());
    assert!(found("zero at once, no ramp; press again to drive").is_empty());
}

#[test]
fn the_table_check_refuses_a_key_said_to_do_what_another_key_does() {
    let tokens = key_tokens();
    let check = |text: &str| mentions(text, &tokens).iter().all(agrees);
    assert!(!check("press m to enable it"), "m is an arc key");
    assert!(check("press e to enable it"));
    assert!(!check("`m` (command mode) enables the drivers"));
    assert!(check("`e` (command mode) enables the drivers"));
    assert!(check("a, y arm; q quits"));
    assert!(!check("y quits"));
    assert!(check("command mode is `e`"));
    assert!(!check("command mode is `m`"));
    assert!(!check("`m` (to enable command mode)"), "stop words say nothing");
    assert!(!check("the `m` key enables command mode"));
}

#[test]
fn shipped_text_names_no_key_by_hand() {
    let tokens = key_tokens();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let literals = string_literals(root);
    assert!(literals.len() > 500, "the scan found the literals: {}", literals.len());
    // Where the screen's words are: the renderer's panels, overlays and messages (folders are read too).
    for place in [
        "src/dashboard/render/footer.rs",
        "src/dashboard/render/message.rs",
        "src/dashboard/render/overlays/",
    ] {
        assert!(literals.iter().any(|(file, ..)| file.starts_with(place)), "the scan skipped {place}");
    }
    let named: Vec<String> = literals
        .iter()
        .flat_map(|(file, line, text)| {
            mentions(text, &tokens)
                .into_iter()
                .map(move |m| format!("{file}:{line}: `{}` in {text:?}", m.key))
        })
        .collect();
    assert!(
        named.is_empty(),
        "name keys with keys::key_name (the key table), not by hand:\n{}",
        named.join("\n")
    );
}

#[test]
fn the_docs_say_what_the_key_table_says() {
    let tokens = key_tokens();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<_> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .filter_map(|entry| entry.ok().map(|entry| entry.path()))
        .filter(|path| path.extension().is_some_and(|ext| ext == "md"))
        .collect();
    // The man pages: clap's texts from cli.rs's doc comments, which the literal scan does not read.
    docs.extend(
        std::fs::read_dir(root.join("docs/man"))
            .unwrap()
            .filter_map(|entry| entry.ok().map(|entry| entry.path()))
            .filter(|path| path.extension().is_some_and(|ext| ext == "1")),
    );
    docs.sort();
    files.extend(docs);
    let mut wrong = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        for (number, line) in text.lines().enumerate() {
            for mention in mentions(line, &tokens).into_iter().filter(|mention| !agrees(mention)) {
                let file = path.strip_prefix(root).unwrap_or(path).display();
                wrong.push(format!("{file}:{}: `{}` {:?}: {line}", number + 1, mention.key, mention.does));
            }
        }
    }
    assert!(wrong.is_empty(), "the key table (src/dashboard/keys.rs) says otherwise:\n{}", wrong.join("\n"));
}
