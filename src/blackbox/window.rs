//! The incident windows: a trigger at `t` keeps the frames of `[t - before, t + after]`; a trigger inside an
//! open window extends it (one incident, every cause listed). Pure: times come in as arguments.

/// One incident in the making.
#[derive(Clone, Debug, PartialEq)]
pub struct Window<C> {
    /// When the first trigger fired (names the incident).
    pub trigger: u64,
    pub start: u64,
    pub end: u64,
    /// Every cause, with when it fired, in order.
    pub causes: Vec<(u64, C)>,
}

/// The open window, if any, and the settings.
#[derive(Clone, Debug)]
pub struct Windows<C> {
    before: u64,
    after: u64,
    open: Option<Window<C>>,
}

impl<C> Windows<C> {
    /// `before` and `after` in microseconds.
    pub fn new(before: u64, after: u64) -> Self {
        Self { before, after, open: None }
    }

    /// A trigger at `at`: opens a window, or extends the open one. Returns a window this closes: one
    /// already over when `at` comes after its end (the caller closes windows on time with [`Self::due`]
    /// too; this catches a trigger that arrives first).
    pub fn trigger(&mut self, at: u64, cause: C) -> Option<Window<C>> {
        let closed = match &mut self.open {
            Some(window) if at <= window.end => {
                window.end = window.end.max(at.saturating_add(self.after));
                window.causes.push((at, cause));
                return None;
            }
            open => open.take(),
        };
        self.open = Some(Window {
            trigger: at,
            start: at.saturating_sub(self.before),
            end: at.saturating_add(self.after),
            causes: vec![(at, cause)],
        });
        closed
    }

    /// The open window, once `now` is past its end.
    pub fn due(&mut self, now: u64) -> Option<Window<C>> {
        if self.open.as_ref().is_some_and(|window| now > window.end) {
            return self.open.take();
        }
        None
    }

    /// The open window, whatever the time (the recording ends).
    pub fn take(&mut self) -> Option<Window<C>> {
        self.open.take()
    }

    pub fn open(&self) -> Option<&Window<C>> {
        self.open.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: u64 = 1_000_000;

    #[test]
    fn a_trigger_keeps_before_and_after() {
        let mut windows = Windows::new(60 * S, 30 * S);
        assert_eq!(windows.trigger(100 * S, "estop"), None);
        assert_eq!(windows.due(130 * S), None, "the end itself is still inside");
        let window = windows.due(130 * S + 1).expect("closed after its end");
        assert_eq!((window.trigger, window.start, window.end), (100 * S, 40 * S, 130 * S));
        assert_eq!(window.causes, [(100 * S, "estop")]);
        assert_eq!(windows.due(200 * S), None);
    }

    #[test]
    fn triggers_inside_extend_one_incident() {
        let mut windows = Windows::new(60 * S, 30 * S);
        windows.trigger(100 * S, "estop");
        assert_eq!(windows.trigger(120 * S, "fault"), None);
        assert_eq!(windows.trigger(150 * S, "mark"), None, "inside the extended window");
        let window = windows.due(181 * S).expect("closed");
        assert_eq!((window.start, window.end), (40 * S, 180 * S));
        assert_eq!(window.causes.iter().map(|c| c.1).collect::<Vec<_>>(), ["estop", "fault", "mark"]);
    }

    #[test]
    fn a_trigger_after_the_end_closes_the_old_window_and_opens_another() {
        let mut windows = Windows::new(10 * S, 5 * S);
        windows.trigger(100 * S, "a");
        let closed = windows.trigger(106 * S, "b").expect("the first one is over");
        assert_eq!(closed.causes, [(100 * S, "a")]);
        assert_eq!(windows.open().map(|w| (w.start, w.end)), Some((96 * S, 111 * S)));
        assert_eq!(windows.take().map(|w| w.trigger), Some(106 * S));
        assert_eq!(windows.take(), None);
    }

    #[test]
    fn early_times_do_not_underflow() {
        let mut windows = Windows::new(60 * S, u64::MAX);
        windows.trigger(S, "a");
        assert_eq!(windows.open().map(|w| (w.start, w.end)), Some((0, u64::MAX)));
        assert_eq!(windows.due(u64::MAX), None);
    }
}
