//! A compressed input that ends early or is corrupt (a segment of the black box cut by a crash, a copy not
//! finished): every whole line before the damage is decoded, then the damage is said with the byte where
//! the compressed data stopped and the line reached. Without `--strict` the next inputs are decoded and the
//! damage is the last word (exit 3); with `--strict` it stops the run there.

use std::io;

use anyhow::Result;

use super::written::read_error;
use super::Decoder;
use crate::candump::{Damage, Damaged};
use crate::exit::Failure;

/// Where the damage left the text: the whole lines read before it and the unfinished one after them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Reached {
    /// Whole lines of this input read before the damage.
    pub lines: u64,
    /// Bytes of the unfinished line after them (not decoded).
    pub unfinished: u64,
}

impl Decoder {
    /// A read of input `name` failed after the lines `reached`: the damage of a compressed input is kept
    /// for the end (or fails at once with `--strict`); any other error ends the run as before. Out of
    /// line: inlined into the line loop's function, it cost `-j1` 1.5 % (callgrind).
    #[cold]
    #[inline(never)]
    pub(super) fn read_failed(&mut self, name: &str, error: io::Error, reached: Reached) -> Result<()> {
        let Some(damaged) = Damaged::of(&error) else {
            return Err(read_error(error, name));
        };
        let message = describe(name, damaged, self.input_bytes, reached);
        if self.strict {
            return Err(Failure::data(message).into());
        }
        self.damaged.push(message);
        Ok(())
    }

    /// The damaged inputs, said after the output: all but the last on stderr, the last as the error.
    pub(super) fn damage_error(&mut self) -> Option<anyhow::Error> {
        let last = self.damaged.pop()?;
        self.say_damage();
        Some(Failure::data(last).into())
    }

    /// The damaged inputs on stderr, when another error or a signal ends the run.
    pub(super) fn say_damage(&mut self) {
        for message in self.damaged.drain(..) {
            crate::say!("tracerctl: {message}");
        }
    }
}

/// One line: which input, what happened to its compressed data and where (`size`: the file's bytes, when
/// known), why that happens, and how far its text was decoded.
pub(super) fn describe(name: &str, damaged: &Damaged, size: Option<u64>, reached: Reached) -> String {
    let (compression, at) = (damaged.compression.name(), damaged.at);
    let what = match damaged.damage {
        Damage::CutShort => {
            let end = if size.is_some() { "the end of the file" } else { "the end of the input" };
            let unit = damaged.compression.unit();
            format!(
                "the {compression} data ends early, at byte {at} ({end}), inside a {unit}: a recording \
                 stopped by a crash or a power cut, or a copy not finished"
            )
        }
        Damage::Corrupt => {
            let of = size.map_or(String::new(), |size| format!(" of {size}"));
            let detail = &damaged.detail;
            format!("the {compression} data is corrupt, found at byte {at}{of} ({detail}): a damaged disk or a bad copy")
        }
    };
    let (lines, unfinished) = (reached.lines, reached.unfinished);
    let mut read = match lines {
        0 => "no whole line before it".to_string(),
        1 => "line 1 read".to_string(),
        _ => format!("lines 1-{lines} read"),
    };
    if damaged.damage == Damage::Corrupt && lines > 0 {
        read.push_str(" (the last ones may be damaged too)");
    }
    let rest = match (unfinished, damaged.damage) {
        (0, Damage::CutShort) => String::new(),
        (0, Damage::Corrupt) => ", the rest of the file not decoded".to_string(),
        (bytes, Damage::CutShort) => {
            format!(", the unfinished line {} ({bytes} bytes) not decoded", lines + 1)
        }
        (bytes, Damage::Corrupt) => {
            format!(
                ", the unfinished line {} ({bytes} bytes) and the rest of the file not decoded",
                lines + 1
            )
        }
    };
    format!("{name}: {what}; {read}{rest}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::Compression;

    fn damaged(damage: Damage, compression: Compression, at: u64) -> Damaged {
        Damaged { compression, damage, at, detail: "Data corruption detected".into() }
    }

    #[test]
    fn a_cut_names_the_byte_the_end_the_cause_and_the_lines_reached() {
        let cut = damaged(Damage::CutShort, Compression::Zstd, 48_213);
        let reached = Reached { lines: 5012, unfinished: 17 };
        assert_eq!(
            describe("ring/a.log.zst", &cut, Some(48_213), reached),
            "ring/a.log.zst: the zstd data ends early, at byte 48213 (the end of the file), inside a frame: \
             a recording stopped by a crash or a power cut, or a copy not finished; lines 1-5012 read, \
             the unfinished line 5013 (17 bytes) not decoded"
        );
        let at_line_end = describe("<stdin>", &cut, None, Reached { lines: 1, unfinished: 0 });
        assert!(
            at_line_end.ends_with(
                "at byte 48213 (the end of the input), inside a frame: a recording \
                 stopped by a crash or a power cut, or a copy not finished; line 1 read"
            ),
            "{at_line_end}"
        );
        let gzip = damaged(Damage::CutShort, Compression::Gzip, 2);
        let nothing = describe("x.gz", &gzip, Some(2), Reached { lines: 0, unfinished: 0 });
        assert!(
            nothing.ends_with(
                "inside a member: a recording stopped by a crash or a power cut, or a copy \
                 not finished; no whole line before it"
            ),
            "{nothing}"
        );
    }

    #[test]
    fn corruption_names_the_byte_of_the_size_the_decompressor_words_and_what_is_lost() {
        let bad = damaged(Damage::Corrupt, Compression::Xz, 271);
        assert_eq!(
            describe("bad.log.xz", &bad, Some(520), Reached { lines: 40, unfinished: 12 }),
            "bad.log.xz: the xz data is corrupt, found at byte 271 of 520 (Data corruption detected): a damaged \
             disk or a bad copy; lines 1-40 read (the last ones may be damaged too), the unfinished line 41 \
             (12 bytes) and the rest of the file not decoded"
        );
        let at_start = describe("bad.log.xz", &bad, None, Reached { lines: 0, unfinished: 0 });
        assert!(
            at_start.ends_with(
                "(Data corruption detected): a damaged disk or a bad copy; no whole line \
                 before it, the rest of the file not decoded"
            ),
            "{at_start}"
        );
    }
}
