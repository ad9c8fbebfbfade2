//! `tracerctl doctor`: why isn't it moving? Checks, in order, everything between this machine and the
//! wheels, and prints PASS / WARN / FAIL per check with what to do:
//!
//! 1. the link: SocketCAN in the kernel, the interface, up, 500 kbit/s, its error state (or the serial
//!    port and baud rate);
//! 2. what the robot sends while we listen: frames, protocol version (or the RS232 frame stream), the
//!    system status rate, other controllers on the bus, control mode and RC override, E-stop, faults,
//!    battery, motors;
//! 3. with `--probe`: whether the robot takes a control-mode command and zero-velocity motion commands.
//!    The probe never commands motion; it puts back a standby or serial mode it changed.
//!
//! Exit status 0 when the robot can be driven (no FAIL), 4 when it cannot.

mod link_checks;
mod probe;
pub mod report;
pub mod robot;

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

use anyhow::Result;

use super::Global;
use crate::exit::{Failure, NOT_DONE, SUCCESS, USAGE};
use crate::link::LinkChoice;
use crate::session::Session;
use crate::signals::Caught;
use report::{Check, Report};

/// `tracerctl doctor`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// Also check that the robot takes commands.
    pub probe: bool,
    /// How long to listen to the robot.
    pub listen: Duration,
    pub format: report::ReportFormat,
    /// The battery's warning voltage: the manual's, or the configuration's `battery.warning_volts`.
    pub battery_warning_volts: f64,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let choice = global.link.clone();
    if args.probe && matches!(choice, LinkChoice::Replay { .. }) {
        return Err(Failure {
            code: USAGE,
            message: "--probe sends commands and needs a live link; --replay is read-only".to_string(),
        }
        .into());
    }
    let stdout = std::io::stdout();
    let color = global.color.enabled(stdout.is_terminal());
    let mut out = stdout.lock();
    let mut report = Report::new(&mut out, args.format, color, link_name(&choice));
    report.heading(&heading(global, args))?;

    let opened = check_link(&choice, &mut report)?;
    let open = || Session::open(&choice, global.protocol, global.sim_config());
    let session = if opened { open_session(&choice, open, &mut report)? } else { None };
    let signal = match &session {
        Some(session) => examine(session, args, &mut report)?,
        None => {
            let can = matches!(choice, LinkChoice::SocketCan { .. });
            add_all(&mut report, robot::skipped("frames", "motors", "the link is not usable", can))?;
            None
        }
    };
    let drivable = report.finish(args.probe && session.is_some())?;
    Ok(exit_status(drivable, signal))
}

/// The checks before opening (the CAN interface, or the serial port); whether the link can be opened.
fn check_link<W: Write>(choice: &LinkChoice, report: &mut Report<W>) -> Result<bool> {
    Ok(match choice {
        #[cfg(target_os = "linux")]
        LinkChoice::SocketCan { iface } => {
            let (checks, ok) = link_checks::can_interface(iface);
            add_all(report, checks)?;
            ok
        }
        #[cfg(not(target_os = "linux"))]
        LinkChoice::SocketCan { .. } => {
            report.add(Check::fail(
                "kernel_can",
                "kernel CAN",
                "SocketCAN exists only on Linux",
                "use --serial PORT, or run on Linux",
            ))?;
            false
        }
        LinkChoice::Serial { path, baud } => {
            let checks = link_checks::serial_port(path, *baud);
            let exists = !checks.iter().any(|check| check.outcome == report::Outcome::Fail);
            add_all(report, checks)?;
            exists
        }
        LinkChoice::Sim => {
            report.add(Check::pass("link", "link", "in-process virtual TRACER (--sim)"))?;
            true
        }
        LinkChoice::Replay { path, .. } => {
            report.add(Check::pass("link", "link", format!("replaying {} (read-only)", path.display())))?;
            true
        }
    })
}

/// The first line of the text report: the link, the protocol, how long it listens.
fn heading(global: &Global, args: &Options) -> String {
    format!(
        "tracerctl doctor: {}, protocol {}, listening {}{}",
        describe_link(&global.link),
        format!("{:?}", global.protocol).to_ascii_lowercase(),
        humantime::format_duration(args.listen),
        if args.probe { ", then probing" } else { "" }
    )
}

/// What the doctor found, kept rather than printed (`tracerctl report` writes it in both formats).
pub struct Diagnosis {
    pub heading: String,
    pub link: String,
    pub checks: Vec<Check>,
    /// The session the checks ran on, still open for the caller; `None` when the link could not be used.
    pub session: Option<Session>,
    pub probed: bool,
    /// The signal that cut the probe short.
    pub interrupted: Option<Caught>,
}

impl Diagnosis {
    /// The report as `doctor --format FORMAT` prints it (without colour).
    pub fn render(&self, format: report::ReportFormat) -> std::io::Result<Vec<u8>> {
        let mut out = Vec::new();
        let mut report = Report::new(&mut out, format, false, self.link.clone());
        report.heading(&self.heading)?;
        add_all(&mut report, self.checks.clone())?;
        if let Some(caught) = self.interrupted {
            report.interrupt(caught);
        }
        report.finish(self.probed)?;
        Ok(out)
    }

    /// True when no check failed.
    pub fn drivable(&self) -> bool {
        self.checks.iter().all(|check| check.outcome != report::Outcome::Fail)
    }
}

/// Runs the doctor's checks on `global`'s link without printing them: the link checks, then, on the session
/// `open` gives, the listen and the robot checks (and the probe when asked). For `tracerctl report`, which
/// opens the session its own way and uses it afterwards.
pub fn diagnose(
    global: &Global,
    args: &Options,
    open: impl FnOnce() -> Result<Session>,
) -> Result<Diagnosis> {
    let choice = &global.link;
    let mut sink = std::io::sink();
    // JSON prints nothing until `finish`, which is never called: the checks are only collected.
    let mut report = Report::new(&mut sink, report::ReportFormat::Json, false, link_name(choice));
    let opened = check_link(choice, &mut report)?;
    let session = if opened { open_session(choice, open, &mut report)? } else { None };
    let signal = match &session {
        Some(session) => examine_caught(session, args, &mut report)?,
        None => {
            let can = matches!(choice, LinkChoice::SocketCan { .. });
            add_all(&mut report, robot::skipped("frames", "motors", "the link is not usable", can))?;
            None
        }
    };
    Ok(Diagnosis {
        heading: heading(global, args),
        link: link_name(choice),
        checks: report.checks().to_vec(),
        probed: args.probe && session.is_some(),
        session,
        interrupted: signal,
    })
}

/// Opens the session, reporting the serial port open (or the link that could not be opened).
fn open_session<W: Write>(
    choice: &LinkChoice,
    open: impl FnOnce() -> Result<Session>,
    report: &mut Report<W>,
) -> Result<Option<Session>> {
    match open() {
        Ok(session) => {
            if let LinkChoice::Serial { path, baud } = choice {
                report.add(Check::pass(
                    "serial_port",
                    "serial port",
                    format!("{} open at {baud} baud, 8N1", path.display()),
                ))?;
            }
            Ok(Some(session))
        }
        Err(error) => {
            let (id, title) = match choice {
                LinkChoice::Serial { .. } => ("serial_port", "serial port"),
                _ => ("open", "open link"),
            };
            report.add(Check::fail(id, title, "cannot open the link", format!("{error:#}")))?;
            Ok(None)
        }
    }
}

fn exit_status(drivable: bool, signal: Option<u8>) -> u8 {
    match (signal, drivable) {
        (Some(status), _) => status,
        (None, true) => SUCCESS,
        (None, false) => NOT_DONE,
    }
}

/// Runs the checks of what the robot sends (and the probe) on an open session; prints the report to
/// `out` and returns the exit status. The tests' entry point (`run` adds the link checks first).
pub fn execute(session: &Session, args: &Options, out: &mut impl Write) -> Result<u8> {
    let mut report = Report::new(out, args.format, false, session.name.clone());
    let signal = examine(session, args, &mut report)?;
    let drivable = report.finish(args.probe)?;
    Ok(exit_status(drivable, signal))
}

/// Listens for `--listen`, checks what arrived, then probes if asked. The exit status of a termination
/// signal that interrupted the probe, if one did.
fn examine<W: Write>(session: &Session, args: &Options, report: &mut Report<W>) -> Result<Option<u8>> {
    Ok(examine_caught(session, args, report)?.map(Caught::exit_status))
}

/// As [`examine`], giving the signal itself.
fn examine_caught<W: Write>(
    session: &Session,
    args: &Options,
    report: &mut Report<W>,
) -> Result<Option<Caught>> {
    let started = Instant::now();
    // A link that fails ends the listening early; everything else is heard out.
    session.wait_for(args.listen, |status| status.link_error.as_ref().map(|_| ()));
    // Encode for V1 if that is what the robot turned out to speak (auto mode).
    session.settle_protocol(Duration::ZERO);
    let status = session.status();
    let seen = robot::Observation {
        status: &status,
        listened: started.elapsed(),
        link: &session.name,
        kind: session.kind,
        wire: session.wire(),
        hint: session.hint(),
        now: Instant::now(),
        battery_warning_dv: crate::protocol::constants::decivolts(args.battery_warning_volts),
    };
    let checks = robot::checks(&seen);
    add_all(report, checks)?;
    if args.probe {
        if status.system.is_none() {
            report.add(Check::skip(
                "probe_mode",
                "probe: mode",
                "no system status to confirm a command with",
            ))?;
            report.add(Check::skip("probe_motion", "probe: zero motion", "no system status"))?;
        } else {
            // The probe only ever sends zero velocity; a signal ends it early and cleanly.
            let signals = crate::signals::listen(|_| {})?;
            let cut_short = probe::run(session, &signals, &mut |check| Ok(report.add(check)?))?;
            let caught = signals.caught();
            if let (true, Some(caught)) = (cut_short, caught) {
                report.interrupt(caught);
            }
            return Ok(caught);
        }
    }
    Ok(None)
}

fn add_all<W: Write>(report: &mut Report<W>, checks: Vec<Check>) -> std::io::Result<()> {
    for check in checks {
        report.add(check)?;
    }
    Ok(())
}

fn link_name(choice: &LinkChoice) -> String {
    match choice {
        LinkChoice::SocketCan { iface } => iface.clone(),
        LinkChoice::Serial { path, .. } => path.display().to_string(),
        LinkChoice::Sim => "sim".to_string(),
        LinkChoice::Replay { path, .. } => path.display().to_string(),
    }
}

fn describe_link(choice: &LinkChoice) -> String {
    match choice {
        LinkChoice::SocketCan { iface } => format!("{iface} (SocketCAN)"),
        LinkChoice::Serial { path, baud } => format!("{} (RS232, {baud} baud)", path.display()),
        LinkChoice::Sim => "the in-process virtual TRACER".to_string(),
        LinkChoice::Replay { path, .. } => format!("{} (replay)", path.display()),
    }
}
