//! A candump log played back as a read-only link, paced by its timestamps.

use std::fs::File;
use std::io::{self, Read};
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{FrameRx, FrameTx, Link, LinkFrame, LinkKind, Received, RxStats};
use crate::candump::{self, Line, LineParser, LineReader, RawLine, Reason, RejectTally, Rejected, Timestamp};
use crate::protocol::Wire;

struct ReadOnly;

impl FrameTx for ReadOnly {
    fn send(&self, _frame: &LinkFrame) -> io::Result<()> {
        Err(io::Error::new(io::ErrorKind::Unsupported, "a --replay source is read-only: nothing can be sent"))
    }
}

struct ReplayRx {
    reader: LineReader<Box<dyn Read + Send>>,
    parser: LineParser,
    speed: f64,
    /// Wall-clock start and the log time it corresponds to.
    origin: Option<(Instant, Timestamp)>,
    pending: Option<Received>,
    stats: RxStats,
    /// The log's path, for `file:line` in messages.
    name: String,
    lines: u64,
    rejected: RejectTally,
    /// Messages about rejected lines not yet taken by the owner (at most the tally's first few).
    notes: Vec<String>,
}

fn nanos(ts: &Timestamp) -> u128 {
    u128::from(ts.secs) * 1_000_000_000 + u128::from(ts.nanos)
}

impl ReplayRx {
    /// The next frame of the log, skipping non-frame lines (bad lines are counted, the first few noted).
    fn next_frame(&mut self) -> io::Result<Option<Received>> {
        loop {
            let Some(raw) = self.reader.next_line()? else { return Ok(None) };
            self.lines += 1;
            self.stats.replayed_lines += 1;
            let (number, text) = match raw {
                RawLine::Line { number, text } => (number, text),
                RawLine::TooLong { number, len } => {
                    let message = candump::line_too_long(len);
                    self.reject(number, &message, Reason::LineTooLong.as_str(), Some(len as u64));
                    continue;
                }
            };
            match self.parser.parse(text) {
                Ok(Line::Frame(record)) => {
                    let ts = record.ts.unwrap_or_else(super::now_timestamp);
                    return Ok(Some(Received { ts, frame: LinkFrame::Can(record.frame) }));
                }
                Ok(_) => {}
                Err(error) => self.reject(number, &error.to_string(), error.reason.as_str(), None),
            }
        }
    }

    fn reject(&mut self, number: u64, message: &str, reason: &str, length: Option<u64>) {
        self.stats.rejected_lines += 1;
        let location = format!("{}:{number}", self.name);
        let rejected = Rejected { location: &location, message, reason, length, in_lines: true };
        if let Some(note) = self.rejected.reject(rejected) {
            self.notes.push(note);
        }
    }
}

impl FrameRx for ReplayRx {
    fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>> {
        if self.pending.is_none() {
            self.pending = self.next_frame()?;
        }
        let Some(next) = self.pending else {
            return Err(io::Error::new(io::ErrorKind::UnexpectedEof, "end of the replayed log"));
        };
        let (start, log_start) = *self.origin.get_or_insert((Instant::now(), next.ts));
        if self.speed > 0.0 {
            let offset = nanos(&next.ts).saturating_sub(nanos(&log_start)) as f64 / self.speed;
            let due = start + Duration::from_nanos(offset.min(u64::MAX as f64) as u64);
            let now = Instant::now();
            if due > now {
                let wait = due - now;
                if wait > timeout {
                    std::thread::sleep(timeout);
                    return Ok(None);
                }
                std::thread::sleep(wait);
            }
        }
        self.pending = None;
        self.stats.frames += 1;
        Ok(Some(next))
    }

    fn stats(&self) -> RxStats {
        self.stats
    }

    fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.notes)
    }

    /// `bus.log: replayed 12 frames from 40 lines; rejected 28: 28 x not a candump line (first at bus.log:1)`
    fn report(&self) -> Option<String> {
        let rejected = self.rejected.describe()?;
        Some(format!(
            "{}: replayed {} frames from {} lines; {rejected}",
            self.name, self.stats.frames, self.lines
        ))
    }
}

/// For a replayed log that gave no frame at all, the words for it (the exit status is then 3, a data error,
/// as `decode` says of a log without frames): empty, only blank lines and comments, or lines rejected.
pub fn nothing_replayed(name: &str, stats: &RxStats) -> Option<String> {
    if stats.frames > 0 {
        return None;
    }
    let why = match (stats.replayed_lines, stats.rejected_lines) {
        (0, _) => "is empty".to_string(),
        (lines, 0) => format!("has no candump frames ({lines} lines, all blank or comments)"),
        (_, rejected) => format!("has no candump frames ({rejected} lines rejected)"),
    };
    Some(format!("nothing to replay: {name} {why}"))
}

/// Opens `path` for replay at `speed` (0 = as fast as possible). Any log `decode` reads replays:
/// compressed, ASC, trc; a format it refuses is refused here too (exit 3).
pub fn open(path: &Path, speed: f64) -> anyhow::Result<Link> {
    let file =
        File::open(path).map_err(|error| anyhow::anyhow!("cannot open {}: {error}", path.display()))?;
    let name = path.display().to_string();
    let (text, format) = candump::open_log(file, &name).map_err(crate::exit::Failure::from)?;
    let rx = ReplayRx {
        reader: LineReader::new(text),
        parser: LineParser::for_format(format),
        speed,
        origin: None,
        pending: None,
        stats: RxStats::default(),
        name: path.display().to_string(),
        lines: 0,
        rejected: RejectTally::default(),
        notes: Vec::new(),
    };
    Ok(Link {
        name: path.display().to_string(),
        kind: LinkKind::Replay,
        wire: Wire::CanV2,
        tx: Arc::new(ReadOnly),
        rx: Box::new(rx),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::candump::DEFAULT_MAX_LINE_LEN;

    #[test]
    fn rejected_lines_are_noted_with_file_line_and_reason_and_totalled() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bus.log");
        let long = "1".repeat(DEFAULT_MAX_LINE_LEN + 10);
        let text = format!("{long}\nnot candump\n\n(1700000000.000000) can0 211#00000103000000B1\n");
        std::fs::write(&path, text).unwrap();
        let mut link = open(&path, 0.0).unwrap();
        let received = link.rx.recv(Duration::from_secs(1)).unwrap().unwrap();
        assert_eq!(
            received.frame,
            LinkFrame::Can(crate::protocol::CanFrame::new(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]).unwrap())
        );
        let name = path.display().to_string();
        assert_eq!(
            link.rx.take_notes(),
            [
                format!(
                    "{name}:1: line of {} bytes is too long for a candump line (limit {DEFAULT_MAX_LINE_LEN} bytes)",
                    DEFAULT_MAX_LINE_LEN + 10
                ),
                format!("{name}:2: column 1: not a candump line"),
            ]
        );
        assert!(link.rx.take_notes().is_empty(), "taken once");
        assert_eq!(link.rx.stats().rejected_lines, 2);
        assert_eq!(
            link.rx.report().unwrap(),
            format!(
                "{name}: replayed 1 frames from 4 lines; rejected 2: 1 x line too long (longest 65546 bytes; first at {name}:1); \
                 1 x not a candump line (first at {name}:2)"
            )
        );
        let end = link.rx.recv(Duration::from_secs(1)).unwrap_err();
        assert_eq!(end.kind(), io::ErrorKind::UnexpectedEof);
        assert_eq!(nothing_replayed(&name, &link.rx.stats()), None, "a frame was replayed");
        let stats = RxStats { rejected_lines: 3, replayed_lines: 5, ..RxStats::default() };
        assert_eq!(
            nothing_replayed("x.log", &stats).unwrap(),
            "nothing to replay: x.log has no candump frames (3 lines rejected)"
        );
        let stats = RxStats { replayed_lines: 2, ..RxStats::default() };
        assert_eq!(
            nothing_replayed("x.log", &stats).unwrap(),
            "nothing to replay: x.log has no candump frames (2 lines, all blank or comments)"
        );
        assert_eq!(
            nothing_replayed("x.log", &RxStats::default()).unwrap(),
            "nothing to replay: x.log is empty"
        );
    }
}
