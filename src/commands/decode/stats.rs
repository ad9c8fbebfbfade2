//! What decoding counted besides frames: lines, skips, rejections, serial losses; and the totals line.

use crate::candump::{Line, RejectTally, Rejection};
use crate::protocol;

/// What happened to the input besides frames: everything that was not decoded is counted here.
/// For candump text, `decoded_lines + rejected_lines + skipped.total() == lines`.
#[derive(Debug, Default)]
pub struct InputStats {
    pub lines: u64,
    pub frames: u64,
    /// Lines that gave a frame.
    pub decoded_lines: u64,
    /// Lines that could not be read (each also counted under its reason in `rejected`).
    pub rejected_lines: u64,
    pub skipped: Skipped,
    /// Frames candump itself reported dropped (DROPCOUNT lines).
    pub candump_dropped: u64,
    /// Rejected input per reason (lines, and bytes of RS232 captures), with the first place of each.
    pub rejected: RejectTally,
    /// Frames with a TRACER ID but invalid content (V1 checksum, too short).
    pub invalid_frames: u64,
    pub serial: Vec<(String, protocol::serial::StreamStats)>,
}

/// Lines that are not frames and not errors, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Skipped {
    pub blank: u64,
    pub comment: u64,
    /// Text following a console ERRORFRAME (`-e`).
    pub error_text: u64,
    /// CAN XL frames: valid, but not decoded.
    pub can_xl: u64,
    /// candump's `DROPCOUNT:` lines (the frames they report are in `candump_dropped`).
    pub dropcount: u64,
}

impl Skipped {
    /// Counts a line that is no frame under its kind; returns the frames a DROPCOUNT line says candump
    /// dropped (0 for every other line).
    pub fn count(&mut self, line: &Line<'_>) -> u64 {
        match *line {
            Line::Frame(_) => {} // decoded by the caller
            Line::Blank => self.blank += 1,
            Line::Comment => self.comment += 1,
            Line::DropCount { dropped } => {
                self.dropcount += 1;
                return dropped;
            }
            Line::ErrorText => self.error_text += 1,
            Line::CanXl => self.can_xl += 1,
        }
        0
    }

    pub fn total(&self) -> u64 {
        self.blank + self.comment + self.error_text + self.can_xl + self.dropcount
    }

    /// `1 blank, 2 comment, ...`: the non-zero kinds.
    pub fn describe(&self) -> String {
        let kinds = [
            (self.blank, "blank"),
            (self.comment, "comment"),
            (self.error_text, "error-frame text"),
            (self.can_xl, "CAN XL frame"),
            (self.dropcount, "DROPCOUNT"),
        ];
        let parts: Vec<String> = kinds
            .iter()
            .filter(|(count, _)| *count > 0)
            .map(|(count, kind)| format!("{count} {kind}"))
            .collect();
        parts.join(", ")
    }
}

impl InputStats {
    pub fn rejected_total(&self) -> u64 {
        self.rejected.total()
    }

    /// Whether the totals line is worth printing after plain decoding: when anything was lost or not
    /// decoded. Blank lines, comments (every ASC and trc file has a header of them) and the text candump
    /// prints after an error frame (which is decoded) lose nothing, so a clean log stays quiet.
    pub(super) fn anything_lost(&self) -> bool {
        self.rejected_total() > 0
            || self.invalid_frames > 0
            || self.candump_dropped > 0
            || self.skipped.can_xl > 0
            || self.skipped.dropcount > 0
            || self.serial.iter().any(|(_, s)| serial_losses(s))
    }

    /// Whether any input was read at all (a refused or missing first input leaves nothing to report).
    pub(super) fn anything_read(&self) -> bool {
        self.lines > 0 || self.frames > 0 || !self.serial.is_empty()
    }
}

fn serial_losses(stats: &protocol::serial::StreamStats) -> bool {
    stats.skipped_bytes > 0 || stats.bad_checksum > 0 || stats.bad_length > 0 || stats.bad_type > 0
}

/// The run's counts when an input began: what the input itself added is told from them.
#[derive(Clone, Copy)]
pub(super) struct InputStart {
    pub lines: u64,
    pub decoded_lines: u64,
    pub rejected_lines: u64,
    pub skipped: Skipped,
    /// Damaged inputs said so far (see damaged.rs).
    pub damaged: usize,
}

/// `decoded N frames from M lines; rejected K lines: ...; skipped S lines: ...; serial ...`
pub fn totals_line(stats: &InputStats) -> String {
    let mut line = format!("decoded {} frames", stats.frames);
    if stats.lines > 0 {
        if stats.decoded_lines == stats.frames {
            line.push_str(&format!(" from {} lines", stats.lines));
        } else {
            line.push_str(&format!(" ({} from {} lines)", stats.decoded_lines, stats.lines));
        }
    }
    let (line_reasons, other_reasons): (Vec<&Rejection>, Vec<&Rejection>) =
        stats.rejected.rejected.iter().partition(|r| r.in_lines);
    if stats.rejected_lines > 0 {
        let reasons: Vec<String> = line_reasons.iter().map(|r| r.describe()).collect();
        line.push_str(&format!("; rejected {} lines: {}", stats.rejected_lines, reasons.join("; ")));
    }
    if stats.skipped.total() > 0 {
        line.push_str(&format!("; skipped {} lines: {}", stats.skipped.total(), stats.skipped.describe()));
    }
    for (name, serial) in &stats.serial {
        line.push_str(&format!("; serial {name}: {} bytes, {} frames", serial.bytes, serial.frames));
        for (count, what) in [
            (serial.skipped_bytes, "bytes skipped"),
            (serial.sync_losses, "sync losses"),
            // Checksum mismatches are rejections, listed with their first place below.
            (serial.bad_length, "bad length bytes"),
            (serial.bad_type, "bad frame types"),
        ] {
            if count > 0 {
                line.push_str(&format!(", {count} {what}"));
            }
        }
    }
    if !other_reasons.is_empty() {
        let reasons: Vec<String> = other_reasons.iter().map(|r| r.describe()).collect();
        line.push_str(&format!("; rejected serial input: {}", reasons.join("; ")));
    }
    if stats.invalid_frames > 0 {
        line.push_str(&format!("; {} invalid frames", stats.invalid_frames));
    }
    if stats.candump_dropped > 0 {
        line.push_str(&format!("; candump reported {} dropped frames", stats.candump_dropped));
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_of_line_is_counted_once_and_a_dropcount_gives_its_frames() {
        let mut skipped = Skipped::default();
        let lines =
            [Line::Blank, Line::Comment, Line::ErrorText, Line::CanXl, Line::DropCount { dropped: 7 }];
        let dropped: Vec<u64> = lines.iter().map(|line| skipped.count(line)).collect();
        assert_eq!(dropped, [0, 0, 0, 0, 7]);
        let expected = Skipped { blank: 1, comment: 1, error_text: 1, can_xl: 1, dropcount: 1 };
        assert_eq!(skipped, expected);
        assert_eq!(skipped.describe(), "1 blank, 1 comment, 1 error-frame text, 1 CAN XL frame, 1 DROPCOUNT");
    }
}
