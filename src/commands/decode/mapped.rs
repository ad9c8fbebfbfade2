//! Windows of a plain file mapped into memory, for the workers of `decode -j`: their lines are decoded where
//! the page cache holds them, without the kernel's copy into a read buffer (a tenth of the parallel summary's
//! time, docs/performance.md).
//!
//! A mapped file that shrinks while it is read (another program truncates it) or whose disk fails makes the
//! next touch of a page past its end raise `SIGBUS`, which would end the process without a word. A handler,
//! installed with the first window, turns such a fault inside a window into a page of zeros and marks the
//! window ([`Window::faulted`]): the reader then decodes the window's range again without mapping, which
//! finds where the file now ends or the disk's error, so no zero mapped in here is ever counted. A fault
//! anywhere else goes to the handler that was there before, as if this one did not exist.

use std::fs::File;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::OnceLock;

use memmap2::{Mmap, MmapOptions};

/// Windows mapped at once: one per thread that reads ranges (the workers, at most 64, and the merging
/// thread); a thread finding none free reads without a mapping.
const SLOTS: usize = 128;

/// A mapped window's addresses, for the handler: `[start, end)`, empty when the slot is free.
///
/// The handler runs on the faulting thread while other threads drop their windows and map new ones in the
/// same slots: read without care, a slot's `end` could be an old window's and its `start` a new one's, a
/// range that never existed, which may hold the faulting address and take the fault from the window it
/// belongs to (left unmarked: its zeros would be decoded). So a slot is a sequence lock: `version` is odd
/// while its addresses change, and the handler believes only addresses read between two equal even
/// versions. A slot that changes meanwhile is never the faulting window's: a window is only mapped,
/// read and dropped by its own thread, which is in the handler.
struct Slot {
    taken: AtomicBool,
    version: AtomicUsize,
    start: AtomicUsize,
    end: AtomicUsize,
    faulted: AtomicBool,
}

static WINDOWS: [Slot; SLOTS] = [const { Slot::free() }; SLOTS];

impl Slot {
    const fn free() -> Self {
        Self {
            taken: AtomicBool::new(false),
            version: AtomicUsize::new(0),
            start: AtomicUsize::new(0),
            end: AtomicUsize::new(0),
            faulted: AtomicBool::new(false),
        }
    }

    /// Sets the window's addresses (`[0, 0)`: none), as one change for the handler.
    fn set(&self, start: usize, end: usize) {
        self.version.fetch_add(1, Ordering::AcqRel);
        self.start.store(start, Ordering::Release);
        self.end.store(end, Ordering::Release);
        self.version.fetch_add(1, Ordering::Release);
    }

    /// Whether `address` lies in the window, read as one; `between` runs between the reads (tests use it to
    /// change the slot there).
    fn holds(&self, address: usize, between: impl Fn()) -> bool {
        let version = self.version.load(Ordering::Acquire);
        if version % 2 == 1 {
            return false;
        }
        let end = self.end.load(Ordering::Acquire);
        between();
        let start = self.start.load(Ordering::Acquire);
        self.version.load(Ordering::Acquire) == version && start <= address && address < end
    }
}

/// Whether the handler is installed (nothing is mapped without it).
static INSTALLED: OnceLock<bool> = OnceLock::new();
/// The page size and the `SIGBUS` action before ours, for the handler: set before it is installed.
static PREVIOUS: OnceLock<(usize, libc::sigaction)> = OnceLock::new();

/// A window of the file, mapped and watched for faults until dropped.
pub struct Window {
    map: Mmap,
    slot: &'static Slot,
}

impl Window {
    /// Maps `len` bytes of `file` from `offset`; `None` when that cannot be done (the reader then reads).
    pub fn map(file: &File, offset: u64, len: usize) -> Option<Self> {
        if !*INSTALLED.get_or_init(install) {
            return None;
        }
        let slot = WINDOWS.iter().find(|slot| !slot.taken.swap(true, Ordering::Acquire))?;
        // SAFETY: the mapping is only read; a change of the file under it is what the handler is for (a page
        // that vanishes reads as zeros and the window is marked, instead of the process ending).
        match unsafe { MmapOptions::new().offset(offset).len(len).map(file) } {
            Ok(map) => {
                let start = map.as_ptr() as usize;
                slot.faulted.store(false, Ordering::Release);
                slot.set(start, start + map.len());
                Some(Self { map, slot })
            }
            Err(_) => {
                slot.taken.store(false, Ordering::Release);
                None
            }
        }
    }

    pub fn bytes(&self) -> &[u8] {
        &self.map
    }

    /// Whether a page of the window could not be read (its bytes read as zeros).
    pub fn faulted(&self) -> bool {
        self.slot.faulted.load(Ordering::Acquire)
    }
}

impl Drop for Window {
    fn drop(&mut self) {
        // Emptied before the mapping goes, so the handler never claims an address no longer the window's.
        self.slot.set(0, 0);
        self.slot.taken.store(false, Ordering::Release);
    }
}

/// Installs the `SIGBUS` handler; whether it could be.
fn install() -> bool {
    // SAFETY: sysconf has no preconditions.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    let Some(page) = usize::try_from(page).ok().filter(|page| page.is_power_of_two()) else { return false };
    // SAFETY: a zeroed sigaction is a valid value; both calls get valid pointers, and the handler only makes
    // async-signal-safe calls (mmap, sigaction) and reads atomics and `PREVIOUS`, set before.
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
    for slot in &WINDOWS {
        if slot.holds(address, || {}) {
            // SAFETY: the page lies inside a live mapping of ours (the slot is emptied before it is unmapped);
            // replacing it with zeros in place changes nothing else.
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
            if zeros != libc::MAP_FAILED {
                slot.faulted.store(true, Ordering::Release);
                return;
            }
        }
    }
    // Not a window's: the action before ours takes the fault, which recurs on return.
    // SAFETY: `previous` is the action sigaction reported, restored as it was.
    unsafe { libc::sigaction(libc::SIGBUS, previous, std::ptr::null_mut()) };
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// The interleaving the handler once lost a fault to: it read a slot's `end` (an old window above the
    /// faulting address), then the slot's thread dropped that window and mapped one below the address, then
    /// the handler read the new `start`: `[new start, old end)` held the address, and the fault went to
    /// this slot instead of the faulting window's.
    #[test]
    fn a_slot_remapped_while_the_handler_reads_it_does_not_take_the_fault() {
        let slot = Slot::free();
        slot.set(0x4000, 0x5000);
        let address = 0x3000;
        let remap = || {
            slot.set(0, 0);
            slot.set(0x1000, 0x2000);
        };
        assert!(!slot.holds(address, remap), "torn addresses are not believed");
        assert!(!slot.holds(address, || {}), "nor are the new window's");
        assert!(slot.holds(0x1800, || {}));
        let torn = Slot { start: AtomicUsize::new(0x1000), end: AtomicUsize::new(0x5000), ..Slot::free() };
        assert!(torn.holds(address, || {}), "the range a torn read made up would have held it");
    }

    #[test]
    fn a_window_of_a_file_that_shrinks_reads_zeros_and_is_marked() {
        let mut file = tempfile::tempfile().unwrap();
        let text = b"0123456789abcde\n".repeat(4096);
        file.write_all(&text).unwrap();
        let window = Window::map(&file, 16, text.len() - 16).expect("mapped");
        assert_eq!(&window.bytes()[..16], b"0123456789abcde\n");
        assert!(!window.faulted());
        // Cut to one page: the pages after it are gone from under the mapping.
        file.set_len(4096).unwrap();
        let past = window.bytes().len() - 1;
        assert_eq!(window.bytes()[past], 0, "a vanished page reads as zeros");
        assert!(window.faulted());
        assert_eq!(&window.bytes()[..16], b"0123456789abcde\n", "the pages still there are intact");
        drop(window);
        let again = Window::map(&file, 0, 4096).expect("mapped");
        assert!(!again.faulted(), "a slot's mark goes with its window");
    }
}
