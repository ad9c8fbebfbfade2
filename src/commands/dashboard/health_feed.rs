//! The dashboard's health figures, made off the event loop: the session's tap feeds the live analysis every
//! frame, and a thread of its own turns the analysis into a ready view once a second when frames came. The
//! loop that takes Space never waits for an analysis (a report can take tens of milliseconds in a long
//! session).

use std::sync::Arc;
use std::time::Duration;

use anyhow::{Context, Result};
use parking_lot::Mutex;

use crate::dashboard::health::HealthView;
use crate::protocol::ProtocolHint;
use crate::session::health::LiveHealth;
use crate::session::FrameTap;

/// A view is made this often, when frames came since the last.
const HEALTH_EVERY: Duration = Duration::from_secs(1);

/// The latest view not yet shown.
pub(super) type LatestHealth = Arc<Mutex<Option<HealthView>>>;

struct Feed {
    live: LiveHealth,
    /// Frames came since the last view.
    changed: bool,
}

/// The tap to give the session, and where its views appear. The view thread ends within a second of the
/// tap's end (the session's).
pub(super) fn health_tap(hint: ProtocolHint) -> Result<(FrameTap, LatestHealth)> {
    let feed = Arc::new(Mutex::new(Feed { live: LiveHealth::new(hint), changed: false }));
    let latest = LatestHealth::default();
    let (watched, out) = (Arc::downgrade(&feed), Arc::clone(&latest));
    std::thread::Builder::new()
        .name("tracerctl-health-view".into())
        .spawn(move || loop {
            std::thread::sleep(HEALTH_EVERY);
            let Some(feed) = watched.upgrade() else { return };
            // A copy under the lock (the tap waits meanwhile), the report outside it.
            let analyzer = {
                let mut feed = feed.lock();
                if !std::mem::take(&mut feed.changed) {
                    continue;
                }
                feed.live.analyzer.clone()
            };
            drop(feed);
            *out.lock() = Some(HealthView::of(&analyzer.report()));
        })
        .context("cannot start the health view thread")?;
    let tap: FrameTap = Arc::new(move |received, direction| {
        let mut feed = feed.lock();
        feed.live.observe(received, direction);
        feed.changed = true;
    });
    Ok((tap, latest))
}
