//! The operator's keyboard during a commissioning run: the terminal in raw mode (no alternate screen: the
//! report stays on it), an input thread, and the terminal restored on every way out (a panic too). Keys are
//! named through the dashboard's key table, never by hand.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use anyhow::{Context, Result};
use ratatui::crossterm::event::{Event, KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use ratatui::crossterm::terminal;

use crate::dashboard::keys::{self as table, Action};
use crate::dashboard::terminal::{install_restoring_panic_hook, spawn_input, Input};
use crate::signals::{Caught, SIGINT};

/// Set while this module holds the terminal in raw mode.
static RAW: AtomicBool = AtomicBool::new(false);

fn restore() {
    if RAW.swap(false, Ordering::SeqCst) {
        let _ = terminal::disable_raw_mode();
    }
}

/// Zeros first (the sender's hook), then the terminal back, then the panic's message.
fn install_panic_hook() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    install_restoring_panic_hook(&INSTALLED, restore);
}

/// What a key press asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Press {
    /// The table's "yes" key.
    Yes,
    /// Ctrl-C: an interrupt, as SIGINT would be outside raw mode.
    Interrupt(Caught),
    /// Any other key, by name.
    Other(String),
    /// The terminal went away.
    Closed(String),
}

/// A key's name: the table's for the keys it shows (`Space`), the terminal's for the others.
pub fn name(key: &KeyEvent) -> String {
    match table::lookup(key) {
        Some((_, bind)) if key.code == KeyCode::Char(' ') => table::key_name(bind.action).to_string(),
        _ => key.code.to_string(),
    }
}

/// Classifies a key press.
pub fn press(key: &KeyEvent) -> Press {
    if key.code == KeyCode::Char('c') && key.modifiers.contains(KeyModifiers::CONTROL) {
        return Press::Interrupt(Caught { signal: SIGINT });
    }
    match table::lookup(key) {
        Some((_, bind)) if bind.action == Action::Yes => Press::Yes,
        _ => Press::Other(name(key)),
    }
}

/// The keyboard in raw mode; dropping it gives the terminal back.
pub struct Keyboard {
    done: Arc<AtomicBool>,
    inbox: Receiver<Input>,
}

impl Keyboard {
    pub fn start() -> Result<Self> {
        install_panic_hook();
        terminal::enable_raw_mode().context("cannot put the terminal in raw mode")?;
        RAW.store(true, Ordering::SeqCst);
        let done = Arc::new(AtomicBool::new(false));
        let inbox = spawn_input(Arc::clone(&done))?;
        Ok(Self { done, inbox })
    }

    /// A key pressed since the last call, if any.
    pub fn pressed(&self) -> Option<Press> {
        while let Ok(input) = self.inbox.try_recv() {
            if let Some(press) = Self::take(input) {
                return Some(press);
            }
        }
        None
    }

    /// Waits up to `timeout` for a key press.
    pub fn wait(&self, timeout: Duration) -> Option<Press> {
        let deadline = std::time::Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(std::time::Instant::now());
            match self.inbox.recv_timeout(left) {
                Ok(input) => {
                    if let Some(press) = Self::take(input) {
                        return Some(press);
                    }
                }
                Err(_) => return None,
            }
        }
    }

    fn take(input: Input) -> Option<Press> {
        match input {
            Input::Event(Event::Key(key)) if key.kind != KeyEventKind::Release => Some(press(&key)),
            Input::Event(_) => None,
            Input::Closed(why) => Some(Press::Closed(why)),
        }
    }
}

impl Drop for Keyboard {
    fn drop(&mut self) {
        self.done.store(true, Ordering::SeqCst);
        restore();
    }
}

/// Writes a line to stderr: in raw mode the terminal does not return the carriage by itself.
pub fn say_line(text: &str) {
    let end = if RAW.load(Ordering::SeqCst) { "\r\n" } else { "\n" };
    let _ = write!(std::io::stderr(), "{}{end}", text.replace('\n', end));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_named_by_the_table_and_ctrl_c_interrupts() {
        let space = KeyEvent::new(KeyCode::Char(' '), KeyModifiers::NONE);
        assert_eq!(press(&space), Press::Other(table::key_name(Action::Stop).to_string()));
        let yes = table::key_name(Action::Yes).chars().next().unwrap();
        assert_eq!(press(&KeyEvent::new(KeyCode::Char(yes), KeyModifiers::NONE)), Press::Yes);
        let interrupt = KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL);
        assert_eq!(press(&interrupt), Press::Interrupt(Caught { signal: SIGINT }));
        assert_eq!(press(&KeyEvent::new(KeyCode::Char('x'), KeyModifiers::NONE)), Press::Other("x".into()));
        assert_eq!(press(&KeyEvent::new(KeyCode::Enter, KeyModifiers::NONE)), Press::Other("Enter".into()));
    }
}
