//! The footer's three lines: how key releases are detected, the keys (from the key table, whole entries
//! only), and the one-line message beside any recording loss.

use ratatui::text::{Line, Span};

use super::message::message_text;
use super::text::fit_words;
use super::theme::{separator, Theme};
use crate::dashboard::app::{App, Arming, ReleaseView};
use crate::dashboard::keys;

/// How key releases are detected (or why nothing drives), with what has been learned of the auto-repeat.
pub(super) fn release_text(app: &App) -> String {
    match app.teleop.release_mode {
        ReleaseView::Unset => "key release: -".to_string(),
        ReleaseView::DrivingOff(why) => format!("driving off: {why}"),
        ReleaseView::Events => "key release: terminal events (kitty protocol)".to_string(),
        ReleaseView::Deadline { delay_ms, interval_ms, timeout_ms, from_flag } => {
            let learned =
                |value: Option<u128>| value.map_or("not learned yet".to_string(), |ms| format!("{ms} ms"));
            let source = if from_flag { "--key-timeout" } else { "timeout" };
            format!(
                "key release: auto-repeat timeout (repeat delay {}, interval {}, {source} {timeout_ms} ms)",
                learned(delay_ms),
                learned(interval_ms)
            )
        }
    }
}

/// The key summary from the key table, long labels or short ones to fit. Still too wide, whole entries go,
/// never part of one: the spare ones first (lowest rank first), then the others from the end of the table,
/// then help; quitting stays.
pub(super) fn keys_line(width: u16, theme: Theme, arming: Arming) -> Line<'static> {
    let width = usize::from(width);
    let entries = keys::footer_entries(arming);
    let length = |keys: &[(&str, &str)]| -> usize {
        keys.iter().map(|(k, d)| k.chars().count() + 1 + d.chars().count()).sum::<usize>()
            + 2 * keys.len().saturating_sub(1)
    };
    let long: Vec<(&str, &str)> = entries.iter().map(|entry| (entry.0, entry.1)).collect();
    let labelled: Vec<(&str, &str)> =
        if length(&long) <= width { long } else { entries.iter().map(|entry| (entry.0, entry.2)).collect() };
    let mut kept = vec![true; labelled.len()];
    let mut order: Vec<usize> = (0..entries.len()).collect();
    order.sort_by_key(|&index| footer_drop_rank(entries[index].0, entries[index].3, index));
    for index in order {
        let shown: Vec<(&str, &str)> =
            labelled.iter().zip(&kept).filter(|(_, keep)| **keep).map(|(entry, _)| *entry).collect();
        if length(&shown) <= width || footer_action(entries[index].0, keys::Action::Quit) {
            break;
        }
        kept[index] = false;
    }
    let mut spans = Vec::new();
    for (key, description) in labelled.iter().zip(&kept).filter(|(_, keep)| **keep).map(|(entry, _)| *entry) {
        if !spans.is_empty() {
            spans.push(Span::raw("  "));
        }
        spans.push(Span::styled(key, theme.key()));
        spans.push(Span::raw(format!(" {description}")));
    }
    Line::from(spans)
}

/// The order in which footer entries give way, lowest first: spare entries by rank, then the others from
/// the end of the table, then help, then quit.
fn footer_drop_rank(keys: &str, spare: Option<u8>, index: usize) -> (u8, usize) {
    match spare {
        Some(rank) => (0, usize::from(rank)),
        None if footer_action(keys, keys::Action::Quit) => (3, 0),
        None if footer_action(keys, keys::Action::Help) => (2, 0),
        None => (1, usize::MAX - index),
    }
}

/// Whether the footer entry shown as `keys` belongs to the row of the key table that does `action`.
fn footer_action(keys: &str, action: keys::Action) -> bool {
    keys::BINDINGS.iter().any(|row| {
        row.footer.is_some_and(|footer| footer.keys == keys)
            && row.keys.iter().any(|bind| bind.action == action)
    })
}

/// The footer: a recording that loses frames (it stays: the exit status will say so too), then the message.
/// Within `width` when given, the texts cut after whole words; `None` where the lines wrap.
pub(super) fn message_line(app: &App, theme: Theme, width: Option<usize>) -> Line<'static> {
    let mut room = width.unwrap_or(usize::MAX);
    let fit = |text: String, room: &mut usize| {
        let text = if *room == usize::MAX { text } else { fit_words(&text, *room) };
        *room = room.saturating_sub(Span::raw(text.as_str()).width());
        text
    };
    let mut spans = Vec::new();
    if let Some(loss) = &app.recording_loss {
        let text = fit(format!("[fault] RECORDING LOST {} frames: {}", loss.frames, loss.reason), &mut room);
        spans.push(Span::styled(text, theme.alarm()));
    }
    if let Some((message, _)) = &app.message {
        if !spans.is_empty() {
            spans.push(separator(theme));
            room = room.saturating_sub(3);
        }
        spans.push(Span::styled("> ", theme.dim()));
        room = room.saturating_sub(2);
        if room > 0 {
            spans.push(Span::styled(fit(message_text(message), &mut room), theme.bold()));
        }
    }
    Line::from(spans)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The footer's entries as drawn at `width`, split on the two spaces between entries.
    fn footer_at(width: u16, arming: Arming) -> Vec<String> {
        let line = keys_line(width, Theme { color: false }, arming);
        let text: String = line.spans.iter().map(|span| span.content.as_ref()).collect();
        assert!(Line::raw(text.clone()).width() <= usize::from(width).max(6), "{width}: {text:?}");
        text.split("  ").map(str::to_string).collect()
    }

    #[test]
    fn the_footer_drops_whole_entries_and_keeps_help_and_quit_last() {
        let every: Vec<String> = keys::footer_entries(Arming::Watching)
            .iter()
            .flat_map(|entry| [format!("{} {}", entry.0, entry.1), format!("{} {}", entry.0, entry.2)])
            .collect();
        for width in 6..=140 {
            let entries = footer_at(width, Arming::Watching);
            for entry in &entries {
                assert!(every.contains(entry), "{width}: {entry:?} is not a whole entry of the table");
            }
            assert_eq!(entries.last().map(String::as_str), Some("q quit"), "{width}: {entries:?}");
            if width >= 14 {
                assert!(entries.contains(&"? help".to_string()), "{width}: {entries:?}");
            }
        }
        assert_eq!(footer_at(14, Arming::Watching), ["? help", "q quit"]);
        assert_eq!(footer_at(13, Arming::Watching), ["q quit"]);
        assert_eq!(footer_at(6, Arming::Watching), ["q quit"]);
        // Whatever rows the table has: the spare entries go first, then the others from the end, in the
        // table's order otherwise.
        let kept: Vec<String> = keys::footer_entries(Arming::Watching)
            .iter()
            .filter(|entry| entry.3.is_none())
            .map(|entry| format!("{} {}", entry.0, entry.2))
            .collect();
        let width = kept.iter().map(|entry| entry.chars().count()).sum::<usize>() + 2 * (kept.len() - 1);
        assert_eq!(footer_at(width as u16, Arming::Watching), kept);
        let mut fewer = kept.clone();
        fewer.remove(kept.len() - 3);
        assert_eq!(footer_at(width as u16 - 1, Arming::Watching), fewer, "the last of the others goes first");
        assert_eq!(kept[..2], ["↑↓←→ drive", "Space stop"]);
    }

    #[test]
    fn the_release_line_says_what_was_learned_in_milliseconds() {
        let mut app = App::new("can0", crate::control::Limits::default(), false);
        let mut said = |release_mode| {
            app.set_teleop(crate::dashboard::app::TeleopView { release_mode, ..Default::default() });
            release_text(&app)
        };
        assert_eq!(said(ReleaseView::Unset), "key release: -");
        assert_eq!(said(ReleaseView::DrivingOff("--watch")), "driving off: --watch");
        let deadline = ReleaseView::Deadline {
            delay_ms: Some(500),
            interval_ms: None,
            timeout_ms: 600,
            from_flag: false,
        };
        assert_eq!(
            said(deadline),
            "key release: auto-repeat timeout (repeat delay 500 ms, interval not learned yet, timeout 600 ms)"
        );
        let flag =
            ReleaseView::Deadline { delay_ms: None, interval_ms: Some(33), timeout_ms: 250, from_flag: true };
        assert_eq!(
            said(flag),
            "key release: auto-repeat timeout (repeat delay not learned yet, interval 33 ms, --key-timeout 250 ms)"
        );
    }
}
