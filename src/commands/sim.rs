//! `tracerctl sim`: a virtual TRACER on a CAN interface, a serial port, or a new pseudo-terminal.
//!
//! Faults come from `--fault NAME@TIME` and, at run time, from lines on standard input (`estop`,
//! `estop-release`, any fault name; `sim --help` documents the language): a test or a trainer in the
//! simulator's terminal can press the E-stop mid-run.

use std::io::{BufRead, Write};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

use super::Global;
use crate::exit::SUCCESS;
use crate::link::{self, Link, LinkChoice};
use crate::signals;
use crate::sim::{serve, FaultKind, RcSwitch, ScheduledFault, SimConfig, SimParamSetting, SimState, SimWire};

/// `tracerctl sim`'s settings (checked by the command line: times and ranges within bounds, `pty` only
/// with the default link).
#[derive(Clone, Debug)]
pub struct Options {
    /// Serve on a new pseudo-terminal instead of the link.
    pub pty: bool,
    pub faults: Vec<ScheduledFault>,
    /// Chassis parameters (`--sim-param NAME=VALUE`, checked), applied after `battery` and `drain`.
    pub params: Vec<SimParamSetting>,
    /// An RC transmitter is on, with SWB here.
    pub rc: Option<RcSwitch>,
    /// Starting battery voltage.
    pub battery: Option<f64>,
    /// Battery drain speed-up factor.
    pub drain: Option<f64>,
    /// Stop after this long; `None`: until a signal.
    pub duration: Option<Duration>,
}

pub fn run(global: &Global, args: &Options) -> Result<u8> {
    let mut config = SimConfig::default();
    config.faults.extend(args.faults.iter().copied());
    if let Some(swb) = args.rc {
        config.rc_present = true;
        config.rc_swb = swb;
    }
    if let Some(volts) = args.battery {
        // As `--sim-param battery-ocv`: a pack at or under the empty voltage lowers "empty" below it
        // (otherwise the model would fall back to its default 26 V).
        let ocv = crate::sim::SimParam::find("battery-ocv").expect("a parameter of the table");
        SimParamSetting { param: ocv, value: crate::sim::ParamValue::Number(volts) }.apply(&mut config);
    }
    if let Some(factor) = args.drain {
        config.battery_drain_factor = factor;
    }
    args.params.iter().for_each(|param| param.apply(&mut config));

    let link = open_served_link(global, args.pty, &mut config)?;
    let params = config.non_default_params();
    if !params.is_empty() {
        let mut stdout = std::io::stdout().lock();
        writeln!(stdout, "chassis parameters: {}", params.join(" "))?;
        stdout.flush()?;
    }
    serve_until_done(config, link, args.duration)
}

/// A new pseudo-terminal, its name announced on standard output.
#[cfg(unix)]
fn open_pty(stdout: &mut impl Write) -> Result<Link> {
    let (master, slave) = serialport::TTYPort::pair().context("cannot create a pseudo-terminal")?;
    let path = serialport::SerialPort::name(&slave).context("the pseudo-terminal has no name")?;
    // Close our handle on the terminal side so the host can open it (it is opened exclusively).
    drop(slave);
    write!(stdout, "PTY {path}\nconnect with: tracerctl --serial {path} monitor\n")?;
    stdout.flush()?;
    link::serial::from_port(Box::new(master), &path, true)
}

/// The command line refuses `--pty` where there are no pseudo-terminals.
#[cfg(not(unix))]
fn open_pty(_: &mut impl Write) -> Result<Link> {
    anyhow::bail!("--pty needs Unix pseudo-terminals")
}

/// The link to serve on (a new pseudo-terminal with `pty`), announced on standard output; the wire follows.
fn open_served_link(global: &Global, pty: bool, config: &mut SimConfig) -> Result<Link> {
    let mut stdout = std::io::stdout().lock();
    let link = if pty {
        config.wire = SimWire::Serial;
        open_pty(&mut stdout)?
    } else {
        match global.link.clone() {
            LinkChoice::Serial { path, baud } => {
                config.wire = SimWire::Serial;
                link::serial::open(&path, baud)?
            }
            choice => {
                let (link, _) = crate::session::open_link(&choice, None)?;
                writeln!(stdout, "serving a virtual TRACER on {}", link.name)?;
                stdout.flush()?;
                link
            }
        }
    };
    Ok(link)
}

/// Serves until a signal, the duration or the end of the link, injecting faults read from standard input and
/// reporting changes on stderr.
fn serve_until_done(config: SimConfig, link: Link, duration: Option<Duration>) -> Result<u8> {
    let link_kind = link.kind;
    let running = serve::start(config, link)?;
    let signal = signals::listen(|_| {})?;
    let inbox = read_stdin_lines()?;

    let started = Instant::now();
    let mut last_report = String::new();
    // Reported at 1, 10, 100, ... frames: a flooded bus must not flood stderr too.
    let mut next_not_sent_report = 1;
    // The status lines are for a person watching; with nobody reading them (a closed stderr) the simulator
    // goes on serving.
    let mut stderr = std::io::stderr().lock();
    while signal.caught().is_none() && duration.is_none_or(|d| started.elapsed() < d) {
        if running.has_ended() {
            break;
        }
        inject_faults(&running, &inbox, &mut stderr);
        let not_sent = running.not_sent();
        if not_sent >= next_not_sent_report {
            let _ = writeln!(
                stderr,
                "sim {:7.2} s: {not_sent} feedback frames not sent so far ({}); still running",
                started.elapsed().as_secs_f64(),
                link::queue_full_meaning(link_kind)
            );
            next_not_sent_report = not_sent.saturating_mul(10).max(1);
        }
        let report = summary(&running.state());
        if report != last_report {
            let _ = writeln!(stderr, "sim {:7.2} s: {report}", started.elapsed().as_secs_f64());
            last_report = report;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let not_sent = running.not_sent();
    running.stop().context("the simulator stopped")?;
    if not_sent > 0 {
        let _ = writeln!(
            stderr,
            "sim: {not_sent} feedback frames not sent ({})",
            link::queue_full_meaning(link_kind)
        );
    }
    Ok(SUCCESS)
}

/// The lines of standard input, read on their own thread (a test or a second terminal types faults there).
fn read_stdin_lines() -> Result<mpsc::Receiver<String>> {
    let (lines, inbox) = mpsc::channel::<String>();
    std::thread::Builder::new()
        .name("tracerctl-sim-stdin".into())
        .spawn(move || {
            for line in std::io::stdin().lock().lines().map_while(Result::ok) {
                if lines.send(line).is_err() {
                    break;
                }
            }
        })
        .context("cannot start the input thread")?;
    Ok(inbox)
}

/// Injects each fault named by a line that came in; says what it did with each non-empty line.
fn inject_faults(running: &serve::Running, inbox: &mpsc::Receiver<String>, stderr: &mut impl Write) {
    while let Ok(line) = inbox.try_recv() {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        match line.parse::<FaultKind>() {
            Ok(fault) => {
                running.inject(fault);
                let _ = writeln!(stderr, "sim: injected {line}");
            }
            // A time has no meaning here: say so rather than call a known name unknown.
            Err(_) if line.split_once('@').is_some_and(|(name, _)| name.parse::<FaultKind>().is_ok()) => {
                let name = line.split('@').next().unwrap_or_default().trim();
                let _ = writeln!(
                    stderr,
                    "sim: not injected: a fault typed here acts at once, so type the name alone ({name}); \
                     --fault NAME@TIME schedules one from the start"
                );
            }
            Err(error) => {
                let _ = writeln!(stderr, "sim: {error}");
            }
        }
    }
}

/// One line of what changed that a person watching the simulator cares about (no speeds: they change
/// every frame; mode, vehicle state, faults, battery to 0.1 V and what blocks motion).
fn summary(state: &SimState) -> String {
    let vehicle = crate::protocol::message::vehicle_state_name(state.vehicle_state).unwrap_or("unknown");
    let blocked = state.motion_block.map(|block| format!(", motion blocked: {block}")).unwrap_or_default();
    format!(
        "mode {}, {vehicle}, {:.1} V, fault code 0x{:04X}{blocked}",
        state.control_mode, state.battery_voltage, state.fault_code
    )
}
