//! A read at a given offset of a file that several threads share, on every platform: `pread` on Unix,
//! `ReadFile` with an offset on Windows (which also moves the file's cursor; the readers of `decode -j`
//! only ever read by position, so nothing relies on it).

use std::fs::File;
use std::io;

/// Reads up to `buf.len()` bytes at `offset`; fewer at the end of the file, as `read` does.
pub fn read_at(file: &File, buf: &mut [u8], offset: u64) -> io::Result<usize> {
    #[cfg(unix)]
    {
        std::os::unix::fs::FileExt::read_at(file, buf, offset)
    }
    #[cfg(windows)]
    {
        std::os::windows::fs::FileExt::seek_read(file, buf, offset)
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    #[test]
    fn reads_where_asked_and_short_at_the_end() {
        let mut file = tempfile::tempfile().unwrap();
        file.write_all(b"0123456789").unwrap();
        let mut buf = [0u8; 4];
        assert_eq!(read_at(&file, &mut buf, 3).unwrap(), 4);
        assert_eq!(&buf, b"3456");
        assert_eq!(read_at(&file, &mut buf, 8).unwrap(), 2);
        assert_eq!(&buf[..2], b"89");
        assert_eq!(read_at(&file, &mut buf, 10).unwrap(), 0);
    }
}
