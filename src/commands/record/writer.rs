//! The recorder's writer thread: everything that touches the disk, so the receive loop never waits for it.
//! It appends each second's batch to the open segment, starts new segments and trims the ring, makes room
//! on a full disk (the oldest ring segments first, incidents last) and counts what it could not write,
//! writes incidents, and rewrites `status.json`.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use parking_lot::Mutex;

use super::incident;
use crate::blackbox::ring::{Bounds, Ring};
use crate::blackbox::segment::Segment;
use crate::blackbox::status::{self, Status};
use crate::blackbox::{incidents_dir, names, ring_dir};

/// Segments are fsynced this often, and when they close: what a power cut can lose (a crash of the
/// process loses only the batch not yet written, at most half a second).
pub const SYNC_EVERY: Duration = Duration::from_secs(10);
/// Batches waiting for the disk before further ones are counted as lost.
pub const QUEUE_BATCHES: usize = 32;

/// Work for the writer, in the order the receive loop sent it.
pub enum Job {
    /// Whole lines to append; with `segment`, first close the open segment and start one at that time.
    Batch {
        segment: Option<u64>,
        text: Vec<u8>,
        lines: u64,
        now: u64,
    },
    /// An incident window is over: its files, from the ring (every line of it was sent before this).
    Incident(Box<incident::Request>),
    Stop,
}

pub struct Limits {
    pub bounds: Bounds,
    pub max_incidents: u32,
}

/// Starts the thread.
pub fn start(
    dir: &Path,
    limits: Limits,
    status: Arc<Mutex<Status>>,
) -> Result<(SyncSender<Job>, JoinHandle<()>)> {
    let ring =
        Ring::open(&ring_dir(dir)).with_context(|| format!("cannot create {}", ring_dir(dir).display()))?;
    std::fs::create_dir_all(incidents_dir(dir))
        .with_context(|| format!("cannot create {}", incidents_dir(dir).display()))?;
    incident::remove_partial(dir);
    let (sender, inbox) = std::sync::mpsc::sync_channel(QUEUE_BATCHES);
    let mut writer = Writer {
        dir: dir.to_path_buf(),
        ring,
        limits,
        segment: None,
        synced: Instant::now(),
        status_written: None,
        status,
        disk_full: false,
        failing: None,
        status_failing: false,
    };
    let handle = std::thread::Builder::new()
        .name("tracerctl-record-writer".into())
        .spawn(move || writer.run(&inbox))
        .context("cannot start the writer thread")?;
    Ok((sender, handle))
}

struct Writer {
    dir: PathBuf,
    ring: Ring,
    limits: Limits,
    segment: Option<Segment>,
    synced: Instant,
    status_written: Option<Instant>,
    status: Arc<Mutex<Status>>,
    /// In a full-disk episode (said once when it starts and once when it ends).
    disk_full: bool,
    /// Another write error, said once until a write succeeds.
    failing: Option<String>,
    /// status.json could not be written (said once until it can).
    status_failing: bool,
}

impl Writer {
    fn run(&mut self, inbox: &Receiver<Job>) {
        while let Ok(job) = inbox.recv() {
            match job {
                Job::Batch { segment, text, lines, now } => self.batch(segment, &text, lines, now),
                Job::Incident(request) => self.incident(&request),
                Job::Stop => break,
            }
            if self.synced.elapsed() >= SYNC_EVERY {
                self.sync();
            }
            if self.status_written.is_none_or(|at| at.elapsed() >= status::EVERY) {
                self.write_status();
            }
        }
        self.sync();
        self.status.lock().state = "stopped".to_string();
        self.write_status();
    }

    fn sync(&mut self) {
        if let Some(segment) = &self.segment {
            if let Err(error) = segment.sync() {
                crate::say!("tracerctl: cannot sync {}: {error}", segment.path().display());
            }
        }
        self.synced = Instant::now();
    }

    fn write_status(&mut self) {
        let mut status = self.status.lock();
        status.updated = names::micros(&crate::link::now_timestamp());
        match status.write(&self.dir) {
            Ok(()) => self.status_failing = false,
            Err(error) if !self.status_failing => {
                self.status_failing = true;
                crate::say!("tracerctl: cannot write {}: {error}", status::path(&self.dir).display());
            }
            Err(_) => {}
        }
        self.status_written = Some(Instant::now());
    }

    fn batch(&mut self, new_segment: Option<u64>, text: &[u8], lines: u64, now: u64) {
        if let Some(start) = new_segment {
            self.close_segment();
            self.trim(now);
            self.open_segment(start);
        }
        if text.is_empty() {
            return;
        }
        if self.segment.is_none() {
            self.open_segment(names::line_time(text).unwrap_or(now));
        }
        loop {
            let result = match &mut self.segment {
                Some(segment) => segment.append(text, lines),
                None => Err(io::Error::other("no segment file could be created")),
            };
            match result {
                Ok(()) => {
                    self.status.lock().frames_recorded += lines;
                    self.recovered();
                    return;
                }
                Err(error) if is_disk_full(&error) && self.make_room() => {}
                Err(error) => {
                    let reason =
                        if is_disk_full(&error) { self.full() } else { self.failed(&error.to_string()) };
                    self.status.lock().lose(lines, &reason);
                    return;
                }
            }
        }
    }

    fn open_segment(&mut self, start: u64) {
        loop {
            match Segment::create(self.ring.dir(), start) {
                Ok(segment) => {
                    self.segment = Some(segment);
                    return;
                }
                Err(error) if is_disk_full(&error) && self.make_room() => {}
                Err(error) => {
                    if is_disk_full(&error) {
                        self.full();
                    } else {
                        self.failed(&format!(
                            "cannot create a segment in {}: {error}",
                            self.ring.dir().display()
                        ));
                    }
                    return;
                }
            }
        }
    }

    fn close_segment(&mut self) {
        if let Some(segment) = self.segment.take() {
            if let Err(error) = segment.sync() {
                crate::say!("tracerctl: cannot sync {}: {error}", segment.path().display());
            }
            // An empty segment (no frame in its time) is not kept.
            if segment.bytes == 0 {
                let _ = std::fs::remove_file(segment.path());
            }
        }
        self.synced = Instant::now();
    }

    fn trim(&mut self, now: u64) {
        match self.ring.trim(self.limits.bounds, now) {
            Ok(removed) => self.status.lock().ring_segments_removed += removed.segments,
            Err(error) => {
                crate::say!("tracerctl: cannot trim the ring {}: {error}", self.ring.dir().display())
            }
        }
    }

    /// Frees room on a full disk for the ring: its oldest segment. False: nothing left (incidents are
    /// not removed for the ring, only for a new incident: [`Self::make_room_for_incident`]).
    fn make_room(&mut self) -> bool {
        if let Ok(Some(removed)) = self.ring.remove_oldest() {
            self.status.lock().ring_segments_removed += removed.segments;
            return true;
        }
        false
    }

    /// Frees room for a new incident: the oldest ring segment first, incidents last.
    fn make_room_for_incident(&mut self) -> bool {
        if self.make_room() {
            return true;
        }
        match incident::remove_oldest(&self.dir) {
            Some(name) => {
                crate::say!("tracerctl: the disk is full: removed the oldest incident {name} to make room");
                self.status.lock().incidents_removed += 1;
                true
            }
            None => false,
        }
    }

    /// The reason frames are lost on a full disk; said when the episode starts.
    fn full(&mut self) -> String {
        let reason = format!("the disk holding {} is full", self.dir.display());
        if !self.disk_full {
            self.disk_full = true;
            crate::say!(
                "tracerctl: {reason}, with nothing older left to remove: frames are counted as lost until there \
                 is room again"
            );
            self.status.lock().state = format!("losing frames: {reason}");
        }
        reason
    }

    fn failed(&mut self, reason: &str) -> String {
        if self.failing.as_deref() != Some(reason) {
            crate::say!("tracerctl: {reason}: frames are counted as lost until a write succeeds");
            self.failing = Some(reason.to_string());
        }
        reason.to_string()
    }

    fn recovered(&mut self) {
        if self.disk_full || self.failing.is_some() {
            self.disk_full = false;
            self.failing = None;
            let lost = self.status.lock().frames_lost;
            crate::say!("tracerctl: recording again ({lost} frames lost in all, see record --status)");
            self.status.lock().state = "recording".to_string();
        }
    }

    fn incident(&mut self, request: &incident::Request) {
        // The window's last lines are in the open segment: out of this process's buffers first.
        let started = Instant::now();
        let mut result = incident::write(&self.dir, &self.ring, request);
        while result.as_ref().is_err_and(|error| error.chain().any(is_full_disk_cause))
            && self.make_room_for_incident()
        {
            result = incident::write(&self.dir, &self.ring, request);
        }
        match result {
            Ok(made) => {
                crate::say!(
                    "tracerctl: incident {}: {}; {} frames from {} to {} (written in {} ms)",
                    made.name,
                    request.causes_text(),
                    made.frames,
                    names::rfc3339_millis(request.window.start),
                    names::rfc3339_millis(request.window.end),
                    started.elapsed().as_millis()
                );
                self.status.lock().incidents_made += 1;
            }
            Err(error) => {
                crate::say!("tracerctl: cannot write the incident of {}: {error:#}", request.causes_text());
            }
        }
        let removed = incident::keep_newest(&self.dir, self.limits.max_incidents);
        if removed > 0 {
            crate::say!(
                "tracerctl: removed the {removed} oldest incident(s): more than --max-incidents {} are kept",
                self.limits.max_incidents
            );
            self.status.lock().incidents_removed += removed;
        }
    }
}

fn is_full_disk_cause(cause: &(dyn std::error::Error + 'static)) -> bool {
    cause.downcast_ref::<io::Error>().is_some_and(is_disk_full)
}

fn is_disk_full(error: &io::Error) -> bool {
    if error.kind() == io::ErrorKind::StorageFull {
        return true;
    }
    #[cfg(unix)]
    if matches!(error.raw_os_error(), Some(libc::ENOSPC | libc::EDQUOT)) {
        return true;
    }
    false
}
