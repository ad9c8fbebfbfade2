//! Reading and writing candump / cansend text.
//!
//! * [`LineParser`] turns one line of a candump log (`candump -l`/`-L`) or of candump's console output
//!   (any mix of `-t a/A/d/z`, `-x`, `-c`, `-a`, `-8`, `-e`, `-d`) into a [`Line`], detecting the format of
//!   every line on its own so mixed files work. Common log lines take a dedicated fast path.
//! * [`parse_cansend`] is the strict `ID#DATA` parser for frames typed on the command line.
//! * [`LineReader`] streams lines out of any reader with one reusable buffer.
//! * [`write_log_line`] writes `candump -L` lines.
//!
//! The grammar and its edge cases are described in `candump-formats.md` (shared reference). Where the
//! tools disagree or the text is ambiguous, this module chooses:
//!
//! * seconds below [`RELATIVE_LIMIT_SECS`] (before 1973) are [`TimestampKind::Relative`] (`-t z`,
//!   python-can's `(0.000000)`); `-t A` wall-clock stamps are converted as if they were UTC;
//! * `-t d` looks exactly like `-t z`, so deltas are summed only when asked
//!   ([`LineParser::with_delta_timestamps`]);
//! * console CAN FD frames get the FDF flag (4) plus BRS/ESI from the `-x` columns, as `candump -L` >= 2025.01
//!   would write them;
//! * 3-digit identifiers above 0x7FF and 8-digit ones with bits 30/31 set are rejected, as is everything
//!   cansend silently drops or ignores (see [`parse_cansend`]);
//! * CAN XL frames are checked but not decoded ([`Line::CanXl`]).
//!
//! ```
//! use tracerctl::candump::{Line, LineParser, LineReader, RawLine};
//!
//! let input = b"(1700000000.002500) can0 211#00000103000000B1\n  can0  221   [8]  00 00 00 00 00 00 00 01\n";
//! let mut reader = LineReader::new(&input[..]);
//! let mut parser = LineParser::new();
//! let mut ids = Vec::new();
//! while let Some(raw) = reader.next_line()? {
//!     if let RawLine::Line { text, .. } = raw {
//!         if let Ok(Line::Frame(record)) = parser.parse(text) {
//!             ids.push(record.frame.id());
//!         }
//!     }
//! }
//! assert_eq!(ids, [0x211, 0x221]);
//! # Ok::<(), std::io::Error>(())
//! ```

mod asc;
mod cansend;
mod decompress;
mod fast_path;
mod general_path;
mod hex;
mod inflate;
mod line;
mod line_limit;
mod open;
mod reader;
mod reason;
mod record;
mod shrink;
mod tally;
mod timestamp;
mod trc;
mod writer;

#[cfg(test)]
mod cansend_tests;
#[cfg(test)]
mod fixture_tests;
#[cfg(test)]
mod formats_tests;
#[cfg(test)]
mod line_tests;

pub use cansend::parse_cansend;
pub use hex::same_bytes;
pub use inflate::{Compression, Damage, Damaged};
pub use line::{CarriedState, LineParser};
pub use line_limit::{LineLimit, LongLine, DEFAULT_MAX_LINE_LEN};
pub(crate) use open::UTF8_BOM;
pub use open::{open_log, FormatError, LogFormat, TextFormat};
pub use reader::{LineReader, RawLine, DEFAULT_BUFFER_CAPACITY};
pub use reason::{FrameSyntaxError, LineError, Reason};
pub use record::{Direction, Line, LogRecord, Record, Timestamp, TimestampKind, RELATIVE_LIMIT_SECS};
pub use shrink::{shrank, Shrank, WatchedFile};
pub use tally::{line_too_long, RejectTally, Rejected, Rejection, MAX_SHOWN_REJECTS};
pub(crate) use timestamp::days_from_civil;
pub use timestamp::DeltaSum;
pub use writer::{write_frame, write_log_line, write_log_record};
