//! Where there is no `SIGBUS` to catch (Windows), nothing is mapped: [`Window::map`] always declines and the
//! workers of `decode -j` read their ranges with positioned reads, which give the same output.

use std::fs::File;

/// A mapped window; none can exist here.
pub enum Window {}

impl Window {
    /// Always `None`: the reader reads instead.
    pub fn map(_file: &File, _offset: u64, _len: usize) -> Option<Self> {
        None
    }

    pub fn bytes(&self) -> &[u8] {
        match *self {}
    }

    pub fn faulted(&self) -> bool {
        match *self {}
    }
}
