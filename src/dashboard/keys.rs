//! Every key of the dashboard, once. [`BINDINGS`] is the one table: each row is a line of the help (the
//! keys as shown, what they do), the keys the terminal reports and the [`Action`] each asks for, the
//! footer's label, and what the keys do while watching and when a dialog owns the keyboard. The dispatcher
//! ([`dispatch`]), the footer and the help overlay (`render`) and `tracerctl dashboard --help`
//! ([`help_text`]) all read it: adding a key is adding a row.

use std::fmt::{self, Write as _};

use ratatui::crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};

use super::app::{Arming, Prompt};
use super::teleop::{Key, KeyAction};
use crate::protocol::id::{FrameId, ID_CONTROL_MODE};

/// What a key asks for, before what is on screen decides what happens (see [`dispatch`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// A drive key (an arrow or a diagonal): held, it drives (see `teleop`).
    Drive(Key),
    /// Zero at once, no ramp.
    Stop,
    /// Disarm when armed; watching, ask to arm.
    Arm,
    Faster,
    Slower,
    Lights,
    ClearFaults,
    CommandMode,
    Help,
    /// Close the prompt or the help on screen.
    Close,
    Suspend,
    Quit,
    /// Yes to the prompt on screen.
    Yes,
}

/// A key as the terminal reports it. A plain key matches whatever modifiers come with it (Shift for `+`);
/// a Ctrl chord is preferred over the plain key when Ctrl is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Chord {
    Plain(KeyCode),
    Ctrl(char),
}

impl Chord {
    fn matches(self, key: &KeyEvent) -> bool {
        match self {
            Chord::Plain(code) => key.code == code,
            Chord::Ctrl(letter) => {
                key.code == KeyCode::Char(letter) && key.modifiers.contains(KeyModifiers::CONTROL)
            }
        }
    }

    /// A key event that this chord matches (for tests and for checking the table).
    pub fn event(self) -> KeyEvent {
        match self {
            Chord::Plain(code) => KeyEvent::new(code, KeyModifiers::NONE),
            Chord::Ctrl(letter) => KeyEvent::new(KeyCode::Char(letter), KeyModifiers::CONTROL),
        }
    }
}

/// What a key does while a dialog (the arm or clear prompt, or the help) owns the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InDialog {
    /// The same as without the dialog (stopping, suspending, Ctrl-C).
    Works,
    /// Works over the help; closes a prompt (q).
    WorksOverHelp,
    /// Answers the prompt; closes the help.
    Answers,
    /// Closes the dialog and does nothing else (a drive key does not drive; its release still counts).
    Closes,
}

/// What a key does while watching (driving not armed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Watching {
    /// The same as when armed: it sends nothing to the robot.
    Works,
    /// It would send something: a press asks "Arm driving?" instead (or says watch-only).
    AsksToArm,
}

/// One key and what it is for.
#[derive(Debug, Clone, Copy)]
pub struct Bind {
    pub chord: Chord,
    pub action: Action,
    pub in_dialog: InDialog,
}

/// An entry of the footer's key summary.
#[derive(Debug, Clone, Copy)]
pub struct Footer {
    /// The keys as the footer shows them.
    pub keys: &'static str,
    pub label: &'static str,
    /// The label when the long ones do not fit.
    pub short: &'static str,
    /// The label while armed, for the entry that arms; it is not shown when arming is impossible.
    pub armed: Option<&'static str>,
    /// Dropped when even the short labels do not fit, lowest first; `None`: always shown.
    pub spare: Option<u8>,
}

/// One line of the help: keys that belong together.
#[derive(Debug, Clone, Copy)]
pub struct Binding {
    /// The keys as the help shows them.
    pub shown: &'static str,
    pub keys: &'static [Bind],
    /// What they do, as the help says it.
    pub help: &'static str,
    pub footer: Option<Footer>,
    pub watching: Watching,
}

const fn bind(chord: Chord, action: Action, in_dialog: InDialog) -> Bind {
    Bind { chord, action, in_dialog }
}

const fn plain(letter: char, action: Action, in_dialog: InDialog) -> Bind {
    bind(Chord::Plain(KeyCode::Char(letter)), action, in_dialog)
}

const fn drive(code: KeyCode, key: Key) -> Bind {
    bind(Chord::Plain(code), Action::Drive(key), InDialog::Closes)
}

const UP: Bind = drive(KeyCode::Up, Key::Up);
const DOWN: Bind = drive(KeyCode::Down, Key::Down);
const LEFT: Bind = drive(KeyCode::Left, Key::Left);
const RIGHT: Bind = drive(KeyCode::Right, Key::Right);

const fn footer(keys: &'static str, label: &'static str, short: &'static str, spare: Option<u8>) -> Footer {
    Footer { keys, label, short, armed: None, spare }
}

/// Every key of the dashboard, in the order the help lists them (the footer keeps that order too).
pub const BINDINGS: &[Binding] = &[
    Binding {
        shown: "↑ ↓",
        keys: &[UP, DOWN],
        help: "drive forward / backward (linear speed)",
        footer: Some(footer("↑↓←→", "drive", "drive", None)),
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "← →",
        keys: &[LEFT, RIGHT],
        help: "turn left / right (angular speed)",
        footer: None,
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "u o m .",
        keys: &[
            drive(KeyCode::Char('u'), Key::ForwardLeft),
            drive(KeyCode::Char('o'), Key::ForwardRight),
            drive(KeyCode::Char('m'), Key::BackLeft),
            drive(KeyCode::Char('.'), Key::BackRight),
            drive(KeyCode::Home, Key::ForwardLeft),
            drive(KeyCode::PageUp, Key::ForwardRight),
            drive(KeyCode::End, Key::BackLeft),
            drive(KeyCode::PageDown, Key::BackRight),
        ],
        help: "arcs ↖ ↗ ↙ ↘, also Home PgUp End PgDn",
        footer: Some(footer("uom.", "arcs", "arcs", Some(4))),
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "↑← ↑→ ...",
        keys: &[UP, DOWN, LEFT, RIGHT],
        help: "held together: arcs (kitty protocol only)",
        footer: None,
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "Space  k",
        keys: &[plain(' ', Action::Stop, InDialog::Works), plain('k', Action::Stop, InDialog::Works)],
        help: "zero at once, no ramp; press again to drive",
        footer: Some(footer("Space", "stop", "stop", None)),
        watching: Watching::Works,
    },
    Binding {
        shown: "a",
        keys: &[plain('a', Action::Arm, InDialog::Closes)],
        help: "arm driving (asks first) / disarm: zero, then nothing is sent",
        footer: Some(Footer { keys: "a", label: "arm", short: "arm", armed: Some("disarm"), spare: None }),
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "y",
        keys: &[plain('y', Action::Yes, InDialog::Answers), plain('Y', Action::Yes, InDialog::Answers)],
        help: "yes to the prompt: arm, send the fault clear",
        footer: None,
        watching: Watching::Works,
    },
    Binding {
        shown: "+ -",
        keys: &[
            plain('+', Action::Faster, InDialog::Closes),
            plain('=', Action::Faster, InDialog::Closes),
            plain('-', Action::Slower, InDialog::Closes),
            plain('_', Action::Slower, InDialog::Closes),
        ],
        help: "speed scale up / down",
        footer: Some(footer("+/-", "scale", "scale", Some(2))),
        watching: Watching::Works,
    },
    Binding {
        shown: "l",
        keys: &[plain('l', Action::Lights, InDialog::Closes)],
        help: "cycle the lights (on, breathing, custom, off, firmware)",
        footer: Some(footer("l", "lights", "lights", Some(1))),
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "c",
        keys: &[plain('c', Action::ClearFaults, InDialog::Closes)],
        help: "clear faults (asks first)",
        footer: Some(footer("c", "clear faults", "clear", Some(3))),
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "e",
        keys: &[plain('e', Action::CommandMode, InDialog::Closes)],
        help: "enable command mode",
        footer: Some(footer("e", "command mode", "mode", Some(0))),
        watching: Watching::AsksToArm,
    },
    Binding {
        shown: "?  Esc",
        keys: &[
            plain('?', Action::Help, InDialog::Closes),
            bind(Chord::Plain(KeyCode::Esc), Action::Close, InDialog::Closes),
        ],
        help: "show / close this help",
        footer: Some(footer("?", "help", "help", None)),
        watching: Watching::Works,
    },
    // Windows consoles have no job control.
    #[cfg(unix)]
    Binding {
        shown: "^Z",
        keys: &[bind(Chord::Ctrl('z'), Action::Suspend, InDialog::Works)],
        help: "zero, then suspend (after fg: press again)",
        footer: None,
        watching: Watching::Works,
    },
    Binding {
        shown: "q  ^C",
        keys: &[
            plain('q', Action::Quit, InDialog::WorksOverHelp),
            bind(Chord::Ctrl('c'), Action::Quit, InDialog::Works),
        ],
        help: "stop the robot and quit",
        footer: Some(footer("q", "quit", "quit", None)),
        watching: Watching::Works,
    },
];

/// A drive key as the screen shows it held: the arrow it drives (`↑`, `↖`).
impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Key::Up => "↑",
            Key::Down => "↓",
            Key::Left => "←",
            Key::Right => "→",
            Key::ForwardLeft => "↖",
            Key::ForwardRight => "↗",
            Key::BackLeft => "↙",
            Key::BackRight => "↘",
        })
    }
}

/// The row and key a key event belongs to; a Ctrl chord wins over the plain key.
pub fn lookup(key: &KeyEvent) -> Option<(&'static Binding, &'static Bind)> {
    let all = || BINDINGS.iter().flat_map(|row| row.keys.iter().map(move |bind| (row, bind)));
    all()
        .find(|(_, bind)| matches!(bind.chord, Chord::Ctrl(_)) && bind.chord.matches(key))
        .or_else(|| all().find(|(_, bind)| bind.chord.matches(key)))
}

/// What is on screen, and whether driving is armed: what a key does depends on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Context {
    pub prompt: Prompt,
    pub help: bool,
    pub armed: bool,
}

impl Context {
    fn dialog(self) -> bool {
        self.prompt != Prompt::None || self.help
    }
}

/// What the loop does for a key event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    /// An arrow's press, repeat or release while driving is armed and nothing is on top.
    Drive(Key, KeyAction),
    Quit,
    Suspend,
    Stop,
    Faster,
    Slower,
    /// Show or hide the help.
    Help,
    /// Close the prompt or the help on screen.
    Close,
    /// Ask "Arm driving?" (or say why arming is impossible).
    AskArm,
    Arm,
    Disarm,
    /// Ask before sending a fault clear.
    AskClear,
    Clear,
    CommandMode,
    Lights,
    None,
}

/// The dispatcher: what a key event does, from [`BINDINGS`]. Only presses act, except the drive keys while
/// armed (their repeats and releases drive too). A prompt or the help owns the keyboard: a key acts as its
/// row's [`InDialog`] says (a drive key closes it and does not drive), and a key that is not in the table
/// closes it; only a drive key's release still reaches the teleop, so no key stays held under a dialog.
/// Watching, a key whose row [`Watching::AsksToArm`] asks to arm instead. Esc closes and never quits.
pub fn dispatch(key: &KeyEvent, context: Context) -> Effect {
    let kind = key_action(key.kind);
    let Some((row, bind)) = lookup(key) else {
        return if kind == KeyAction::Press && context.dialog() { Effect::Close } else { Effect::None };
    };
    if let (Action::Drive(arrow), true) = (bind.action, context.armed) {
        if !context.dialog() || kind == KeyAction::Release {
            return Effect::Drive(arrow, kind);
        }
    }
    if kind != KeyAction::Press {
        return Effect::None;
    }
    if context.dialog() {
        match (bind.in_dialog, context.prompt) {
            (InDialog::Works, _) | (InDialog::WorksOverHelp, Prompt::None) => {}
            (InDialog::Answers, Prompt::ConfirmArm) => return Effect::Arm,
            (InDialog::Answers, Prompt::ConfirmClear) => return Effect::Clear,
            _ => return Effect::Close,
        }
    }
    if !context.armed && row.watching == Watching::AsksToArm {
        return Effect::AskArm;
    }
    effect(bind.action, kind, context.armed)
}

/// What an action does on the main screen.
fn effect(action: Action, kind: KeyAction, armed: bool) -> Effect {
    match action {
        Action::Drive(arrow) => Effect::Drive(arrow, kind),
        Action::Stop => Effect::Stop,
        Action::Arm if armed => Effect::Disarm,
        Action::Arm => Effect::AskArm,
        Action::Faster => Effect::Faster,
        Action::Slower => Effect::Slower,
        Action::Lights => Effect::Lights,
        Action::ClearFaults => Effect::AskClear,
        Action::CommandMode => Effect::CommandMode,
        Action::Help => Effect::Help,
        Action::Close => Effect::Close,
        Action::Suspend => Effect::Suspend,
        Action::Quit => Effect::Quit,
        // Yes without a prompt: nothing to answer.
        Action::Yes => Effect::None,
    }
}

/// What kind of key event this is. Legacy terminals report every byte as a press.
pub fn key_action(kind: KeyEventKind) -> KeyAction {
    match kind {
        KeyEventKind::Press => KeyAction::Press,
        KeyEventKind::Repeat => KeyAction::Repeat,
        KeyEventKind::Release => KeyAction::Release,
    }
}

/// The footer's entries for this arming state, in the table's order: (keys, label, short label, spare).
/// Watch-only (`--watch`, `--replay`) shows only the keys that do something there: help and quit.
pub fn footer_entries(arming: Arming) -> Vec<(&'static str, &'static str, &'static str, Option<u8>)> {
    BINDINGS
        .iter()
        .filter(|row| {
            arming != Arming::WatchOnly || row.keys.iter().all(|bind| works_watch_only(bind.action))
        })
        .filter_map(|row| row.footer)
        .filter_map(|entry| match (entry.armed, arming) {
            (Some(_), Arming::WatchOnly) => None,
            (Some(armed), Arming::Armed) => Some((entry.keys, armed, armed, entry.spare)),
            _ => Some((entry.keys, entry.label, entry.short, entry.spare)),
        })
        .collect()
}

/// Whether `action` does anything when driving cannot be armed: nothing is sent, so only the screen's own
/// keys do (a stop or a speed scale has nothing to act on).
fn works_watch_only(action: Action) -> bool {
    matches!(action, Action::Help | Action::Close | Action::Quit | Action::Suspend)
}

/// The paragraphs of `tracerctl dashboard --help` before the keys.
const HELP_BEFORE: &str = "\
The dashboard opens WATCHING: it sends nothing to the robot (a robot that ROS or an RC transmitter drives
is not disturbed). The first drive key, {ASKING} asks \"Arm driving?\"; {YES} arms ({MODE_COMMAND} command mode, then
motion commands at 50 Hz), {ARM} disarms at once. --watch forbids arming. The header says ARMED or
WATCHING.";

/// The paragraph of `tracerctl dashboard --help` after the keys.
const HELP_AFTER: &str = "\
A key counts as held until the terminal reports its release (kitty keyboard protocol: kitty, foot,
WezTerm, alacritty, Ghostty, iTerm2) or, in other terminals and in tmux, until no auto-repeat arrives
before a deadline learned from the key stream (longer over a link that delivers repeats late;
--key-timeout sets it); releasing brakes at --decel. Those terminals repeat only the last key pressed:
drive arcs with one diagonal key. While the robot reports an E-stop, a latched fault or RC override,
zero is sent and keys are ignored until a fresh press once it is clear; the same after the process was
suspended. If input or drawing stalls, the robot is commanded to zero within 250 ms; every exit sends
zero-velocity frames.";

/// The keys besides the drive keys and arming's own that ask to arm while watching: `e, c or l`.
fn asking_to_arm() -> String {
    let names: Vec<&str> = BINDINGS
        .iter()
        .filter(|row| row.watching == Watching::AsksToArm)
        .filter(|row| row.keys.iter().all(|bind| !matches!(bind.action, Action::Drive(_) | Action::Arm)))
        .filter_map(|row| row.shown.split_whitespace().next())
        .collect();
    match names.split_last() {
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// The help's key column width, in characters.
pub const KEY_COLUMN: usize = 10;

/// `tracerctl dashboard --help` after the options: how arming works, every key of [`BINDINGS`] with the
/// help overlay's words, and how releases and stalls are handled.
pub fn help_text() -> String {
    let before = HELP_BEFORE
        .replace("{MODE_COMMAND}", &FrameId::standard(ID_CONTROL_MODE).to_string())
        .replace("{ASKING}", &asking_to_arm())
        .replace("{YES}", key_name(Action::Yes))
        .replace("{ARM}", key_name(Action::Arm));
    let mut text = format!("{before}\n\nKeys:\n");
    for row in BINDINGS {
        let _ = writeln!(text, "  {:<KEY_COLUMN$}{}", row.shown, row.help);
    }
    text.push('\n');
    text.push_str(HELP_AFTER);
    text
}

/// The keys as a Markdown table (README.md's key table is this, between marker comments; a test keeps it so).
pub fn markdown_table() -> String {
    let mut table = String::from("| key | does |\n|---|---|\n");
    for row in BINDINGS {
        let keys: Vec<String> = row.shown.split_whitespace().map(|key| format!("`{key}`")).collect();
        let _ = writeln!(table, "| {} | {} |", keys.join(" "), row.help);
    }
    table
}

/// How a prompt names a key: the first key of the table's row for `action`, as the help shows it (`y`,
/// `Space`).
pub fn key_name(action: Action) -> &'static str {
    BINDINGS
        .iter()
        .find(|row| row.keys.iter().any(|bind| bind.action == action))
        .and_then(|row| row.shown.split_whitespace().next())
        .unwrap_or("?")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every action; the match makes a new action a compile error here until it is listed.
    fn every_action() -> Vec<Action> {
        let all = vec![
            Action::Drive(Key::Up),
            Action::Drive(Key::Down),
            Action::Drive(Key::Left),
            Action::Drive(Key::Right),
            Action::Stop,
            Action::Arm,
            Action::Faster,
            Action::Slower,
            Action::Lights,
            Action::ClearFaults,
            Action::CommandMode,
            Action::Help,
            Action::Close,
            // Ctrl-Z has no key where there is no job control (Windows).
            #[cfg(unix)]
            Action::Suspend,
            Action::Quit,
            Action::Yes,
        ];
        for action in &all {
            match action {
                Action::Drive(_)
                | Action::Stop
                | Action::Arm
                | Action::Faster
                | Action::Slower
                | Action::Lights
                | Action::ClearFaults
                | Action::CommandMode
                | Action::Help
                | Action::Close
                | Action::Suspend
                | Action::Quit
                | Action::Yes => {}
            }
        }
        all
    }

    #[test]
    fn every_action_has_a_key_and_every_row_a_help_text() {
        for action in every_action() {
            let rows: Vec<&Binding> =
                BINDINGS.iter().filter(|row| row.keys.iter().any(|bind| bind.action == action)).collect();
            assert!(!rows.is_empty(), "{action:?} has no key");
            assert!(rows.iter().all(|row| !row.help.is_empty() && !row.shown.is_empty()), "{action:?}");
        }
        for row in BINDINGS {
            assert!(!row.keys.is_empty(), "{} has no key", row.shown);
            assert!(row.help.len() > 5, "{} says what it does", row.shown);
        }
        // Every action the footer names is reachable from a row the help lists too.
        let footer = footer_entries(Arming::Armed);
        let keys: Vec<&str> = footer.iter().map(|entry| entry.0).collect();
        assert_eq!(keys, ["↑↓←→", "uom.", "Space", "a", "+/-", "l", "c", "e", "?", "q"]);
        assert!(footer.iter().all(|entry| !entry.1.is_empty() && !entry.2.is_empty()));
    }

    #[test]
    fn the_dispatcher_maps_every_table_key_to_its_action() {
        let armed = Context { prompt: Prompt::None, help: false, armed: true };
        for row in BINDINGS {
            for bind in row.keys {
                let event = bind.chord.event();
                let (_, found) = lookup(&event).expect("every table key is found");
                assert_eq!(found.action, bind.action, "{:?}", bind.chord);
                assert_eq!(
                    dispatch(&event, armed),
                    effect(bind.action, KeyAction::Press, true),
                    "{:?}",
                    bind.chord
                );
            }
        }
    }

    #[test]
    fn the_same_key_means_the_same_action_in_every_row() {
        for row in BINDINGS {
            for bind in row.keys {
                let others =
                    BINDINGS.iter().flat_map(|other| other.keys).filter(|other| other.chord == bind.chord);
                for other in others {
                    assert_eq!(other.action, bind.action, "{:?}", bind.chord);
                    assert_eq!(other.in_dialog, bind.in_dialog, "{:?}", bind.chord);
                }
            }
        }
    }

    fn press(code: KeyCode) -> KeyEvent {
        KeyEvent::new(code, KeyModifiers::NONE)
    }

    fn on(prompt: Prompt, help: bool, armed: bool) -> Context {
        Context { prompt, help, armed }
    }

    #[test]
    fn keys_map_to_actions_and_the_prompt_takes_precedence() {
        let armed = |code| dispatch(&press(code), on(Prompt::None, false, true));
        assert_eq!(armed(KeyCode::Char('q')), Effect::Quit);
        assert_eq!(armed(KeyCode::Esc), Effect::Close, "Esc never quits");
        let ctrl_c = Chord::Ctrl('c').event();
        assert_eq!(
            dispatch(&ctrl_c, on(Prompt::ConfirmClear, false, true)),
            Effect::Quit,
            "Ctrl-C always quits"
        );
        assert_eq!(dispatch(&ctrl_c, on(Prompt::None, true, false)), Effect::Quit);
        let ctrl_z = Chord::Ctrl('z').event();
        #[cfg(unix)]
        {
            assert_eq!(dispatch(&ctrl_z, on(Prompt::None, false, true)), Effect::Suspend);
            assert_eq!(dispatch(&ctrl_z, on(Prompt::ConfirmArm, false, false)), Effect::Suspend);
        }
        // No job control on Windows: Ctrl-Z is no key there.
        #[cfg(not(unix))]
        assert_eq!(dispatch(&ctrl_z, on(Prompt::None, false, true)), Effect::None);
        assert_eq!(armed(KeyCode::Char('c')), Effect::AskClear);
        assert_eq!(armed(KeyCode::Char('a')), Effect::Disarm);
        assert_eq!(armed(KeyCode::Char('=')), Effect::Faster);
        assert_eq!(armed(KeyCode::Char('_')), Effect::Slower);
        assert_eq!(armed(KeyCode::Char('y')), Effect::None, "nothing to answer");
        assert_eq!(armed(KeyCode::Char('w')), Effect::None, "not a key of the table");
        let clear = on(Prompt::ConfirmClear, false, true);
        assert_eq!(dispatch(&press(KeyCode::Char('y')), clear), Effect::Clear);
        assert_eq!(dispatch(&press(KeyCode::Char('Y')), clear), Effect::Clear);
        assert_eq!(dispatch(&press(KeyCode::Char('q')), clear), Effect::Close);
        assert_eq!(dispatch(&press(KeyCode::Esc), clear), Effect::Close);
        assert_eq!(dispatch(&press(KeyCode::Char('x')), clear), Effect::Close);
        assert_eq!(dispatch(&press(KeyCode::Char(' ')), clear), Effect::Stop);
        let help = on(Prompt::None, true, true);
        assert_eq!(dispatch(&press(KeyCode::Esc), help), Effect::Close, "Esc closes help");
        assert_eq!(dispatch(&press(KeyCode::Char('?')), help), Effect::Close);
        assert_eq!(dispatch(&press(KeyCode::Char('l')), help), Effect::Close);
        assert_eq!(dispatch(&press(KeyCode::Char('y')), help), Effect::Close);
        assert_eq!(dispatch(&press(KeyCode::Char('q')), help), Effect::Quit);
    }

    #[test]
    fn watching_every_key_that_sends_asks_to_arm_first() {
        let watching = |code| dispatch(&press(code), on(Prompt::None, false, false));
        for code in [
            KeyCode::Char('a'),
            KeyCode::Char('c'),
            KeyCode::Char('e'),
            KeyCode::Char('l'),
            KeyCode::Up,
            KeyCode::Char('m'),
            KeyCode::Home,
        ] {
            assert_eq!(watching(code), Effect::AskArm, "{code:?}");
        }
        assert_eq!(watching(KeyCode::Char('+')), Effect::Faster, "the scale sends nothing");
        assert_eq!(watching(KeyCode::Char(' ')), Effect::Stop);
        assert_eq!(watching(KeyCode::Char('?')), Effect::Help);
        let arm = on(Prompt::ConfirmArm, false, false);
        assert_eq!(dispatch(&press(KeyCode::Char('y')), arm), Effect::Arm);
        assert_eq!(dispatch(&press(KeyCode::Char('n')), arm), Effect::Close);
    }

    #[test]
    fn arrows_drive_only_when_armed_and_nothing_is_on_top() {
        let event = |kind| KeyEvent::new_with_kind(KeyCode::Up, KeyModifiers::NONE, kind);
        let armed = on(Prompt::None, false, true);
        assert_eq!(dispatch(&event(KeyEventKind::Press), armed), Effect::Drive(Key::Up, KeyAction::Press));
        assert_eq!(dispatch(&event(KeyEventKind::Repeat), armed), Effect::Drive(Key::Up, KeyAction::Repeat));
        assert_eq!(
            dispatch(&event(KeyEventKind::Release), armed),
            Effect::Drive(Key::Up, KeyAction::Release)
        );
        let ctrl_up = KeyEvent::new(KeyCode::Up, KeyModifiers::CONTROL);
        assert_eq!(dispatch(&ctrl_up, armed), Effect::Drive(Key::Up, KeyAction::Press));
        // Watching nothing drives: a press asks to arm, the rest is ignored.
        let watching = on(Prompt::None, false, false);
        assert_eq!(dispatch(&event(KeyEventKind::Press), watching), Effect::AskArm);
        assert_eq!(dispatch(&event(KeyEventKind::Repeat), watching), Effect::None);
        assert_eq!(dispatch(&event(KeyEventKind::Release), watching), Effect::None);
        // A dialog owns the keyboard: a press closes it and does not drive, a repeat does nothing, and only
        // a release still reaches the teleop (so nothing stays held under the dialog).
        for context in [
            on(Prompt::None, true, true),
            on(Prompt::ConfirmClear, false, true),
            on(Prompt::ConfirmArm, false, false),
            on(Prompt::None, true, false),
        ] {
            assert_eq!(dispatch(&event(KeyEventKind::Press), context), Effect::Close, "{context:?}");
            assert_eq!(dispatch(&event(KeyEventKind::Repeat), context), Effect::None, "{context:?}");
            let release =
                if context.armed { Effect::Drive(Key::Up, KeyAction::Release) } else { Effect::None };
            assert_eq!(dispatch(&event(KeyEventKind::Release), context), release, "{context:?}");
        }
        // Only presses act for the other keys (a kitty terminal also reports their releases).
        let q_release =
            KeyEvent::new_with_kind(KeyCode::Char('q'), KeyModifiers::NONE, KeyEventKind::Release);
        assert_eq!(dispatch(&q_release, armed), Effect::None);
    }

    #[test]
    fn diagonal_keys_drive_arcs_and_close_dialogs() {
        let armed = on(Prompt::None, false, true);
        let cases = [
            (KeyCode::Char('u'), Key::ForwardLeft),
            (KeyCode::Char('o'), Key::ForwardRight),
            (KeyCode::Char('m'), Key::BackLeft),
            (KeyCode::Char('.'), Key::BackRight),
            (KeyCode::Home, Key::ForwardLeft),
            (KeyCode::PageUp, Key::ForwardRight),
            (KeyCode::End, Key::BackLeft),
            (KeyCode::PageDown, Key::BackRight),
        ];
        for (code, key) in cases {
            assert_eq!(dispatch(&press(code), armed), Effect::Drive(key, KeyAction::Press), "{code:?}");
            assert_eq!(dispatch(&press(code), on(Prompt::ConfirmClear, false, true)), Effect::Close);
            assert_eq!(dispatch(&press(code), on(Prompt::None, false, false)), Effect::AskArm);
        }
        assert_eq!(dispatch(&press(KeyCode::Char('e')), armed), Effect::CommandMode);
        assert_eq!(dispatch(&press(KeyCode::Char('k')), armed), Effect::Stop);
        // Every letter drives one thing only: no letter key is in two rows with different actions.
        let mut letters: Vec<char> = BINDINGS
            .iter()
            .flat_map(|row| row.keys)
            .filter_map(|bind| match bind.chord {
                Chord::Plain(KeyCode::Char(letter)) => Some(letter),
                _ => None,
            })
            .collect();
        let before = letters.len();
        letters.sort_unstable();
        letters.dedup();
        assert_eq!(letters.len(), before, "{letters:?}");
    }

    #[test]
    fn esc_closes_every_dialog_and_never_quits() {
        for context in [
            on(Prompt::None, true, true),
            on(Prompt::None, true, false),
            on(Prompt::ConfirmClear, false, true),
            on(Prompt::ConfirmArm, false, false),
            on(Prompt::None, false, true),
        ] {
            assert_eq!(dispatch(&press(KeyCode::Esc), context), Effect::Close, "{context:?}");
        }
    }

    #[test]
    fn drive_keys_show_as_the_arrows_the_table_names() {
        let shown: Vec<String> = Key::ALL.iter().map(Key::to_string).collect();
        assert_eq!(shown, ["↑", "↓", "←", "→", "↖", "↗", "↙", "↘"]);
        // The arrows' rows show them as they are displayed held; the diagonals' help lists theirs.
        let row_of = |a: Key, b: Key| {
            let actions = [Action::Drive(a), Action::Drive(b)];
            BINDINGS.iter().find(|row| row.keys.iter().map(|bind| bind.action).eq(actions)).unwrap().shown
        };
        assert_eq!(row_of(Key::Up, Key::Down), format!("{} {}", Key::Up, Key::Down));
        assert_eq!(row_of(Key::Left, Key::Right), format!("{} {}", Key::Left, Key::Right));
        let arcs = BINDINGS.iter().find(|row| row.shown == "u o m .").unwrap();
        for key in &Key::ALL[4..] {
            assert!(arcs.help.contains(&key.to_string()), "{key:?}");
        }
    }

    #[test]
    fn prompts_and_markdown_name_the_tables_keys() {
        assert_eq!(key_name(Action::Yes), "y");
        assert_eq!(key_name(Action::Stop), "Space");
        let table = markdown_table();
        assert!(table.starts_with("| key | does |\n|---|---|\n"), "{table}");
        assert!(table.contains("| `u` `o` `m` `.` | arcs ↖ ↗ ↙ ↘, also Home PgUp End PgDn |\n"), "{table}");
        assert!(table.contains("| `↑←` `↑→` `...` | held together: arcs (kitty protocol only) |\n"));
        assert_eq!(table.lines().count(), BINDINGS.len() + 2);
    }

    #[test]
    fn the_footer_follows_the_arming_state() {
        let labels = |arming| footer_entries(arming).into_iter().map(|e| (e.0, e.1)).collect::<Vec<_>>();
        assert!(labels(Arming::Watching).contains(&("a", "arm")));
        assert!(labels(Arming::Armed).contains(&("a", "disarm")));
        assert!(!labels(Arming::WatchOnly).iter().any(|(keys, _)| *keys == "a"), "nothing to arm");
        // Watch-only (--watch, --replay): only the keys that do something there.
        assert_eq!(labels(Arming::WatchOnly), [("?", "help"), ("q", "quit")]);
    }

    #[test]
    fn help_text_lists_every_row_with_the_overlays_words() {
        let text = help_text();
        for row in BINDINGS {
            assert!(text.contains(&format!("  {:<KEY_COLUMN$}{}\n", row.shown, row.help)), "{}", row.shown);
        }
        assert!(text.contains("  q  ^C     stop the robot and quit\n"), "{text}");
        assert!(text.starts_with("The dashboard opens WATCHING"));
        let words = text.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(words.ends_with("every exit sends zero-velocity frames."), "{text}");
        assert!(words.contains("--key-timeout sets it"), "{text}");
    }
}
