//! Opening a log someone handed us: transparent decompression, a UTF-8 BOM skipped, and the text format
//! recognised from the first bytes and lines, not from the file name.
//!
//! [`open_log`] is the one call every reader of logs uses (`decode`, `--replay`): it returns a reader of
//! the plain text and the [`LogFormat`] to build a [`LineParser`](super::LineParser) with
//! ([`LineParser::for_format`](super::LineParser::for_format)). Formats that tracerctl does not read are
//! refused with one line naming the format and a converter, instead of one rejected line per line.
//!
//! Detection is conservative: anything that is not clearly another format is read as candump text, so a
//! real candump log is never refused. Only the first line or the first few header lines are looked at,
//! and no more is read than needed to decide, so a live `candump -L can0 | tracerctl decode -` is decided
//! by its first line.

use std::fmt;
use std::io::{self, Cursor, Read};

use memchr::memchr;

use super::decompress;
use super::inflate::{Compression, Damage, Damaged, Inflate};

/// Bytes looked at to recognise a compressed stream.
const MAGIC_LEN: usize = 10;
/// At most this much text is read to recognise the format (header lines of ASC/TRC/Microchip files).
const SNIFF_MAX_BYTES: usize = 16 * 1024;
/// At most this many lines are looked at.
const SNIFF_MAX_LINES: usize = 24;
pub(crate) const UTF8_BOM: &[u8; 3] = b"\xEF\xBB\xBF";

/// The text format a log holds, with the compression it came in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LogFormat {
    pub text: TextFormat,
    pub compression: Option<Compression>,
}

/// The text formats tracerctl reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextFormat {
    /// candump's log and console outputs (every option set), cansend lines, Pengutronix canutils.
    #[default]
    Candump,
    /// Vector ASC (CANalyzer/CANoe, python-can, `log2asc`).
    VectorAsc,
    /// PEAK PCAN-View / PEAK-Converter trace; the version from `;$FILEVERSION=` (10 for 1.0, 21 for 2.1),
    /// 10 when the header has none.
    PeakTrc { version: u8 },
}

impl TextFormat {
    pub fn name(&self) -> &'static str {
        match self {
            TextFormat::Candump => "candump",
            TextFormat::VectorAsc => "Vector ASC",
            TextFormat::PeakTrc { .. } => "PEAK trc",
        }
    }
}

/// Why a log cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    /// A format tracerctl recognises but does not read.
    #[error("{name} is {format}, which tracerctl does not read: {advice}")]
    Unsupported { name: String, format: &'static str, advice: String },
    /// Reading the first bytes failed (a missing file, a corrupt compressed header).
    #[error("cannot read {name}: {source}")]
    Io { name: String, source: io::Error },
}

impl FormatError {
    /// The name of the refused format, if the log was refused for its format.
    pub fn unsupported_format(&self) -> Option<&'static str> {
        match self {
            FormatError::Unsupported { format, .. } => Some(format),
            FormatError::Io { .. } => None,
        }
    }
}

impl From<FormatError> for crate::exit::Failure {
    /// A refused format is a data error (exit 3); failing to read is an ordinary failure (exit 1).
    fn from(error: FormatError) -> Self {
        let code = match error {
            FormatError::Unsupported { .. } => crate::exit::DATA_ERROR,
            FormatError::Io { .. } => crate::exit::FAILURE,
        };
        Self { code, message: error.to_string() }
    }
}

/// Opens a log for reading: decompresses gzip, zstd, xz and bzip2 streams (recognised by their magic
/// bytes, whatever the name), skips a UTF-8 BOM, and recognises the text format. `name` is used in
/// messages only.
///
/// Decompression streams (memory stays flat) on its own thread ([`super::decompress`]), so the caller
/// decodes while the next blocks are inflated; a truncated or corrupt compressed stream makes a later
/// read fail with a [`Damaged`] error (the compression, cut short or corrupt, the compressed byte), after
/// everything before the damage was returned; even one cut inside its first header opens, and fails so.
/// The reader is `'static` for that thread. While a compressed stream is quiet (a live pipe), a read
/// returns `Interrupted` every 50 ms so a caller can look at its signal flag; retry it, as
/// [`LineReader`](super::LineReader) and `read_to_end` do.
///
/// ```
/// use tracerctl::candump::{open_log, TextFormat};
/// use std::io::Read;
///
/// let (mut reader, format) = open_log(&b"\xEF\xBB\xBF(1.000000) can0 211#00\n"[..], "x.log")?;
/// assert_eq!(format.text, TextFormat::Candump);
/// let mut text = String::new();
/// reader.read_to_string(&mut text)?;
/// assert_eq!(text, "(1.000000) can0 211#00\n");
///
/// let Err(refused) = open_log(&b"LOGG\x90\x00\x00\x00"[..], "f.blf") else { panic!("BLF is refused") };
/// assert!(refused.to_string().starts_with("f.blf is a Vector BLF log, which tracerctl does not read"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn open_log(
    reader: impl Read + Send + 'static,
    name: &str,
) -> Result<(Box<dyn Read + Send>, LogFormat), FormatError> {
    let io_error = |source| FormatError::Io { name: name.to_string(), source };
    let mut reader = reader;
    let mut magic = Vec::with_capacity(MAGIC_LEN);
    fill_to(&mut reader, &mut magic, MAGIC_LEN).map_err(io_error)?;
    if magic.len() < MAGIC_LEN {
        if let Some(compression) = Compression::cut_in_magic(&magic) {
            let detail = "the file ends inside its first header".to_string();
            let damaged = Damaged { compression, damage: Damage::CutShort, at: magic.len() as u64, detail };
            let format = LogFormat { text: TextFormat::Candump, compression: Some(compression) };
            return Ok((Box::new(FailOnce(Some(damaged.into_error()))), format));
        }
    }
    let compression = Compression::detect(&magic);
    let raw = Cursor::new(magic).chain(reader);
    let mut text: Box<dyn Read + Send> = match compression {
        None => Box::new(raw),
        Some(compression) => {
            let inner = Inflate::new(compression, raw).map_err(io_error)?;
            Box::new(decompress::spawn(inner).map_err(io_error)?)
        }
    };

    let mut head = Vec::with_capacity(4096);
    let mut decision = None;
    // A compressed stream damaged this early: decided on what came before it, the damage read after it.
    let mut damaged = None;
    while decision.is_none() {
        let before = head.len();
        match fill_to(&mut text, &mut head, before + 1) {
            Ok(()) => {}
            Err(error) if Damaged::of(&error).is_some() => damaged = Some(error),
            Err(error) => return Err(io_error(error)),
        }
        let at_end = head.len() == before || head.len() >= SNIFF_MAX_BYTES || damaged.is_some();
        decision = sniff(&head, at_end);
    }
    let bom = if head.starts_with(UTF8_BOM) { UTF8_BOM.len() } else { 0 };
    let text_format = match decision {
        Some(Sniffed::Reads(format)) => format,
        Some(Sniffed::Refused(refusal)) => {
            let advice = refusal.advice(name);
            return Err(FormatError::Unsupported { name: name.to_string(), format: refusal.format, advice });
        }
        None => TextFormat::Candump,
    };
    let mut head = Cursor::new(head);
    head.set_position(bom as u64);
    let format = LogFormat { text: text_format, compression };
    match damaged {
        Some(error) => Ok((Box::new(head.chain(FailOnce(Some(error)))), format)),
        None => Ok((Box::new(head.chain(text)), format)),
    }
}

/// A reader that fails with its error once, then is at its end.
struct FailOnce(Option<io::Error>);

impl Read for FailOnce {
    fn read(&mut self, _: &mut [u8]) -> io::Result<usize> {
        self.0.take().map_or(Ok(0), Err)
    }
}

/// Reads until `buf` holds at least `want` bytes or the input ends. A read returns what is there, so a
/// live pipe is not waited on for more than it has.
fn fill_to(reader: &mut impl Read, buf: &mut Vec<u8>, want: usize) -> io::Result<()> {
    let mut chunk = [0u8; 4096];
    while buf.len() < want {
        match reader.read(&mut chunk) {
            Ok(0) => return Ok(()),
            Ok(n) => buf.extend_from_slice(&chunk[..n]),
            Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
    Ok(())
}

/// A format recognised but not read, with what to do about it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Refusal {
    format: &'static str,
    advice: Advice,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Advice {
    /// python-can converts it: `python -m can.logconvert NAME NAME.log`.
    LogConvert,
    /// SavvyCAN loads it and saves candump or Vector ASC logs.
    SavvyCan,
    /// A packet capture: Wireshark reads it.
    Wireshark,
    /// A text encoding problem: iconv fixes it.
    Utf16,
    /// No converter we know of: record with candump instead.
    RecordAgain,
    /// Raw bytes, perhaps an RS232 capture: `decode --serial` reads those.
    Serial,
}

impl Refusal {
    fn advice(&self, name: &str) -> String {
        let file = if name.starts_with('<') { "FILE" } else { name };
        match self.advice {
            Advice::LogConvert => {
                let stem = file.rsplit_once('.').map_or(file, |(stem, _)| stem);
                format!("convert it with `python -m can.logconvert {file} {stem}.log` (python-can), then decode the .log")
            }
            Advice::SavvyCan => {
                "load it in SavvyCAN and save it as a candump or Vector ASC log, then decode that".to_string()
            }
            Advice::Wireshark => "open it in Wireshark, or record the bus with `candump -L can0 > FILE.log`".to_string(),
            Advice::Utf16 => format!("convert it with `iconv -f UTF-16 -t UTF-8 {file} > {file}.utf8` (a PowerShell `>` writes UTF-16)"),
            Advice::Serial => format!("an RS232 capture? use `tracerctl decode --serial {file}`"),
            Advice::RecordAgain => {
                "no converter is known; record the bus with `candump -L can0 > FILE.log` instead".to_string()
            }
        }
    }
}

#[derive(Debug, PartialEq, Eq)]
enum Sniffed {
    Reads(TextFormat),
    Refused(Refusal),
}

const fn refuse(format: &'static str, advice: Advice) -> Option<Sniffed> {
    Some(Sniffed::Refused(Refusal { format, advice }))
}

/// Decides the format from the start of the text, or `None` when more lines are needed (never at the end).
fn sniff(head: &[u8], at_end: bool) -> Option<Sniffed> {
    let undecided = if at_end { Some(Sniffed::Reads(TextFormat::Candump)) } else { None };
    let binary = match head {
        [b'L', b'O', b'G', b'G', ..] => refuse("a Vector BLF log", Advice::LogConvert),
        [0xD4, 0xC3, 0xB2, 0xA1, ..] | [0xA1, 0xB2, 0xC3, 0xD4, ..] | [0x4D, 0x3C, 0xB2, 0xA1, ..] => {
            refuse("a pcap capture", Advice::Wireshark)
        }
        [0x0A, 0x0D, 0x0D, 0x0A, ..] => refuse("a pcapng capture", Advice::Wireshark),
        [b'M', b'D', b'F', b' ', b' ', b' ', b' ', b' ', ..] => {
            refuse("an ASAM MDF (MF4) log", Advice::LogConvert)
        }
        [0xFF, 0xFE, ..] | [0xFE, 0xFF, ..] => refuse("UTF-16 text", Advice::Utf16),
        _ => None,
    };
    if binary.is_some() {
        return binary;
    }
    if looks_binary(head) {
        return refuse("binary data, not a text log", Advice::Serial);
    }
    let text = head.strip_prefix(UTF8_BOM).unwrap_or(head);
    // Complete lines only (the last one is complete at the end of input), without blank ones.
    let complete = if at_end { text } else { &text[..memchr::memrchr(b'\n', text).map_or(0, |i| i + 1)] };
    let mut lines = complete
        .split(|&b| b == b'\n')
        .map(|line| line.strip_suffix(b"\r").unwrap_or(line))
        .filter(|line| !line.trim_ascii().is_empty())
        .take(SNIFF_MAX_LINES);
    let Some(first) = lines.next() else {
        return undecided;
    };
    let first_trimmed = first.trim_ascii_start();

    // Formats that need a second look at the following header lines.
    if first.starts_with(b"date ") {
        return match lines.next() {
            Some(second) if second.starts_with(b"base ") => Some(Sniffed::Reads(TextFormat::VectorAsc)),
            Some(_) => Some(Sniffed::Reads(TextFormat::Candump)),
            None => undecided,
        };
    }
    if let Some(version) = first.strip_prefix(b";$FILEVERSION=") {
        return Some(trc_version(version.trim_ascii()));
    }
    if first.starts_with(b";") {
        // PCAN-View 1.0 traces have no version line, only a commented header with the start time.
        let mut closed = false;
        for line in std::iter::once(first).chain(lines.by_ref()) {
            if !line.starts_with(b";") {
                closed = true;
                break;
            }
            if contains(line, b"Start time:") {
                return Some(Sniffed::Reads(TextFormat::PeakTrc { version: 10 }));
            }
        }
        return if closed || line_count(complete) >= SNIFF_MAX_LINES {
            Some(Sniffed::Reads(TextFormat::Candump))
        } else {
            undecided
        };
    }
    if first.starts_with(b"//") || first.starts_with(b"Microchip") {
        const MICROCHIP_HEADER_LINES: usize = 6;
        let mut header = std::iter::once(first).chain(lines.by_ref()).take(MICROCHIP_HEADER_LINES);
        if header.any(|line| contains(line, b"Microchip Technology") || contains(line, b"CAN BUS Analyzer")) {
            return refuse("a Microchip CAN BUS Analyzer log", Advice::SavvyCan);
        }
        return if line_count(complete) >= MICROCHIP_HEADER_LINES {
            Some(Sniffed::Reads(TextFormat::Candump))
        } else {
            undecided
        };
    }
    Some(one_line_format(first, first_trimmed))
}

/// Whether the start of the input is raw bytes rather than text: more than one byte in 16 is a control
/// character no log holds (tabs, line ends, form feeds and the escapes of coloured console output aside).
/// Random data has about one in ten; a log with a stray corrupted byte stays text, and is read line by line.
fn looks_binary(head: &[u8]) -> bool {
    let control =
        head.iter().filter(|&&byte| matches!(byte, 0x00..=0x08 | 0x0E..=0x1A | 0x1C..=0x1F | 0x7F)).count();
    control * 16 > head.len()
}

/// Formats recognisable from their first line alone.
fn one_line_format(first: &[u8], trimmed: &[u8]) -> Sniffed {
    let candump = Sniffed::Reads(TextFormat::Candump);
    if first.starts_with(b"***BUSMASTER") {
        return Sniffed::Refused(Refusal { format: "a BUSMASTER log", advice: Advice::SavvyCan });
    }
    if first.starts_with(b"@ TEXT @") {
        return Sniffed::Refused(Refusal { format: "a CarBusAnalyzer trace", advice: Advice::SavvyCan });
    }
    if first.starts_with(b"Time Stamp,ID,Extended,") || first.starts_with(b"ID,Data Bytes") {
        return Sniffed::Refused(Refusal { format: "a SavvyCAN/GVRET CSV log", advice: Advice::SavvyCan });
    }
    if first.starts_with(b"timestamp,arbitration_id,extended,remote,error,dlc,data") {
        return Sniffed::Refused(Refusal { format: "a python-can CSV log", advice: Advice::LogConvert });
    }
    let mut fields = trimmed.split(|b| b.is_ascii_whitespace()).filter(|f| !f.is_empty());
    let (Some(one), two, three) = (fields.next(), fields.next(), fields.next()) else {
        return candump;
    };
    // TruckDevil: "(0.001232) 18F0090B    06 F009 0B --> FF [0008] FFFF..."
    if one.starts_with(b"(") && contains(trimmed, b" --> ") && contains(trimmed, b" [") {
        return Sniffed::Refused(Refusal { format: "a TruckDevil dump", advice: Advice::RecordAgain });
    }
    // CRTD: "166.064000 R11 0000021A FE 36 ..." or the "CXX" header.
    if is_decimal(one) && matches!(two, Some(b"CXX" | b"CEV" | b"R11" | b"R29" | b"T11" | b"T29")) {
        return Sniffed::Refused(Refusal { format: "a CRTD log", advice: Advice::SavvyCan });
    }
    // Yacht Devices RAW: "21:55:35.425 R 15FD0723 FF C0 ..."
    if is_clock(one)
        && matches!(two, Some(b"R" | b"T"))
        && three.is_some_and(|id| id.len() == 8 && id.iter().all(u8::is_ascii_hexdigit))
    {
        return Sniffed::Refused(Refusal { format: "a Yacht Devices RAW log", advice: Advice::RecordAgain });
    }
    // Actisense / canboat CSV: "2024-11-17-17:41:46.906,3,130823,27,255,8,00,df,..."
    if two.is_none() && is_canboat_csv(one) {
        return Sniffed::Refused(Refusal {
            format: "an Actisense/canboat CSV log",
            advice: Advice::RecordAgain,
        });
    }
    candump
}

fn trc_version(text: &[u8]) -> Sniffed {
    let version = match text {
        b"1.1" => 11,
        b"1.2" => 12,
        b"1.3" => 13,
        b"2.0" => 20,
        b"2.1" => 21,
        _ => {
            return Sniffed::Refused(Refusal {
                format: "a PEAK trc log of a version not read",
                advice: Advice::LogConvert,
            })
        }
    };
    Sniffed::Reads(TextFormat::PeakTrc { version })
}

fn line_count(text: &[u8]) -> usize {
    text.split(|&b| b == b'\n').filter(|line| !line.trim_ascii().is_empty()).count()
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    memchr::memmem::find(haystack, needle).is_some()
}

/// `123.456`: digits, a dot, digits.
fn is_decimal(text: &[u8]) -> bool {
    match memchr(b'.', text) {
        Some(dot) => {
            let (int, frac) = (&text[..dot], &text[dot + 1..]);
            !int.is_empty() && !frac.is_empty() && int.iter().chain(frac).all(u8::is_ascii_digit)
        }
        None => false,
    }
}

/// `HH:MM:SS.mmm`.
fn is_clock(text: &[u8]) -> bool {
    matches!(text, [h1, h2, b':', m1, m2, b':', s1, s2, b'.', frac @ ..]
        if [h1, h2, m1, m2, s1, s2].iter().all(|d| d.is_ascii_digit()) && !frac.is_empty() && frac.iter().all(u8::is_ascii_digit))
}

/// `YYYY-MM-DD-HH:MM:SS.mmm,prio,pgn,src,dst,len,hex,...`: a date, then at least six comma-separated fields.
fn is_canboat_csv(text: &[u8]) -> bool {
    let mut fields = text.split(|&b| b == b',');
    let date_ok = fields.next().is_some_and(|date| {
        matches!(date, [y1, y2, y3, y4, b'-', m1, m2, b'-', d1, d2, b'-' | b'T' | b' ', ..]
            if [y1, y2, y3, y4, m1, m2, d1, d2].iter().all(|d| d.is_ascii_digit()))
    });
    date_ok && fields.filter(|f| !f.is_empty() && f.iter().all(u8::is_ascii_hexdigit)).count() >= 6
}

impl fmt::Display for LogFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.text.name())?;
        if let Some(compression) = self.compression {
            write!(f, " ({})", compression.name())?;
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "open_tests.rs"]
pub(super) mod tests;
