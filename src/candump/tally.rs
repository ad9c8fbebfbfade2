//! Rejected input, counted per reason with the first place each occurred; the first few are shown as they
//! happen, the rest only counted. `decode` and `--replay` both report bad lines with it, in the same words.

/// How many rejected lines are shown one by one before the rest are only counted.
pub const MAX_SHOWN_REJECTS: usize = 10;

/// One reason and how often it occurred.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rejection {
    pub reason: String,
    pub count: u64,
    /// `file:line` (or `file: byte N`) of the first input rejected for this reason.
    pub first_at: String,
    /// For "line too long": the longest such line, in bytes.
    pub longest: Option<u64>,
    /// Counted in lines (candump text), not bytes (RS232 captures).
    pub in_lines: bool,
}

impl Rejection {
    /// `3 x line too long (longest 250000 bytes; first at f.log:7)`
    pub fn describe(&self) -> String {
        format!("{} x {}", self.count, self.describe_after_count())
    }

    /// `line too long (longest 250000 bytes; first at f.log:7)`
    pub fn describe_after_count(&self) -> String {
        match self.longest {
            Some(longest) => format!("{} (longest {longest} bytes; first at {})", self.reason, self.first_at),
            None => format!("{} (first at {})", self.reason, self.first_at),
        }
    }
}

/// What is said about a line over the reader's limit; it is always counted as [`Reason::LineTooLong`], one
/// reason whatever the length, so the totals stay one short line.
///
/// [`Reason::LineTooLong`]: super::Reason::LineTooLong
pub fn line_too_long(len: usize) -> String {
    format!(
        "line of {len} bytes is too long for a candump line (limit {} bytes)",
        super::DEFAULT_MAX_LINE_LEN
    )
}

/// Where and what was rejected: `location` is `file:12` or `file: byte 40`, `message` says why in full,
/// `reason` is the short text counted (a closed set, so the tally stays small).
#[derive(Clone, Copy, Debug)]
pub struct Rejected<'a> {
    pub location: &'a str,
    pub message: &'a str,
    pub reason: &'a str,
    /// The line's length, for over-long lines.
    pub length: Option<u64>,
    /// A line of text (false: bytes of an RS232 capture).
    pub in_lines: bool,
}

/// Rejected lines per reason. The reasons are a closed set (`Reason::as_str`, "line too long"), so the list
/// stays small however many lines are rejected.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RejectTally {
    pub rejected: Vec<Rejection>,
    shown: usize,
}

impl RejectTally {
    /// Counts a rejection. Returns what to tell the user now, without the `tracerctl: ` prefix: the
    /// location and message for the first [`MAX_SHOWN_REJECTS`], then once that further ones are only
    /// counted, then nothing.
    pub fn reject(&mut self, rejected: Rejected) -> Option<String> {
        match self.rejected.iter_mut().find(|r| r.reason == rejected.reason) {
            Some(rejection) => {
                rejection.count += 1;
                rejection.longest = rejection.longest.max(rejected.length);
            }
            None => self.rejected.push(Rejection {
                reason: rejected.reason.to_string(),
                count: 1,
                first_at: rejected.location.to_string(),
                longest: rejected.length,
                in_lines: rejected.in_lines,
            }),
        }
        self.shown += 1;
        match self.shown {
            shown if shown <= MAX_SHOWN_REJECTS => {
                Some(format!("{}: {}", rejected.location, rejected.message))
            }
            shown if shown == MAX_SHOWN_REJECTS + 1 => {
                Some("further rejected input is only counted (see the totals at the end)".to_string())
            }
            _ => None,
        }
    }

    /// Lines rejected in all.
    pub fn total(&self) -> u64 {
        self.rejected.iter().map(|r| r.count).sum()
    }

    /// `rejected 12: 10 x not a candump line (first at bus.log:3); 2 x bad hex digit (first at bus.log:9)`,
    /// the part of a totals line `decode` writes; `None` when nothing was rejected.
    pub fn describe(&self) -> Option<String> {
        let total = self.total();
        if total == 0 {
            return None;
        }
        let reasons: Vec<String> = self.rejected.iter().map(Rejection::describe).collect();
        Some(format!("rejected {total}: {}", reasons.join("; ")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_ten_are_shown_then_one_notice_then_only_counts() {
        let mut tally = RejectTally::default();
        assert_eq!(tally.describe(), None);
        let mut shown = Vec::new();
        for line in 1..=25u32 {
            let reason = if line % 5 == 0 { "bad hex digit" } else { "not a candump line" };
            let message = format!("{reason} at column 3");
            let location = format!("bus.log:{line}");
            let rejected =
                Rejected { location: &location, message: &message, reason, length: None, in_lines: true };
            if let Some(text) = tally.reject(rejected) {
                shown.push(text);
            }
        }
        assert_eq!(shown.len(), 11);
        assert_eq!(shown[0], "bus.log:1: not a candump line at column 3");
        assert_eq!(shown[4], "bus.log:5: bad hex digit at column 3");
        assert_eq!(shown[10], "further rejected input is only counted (see the totals at the end)");
        assert_eq!(tally.total(), 25);
        assert_eq!(
            tally.describe().unwrap(),
            "rejected 25: 20 x not a candump line (first at bus.log:1); 5 x bad hex digit (first at bus.log:5)"
        );
    }
}
