//! Where there is no `SIGBUS` to catch (Windows), nothing is mapped: no [`FaultHandler`] is ever installed,
//! so no [`Window`] exists, and the workers of `decode -j` read their ranges with positioned reads, which give
//! the same output.

use std::fs::File;

/// Proof of a fault handler; none can exist here.
#[derive(Clone, Copy, Debug)]
pub enum FaultHandler {}

/// Always `None`: the workers read instead.
pub fn install_fault_handler() -> Option<FaultHandler> {
    None
}

/// A mapped window; none can exist here.
pub enum Window {}

impl Window {
    /// Unreachable: no [`FaultHandler`] exists.
    ///
    /// # Safety
    ///
    /// As on Unix (mapped.rs): the caller only parses the bytes of a window that did not fault.
    pub unsafe fn map(handler: FaultHandler, _file: &File, _offset: u64, _len: usize) -> Option<Self> {
        match handler {}
    }

    pub fn bytes(&self) -> &[u8] {
        match *self {}
    }

    pub fn faulted(&self) -> bool {
        match *self {}
    }
}
