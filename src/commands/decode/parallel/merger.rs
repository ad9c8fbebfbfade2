//! This thread's side of `decode -j`: the chunks back in input order, settled, written and counted into the
//! [`Decoder`] as if one thread had decoded them.

use std::collections::BTreeMap;
use std::io;
use std::sync::mpsc::{self, RecvTimeoutError};

use anyhow::{bail, Result};
use parking_lot::Mutex;

use super::super::damaged::Reached;
use super::super::written::Interrupted;
use super::super::{Decoder, Sink};
use super::settings::{Settings, Start};
use super::worker::{decode_chunk, settle, Chunk, Events, Outcome, Stamp};
use super::WAKE;
use crate::candump::{CarriedState, DeltaSum, LineParser, Rejected, Rejection};
use crate::exit::Failure;
use crate::output::{Event, FrameRef};

/// This thread's side: chunks back in order, merged into the decoder.
pub(super) struct Merger<'a> {
    pub decoder: &'a mut Decoder,
    pub name: &'a str,
    pub settings: &'a Settings,
    pub guess: &'a Mutex<Start>,
    pub size: Option<u64>,
    /// The lines of the inputs before this one: a chunk's first line number counts from this input's start.
    pub lines_before: u64,
    /// `-t d`: the sum of the deltas of the chunks merged so far.
    pub deltas: DeltaSum,
}

impl Merger<'_> {
    pub fn run(mut self, done: &mpsc::Receiver<Chunk>, pool: &mpsc::Sender<Chunk>) -> Result<()> {
        let bar = self.decoder.progress_bar(self.size);
        let mut waiting = BTreeMap::new();
        let mut carried = LineParser::for_format(self.settings.format).carried();
        let (mut next, mut consumed) = (0u64, 0u64);
        // A plain file's last range reads on to the end: until it is merged, the file is not.
        let mut reached_end = self.settings.ranges.is_none();
        loop {
            let chunk = match done.recv_timeout(WAKE) {
                Ok(chunk) => chunk,
                Err(RecvTimeoutError::Timeout) if self.decoder.signals.received().is_some() => {
                    return Err(io::Error::other(Interrupted).into());
                }
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => break,
            };
            waiting.insert(chunk.index, chunk);
            while let Some(mut chunk) = waiting.remove(&next) {
                if self.decoder.signals.received().is_some() {
                    return Err(io::Error::other(Interrupted).into());
                }
                self.merge(&mut chunk, &mut carried)?;
                reached_end |= chunk.range.is_some_and(|range| range.end.is_none());
                consumed += chunk.text.bytes;
                if let Some(bar) = &bar {
                    bar.set_position(consumed);
                }
                next += 1;
                let _ = pool.send(chunk);
            }
        }
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
        // Every worker ended: a chunk that never came back would leave the ones after it here, and the
        // input's tail unsaid. Never seen; said, should it happen, rather than lost.
        if !waiting.is_empty() || !reached_end {
            let after = waiting.len();
            bail!(
                "internal error: chunk {next} of {} was lost ({after} decoded after it not written)",
                self.name
            );
        }
        Ok(())
    }

    /// One chunk, in order: decoded again if its start was guessed wrong, then written and counted.
    fn merge(&mut self, chunk: &mut Chunk, carried: &mut CarriedState) -> Result<()> {
        let detector = &self.decoder.detector;
        let truth = Start {
            carried: carried.clone(),
            v1_seen: detector.v1_frames > 0,
            v2_seen: detector.v2_frames > 0,
        };
        settle(self.settings, chunk, &truth);
        if let (Sink::Lines { output, .. }, Some(_)) = (&self.decoder.sink, self.settings.writer) {
            output.borrow_mut().write_through(&chunk.output)?;
        }
        if self.settings.partial {
            self.absorb(chunk, &truth)?;
        }
        if self.settings.record {
            self.replay(&chunk.events)?;
            if let (Sink::Lines { output, .. }, None) = (&self.decoder.sink, self.settings.writer) {
                // Lines this thread wrote (-t d) leave with their chunk, as a live stream's must.
                output.borrow_mut().flush()?;
            }
        }
        let decoder = &mut *self.decoder;
        // Line numbers count within this input, as one thread's reader counts them.
        let base = decoder.stats.lines - self.lines_before;
        let outcome = &chunk.outcome;
        let stats = &mut decoder.stats;
        stats.lines += outcome.lines;
        stats.frames += outcome.frames;
        stats.decoded_lines += outcome.decoded_lines;
        stats.rejected_lines += outcome.rejected_lines;
        stats.invalid_frames += outcome.invalid_frames;
        stats.candump_dropped = stats.candump_dropped.saturating_add(outcome.candump_dropped);
        let (skipped, more) = (&mut stats.skipped, &outcome.skipped);
        skipped.blank += more.blank;
        skipped.comment += more.comment;
        skipped.error_text += more.error_text;
        skipped.can_xl += more.can_xl;
        skipped.dropcount += more.dropcount;
        decoder.detector.v1_frames += outcome.v1_frames;
        decoder.detector.v2_frames += outcome.v2_frames;
        self.tally(base, outcome);
        *carried = outcome.end.clone();
        // The next chunks' guess: the settled verdict and interface; an error frame rarely ends a chunk.
        let detector = &self.decoder.detector;
        let mut guess = self.guess.lock();
        *guess = Start {
            carried: CarriedState { after_error_frame: false, ..carried.clone() },
            // A worker may have seen further ahead (see publish_verdict).
            v1_seen: detector.v1_frames > 0 || guess.v1_seen,
            v2_seen: detector.v2_frames > 0 || guess.v2_seen,
        };
        drop(guess);
        if let Some(stop) = &outcome.stop {
            let message = match stop.line {
                Some(line) => format!("{}:{}: {}", self.name, base + line, stop.message),
                None => stop.message.clone(),
            };
            return Err(Failure::data(message).into());
        }
        match chunk.text.read_error.take() {
            Some(error) => {
                let lines = self.decoder.stats.lines - self.lines_before;
                self.decoder.read_failed(
                    self.name,
                    error,
                    Reached { lines, unfinished: chunk.text.unfinished },
                )
            }
            None => Ok(()),
        }
    }

    /// The chunk's partial summary merged into the run's; one that cannot be merged exactly (see
    /// [`Summary::can_absorb`]: rare) is decoded again here into events and replayed.
    fn absorb(&mut self, chunk: &mut Chunk, truth: &Start) -> Result<()> {
        if let Sink::Summary(summary) = &mut self.decoder.sink {
            if summary.can_absorb(&chunk.summary) {
                summary.absorb(&chunk.summary);
                return Ok(());
            }
        }
        let settings =
            Settings { record: true, partial: false, summary_only: false, ..self.settings.clone() };
        decode_chunk(&settings, truth, chunk);
        self.replay(&chunk.events)
    }

    /// The chunk's events, delivered as one thread delivers them (the workers counted and filtered them).
    fn replay(&mut self, events: &Events) -> Result<()> {
        let decoder = &mut *self.decoder;
        let workers_wrote = self.settings.writer.is_some();
        // Events nearly all share one interface: its name is looked up when it changes.
        let (mut named, mut name) = (u32::MAX, "");
        for replay in &events.list {
            if replay.iface != named {
                (named, name) = (replay.iface, events.name(replay.iface));
            }
            let ts = match replay.stamp {
                Stamp::Given(ts) => ts,
                Stamp::Summed(sum) => Some({ self.deltas }.add(sum.secs, sum.nanos)),
            };
            let frame = FrameRef::Can(&replay.frame);
            let event = Event { ts, iface: name, dir: replay.dir, frame, decoded: replay.decoded };
            match &mut decoder.sink {
                Sink::Summary(summary) => summary.event(&event),
                // The workers wrote the output: only the plot is left.
                Sink::Lines { .. } if workers_wrote => {}
                // MCAP: the workers parse and decode, this thread writes the container (and the plot).
                Sink::Lines { .. } | Sink::Mcap(_) => {
                    decoder.deliver(&event)?;
                    continue;
                }
            }
            if let Some(plot) = &mut decoder.plot {
                plot.event(&event);
            }
        }
        let sum = events.deltas.total();
        self.deltas.add(sum.secs, sum.nanos);
        Ok(())
    }

    /// The chunk's rejections, said and counted as if they had come one by one.
    fn tally(&mut self, base: u64, outcome: &Outcome) {
        let tally = &mut self.decoder.stats.rejected;
        for reject in &outcome.shown {
            let location = format!("{}:{}", self.name, base + reject.line);
            let (message, reason, length) = (reject.message.as_str(), reject.reason, reject.length);
            if let Some(note) =
                tally.reject(Rejected { location: &location, message, reason, length, in_lines: true })
            {
                crate::say!("tracerctl: {note}");
            }
        }
        // Past the shown ones nothing more is said: only the counts, longest lines and first places.
        for reject in &outcome.counted {
            match tally.rejected.iter_mut().find(|known| known.reason == reject.reason) {
                Some(known) => {
                    known.count += reject.count;
                    known.longest = known.longest.max(reject.length);
                }
                None => tally.rejected.push(Rejection {
                    reason: reject.reason.to_string(),
                    count: reject.count,
                    first_at: format!("{}:{}", self.name, base + reject.line),
                    longest: reject.length,
                    in_lines: true,
                }),
            }
        }
    }
}
