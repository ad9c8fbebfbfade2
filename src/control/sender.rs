//! The 50 Hz sender thread: its own clock on an absolute 20 ms grid, the latest target ramped within the
//! limits, the holds (halt, suspend, a gap in its clock, the watchdog), and the stop frames on every way out
//! of its loop. The stop rules it keeps are in the folder's doc ([`crate::control`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use parking_lot::Mutex;

use super::limits::{ramp_step, Limits};
use super::stop::{
    install_panic_hook, panicked, send_motion_frame, send_stop_frames, set_emergency, STOP_FRAMES,
};
use crate::link::{is_queue_full, FrameTx, LinkFrame};
use crate::protocol::message::MotionCommand;
use crate::protocol::Codec;

/// The chassis wants a motion command every 20 ms (and stops by itself after 500 ms without one).
pub const PERIOD: Duration = Duration::from_millis(20);
/// A gap this long in the sender's own clock (ten periods) means the process or the machine did not run:
/// the robot has stopped by itself (500 ms) or is about to, so the ramp state becomes zero and the sender
/// holds zero until a fresh command. Shorter stalls happen on a busy machine (110 ms measured during a
/// parallel test run on the 2-core build machine) while the robot is still obeying the last command.
pub const GAP_LIMIT: Duration = Duration::from_millis(200);
/// A link with this many frames still queued for output is not draining: motion is held back.
const BACKLOG_LIMIT: usize = 2;

/// Why the sender holds zero and ignores the target until [`MotionSender::resume`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hold {
    /// Asked to stop at once (Space, a state that forbids driving).
    Halt,
    /// SIGTSTP: zeros sent, the process is about to stop.
    Suspend,
    /// The sender's own clock jumped by this much: the process was suspended or the machine stalled.
    Gap(Duration),
    /// The owner stopped refreshing the target (input stalled) for longer than the watchdog.
    Watchdog,
    /// Asked to send nothing at all (the command-timeout probe of `commission`: the robot's own timeout
    /// must stop it). The ramp state is zero, so whatever is sent after the resume starts from rest.
    Silence,
}

impl Hold {
    /// Zero at once rather than braking: the operator asked, or the robot has stopped by itself already.
    fn is_immediate(self) -> bool {
        !matches!(self, Hold::Watchdog)
    }
}

#[derive(Clone, Copy, Debug)]
struct Target {
    linear: f64,
    angular: f64,
    set_at: Instant,
}

/// What the sender has done, for status displays and the end-of-run report.
#[derive(Clone, Copy, Debug, Default)]
pub struct SenderStats {
    /// The last command sent.
    pub sent: MotionCommand,
    /// When the last motion frame left.
    pub sent_at: Option<Instant>,
    pub frames: u64,
    /// Sends that failed, for any reason (`queue_full` included).
    pub send_errors: u64,
    /// Frames not sent because the transmit queue was full (ENOBUFS, EAGAIN, a write timeout).
    pub queue_full: u64,
    /// Motion frames not written because the link's output was not draining (they would arrive stale).
    pub held_back: u64,
    /// Frames still queued for output that were discarded before the stop frames.
    pub discarded: u64,
    /// The link also discarded output it cannot count (a pseudo-terminal's), before the stop frames.
    pub discarded_uncounted: bool,
    pub mode_frames: u64,
    /// Ticks where the watchdog zeroed a stale target.
    pub watchdog_trips: u64,
    /// Gaps in the sender's clock longer than [`GAP_LIMIT`], and the latest one.
    pub gaps: u64,
    pub last_gap: Option<Duration>,
    /// Why the sender holds zero now, if it does.
    pub hold: Option<Hold>,
    /// Zero-velocity frames the link took when the sender stopped; `None` while it runs.
    pub stop_frames_sent: Option<usize>,
    /// Frames still queued in the link's output a moment after the stop frames (where the link can tell):
    /// more than none means the adapter is not sending, and the stop frames have not left.
    pub stop_frames_queued: usize,
}

impl SenderStats {
    /// True when the sender stopped, the link took at least one stop frame, and nothing of it is still
    /// waiting in an output queue that does not drain.
    pub fn stop_confirmed(&self) -> bool {
        self.stop_frames_sent.is_some_and(|sent| sent > 0) && self.stop_frames_queued == 0
    }
}

/// How long the stop frames may take to leave a queue the link reports (a serial adapter that has stopped
/// sending: a stalled USB adapter may recover), before they count as stuck and the command ends saying so.
const STOP_DRAIN: Duration = Duration::from_secs(2);

struct Shared {
    target: Mutex<Target>,
    stats: Mutex<SenderStats>,
    stop: AtomicBool,
    /// Set by whoever sees the robot in another control mode: send the mode-enable frame next tick.
    enable_mode: AtomicBool,
    /// A new target that should not wait for the next tick (a key press): send now, restart the grid.
    kicked: AtomicBool,
    /// A hold asked for by the owner or a signal, taken by the sender at its next tick.
    hold_request: Mutex<Option<Hold>>,
    /// Set by `resume`: clear the hold at the next tick.
    resume_request: AtomicBool,
    /// Halts asked for, and the latest one whose zero frame has left (so SIGTSTP can wait for it).
    halts_asked: AtomicU64,
    halts_done: AtomicU64,
    last_error: Mutex<Option<String>>,
}

impl Shared {
    fn stats(&self) -> parking_lot::MutexGuard<'_, SenderStats> {
        self.stats.lock()
    }

    /// Counts a send: a frame (motion or mode-enable) that left, or an error, with a full queue apart.
    fn record(&self, result: std::io::Result<()>, mode: bool) {
        let mut stats = self.stats();
        match result {
            Ok(()) if mode => stats.mode_frames += 1,
            Ok(()) => stats.frames += 1,
            Err(error) => {
                stats.send_errors += 1;
                if is_queue_full(&error) {
                    stats.queue_full += 1;
                }
                *self.last_error.lock() = Some(error.to_string());
            }
        }
    }

    /// Asks for zero at once and holding; returns the halt's number.
    fn halt(&self, hold: Hold) -> u64 {
        *self.hold_request.lock() = Some(hold);
        self.resume_request.store(false, Ordering::SeqCst);
        let number = self.halts_asked.fetch_add(1, Ordering::SeqCst) + 1;
        self.kicked.store(true, Ordering::SeqCst);
        number
    }
}

/// Stops the sender from another thread (a signal handler thread): zero-velocity frames at once.
#[derive(Clone)]
pub struct Stopper {
    shared: Arc<Shared>,
    thread: std::thread::Thread,
}

impl Stopper {
    /// Ends the sender: zero-velocity frames at once, then its thread ends.
    pub fn stop_now(&self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.thread.unpark();
    }

    /// For SIGTSTP: zero at once and hold; returns once the zero frame has left (or after `timeout`), so the
    /// process can stop knowing the robot was told to stop. True if it left in time.
    pub fn suspend(&self, timeout: Duration) -> bool {
        let number = self.shared.halt(Hold::Suspend);
        self.thread.unpark();
        let deadline = Instant::now() + timeout;
        while Instant::now() < deadline {
            if self.shared.halts_done.load(Ordering::SeqCst) >= number {
                return true;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        false
    }
}

/// The running sender. Dropping it stops the robot.
pub struct MotionSender {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    tx: Arc<dyn FrameTx>,
    stop_frame: LinkFrame,
}

impl MotionSender {
    /// Starts sending at 50 Hz. `codec` encodes for the link's wire; `watchdog` is how old a target may get
    /// before the sender treats input as stalled, commands zero and holds it.
    pub fn start(tx: Arc<dyn FrameTx>, mut codec: Codec, limits: Limits, watchdog: Duration) -> Result<Self> {
        install_panic_hook();
        let stop_frame = codec.motion(MotionCommand::STOP);
        set_emergency(Some((Arc::clone(&tx), stop_frame)));
        let shared = Arc::new(Shared {
            target: Mutex::new(Target { linear: 0.0, angular: 0.0, set_at: Instant::now() }),
            stats: Mutex::new(SenderStats::default()),
            stop: AtomicBool::new(false),
            enable_mode: AtomicBool::new(true),
            kicked: AtomicBool::new(false),
            hold_request: Mutex::new(None),
            resume_request: AtomicBool::new(false),
            halts_asked: AtomicU64::new(0),
            halts_done: AtomicU64::new(0),
            last_error: Mutex::new(None),
        });
        let thread = {
            let (shared, tx) = (Arc::clone(&shared), Arc::clone(&tx));
            std::thread::Builder::new()
                .name("tracerctl-sender".into())
                .spawn(move || send_loop(&shared, tx.as_ref(), &mut codec, limits, watchdog))
                .context("cannot start the sender thread")?
        };
        Ok(Self { shared, thread: Some(thread), tx, stop_frame })
    }

    /// A handle that stops the robot from any thread.
    pub fn stopper(&self) -> Stopper {
        let thread = self.thread.as_ref().expect("running").thread().clone();
        Stopper { shared: Arc::clone(&self.shared), thread }
    }

    /// Sets what to drive at (m/s, rad/s); also tells the watchdog that input is alive. Ignored while the
    /// sender holds zero.
    pub fn set_target(&self, linear: f64, angular: f64) {
        *self.shared.target.lock() = Target { linear, angular, set_at: Instant::now() };
    }

    /// Sets the target and sends it now rather than at the next tick (for a key press: the first changed
    /// frame leaves within a millisecond; the 20 ms grid restarts from it).
    pub fn set_target_now(&self, linear: f64, angular: f64) {
        self.set_target(linear, angular);
        self.kick();
    }

    fn kick(&self) {
        self.shared.kicked.store(true, Ordering::SeqCst);
        if let Some(thread) = &self.thread {
            thread.thread().unpark();
        }
    }

    /// Sends no frame at all (not even zeros) until [`MotionSender::resume`]; the ramp state becomes zero.
    /// Stopping still sends the stop frames. For measuring the robot's own command timeout.
    pub fn silence(&self) {
        self.set_target(0.0, 0.0);
        self.shared.halt(Hold::Silence);
        self.kick();
    }

    /// Zero at once (no ramp), then hold zero until [`MotionSender::resume`].
    pub fn halt(&self) {
        self.set_target(0.0, 0.0);
        self.shared.halt(Hold::Halt);
        self.kick();
    }

    /// Ends a hold: the next target counts again, ramped up from zero. Call it only on a fresh command from
    /// the operator (a key pressed after the hold began).
    pub fn resume(&self) {
        *self.shared.hold_request.lock() = None;
        self.shared.resume_request.store(true, Ordering::SeqCst);
    }

    /// Asks for the mode-enable frame (0x421 = CAN on V2) before the next motion frame.
    pub fn request_mode_enable(&self) {
        self.shared.enable_mode.store(true, Ordering::SeqCst);
    }

    pub fn stats(&self) -> SenderStats {
        *self.shared.stats()
    }

    /// The sender's latest send error, if sending failed (the thread keeps trying).
    pub fn last_error(&self) -> Option<String> {
        self.shared.last_error.lock().clone()
    }

    /// True while the sender thread runs.
    pub fn is_running(&self) -> bool {
        self.thread.as_ref().is_some_and(|thread| !thread.is_finished())
    }

    /// Brakes to zero within the deceleration limits (for a normal end), then stops.
    pub fn ramp_down_and_stop(self, limits: &Limits) -> SenderStats {
        self.set_target(0.0, 0.0);
        let deadline =
            Instant::now() + limits.braking_time(self.stats().sent).min(Duration::from_secs(5)) + PERIOD * 2;
        while Instant::now() < deadline && self.stats().sent != MotionCommand::STOP && self.is_running() {
            self.set_target(0.0, 0.0);
            std::thread::sleep(Duration::from_millis(5));
        }
        self.stop()
    }

    /// Stops now: zero-velocity frames at once, then the thread ends.
    pub fn stop(mut self) -> SenderStats {
        self.shutdown();
        self.stats()
    }

    fn shutdown(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        if let Some(thread) = self.thread.take() {
            thread.thread().unpark();
            if thread.join().is_err() {
                // The sender thread panicked (its hook already sent zeros); send them again from here.
                self.tx.discard_pending();
                let sent = (0..STOP_FRAMES).filter(|_| self.tx.send(&self.stop_frame).is_ok()).count();
                self.shared.stats().stop_frames_sent = Some(sent);
            }
        }
        set_emergency(None);
    }
}

impl Drop for MotionSender {
    fn drop(&mut self) {
        self.shutdown();
    }
}

/// What the sender carries from one tick to the next.
struct LoopState {
    /// The next point on the 20 ms grid.
    next_tick: Instant,
    /// The velocity sent last (after ramps and caps), m/s and rad/s.
    current: (f64, f64),
    last_tick: Option<Instant>,
    hold: Option<Hold>,
}

fn send_loop(shared: &Shared, tx: &dyn FrameTx, codec: &mut Codec, limits: Limits, watchdog: Duration) {
    let mut state = LoopState { next_tick: Instant::now(), current: (0.0, 0.0), last_tick: None, hold: None };
    while !(shared.stop.load(Ordering::SeqCst) || panicked()) {
        tick(shared, tx, codec, &limits, watchdog, &mut state);
        state.next_tick = wait_for_next_tick(shared, state.next_tick);
    }
    // Every way out of the loop ends here.
    send_final_stop(shared, tx, codec);
}

/// One tick: the hold, the ramp toward the target (or toward zero while holding), and the frames.
fn tick(
    shared: &Shared,
    tx: &dyn FrameTx,
    codec: &mut Codec,
    limits: &Limits,
    watchdog: Duration,
    state: &mut LoopState,
) {
    let now = Instant::now();
    let halt_number = shared.halts_asked.load(Ordering::SeqCst);
    let (since, target) = update_hold(shared, now, watchdog, state);
    state.current = match state.hold {
        Some(reason) if reason.is_immediate() => (0.0, 0.0),
        Some(_) => ramp_step(state.current, (0.0, 0.0), limits, since.clamp(PERIOD, PERIOD * 5)),
        // At least one period's step: a frame sent early for a key press must already move (it restarts
        // the grid, so the ramp gains at most one step per press).
        None => {
            ramp_step(state.current, (target.linear, target.angular), limits, since.clamp(PERIOD, PERIOD * 5))
        }
    };
    state.last_tick = Some(now);
    shared.stats().hold = state.hold;
    if state.hold == Some(Hold::Silence) {
        return;
    }
    if shared.enable_mode.swap(false, Ordering::SeqCst) {
        shared.record(tx.send(&codec.enable_command_mode()), true);
    }
    send_motion(shared, tx, codec, state.current, halt_number);
}

/// Takes the owner's resume and hold requests, then holds on a gap in the sender's own clock or when the
/// target has not been renewed within the watchdog. Returns the time since the last tick and the target.
fn update_hold(
    shared: &Shared,
    now: Instant,
    watchdog: Duration,
    state: &mut LoopState,
) -> (Duration, Target) {
    if shared.resume_request.swap(false, Ordering::SeqCst) {
        state.hold = None;
    }
    if let Some(asked) = shared.hold_request.lock().take() {
        state.hold = Some(asked);
    }
    // The sender's own clock: a jump means nothing ran (SIGSTOP, Ctrl-Z, a stalled machine).
    let since = state.last_tick.map_or(Duration::ZERO, |last| now.duration_since(last));
    if since > GAP_LIMIT {
        state.hold = Some(Hold::Gap(since));
        let mut stats = shared.stats();
        stats.gaps += 1;
        stats.last_gap = Some(since);
    }
    let target = *shared.target.lock();
    let moving_target = target.linear != 0.0 || target.angular != 0.0;
    if state.hold.is_none() && moving_target && now.duration_since(target.set_at) > watchdog {
        state.hold = Some(Hold::Watchdog);
        shared.stats().watchdog_trips += 1;
    }
    (since, target)
}

/// Sends the motion frame for `current`, unless the link's queue holds a backlog.
fn send_motion(shared: &Shared, tx: &dyn FrameTx, codec: &mut Codec, current: (f64, f64), halt_number: u64) {
    let (command, _) = MotionCommand::clamped_from_si(current.0, current.1);
    // Not behind a backlog: a motion frame queued there would reach the robot late, and stale.
    if tx.pending().is_some_and(|queued| queued >= BACKLOG_LIMIT) {
        shared.stats().held_back += 1;
        return;
    }
    // After a panic nothing but the stop frames goes out (the loop ends at its next check).
    let Some(result) = send_motion_frame(tx, &codec.motion(command)) else { return };
    let sent = result.is_ok();
    shared.record(result, false);
    if sent {
        let mut stats = shared.stats();
        stats.sent = command;
        stats.sent_at = Some(Instant::now());
        if command == MotionCommand::STOP {
            shared.halts_done.fetch_max(halt_number, Ordering::SeqCst);
        }
    }
}

/// Sleeps until the next point on the 20 ms grid (returned), or until stopped or kicked (a new target that
/// should not wait: the grid restarts now). Late by whole periods, it skips them rather than burst.
fn wait_for_next_tick(shared: &Shared, previous: Instant) -> Instant {
    let mut next_tick = previous + PERIOD;
    let now = Instant::now();
    if next_tick <= now {
        let behind = now.duration_since(next_tick).as_nanos() / PERIOD.as_nanos() + 1;
        next_tick += PERIOD * behind as u32;
    }
    while !shared.stop.load(Ordering::SeqCst) && !panicked() {
        let now = Instant::now();
        if now >= next_tick {
            break;
        }
        if shared.kicked.swap(false, Ordering::SeqCst) {
            next_tick = now;
            break;
        }
        std::thread::park_timeout(next_tick - now);
    }
    next_tick
}

/// The stop frames every exit sends, then, where the link can tell (a serial driver's queue), a wait to see
/// that they leave; the outcome goes into the stats.
fn send_final_stop(shared: &Shared, tx: &dyn FrameTx, codec: &mut Codec) {
    let (sent, discarded) = send_stop_frames(tx, codec, |result| shared.record(result, false));
    let drained_by = Instant::now() + STOP_DRAIN;
    let mut queued = tx.pending().unwrap_or(0);
    while queued > 0 && sent > 0 && Instant::now() < drained_by {
        std::thread::sleep(Duration::from_millis(5));
        queued = tx.pending().unwrap_or(0);
    }
    let mut stats = shared.stats();
    stats.discarded += discarded.frames as u64;
    stats.discarded_uncounted |= discarded.uncounted;
    stats.stop_frames_sent = Some(sent);
    stats.stop_frames_queued = if sent > 0 { queued } else { 0 };
    if sent > 0 {
        stats.sent = MotionCommand::STOP;
        stats.sent_at = Some(Instant::now());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::Discarded;
    use crate::protocol::Wire;
    use std::sync::{mpsc, Mutex};

    /// A link that records what was sent.
    struct Recorder(Mutex<mpsc::Sender<(Instant, LinkFrame)>>);
    impl FrameTx for Recorder {
        fn send(&self, frame: &LinkFrame) -> std::io::Result<()> {
            let _ = self.0.lock().unwrap().send((Instant::now(), *frame));
            Ok(())
        }
    }

    fn linear_of(frame: &LinkFrame) -> Option<i16> {
        match frame {
            LinkFrame::Can(frame) if frame.id() == 0x111 => {
                Some(i16::from_be_bytes([frame.data()[0], frame.data()[1]]))
            }
            _ => None,
        }
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn mode_first_then_motion_then_zeros_on_stop() {
        let (sender, frames) = mpsc::channel();
        let tx: Arc<dyn FrameTx> = Arc::new(Recorder(Mutex::new(sender)));
        let limits = Limits { linear_accel: 100.0, ..Limits::default() };
        let motion =
            MotionSender::start(tx, Codec::new(Wire::CanV2), limits, Duration::from_secs(5)).unwrap();
        motion.set_target(0.3, 0.0);
        std::thread::sleep(Duration::from_millis(120));
        let stopped_at = Instant::now();
        motion.stop();
        let frames: Vec<(Instant, LinkFrame)> = frames.try_iter().collect();
        let LinkFrame::Can(first) = frames[0].1 else { panic!() };
        assert_eq!(first.to_string(), "421#01", "command mode before any motion");
        assert!(frames.iter().any(|(_, f)| linear_of(f) == Some(300)), "drove at 0.3 m/s");
        let tail: Vec<Option<i16>> =
            frames[frames.len() - STOP_FRAMES..].iter().map(|(_, f)| linear_of(f)).collect();
        assert_eq!(tail, vec![Some(0); STOP_FRAMES]);
        let first_zero = frames[frames.len() - STOP_FRAMES].0;
        assert!(first_zero.duration_since(stopped_at) < Duration::from_millis(50), "zeros at once");
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_stalled_input_is_zeroed_by_the_watchdog() {
        let (sender, frames) = mpsc::channel();
        let tx: Arc<dyn FrameTx> = Arc::new(Recorder(Mutex::new(sender)));
        let limits = Limits { linear_accel: 100.0, ..Limits::default() };
        let motion =
            MotionSender::start(tx, Codec::new(Wire::CanV2), limits, Duration::from_millis(100)).unwrap();
        motion.set_target(0.3, 0.0);
        // No further set_target: input has stalled.
        std::thread::sleep(Duration::from_millis(400));
        let stats = motion.stats();
        assert_eq!(stats.sent, MotionCommand::STOP, "zero after the watchdog");
        assert!(stats.watchdog_trips > 0);
        drop(motion);
        let speeds: Vec<i16> = frames.try_iter().filter_map(|(_, f)| linear_of(&f)).collect();
        assert!(speeds.contains(&300));
        assert_eq!(speeds.last(), Some(&0));
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_kick_sends_the_new_target_at_once() {
        let (sender, frames) = mpsc::channel();
        let tx: Arc<dyn FrameTx> = Arc::new(Recorder(Mutex::new(sender)));
        let limits = Limits { linear_accel: 100.0, ..Limits::default() };
        let motion =
            MotionSender::start(tx, Codec::new(Wire::CanV2), limits, Duration::from_secs(5)).unwrap();
        std::thread::sleep(Duration::from_millis(45));
        let pressed = Instant::now();
        motion.set_target_now(0.2, 0.0);
        std::thread::sleep(Duration::from_millis(30));
        drop(motion);
        let first_moving = frames
            .try_iter()
            .find(|(_, f)| linear_of(f).is_some_and(|speed| speed != 0))
            .map(|(at, _)| at.duration_since(pressed))
            .unwrap();
        assert!(
            first_moving < Duration::from_millis(5),
            "the first frame after the press already moves: {first_moving:?}"
        );
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_panic_on_the_driving_thread_unwinds_into_zeros() {
        let (sender, frames) = mpsc::channel();
        let tx: Arc<dyn FrameTx> = Arc::new(Recorder(Mutex::new(sender)));
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let limits = Limits { linear_accel: 100.0, ..Limits::default() };
            let motion = MotionSender::start(tx, Codec::new(Wire::CanV2), limits, PERIOD * 50).unwrap();
            motion.set_target(0.3, 0.0);
            std::thread::sleep(Duration::from_millis(80));
            // Unwinding drops `motion`, which stops the robot. (No panic hook here: `resume_unwind`.)
            std::panic::resume_unwind(Box::new("simulated bug"));
        }));
        assert!(result.is_err());
        let speeds: Vec<i16> = frames.try_iter().filter_map(|(_, f)| linear_of(&f)).collect();
        assert!(speeds.contains(&300));
        assert_eq!(&speeds[speeds.len() - STOP_FRAMES..], &[0; STOP_FRAMES]);
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn dropping_the_sender_stops_the_robot() {
        let (sender, frames) = mpsc::channel();
        let tx: Arc<dyn FrameTx> = Arc::new(Recorder(Mutex::new(sender)));
        {
            let motion =
                MotionSender::start(tx, Codec::new(Wire::Serial), Limits::default(), PERIOD * 50).unwrap();
            motion.set_target(0.2, 0.1);
            std::thread::sleep(Duration::from_millis(60));
        }
        let last = frames.try_iter().last().unwrap().1;
        let LinkFrame::Serial(frame) = last else { panic!("serial link") };
        assert_eq!((frame.command, frame.payload[2], frame.payload[3]), (0x01, 0, 0), "zero percent");
    }

    /// A link whose behaviour the test sets: sends that stall, fail or hit a full queue, and a backlog.
    #[derive(Default)]
    struct FaultyLink {
        frames: Mutex<Vec<(Instant, LinkFrame)>>,
        /// The send with this number (1-based) blocks for this long first: a stalled machine, as the
        /// sender's own clock sees it.
        stall: Mutex<Option<(usize, Duration)>>,
        sends: std::sync::atomic::AtomicUsize,
        /// Every send fails with this errno (e.g. EPIPE 32, ENOBUFS 105) while set; `failures_left` limits it.
        fail_errno: Mutex<Option<i32>>,
        failures_left: std::sync::atomic::AtomicUsize,
        pending: Mutex<Option<usize>>,
        /// A queue that never drains, whatever is discarded (an adapter that sends nothing).
        stuck: Mutex<Option<usize>>,
        discards: Mutex<Vec<(Instant, usize)>>,
    }

    impl FrameTx for FaultyLink {
        fn send(&self, frame: &LinkFrame) -> std::io::Result<()> {
            let number = self.sends.fetch_add(1, Ordering::SeqCst) + 1;
            if let Some((at, pause)) = *self.stall.lock().unwrap() {
                if at == number {
                    std::thread::sleep(pause);
                }
            }
            if let Some(errno) = *self.fail_errno.lock().unwrap() {
                if self.failures_left.load(Ordering::SeqCst) > 0 {
                    self.failures_left.fetch_sub(1, Ordering::SeqCst);
                    return Err(std::io::Error::from_raw_os_error(errno));
                }
            }
            self.frames.lock().unwrap().push((Instant::now(), *frame));
            Ok(())
        }

        fn pending(&self) -> Option<usize> {
            self.stuck.lock().unwrap().or(*self.pending.lock().unwrap())
        }

        fn discard_pending(&self) -> Discarded {
            let queued = self.pending.lock().unwrap().take().unwrap_or(0);
            self.discards.lock().unwrap().push((Instant::now(), queued));
            Discarded { frames: queued, uncounted: false }
        }
    }

    impl FaultyLink {
        fn speeds(&self) -> Vec<(Instant, i16)> {
            self.frames.lock().unwrap().iter().filter_map(|(at, f)| Some((*at, linear_of(f)?))).collect()
        }
    }

    fn sender_kept_going(link: &FaultyLink) -> bool {
        link.speeds().iter().filter(|(_, speed)| *speed == 300).count() >= 3
    }

    fn start(link: &Arc<FaultyLink>, limits: Limits) -> MotionSender {
        let tx: Arc<dyn FrameTx> = Arc::clone(link) as Arc<dyn FrameTx>;
        MotionSender::start(tx, Codec::new(Wire::CanV2), limits, Duration::from_millis(250)).unwrap()
    }

    /// Keeps refreshing the target, as drive's and the dashboard's loops do (also right after a resume).
    fn keep_asking(sender: &MotionSender, linear: f64, how_long: Duration) {
        let until = Instant::now() + how_long;
        while Instant::now() < until {
            sender.set_target(linear, 0.0);
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_gap_in_the_senders_clock_zeroes_the_ramp_and_holds_until_resumed() {
        let link = Arc::new(FaultyLink::default());
        // The 30th send stalls 300 ms: the sender is at full speed by then (0.3 m/s at 100 m/s²).
        *link.stall.lock().unwrap() = Some((30, Duration::from_millis(300)));
        let sender = start(&link, Limits { linear_accel: 100.0, linear_decel: 100.0, ..Limits::default() });
        keep_asking(&sender, 0.3, Duration::from_millis(1200));
        let stats = sender.stats();
        assert_eq!(stats.gaps, 1);
        assert!(matches!(stats.hold, Some(Hold::Gap(gap)) if gap >= Duration::from_millis(300)), "{stats:?}");
        let speeds = link.speeds();
        let stalled = speeds.iter().position(|(_, speed)| *speed == 300).unwrap() + 30;
        // Everything after the stalled frame is zero although the target stayed at 0.3 m/s throughout.
        let after: Vec<i16> = speeds[stalled.min(speeds.len())..].iter().map(|(_, s)| *s).collect();
        let first_after_gap =
            speeds.iter().position(|(at, _)| *at > speeds[29].0 + Duration::from_millis(250));
        let first_after_gap = first_after_gap.expect("frames after the gap");
        assert!(speeds[first_after_gap..].iter().all(|(_, s)| *s == 0), "held zero: {after:?}");
        // A fresh command: the ramp starts again from zero, one step at a time.
        sender.resume();
        keep_asking(&sender, 0.3, Duration::from_millis(100));
        let speeds: Vec<i16> = link.speeds().iter().map(|(_, s)| *s).collect();
        assert!(speeds.ends_with(&[300]) || speeds.contains(&300), "drives again after resume: {speeds:?}");
        assert_eq!(sender.stats().hold, None);
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_halt_is_zero_at_once_with_no_ramp_and_holds() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits { max_linear: 1.5, linear_accel: 100.0, ..Limits::default() });
        keep_asking(&sender, 1.5, Duration::from_millis(150));
        let halted = Instant::now();
        sender.halt();
        keep_asking(&sender, 1.5, Duration::from_millis(100));
        let speeds = link.speeds();
        let after: Vec<(Duration, i16)> = speeds
            .iter()
            .filter(|(at, _)| *at >= halted)
            .map(|(at, s)| (at.duration_since(halted), *s))
            .collect();
        assert!(speeds.iter().any(|(at, s)| *at < halted && *s == 1500), "was at 1.5 m/s");
        assert_eq!(after[0].1, 0, "the first frame after Space is zero: {after:?}");
        assert!(after[0].0 < Duration::from_millis(10), "and leaves at once: {after:?}");
        assert!(after.iter().all(|(_, s)| *s == 0), "{after:?}");
        assert_eq!(sender.stats().hold, Some(Hold::Halt));
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_release_brakes_from_0_15_to_zero_within_150_ms() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits::default());
        keep_asking(&sender, 0.15, Duration::from_millis(600));
        let released = Instant::now();
        sender.set_target_now(0.0, 0.0);
        keep_asking(&sender, 0.0, Duration::from_millis(250));
        let zero = link.speeds().into_iter().find(|(at, s)| *at >= released && *s == 0).unwrap().0;
        assert!(zero.duration_since(released) <= Duration::from_millis(150), "{:?}", zero - released);
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn suspend_returns_once_the_zero_frame_has_left() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits { linear_accel: 100.0, linear_decel: 100.0, ..Limits::default() });
        keep_asking(&sender, 0.3, Duration::from_millis(100));
        assert!(sender.stopper().suspend(Duration::from_millis(100)));
        let last = *link.speeds().last().unwrap();
        assert_eq!(last.1, 0, "the latest frame on the link is zero when suspend returns");
        assert_eq!(sender.stats().hold, Some(Hold::Suspend));
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn stop_frames_that_cannot_be_sent_are_not_reported_as_sent() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits::default());
        keep_asking(&sender, 0.3, Duration::from_millis(100));
        *link.fail_errno.lock().unwrap() = Some(5); // EIO: the adapter is gone
        link.failures_left.store(usize::MAX, Ordering::SeqCst);
        let stats = sender.stop();
        assert_eq!(stats.stop_frames_sent, Some(0));
        assert!(!stats.stop_confirmed());
        assert_ne!(stats.sent, MotionCommand::STOP, "the last command that left was not a stop");
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn a_full_transmit_queue_is_counted_and_the_stop_frames_are_retried() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits { linear_accel: 100.0, linear_decel: 100.0, ..Limits::default() });
        keep_asking(&sender, 0.3, Duration::from_millis(60));
        *link.fail_errno.lock().unwrap() = Some(105); // ENOBUFS
        link.failures_left.store(4, Ordering::SeqCst);
        keep_asking(&sender, 0.3, Duration::from_millis(200));
        assert_eq!(link.failures_left.load(Ordering::SeqCst), 0, "four sends hit the full queue");
        link.failures_left.store(2, Ordering::SeqCst);
        let stats = sender.stop();
        assert_eq!(stats.queue_full, 6, "{stats:?}");
        assert!(sender_kept_going(&link), "the sender went on after the full queue");
        assert_eq!(stats.stop_frames_sent, Some(STOP_FRAMES), "retried until the queue took them");
        let speeds: Vec<i16> = link.speeds().iter().map(|(_, s)| *s).collect();
        assert_eq!(&speeds[speeds.len() - STOP_FRAMES..], &[0; STOP_FRAMES]);
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn motion_is_held_back_behind_a_backlog_and_the_backlog_is_discarded_before_the_stop() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits { linear_accel: 100.0, ..Limits::default() });
        keep_asking(&sender, 0.3, Duration::from_millis(100));
        // The peer stops reading: the driver holds 40 frames.
        *link.pending.lock().unwrap() = Some(40);
        let stalled = Instant::now();
        keep_asking(&sender, 0.3, Duration::from_millis(100));
        let stats = sender.stop();
        assert!(stats.held_back >= 3, "{stats:?}");
        assert_eq!(stats.discarded, 40);
        let frames = link.frames.lock().unwrap().clone();
        let during: Vec<Option<i16>> = frames
            .iter()
            .filter(|(at, _)| *at > stalled + Duration::from_millis(5))
            .map(|(_, f)| linear_of(f))
            .collect();
        assert_eq!(during, vec![Some(0); STOP_FRAMES], "only the stop frames, after the discard");
        let discarded_at = link.discards.lock().unwrap()[0].0;
        assert!(frames.iter().rev().take(STOP_FRAMES).all(|(at, _)| *at >= discarded_at));
    }

    #[test]
    #[ignore = "timing group: the sender's own 20 ms clock on a real thread; .ci/run runs it alone"]
    fn stop_frames_stuck_in_a_queue_that_never_drains_are_not_a_confirmed_stop() {
        let link = Arc::new(FaultyLink::default());
        let sender = start(&link, Limits::default());
        keep_asking(&sender, 0.3, Duration::from_millis(60));
        // The adapter stops sending: three frames stay queued whatever is discarded.
        *link.stuck.lock().unwrap() = Some(3);
        let stats = sender.stop();
        assert_eq!(stats.stop_frames_sent, Some(STOP_FRAMES), "the link took them");
        assert_eq!(stats.stop_frames_queued, 3, "but they did not leave");
        assert!(!stats.stop_confirmed(), "so the stop is not reported as done");
    }
}
