//! The four compressions, recognised by their magic bytes, and their decompressors, each reading the
//! compressed input through a [`Counted`] buffer, so that when one fails it is known where in the
//! compressed bytes it stopped and whether the input had ended: a stream cut short (a recording stopped by
//! a crash, a copy not finished) or a corrupt one ([`Damaged`]).
//!
//! Every decompressor reads concatenated streams to their end (zstd frames, gzip members, xz streams,
//! bzip2 streams), so a log written as many independent frames reads as one.

use std::fmt;
use std::io::{self, BufRead, BufReader, Read};

/// Compressed bytes read from the input at once: zstd's preferred input size, about one of its blocks.
const INPUT_BUFFER: usize = 128 * 1024 + 512;
/// What follows bzip2's `BZh` and block size: a block's magic, or the end of the stream's.
const BZ_BLOCK: &[u8] = &[0x31, 0x41, 0x59, 0x26, 0x53, 0x59];
const BZ_END: &[u8] = &[0x17, 0x72, 0x45, 0x38, 0x50, 0x90];

/// How a log was compressed (recognised by its magic bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    Gzip,
    Zstd,
    Xz,
    Bzip2,
}

impl Compression {
    pub fn name(&self) -> &'static str {
        match self {
            Compression::Gzip => "gzip",
            Compression::Zstd => "zstd",
            Compression::Xz => "xz",
            Compression::Bzip2 => "bzip2",
        }
    }

    pub(super) fn detect(head: &[u8]) -> Option<Self> {
        match head {
            [0x1F, 0x8B, 0x08, ..] => Some(Compression::Gzip),
            [0x28, 0xB5, 0x2F, 0xFD, ..] => Some(Compression::Zstd),
            [0xFD, b'7', b'z', b'X', b'Z', 0x00, ..] => Some(Compression::Xz),
            // "BZh" is also text: require the block size and a block or end-of-stream magic.
            [b'B', b'Z', b'h', b'1'..=b'9', rest @ ..]
                if rest.starts_with(BZ_BLOCK) || rest.starts_with(BZ_END) =>
            {
                Some(Compression::Bzip2)
            }
            _ => None,
        }
    }

    /// What one of its independent parts is called, for "the input ends inside a frame".
    pub fn unit(&self) -> &'static str {
        match self {
            Compression::Zstd => "frame",
            Compression::Gzip => "member",
            Compression::Xz | Compression::Bzip2 => "stream",
        }
    }

    /// The compression whose magic bytes a whole input shorter than them starts: a compressed log cut
    /// short inside its first header. Two bytes at least (a lone `(` is text), and for bzip2 its four
    /// printable ones (`BZh9`) and more.
    pub(super) fn cut_in_magic(input: &[u8]) -> Option<Self> {
        let starts = |magic: &[u8]| input.len() >= 2 && input.len() < magic.len() && magic.starts_with(input);
        match input {
            _ if starts(&[0x1F, 0x8B, 0x08]) => Some(Compression::Gzip),
            _ if starts(&[0x28, 0xB5, 0x2F, 0xFD]) => Some(Compression::Zstd),
            _ if starts(&[0xFD, b'7', b'z', b'X', b'Z', 0x00]) => Some(Compression::Xz),
            [b'B', b'Z', b'h', b'1'..=b'9', rest @ ..]
                if rest.len() < BZ_BLOCK.len()
                    && (BZ_BLOCK.starts_with(rest) || BZ_END.starts_with(rest)) =>
            {
                Some(Compression::Bzip2)
            }
            _ => None,
        }
    }
}

/// What was wrong with a compressed stream that could not be read to its end.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Damage {
    /// The input ended before the stream did.
    CutShort,
    /// The decompressor refused the bytes (a checksum that does not match, a header that makes no sense).
    Corrupt,
}

/// A compressed stream that could not be read to its end. Travels inside an `io::Error` (of the
/// decompressor's kind) after every byte decompressed before it.
#[derive(Debug, thiserror::Error)]
pub struct Damaged {
    pub compression: Compression,
    pub damage: Damage,
    /// Where in the compressed bytes the decompressor stopped: the length of the input when cut short;
    /// where the damage was found when corrupt (a checksum is found wrong at the end of its frame; zstd
    /// gives up on the input it was handed without taking any, so its place is the end of that read, at
    /// most [`INPUT_BUFFER`] bytes further).
    pub at: u64,
    /// The decompressor's own words (`incomplete frame`, `invalid gzip header`).
    pub detail: String,
}

impl fmt::Display for Damaged {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (name, at, detail) = (self.compression.name(), self.at, &self.detail);
        match self.damage {
            Damage::CutShort => {
                let unit = self.compression.unit();
                write!(f, "truncated {name} data: the input ends at byte {at}, inside a {unit} ({detail})")
            }
            Damage::Corrupt => write!(f, "corrupt {name} data, found at byte {at} ({detail})"),
        }
    }
}

impl Damaged {
    /// The damage a read error reports, if it is one.
    pub fn of(error: &io::Error) -> Option<&Damaged> {
        error.get_ref()?.downcast_ref::<Damaged>()
    }

    /// The read error that carries it.
    pub fn into_error(self) -> io::Error {
        let kind = match self.damage {
            Damage::CutShort => io::ErrorKind::UnexpectedEof,
            Damage::Corrupt => io::ErrorKind::InvalidData,
        };
        io::Error::new(kind, self)
    }
}

/// The compressed input as a decompressor reads it: buffered, with the bytes read counted, and whether it
/// reached the end or failed itself.
pub(super) struct Counted<R> {
    inner: BufReader<R>,
    /// Bytes the decompressor consumed.
    taken: u64,
    /// Bytes read from the input (consumed or buffered).
    read_to: u64,
    ended: bool,
    failed: bool,
}

impl<R: Read> Counted<R> {
    fn new(inner: R) -> Self {
        Self {
            inner: BufReader::with_capacity(INPUT_BUFFER, inner),
            taken: 0,
            read_to: 0,
            ended: false,
            failed: false,
        }
    }
}

impl<R: Read> BufRead for Counted<R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        match self.inner.fill_buf() {
            Ok(bytes) => {
                self.ended = bytes.is_empty();
                if self.read_to < self.taken + bytes.len() as u64 {
                    self.read_to = self.taken + bytes.len() as u64;
                }
                Ok(bytes)
            }
            Err(error) => {
                self.failed = error.kind() != io::ErrorKind::Interrupted;
                Err(error)
            }
        }
    }

    fn consume(&mut self, amount: usize) {
        self.taken += amount as u64;
        self.inner.consume(amount);
    }
}

impl<R: Read> Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(buf.len());
        buf[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

enum Decoder<R: Read> {
    Gzip(flate2::bufread::MultiGzDecoder<Counted<R>>),
    Zstd(zstd::stream::read::Decoder<'static, Counted<R>>),
    Xz(liblzma::bufread::XzDecoder<Counted<R>>),
    Bzip2(bzip2::bufread::MultiBzDecoder<Counted<R>>),
}

/// The text of a compressed input; a failure of the decompressor comes out as [`Damaged`], a failure to
/// read the input (a disk error, a file that shrank) unchanged.
pub(super) struct Inflate<R: Read> {
    decoder: Decoder<R>,
    compression: Compression,
}

impl<R: Read> Inflate<R> {
    pub fn new(compression: Compression, raw: R) -> io::Result<Self> {
        let counted = Counted::new(raw);
        let decoder = match compression {
            Compression::Gzip => Decoder::Gzip(flate2::bufread::MultiGzDecoder::new(counted)),
            Compression::Zstd => Decoder::Zstd(zstd::stream::read::Decoder::with_buffer(counted)?),
            Compression::Xz => Decoder::Xz(liblzma::bufread::XzDecoder::new_multi_decoder(counted)),
            Compression::Bzip2 => Decoder::Bzip2(bzip2::bufread::MultiBzDecoder::new(counted)),
        };
        Ok(Self { decoder, compression })
    }

    fn input(&self) -> &Counted<R> {
        match &self.decoder {
            Decoder::Gzip(decoder) => decoder.get_ref(),
            Decoder::Zstd(decoder) => decoder.get_ref(),
            Decoder::Xz(decoder) => decoder.get_ref(),
            Decoder::Bzip2(decoder) => decoder.get_ref(),
        }
    }

    #[cold]
    fn damaged(&self, error: io::Error) -> io::Error {
        let input = self.input();
        if error.kind() == io::ErrorKind::Interrupted || input.failed {
            return error;
        }
        // A decompressor that asked for more than there was found the stream cut short, whatever it calls it.
        let damage = if input.ended { Damage::CutShort } else { Damage::Corrupt };
        let at = if self.compression == Compression::Zstd { input.read_to } else { input.taken };
        let (compression, detail) = (self.compression, error.to_string());
        Damaged { compression, damage, at, detail }.into_error()
    }
}

impl<R: Read> Read for Inflate<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let read = match &mut self.decoder {
            Decoder::Gzip(decoder) => decoder.read(buf),
            Decoder::Zstd(decoder) => decoder.read(buf),
            Decoder::Xz(decoder) => decoder.read(buf),
            Decoder::Bzip2(decoder) => decoder.read(buf),
        };
        read.map_err(|error| self.damaged(error))
    }
}

#[cfg(test)]
mod tests {
    use super::super::open::tests::{compress, ALL};
    use super::super::open_log;
    use super::*;

    fn log(lines: std::ops::Range<usize>) -> Vec<u8> {
        lines
            .flat_map(|i| {
                format!("(1700000000.{i:06}) can0 211#00000103000000{:02X}\n", i % 256).into_bytes()
            })
            .collect()
    }

    /// Everything `open_log` gives for `bytes`: the text, then the error if any (`None` if refused).
    fn read(bytes: &[u8]) -> Option<(Vec<u8>, Option<io::Error>)> {
        let (mut reader, _) = open_log(io::Cursor::new(bytes.to_vec()), "x").ok()?;
        let mut text = Vec::new();
        let error = reader.read_to_end(&mut text).err();
        Some((text, error))
    }

    /// Two parts (frames, members, streams) one after the other, as the recorder writes them: each cut
    /// inside a part is that compression's cut at that byte, after text the log starts with; a cut between
    /// parts is no damage at all.
    #[test]
    fn every_cut_gives_text_the_log_starts_with_then_the_cut_at_its_byte() {
        let (first, second) = (log(0..40), log(40..70));
        let whole_text = [first.clone(), second.clone()].concat();
        for compression in ALL {
            let one = compress(compression, &first);
            let both = [one.clone(), compress(compression, &second)].concat();
            // Below this, too little is there to tell a compressed file (a lone `(` is text).
            let least = if compression == Compression::Bzip2 { 4 } else { 2 };
            for cut in 0..=both.len() {
                let Some((text, error)) = read(&both[..cut]) else { continue };
                if cut > 0 && cut < least {
                    continue;
                }
                assert!(whole_text.starts_with(&text), "{compression:?} cut at {cut}");
                if cut == 0 || cut == one.len() || cut == both.len() {
                    assert!(error.is_none(), "{compression:?} cut at {cut}: {error:?}");
                    let expected = if cut == 0 {
                        &[][..]
                    } else if cut == one.len() {
                        &first
                    } else {
                        &whole_text
                    };
                    assert_eq!(text, expected, "{compression:?} cut at {cut}");
                } else if cut >= least {
                    let error = error.unwrap_or_else(|| panic!("{compression:?} cut at {cut}: no error"));
                    let damaged =
                        Damaged::of(&error).unwrap_or_else(|| panic!("{compression:?} {cut}: {error}"));
                    assert_eq!(
                        (damaged.damage, damaged.at),
                        (Damage::CutShort, cut as u64),
                        "{compression:?}"
                    );
                    assert_eq!(damaged.compression, compression);
                    assert_eq!(error.kind(), io::ErrorKind::UnexpectedEof);
                    let said = format!(
                        "truncated {} data: the input ends at byte {cut}, inside a ",
                        compression.name()
                    );
                    assert!(error.to_string().starts_with(&said), "{error}");
                }
            }
        }
    }

    #[test]
    fn a_wrong_checksum_is_corruption_found_at_the_end_of_its_part() {
        let (first, second) = (log(0..40), log(40..70));
        for compression in ALL {
            let one = compress(compression, &first);
            let mut both = [one.clone(), compress(compression, &second)].concat();
            // The last byte of the first part: its checksum (bzip2's stream CRC ends a few bits before).
            let at = if compression == Compression::Bzip2 { one.len() - 2 } else { one.len() - 1 };
            both[at] ^= 0x55;
            let (text, error) = read(&both).unwrap();
            let error = error.unwrap_or_else(|| panic!("{compression:?}: no error"));
            let damaged = Damaged::of(&error).unwrap_or_else(|| panic!("{compression:?}: {error}"));
            assert_eq!(damaged.damage, Damage::Corrupt, "{compression:?}: {error}");
            assert!(damaged.at > at as u64 && damaged.at <= both.len() as u64, "{compression:?}: {error}");
            assert_eq!(error.kind(), io::ErrorKind::InvalidData);
            assert!(first.starts_with(&text), "{compression:?}: nothing of the second part");
            let said = format!("corrupt {} data, found at byte {}", compression.name(), damaged.at);
            assert!(error.to_string().starts_with(&said), "{error}");
        }
    }

    #[test]
    fn a_failing_input_is_its_own_error_not_damage() {
        struct Failing(io::Cursor<Vec<u8>>);
        impl Read for Failing {
            fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
                match self.0.read(buf)? {
                    0 => Err(io::Error::other("the disk went away")),
                    n => Ok(n),
                }
            }
        }
        let text = log(0..4000);
        for compression in ALL {
            let whole = compress(compression, &text);
            let raw = Failing(io::Cursor::new(whole[..whole.len() / 2].to_vec()));
            let mut inflate = Inflate::new(compression, raw).unwrap();
            let error = io::copy(&mut inflate, &mut io::sink()).unwrap_err();
            assert!(Damaged::of(&error).is_none(), "{compression:?}: {error}");
            assert_eq!(error.to_string(), "the disk went away", "{compression:?}");
        }
    }
}
