//! Windows of a plain file mapped into memory, for the workers of `decode -j`: their lines are decoded where
//! the page cache holds them, without the kernel's copy into a read buffer (a tenth of the parallel summary's
//! time, docs/performance.md). Mapping is decode's choice, made once at the start (`--no-mmap` and
//! `TRACERCTL_NO_MMAP` turn it off; the output is the same).
//!
//! A mapped file that shrinks while it is read (another program truncates it) or whose disk fails makes the
//! next touch of a page past its end raise `SIGBUS`, which would end the process without a word. A handler,
//! installed by decode's set-up ([`install_fault_handler`]) before any window is mapped, turns such a fault
//! inside the faulting thread's own window into a page of zeros and marks the window ([`Window::faulted`]):
//! the reader then decodes the window's range again without mapping, which finds where the file now ends or
//! the disk's error, so no zero mapped in here is ever counted. A fault anywhere else goes to the handler
//! that was there before, as if this one did not exist.

use std::fs::File;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::OnceLock;

use memmap2::{Mmap, MmapOptions};

/// A thread's mapped window, for the handler: `[start, end)`, empty when the thread maps none.
///
/// `SIGBUS` from a mapped page is delivered to the thread that touched it, and each thread maps at most one
/// window at a time and is the only one to change its slot: the handler looks at its own thread's slot
/// only, which cannot change while the handler runs. No other thread's addresses are ever read, so no torn
/// read can make up a window that holds the faulting address.
struct Slot {
    start: AtomicUsize,
    end: AtomicUsize,
    faulted: AtomicBool,
}

impl Slot {
    const fn free() -> Self {
        Self { start: AtomicUsize::new(0), end: AtomicUsize::new(0), faulted: AtomicBool::new(false) }
    }

    fn is_free(&self) -> bool {
        self.end.load(Ordering::Acquire) == 0
    }

    fn set(&self, start: usize, end: usize) {
        self.start.store(start, Ordering::Release);
        self.end.store(end, Ordering::Release);
    }

    fn holds(&self, address: usize) -> bool {
        self.start.load(Ordering::Acquire) <= address && address < self.end.load(Ordering::Acquire)
    }
}

thread_local! {
    // Initialised in place, no destructor: reading it in the signal handler touches only this thread's
    // static TLS block.
    static OWN: Slot = const { Slot::free() };
}

/// Proof that the `SIGBUS` handler is installed: windows are mapped only with it.
#[derive(Clone, Copy, Debug)]
pub struct FaultHandler(());

/// The page size and the `SIGBUS` action before ours, for the handler: set before it is installed.
static PREVIOUS: OnceLock<(usize, libc::sigaction)> = OnceLock::new();
/// Whether the handler is installed (once per process).
static INSTALLED: OnceLock<bool> = OnceLock::new();

/// Installs the `SIGBUS` handler (once per process); `None` when it cannot be (the workers then read).
pub fn install_fault_handler() -> Option<FaultHandler> {
    INSTALLED.get_or_init(install).then_some(FaultHandler(()))
}

/// A window of the file, mapped and watched for faults until dropped; it stays on the thread that mapped it.
pub struct Window {
    map: Mmap,
    /// Not `Send`: the slot watched is the mapping thread's.
    on_this_thread: PhantomData<*const ()>,
}

impl Window {
    /// Maps `len` bytes of `file` from `offset`; `None` when that cannot be done, or when this thread
    /// already holds a window (the reader then reads).
    ///
    /// # Safety
    ///
    /// Another program may change or cut the file while it is mapped, so the bytes of [`Window::bytes`] may
    /// change under the slice: the caller only parses them (any bytes are valid input) and takes none of
    /// its output from a window that [`Window::faulted`], or whose file shrank, after reading it.
    pub unsafe fn map(_handler: FaultHandler, file: &File, offset: u64, len: usize) -> Option<Self> {
        if !OWN.with(Slot::is_free) {
            return None;
        }
        // SAFETY: the caller's contract above: the mapping is only read and its bytes only parsed; a page
        // that vanishes reads as zeros (the handler) and the window is marked, instead of the process ending.
        let map = unsafe { MmapOptions::new().offset(offset).len(len).map(file) }.ok()?;
        let start = map.as_ptr() as usize;
        OWN.with(|slot| {
            slot.faulted.store(false, Ordering::Release);
            slot.set(start, start + map.len());
        });
        Some(Self { map, on_this_thread: PhantomData })
    }

    pub fn bytes(&self) -> &[u8] {
        &self.map
    }

    /// Whether a page of the window could not be read (its bytes read as zeros).
    pub fn faulted(&self) -> bool {
        OWN.with(|slot| slot.faulted.load(Ordering::Acquire))
    }
}

impl Drop for Window {
    fn drop(&mut self) {
        // Emptied before the mapping goes, so the handler never claims an address no longer the window's.
        OWN.with(|slot| slot.set(0, 0));
    }
}

/// Installs the `SIGBUS` handler; whether it could be.
fn install() -> bool {
    // SAFETY: sysconf has no preconditions.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    let Some(page) = usize::try_from(page).ok().filter(|page| page.is_power_of_two()) else { return false };
    // SAFETY: a zeroed sigaction is a valid value; both calls get valid pointers, and the handler only makes
    // async-signal-safe calls (mmap, sigaction) and reads atomics, its thread's slot and `PREVIOUS`, set
    // before.
    unsafe {
        let mut previous: libc::sigaction = std::mem::zeroed();
        if libc::sigaction(libc::SIGBUS, std::ptr::null(), &mut previous) != 0 {
            return false;
        }
        // Set before the handler can run: it reads the previous action from here.
        let _ = PREVIOUS.set((page, previous));
        let mut action: libc::sigaction = std::mem::zeroed();
        action.sa_sigaction = on_bus_error
            as extern "C" fn(libc::c_int, *mut libc::siginfo_t, *mut libc::c_void)
            as libc::sighandler_t;
        action.sa_flags = libc::SA_SIGINFO | libc::SA_ONSTACK;
        libc::sigemptyset(&mut action.sa_mask);
        libc::sigaction(libc::SIGBUS, &action, std::ptr::null_mut()) == 0
    }
}

extern "C" fn on_bus_error(_signal: libc::c_int, info: *mut libc::siginfo_t, _context: *mut libc::c_void) {
    let Some(&(page, ref previous)) = PREVIOUS.get() else { return };
    // SAFETY: the kernel passes a valid siginfo to an SA_SIGINFO handler.
    let address = unsafe { (*info).si_addr() } as usize;
    let taken = OWN.with(|slot| {
        if !slot.holds(address) {
            return false;
        }
        // SAFETY: the page lies inside this thread's live mapping (the slot is emptied before it is
        // unmapped, by this thread); replacing it with zeros in place changes nothing else.
        let zeros = unsafe {
            libc::mmap(
                (address & !(page - 1)) as *mut libc::c_void,
                page,
                libc::PROT_READ,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS | libc::MAP_FIXED,
                -1,
                0,
            )
        };
        let replaced = zeros != libc::MAP_FAILED;
        if replaced {
            slot.faulted.store(true, Ordering::Release);
        }
        replaced
    });
    if !taken {
        // Not this thread's window: the action before ours takes the fault, which recurs on return.
        // SAFETY: `previous` is the action sigaction reported, restored as it was.
        unsafe { libc::sigaction(libc::SIGBUS, previous, std::ptr::null_mut()) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    fn handler() -> FaultHandler {
        install_fault_handler().expect("the handler installs")
    }

    fn file_of(text: &[u8]) -> File {
        let mut file = tempfile::tempfile().unwrap();
        file.write_all(text).unwrap();
        file
    }

    /// The handler looks only at the faulting thread's window: another thread's window, mapped and held
    /// while this thread asks, never holds an address for it.
    #[test]
    fn the_handler_sees_only_its_own_threads_window() {
        let file = file_of(&b"0123456789abcde\n".repeat(512));
        // SAFETY: the file is only read here, and nobody changes it.
        let window = unsafe { Window::map(handler(), &file, 0, 8192) }.expect("mapped");
        let inside = window.bytes().as_ptr() as usize + 100;
        assert!(OWN.with(|slot| slot.holds(inside)), "this thread's own window");
        let elsewhere = std::thread::spawn(move || OWN.with(|slot| slot.holds(inside))).join().unwrap();
        assert!(!elsewhere, "another thread never takes this window's fault");
        // SAFETY: as above.
        assert!(unsafe { Window::map(handler(), &file, 0, 4096) }.is_none(), "one window per thread");
        drop(window);
        assert!(!OWN.with(|slot| slot.holds(inside)), "a dropped window holds nothing");
    }

    #[test]
    fn a_window_of_a_file_that_shrinks_reads_zeros_and_is_marked() {
        let text = b"0123456789abcde\n".repeat(4096);
        let file = file_of(&text);
        // SAFETY: the test cuts the file on purpose; it reads the window's bytes only to check them.
        let window = unsafe { Window::map(handler(), &file, 16, text.len() - 16) }.expect("mapped");
        assert_eq!(&window.bytes()[..16], b"0123456789abcde\n");
        assert!(!window.faulted());
        // Cut to one page: the pages after it are gone from under the mapping.
        file.set_len(4096).unwrap();
        let past = window.bytes().len() - 1;
        assert_eq!(window.bytes()[past], 0, "a vanished page reads as zeros");
        assert!(window.faulted());
        assert_eq!(&window.bytes()[..16], b"0123456789abcde\n", "the pages still there are intact");
        drop(window);
        // SAFETY: as above.
        let again = unsafe { Window::map(handler(), &file, 0, 4096) }.expect("mapped");
        assert!(!again.faulted(), "a slot's mark goes with its window");
    }
}
