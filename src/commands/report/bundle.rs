//! The bundle itself: which members fit under the size cap (pure: [`fit`]), and the tar.gz writer. A
//! member from the recorder's directory is read when it is written, up to the size it had when it was
//! chosen (a segment still being written grows meanwhile; one rotated away is left out and said).

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use flate2::write::GzEncoder;

/// A tar header, and the unit data is padded to.
const BLOCK: u64 = 512;

/// What a member holds: text made by the report, or a file of the recorder's directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Content {
    Made(Vec<u8>),
    File(PathBuf),
}

/// One file of the bundle.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    /// Its path inside the bundle's folder (`doctor.txt`, `recorder/ring/...`).
    pub name: String,
    pub content: Content,
    pub size: u64,
    /// What it is, for README.txt.
    pub about: String,
}

impl Member {
    pub fn made(name: impl Into<String>, bytes: Vec<u8>, about: impl Into<String>) -> Self {
        let size = bytes.len() as u64;
        Self { name: name.into(), content: Content::Made(bytes), size, about: about.into() }
    }

    pub fn file(name: impl Into<String>, path: &Path, size: u64, about: impl Into<String>) -> Self {
        Self { name: name.into(), content: Content::File(path.to_path_buf()), size, about: about.into() }
    }
}

/// A member left out, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Omitted {
    pub name: String,
    pub size: u64,
    pub why: String,
}

/// The bytes a member of `size` takes in the tar stream: its header and its data padded to 512.
pub fn tar_bytes(size: u64) -> u64 {
    BLOCK + size.div_ceil(BLOCK) * BLOCK
}

/// The tar bytes allowed for a cap on the compressed file: the closing blocks and a long name's extra
/// header or two aside, and gzip's worst case on data that does not compress (compressed segments): a few
/// bytes per 16 KiB block, kept as 1/256 of the cap plus its own header and trailer.
pub fn tar_budget(cap: u64) -> u64 {
    cap.saturating_sub(cap / 256).saturating_sub(20 * BLOCK + 64)
}

/// Which of the candidates (in order of preference, by size) are taken: each when it still fits after
/// `used` and those taken before it; one that does not is passed over and the next tried.
pub fn fit(used: u64, sizes: &[u64], budget: u64) -> Vec<bool> {
    let mut total = used;
    sizes
        .iter()
        .map(|&size| {
            // A long name may take an extra header block.
            let need = tar_bytes(size) + BLOCK;
            let fits = total.saturating_add(need) <= budget;
            if fits {
                total += need;
            }
            fits
        })
        .collect()
}

/// The tar.gz being written.
pub struct Writer {
    builder: tar::Builder<GzEncoder<BufWriter<File>>>,
    path: PathBuf,
    folder: String,
    mtime: u64,
}

impl Writer {
    /// Creates `path`, refusing an existing file unless `replace`; members go into `folder`.
    pub fn create(path: &Path, replace: bool, folder: &str, mtime: u64) -> Result<Self> {
        let mut options = OpenOptions::new();
        options.write(true);
        if replace {
            options.create(true).truncate(true);
        } else {
            options.create_new(true);
        }
        let file = options.open(path).with_context(|| format!("cannot create {}", path.display()))?;
        let gzip = GzEncoder::new(BufWriter::new(file), flate2::Compression::default());
        let mut builder = tar::Builder::new(gzip);
        builder.mode(tar::HeaderMode::Deterministic);
        Ok(Self { builder, path: path.to_path_buf(), folder: folder.to_string(), mtime })
    }

    /// Adds a member; a file of the recorder's directory that can no longer be read is left out (said in
    /// the returned `Omitted`). The bytes written (what `fit` counted).
    pub fn add(&mut self, member: &Member) -> Result<std::result::Result<u64, Omitted>> {
        let bytes = match &member.content {
            Content::Made(bytes) => bytes.clone(),
            Content::File(path) => match read_up_to(path, member.size) {
                Ok(bytes) => bytes,
                Err(error) => {
                    return Ok(Err(Omitted {
                        name: member.name.clone(),
                        size: member.size,
                        why: format!("could not be read when the bundle was written ({error}): removed by the recorder's rotation?"),
                    }))
                }
            },
        };
        let mut header = tar::Header::new_gnu();
        header.set_size(bytes.len() as u64);
        header.set_mode(0o644);
        header.set_mtime(self.mtime);
        header.set_uid(0);
        header.set_gid(0);
        header.set_entry_type(tar::EntryType::Regular);
        let name = format!("{}/{}", self.folder, member.name);
        self.builder
            .append_data(&mut header, &name, bytes.as_slice())
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        Ok(Ok(tar_bytes(bytes.len() as u64)))
    }

    /// Ends the tar and the gzip stream, writes everything out; the file's size.
    pub fn finish(self) -> Result<u64> {
        let context = || format!("cannot write {}", self.path.display());
        let gzip = self.builder.into_inner().with_context(context)?;
        let mut out = gzip.finish().with_context(context)?;
        out.flush().with_context(context)?;
        let file = out.into_inner().map_err(|error| error.into_error()).with_context(context)?;
        file.sync_all().with_context(context)?;
        Ok(file.metadata().with_context(context)?.len())
    }
}

/// The first `limit` bytes of the file (all of it when shorter).
fn read_up_to(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    File::open(path)?.take(limit).read_to_end(&mut bytes)?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tar_sizes_count_the_header_and_the_padding() {
        assert_eq!(tar_bytes(0), 512);
        assert_eq!(tar_bytes(1), 1024);
        assert_eq!(tar_bytes(512), 1024);
        assert_eq!(tar_bytes(513), 1536);
    }

    #[test]
    fn fit_passes_over_what_does_not_fit_and_takes_smaller_ones_after() {
        let budget = 10 * 1024;
        // Each small one takes 512 + 512 + 512 (long-name allowance) = 1536.
        assert_eq!(fit(0, &[100, 9000, 100, 100], budget), [true, false, true, true]);
        assert_eq!(fit(9 * 1024, &[100], budget), [false]);
        assert_eq!(fit(0, &[], budget), Vec::<bool>::new());
        assert!(tar_budget(50_000_000) < 50_000_000 - 50_000_000 / 256);
        assert_eq!(tar_budget(100), 0);
    }

    #[test]
    fn members_are_written_and_read_back_by_the_tar_crate() {
        let dir = tempfile::tempdir().unwrap();
        let source = dir.path().join("segment");
        std::fs::write(&source, b"0123456789").unwrap();
        let out = dir.path().join("b.tar.gz");
        let mut writer = Writer::create(&out, false, "top", 1_700_000_000).unwrap();
        writer.add(&Member::made("a.txt", b"hello".to_vec(), "a")).unwrap().unwrap();
        // Chosen at 4 bytes; the file grew since: only the 4 are taken.
        writer.add(&Member::file("ring/s", &source, 4, "s")).unwrap().unwrap();
        let gone = writer.add(&Member::file("ring/gone", &dir.path().join("gone"), 4, "g")).unwrap();
        assert!(gone.unwrap_err().why.contains("could not be read"));
        writer.finish().unwrap();
        let mut archive = tar::Archive::new(flate2::read::GzDecoder::new(File::open(&out).unwrap()));
        let mut seen = Vec::new();
        for entry in archive.entries().unwrap() {
            let mut entry = entry.unwrap();
            let mut text = String::new();
            entry.read_to_string(&mut text).unwrap();
            assert_eq!(entry.header().mode().unwrap(), 0o644);
            seen.push((entry.path().unwrap().display().to_string(), text));
        }
        assert_eq!(
            seen,
            [("top/a.txt".to_string(), "hello".to_string()), ("top/ring/s".to_string(), "0123".to_string())]
        );
        let again = Writer::create(&out, false, "top", 0);
        assert!(again.is_err(), "an existing file is not replaced");
        assert!(Writer::create(&out, true, "top", 0).is_ok(), "unless asked");
    }
}
