//! Termination signals (SIGINT, SIGTERM, SIGHUP) turned into a flag commands poll, plus a callback that runs
//! at once on a helper thread (to stop the robot without waiting for the next poll).

use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;

#[cfg(unix)]
use anyhow::Context;
use anyhow::Result;

use crate::exit::SIGNAL_BASE;

/// Ctrl-C: libc's number (2 on every system, Windows' C runtime included).
pub const SIGINT: i32 = libc::SIGINT;
/// `kill`'s default: libc's number (15).
pub const SIGTERM: i32 = libc::SIGTERM;
/// The terminal went away: libc's number (1).
#[cfg(unix)]
pub const SIGHUP: i32 = libc::SIGHUP;
/// Windows' C runtime has no SIGHUP; a closed console stands for it with the POSIX number, so that the exit
/// status is the same as on Linux.
#[cfg(not(unix))]
pub const SIGHUP: i32 = 1;

/// The termination signals every command that can move the robot handles.
#[cfg(unix)]
pub const TERMINATION: [i32; 3] = [SIGINT, SIGTERM, SIGHUP];

/// A termination signal a command caught: what its end says and the exit status it gives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Caught {
    pub signal: i32,
}

impl Caught {
    /// `SIGINT`, `SIGTERM`, `SIGHUP`, or `a signal` for any other.
    pub fn name(self) -> &'static str {
        match self.signal {
            SIGINT => "SIGINT",
            SIGTERM => "SIGTERM",
            SIGHUP => "SIGHUP",
            _ => "a signal",
        }
    }

    /// The conventional exit status after a signal: 128 + its number (130 SIGINT, 143 SIGTERM, 129 SIGHUP).
    pub fn exit_status(self) -> u8 {
        (i32::from(SIGNAL_BASE) + self.signal).clamp(0, 255) as u8
    }
}

/// Which signal arrived (0 = none yet).
#[derive(Clone, Default)]
pub struct SignalFlag(Arc<AtomicI32>);

impl SignalFlag {
    /// The signal number received, if any.
    pub fn received(&self) -> Option<i32> {
        match self.0.load(Ordering::SeqCst) {
            0 => None,
            signal => Some(signal),
        }
    }

    /// The signal received, if any.
    pub fn caught(&self) -> Option<Caught> {
        self.received().map(|signal| Caught { signal })
    }
}

/// Starts listening for termination signals; `on_signal` runs on a helper thread as soon as one arrives.
#[cfg(unix)]
pub fn listen(on_signal: impl Fn(i32) + Send + 'static) -> Result<SignalFlag> {
    listen_inner(on_signal, None::<fn()>)
}

/// As [`listen`], and SIGTSTP (Ctrl-Z, `kill -TSTP`) runs `before_stop` (which stops the robot and returns
/// once the zero frames have left) and then stops the process for real. After SIGCONT the sender sees the
/// gap in its clock and holds zero until a fresh command.
#[cfg(unix)]
pub fn listen_suspendable(
    on_signal: impl Fn(i32) + Send + 'static,
    before_stop: impl Fn() + Send + 'static,
) -> Result<SignalFlag> {
    listen_inner(on_signal, Some(before_stop))
}

#[cfg(unix)]
fn listen_inner(
    on_signal: impl Fn(i32) + Send + 'static,
    before_stop: Option<impl Fn() + Send + 'static>,
) -> Result<SignalFlag> {
    use signal_hook::consts::SIGTSTP;
    let flag = SignalFlag::default();
    let mut wanted = TERMINATION.to_vec();
    if before_stop.is_some() {
        wanted.push(SIGTSTP);
    }
    let mut signals =
        signal_hook::iterator::Signals::new(wanted).context("cannot install signal handlers")?;
    let inner = Arc::clone(&flag.0);
    std::thread::Builder::new()
        .name("tracerctl-signals".into())
        .spawn(move || {
            for signal in signals.forever() {
                if signal == SIGTSTP {
                    if let Some(before_stop) = &before_stop {
                        before_stop();
                    }
                    // SIGSTOP cannot be caught: the process stops here, as Ctrl-Z expects, until SIGCONT.
                    let _ = signal_hook::low_level::raise(signal_hook::consts::SIGSTOP);
                    continue;
                }
                inner.store(signal, Ordering::SeqCst);
                on_signal(signal);
            }
        })
        .context("cannot start the signal thread")?;
    Ok(flag)
}

/// On Windows, the console's control events stand for the signals: Ctrl-C and Ctrl-Break for SIGINT, closing
/// the console window, logging off and shutting down for SIGHUP (the terminal went away), with the same
/// messages and exit statuses as on Linux. There is no Ctrl-Z job control, so `before_stop` never runs.
#[cfg(windows)]
pub fn listen(on_signal: impl Fn(i32) + Send + 'static) -> Result<SignalFlag> {
    console::listen(Box::new(on_signal))
}

#[cfg(windows)]
pub fn listen_suspendable(
    on_signal: impl Fn(i32) + Send + 'static,
    _before_stop: impl Fn() + Send + 'static,
) -> Result<SignalFlag> {
    console::listen(Box::new(on_signal))
}

/// The signal a Windows console control event stands for (the event numbers are wincon.h's, fixed by the
/// Windows API): Ctrl-C and Ctrl-Break interrupt, closing the console, logging off and shutting down hang
/// up. Pure, so that it is tested on every platform.
#[cfg_attr(not(windows), allow(dead_code))]
fn console_signal(event: u32) -> Option<i32> {
    const CTRL_C_EVENT: u32 = 0;
    const CTRL_BREAK_EVENT: u32 = 1;
    const CTRL_CLOSE_EVENT: u32 = 2;
    const CTRL_LOGOFF_EVENT: u32 = 5;
    const CTRL_SHUTDOWN_EVENT: u32 = 6;
    match event {
        CTRL_C_EVENT | CTRL_BREAK_EVENT => Some(SIGINT),
        CTRL_CLOSE_EVENT | CTRL_LOGOFF_EVENT | CTRL_SHUTDOWN_EVENT => Some(SIGHUP),
        _ => None,
    }
}

#[cfg(windows)]
mod console {
    use std::sync::atomic::{AtomicI32, Ordering};
    use std::sync::Arc;
    use std::time::Duration;

    use anyhow::{bail, Result};
    use parking_lot::Mutex;
    use windows_sys::core::BOOL;
    use windows_sys::Win32::System::Console::SetConsoleCtrlHandler;

    use super::{SignalFlag, SIGHUP};

    // console_signal's numbers are the API's.
    const _: () = {
        use windows_sys::Win32::System::Console as c;
        assert!(c::CTRL_C_EVENT == 0 && c::CTRL_BREAK_EVENT == 1 && c::CTRL_CLOSE_EVENT == 2);
        assert!(c::CTRL_LOGOFF_EVENT == 5 && c::CTRL_SHUTDOWN_EVENT == 6);
    };

    /// How long a closing console waits for the command to finish on its own once the robot is stopped;
    /// Windows ends the process 5 s after the close whatever the handler does.
    const CLOSE_GRACE: Duration = Duration::from_secs(3);

    type Listener = (Arc<AtomicI32>, Box<dyn Fn(i32) + Send>);

    /// Every flag and callback of this process; the handler is a plain function, so they live here.
    static LISTENERS: Mutex<Vec<Listener>> = Mutex::new(Vec::new());

    pub(super) fn listen(on_signal: Box<dyn Fn(i32) + Send>) -> Result<SignalFlag> {
        let flag = SignalFlag::default();
        let mut listeners = LISTENERS.lock();
        if listeners.is_empty() {
            // SAFETY: `handle` is a valid handler for the whole life of the process (a plain function).
            if unsafe { SetConsoleCtrlHandler(Some(handle), 1) } == 0 {
                bail!("cannot install the console control handler: {}", std::io::Error::last_os_error());
            }
        }
        listeners.push((Arc::clone(&flag.0), on_signal));
        Ok(flag)
    }

    /// Runs on a thread Windows starts for the event: an ordinary thread, so the callbacks (which stop the
    /// robot and return once the zero frames have left) run here, before anything can end the process.
    unsafe extern "system" fn handle(event: u32) -> BOOL {
        let Some(signal) = super::console_signal(event) else { return 0 };
        // A second event while the first is handled waits here; the robot is stopped by then.
        let listeners = LISTENERS.lock();
        for (flag, on_signal) in listeners.iter() {
            flag.store(signal, Ordering::SeqCst);
            on_signal(signal);
        }
        drop(listeners);
        if signal == SIGHUP {
            // Returning lets Windows end the process at once: give the command its own exit first.
            std::thread::sleep(CLOSE_GRACE);
        }
        1
    }
}

#[cfg(not(any(unix, windows)))]
pub fn listen(_on_signal: impl Fn(i32) + Send + 'static) -> Result<SignalFlag> {
    Ok(SignalFlag::default())
}

#[cfg(not(any(unix, windows)))]
pub fn listen_suspendable(
    _on_signal: impl Fn(i32) + Send + 'static,
    _before_stop: impl Fn() + Send + 'static,
) -> Result<SignalFlag> {
    Ok(SignalFlag::default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn console_events_stand_for_the_signals_with_their_names_and_statuses() {
        let status = |event| {
            let flag = SignalFlag::default();
            flag.0.store(console_signal(event).unwrap(), Ordering::SeqCst);
            let caught = flag.caught().unwrap();
            (caught.name(), caught.exit_status())
        };
        assert_eq!(status(0), ("SIGINT", 130), "Ctrl-C");
        assert_eq!(status(1), ("SIGINT", 130), "Ctrl-Break");
        assert_eq!(status(2), ("SIGHUP", 129), "console closed");
        assert_eq!(status(5), ("SIGHUP", 129), "logoff");
        assert_eq!(status(6), ("SIGHUP", 129), "shutdown");
        assert_eq!(console_signal(3), None);
        assert_eq!(console_signal(4), None);
    }

    #[test]
    fn caught_signals_name_themselves_and_give_128_plus_their_number() {
        let caught = |signal| (Caught { signal }.name(), Caught { signal }.exit_status());
        assert_eq!(caught(SIGINT), ("SIGINT", 130));
        assert_eq!(caught(SIGTERM), ("SIGTERM", 143));
        assert_eq!(caught(SIGHUP), ("SIGHUP", 129));
        assert_eq!(caught(10), ("a signal", 138));
        assert_eq!(caught(200), ("a signal", 255), "clamped to a byte");
        assert_eq!(SignalFlag::default().caught(), None);
    }
}
