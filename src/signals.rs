//! Termination signals (SIGINT, SIGTERM, SIGHUP) turned into a flag commands poll, plus a callback that runs
//! at once on a helper thread (to stop the robot without waiting for the next poll).

use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;

use anyhow::{Context, Result};

/// The termination signals every command that can move the robot handles.
#[cfg(unix)]
pub const TERMINATION: [i32; 3] =
    [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM, signal_hook::consts::SIGHUP];

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

    /// The conventional exit status after a signal: 128 + its number.
    pub fn exit_status(&self) -> Option<u8> {
        self.received().map(|signal| (128 + signal).clamp(0, 255) as u8)
    }

    pub fn name(&self) -> &'static str {
        match self.received() {
            Some(2) => "SIGINT",
            Some(15) => "SIGTERM",
            Some(1) => "SIGHUP",
            Some(_) => "a signal",
            None => "",
        }
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

#[cfg(not(unix))]
pub fn listen(_on_signal: impl Fn(i32) + Send + 'static) -> Result<SignalFlag> {
    Ok(SignalFlag::default())
}

#[cfg(not(unix))]
pub fn listen_suspendable(
    _on_signal: impl Fn(i32) + Send + 'static,
    _before_stop: impl Fn() + Send + 'static,
) -> Result<SignalFlag> {
    Ok(SignalFlag::default())
}
