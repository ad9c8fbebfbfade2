//! Ctrl-C (or SIGTERM, SIGHUP) while `decode` reads a live stream: `candump -L can0 | tracerctl decode -`
//! spends its time blocked in `read` on the pipe. The signal must end that read so what was decoded is
//! written out with the totals, and the exit status is 128 + the signal.
//!
//! signal-hook installs its handlers with `SA_RESTART`, which restarts a blocked read instead of ending it,
//! and the kernel may run the handler on any thread. So, on Linux, `SA_RESTART` is cleared for these
//! signals (only `decode` does this) and the signal is sent on to the main thread, repeatedly, since it may
//! arrive just before the read starts. The read then fails with EINTR, and the reader sees the flag.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::Result;

use crate::signals::SignalFlag;

/// When the threads of `decode -j` stop reading: a termination signal, or the merging thread stopped
/// taking chunks (an error, `--strict`). Every read loop looks at it, so a thread inside an endless line (a
/// decompression bomb of zeros, read on to its `\n`) lets go at once.
#[derive(Clone)]
pub struct StopReading {
    signals: SignalFlag,
    finished: Arc<AtomicBool>,
}

impl StopReading {
    pub fn new(signals: SignalFlag, finished: Arc<AtomicBool>) -> Self {
        Self { signals, finished }
    }

    pub fn now(&self) -> bool {
        self.signals.received().is_some() || self.finished.load(Ordering::Relaxed)
    }
}

#[cfg(target_os = "linux")]
pub fn listen() -> Result<SignalFlag> {
    use std::time::Duration;

    // SAFETY: pthread_self has no preconditions.
    let main_thread = MainThread(unsafe { libc::pthread_self() });
    let forwarding = AtomicBool::new(false);
    let flag = crate::signals::listen(move |signal| {
        if forwarding.swap(true, Ordering::SeqCst) {
            return;
        }
        // The process exits as soon as the main thread sees the flag; until then, keep waking it.
        loop {
            main_thread.wake(signal);
            std::thread::sleep(Duration::from_millis(50));
        }
    })?;
    for signal in crate::signals::TERMINATION {
        // SAFETY: reads the action signal-hook installed and writes it back without SA_RESTART; the
        // sigaction struct is fully initialised by the first call before it is used.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(signal, std::ptr::null(), &mut action) == 0 {
                action.sa_flags &= !libc::SA_RESTART;
                libc::sigaction(signal, &action, std::ptr::null_mut());
            }
        }
    }
    Ok(flag)
}

/// The main thread's handle, for the signal thread to wake it. musl's `pthread_t` is a pointer, so not
/// `Send` by itself.
#[cfg(target_os = "linux")]
#[derive(Clone, Copy)]
struct MainThread(libc::pthread_t);

// SAFETY: a pthread_t is an opaque handle, valid from any thread of the process; it is only passed to
// pthread_kill, never dereferenced.
#[cfg(target_os = "linux")]
unsafe impl Send for MainThread {}

#[cfg(target_os = "linux")]
impl MainThread {
    fn wake(&self, signal: i32) {
        // SAFETY: the main thread lives until the process exits, which ends the caller's loop too.
        unsafe { libc::pthread_kill(self.0, signal) };
    }
}

/// Elsewhere the flag is seen before the next read (a stream that goes quiet waits for its next line).
#[cfg(not(target_os = "linux"))]
pub fn listen() -> Result<SignalFlag> {
    crate::signals::listen(|_| {})
}
