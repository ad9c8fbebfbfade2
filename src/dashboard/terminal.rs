//! The terminal side of the dashboard: raw mode, the alternate screen, the keyboard-enhancement flags (key
//! release events), an input thread, and restoring all of it on every way out, panics included.

use std::io::{self, Stdout, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use anyhow::{Context, Result};
use ratatui::backend::CrosstermBackend;
use ratatui::crossterm::event::{
    self, Event, KeyboardEnhancementFlags, PopKeyboardEnhancementFlags, PushKeyboardEnhancementFlags,
};
use ratatui::crossterm::terminal::{self, EnterAlternateScreen, LeaveAlternateScreen};
use ratatui::crossterm::{cursor, execute};
use ratatui::Terminal;

/// Whether we pushed keyboard flags (they must be popped on exit, the panic path too).
static FLAGS_PUSHED: AtomicBool = AtomicBool::new(false);
static TERMINAL_ACTIVE: AtomicBool = AtomicBool::new(false);

/// Puts the terminal back as it was: pop the keyboard flags, leave the alternate screen, show the cursor,
/// leave raw mode. Safe to call more than once and from a panic hook.
pub fn restore() {
    if !TERMINAL_ACTIVE.swap(false, Ordering::SeqCst) {
        return;
    }
    let mut out = io::stdout();
    if FLAGS_PUSHED.swap(false, Ordering::SeqCst) {
        let _ = execute!(out, PopKeyboardEnhancementFlags);
    }
    let _ = execute!(out, LeaveAlternateScreen, cursor::Show);
    let _ = terminal::disable_raw_mode();
    let _ = out.flush();
}

/// Installs (once) a panic hook: zero-velocity frames first, then the terminal restored, then the report,
/// so the message is readable and the robot is already stopped.
fn install_panic_hook() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    install_restoring_panic_hook(&INSTALLED, restore);
}

/// A panic hook, installed once per `installed`: the sender's zeros first, then `restore` (whatever the
/// caller did to the terminal), then the previous hook's report.
pub fn install_restoring_panic_hook(installed: &'static OnceLock<()>, restore: fn()) {
    crate::control::install_panic_hook();
    installed.get_or_init(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            crate::control::emergency_stop();
            restore();
            previous(info);
        }));
    });
}

/// The terminal in dashboard mode; dropping it restores the terminal.
pub struct Screen {
    pub terminal: Terminal<CrosstermBackend<Stdout>>,
    /// True when the terminal reports key releases (kitty keyboard protocol).
    pub key_release: bool,
}

impl Screen {
    /// Enters raw mode and the alternate screen; asks the terminal for key-release events.
    pub fn enter() -> Result<Self> {
        install_panic_hook();
        terminal::enable_raw_mode().context("cannot put the terminal in raw mode")?;
        TERMINAL_ACTIVE.store(true, Ordering::SeqCst);
        let mut out = io::stdout();
        // Ask before the input thread starts: the answer arrives on stdin.
        let key_release = terminal::supports_keyboard_enhancement().unwrap_or(false);
        if key_release {
            let flags = KeyboardEnhancementFlags::DISAMBIGUATE_ESCAPE_CODES
                | KeyboardEnhancementFlags::REPORT_EVENT_TYPES;
            if execute!(out, PushKeyboardEnhancementFlags(flags)).is_ok() {
                FLAGS_PUSHED.store(true, Ordering::SeqCst);
            }
        }
        execute!(out, EnterAlternateScreen, cursor::Hide).context("cannot switch to the alternate screen")?;
        let terminal = Terminal::new(CrosstermBackend::new(out)).context("cannot set up the terminal")?;
        Ok(Self { terminal, key_release: key_release && FLAGS_PUSHED.load(Ordering::SeqCst) })
    }
}

impl Screen {
    /// After the process was stopped with the terminal given back (SIGTSTP, Ctrl-Z): raw mode, the
    /// keyboard flags and the alternate screen again, and a full redraw. True if it had to.
    pub fn take_back(&mut self) -> Result<bool> {
        if TERMINAL_ACTIVE.load(Ordering::SeqCst) {
            return Ok(false);
        }
        terminal::enable_raw_mode().context("cannot put the terminal in raw mode again")?;
        TERMINAL_ACTIVE.store(true, Ordering::SeqCst);
        let mut out = io::stdout();
        if self.key_release {
            let flags = KeyboardEnhancementFlags::DISAMBIGUATE_ESCAPE_CODES
                | KeyboardEnhancementFlags::REPORT_EVENT_TYPES;
            if execute!(out, PushKeyboardEnhancementFlags(flags)).is_ok() {
                FLAGS_PUSHED.store(true, Ordering::SeqCst);
            }
        }
        execute!(out, EnterAlternateScreen, cursor::Hide).context("cannot switch to the alternate screen")?;
        self.terminal.clear().context("cannot redraw the terminal")?;
        Ok(true)
    }
}

impl Drop for Screen {
    fn drop(&mut self) {
        restore();
    }
}

/// What the input thread delivers.
pub enum Input {
    Event(Event),
    /// The terminal is gone (SSH dropped, the pseudo-terminal closed): time to stop.
    Closed(String),
}

/// Reads terminal events on a thread of its own, so input never waits for drawing (and vice versa). The
/// thread ends when `done` is set or the receiver goes away.
pub fn spawn_input(done: Arc<AtomicBool>) -> Result<Receiver<Input>> {
    let (sender, inbox) = mpsc::channel();
    std::thread::Builder::new()
        .name("tracerctl-input".into())
        .spawn(move || {
            while !done.load(Ordering::SeqCst) {
                let event = match event::poll(Duration::from_millis(50)) {
                    Ok(false) => continue,
                    Ok(true) => event::read(),
                    Err(error) => Err(error),
                };
                let input = match event {
                    Ok(event) => Input::Event(event),
                    Err(error) => Input::Closed(error.to_string()),
                };
                let closed = matches!(input, Input::Closed(_));
                if sender.send(input).is_err() || closed {
                    return;
                }
            }
        })
        .context("cannot start the input thread")?;
    Ok(inbox)
}
