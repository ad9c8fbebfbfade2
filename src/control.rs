//! The 50 Hz motion sender: its own clock, caps, ramps, a watchdog, and zero-velocity frames on every way out.
//!
//! The sender thread wakes on an absolute 20 ms grid (late wake-ups skip ticks rather than burst). Each tick it
//! takes the latest target, zeroes it if the target is older than the watchdog (input stalled), clamps it to
//! the caps, moves the sent command towards it by at most the acceleration limits, and sends it. Stopping, by
//! [`MotionSender::stop`], by dropping the sender (errors, panics that unwind), by the panic hook (panics on
//! any thread), or by a termination signal, sends zero-velocity frames at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, OnceLock};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use crate::link::{Codec, FrameTx, LinkFrame};
use crate::protocol::message::{MotionCommand, ANGULAR_LIMIT, LINEAR_LIMIT};

/// The chassis wants a motion command every 20 ms (and stops by itself after 500 ms without one).
pub const PERIOD: Duration = Duration::from_millis(20);
/// How many zero-velocity frames end a drive (a lost frame or two must not matter).
pub const STOP_FRAMES: usize = 3;

/// Caps and ramps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// m/s; never above the protocol limit.
    pub max_linear: f64,
    /// rad/s.
    pub max_angular: f64,
    /// m/s².
    pub linear_accel: f64,
    /// rad/s².
    pub angular_accel: f64,
}

impl Default for Limits {
    /// Safe defaults for driving next to people: 0.5 m/s, 0.5 rad/s, reached in about a second.
    fn default() -> Self {
        Self { max_linear: 0.5, max_angular: 0.5, linear_accel: 0.5, angular_accel: 1.0 }
    }
}

impl Limits {
    /// Clamps caps to the protocol limits and rejects nonsense.
    pub fn validated(self) -> Result<Self> {
        let positive = |value: f64, what: &str| {
            anyhow::ensure!(
                value.is_finite() && value > 0.0,
                "{what} must be a positive number, not {value}"
            );
            Ok(())
        };
        positive(self.max_linear, "--max-linear")?;
        positive(self.max_angular, "--max-angular")?;
        positive(self.linear_accel, "--accel")?;
        positive(self.angular_accel, "--angular-accel")?;
        Ok(Self {
            max_linear: self.max_linear.min(LINEAR_LIMIT),
            max_angular: self.max_angular.min(ANGULAR_LIMIT),
            ..self
        })
    }
}

/// One step of the sender's control law: clamp the target, then move `current` towards it within the
/// acceleration allowed in `dt`. Pure, so the ramp is tested without threads.
pub fn ramp_step(current: (f64, f64), target: (f64, f64), limits: &Limits, dt: Duration) -> (f64, f64) {
    let dt = dt.as_secs_f64();
    let clamp = |value: f64, cap: f64| if value.is_nan() { 0.0 } else { value.clamp(-cap, cap) };
    let toward = |from: f64, to: f64, step: f64| from + (to - from).clamp(-step, step);
    (
        toward(current.0, clamp(target.0, limits.max_linear), limits.linear_accel * dt),
        toward(current.1, clamp(target.1, limits.max_angular), limits.angular_accel * dt),
    )
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
    pub frames: u64,
    pub send_errors: u64,
    pub mode_frames: u64,
    /// Ticks where the watchdog zeroed a stale target.
    pub watchdog_trips: u64,
}

struct Shared {
    target: Mutex<Target>,
    stats: Mutex<SenderStats>,
    stop: AtomicBool,
    /// Set by whoever sees the robot in another control mode: send the mode-enable frame next tick.
    enable_mode: AtomicBool,
    /// A new target that should not wait for the next tick (a key press): send now, restart the grid.
    kicked: AtomicBool,
    last_error: Mutex<Option<String>>,
}

/// Stops the sender from another thread (a signal handler thread): zero-velocity frames at once.
#[derive(Clone)]
pub struct Stopper {
    shared: Arc<Shared>,
    thread: std::thread::Thread,
}

impl Stopper {
    pub fn stop_now(&self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.thread.unpark();
    }
}

/// The running sender. Dropping it stops the robot.
pub struct MotionSender {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    tx: Arc<dyn FrameTx>,
    stop_frame: LinkFrame,
}

/// Set by the panic hook: after a panic on any thread, no sender moves the robot again in this process.
static PANICKED: AtomicBool = AtomicBool::new(false);

/// True once any thread of this process has panicked.
pub fn panicked() -> bool {
    PANICKED.load(Ordering::SeqCst)
}

/// The frame and link the panic hook uses to stop the robot.
type Emergency = (Arc<dyn FrameTx>, LinkFrame);
static EMERGENCY: OnceLock<Mutex<Option<Emergency>>> = OnceLock::new();

fn emergency() -> &'static Mutex<Option<Emergency>> {
    EMERGENCY.get_or_init(|| Mutex::new(None))
}

/// Sends zero-velocity frames on the link of the running sender, if any (used by panic hooks).
pub fn emergency_stop() {
    PANICKED.store(true, Ordering::SeqCst);
    if let Ok(guard) = emergency().try_lock() {
        if let Some((tx, frame)) = guard.as_ref() {
            for _ in 0..STOP_FRAMES {
                let _ = tx.send(frame);
            }
        }
    }
}

/// Installs (once) a panic hook that sends zero-velocity frames before the usual panic report.
pub fn install_panic_hook() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            emergency_stop();
            previous(info);
        }));
    });
}

impl MotionSender {
    /// Starts sending at 50 Hz. `codec` encodes for the link's wire; `watchdog` is how old a target may get
    /// before the sender treats input as stalled and commands zero.
    pub fn start(tx: Arc<dyn FrameTx>, mut codec: Codec, limits: Limits, watchdog: Duration) -> Result<Self> {
        install_panic_hook();
        let stop_frame = codec.motion(MotionCommand::STOP);
        *emergency().lock().unwrap_or_else(|p| p.into_inner()) = Some((Arc::clone(&tx), stop_frame));
        let shared = Arc::new(Shared {
            target: Mutex::new(Target { linear: 0.0, angular: 0.0, set_at: Instant::now() }),
            stats: Mutex::new(SenderStats::default()),
            stop: AtomicBool::new(false),
            enable_mode: AtomicBool::new(true),
            kicked: AtomicBool::new(false),
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

    /// Sets what to drive at (m/s, rad/s); also tells the watchdog that input is alive.
    pub fn set_target(&self, linear: f64, angular: f64) {
        *self.shared.target.lock().unwrap_or_else(|p| p.into_inner()) =
            Target { linear, angular, set_at: Instant::now() };
    }

    /// Sets the target and sends it now rather than at the next tick (for a key press: the first changed
    /// frame leaves within a millisecond; the 20 ms grid restarts from it).
    pub fn set_target_now(&self, linear: f64, angular: f64) {
        self.set_target(linear, angular);
        self.shared.kicked.store(true, Ordering::SeqCst);
        if let Some(thread) = &self.thread {
            thread.thread().unpark();
        }
    }

    /// Asks for the mode-enable frame (0x421 = CAN on V2) before the next motion frame.
    pub fn request_mode_enable(&self) {
        self.shared.enable_mode.store(true, Ordering::SeqCst);
    }

    pub fn stats(&self) -> SenderStats {
        *self.shared.stats.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The sender's error, if sending failed (the thread keeps trying).
    pub fn last_error(&self) -> Option<String> {
        self.shared.last_error.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }

    /// True while the sender thread runs.
    pub fn is_running(&self) -> bool {
        self.thread.as_ref().is_some_and(|thread| !thread.is_finished())
    }

    /// Ramps down to zero within the acceleration limits (for a normal end), then stops.
    pub fn ramp_down_and_stop(self, limits: &Limits) -> SenderStats {
        self.set_target(0.0, 0.0);
        let sent = self.stats().sent;
        let seconds =
            (sent.linear().abs() / limits.linear_accel).max(sent.angular().abs() / limits.angular_accel);
        let deadline = Instant::now() + Duration::from_secs_f64(seconds.min(5.0)) + PERIOD * 2;
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
                for _ in 0..STOP_FRAMES {
                    let _ = self.tx.send(&self.stop_frame);
                }
            }
        }
        *emergency().lock().unwrap_or_else(|p| p.into_inner()) = None;
    }
}

impl Drop for MotionSender {
    fn drop(&mut self) {
        self.shutdown();
    }
}

fn send_loop(shared: &Shared, tx: &dyn FrameTx, codec: &mut Codec, limits: Limits, watchdog: Duration) {
    let mut next_tick = Instant::now();
    let mut current = (0.0, 0.0);
    let mut last_tick = Instant::now();
    let record = |result: std::io::Result<()>, mode: bool| {
        let mut stats = shared.stats.lock().unwrap_or_else(|p| p.into_inner());
        match result {
            Ok(()) if mode => stats.mode_frames += 1,
            Ok(()) => stats.frames += 1,
            Err(error) => {
                stats.send_errors += 1;
                *shared.last_error.lock().unwrap_or_else(|p| p.into_inner()) = Some(error.to_string());
            }
        }
    };
    loop {
        if shared.stop.load(Ordering::SeqCst) || panicked() {
            break;
        }
        let now = Instant::now();
        let target = *shared.target.lock().unwrap_or_else(|p| p.into_inner());
        let stale = now.duration_since(target.set_at) > watchdog;
        let wanted = if stale { (0.0, 0.0) } else { (target.linear, target.angular) };
        if stale && (target.linear != 0.0 || target.angular != 0.0) {
            shared.stats.lock().unwrap_or_else(|p| p.into_inner()).watchdog_trips += 1;
        }
        // At least one period's step: a frame sent early for a key press must already move (it restarts the
        // grid, so the ramp gains at most one step per press).
        current =
            ramp_step(current, wanted, &limits, now.duration_since(last_tick).clamp(PERIOD, PERIOD * 5));
        last_tick = now;
        if shared.enable_mode.swap(false, Ordering::SeqCst) {
            record(tx.send(&codec.enable_command_mode()), true);
        }
        let (command, _) = MotionCommand::clamped_from_si(current.0, current.1);
        record(tx.send(&codec.motion(command)), false);
        shared.stats.lock().unwrap_or_else(|p| p.into_inner()).sent = command;

        // Next point on the 20 ms grid; if we are late by whole periods, skip them rather than burst.
        next_tick += PERIOD;
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
    }
    // Every way out of the loop ends here: zero velocity, several times (each frame encoded anew, so
    // RS232 frame ids keep rolling).
    for _ in 0..STOP_FRAMES {
        record(tx.send(&codec.motion(MotionCommand::STOP)), false);
    }
    shared.stats.lock().unwrap_or_else(|p| p.into_inner()).sent = MotionCommand::STOP;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::Wire;
    use std::sync::mpsc;

    #[test]
    fn ramp_respects_acceleration_and_caps() {
        let limits = Limits { max_linear: 0.5, max_angular: 0.4, linear_accel: 0.5, angular_accel: 1.0 };
        let mut current = (0.0, 0.0);
        current = ramp_step(current, (2.0, -2.0), &limits, PERIOD);
        assert!((current.0 - 0.01).abs() < 1e-12 && (current.1 + 0.02).abs() < 1e-12, "{current:?}");
        for _ in 0..100 {
            current = ramp_step(current, (2.0, -2.0), &limits, PERIOD);
        }
        assert_eq!(current, (0.5, -0.4), "capped");
        current = ramp_step(current, (0.0, 0.0), &limits, PERIOD);
        assert!((current.0 - 0.49).abs() < 1e-12);
        assert_eq!(ramp_step((0.0, 0.0), (f64::NAN, 0.1), &limits, PERIOD).0, 0.0);
    }

    #[test]
    fn limits_are_validated_and_clamped_to_the_protocol() {
        let limits = Limits { max_linear: 9.0, ..Limits::default() }.validated().unwrap();
        assert_eq!(limits.max_linear, LINEAR_LIMIT);
        assert!(Limits { linear_accel: 0.0, ..Limits::default() }.validated().is_err());
        assert!(Limits { max_angular: f64::NAN, ..Limits::default() }.validated().is_err());
    }

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
}
