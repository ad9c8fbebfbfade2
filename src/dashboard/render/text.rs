//! Text fitted to a width: whole words kept, what does not fit cut with `…` or wrapped.

/// `/home/me/lo…/session.log`: the start and the end of `text` (a path's file name), in `width` characters.
pub(super) fn middle_ellipsis(text: &str, width: usize) -> String {
    let count = text.chars().count();
    if count <= width {
        return text.to_string();
    }
    let keep = width.saturating_sub(1);
    // More of the end: a file's name says more than the start of its directory.
    let tail = (keep * 2).div_ceil(3);
    let head = keep - tail;
    let mut out: String = text.chars().take(head).collect();
    out.push('…');
    out.extend(text.chars().skip(count - tail));
    out
}

/// `text` within `width` characters, cut after a whole word with `…` when it is longer (a word longer than
/// the line is cut). Words end at a space or at a comma of a list (`overcurrent,overheat`).
pub(super) fn fit_words(text: &str, width: usize) -> String {
    let chars: Vec<char> = text.chars().collect();
    if chars.len() <= width {
        return text.to_string();
    }
    let keep = width.saturating_sub(1);
    let separator = |c: char| c == ' ' || c == ',';
    // The longest start that ends where a word does: the next character separates.
    let end = (1..=keep).rev().find(|&end| separator(chars[end])).unwrap_or(keep);
    let mut out: String = chars[..end].iter().collect();
    out.truncate(out.trim_end_matches(separator).len());
    out.push('…');
    out
}

/// `3.0 s`, `42 s`.
pub(super) fn age_text(deciseconds: u64) -> String {
    if deciseconds < 600 {
        format!("{}.{} s", deciseconds / 10, deciseconds % 10)
    } else {
        format!("{} s", deciseconds / 10)
    }
}

/// `prefix` and as many whole `names` as fit `width`, then `+N`: `... driver_overheat_protection +1`.
pub(super) fn names_within(prefix: &str, names: &[String], width: usize) -> String {
    let Some(first) = names.first() else { return prefix.to_string() };
    let mut text = format!("{prefix}{first}");
    for (index, name) in names.iter().enumerate().skip(1) {
        let next = format!("{text}, {name}");
        let after = names.len() - index - 1;
        let suffix = if after > 0 { format!(" +{after}").len() } else { 0 };
        if next.chars().count() + suffix > width {
            return format!("{text} +{}", names.len() - index);
        }
        text = next;
    }
    text
}

/// Word wrap to `width` columns (the texts are ASCII); words longer than a line are split.
pub(super) fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut rows = Vec::new();
    let mut current = String::new();
    for word in text.split(' ') {
        let mut word = word.to_string();
        loop {
            let needed = if current.is_empty() { word.len() } else { current.len() + 1 + word.len() };
            if needed <= width {
                if !current.is_empty() {
                    current.push(' ');
                }
                current.push_str(&word);
                break;
            }
            if current.is_empty() {
                let rest = word.split_off(width.min(word.len()));
                rows.push(std::mem::replace(&mut word, rest));
                if word.is_empty() {
                    break;
                }
            } else {
                rows.push(std::mem::take(&mut current));
            }
        }
    }
    if !current.is_empty() || rows.is_empty() {
        rows.push(current);
    }
    rows
}

pub(super) fn truncate(text: &str, width: usize) -> String {
    if text.chars().count() <= width {
        return text.to_string();
    }
    let mut out: String = text.chars().take(width.saturating_sub(1)).collect();
    out.push('…');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_keeps_words_and_splits_long_ones() {
        assert_eq!(wrap("check the cable and power", 10), ["check the", "cable and", "power"]);
        assert_eq!(wrap("abcdefghijkl xy", 5), ["abcde", "fghij", "kl xy"]);
        assert_eq!(wrap("", 5), [""]);
        assert_eq!(truncate("abcdef", 4), "abc…");
    }
}
