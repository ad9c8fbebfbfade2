//! The streaming analysis: observations go into bounded queues; a stretch is analysed at once when the
//! robot is back at rest (or commands have long ceased), and only what precedes it is kept as context.
//!
//! Those rests are what make a log's chunks mergeable exactly (`decode -j N --summary`): at a rest the
//! state depends only on the last [`CONTEXT_US`] of observations, so a chunk's analyzer that has seen that
//! much before its first rest is, from there on, in the very state a single pass would be in. A chunk's
//! analyzer ([`Analyzer::partial`]) therefore keeps its raw observations up to its first rest, and the merge
//! ([`Analyzer::absorb`]) replays them into the analyzer before it, then takes over the chunk's state and
//! appends what the chunk found after its first rest. Sums are kept in integers, so they add up exactly
//! in any grouping.

use super::sample::Sample;
use super::segment::{analyse, Found, HOLD_US};
use super::series::Series;
use super::Report;

/// A zero command held this long with the robot still (within [`QUIET`]) is a rest, µs ...
const REST_HOLD_US: i64 = HOLD_US;
/// ... or held this long with the robot within [`NEARLY_STILL`] (a creep, a sensor that never reads 0).
const SLOW_REST_HOLD_US: i64 = 3 * HOLD_US;
/// Measured (linear mm/s, angular mrad/s) within these is still: the least noise threshold of the stop's
/// analysis (2 quanta), so a rest never cuts a stop before its standstill (a long lag's creep).
const QUIET: (i32, i32) = (2, 2);
const NEARLY_STILL: (i32, i32) = (20, 50);
/// No command frame for this long is a rest too (commands ceased; the robot's own stop is over), µs.
const CEASED_US: i64 = 2_500_000;
/// What a stretch keeps of the time before it (the level before a step, the start of a load step), µs.
const CONTEXT_US: i64 = 400_000;
/// A stamp at most this far before the last one is taken as simultaneous with it, µs: a live recording
/// stamps a sent frame when it leaves and a received one when it arrived, so the two clocks of one ordered
/// log cross by a few µs (and a log merged from two interfaces by more).
const JITTER_US: i64 = 20_000;
/// A time going further backwards, or a gap this long between observations, starts afresh, µs.
const GAP_US: i64 = 1_000_000;
/// Times are held within ±this, µs (73,000 years): any difference of two times, and a time plus or minus
/// any span of the analysis, then fits in an `i64` (a log's stamps can be anything).
const TIME_LIMIT_US: i64 = 1 << 61;
/// A chunk's analyzer keeps at most this many observations before its first rest; beyond, it cannot be
/// merged and the chunk is analysed again in order.
const MAX_PENDING: usize = 1 << 17;

/// The state between observations.
#[derive(Clone, Debug, Default)]
struct State {
    series: Series,
    /// The current stretch started here: earlier observations are its context.
    stretch_start: i64,
    /// The stretch holds a command change or a non-zero command: worth analysing.
    active: bool,
    command: Option<(i32, i32)>,
    command_since: i64,
    last_command_at: Option<i64>,
    /// The first observation since the start (or a fresh start).
    view_start: Option<i64>,
    last_time: Option<i64>,
}

/// Why a stretch ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Rest {
    /// A zero command held, the robot at rest.
    Stopped,
    /// No command frame for [`CEASED_US`].
    Ceased,
}

/// A chunk's observations up to its first rest.
#[derive(Clone, Debug, Default)]
struct Pending {
    samples: Vec<(i64, Sample)>,
    overflowed: bool,
    rested: bool,
}

/// The streaming analysis.
#[derive(Clone, Debug, Default)]
pub struct Analyzer {
    state: State,
    found: Found,
    /// Some for one chunk of a log (see the module's documentation).
    pending: Option<Pending>,
}

impl Analyzer {
    pub fn new() -> Self {
        Self::default()
    }

    /// One message at `time_us` (µs of the run's clock), in time order. Messages the analysis does not use
    /// cost one match; nothing is allocated except when a result is recorded.
    #[inline]
    pub fn observe(&mut self, time_us: i64, message: &crate::protocol::message::Message) {
        if let Some(sample) = Sample::of(message) {
            self.observe_sample(time_us.clamp(-TIME_LIMIT_US, TIME_LIMIT_US), sample);
        }
    }

    /// What has been found so far (the stretch under way included).
    pub fn report(&self) -> Report {
        let mut found = self.found.clone();
        let mut state = self.state.clone();
        if state.active {
            if let Some(end) = state.last_time {
                analyse(&state.series.view(), state.stretch_start, end, &mut found);
            }
        }
        Report::from_found(&found)
    }

    /// An analyzer for one chunk of a log, to be merged with [`Self::absorb`].
    pub fn partial() -> Self {
        Self { pending: Some(Pending::default()), ..Self::default() }
    }

    /// Whether [`Self::absorb`] merges `later` exactly: not when it kept too many observations before its
    /// first rest.
    pub fn can_absorb(&self, later: &Self) -> bool {
        later.pending.as_ref().is_none_or(|pending| !pending.overflowed)
    }

    /// The analyzer of the next chunk, merged as if its observations had come here one by one.
    pub fn absorb(&mut self, later: &Self) {
        let Some(pending) = &later.pending else {
            self.found.absorb(&later.found);
            return;
        };
        for &(t, sample) in &pending.samples {
            self.observe_sample(t, sample);
        }
        if pending.rested {
            self.state.clone_from(&later.state);
            self.found.absorb(&later.found);
        }
    }

    fn observe_sample(&mut self, t: i64, sample: Sample) {
        if let Some(pending) = self.pending.as_mut().filter(|pending| !pending.rested) {
            if pending.samples.len() < MAX_PENDING {
                pending.samples.push((t, sample));
            } else {
                pending.overflowed = true;
            }
        }
        match sample {
            Sample::Command { .. } => self.found.command_frames += 1,
            Sample::Current { .. } => self.found.current_frames += 1,
            Sample::Voltage { .. } => self.found.voltage_frames += 1,
            _ => {}
        }
        // Taken as simultaneous: see `JITTER_US`.
        let t = match self.state.last_time {
            Some(last) if t < last && last - t <= JITTER_US => last,
            _ => t,
        };
        match self.state.last_time {
            Some(last) if t < last || t - last > GAP_US => self.start_afresh(t),
            None => self.start_afresh(t),
            Some(_) => {}
        }
        let state = &mut self.state;
        state.last_time = Some(t);
        let full = state.series.push(t, sample);
        if let Sample::Command { linear, angular } = sample {
            if state.command != Some((linear, angular)) {
                state.command = Some((linear, angular));
                state.command_since = t;
                state.active = true;
            }
            state.active |= linear != 0 || angular != 0;
            state.last_command_at = Some(t);
        }
        if full {
            self.end_stretch(t);
        }
        if let Some(rest) = self.rest(t, sample) {
            self.rested(t, rest);
        }
    }

    /// Whether the observation at `t` is at a rest.
    fn rest(&self, t: i64, sample: Sample) -> Option<Rest> {
        let state = &self.state;
        match sample {
            Sample::Command { linear: 0, angular: 0 } => {
                let held = t - state.command_since;
                let within = |(linear, angular): (i32, i32)| {
                    state
                        .series
                        .last_motion()
                        .is_some_and(|m| m.linear.abs() <= linear && m.angular.abs() <= angular)
                };
                let rest = (held >= REST_HOLD_US && within(QUIET))
                    || (held >= SLOW_REST_HOLD_US && within(NEARLY_STILL));
                rest.then_some(Rest::Stopped)
            }
            Sample::Command { .. } => None,
            _ => {
                let since = state.last_command_at.or(state.view_start)?;
                (t - since >= CEASED_US).then_some(Rest::Ceased)
            }
        }
    }

    // Rare (a rest, a full queue, a gap): kept out of line so the per-message path stays small.
    #[cold]
    #[inline(never)]
    fn rested(&mut self, t: i64, rest: Rest) {
        let first_of_chunk = self.pending.as_ref().is_some_and(|pending| !pending.rested);
        // A chunk's first rest counts only once it has seen all the context a single pass would keep.
        if first_of_chunk && self.state.view_start.is_none_or(|start| start >= t - CONTEXT_US) {
            return;
        }
        self.end_stretch(t);
        let state = &mut self.state;
        // What is left is the same whatever came before the rest: held as long as any rest needs, so the next
        // still sample is a rest again however long the zero command really was held.
        match rest {
            Rest::Stopped => state.command_since = t - SLOW_REST_HOLD_US,
            Rest::Ceased => {
                state.command = None;
                state.last_command_at = None;
                state.view_start = Some(t - CEASED_US);
            }
        }
        if let Some(pending) = self.pending.as_mut().filter(|_| first_of_chunk) {
            pending.rested = true;
            // Found before this rest without the chunk's past: the merge finds it again from the samples.
            self.found = Found::default();
        }
    }

    /// Analyses the stretch up to `t` and keeps only its context.
    // Rare (a rest, a full queue, a gap): kept out of line so the per-message path stays small.
    #[cold]
    #[inline(never)]
    fn end_stretch(&mut self, t: i64) {
        let state = &mut self.state;
        if state.active {
            analyse(&state.series.view(), state.stretch_start, t, &mut self.found);
        }
        state.active = false;
        state.stretch_start = t;
        state.series.keep_from(t - CONTEXT_US);
    }

    /// Time went backwards or paused: what is under way is analysed up to the last observation, then
    /// everything starts again at `t`.
    // Rare (a rest, a full queue, a gap): kept out of line so the per-message path stays small.
    #[cold]
    #[inline(never)]
    fn start_afresh(&mut self, t: i64) {
        let state = &mut self.state;
        if let (true, Some(end)) = (state.active, state.last_time) {
            analyse(&state.series.view(), state.stretch_start, end, &mut self.found);
        }
        state.series.clear();
        *state = State {
            series: std::mem::take(&mut state.series),
            stretch_start: t,
            view_start: Some(t),
            ..State::default()
        };
    }
}
