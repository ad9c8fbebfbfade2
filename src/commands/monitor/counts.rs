//! Per-identifier counts for the end-of-run summary: how many frames and over what span of link time, so a
//! mean rate. Pure: fed frames and their link timestamps.

use crate::link::LinkFrame;
use crate::protocol::frame::ERR_FLAG;
use crate::protocol::{FrameId, FrameKind};

/// Identifiers other than standard CAN ones counted individually (extended IDs from a flood are unbounded).
pub(super) const MAX_OTHER_IDS: usize = 256;

/// Frames and the time span they were seen over, for one identifier.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Count {
    pub(super) frames: u64,
    first: f64,
    last: f64,
    /// The message name of the latest frame.
    pub(super) msg: &'static str,
}

impl Count {
    fn add(&mut self, secs: f64, msg: &'static str) {
        if self.frames == 0 {
            self.first = secs;
        }
        self.frames += 1;
        self.last = secs;
        self.msg = msg;
    }

    /// Mean frames per second from the link's timestamps; `None` below two frames.
    pub(super) fn rate(&self) -> Option<f64> {
        let span = self.last - self.first;
        (self.frames >= 2 && span > 0.0).then(|| (self.frames - 1) as f64 / span)
    }
}

/// What kind of frame a row of the summary counts (besides standard CAN data frames), in the rows' order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum RowKind {
    Data,
    Remote,
    Fd,
    Error,
    Serial,
}

/// Per-identifier counts: a table for the 2048 standard identifiers, a bounded list for everything else.
pub(super) struct Counts {
    standard: Box<[Count]>,
    others: Vec<((RowKind, FrameId), Count)>,
    /// Frames of identifiers beyond `MAX_OTHER_IDS`.
    pub(super) overflow: u64,
}

impl Counts {
    pub(super) fn new() -> Self {
        Self { standard: vec![Count::default(); 0x800].into_boxed_slice(), others: Vec::new(), overflow: 0 }
    }

    pub(super) fn add(&mut self, frame: &LinkFrame, secs: f64, msg: &'static str) {
        let key = match frame {
            LinkFrame::Can(frame) if frame.is_standard_data() => {
                self.standard[(frame.id() & 0x7FF) as usize].add(secs, msg);
                return;
            }
            LinkFrame::Can(frame) => {
                let kind = match frame.kind() {
                    FrameKind::Error => RowKind::Error,
                    FrameKind::Remote => RowKind::Remote,
                    FrameKind::Fd => RowKind::Fd,
                    FrameKind::Data => RowKind::Data,
                };
                (kind, frame.frame_id())
            }
            LinkFrame::Serial(frame) => (RowKind::Serial, frame.frame_id()),
        };
        if let Some((_, count)) = self.others.iter_mut().find(|(k, _)| *k == key) {
            count.add(secs, msg);
        } else if self.others.len() < MAX_OTHER_IDS {
            let mut count = Count::default();
            count.add(secs, msg);
            self.others.push((key, count));
        } else {
            self.overflow += 1;
        }
    }

    /// Every identifier seen, in order: standard CAN, then the others by kind and identifier.
    pub(super) fn rows(&self) -> Vec<(String, Count)> {
        let mut rows: Vec<(String, Count)> = (0..self.standard.len())
            .filter(|&id| self.standard[id].frames > 0)
            .map(|id| (FrameId::standard(id as u32).to_string(), self.standard[id]))
            .collect();
        let mut others = self.others.clone();
        others.sort_by_key(|(key, _)| *key);
        rows.extend(others.into_iter().map(|((kind, id), count)| {
            let label = match kind {
                // An error frame's "identifier" is its error classes, printed as candump does.
                RowKind::Error => format!("0x{:08X}", id.value() | ERR_FLAG),
                _ => id.to_string(),
            };
            (label, count)
        }));
        rows
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::CanFrame;

    fn can(id: u32) -> LinkFrame {
        LinkFrame::Can(CanFrame::new(id, &[0; 8]).unwrap())
    }

    #[test]
    fn a_rate_needs_two_frames_over_some_time() {
        let mut count = Count::default();
        count.add(10.0, "system_state");
        assert_eq!(count.rate(), None);
        count.add(10.0, "system_state");
        assert_eq!(count.rate(), None, "no span yet");
        count.add(10.1, "system_state");
        assert_eq!(count.rate(), Some(2.0 / (10.1 - 10.0)));
    }

    #[test]
    fn rows_list_standard_ids_first_then_the_others_by_kind_and_id() {
        let mut counts = Counts::new();
        counts.add(&can(0x311), 1.0, "odometry");
        counts.add(&LinkFrame::Can(CanFrame::new_extended(0x18FF_0001, &[1]).unwrap()), 1.0, "raw");
        counts.add(&can(0x211), 1.0, "system_state");
        counts.add(&can(0x211), 2.0, "system_state");
        let rows: Vec<(String, u64)> =
            counts.rows().into_iter().map(|(id, count)| (id, count.frames)).collect();
        assert_eq!(rows, [("0x211".to_string(), 2), ("0x311".to_string(), 1), ("0x18FF0001".to_string(), 1)]);
    }

    #[test]
    fn identifiers_beyond_the_bound_are_counted_together() {
        let mut counts = Counts::new();
        for id in 0..MAX_OTHER_IDS as u32 + 3 {
            counts.add(&LinkFrame::Can(CanFrame::new_extended(0x1000_0000 + id, &[]).unwrap()), 1.0, "raw");
        }
        assert_eq!(counts.rows().len(), MAX_OTHER_IDS);
        assert_eq!(counts.overflow, 3);
    }
}
