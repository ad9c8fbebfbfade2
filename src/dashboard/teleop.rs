//! Keyboard teleop: driving keys in, a velocity request out.
//!
//! Pure: no terminal types, no clock, no I/O. Time is a [`Duration`] since an arbitrary start, passed in by the
//! caller; the terminal glue maps its key events to [`Key`] and [`KeyAction`]. Each pass of the UI loop asks
//! [`Teleop::request`] for the current request, multiplies it by the dashboard's caps and hands it to
//! `MotionSender::set_target`, whose ramps, caps and 250 ms watchdog (a stalled UI loop) come on top.
//!
//! # The problem
//! A terminal sends a byte when a key goes down and, while it stays down, auto-repeats after an initial delay
//! (Linux console 250 ms then ~11/s; desktop terminals 500-660 ms then 25-40/s). It sends nothing when the key
//! goes up. The kitty keyboard protocol adds press/repeat/release events; where the terminal supports it the
//! glue uses [`ReleaseMode::Events`], otherwise [`ReleaseMode::Deadline`].
//!
//! # `Events` mode
//! A key is held from `Press` to `Release`; `Repeat` keeps it held. A release can still get lost (an SSH stall
//! while the key is down, a terminal that stops reporting), so a held key also expires when its events stop:
//! - after a `Press`, when nothing more of it arrives for [`EVENTS_PRESS_CAP`] (1 s, or the learned first
//!   deadline if that is longer): the wait for the first auto-repeat, which is at most 1 s on any plausible
//!   terminal;
//! - after a `Repeat` (or a second `Press`, as Windows reports repeats), when nothing more arrives for
//!   [`EVENTS_REPEAT_CAP`] (500 ms, many repeat intervals, so a live hold never trips it).
//!
//! The bound is "the later of the current bound and now + cap", so no key counts as held more than
//! [`FIRST_DEADLINE_MAX`] after the last event of any key.
//!
//! *Combinations*: terminals repeat only the last key pressed, so in Up+Left only Left repeats while Up
//! stays down without events. Any event of any key proves the stream alive (a release of Up would have come
//! with it), so it extends every other held key as it would extend its own key (by the press cap after a
//! press, by [`EVENTS_REPEAT_CAP`] after a repeat or a release): Up+Left drives an arc for as long as both
//! are down. Once Left is released, Up has no events left and stops [`EVENTS_REPEAT_CAP`] later (a
//! lost release cannot be told from a held key that does not repeat): press it again. The cost: with auto-repeat switched off in the desktop
//! settings a held key stops after 1 s and must be pressed again. An expired key, like a released one, is
//! not revived by a `Repeat`: after a stall the buffered repeats are stale, so only a new `Press` drives again.
//!
//! # `Deadline` mode
//! Without releases a key counts as held until a deadline that each new byte of that key pushes out:
//! - a byte of a key that is not held is a press: held until now + the *first deadline*, which must cover
//!   the terminal's initial repeat delay (700 ms before anything is learned: covers 250-660 ms);
//! - a byte of a held key is a repeat: held until now + the *repeat deadline*, a few repeat intervals (150 ms
//!   before anything is learned). A repeat may shorten the hold: that is what makes a release after a long
//!   hold quick.
//!
//! The deadlines are learned from the key stream (in both modes, so the screen can show them):
//! - the terminal's *delay* is the gap from a press to its first repeat, taken only when it lies in
//!   150..=1000 ms, when the run started from silence (a press, not a stalled repeat), and when it is confirmed
//!   by a repeat interval following it and is at least 1.5 times that interval; two taps 400 ms apart, an SSH
//!   stall in the middle of a repeat stream, or a gap of 2 s (a new press) are not delays;
//! - the *interval* is any gap between consecutive repeats within 10..=200 ms (shorter gaps are bytes bunched
//!   by the network and carry no timing);
//! - each estimate is the (upper) median of the latest samples (7 delays, 31 intervals), so outliers do not
//!   move it;
//! - first deadline = delay + max(25 %, 60 ms), at most 1.25 s: console 312.5 ms, desktop 600 ms → 750 ms;
//!   the margin absorbs SSH jitter on the first repeat. A delay longer than the 700 ms default is learned
//!   too: the first long hold stutters once (the key expires before its first repeat, which then counts as a
//!   new press), later holds do not.
//! - repeat deadline = 2.5 × interval + 20 ms, clamped to 60..=250 ms: console 90 ms → 245 ms, desktop
//!   33 ms → 102.5 ms. 2.5 intervals ride out a late or lost repeat; the floor keeps SSH jitter from
//!   stuttering on fast-repeating terminals; the cap bounds how long the robot coasts after a release;
//! - unless the link delivers late (below): then the longest recent gap + [`LATE_MARGIN`], same clamp.
//! - `--key-timeout` ([`Teleop::with_key_timeout`]) replaces the learned repeat deadline (and is the least
//!   first deadline).
//!
//! # Jittery links
//! Over a congested SSH link the repeats of a held key arrive late, then in a burst: a steady 33 ms stream
//! with a 150 ms pause every 0.8 s has gaps of up to 183 ms in it. A 102.5 ms deadline lets the key expire in
//! every pause: the sender brakes, then speeds up again on the burst (a stutter, the worse the stronger the
//! braking). So the learner also keeps the latest 64 gaps of the repeat streams (intervals and
//! late repeats: a gap up to 250 ms after which the stream goes on at its interval; bunched bytes under 10 ms
//! carry no timing), and the repeat deadline is at least the longest of them + [`LATE_MARGIN`]. The first
//! pause still stutters (nothing is learned before it); later ones do not. The price is release latency:
//! after the last key the robot is driven for the longest recent gap + 10 ms (192 ms in the bench instead of
//! 102.5 ms), then brakes (0.1 s from 0.15 m/s at the default 1.5 m/s²): zero about 0.29 s after the last
//! key. The margin is small because every ms of it is paid on every release; the window forgets a pause after
//! ~2 s of smooth repeats. The test `jittery_link_neither_stutters_nor_releases_late` measures both with the
//! sender's ramp.
//!
//! Trade-offs that follow from having no release events:
//! - *A tap is a pulse*: a single press with no repeat is held for the whole first deadline (700 ms before
//!   learning, 312.5 ms on a Linux console, 750 ms on a 600 ms desktop terminal), however short the tap was.
//!   The sender's acceleration ramp keeps such a pulse small.
//! - *Release latency*: after a held key is released the robot is driven for up to one repeat deadline more
//!   (at most 250 ms, ~100 ms on desktop terminals).
//! - *One key at a time*: terminals auto-repeat only the last key pressed. When a second key is pressed while
//!   the first is held, the first key's bytes stop and it counts as released at its own deadline even if it
//!   is still physically down; so Up+Left only drives both for that moment. Arcs take one diagonal key
//!   ([`Key::ForwardLeft`] and the others: u o m . and Home PgUp End PgDn); combinations need `Events` mode.
//! - A `Release` that does arrive (some terminals report it anyway) releases the key at once. A `Repeat` only
//!   extends a hold, never starts one; the glue passes `Press` for every legacy byte.
//!
//! [`Teleop::release_all`] (Space, focus lost, a stall) drops every hold until the key is pressed again.

use std::time::Duration;

const fn ms(millis: u64) -> Duration {
    Duration::from_millis(millis)
}

/// The first deadline before the terminal's repeat delay has been learned (covers 250-660 ms delays).
pub const DEFAULT_FIRST_DEADLINE: Duration = ms(700);
/// The repeat deadline before the terminal's repeat interval has been learned (covers intervals up to ~120 ms).
pub const DEFAULT_REPEAT_DEADLINE: Duration = ms(150);
/// Plausible initial repeat delays; other gaps are not learned as delays.
pub const DELAY_MIN: Duration = ms(150);
/// Also the longest gap that still continues a run of one key's bytes.
pub const DELAY_MAX: Duration = ms(1000);
/// Plausible repeat intervals; shorter gaps are bunched bytes, longer ones end the repeat stream.
pub const INTERVAL_MIN: Duration = ms(10);
pub const INTERVAL_MAX: Duration = ms(200);
/// The least margin added to the learned delay.
pub const FIRST_MARGIN_MIN: Duration = ms(60);
/// The longest first deadline (the longest plausible delay + 25 %); also the longest any key stays held after
/// its last event, in either mode.
pub const FIRST_DEADLINE_MAX: Duration = ms(1250);
/// Added to 2.5 learned intervals.
pub const REPEAT_JITTER: Duration = ms(20);
pub const REPEAT_DEADLINE_MIN: Duration = ms(60);
pub const REPEAT_DEADLINE_MAX: Duration = ms(250);
/// Added to the longest recent gap of a repeat stream. Small on purpose: every ms of it is a ms more before
/// a release brakes (see "Jittery links" in the module doc).
pub const LATE_MARGIN: Duration = ms(10);
/// The shortest `--key-timeout`.
pub const KEY_TIMEOUT_MIN: Duration = ms(20);
/// `Events` mode: a pressed key with no further event for this long (or the learned first deadline, if
/// longer) counts as released: its release was lost.
pub const EVENTS_PRESS_CAP: Duration = ms(1000);
/// `Events` mode: a repeating key with no further event for this long counts as released.
pub const EVENTS_REPEAT_CAP: Duration = ms(500);

const DELAY_SAMPLES: usize = 7;
const INTERVAL_SAMPLES: usize = 31;
/// Repeat gaps whose longest sets the late-delivery deadline: about 2 s of a 33 ms stream, 6 s of a 90 ms one.
const GAP_SAMPLES: usize = 64;
/// Scale in tenths.
const SCALE_MIN: u8 = 1;
const SCALE_MAX: u8 = 10;
const SCALE_START: u8 = 3;

/// The driving keys; Space, `+`, `-` and the rest are handled by the app. The four diagonals drive an arc
/// with one key, so arcs work where a terminal repeats only the last key pressed (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    Up,
    Down,
    Left,
    Right,
    /// Forward while turning left (teleop_twist_keyboard's `u`).
    ForwardLeft,
    /// Forward while turning right (`o`).
    ForwardRight,
    /// Backward with the rear swinging left, i.e. turning clockwise (`m`).
    BackLeft,
    /// Backward with the rear swinging right, turning counter-clockwise (`.`).
    BackRight,
}

/// How many driving keys there are.
const KEYS: usize = 8;

impl Key {
    /// Every driving key, in the order [`Teleop::held`] lists them.
    pub const ALL: [Key; KEYS] = [
        Key::Up,
        Key::Down,
        Key::Left,
        Key::Right,
        Key::ForwardLeft,
        Key::ForwardRight,
        Key::BackLeft,
        Key::BackRight,
    ];

    fn index(self) -> usize {
        self as usize
    }

    /// What the key asks for, (linear, angular), each -1, 0 or 1: forward is +linear, left (counter-clockwise)
    /// +angular. The backward diagonals follow teleop_twist_keyboard: the robot moves towards the named side,
    /// so back-left turns clockwise.
    pub const fn direction(self) -> (i8, i8) {
        match self {
            Key::Up => (1, 0),
            Key::Down => (-1, 0),
            Key::Left => (0, 1),
            Key::Right => (0, -1),
            Key::ForwardLeft => (1, 1),
            Key::ForwardRight => (1, -1),
            Key::BackLeft => (-1, -1),
            Key::BackRight => (-1, 1),
        }
    }
}

/// What happened to a key. `Repeat` is an auto-repeat the terminal reported as such (kitty); in legacy mode
/// the glue passes `Press` for every byte, repeats included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyAction {
    Press,
    Repeat,
    Release,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReleaseMode {
    /// The terminal reports releases (kitty keyboard protocol): a key is held from Press until Release.
    Events,
    /// No releases: a key is held until no repeat arrives before a deadline learned from the key stream.
    Deadline,
}

/// The keyboard teleop state: which keys are held until when, the speed scale, and what has been learned
/// about the terminal's auto-repeat. See the module documentation.
#[derive(Clone, Debug)]
pub struct Teleop {
    mode: ReleaseMode,
    /// The speed scale in tenths.
    tenths: u8,
    /// Per key: held until this instant (exclusive); `None` when released.
    until: [Option<Duration>; KEYS],
    learner: Learner,
    /// `--key-timeout`: the repeat deadline, instead of the learned one.
    key_timeout: Option<Duration>,
}

impl Teleop {
    pub fn new(mode: ReleaseMode) -> Self {
        Self {
            mode,
            tenths: SCALE_START,
            until: [None; KEYS],
            learner: Learner::default(),
            key_timeout: None,
        }
    }

    /// A fixed repeat deadline instead of the learned one (`--key-timeout`), in `Deadline` mode; the first
    /// deadline is at least as long. Clamped to [`KEY_TIMEOUT_MIN`]..=[`FIRST_DEADLINE_MAX`].
    pub fn with_key_timeout(mut self, timeout: Option<Duration>) -> Self {
        self.key_timeout = timeout.map(|timeout| timeout.clamp(KEY_TIMEOUT_MIN, FIRST_DEADLINE_MAX));
        self
    }

    pub fn mode(&self) -> ReleaseMode {
        self.mode
    }

    /// The `--key-timeout` in force, if one was given.
    pub fn key_timeout(&self) -> Option<Duration> {
        self.key_timeout
    }

    /// A driving key event at `now`.
    pub fn key(&mut self, now: Duration, key: Key, action: KeyAction) {
        let index = key.index();
        if self.mode == ReleaseMode::Events {
            self.keep_combination(now, key, action);
        }
        if action == KeyAction::Release {
            self.until[index] = None;
            self.learner.reset();
            return;
        }
        let held = self.is_held(key, now);
        let fresh_press = self.mode == ReleaseMode::Events && action == KeyAction::Press && !held;
        self.learner.observe(key, now, fresh_press);
        if !held && action == KeyAction::Repeat {
            // A repeat never starts a hold: the key was released, expired or dropped by `release_all`.
            return;
        }
        self.until[index] = Some(match self.mode {
            ReleaseMode::Deadline if held => now.saturating_add(self.repeat_deadline()),
            ReleaseMode::Deadline => now.saturating_add(self.first_deadline()),
            ReleaseMode::Events => {
                let cap = if held { EVENTS_REPEAT_CAP } else { self.events_press_cap() };
                let bound = now.saturating_add(cap);
                match self.until[index] {
                    Some(until) if held => until.max(bound),
                    _ => bound,
                }
            }
        });
    }

    /// `Events` mode: any event proves the key stream alive, and a release would have come with it; so the
    /// other keys held (the first of a combination, which the terminal no longer repeats) stay held as long
    /// as the key of this event would: the press cap after a press (the wait for its first repeat), else
    /// [`EVENTS_REPEAT_CAP`].
    fn keep_combination(&mut self, now: Duration, key: Key, action: KeyAction) {
        let cap = if action == KeyAction::Press { self.events_press_cap() } else { EVENTS_REPEAT_CAP };
        let bound = now.saturating_add(cap);
        for other in Key::ALL.into_iter().filter(|&other| other != key) {
            if self.is_held(other, now) {
                if let Some(until) = &mut self.until[other.index()] {
                    *until = (*until).max(bound);
                }
            }
        }
    }

    /// Everything released at once (Space, focus lost, a stall): no key counts as held until pressed again.
    pub fn release_all(&mut self) {
        self.until = [None; KEYS];
        self.learner.reset();
    }

    /// One step (0.1) faster, up to 1.0. Returns the new scale.
    pub fn faster(&mut self) -> f64 {
        self.tenths = (self.tenths + 1).min(SCALE_MAX);
        self.scale()
    }

    /// One step (0.1) slower, down to 0.1. Returns the new scale.
    pub fn slower(&mut self) -> f64 {
        self.tenths = self.tenths.saturating_sub(1).max(SCALE_MIN);
        self.scale()
    }

    /// The speed scale, 0.1..=1.0; starts at 0.3.
    pub fn scale(&self) -> f64 {
        f64::from(self.tenths) / 10.0
    }

    /// What the keys ask for at `now` as fractions of full speed, (linear, angular), each in -1..=1 and
    /// already multiplied by the scale: Up +linear, Down -linear, Left +angular (counter-clockwise), Right
    /// -angular; Up+Down cancel; Up+Left give both. Expired holds count as released.
    pub fn request(&self, now: Duration) -> (f64, f64) {
        let (linear, angular) = self
            .held(now)
            .into_iter()
            .map(Key::direction)
            .fold((0i8, 0i8), |(linear, angular), (l, a)| (linear + l, angular + a));
        let axis = |sum: i8| f64::from(sum.clamp(-1, 1)) * self.scale();
        (axis(linear), axis(angular))
    }

    /// The next instant after `now` at which a held key expires (the request may change then without any
    /// key event): the loop wakes up for it, so a release leaves on time.
    pub fn next_expiry(&self, now: Duration) -> Option<Duration> {
        self.until.iter().flatten().copied().filter(|&until| until > now).min()
    }

    /// The keys that count as held at `now`, in [`Key::ALL`] order.
    pub fn held(&self, now: Duration) -> Vec<Key> {
        Key::ALL.into_iter().filter(|&key| self.is_held(key, now)).collect()
    }

    /// The learned repeat delay and interval of the terminal; [`Duration::ZERO`] for what is not learned yet.
    pub fn learned(&self) -> (Duration, Duration) {
        (
            self.learner.delays.median().unwrap_or(Duration::ZERO),
            self.learner.intervals.median().unwrap_or(Duration::ZERO),
        )
    }

    /// The deadline applied now to a just-pressed key and to a repeating key: in `Deadline` mode the first
    /// and repeat deadlines, in `Events` mode the caps after which a lost release is assumed.
    pub fn deadlines(&self) -> (Duration, Duration) {
        match self.mode {
            ReleaseMode::Deadline => (self.first_deadline(), self.repeat_deadline()),
            ReleaseMode::Events => (self.events_press_cap(), EVENTS_REPEAT_CAP),
        }
    }

    fn is_held(&self, key: Key, now: Duration) -> bool {
        self.until[key.index()].is_some_and(|until| now < until)
    }

    fn first_deadline(&self) -> Duration {
        let learned = match self.learner.delays.median() {
            None => DEFAULT_FIRST_DEADLINE,
            Some(delay) => (delay + (delay / 4).max(FIRST_MARGIN_MIN)).min(FIRST_DEADLINE_MAX),
        };
        learned.max(self.key_timeout.unwrap_or_default())
    }

    fn repeat_deadline(&self) -> Duration {
        if let Some(timeout) = self.key_timeout {
            return timeout;
        }
        let Some(interval) = self.learner.intervals.median() else {
            return DEFAULT_REPEAT_DEADLINE;
        };
        // The steady stream's deadline, or the longest recent gap in it (a link that delivers late) plus a
        // little: whichever is longer.
        let steady = interval * 5 / 2 + REPEAT_JITTER;
        let late = self.learner.gaps.max().map_or(Duration::ZERO, |gap| gap + LATE_MARGIN);
        steady.max(late).clamp(REPEAT_DEADLINE_MIN, REPEAT_DEADLINE_MAX)
    }

    fn events_press_cap(&self) -> Duration {
        EVENTS_PRESS_CAP.max(self.first_deadline())
    }
}

/// Where the current run of one key's bytes is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Phase {
    /// One byte so far, after silence, another key or a release: a press.
    #[default]
    First,
    /// Two or more bytes, the last gap not yet confirmed as a repeat interval.
    Second,
    /// Repeating at the terminal's interval.
    Repeating,
}

/// Learns the terminal's repeat delay and interval from the gaps between bytes of the same key.
#[derive(Clone, Debug, Default)]
struct Learner {
    last: Option<(Key, Duration)>,
    phase: Phase,
    /// The gap from a press to the next byte, a delay if a repeat interval follows.
    pending: Option<Duration>,
    /// A gap in a repeat stream longer than an interval, a late repeat if the stream goes on after it.
    late: Option<Duration>,
    delays: Window<DELAY_SAMPLES>,
    intervals: Window<INTERVAL_SAMPLES>,
    /// Every gap of the repeat streams, late ones included: the longest sets the deadline.
    gaps: Window<GAP_SAMPLES>,
}

impl Learner {
    /// Ends the current run: the next byte is a press.
    fn reset(&mut self) {
        self.last = None;
        self.phase = Phase::First;
        self.pending = None;
        self.late = None;
    }

    /// A byte (Press or Repeat) of `key` at `now`; `fresh_press` when the terminal says it is a new press.
    fn observe(&mut self, key: Key, now: Duration, fresh_press: bool) {
        let gap = match self.last {
            Some((last, at)) if last == key && !fresh_press => now.checked_sub(at),
            _ => None,
        };
        match gap {
            // Bytes bunched by the network: no timing in them.
            Some(gap) if gap < INTERVAL_MIN => {}
            Some(gap) if gap <= DELAY_MAX => self.step(gap),
            _ => self.reset(),
        }
        self.last = Some((key, now));
    }

    fn step(&mut self, gap: Duration) {
        let interval = gap <= INTERVAL_MAX;
        if let Some(late) = self.late.take() {
            // The stream went on at its interval after a long gap: that gap was a late repeat.
            if interval {
                self.gaps.push(late);
            }
        }
        match (self.phase, interval) {
            (Phase::First, _) => {
                self.phase = Phase::Second;
                self.pending = (gap >= DELAY_MIN).then_some(gap);
            }
            (Phase::Second, true) => {
                if let Some(delay) = self.pending.take() {
                    if delay * 2 >= gap * 3 {
                        self.delays.push(delay);
                    }
                }
                self.intervals.push(gap);
                self.gaps.push(gap);
                self.phase = Phase::Repeating;
            }
            // Press, press again (a tap), maybe the second one is held: the gap from it may be the delay.
            (Phase::Second, false) => self.pending = Some(gap),
            (Phase::Repeating, true) => {
                self.intervals.push(gap);
                self.gaps.push(gap);
            }
            // The repeat stream ended: a new press, or a stall or late delivery, which the next gap shows.
            (Phase::Repeating, false) => {
                self.phase = Phase::First;
                self.pending = None;
                self.late = (gap <= REPEAT_DEADLINE_MAX).then_some(gap);
            }
        }
    }
}

/// The latest `N` samples.
#[derive(Clone, Debug)]
struct Window<const N: usize> {
    samples: [Duration; N],
    len: usize,
    next: usize,
}

impl<const N: usize> Default for Window<N> {
    fn default() -> Self {
        Self { samples: [Duration::ZERO; N], len: 0, next: 0 }
    }
}

impl<const N: usize> Window<N> {
    fn push(&mut self, sample: Duration) {
        self.samples[self.next] = sample;
        self.next = (self.next + 1) % N;
        self.len = (self.len + 1).min(N);
    }

    fn max(&self) -> Option<Duration> {
        self.samples[..self.len].iter().copied().max()
    }

    /// The upper median (the longer one of an even count: longer deadlines stutter less).
    fn median(&self) -> Option<Duration> {
        if self.len == 0 {
            return None;
        }
        let mut sorted = self.samples;
        sorted[..self.len].sort_unstable();
        Some(sorted[self.len / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use KeyAction::{Press, Release, Repeat};

    type Event = (u64, Key, KeyAction);

    /// Feeds `events` (sorted by time, in ms) and returns the request at every ms of `0..=end`, taken after
    /// all events at or before that ms.
    fn trace(teleop: &mut Teleop, events: &[Event], end: u64) -> Vec<(f64, f64)> {
        trace_span(teleop, events, 0, end)
    }

    /// Like [`trace`] for the ms `from..=end`; element `i` is the request at `from + i`.
    fn trace_span(teleop: &mut Teleop, events: &[Event], from: u64, end: u64) -> Vec<(f64, f64)> {
        let mut pending = events.iter().peekable();
        (from..=end)
            .map(|t| {
                while let Some(&&(at, key, action)) = pending.peek() {
                    if at > t {
                        break;
                    }
                    teleop.key(ms(at), key, action);
                    pending.next();
                }
                teleop.request(ms(t))
            })
            .collect()
    }

    /// A held key on a legacy terminal: a press at `start`, then a byte after `delay` and every `interval`,
    /// the last one no later than `stop`. All `Press`, as the glue passes them.
    fn legacy_hold(key: Key, start: u64, delay: u64, interval: u64, stop: u64) -> Vec<Event> {
        let mut events = vec![(start, key, Press)];
        let mut t = start + delay;
        while t <= stop {
            events.push((t, key, Press));
            t += interval;
        }
        events
    }

    fn last_time(events: &[Event]) -> u64 {
        events.last().expect("events").0
    }

    /// The first ms after `from` at which the request is zero.
    fn first_zero_after(trace: &[(f64, f64)], from: u64) -> u64 {
        (from..trace.len() as u64).find(|&t| trace[t as usize] == (0.0, 0.0)).expect("released")
    }

    fn assert_driving(trace: &[(f64, f64)], from: u64, to: u64, want: (f64, f64)) {
        for t in from..=to {
            assert_eq!(trace[t as usize], want, "at {t} ms");
        }
    }

    #[test]
    fn starts_released_with_default_deadlines() {
        for mode in [ReleaseMode::Events, ReleaseMode::Deadline] {
            let teleop = Teleop::new(mode);
            assert_eq!(teleop.mode(), mode);
            assert_eq!(teleop.scale(), 0.3);
            assert_eq!(teleop.request(ms(0)), (0.0, 0.0));
            assert!(teleop.held(ms(0)).is_empty());
            assert_eq!(teleop.learned(), (Duration::ZERO, Duration::ZERO));
        }
        assert_eq!(Teleop::new(ReleaseMode::Deadline).deadlines(), (ms(700), ms(150)));
        assert_eq!(Teleop::new(ReleaseMode::Events).deadlines(), (ms(1000), ms(500)));
    }

    #[test]
    fn events_press_repeat_release_drives_exactly_while_held() {
        let mut teleop = Teleop::new(ReleaseMode::Events);
        let mut events = vec![(100, Key::Up, Press)];
        events.extend((0..20).map(|i| (700 + i * 33, Key::Up, Repeat)));
        events.push((1400, Key::Up, Release));
        let trace = trace(&mut teleop, &events, 2000);
        assert_driving(&trace, 0, 99, (0.0, 0.0));
        assert_driving(&trace, 100, 1399, (0.3, 0.0));
        assert_driving(&trace, 1400, 2000, (0.0, 0.0));
        assert!(teleop.held(ms(1400)).is_empty());
        // The release events make the deadlines irrelevant, but the stream was learned for the screen.
        assert_eq!(teleop.learned(), (ms(600), ms(33)));
    }

    #[test]
    fn events_up_left_gives_both_and_down_cancels_up() {
        let mut teleop = Teleop::new(ReleaseMode::Events);
        let events = [
            (0, Key::Up, Press),
            (200, Key::Left, Press),
            (400, Key::Down, Press),
            (600, Key::Down, Release),
            (800, Key::Right, Press),
            (900, Key::Left, Release),
            (950, Key::Up, Release),
            (960, Key::Right, Release),
        ];
        let trace = trace(&mut teleop, &events, 1000);
        assert_driving(&trace, 0, 199, (0.3, 0.0));
        assert_driving(&trace, 200, 399, (0.3, 0.3));
        assert_driving(&trace, 400, 599, (0.0, 0.3));
        assert_driving(&trace, 600, 799, (0.3, 0.3));
        assert_driving(&trace, 800, 899, (0.3, 0.0));
        assert_driving(&trace, 900, 949, (0.3, -0.3));
        assert_driving(&trace, 950, 959, (0.0, -0.3));
        assert_driving(&trace, 960, 1000, (0.0, 0.0));
        assert!(teleop.held(ms(960)).is_empty());
    }

    #[test]
    fn events_release_of_one_key_leaves_the_other() {
        let mut teleop = Teleop::new(ReleaseMode::Events);
        teleop.key(ms(0), Key::Down, Press);
        teleop.key(ms(10), Key::Right, Press);
        assert_eq!(teleop.held(ms(20)), vec![Key::Down, Key::Right]);
        assert_eq!(teleop.request(ms(20)), (-0.3, -0.3));
        teleop.key(ms(30), Key::Right, Release);
        assert_eq!(teleop.held(ms(30)), vec![Key::Down]);
        assert_eq!(teleop.request(ms(30)), (-0.3, 0.0));
    }

    #[test]
    fn events_lost_release_expires_after_the_caps() {
        // Pressed, never repeated nor released: held for the press cap (1 s).
        let mut teleop = Teleop::new(ReleaseMode::Events);
        teleop.key(ms(0), Key::Up, Press);
        assert_eq!(teleop.request(ms(999)), (0.3, 0.0));
        assert_eq!(teleop.request(ms(1000)), (0.0, 0.0));
        // Repeating, then silence (an SSH stall, a lost release): held until 500 ms after the last repeat.
        let mut teleop = Teleop::new(ReleaseMode::Events);
        let mut events = vec![(0, Key::Left, Press)];
        events.extend((0..10).map(|i| (500 + i * 40, Key::Left, Repeat)));
        let last = last_time(&events);
        let trace = trace(&mut teleop, &events, 2000);
        assert_driving(&trace, 0, last + 499, (0.0, 0.3));
        assert_driving(&trace, last + 500, 2000, (0.0, 0.0));
        // Stale repeats after the stall do not revive the key; a new press does.
        teleop.key(ms(2000), Key::Left, Repeat);
        assert_eq!(teleop.request(ms(2000)), (0.0, 0.0));
        teleop.key(ms(2010), Key::Left, Press);
        assert_eq!(teleop.request(ms(2010)), (0.0, 0.3));
    }

    #[test]
    fn events_windows_repeats_as_presses_keep_the_key_held() {
        // crossterm on Windows reports auto-repeats as further Press events.
        let mut teleop = Teleop::new(ReleaseMode::Events);
        let events = legacy_hold(Key::Up, 0, 500, 33, 1500);
        let last = last_time(&events);
        let trace = trace(&mut teleop, &events, 3000);
        assert_driving(&trace, 0, last + 499, (0.3, 0.0));
        assert_driving(&trace, last + 500, 3000, (0.0, 0.0));
        teleop.key(ms(3000), Key::Up, Press);
        assert_eq!(teleop.request(ms(3099)), (0.3, 0.0));
        teleop.key(ms(3100), Key::Up, Release);
        assert_eq!(teleop.request(ms(3100)), (0.0, 0.0));
    }

    #[test]
    fn deadline_linux_console_holds_without_stutter_and_releases_within_250ms() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let events = legacy_hold(Key::Up, 0, 250, 90, 1000);
        let last = last_time(&events);
        assert_eq!(last, 970);
        let trace = trace(&mut teleop, &events, 2000);
        assert_driving(&trace, 0, last, (0.3, 0.0));
        assert_eq!(teleop.learned(), (ms(250), ms(90)));
        assert_eq!(teleop.deadlines(), (Duration::from_micros(312_500), ms(245)));
        let latency = first_zero_after(&trace, last) - last;
        assert_eq!(latency, 245);
        assert!(latency < 250);
        // A second hold uses the learned deadlines from its start.
        let events = legacy_hold(Key::Right, 3000, 250, 90, 4000);
        let last = last_time(&events);
        let trace = self::trace(&mut teleop, &events, 4500);
        assert_driving(&trace, 3000, last, (0.0, -0.3));
        assert_eq!(first_zero_after(&trace, last) - last, 245);
    }

    #[test]
    fn deadline_desktop_terminal_holds_without_stutter_and_releases_within_120ms() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let events = legacy_hold(Key::Left, 0, 600, 33, 2000);
        let last = last_time(&events);
        let trace = trace(&mut teleop, &events, 3000);
        assert_driving(&trace, 0, last, (0.0, 0.3));
        assert_eq!(teleop.learned(), (ms(600), ms(33)));
        assert_eq!(teleop.deadlines(), (ms(750), Duration::from_micros(102_500)));
        let latency = first_zero_after(&trace, last) - last;
        assert_eq!(latency, 103, "102.5 ms, seen at the next whole ms");
        assert!(latency < 120);
    }

    #[test]
    fn deadline_single_tap_is_a_pulse_of_the_first_deadline() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        teleop.key(ms(0), Key::Down, Press);
        assert_eq!(teleop.request(ms(699)), (-0.3, 0.0));
        assert_eq!(teleop.request(ms(700)), (0.0, 0.0));
        // Once the console's 250 ms delay is learned, a tap is a 312.5 ms pulse.
        let events = legacy_hold(Key::Up, 2000, 250, 90, 3000);
        trace(&mut teleop, &events, 3000);
        teleop.key(ms(5000), Key::Down, Press);
        assert_eq!(teleop.request(ms(5312)), (-0.3, 0.0));
        assert_eq!(teleop.request(ms(5313)), (0.0, 0.0));
    }

    #[test]
    fn deadline_learns_a_delay_longer_than_the_default_after_one_stutter() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let events = legacy_hold(Key::Up, 0, 800, 40, 1500);
        let trace = trace(&mut teleop, &events, 1500);
        assert_driving(&trace, 0, 699, (0.3, 0.0));
        assert_driving(&trace, 700, 799, (0.0, 0.0));
        assert_driving(&trace, 800, 1500, (0.3, 0.0));
        assert_eq!(teleop.learned(), (ms(800), ms(40)));
        assert_eq!(teleop.deadlines(), (ms(1000), ms(120)));
        let events = legacy_hold(Key::Up, 3000, 800, 40, 4500);
        let last = last_time(&events);
        let trace = self::trace(&mut teleop, &events, 5000);
        assert_driving(&trace, 3000, last, (0.3, 0.0));
        assert_eq!(first_zero_after(&trace, last) - last, 120);
    }

    #[test]
    fn deadline_learning_ignores_outliers() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let mut events = legacy_hold(Key::Up, 0, 250, 90, 1000);
        // Taps 2 s apart (new presses), a double tap 400 ms apart, three fast taps 150 ms apart.
        events.extend([(3000, Key::Up, Press), (5000, Key::Up, Press), (7000, Key::Up, Press)]);
        events.extend([(7400, Key::Up, Press), (9000, Key::Left, Press), (9150, Key::Left, Press)]);
        events.push((9300, Key::Left, Press));
        // A hold with an SSH stall (350 ms) in its repeat stream and two bunched bytes (2 ms apart).
        let mut hold = legacy_hold(Key::Down, 11_000, 250, 90, 11_700);
        hold.extend(legacy_hold(Key::Down, 12_000, 90, 90, 12_450));
        hold.push((12_452, Key::Down, Press));
        hold.extend(legacy_hold(Key::Down, 12_540, 90, 90, 13_000));
        events.extend(hold);
        // Double tap then hold: tap at 15 000, press and hold at 15 300.
        events.push((15_000, Key::Right, Press));
        events.extend(legacy_hold(Key::Right, 15_300, 250, 90, 16_000));
        trace(&mut teleop, &events, 17_000);
        assert_eq!(teleop.learned(), (ms(250), ms(90)));
        assert_eq!(teleop.deadlines(), (Duration::from_micros(312_500), ms(245)));
        // Fed one by one: the stall, the taps and the 2 s gaps gave no delay sample; the three holds gave 250.
        assert_eq!(teleop.learner.delays.len, 3);
    }

    #[test]
    fn deadline_two_keys_only_the_repeating_key_stays_held() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        // Up held; Left pressed at 560 while Up is still down: the terminal stops repeating Up and repeats Left.
        let mut events = legacy_hold(Key::Up, 0, 250, 90, 520);
        events.extend(legacy_hold(Key::Left, 560, 250, 90, 1500));
        let last_left = last_time(&events);
        let trace = trace(&mut teleop, &events, 2000);
        assert_driving(&trace, 0, 559, (0.3, 0.0));
        // Up counts as held until its own deadline after its last byte (520 + 245).
        assert_driving(&trace, 560, 764, (0.3, 0.3));
        assert_driving(&trace, 765, last_left, (0.0, 0.3));
        assert_eq!(first_zero_after(&trace, last_left) - last_left, 245);
    }

    #[test]
    fn deadline_up_then_down_cancel_while_both_count_as_held() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let mut events = legacy_hold(Key::Up, 0, 250, 90, 700);
        assert_eq!(last_time(&events), 700);
        events.extend(legacy_hold(Key::Down, 720, 250, 90, 1500));
        let trace = trace(&mut teleop, &events, 1500);
        assert_driving(&trace, 0, 719, (0.3, 0.0));
        assert_driving(&trace, 720, 944, (0.0, 0.0)); // Up counts as held until 700 + 245
        assert_driving(&trace, 945, 1500, (-0.3, 0.0));
    }

    #[test]
    fn deadline_release_events_that_do_arrive_release_at_once() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        teleop.key(ms(0), Key::Right, Press);
        assert_eq!(teleop.request(ms(39)), (0.0, -0.3));
        teleop.key(ms(40), Key::Right, Release);
        assert_eq!(teleop.request(ms(40)), (0.0, 0.0));
        // A repeat reported as such extends a hold but never starts one.
        teleop.key(ms(50), Key::Right, Repeat);
        assert_eq!(teleop.request(ms(50)), (0.0, 0.0));
        teleop.key(ms(60), Key::Right, Press);
        teleop.key(ms(500), Key::Right, Repeat); // default repeat deadline: held until 650
        assert_eq!(teleop.request(ms(649)), (0.0, -0.3));
        assert_eq!(teleop.request(ms(650)), (0.0, 0.0));
    }

    #[test]
    fn scale_steps_by_tenths_within_bounds() {
        let mut teleop = Teleop::new(ReleaseMode::Events);
        assert_eq!(teleop.faster(), 0.4);
        assert_eq!(teleop.faster(), 0.5);
        let steps: Vec<f64> = (0..7).map(|_| teleop.faster()).collect();
        assert_eq!(steps, [0.6, 0.7, 0.8, 0.9, 1.0, 1.0, 1.0]);
        teleop.key(ms(0), Key::Up, Press);
        teleop.key(ms(0), Key::Left, Press);
        assert_eq!(teleop.request(ms(0)), (1.0, 1.0));
        let steps: Vec<f64> = (0..11).map(|_| teleop.slower()).collect();
        assert_eq!(steps, [0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1, 0.1, 0.1]);
        assert_eq!(teleop.scale(), 0.1);
        assert_eq!(teleop.request(ms(0)), (0.1, 0.1));
    }

    #[test]
    fn release_all_drops_every_key_until_pressed_again() {
        let mut teleop = Teleop::new(ReleaseMode::Events);
        teleop.key(ms(0), Key::Up, Press);
        teleop.key(ms(0), Key::Right, Press);
        teleop.release_all();
        assert_eq!(teleop.request(ms(1)), (0.0, 0.0));
        assert!(teleop.held(ms(1)).is_empty());
        teleop.key(ms(600), Key::Up, Repeat);
        assert_eq!(teleop.request(ms(600)), (0.0, 0.0), "a repeat does not revive the key");
        teleop.key(ms(700), Key::Up, Press);
        assert_eq!(teleop.held(ms(700)), vec![Key::Up]);

        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let events = legacy_hold(Key::Down, 0, 250, 90, 1000);
        trace(&mut teleop, &events, 1000);
        teleop.release_all();
        assert_eq!(teleop.request(ms(1000)), (0.0, 0.0));
        assert_eq!(teleop.learned(), (ms(250), ms(90)), "release_all keeps what was learned");
        // The next byte is a new press: held for the first deadline.
        teleop.key(ms(1050), Key::Down, Press);
        assert_eq!(teleop.request(ms(1362)), (-0.3, 0.0));
        assert_eq!(teleop.request(ms(1363)), (0.0, 0.0));
    }

    #[test]
    fn window_median_keeps_the_latest_samples() {
        let mut window = Window::<3>::default();
        assert_eq!(window.median(), None);
        window.push(ms(5));
        window.push(ms(1));
        assert_eq!(window.median(), Some(ms(5)), "upper median of two");
        window.push(ms(3));
        assert_eq!(window.median(), Some(ms(3)));
        window.push(ms(9));
        window.push(ms(8));
        assert_eq!(window.median(), Some(ms(8)), "3, 9, 8");
    }

    #[test]
    fn diagonal_keys_drive_arcs_like_teleop_twist_keyboard() {
        let cases = [
            (Key::ForwardLeft, (0.3, 0.3)),
            (Key::ForwardRight, (0.3, -0.3)),
            (Key::BackLeft, (-0.3, -0.3)),
            (Key::BackRight, (-0.3, 0.3)),
        ];
        for (key, want) in cases {
            let mut teleop = Teleop::new(ReleaseMode::Deadline);
            // Held on a legacy terminal (tmux): one key repeats, and it drives both axes all along.
            let events = legacy_hold(key, 0, 500, 33, 1500);
            let last = last_time(&events);
            let trace = trace(&mut teleop, &events, 2000);
            assert_driving(&trace, 0, last, want);
            assert_eq!(first_zero_after(&trace, last) - last, 103, "{key:?}");
        }
        // A diagonal and an arrow add up, each axis within the scale; opposite ones cancel.
        let mut teleop = Teleop::new(ReleaseMode::Events);
        teleop.key(ms(0), Key::ForwardLeft, Press);
        teleop.key(ms(0), Key::Up, Press);
        assert_eq!(teleop.request(ms(1)), (0.3, 0.3));
        teleop.key(ms(2), Key::BackLeft, Press);
        assert_eq!(teleop.request(ms(3)), (0.3, 0.0));
        assert_eq!(teleop.held(ms(3)), vec![Key::Up, Key::ForwardLeft, Key::BackLeft]);
    }

    #[test]
    fn events_combination_stays_held_while_only_the_last_key_repeats() {
        // kitty: Up pressed and repeating; Left pressed at 600 and only Left repeats from then on (the terminal
        // repeats the last key); Up is released at 2500, Left at 3000.
        let mut teleop = Teleop::new(ReleaseMode::Events);
        let mut events = vec![(0, Key::Up, Press)];
        events.extend((0..3).map(|i| (500 + i * 33, Key::Up, Repeat)));
        events.push((600, Key::Left, Press));
        events.extend((0..50).map(|i| (1100 + i * 33, Key::Left, Repeat)));
        events.push((2500, Key::Up, Release));
        events.extend((50..57).map(|i| (1100 + i * 33, Key::Left, Repeat)));
        events.push((3000, Key::Left, Release));
        events.sort_by_key(|event| event.0);
        let trace = trace(&mut teleop, &events, 3500);
        assert_driving(&trace, 0, 599, (0.3, 0.0));
        // Before: Up expired 500 ms after its last repeat (566 + 500) and the arc became a spin.
        assert_driving(&trace, 600, 2499, (0.3, 0.3));
        assert_driving(&trace, 2500, 2999, (0.0, 0.3));
        assert_driving(&trace, 3000, 3500, (0.0, 0.0));
    }

    #[test]
    fn events_combination_without_events_expires_as_a_lost_release() {
        // Up+Left, then Left released: Up no longer repeats and its release may be lost: it stops 500 ms after
        // the last event of any key, and a press drives again.
        let mut teleop = Teleop::new(ReleaseMode::Events);
        let events = [(0, Key::Up, Press), (100, Key::Left, Press), (900, Key::Left, Release)];
        let trace = trace(&mut teleop, &events, 2000);
        assert_driving(&trace, 100, 899, (0.3, 0.3));
        assert_driving(&trace, 900, 1399, (0.3, 0.0));
        assert_driving(&trace, 1400, 2000, (0.0, 0.0));
        teleop.key(ms(2000), Key::Up, Press);
        assert_eq!(teleop.request(ms(2000)), (0.3, 0.0));
    }

    /// A held key on a jittery link: a byte every `interval` ms, and delivery pausing for `pause` ms every
    /// `every` ms (the repeats of the pause come in a burst right after it, 1 ms apart).
    fn jittery_hold(key: Key, start: u64, stop: u64, interval: u64, pause: u64, every: u64) -> Vec<Event> {
        let mut events = vec![(start, key, Press)];
        let mut t = start + interval;
        let mut next_pause = start + every;
        while t <= stop {
            if t >= next_pause {
                let resume = next_pause + pause;
                let mut burst = resume;
                while t < resume {
                    events.push((burst, key, Press));
                    burst += 1;
                    t += interval;
                }
                next_pause += every;
                continue;
            }
            events.push((t, key, Press));
            t += interval;
        }
        events
    }

    /// The sender's frames for a trace: every 20 ms, and at once when the target changes (the dashboard
    /// kicks the sender on a change), each a ramp step over the time since the previous frame. Returns
    /// (ms, linear m/s) per frame.
    fn frames(trace: &[(f64, f64)], limits: &crate::control::Limits) -> Vec<(u64, f64)> {
        let mut frames = vec![];
        let (mut sent, mut last_frame, mut last_target) = ((0.0, 0.0), 0u64, (0.0, 0.0));
        for (t, &request) in trace.iter().enumerate() {
            let t = t as u64;
            let target = (request.0 * limits.max_linear, request.1 * limits.max_angular);
            if t > 0 && (t - last_frame >= 20 || target != last_target) {
                sent = crate::control::ramp_step(sent, target, limits, ms(t - last_frame));
                frames.push((t, sent.0));
                last_frame = t;
            }
            last_target = target;
        }
        frames
    }

    /// (dips, ms from the last key to the first zero frame) of a jittery 33 ms hold of `hold_ms`.
    fn jittery_run(teleop: &mut Teleop, hold_ms: u64) -> (Vec<(u64, f64)>, u64) {
        let limits = crate::control::Limits::default();
        let events = jittery_hold(Key::Up, 0, hold_ms, 33, 150, 800);
        let last = last_time(&events);
        let trace = trace(teleop, &events, last + 600);
        let frames = frames(&trace, &limits);
        let cruise = 0.3 * limits.max_linear;
        // Once up to speed after the first pause (0.8 s), every frame until the last key is at cruise speed.
        let dips: Vec<(u64, f64)> = frames
            .iter()
            .filter(|(t, v)| (1200..=last).contains(t) && (*v - cruise).abs() > 1e-9)
            .copied()
            .collect();
        let zero = frames.iter().find(|(t, v)| *t > last && *v == 0.0).expect("stops").0;
        (dips, zero - last)
    }

    /// The jittery-link bench (docs/troubleshooting.md quotes its figures): holding Up on a 33 ms terminal
    /// whose delivery pauses 150 ms every 0.8 s, through the sender's ramp (default limits: 1.5 m/s² braking).
    #[test]
    fn jittery_link_neither_stutters_nor_releases_late() {
        // The old fixed deadline (2.5 intervals + 20 ms, as --key-timeout 103ms): a dip at every pause.
        let mut fixed =
            Teleop::new(ReleaseMode::Deadline).with_key_timeout(Some(Duration::from_micros(102_500)));
        let (dips, latency) = jittery_run(&mut fixed, 5000);
        // 59 of the frames from 1.2 s to the last key are below cruise speed; zero 163 ms after the last key.
        assert_eq!((dips.len(), latency), (59, 163));
        assert!(dips.iter().any(|(_, v)| *v < 0.1), "the old deadline stutters: {dips:?}");
        // Learned: the first pause (at 0.8 s, before cruising) teaches the late gap; no later pause dips.
        let mut learned = Teleop::new(ReleaseMode::Deadline);
        let (dips, latency) = jittery_run(&mut learned, 5000);
        assert_eq!(dips, vec![], "no stutter once learned");
        assert_eq!(learned.deadlines().1, ms(192), "the longest gap (182 ms) + 10 ms");
        assert_eq!(latency, 292, "zero within 300 ms of the last key");
        // A smooth link keeps the quick release: the pauses age out of the window.
        let events = legacy_hold(Key::Up, 7000, 500, 33, 10_000);
        trace_span(&mut learned, &events, 7000, 10_000);
        assert_eq!(learned.deadlines().1, Duration::from_micros(102_500));
    }

    #[test]
    fn a_late_repeat_counts_only_when_the_stream_goes_on_after_it() {
        // Repeating at 33 ms; a 230 ms gap, then the terminal's 500 ms delay: a release and a new press, not
        // a late repeat. The deadline stays the steady one.
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        let mut events = legacy_hold(Key::Up, 0, 500, 33, 1500);
        let last = last_time(&events);
        events.extend(legacy_hold(Key::Up, last + 230, 500, 33, 3000));
        trace(&mut teleop, &events, 3000);
        assert_eq!(teleop.deadlines().1, Duration::from_micros(102_500));
        // A 230 ms gap after which the repeats go on at 33 ms: a late repeat, learned (230 + 10 ms).
        let mut events = legacy_hold(Key::Up, 4000, 500, 33, 5000);
        let last = last_time(&events);
        events.extend(legacy_hold(Key::Up, last + 230, 33, 33, 6000));
        trace_span(&mut teleop, &events, 4000, 6000);
        assert_eq!(teleop.deadlines().1, ms(240));
        // Bunched bytes (under 10 ms apart) after the gap do not hide it; a gap over 250 ms is a stall.
        let mut events = vec![];
        events.extend(legacy_hold(Key::Down, 8000, 500, 33, 8600));
        events.extend([(8835, Key::Down, Press), (8836, Key::Down, Press), (8869, Key::Down, Press)]);
        events.extend(legacy_hold(Key::Down, 9000, 33, 33, 9300));
        let mut fresh = Teleop::new(ReleaseMode::Deadline);
        trace_span(&mut fresh, &events, 8000, 9300);
        assert_eq!(fresh.deadlines().1, ms(246), "the 236 ms gap before the burst + 10 ms");
        let mut stalled = Teleop::new(ReleaseMode::Deadline);
        let mut events = legacy_hold(Key::Down, 0, 500, 33, 600);
        events.extend(legacy_hold(Key::Down, 900, 33, 33, 1300));
        trace(&mut stalled, &events, 1300);
        assert_eq!(stalled.deadlines().1, Duration::from_micros(102_500), "a 306 ms stall is not learned");
    }

    #[test]
    fn key_timeout_overrides_the_learned_deadline() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline).with_key_timeout(Some(ms(300)));
        let events = legacy_hold(Key::Up, 0, 250, 90, 1000);
        let last = last_time(&events);
        let trace = trace(&mut teleop, &events, 2000);
        assert_driving(&trace, 0, last, (0.3, 0.0));
        assert_eq!(first_zero_after(&trace, last) - last, 300);
        assert_eq!(teleop.learned(), (ms(250), ms(90)), "still learned, for the screen");
        assert_eq!(teleop.deadlines(), (ms(312) + Duration::from_micros(500), ms(300)));
        // The first deadline is at least the timeout; out-of-range values are clamped.
        let teleop = Teleop::new(ReleaseMode::Deadline).with_key_timeout(Some(ms(1000)));
        assert_eq!(teleop.deadlines(), (ms(1000), ms(1000)));
        let teleop = Teleop::new(ReleaseMode::Deadline).with_key_timeout(Some(ms(5)));
        assert_eq!(teleop.deadlines(), (ms(700), KEY_TIMEOUT_MIN));
        assert_eq!(teleop.key_timeout(), Some(KEY_TIMEOUT_MIN));
    }

    #[test]
    fn next_expiry_is_the_earliest_hold_ending() {
        let mut teleop = Teleop::new(ReleaseMode::Deadline);
        assert_eq!(teleop.next_expiry(ms(0)), None);
        teleop.key(ms(0), Key::Up, Press);
        teleop.key(ms(100), Key::Left, Press);
        assert_eq!(teleop.next_expiry(ms(100)), Some(ms(700)));
        assert_eq!(teleop.next_expiry(ms(700)), Some(ms(800)));
        assert_eq!(teleop.next_expiry(ms(800)), None);
    }

    mod props {
        use super::*;
        use proptest::collection::vec;
        use proptest::prelude::*;

        fn key() -> impl Strategy<Value = Key> {
            (0..KEYS).prop_map(|index| Key::ALL[index])
        }

        fn action() -> impl Strategy<Value = KeyAction> {
            prop_oneof![4 => Just(Press), 4 => Just(Repeat), 1 => Just(Release)]
        }

        fn mode() -> impl Strategy<Value = ReleaseMode> {
            prop_oneof![Just(ReleaseMode::Events), Just(ReleaseMode::Deadline)]
        }

        proptest! {
            /// For any event stream, the request stays within the scale, and no key counts as held more
            /// than `FIRST_DEADLINE_MAX` after its last Press/Repeat (in `Events` mode: after the last event
            /// of any key, which keeps a combination held), so the request is zero that long after the last
            /// event.
            #[test]
            fn request_is_bounded_and_expires(
                mode in mode(),
                steps in vec((0u64..1500, key(), action(), -1i8..=1), 1..80),
            ) {
                let mut teleop = Teleop::new(mode);
                let mut now = 0;
                let mut last_byte = [None::<u64>; KEYS];
                let mut last_event = None::<u64>;
                let check = |teleop: &Teleop, t: u64, last_byte: &[Option<u64>; KEYS], last_event: Option<u64>| {
                    let (linear, angular) = teleop.request(ms(t));
                    let scale = teleop.scale();
                    prop_assert!(linear.abs() <= scale && angular.abs() <= scale && scale <= 1.0);
                    for key in teleop.held(ms(t)) {
                        let last = match mode {
                            ReleaseMode::Deadline => last_byte[key.index()],
                            ReleaseMode::Events => last_event,
                        };
                        prop_assert!(last.is_some_and(|at| t < at + 1250), "{key:?} held at {t}");
                    }
                    Ok(())
                };
                for (gap, key, action, scale) in steps {
                    for t in [now + gap / 3, now + gap / 2, now + gap - gap.min(1)] {
                        check(&teleop, t, &last_byte, last_event)?;
                    }
                    now += gap;
                    match scale {
                        1 => { teleop.faster(); }
                        -1 => { teleop.slower(); }
                        _ => {}
                    }
                    teleop.key(ms(now), key, action);
                    if action != Release {
                        last_byte[key.index()] = Some(now);
                    }
                    last_event = Some(now);
                    check(&teleop, now, &last_byte, last_event)?;
                }
                prop_assert_eq!(teleop.request(ms(now) + FIRST_DEADLINE_MAX), (0.0, 0.0));
                prop_assert!(teleop.held(ms(now) + FIRST_DEADLINE_MAX).is_empty());
            }

            /// A steady legacy terminal (any delay up to 660 ms, any interval up to 100 ms, a few ms of
            /// jitter) never stutters while a key is held, and after the first hold a release is seen within
            /// the learned repeat deadline (at most 250 ms).
            #[test]
            fn steady_terminal_never_stutters(
                delay in 150u64..=660,
                interval in 10u64..=100,
                jitter in vec(0u64..=4, 64),
                holds in vec((key(), 1u64..=40, 300u64..=2000), 1..5),
            ) {
                let mut teleop = Teleop::new(ReleaseMode::Deadline);
                let mut start = 0;
                for (hold, &(key, repeats, pause)) in holds.iter().enumerate() {
                    let mut events = vec![(start, key, Press)];
                    for i in 0..repeats {
                        let t = start + delay + i * interval + jitter[i as usize % jitter.len()];
                        events.push((t.max(last_time(&events)), key, Press));
                    }
                    let last = last_time(&events);
                    let end = last + 250 + pause;
                    let trace = trace_span(&mut teleop, &events, start, end);
                    let at = |t: u64| trace[(t - start) as usize];
                    for t in start..=last {
                        prop_assert_ne!(at(t), (0.0, 0.0), "hold {} at {}", hold, t);
                    }
                    let latency = (last..=end).find(|&t| at(t) == (0.0, 0.0)).map(|t| t - last);
                    let (_, repeat_deadline) = teleop.deadlines();
                    let limit = repeat_deadline.as_millis() as u64 + 1;
                    prop_assert!(latency.is_some_and(|l| l <= limit && l <= 250), "hold {hold}: {latency:?}");
                    start = end;
                }
            }
        }
    }
}
