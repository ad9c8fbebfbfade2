//! The line-length limit and its one rule, for every reader of text logs ([`super::LineReader`], decode's
//! splitter and its positioned reads): a line longer than the limit is never buffered whole. It is kept only
//! up to one byte past the limit (enough to tell that it is too long) and its true length is counted on to
//! its `\n`, so it is rejected as one line of that length, whatever it holds.

/// The longest line read by default, without its `\n` (a candump line is under 200 bytes; 64 KiB leaves
/// room for any line of any format while a line of gigabytes costs no memory).
pub const DEFAULT_MAX_LINE_LEN: usize = 64 * 1024;

/// Where lines are cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineLimit {
    max: usize,
}

impl LineLimit {
    /// The limit of every reader unless a test sets another.
    pub const DEFAULT: Self = Self { max: DEFAULT_MAX_LINE_LEN };

    /// Lines longer than `max` bytes (without their `\n`) are too long.
    pub const fn new(max: usize) -> Self {
        Self { max }
    }

    /// The longest line that is not too long.
    pub const fn max(self) -> usize {
        self.max
    }

    /// The bytes a reader keeps of a line: one past the limit, enough to tell it is too long.
    pub const fn kept(self) -> usize {
        self.max.saturating_add(1)
    }

    /// Whether a line of `length` bytes (without its `\n`) is too long.
    #[inline]
    pub const fn is_over(self, length: usize) -> bool {
        length > self.max
    }

    /// The open line of `length` bytes (no `\n` seen yet), to be cut short if it is already too long.
    #[inline]
    pub fn cut(self, length: usize) -> Option<LongLine> {
        self.is_over(length).then_some(LongLine { length })
    }
}

/// A line over the limit, cut short where it was found: its true length so far, counted on to its `\n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LongLine {
    length: usize,
}

impl LongLine {
    /// `bytes` more of the line, still before its `\n`.
    #[inline]
    pub fn extend(&mut self, bytes: usize) {
        self.length = self.length.saturating_add(bytes);
    }

    /// The line's length without its `\n`.
    pub const fn length(self) -> usize {
        self.length
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_one_byte_past_the_limit_is_cut_and_counted_on() {
        let limit = LineLimit::new(8);
        assert_eq!(limit.kept(), 9);
        assert!(!limit.is_over(8) && limit.is_over(9));
        assert_eq!(limit.cut(8), None);
        let mut long = limit.cut(9).expect("too long");
        long.extend(100);
        long.extend(usize::MAX);
        assert_eq!(long.length(), usize::MAX, "a length never wraps");
        assert_eq!(LineLimit::DEFAULT.max(), 64 * 1024);
        assert_eq!(LineLimit::new(usize::MAX).kept(), usize::MAX);
    }
}
