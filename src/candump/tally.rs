//! Rejected lines, counted per reason with the first place each occurred; the first few are shown as they
//! happen, the rest only counted. `--replay` reports its log's bad lines with it, in `decode`'s words (decode
//! keeps its own copy for now; this type is meant to replace it).

/// How many rejected lines are shown one by one before the rest are only counted.
pub const MAX_SHOWN_REJECTS: usize = 10;

/// One reason and how often it occurred.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rejection {
    pub reason: String,
    pub count: u64,
    /// `file:line` of the first line rejected for this reason.
    pub first_at: String,
}

/// Rejected lines per reason. The reasons are a closed set (`Reason::as_str`, "line too long"), so the list
/// stays small however many lines are rejected.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RejectTally {
    pub rejected: Vec<Rejection>,
    shown: usize,
}

impl RejectTally {
    /// Counts a line rejected at `location` (`file:12`) for `reason`; `message` says why in full. Returns
    /// what to tell the user now, without the `tracerctl: ` prefix: the line itself for the first
    /// [`MAX_SHOWN_REJECTS`], then once that further ones are only counted, then nothing.
    pub fn reject(&mut self, location: &str, message: &str, reason: &str) -> Option<String> {
        match self.rejected.iter_mut().find(|r| r.reason == reason) {
            Some(rejection) => rejection.count += 1,
            None => self.rejected.push(Rejection {
                reason: reason.to_string(),
                count: 1,
                first_at: location.to_string(),
            }),
        }
        self.shown += 1;
        match self.shown {
            shown if shown <= MAX_SHOWN_REJECTS => Some(format!("{location}: {message}")),
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
        let reasons: Vec<String> = self
            .rejected
            .iter()
            .map(|r| format!("{} x {} (first at {})", r.count, r.reason, r.first_at))
            .collect();
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
            if let Some(text) = tally.reject(&format!("bus.log:{line}"), &message, reason) {
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
