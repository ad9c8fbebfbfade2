//! What every worker of `decode -j` decodes with, and the state a chunk starts from.

use std::sync::Arc;

use crate::candump::{CarriedState, LogFormat};
use crate::output::filter::Filter;
use crate::output::EventWriter;
use crate::protocol::ProtocolHint;

use super::super::ranges::Ranges;

/// The state a chunk's first line is decoded from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct Start {
    pub carried: CarriedState,
    /// The detector's verdict: V1-only and V2-only identifiers seen before.
    pub v1_seen: bool,
    pub v2_seen: bool,
}

/// What every worker decodes with.
#[derive(Clone)]
pub(super) struct Settings {
    /// candump, ASC or trc text (the format [`crate::candump::open_log`] recognised).
    pub format: LogFormat,
    pub protocol: ProtocolHint,
    pub filter: Filter,
    /// Workers write the output (not with `-t d`, whose stamps are sums over everything before).
    pub writer: Option<EventWriter>,
    /// Workers keep the events for this thread to replay.
    pub record: bool,
    /// Workers summarize their chunk into a partial summary for this thread to merge (`--summary`).
    pub partial: bool,
    /// `partial` without a filter: frames go to the summary without an event built.
    pub summary_only: bool,
    pub delta_stamps: bool,
    pub strict: bool,
    /// A plain file: the ranges the workers read (and this thread reads again to decode a chunk again).
    pub ranges: Option<Arc<Ranges>>,
}
