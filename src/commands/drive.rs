//! `tracerctl drive`: drive at a fixed speed, ramped and capped, with zero-velocity frames on every way out.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

use anyhow::Result;

use super::live;
use crate::cli::{Cli, DriveArgs};
use crate::control::{Limits, MotionSender};
use crate::exit::{Failure, SUCCESS};
use crate::link::Codec;
use crate::protocol::message::MODE_CAN;
use crate::protocol::Wire;
use crate::session::Session;
use crate::signals;

/// The main loop refreshes the target this often; the watchdog zeroes it if that stops for this long.
const REFRESH: Duration = Duration::from_millis(20);
const WATCHDOG: Duration = Duration::from_millis(250);
/// Status line rate on a terminal; in a pipe or log, one line a second.
const STATUS_EVERY_TTY: Duration = Duration::from_millis(250);
const STATUS_EVERY_PIPE: Duration = Duration::from_secs(1);
/// Re-enable command mode at most this often when the robot reports another mode.
const MODE_RETRY: Duration = Duration::from_millis(200);
/// The robot sends feedback every 20 ms; this long without any frame means the link is gone.
const FEEDBACK_LOST: Duration = Duration::from_secs(1);

/// Why the drive ended.
#[derive(Debug, PartialEq)]
enum End {
    TimeUp,
    Signal(&'static str, u8),
    EStop,
    LinkLost(String),
}

pub fn run(cli: &Cli, args: &DriveArgs) -> Result<u8> {
    let limits = args.limits.limits()?;
    anyhow::ensure!(
        args.linear.is_finite() && args.angular.is_finite(),
        "--linear and --angular must be numbers"
    );
    let session = live::open(cli, true)?;
    execute(&session, args, limits, &mut std::io::stderr())
}

/// Drives on an open session; progress and the result go to `out`.
pub fn execute(session: &Session, args: &DriveArgs, limits: Limits, out: &mut impl Write) -> Result<u8> {
    let target = (
        args.linear.clamp(-limits.max_linear, limits.max_linear),
        args.angular.clamp(-limits.max_angular, limits.max_angular),
    );
    if target != (args.linear, args.angular) {
        writeln!(
            out,
            "capped: {:+.3} m/s {:+.3} rad/s -> {:+.3} m/s {:+.3} rad/s (--max-linear {}, --max-angular {})",
            args.linear, args.angular, target.0, target.1, limits.max_linear, limits.max_angular
        )?;
    }

    match live::first_status(session) {
        Some((state, wire)) => {
            let protocol = match wire {
                Wire::Serial => "RS232".to_string(),
                _ => session.status().detector.describe(),
            };
            writeln!(out, "robot: {} (protocol {protocol})", live::describe(&state, wire))?;
            if let Some(reason) = live::not_drivable(&state, wire) {
                if !args.ignore_faults {
                    return Err(Failure::not_done(format!(
                        "not driving: {reason} (--ignore-faults to try anyway)"
                    ))
                    .into());
                }
                writeln!(out, "warning: {reason}; driving anyway (--ignore-faults)")?;
            }
        }
        None => {
            let reason = live::no_status_message(session, &session.status());
            if !args.ignore_faults {
                return Err(Failure::not_done(format!(
                    "not driving: {reason} (--ignore-faults to try anyway)"
                ))
                .into());
            }
            writeln!(out, "warning: {reason}; driving anyway (--ignore-faults)")?;
        }
    }

    let sender = MotionSender::start(session.tx.clone(), Codec::new(session.wire()), limits, WATCHDOG)?;
    // A signal stops the robot from the signal thread at once; the loop below notices and reports.
    let stopper = sender.stopper();
    let signal = signals::listen(move |_| stopper.stop_now())?;

    let started = Instant::now();
    let mut last_status = Instant::now() - STATUS_EVERY_PIPE;
    let mut last_mode_request = Instant::now();
    let status_every = if std::io::stderr().is_terminal() { STATUS_EVERY_TTY } else { STATUS_EVERY_PIPE };
    let end = loop {
        if let (Some(signo), name) = (signal.exit_status(), signal.name()) {
            break End::Signal(name, signo);
        }
        if args.duration.is_some_and(|duration| started.elapsed() >= duration) {
            break End::TimeUp;
        }
        sender.set_target(target.0, target.1);
        if crate::control::panicked() {
            break End::LinkLost("an internal error (a thread panicked); the robot was stopped".to_string());
        }
        let status = session.status();
        if let Some(error) = status.link_error.clone() {
            break End::LinkLost(error);
        }
        // Had feedback, and it stopped: do not keep driving blind.
        if status.last_frame.is_some_and(|at| at.elapsed() > FEEDBACK_LOST) {
            break End::LinkLost(format!("no frames from the robot for {} s", FEEDBACK_LOST.as_secs()));
        }
        if let Some((state, wire)) = status.fresh_system(Duration::from_millis(200)) {
            if state.is_estop() && !args.ignore_faults {
                break End::EStop;
            }
            // Power-cycle or RC override put the robot in another mode: ask for command mode again.
            if wire == Wire::CanV2
                && state.control_mode != MODE_CAN
                && last_mode_request.elapsed() >= MODE_RETRY
            {
                sender.request_mode_enable();
                last_mode_request = Instant::now();
            }
        }
        if last_status.elapsed() >= status_every {
            write_status(out, started.elapsed(), target, &sender, session, status_every == STATUS_EVERY_TTY)?;
            last_status = Instant::now();
        }
        std::thread::sleep(REFRESH);
    };

    let stats = match end {
        End::TimeUp => sender.ramp_down_and_stop(&limits),
        _ => sender.stop(),
    };
    if status_every == STATUS_EVERY_TTY {
        writeln!(out)?;
    }
    let summary = format!(
        "{} motion frames sent ({} send errors, {} watchdog stops); last command {:+.3} m/s {:+.3} rad/s",
        stats.frames,
        stats.send_errors,
        stats.watchdog_trips,
        stats.sent.linear(),
        stats.sent.angular()
    );
    let elapsed = started.elapsed().as_secs_f64();
    match end {
        End::TimeUp => {
            writeln!(out, "stopped after {elapsed:.2} s (time up): {summary}")?;
            Ok(SUCCESS)
        }
        End::Signal(name, status) => {
            writeln!(out, "stopped after {elapsed:.2} s ({name}): {summary}")?;
            Ok(status)
        }
        End::EStop => {
            Err(Failure::not_done(format!("stopped after {elapsed:.2} s: the E-stop was pressed; {summary}"))
                .into())
        }
        End::LinkLost(error) => anyhow::bail!(
            "stopped after {elapsed:.2} s: the link {} failed ({error}); {summary}",
            session.name
        ),
    }
}

fn write_status(
    out: &mut impl Write,
    elapsed: Duration,
    target: (f64, f64),
    sender: &MotionSender,
    session: &Session,
    overwrite: bool,
) -> Result<()> {
    let sent = sender.stats().sent;
    let status = session.status();
    let measured = status
        .motion
        .map(|(_, m)| format!("{:+.3} m/s {:+.3} rad/s", m.linear(), m.angular()))
        .unwrap_or_else(|| "-".to_string());
    let robot = status
        .fresh_system(Duration::from_millis(500))
        .map(|(state, wire)| live::describe(&state, wire))
        .unwrap_or_else(|| "no status".to_string());
    let line = format!(
        "{:6.2} s  target {:+.3} m/s {:+.3} rad/s  sent {:+.3} {:+.3}  measured {measured}  {robot}",
        elapsed.as_secs_f64(),
        target.0,
        target.1,
        sent.linear(),
        sent.angular()
    );
    if overwrite {
        write!(out, "\r\x1b[K{line}")?;
    } else {
        writeln!(out, "{line}")?;
    }
    if let Some(error) = sender.last_error() {
        writeln!(out, "\nsend error: {error}")?;
    }
    out.flush()?;
    Ok(())
}
