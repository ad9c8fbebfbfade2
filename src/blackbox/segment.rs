//! One ring segment being written: candump -L lines compressed a second at a time into independent zstd
//! frames, appended to the file. A crash loses at most the batch not yet written; the file is always a
//! sequence of whole frames (a failed write is cut back off), so every frame written reads back.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use super::names;

/// zstd's level for segments: level 3 (zstd's default) costs about 1 ms per second of a saturated bus.
pub const LEVEL: i32 = 3;

/// The segment file open for appending.
pub struct Segment {
    file: File,
    path: PathBuf,
    /// The first frame's time (the file's name), microseconds.
    pub start: u64,
    /// Bytes in the file: all whole zstd frames.
    pub bytes: u64,
    /// Lines (frames of the bus) in the file.
    pub lines: u64,
    compressor: zstd::bulk::Compressor<'static>,
    compressed: Vec<u8>,
}

impl Segment {
    /// Creates `DIR/<start>.log.zst` (appending if a file of that name exists: a zstd file may hold any
    /// number of frames).
    pub fn create(dir: &Path, start: u64) -> io::Result<Self> {
        let path = dir.join(names::segment_name(start));
        let file = OpenOptions::new().create(true).append(true).open(&path)?;
        let bytes = file.metadata()?.len();
        let mut compressor = zstd::bulk::Compressor::new(LEVEL)?;
        // As the zstd tool does: a flipped bit is then an error, not wrong lines.
        compressor.set_parameter(zstd::zstd_safe::CParameter::ChecksumFlag(true))?;
        Ok(Self { file, path, start, bytes, lines: 0, compressor, compressed: Vec::new() })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends `text` (whole lines, `lines` of them) as one zstd frame. On failure (a full disk) the
    /// file is cut back to its whole frames and the error returned: the batch is not in the file.
    pub fn append(&mut self, text: &[u8], lines: u64) -> io::Result<()> {
        if text.is_empty() {
            return Ok(());
        }
        self.compressed.clear();
        self.compressed.reserve(zstd::zstd_safe::compress_bound(text.len()));
        self.compressor.compress_to_buffer(text, &mut self.compressed)?;
        if let Err(error) = self.file.write_all(&self.compressed) {
            // A partial frame would make every later frame unreadable: cut it off.
            let _ = self.file.set_len(self.bytes);
            return Err(error);
        }
        self.bytes += self.compressed.len() as u64;
        self.lines += lines;
        Ok(())
    }

    /// Data and size to the disk (the fsync schedule is the caller's).
    pub fn sync(&self) -> io::Result<()> {
        self.file.sync_data()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_append_is_a_frame_and_the_file_reads_whole() {
        let dir = tempfile::tempdir().unwrap();
        let mut segment = Segment::create(dir.path(), 1_700_000_000_000_000).unwrap();
        assert_eq!(segment.path().file_name().unwrap(), "20231114T221320.000Z.log.zst");
        segment.append(b"(1700000000.000000) can0 211#00\n", 1).unwrap();
        segment.append(b"", 0).unwrap();
        segment.append(b"(1700000001.000000) can0 221#01\n(1700000001.500000) can0 221#02\n", 2).unwrap();
        segment.sync().unwrap();
        assert_eq!(segment.lines, 3);
        let bytes = std::fs::read(segment.path()).unwrap();
        assert_eq!(bytes.len() as u64, segment.bytes);
        let text = zstd::decode_all(&bytes[..]).unwrap();
        assert_eq!(
            text,
            b"(1700000000.000000) can0 211#00\n(1700000001.000000) can0 221#01\n(1700000001.500000) can0 221#02\n"
        );
        // Two frames: the first one alone is whole too (what a crash after it leaves).
        let first = zstd::zstd_safe::find_frame_compressed_size(&bytes).unwrap();
        assert!(first < bytes.len());
        assert_eq!(zstd::decode_all(&bytes[..first]).unwrap(), b"(1700000000.000000) can0 211#00\n");
    }

    #[test]
    fn a_flipped_bit_is_an_error_not_wrong_lines() {
        let dir = tempfile::tempdir().unwrap();
        let mut segment = Segment::create(dir.path(), 5_000_000).unwrap();
        let text = b"(1700000000.000000) can0 211#0000010300000000\n".repeat(20);
        segment.append(&text, 20).unwrap();
        let mut bytes = std::fs::read(segment.path()).unwrap();
        assert_eq!(zstd::decode_all(&bytes[..]).unwrap(), text);
        // A literal byte of the block, past the frame header: without a checksum, silently other text.
        let at = bytes.len() / 2;
        bytes[at] ^= 0x01;
        assert!(zstd::decode_all(&bytes[..]).is_err());
    }

    #[test]
    fn an_existing_file_of_the_same_name_is_appended_to() {
        let dir = tempfile::tempdir().unwrap();
        let mut first = Segment::create(dir.path(), 5_000_000).unwrap();
        first.append(b"a\n", 1).unwrap();
        drop(first);
        let mut again = Segment::create(dir.path(), 5_000_000).unwrap();
        assert!(again.bytes > 0);
        again.append(b"b\n", 1).unwrap();
        assert_eq!(zstd::decode_all(&std::fs::read(again.path()).unwrap()[..]).unwrap(), b"a\nb\n");
    }
}
