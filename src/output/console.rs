//! Escape codes on the Windows console. Colour, drive's status line redrawn in place (`\r` + erase to the end
//! of the line) and the progress bar are written as ANSI escape codes; the Windows 10 and 11 console runs
//! them only with ENABLE_VIRTUAL_TERMINAL_PROCESSING on, and shows them as `←[K` otherwise. Terminals
//! elsewhere run them already.

/// Turns escape-code processing on for standard output and standard error where they are a console
/// (a pipe or a file is left alone). Called once at start.
#[cfg(windows)]
pub fn enable_escape_codes() {
    use windows_sys::Win32::System::Console::{
        GetConsoleMode, GetStdHandle, SetConsoleMode, ENABLE_VIRTUAL_TERMINAL_PROCESSING, STD_ERROR_HANDLE,
        STD_OUTPUT_HANDLE,
    };
    for which in [STD_OUTPUT_HANDLE, STD_ERROR_HANDLE] {
        // SAFETY: GetStdHandle takes a constant and returns a handle or an invalid/null one, which
        // GetConsoleMode rejects; the mode is written to a local; SetConsoleMode only changes the console's
        // own flags.
        unsafe {
            let handle = GetStdHandle(which);
            let mut mode = 0;
            if GetConsoleMode(handle, &mut mode) != 0 {
                SetConsoleMode(handle, mode | ENABLE_VIRTUAL_TERMINAL_PROCESSING);
            }
        }
    }
}

#[cfg(not(windows))]
pub fn enable_escape_codes() {}
