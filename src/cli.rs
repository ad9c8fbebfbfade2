//! The command line: the single source for parsing, `--help`, shell completions and man pages, and the
//! boundary of the program. Here clap's arguments become the plain settings of each command (checked once,
//! with errors that name the options); [`run`] dispatches them. Nothing else in the crate knows clap or
//! the options' spelling.

use std::path::PathBuf;
use std::time::Duration;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::commands::{self, usage, Global};
use crate::control::limits::{LimitError, LimitName, Limits};
use crate::link::LinkChoice;
use crate::output::stamp::TimeMode;
use crate::output::{ColorChoice, Format};
use crate::protocol::{ClearTarget, ControlMode, LightMode, ProtocolHint};

const ABOUT: &str = "Decode, monitor, drive and diagnose the AgileX TRACER robot";

// Prose is written as paragraphs that `reflow` joins, so clap wraps it once, to the terminal; indented lines
// (examples, key tables) are kept as written and fit 80 columns.
const AFTER_HELP: &str = "\
Examples:
  Try the dashboard on the built-in virtual robot, no robot needed:
    tracerctl --sim dashboard
  Why isn't it moving? A checklist of PASS/WARN/FAIL with what to do:
    tracerctl doctor
  Drive forward at 0.3 m/s for 2 s over CAN interface can0:
    tracerctl --iface can0 drive --linear 0.3 --for 2s
  Watch the robot's state and speeds live, with stale frames flagged:
    tracerctl monitor --msg system_state,motion_state
  The technician's report of a log: rates, lost frames, faults, battery:
    tracerctl decode --summary capture.log
  Decode one frame given in cansend syntax:
    tracerctl decode {EXAMPLE_FRAME}

Each command has its own help: tracerctl COMMAND --help (or -h for a summary).";

/// A help text with the example frame (`{EXAMPLE_FRAME}`) taken from the codec.
fn with_example_frame(text: &str) -> String {
    reflow(&text.replace("{EXAMPLE_FRAME}", crate::protocol::can::EXAMPLE_FRAME))
}

/// An after-help text as clap should get it: each hand-wrapped prose paragraph joined into one line, so
/// that clap wraps it once, to the terminal (wrapping it twice left orphan words); indented lines
/// (examples, key tables) and lines ending with `:` (headings) stay as written.
pub fn reflow(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut joinable = false;
    for line in text.lines() {
        let prose = !line.trim().is_empty() && !line.starts_with(char::is_whitespace);
        if joinable && prose {
            out.push(' ');
        } else if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(if prose { line.trim_end() } else { line });
        joinable = prose && !line.trim_end().ends_with(':');
    }
    out
}

/// The heading of the options every command takes (`--protocol`, `--color`), after the command's own.
pub const GLOBAL_HEADING: &str = "Global options";
/// The heading of the link options ([`LinkArgs`]), after the global ones.
pub const LINK_HEADING: &str = "Link options";

#[derive(Debug, Parser)]
#[command(name = "tracerctl", version, about = ABOUT, after_help = with_example_frame(AFTER_HELP), propagate_version = true, max_term_width = 100)]
pub struct Cli {
    /// Protocol version: auto detects from the identifiers on the bus
    #[arg(long, global = true, help_heading = GLOBAL_HEADING, value_enum, default_value_t = ProtocolArg::Auto, value_name = "VERSION")]
    pub protocol: ProtocolArg,

    /// When to colour output (an explicit always or never overrides NO_COLOR)
    #[arg(long, global = true, help_heading = GLOBAL_HEADING, value_enum, default_value_t = ColorArg::Auto, value_name = "WHEN")]
    pub color: ColorArg,

    /// Settings of this robot's profile in the configuration files ([profiles.NAME]; tracerctl config show)
    #[arg(long, global = true, help_heading = GLOBAL_HEADING, value_name = "NAME", env = crate::config::PROFILE_ENV, hide_env_values = true)]
    pub profile: Option<String>,

    #[command(flatten)]
    pub link: LinkArgs,

    #[command(subcommand)]
    pub command: Command,

    /// The configuration files as applied to this command line (not an option).
    #[arg(skip)]
    pub config: Configured,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Decode candump logs, single frames or RS232 captures
    #[command(after_help = with_example_frame(DECODE_AFTER_HELP))]
    Decode(DecodeArgs),
    /// Watch the live bus, decoded, with warnings when periodic frames go stale
    Monitor(MonitorArgs),
    /// Drive at a fixed speed: 50 Hz commands, ramped and capped; Ctrl-C stops it
    Drive(DriveArgs),
    /// Acceptance test drive: measure how the robot answers, PASS/WARN/FAIL per figure
    #[command(after_help = reflow(COMMISSION_AFTER_HELP))]
    Commission(CommissionArgs),
    /// Why isn't it moving? Check the link, bus, protocol, mode, E-stop, faults and battery (PASS/WARN/FAIL)
    #[command(after_help = doctor_after_help())]
    Doctor(DoctorArgs),
    /// Switch the control mode (0x421) and report it before and after
    Mode(ModeArgs),
    /// Clear latched faults (0x441) and report which bits cleared and which remain
    ClearErrors(ClearErrorsArgs),
    /// Set the lights (0x121), confirmed from the light state (0x231)
    Lights(LightsArgs),
    /// Show what raw frames mean, then send them (cansend syntax, or hex RS232 frames)
    SendRaw(SendRawArgs),
    /// Run a virtual TRACER on a CAN interface (e.g. --iface vcan0) or a new pseudo-terminal (--pty)
    Sim(SimArgs),
    /// Live dashboard: battery, faults, motors, odometry, link health; arrow keys drive
    #[command(visible_alias = "dash", after_help = reflow(&crate::dashboard::keys::help_text()))]
    Dashboard(DashboardArgs),
    /// Black box: record the bus unattended, keep the minutes around each fault as an incident; never sends
    #[command(after_help = reflow(RECORD_AFTER_HELP))]
    Record(RecordArgs),
    /// Make the support bundle for the vendor: doctor, firmware version, rates, incidents, host facts
    #[command(after_help = reflow(REPORT_AFTER_HELP))]
    Report(ReportArgs),
    /// Print a shell completion script to standard output
    Completions(CompletionsArgs),
    /// The configuration files: every effective setting with its source (show), the files read (path)
    #[command(after_help = reflow(CONFIG_AFTER_HELP))]
    Config(ConfigArgs),
}

const COMMISSION_AFTER_HELP: &str = "\
A bounded, guided test drive for delivery, after repairs and every month (docs/commission.md). It
opens the link and listens (nothing is sent), runs the doctor's checks and drives only if they pass,
shows the steps, the bounds, the duration and the free space it needs (1.5 m clear ahead and behind;
it ends near where it started), and asks on the terminal (or --yes). Each step is sent as a step
(the sender's ramp does not shape it) within --max-linear and --max-angular. Any key, Ctrl-C,
SIGTERM, SIGHUP, an E-stop, a fault, the vehicle exception, RC override, a mode change, link silence,
a serial peer that stops reading or a robot that does not follow stops it at once with zero frames;
the report keeps what was measured before. Thresholds: the [commission] table of the configuration
file (tracerctl config show).

Examples:
  What it would do (no link, nothing sent):
    tracerctl commission --dry-run
  On the robot, keeping the record in DIR and the recording:
    tracerctl --iface can0 commission --record run.log --save DIR
  A month later, what drifted (tyre wear, battery):
    tracerctl --iface can0 commission --compare DIR/can0-2025-01-02T030405Z.json
  On the simulator, with the command-timeout probe and a plot:
    tracerctl --sim commission --yes --include timeout --plot run.svg

Exit status: 0 every figure passed (warnings are said), 5 a figure failed, 4 the robot was not ready
or the drive was aborted (E-stop, fault, RC, mode, key, not following, or cancelled at the prompt),
1 an error (the link lost or stalled, the stop frames not sent), 2 usage error (also: no terminal
and no --yes), 130/143/129 after SIGINT (or Ctrl-C)/SIGTERM/SIGHUP.";

/// `commission --include`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IncludeArg {
    /// The command-timeout probe: nothing is sent for 1.5 s at 0.1 m/s; the robot must stop by itself
    Timeout,
}

#[derive(Debug, Args)]
pub struct CommissionArgs {
    /// Cap on the linear speed of the steps, m/s (at most 0.6 is used: the 1 m straight must hold a step)
    #[arg(long, default_value_t = 0.3, value_name = "M/S", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub max_linear: f64,

    /// Cap on the angular speed of the spins, rad/s (at most 0.7853 is used)
    #[arg(long, default_value_t = 0.5, value_name = "RAD/S", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub max_angular: f64,

    /// Add an opt-in step (repeatable)
    #[arg(long, value_enum, value_name = "STEP")]
    pub include: Vec<IncludeArg>,

    /// Drive without asking on the terminal (the operator has checked the free space)
    #[arg(long)]
    pub yes: bool,

    /// Print the steps, the bounds and the duration, and exit: no link opened, nothing sent
    #[arg(long)]
    pub dry_run: bool,

    /// Write a candump log of the run (frames received and sent) to FILE; a .mcap name writes MCAP
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,

    /// The report on stdout: text, or one JSON object (docs/commission.md)
    #[arg(long, short = 'f', value_enum, default_value_t = ReportFormatArg::Text)]
    pub format: ReportFormatArg,

    /// Draw each step (commanded, measured and wheel speeds) into FILE.svg
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,

    /// Keep the JSON record as DIR/<link>-<UTC time>.json (never overwriting)
    #[arg(long, value_name = "DIR")]
    pub save: Option<PathBuf>,

    /// After the run, show each figure's old and new value and flag what drifted since OLD.json
    #[arg(long, value_name = "OLD.json")]
    pub compare: Option<PathBuf>,
}

impl CommissionArgs {
    fn options(self, configured: &Configured) -> anyhow::Result<commands::commission::Options> {
        if self.dry_run && self.compare.is_some() {
            return Err(usage("--compare needs a run to compare: it does not go with --dry-run"));
        }
        Ok(commands::commission::Options {
            plan: crate::health::plan::PlanOptions {
                max_linear: self.max_linear,
                max_angular: self.max_angular,
                include_timeout: self.include.contains(&IncludeArg::Timeout),
            },
            yes: self.yes,
            dry_run: self.dry_run,
            record: self.record,
            format: self.format.into(),
            plot: self.plot,
            save: self.save,
            compare: self.compare,
            thresholds: configured.commission_thresholds()?,
            battery_warning_volts: configured.battery_warning_volts(),
        })
    }
}

const RECORD_AFTER_HELP: &str = "\
The recorder keeps every frame in a ring of zstd-compressed candump -L segments under DIR/ring (bounded by
--max-total and --max-age, oldest removed first) and, for each trigger, an incident in DIR/incidents: the
frames from --before to --after around it as frames.log and frames.mcap, summary.txt, summary.json and
incident.json. It never sends a frame. SIGTERM or Ctrl-C ends it (exit 0); a link that goes away is
waited for. docs/troubleshooting.md sets it up as a service (tracerctl-record@can0).

Examples:
  Record can0 into /var/lib/tracerctl/can0 with the default triggers:
    tracerctl --iface can0 record --dir /var/lib/tracerctl/can0
  Also keep an incident when the battery drops below 23 V:
    tracerctl record --dir DIR --trigger 'battery_voltage<23.0'
  The operator saw something: mark it (the running recorder keeps an incident):
    tracerctl record --mark --dir DIR 'stopped by the lift'
  Is it running, what did it keep?
    tracerctl record --status --dir DIR
    tracerctl record --list --dir DIR

Exit status: 0 success (--status: a recorder runs), 1 error (--status: none runs), 2 usage error.";

/// `record --max-total`: a ring below 1 MiB holds too little to be a ring.
pub const RING_SIZE: (u64, u64) = (1 << 20, 1 << 50);
/// `record --segment`.
pub const SEGMENT_TIME: DurationRange = DurationRange { min: secs(1), max: secs(24 * 3600) };
/// `record --max-age`.
pub const RING_AGE: DurationRange = DurationRange { min: secs(60), max: secs(366 * 24 * 3600) };
/// `record --before`, `--after`.
pub const WINDOW_TIME: DurationRange = DurationRange { min: Duration::ZERO, max: secs(3600) };

#[derive(Debug, Args)]
pub struct RecordArgs {
    /// The recorder directory [default: $XDG_STATE_HOME/tracerctl/record, or for --status, --list and
    /// --mark the one recorder directory under /var/lib/tracerctl when there is only one]
    #[arg(long, value_name = "DIR", value_hint = clap::ValueHint::DirPath)]
    pub dir: Option<PathBuf>,

    /// A new segment this often (1s to 1d)
    #[arg(long, value_name = "DURATION", default_value = "1m", value_parser = duration_in(SEGMENT_TIME))]
    pub segment: Duration,

    /// The ring's size, e.g. 1GiB, 500MB (at least 1 MiB)
    #[arg(long, value_name = "SIZE", default_value = "1GiB", value_parser = parse_ring_size)]
    pub max_total: u64,

    /// Segments older than this are removed (1m to 366d)
    #[arg(long, value_name = "DURATION", default_value = "7days", value_parser = duration_in(RING_AGE))]
    pub max_age: Duration,

    /// An incident keeps the frames from this long before its trigger, from 0 to 1h
    #[arg(long, value_name = "DURATION", default_value = "60s", value_parser = duration_in(WINDOW_TIME))]
    pub before: Duration,

    /// ... to this long after it (0 to 1h); a trigger inside the window extends it
    #[arg(long, value_name = "DURATION", default_value = "30s", value_parser = duration_in(WINDOW_TIME))]
    pub after: Duration,

    /// Incidents kept, the oldest removed first
    #[arg(long, value_name = "N", default_value_t = 100, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub max_incidents: u32,

    /// Also a trigger (repeatable): a decoded field and a value, e.g. 'battery_voltage<23.0' or 'id=0x441'
    #[arg(long, value_name = "EXPR", value_parser = parse_trigger)]
    pub trigger: Vec<crate::blackbox::triggers::Expression>,

    /// Only the --trigger expressions and marks, not the default triggers
    #[arg(long)]
    pub no_default_triggers: bool,

    /// The link from a systemd instance name: a profile, can0 (SocketCAN), or ttyUSB0, dev/ttyUSB0 (serial)
    #[arg(long, value_name = "NAME", conflicts_with_all = ["status", "list", "mark"])]
    pub instance: Option<String>,

    /// Print the link, directory and settings it would record with, and exit without opening the link
    #[arg(long, conflicts_with_all = ["status", "list", "mark"])]
    pub dry_run: bool,

    /// Is a recorder running in DIR: since when, frames recorded and lost, the ring, the last incidents
    #[arg(long, conflicts_with_all = ["list", "mark"])]
    pub status: bool,

    /// The incidents in DIR, oldest first
    #[arg(long, conflicts_with = "mark")]
    pub list: bool,

    /// Leave a mark (with NOTE): the running recorder keeps an incident around now
    #[arg(long)]
    pub mark: bool,

    /// The mark's note (with --mark)
    #[arg(value_name = "NOTE", requires = "mark")]
    pub note: Option<String>,

    /// Output format of --status and --list
    #[arg(long, short = 'f', value_enum, default_value_t = ReportFormatArg::Text)]
    pub format: ReportFormatArg,
}

fn parse_trigger(text: &str) -> Result<crate::blackbox::triggers::Expression, String> {
    text.parse()
        .map_err(|error: <crate::blackbox::triggers::Expression as std::str::FromStr>::Err| error.to_string())
}

const REPORT_AFTER_HELP: &str = "\
Writes tracerctl-report-HOST-TIME.tar.gz (UTC time) for the vendor: doctor's report (text and JSON), the
firmware version when the robot answers the version query (sent only on a live CAN link where the robot
is heard; nothing else is sent unless --probe), the protocol and frames per identifier, host facts (OS
release, kernel, CAN driver and modules, ip -details -statistics link, serial port owner and mode), and
from the recorder's directory: its fault timeline, the newest incidents and the ring's last minutes, under
--max-size (what is left out is said, in README.txt and here). When no recorder runs, the frames of the
listen are kept instead. README.txt inside says what each file is. Never in a bundle: environment
variables, files from outside the recorder's directory, anything about other processes.

Examples:
  On the robot's computer, with the recorder's service running:
    tracerctl --iface can0 report
  Offline, to a USB stick, at most 20 MB:
    tracerctl --iface can0 report -o /media/usb/ --max-size 20MB

Exit status: 0 the bundle was written (whatever the doctor found), 1 it could not be, 2 usage error (an
existing file without --force, the output an input or in the recorder's directory).";

#[derive(Debug, Args)]
pub struct ReportArgs {
    /// The bundle's file, or a directory to write the default name in [default:
    /// tracerctl-report-HOST-TIME.tar.gz here]
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,

    /// Replace an existing file of that name
    #[arg(long)]
    pub force: bool,

    /// The recorder's directory [default: /var/lib/tracerctl/record, if there is one]
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,

    /// Also run the doctor's probe: it sends a mode command and zero-velocity motion, never moving the robot
    #[arg(long)]
    pub probe: bool,

    /// How long to listen to the robot (100ms to 10m); its frames are kept when no recorder runs
    #[arg(long, value_name = "DURATION", default_value = "10s", allow_hyphen_values = true, value_parser = duration_in(LISTEN))]
    pub listen: std::time::Duration,

    /// The cap on the bundle's size: 50MB, 500kB, 1GiB (kB, MB, GB are powers of 1000; KiB, MiB, GiB of 1024)
    #[arg(long, value_name = "SIZE", default_value = "50MB", value_parser = parse_size)]
    pub max_size: u64,

    /// How many incidents to take, newest first
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub incidents: usize,

    /// How many minutes of the recorder's ring to take (its last ones)
    #[arg(long, value_name = "MINUTES", default_value_t = 10, value_parser = clap::value_parser!(u64).range(0..=10_080))]
    pub ring_minutes: u64,
}

impl ReportArgs {
    fn options(self) -> commands::report::Options {
        commands::report::Options {
            output: self.output,
            force: self.force,
            dir: self.dir,
            probe: self.probe,
            listen: self.listen,
            max_size: self.max_size,
            incidents: self.incidents,
            ring_minutes: self.ring_minutes,
        }
    }
}

/// `record --max-total`: a size such as `1GiB` or `500MB`, from 1 MiB.
fn parse_ring_size(text: &str) -> Result<u64, String> {
    parse_size_in(text, RING_SIZE, "from 1MiB to 1024TiB")
}

/// `report --max-size`: a size such as `50MB` or `500kB`, from 1 kB.
pub fn parse_size(text: &str) -> Result<u64, String> {
    parse_size_in(text, (1_000, 1_000_000_000_000_000), "from 1kB to 1000TB")
}

/// A size such as `50MB`, `500kB`, `1GiB` or plain bytes within `range`: k, M, G, T (and kB, MB, GB, TB)
/// are powers of 1000, KiB, MiB, GiB, TiB of 1024.
fn parse_size_in(text: &str, range: (u64, u64), range_text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let split = trimmed.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(trimmed.len());
    let (number, unit) = trimmed.split_at(split);
    let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kb" => 1_000,
        "m" | "mb" => 1_000_000,
        "g" | "gb" => 1_000_000_000,
        "t" | "tb" => 1_000_000_000_000,
        "kib" => 1 << 10,
        "mib" => 1 << 20,
        "gib" => 1 << 30,
        "tib" => 1 << 40,
        _ => return Err(format!("'{text}' is not a size such as 50MB, 500kB or 1GiB")),
    };
    let value: f64 =
        number.parse().map_err(|_| format!("'{text}' is not a size such as 50MB, 500kB or 1GiB"))?;
    let bytes = value * scale as f64;
    if !(bytes >= range.0 as f64 && bytes <= range.1 as f64) {
        return Err(format!("'{text}' is out of range: give a size {range_text}"));
    }
    Ok(bytes as u64)
}

/// The directory `record` uses without `--dir`.
fn default_record_dir(looking: bool) -> PathBuf {
    // --status, --list and --mark find the service's directory when there is exactly one.
    if looking {
        let found: Vec<PathBuf> = std::fs::read_dir("/var/lib/tracerctl")
            .map(|entries| {
                entries
                    .flatten()
                    .map(|entry| entry.path())
                    .filter(|path| path.join("status.json").is_file())
                    .collect()
            })
            .unwrap_or_default();
        if let [only] = found.as_slice() {
            return only.clone();
        }
    }
    let state = std::env::var_os("XDG_STATE_HOME")
        .filter(|dir| !dir.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("LOCALAPPDATA").filter(|dir| !dir.is_empty()).map(PathBuf::from))
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|dir| !dir.is_empty())
                .map(|home| PathBuf::from(home).join(".local/state"))
        })
        .unwrap_or_else(|| PathBuf::from("."));
    state.join("tracerctl").join("record")
}

/// `--instance NAME`: the link a systemd instance name gives.
pub fn instance_link(name: &str) -> anyhow::Result<LinkChoice> {
    let name = name.trim();
    if name.is_empty() {
        return Err(usage("--instance needs a name: can0, ttyUSB0 or dev/ttyUSB0"));
    }
    if name.contains('/') {
        let path = format!("/{}", name.trim_start_matches('/'));
        return Ok(LinkChoice::Serial { path: PathBuf::from(path), baud: DEFAULT_BAUD });
    }
    if name.starts_with("tty") || name.starts_with("rfcomm") {
        return Ok(LinkChoice::Serial { path: PathBuf::from("/dev").join(name), baud: DEFAULT_BAUD });
    }
    if name.len() > 15 {
        return Err(usage(format!("--instance {name}: an interface name has at most 15 characters")));
    }
    Ok(LinkChoice::SocketCan { iface: name.to_string() })
}

impl RecordArgs {
    /// The options, and the link `--instance` chose (refused beside the link options).
    fn options(
        self,
        link: &LinkArgs,
        profiled: bool,
    ) -> anyhow::Result<(commands::record::Options, Option<LinkChoice>)> {
        use commands::record::{Action, Options, Settings};
        let format = match self.format {
            ReportFormatArg::Text => commands::decode::ReportFormat::Text,
            ReportFormatArg::Json => commands::decode::ReportFormat::Json,
        };
        let looking = self.status || self.list || self.mark;
        let dir = self.dir.clone().unwrap_or_else(|| default_record_dir(looking));
        let instance_link = match &self.instance {
            Some(_) if profiled => None,
            Some(name) => {
                if link.sim || link.replay.is_some() || link.iface.is_some() || !link.serial.is_empty() {
                    return Err(usage(
                        "--instance chooses the link: give it without --iface, --serial, --sim or --replay",
                    ));
                }
                Some(instance_link(name)?)
            }
            None => None,
        };
        let settings = Settings {
            segment: self.segment,
            max_total: self.max_total,
            max_age: self.max_age,
            before: self.before,
            after: self.after,
            max_incidents: self.max_incidents,
            triggers: crate::blackbox::triggers::TriggerSettings {
                defaults: !self.no_default_triggers,
                expressions: self.trigger,
                ..Default::default()
            },
            instance: self.instance,
        };
        let action = if self.status {
            Action::Status(format)
        } else if self.list {
            Action::List(format)
        } else if self.mark {
            Action::Mark(self.note.unwrap_or_default())
        } else if self.dry_run {
            Action::DryRun(settings)
        } else {
            Action::Record(settings)
        };
        Ok((Options { dir, action }, instance_link))
    }
}

const DECODE_AFTER_HELP: &str = "\
Inputs are candump logs in any variant (candump -l/-L files, console output with or without
timestamps, -x, -a, -e, colour), '-' for standard input, or frames in cansend syntax ({EXAMPLE_FRAME}).
A directory of `tracerctl record` stands for its logs: an incident's frames.log, or the ring's
*.log.zst segments in time order (DIR or DIR/ring).
Bad lines are reported with file:line and the reason, counted, and skipped (--strict stops at the first).

Exit status: 0 success, 1 error, 2 usage error (an output that is an input too), 3 bad input
(with --strict; a format it does not read; no frames at all; a compressed log cut short or
corrupt: every whole line before the damage is decoded first).";

#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// candump logs, recorder directories, '-' for standard input, or frames in cansend syntax (e.g. 211#00000103000000B1)
    #[arg(value_name = "INPUT")]
    pub inputs: Vec<String>,

    /// Output format [default: text, or mcap for -o FILE.mcap]. MCAP (Foxglove, PlotJuggler) needs -o FILE
    /// and is written by one thread
    #[arg(long, short = 'f', value_enum)]
    pub format: Option<DecodeFormatArg>,

    /// Write the output to FILE instead of standard output (a .mcap name means --format mcap)
    #[arg(long, short = 'o', value_name = "FILE", value_hint = clap::ValueHint::FilePath)]
    pub output: Option<PathBuf>,

    /// Chunk compression of MCAP output
    #[arg(long, value_enum, default_value_t = McapCompressionArg::Zstd, value_name = "METHOD")]
    pub mcap_compression: McapCompressionArg,

    /// Print a report instead of every frame: rates, gaps, lost frames, modes, faults, battery, distance
    #[arg(long, short = 's')]
    pub summary: bool,

    /// Stop at the first bad line, bad frame or corrupted serial frame (exit status 3)
    #[arg(long)]
    pub strict: bool,

    /// Only frames with these identifiers (hex, comma-separated: 0x211,221, or AA01 for serial)
    #[arg(long = "id", value_name = "IDS", value_delimiter = ',', value_hint = clap::ValueHint::Other, value_parser = parse_id)]
    pub ids: Vec<crate::protocol::FrameId>,

    /// Only these messages (comma-separated), e.g. system_state,odometry; also raw, invalid, error_frame
    #[arg(long = "msg", value_name = "NAMES", value_delimiter = ',', value_parser = Completing { parse: parse_msg_name, values: msg_values }, hide_possible_values = true, long_help = msg_long_help())]
    pub messages: Vec<&'static str>,

    /// Console timestamps are deltas between frames (candump -t d): add them up. Such stamps look
    /// exactly like those of candump -t z, so tracerctl cannot tell them apart.
    #[arg(long)]
    pub delta_stamps: bool,

    /// Never show a progress bar (shown only for large files, on a terminal)
    #[arg(long)]
    pub no_progress: bool,

    /// Draw battery voltage, commanded vs measured speeds, motor RPM and current, with fault and E-stop events marked, as an SVG file
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,

    /// Threads for text logs (candump, Vector ASC, PEAK trc): files and standard input, plain or compressed, in every mode (--summary, --plot, --delta-stamps too; default: all cores; 1: one)
    #[arg(long, short = 'j', value_name = "N", value_hint = clap::ValueHint::Other, value_parser = clap::value_parser!(u16).range(1..))]
    pub threads: Option<u16>,

    /// Read files with positioned reads only, never mapped into memory (also TRACERCTL_NO_MMAP=1); the output is the same
    #[arg(long)]
    pub no_mmap: bool,
}

/// Bytes of input per parallel chunk from `TRACERCTL_CHUNK_BYTES`, for tests: tiny chunks put boundaries
/// everywhere. An environment variable rather than a hidden option, so completions never offer it.
fn chunk_bytes_from_env() -> Option<usize> {
    std::env::var("TRACERCTL_CHUNK_BYTES").ok()?.parse().ok().filter(|&bytes: &usize| bytes > 0)
}

/// `--format` of decode: monitor's formats and MCAP.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DecodeFormatArg {
    /// One readable line per frame.
    Text,
    /// One JSON object per line (schema in docs/json.md).
    Json,
    /// Comma-separated values with a fixed header (for spreadsheets).
    Csv,
    /// An MCAP file for Foxglove and PlotJuggler (docs/foxglove.md); needs -o FILE.
    Mcap,
}

/// `--mcap-compression`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum McapCompressionArg {
    Zstd,
    Lz4,
    None,
}

impl From<McapCompressionArg> for crate::output::mcap::Compression {
    fn from(value: McapCompressionArg) -> Self {
        match value {
            McapCompressionArg::Zstd => Self::Zstd,
            McapCompressionArg::Lz4 => Self::Lz4,
            McapCompressionArg::None => Self::None,
        }
    }
}

impl DecodeArgs {
    fn options(self, serial: Vec<PathBuf>) -> anyhow::Result<commands::decode::Options> {
        let output = self.output.filter(|path| path.as_os_str() != "-");
        let inferred = match output.as_deref() {
            Some(path) if crate::output::mcap::is_mcap_path(path) => DecodeFormatArg::Mcap,
            _ => DecodeFormatArg::Text,
        };
        let format = self.format.unwrap_or(inferred);
        if format == DecodeFormatArg::Mcap {
            if output.is_none() {
                return Err(usage(
                    "--format mcap needs a file it can seek in (the index is written last): give -o FILE.mcap, \
                     not standard output",
                ));
            }
            if self.summary || self.plot.is_some() {
                return Err(usage("--format mcap writes every frame: leave out --summary and --plot"));
            }
        }
        let lines = |format| commands::decode::Output::Lines { format, file: output.clone() };
        let output = match (format, self.summary, output.clone()) {
            (DecodeFormatArg::Mcap, _, Some(file)) => {
                commands::decode::Output::Mcap { compression: self.mcap_compression.into(), file }
            }
            (DecodeFormatArg::Csv, true, _) => {
                return Err(usage(
                    "--summary prints a report as text or JSON (--format text or json), not CSV",
                ))
            }
            (DecodeFormatArg::Json, true, file) => {
                commands::decode::Output::Summary { format: commands::decode::ReportFormat::Json, file }
            }
            (_, true, file) => {
                commands::decode::Output::Summary { format: commands::decode::ReportFormat::Text, file }
            }
            (DecodeFormatArg::Json, false, _) => lines(Format::Json),
            (DecodeFormatArg::Csv, false, _) => lines(Format::Csv),
            (DecodeFormatArg::Text | DecodeFormatArg::Mcap, false, _) => lines(Format::Text),
        };
        Ok(commands::decode::Options {
            inputs: self.inputs,
            serial,
            output,
            strict: self.strict,
            ids: self.ids,
            messages: self.messages,
            delta_stamps: self.delta_stamps,
            no_progress: self.no_progress,
            plot: self.plot,
            threads: match self.threads {
                Some(threads) => usize::from(threads),
                None => std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
            },
            chunk_bytes: chunk_bytes_from_env(),
            mmap: !self.no_mmap && std::env::var_os("TRACERCTL_NO_MMAP").is_none(),
        })
    }
}

/// `--format` of decode and monitor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    /// One readable line per frame.
    Text,
    /// One JSON object per line (schema in docs/json.md).
    Json,
    /// Comma-separated values with a fixed header (for spreadsheets).
    Csv,
}

impl From<FormatArg> for Format {
    fn from(value: FormatArg) -> Self {
        match value {
            FormatArg::Text => Format::Text,
            FormatArg::Json => Format::Json,
            FormatArg::Csv => Format::Csv,
        }
    }
}

#[derive(Debug, Args)]
pub struct MonitorArgs {
    /// Output format
    #[arg(long, short = 'f', value_enum, default_value_t = FormatArg::Text)]
    pub format: FormatArg,

    /// Print frames as candump -L lines, undecoded (so not with --format)
    #[arg(long, conflicts_with = "format")]
    pub raw: bool,

    /// Only frames with these identifiers (comma-separated hex numbers)
    #[arg(long = "id", value_name = "IDS", value_delimiter = ',', value_hint = clap::ValueHint::Other, value_parser = parse_id)]
    pub ids: Vec<crate::protocol::FrameId>,

    /// Only these messages, e.g. system_state,odometry (see --help for all)
    #[arg(long = "msg", value_name = "NAMES", value_delimiter = ',', value_parser = Completing { parse: parse_msg_name, values: msg_values }, hide_possible_values = true, long_help = msg_long_help())]
    pub messages: Vec<&'static str>,

    /// Also write every frame to FILE in candump -L format (replayable with canplayer), flushed per line; a
    /// .mcap name writes MCAP instead (docs/foxglove.md), flushed every second
    #[arg(long, value_name = "FILE")]
    pub log: Option<PathBuf>,

    /// Stop after this long (e.g. 10s; up to 30 days); default: until Ctrl-C
    #[arg(long, value_name = "DURATION", allow_hyphen_values = true, value_parser = duration_in(RUN_TIME))]
    pub duration: Option<std::time::Duration>,

    /// Warn when the bus is silent this long (0 to 1h; 0: never)
    #[arg(long, value_name = "DURATION", default_value = "500ms", allow_hyphen_values = true, value_parser = duration_in(SILENCE))]
    pub silence: std::time::Duration,

    /// Time column of text lines, as candump -t: a, d, z or A (default: absolute)
    #[arg(long = "timestamp", short = 't', value_enum, value_name = "MODE")]
    pub timestamp: Option<TimestampArg>,

    /// Exit after COUNT frames shown (as candump -n), with the summary; exit status 0
    #[arg(long = "count", short = 'n', value_name = "COUNT", value_parser = clap::value_parser!(u64).range(1..))]
    pub count: Option<u64>,

    /// Leave the raw bytes out of text lines (the line decode prints, for scripts that parse it)
    #[arg(long)]
    pub no_data: bool,
}

/// `monitor --timestamp`: candump's `-t` letters, or their names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum TimestampArg {
    /// (a) seconds since the epoch, 6 decimals (9 when the link stamps nanoseconds)
    #[value(alias = "a")]
    Absolute,
    /// (d) seconds since the previous line shown (000.020000); the first line is 0
    #[value(alias = "d")]
    Delta,
    /// (z) seconds since the first line shown (000.000000 first)
    #[value(alias = "z")]
    Zero,
    /// (A) local date and time (2023-11-14 22:13:20.000250)
    #[value(alias = "A")]
    Date,
}

impl From<TimestampArg> for TimeMode {
    fn from(value: TimestampArg) -> Self {
        match value {
            TimestampArg::Absolute => TimeMode::Absolute,
            TimestampArg::Delta => TimeMode::Delta,
            TimestampArg::Zero => TimeMode::Zero,
            TimestampArg::Date => TimeMode::Date,
        }
    }
}

impl MonitorArgs {
    fn options(self) -> anyhow::Result<commands::monitor::Options> {
        // The text line's columns only: JSON and CSV keep the stamp as received (and JSON the bytes in
        // `data`), candump -L lines are candump's own format.
        let text = self.format == FormatArg::Text && !self.raw;
        let column_options = [(self.timestamp.is_some(), "--timestamp"), (self.no_data, "--no-data")];
        if let Some((_, option)) = column_options.iter().find(|(given, _)| *given && !text) {
            return Err(usage(format!(
                "{option} is for text lines; JSON and CSV keep the stamp as received (`ts`, `ts_ns`) and the \
                 bytes in `data`, and --raw lines are candump's"
            )));
        }
        Ok(commands::monitor::Options {
            format: self.format.into(),
            raw: self.raw,
            ids: self.ids,
            messages: self.messages,
            log: self.log,
            duration: self.duration,
            silence: self.silence,
            time_mode: self.timestamp.map_or(TimeMode::Absolute, TimeMode::from),
            data_column: !self.no_data,
            count: self.count,
        })
    }
}

#[derive(Debug, Args)]
pub struct DriveArgs {
    /// Linear speed in m/s (+ forward; -100 to 100, capped at --max-linear); 0 when only --angular is given
    #[arg(long, allow_negative_numbers = true, value_name = "M/S", value_parser = number_in(SPEED))]
    pub linear: Option<f64>,

    /// Angular speed in rad/s (+ turns counter-clockwise; -100 to 100, capped at --max-angular); 0 when only
    /// --linear is given
    #[arg(long, allow_negative_numbers = true, value_name = "RAD/S", value_parser = number_in(SPEED))]
    pub angular: Option<f64>,

    /// How long to drive (e.g. 2s, 1500ms; up to 24h); default: until Ctrl-C
    #[arg(long = "for", visible_alias = "duration", value_name = "DURATION", allow_hyphen_values = true, value_parser = duration_in(DRIVE_TIME))]
    pub duration: Option<std::time::Duration>,

    #[command(flatten)]
    pub limits: MotionLimitArgs,

    /// Start even with the E-stop pressed or a latched fault (the robot may still refuse)
    #[arg(long)]
    pub ignore_faults: bool,

    /// Status lines and final report on stdout: text, or JSON (docs/json.md)
    #[arg(long, short = 'f', value_enum, default_value_t = ReportFormatArg::Text)]
    pub format: ReportFormatArg,

    /// Record the frames received and sent to FILE (candump log; MCAP for a .mcap name)
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,
}

impl DriveArgs {
    fn options(self) -> anyhow::Result<commands::drive::Options> {
        let limits = self.limits.limits()?;
        // Without a speed, drive would take command mode from whoever drives the robot (ROS) and hold it at
        // zero: that is never what was meant, so it is a usage error; an explicit `--linear 0` still does it.
        if self.linear.is_none() && self.angular.is_none() {
            return Err(usage(
                "drive needs a speed: give --linear M/S and/or --angular RAD/S (e.g. --linear 0.3 --for 2s; \
                 --linear 0 holds the robot at zero)",
            ));
        }
        Ok(commands::drive::Options {
            linear: self.linear.unwrap_or(0.0),
            angular: self.angular.unwrap_or(0.0),
            duration: self.duration,
            limits,
            ignore_faults: self.ignore_faults,
            format: self.format.into(),
            record: self.record,
        })
    }
}

// Caps and ramps of the commands that move the robot (drive, dashboard). A plain comment: clap would take
// a flattened struct's doc as the command's description.
#[derive(Debug, Args)]
pub struct MotionLimitArgs {
    /// Cap on the linear speed, m/s (above 0; at most 1.5 is used)
    #[arg(long, default_value_t = 0.5, value_name = "M/S", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub max_linear: f64,

    /// Cap on the angular speed, rad/s (above 0; at most 0.7853 is used)
    #[arg(long, default_value_t = 0.5, value_name = "RAD/S", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub max_angular: f64,

    /// Linear acceleration of the ramp, m/s²
    #[arg(long, default_value_t = 0.5, value_name = "M/S2", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub accel: f64,

    /// Angular acceleration of the ramp, rad/s²
    #[arg(long, default_value_t = 1.0, value_name = "RAD/S2", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub angular_accel: f64,

    /// Braking (slowing down, reversing), m/s²; at least --accel. From 0.15 m/s to zero in 0.1 s
    #[arg(long, default_value_t = 1.5, value_name = "M/S2", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub decel: f64,

    /// Angular braking, rad/s²; at least --angular-accel
    #[arg(long, default_value_t = 3.0, value_name = "RAD/S2", allow_negative_numbers = true, value_parser = number_in(LIMIT))]
    pub angular_decel: f64,

    /// The limits that came from the configuration files, to name them in an error (not an option).
    #[arg(skip)]
    pub from_config: Vec<ConfigOrigin>,
}

impl MotionLimitArgs {
    /// The validated limits (caps clamped to the protocol's). Limits that contradict each other are a
    /// command-line mistake, like a number out of range: a usage error that names the options.
    pub fn limits(&self) -> anyhow::Result<Limits> {
        Limits {
            max_linear: self.max_linear,
            max_angular: self.max_angular,
            linear_accel: self.accel,
            angular_accel: self.angular_accel,
            linear_decel: self.decel,
            angular_decel: self.angular_decel,
        }
        .validated()
        .map_err(|error| usage(limit_error_text_from(error, &self.from_config)))
    }
}

/// A [`LimitError`] in the words of the command line.
#[cfg(test)]
fn limit_error_text(error: LimitError) -> String {
    limit_error_text_from(error, &[])
}

/// A [`LimitError`] naming each limit by its option, or by its key when it came from a configuration file
/// (then the error starts with that value's `FILE:LINE:COLUMN`).
fn limit_error_text_from(error: LimitError, from_config: &[ConfigOrigin]) -> String {
    let arg = |name| match name {
        LimitName::MaxLinear => "max_linear",
        LimitName::MaxAngular => "max_angular",
        LimitName::LinearAccel => "accel",
        LimitName::AngularAccel => "angular_accel",
        LimitName::LinearDecel => "decel",
        LimitName::AngularDecel => "angular_decel",
    };
    let origin = |name| from_config.iter().find(|origin| origin.arg == arg(name));
    let option =
        |name| origin(name).map_or_else(|| format!("--{}", arg(name).replace('_', "-")), |o| o.key.clone());
    let place = |names: &[LimitName]| {
        names
            .iter()
            .find_map(|name| origin(*name))
            .map_or_else(String::new, |origin| format!("{}: ", origin.at))
    };
    match error {
        LimitError::NotPositive { name, value } => {
            format!("{}{} must be a positive number, not {value}", place(&[name]), option(name))
        }
        LimitError::BrakingWeaker { angular, decel, accel } => {
            let (decel_name, accel_name, unit) = if angular {
                (LimitName::AngularDecel, LimitName::AngularAccel, "rad/s²")
            } else {
                (LimitName::LinearDecel, LimitName::LinearAccel, "m/s²")
            };
            format!(
                "{}{} ({decel} {unit}) must be at least {} ({accel} {unit}): braking is never weaker than speeding up",
                place(&[decel_name, accel_name]),
                option(decel_name),
                option(accel_name),
            )
        }
    }
}

/// The modes `tracerctl mode` accepts, named and described by `protocol::ControlMode` itself.
fn requestable_mode() -> impl clap::builder::TypedValueParser<Value = ControlMode> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    let values = ControlMode::REQUESTABLE
        .map(|mode| PossibleValue::new(mode.name()).help(mode.help().unwrap_or_default()));
    PossibleValuesParser::new(values).try_map(|name| name.parse::<ControlMode>())
}

#[derive(Debug, Args)]
pub struct ModeArgs {
    #[arg(value_parser = requestable_mode())]
    pub mode: ControlMode,

    /// How long to wait for the robot to confirm (0 to 10m)
    #[arg(long, value_name = "DURATION", default_value = "1s", allow_hyphen_values = true, value_parser = duration_in(TIMEOUT))]
    pub timeout: std::time::Duration,
}

impl ModeArgs {
    fn options(self) -> commands::mode::Options {
        commands::mode::Options { mode: self.mode, timeout: self.timeout }
    }
}

#[derive(Debug, Args)]
pub struct ClearErrorsArgs {
    /// Which latched faults to clear
    #[arg(value_enum, default_value_t = ClearTargetArg::All)]
    pub target: ClearTargetArg,

    /// How long to watch the status afterwards (0 to 10m)
    #[arg(long, value_name = "DURATION", default_value = "1s", allow_hyphen_values = true, value_parser = duration_in(TIMEOUT))]
    pub timeout: std::time::Duration,
}

impl ClearErrorsArgs {
    fn options(self) -> commands::clear_errors::Options {
        let target = match self.target {
            ClearTargetArg::All => ClearTarget::All,
            ClearTargetArg::Motor1 => ClearTarget::Motor1,
            ClearTargetArg::Motor2 => ClearTarget::Motor2,
        };
        commands::clear_errors::Options { target, timeout: self.timeout }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ClearTargetArg {
    All,
    Motor1,
    Motor2,
}

/// The light modes `tracerctl lights` accepts, named by `protocol::LightMode` itself.
fn light_mode() -> impl clap::builder::TypedValueParser<Value = LightMode> {
    use clap::builder::{PossibleValuesParser, TypedValueParser};
    use strum::VariantArray;
    PossibleValuesParser::new(LightMode::VARIANTS.iter().map(|mode| mode.name()))
        .try_map(|name| name.parse::<LightMode>())
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("what").required(true).args(["front", "release"])))]
pub struct LightsArgs {
    /// Front light mode
    #[arg(long, value_parser = light_mode())]
    pub front: Option<LightMode>,

    /// Front brightness for --front custom, percent (0-100)
    #[arg(long, value_name = "PERCENT", value_parser = clap::value_parser!(u8).range(0..=100))]
    pub brightness: Option<u8>,

    /// Rear light mode (reserved on TRACER: the firmware ignores it)
    #[arg(long, value_parser = light_mode())]
    pub rear: Option<LightMode>,

    /// Rear brightness for --rear custom, percent (0-100)
    #[arg(long, value_name = "PERCENT", value_parser = clap::value_parser!(u8).range(0..=100))]
    pub rear_brightness: Option<u8>,

    /// Hand the lights back to the firmware
    #[arg(long, conflicts_with_all = ["front", "brightness", "rear", "rear_brightness"])]
    pub release: bool,

    /// How long to wait for the light state to confirm (0 to 10m)
    #[arg(long, value_name = "DURATION", default_value = "1s", allow_hyphen_values = true, value_parser = duration_in(TIMEOUT))]
    pub timeout: std::time::Duration,
}

impl LightsArgs {
    fn options(self) -> commands::lights::Options {
        commands::lights::Options {
            front: self.front,
            brightness: self.brightness,
            rear: self.rear,
            rear_brightness: self.rear_brightness,
            release: self.release,
            timeout: self.timeout,
        }
    }
}

#[derive(Debug, Args)]
pub struct SendRawArgs {
    /// Frames in cansend syntax (111#0096000000000000), or 13-byte RS232 frames in hex with --serial
    #[arg(required = true, value_name = "FRAME")]
    pub frames: Vec<String>,

    /// Send the frames this many times
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub repeat: u32,

    /// Time between repeats, milliseconds
    #[arg(long, default_value_t = 20, value_name = "MS")]
    pub period: u64,

    /// Allow frames that can move the robot (0x111, 0x130, 0x421, RS232 motion control), and frames the robot would reject (a TRACER identifier with the wrong length or checksum)
    #[arg(long)]
    pub force: bool,

    /// Compute RS232 checksums instead of requiring them
    #[arg(long)]
    pub fix_checksum: bool,

    /// What was sent, on stdout, as text or JSON (docs/json.md); diagnostics go to stderr
    #[arg(long, short = 'f', value_enum, default_value_t = ReportFormatArg::Text)]
    pub format: ReportFormatArg,
}

impl SendRawArgs {
    fn options(self) -> commands::send_raw::Options {
        commands::send_raw::Options {
            frames: self.frames,
            repeat: self.repeat,
            period: self.period,
            force: self.force,
            fix_checksum: self.fix_checksum,
            format: self.format.into(),
        }
    }
}

/// `doctor --help` after the options, with the command-mode request from the catalog.
fn doctor_after_help() -> String {
    let request = ControlMode::Can.request_text(crate::protocol::Wire::CanV2).unwrap_or_default();
    reflow(&DOCTOR_AFTER_HELP.replace("{MODE_REQUEST}", &request))
}

const DOCTOR_AFTER_HELP: &str = "\
Checks in order: kernel CAN support, the interface (exists, up, 500 kbit/s, error state and counters) or
the serial port; then, listening to the robot: frames arriving, protocol version (or the RS232 frame
stream: checksum errors, sync losses), system status rate, other controllers on the bus, control mode
and RC override, E-stop, faults, battery, motors. Every WARN and every FAIL says what to do.

--probe also sends the command-mode command ({MODE_REQUEST}; on RS232 and V1 a zero-speed motion command)
and zero-velocity motion commands for 0.5 s, and checks the robot takes them. It never commands motion,
and puts back a standby or serial mode it changed.

Exit status: 0 the robot can be driven (no FAIL), 4 it cannot, 2 usage error.";

#[derive(Debug, Args)]
pub struct DoctorArgs {
    /// Also check that the robot accepts commands: control mode and zero-velocity motion (it does not move)
    #[arg(long)]
    pub probe: bool,

    /// How long to listen to the robot (100ms to 10m)
    #[arg(long, value_name = "DURATION", default_value = "1s", allow_hyphen_values = true, value_parser = duration_in(LISTEN))]
    pub listen: std::time::Duration,

    /// Format of the report
    #[arg(long, short = 'f', value_enum, default_value_t = ReportFormatArg::Text)]
    pub format: ReportFormatArg,
}

impl DoctorArgs {
    fn options(self, battery_warning_volts: f64) -> commands::doctor::Options {
        use commands::doctor::report::ReportFormat;
        let format = match self.format {
            ReportFormatArg::Text => ReportFormat::Text,
            ReportFormatArg::Json => ReportFormat::Json,
        };
        commands::doctor::Options { probe: self.probe, listen: self.listen, format, battery_warning_volts }
    }
}

/// `--format` of doctor, drive and send-raw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ReportFormatArg {
    /// Lines for people
    Text,
    /// JSON (docs/json.md)
    Json,
}

impl From<ReportFormatArg> for Format {
    fn from(value: ReportFormatArg) -> Self {
        match value {
            ReportFormatArg::Text => Format::Text,
            ReportFormatArg::Json => Format::Json,
        }
    }
}

#[derive(Debug, Args)]
pub struct DashboardArgs {
    #[command(flatten)]
    pub limits: MotionLimitArgs,

    /// Watch only: never arm driving, never send anything (for a robot that ROS or an RC transmitter drives)
    #[arg(long)]
    pub watch: bool,

    /// Write a candump log of the session (frames received and sent) to FILE; a .mcap name writes MCAP
    /// (Foxglove, PlotJuggler: docs/foxglove.md)
    #[arg(long, value_name = "FILE")]
    pub record: Option<PathBuf>,

    /// Without key-release events (tmux, most terminals over SSH): a held key counts as released when no auto-repeat came for DURATION (20ms to 1.25s), instead of the deadline learned from the key stream. Longer rides out a jittery link, shorter stops sooner
    #[arg(long, value_name = "DURATION", value_parser = duration_in(KEY_TIMEOUT))]
    pub key_timeout: Option<Duration>,
}

/// `dashboard --key-timeout`: from the teleop's shortest to its longest hold after a key's last byte.
pub const KEY_TIMEOUT: DurationRange = DurationRange {
    min: crate::dashboard::teleop::KEY_TIMEOUT_MIN,
    max: crate::dashboard::teleop::FIRST_DEADLINE_MAX,
};

impl DashboardArgs {
    fn options(self, battery_warning_volts: f64) -> anyhow::Result<commands::dashboard::Options> {
        Ok(commands::dashboard::Options {
            limits: self.limits.limits()?,
            watch: self.watch,
            record: self.record,
            key_timeout: self.key_timeout,
            battery_warning_volts,
        })
    }
}

#[derive(Debug, Args)]
#[command(after_help = reflow(&format!("{}\n\n{}", crate::sim::fault_help(), crate::sim::param_help())))]
pub struct SimArgs {
    /// Serve on a new pseudo-terminal (prints its path) instead of a CAN interface or --serial port
    #[arg(long)]
    pub pty: bool,

    /// An RC transmitter is on, with SWB in this position (middle = RC mode overrides commands)
    #[arg(long, value_enum, value_name = "SWB")]
    pub rc: Option<RcSwitchChoice>,

    /// Starting battery voltage (18 to 30)
    #[arg(long, value_name = "VOLTS", allow_negative_numbers = true, value_parser = number_in(BATTERY))]
    pub battery: Option<f64>,

    /// Speed up battery drain by this factor (to see the low-battery warnings quickly; 0 to 1000000)
    #[arg(long, value_name = "FACTOR", allow_negative_numbers = true, value_parser = number_in(DRAIN))]
    pub drain: Option<f64>,

    /// Stop after this long (at most 30 days); default: until Ctrl-C
    #[arg(long, value_name = "DURATION", allow_hyphen_values = true, value_parser = duration_in(RUN_TIME))]
    pub duration: Option<std::time::Duration>,
}

impl SimArgs {
    /// The settings, once the link options fit a simulator: it serves a link, so not `--sim` or `--replay`,
    /// and `--pty` is a link of its own. Checked here because clap does not check a subcommand's options
    /// against global ones given before it.
    fn options(self, link: &LinkArgs) -> anyhow::Result<commands::sim::Options> {
        if link.sim {
            return Err(usage("`sim` is the simulator itself: leave out --sim"));
        }
        if link.replay.is_some() {
            return Err(usage("`sim` serves a link: --replay does not apply"));
        }
        if self.pty && cfg!(not(unix)) {
            return Err(usage(
                "--pty needs Unix pseudo-terminals: on Windows serve on one end of a null-modem pair (com0com) with --serial COMn",
            ));
        }
        if self.pty && (link.iface.is_some() || !link.serial.is_empty()) {
            return Err(usage(
                "--pty serves on a new pseudo-terminal: leave out --iface and --serial (or drop --pty to serve on them)",
            ));
        }
        let rc = self.rc.map(|swb| match swb {
            RcSwitchChoice::Top => crate::sim::RcSwitch::Top,
            RcSwitchChoice::Middle => crate::sim::RcSwitch::Middle,
        });
        Ok(commands::sim::Options {
            pty: self.pty,
            faults: link.faults.clone(),
            params: link.sim_params.clone(),
            rc,
            battery: self.battery,
            drain: self.drain,
            duration: self.duration,
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RcSwitchChoice {
    /// SWB at the top: command mode allowed
    Top,
    /// SWB in the middle: RC mode, commands are ignored
    Middle,
}

/// The durations one option accepts, inclusive. Bounded so that no deadline (`Instant + d`) can overflow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DurationRange {
    pub min: Duration,
    pub max: Duration,
}

const fn secs(seconds: u64) -> Duration {
    Duration::from_secs(seconds)
}

/// `drive --for`.
pub const DRIVE_TIME: DurationRange = DurationRange { min: Duration::ZERO, max: secs(24 * 3600) };
/// `monitor --duration`, `sim --duration`, `sim --fault NAME@TIME`.
pub const RUN_TIME: DurationRange = DurationRange { min: Duration::ZERO, max: secs(30 * 24 * 3600) };
/// `monitor --silence` (0: never warn).
pub const SILENCE: DurationRange = DurationRange { min: Duration::ZERO, max: secs(3600) };
/// `doctor --listen`: rates need some frames, and a technician waits minutes at most.
pub const LISTEN: DurationRange = DurationRange { min: Duration::from_millis(100), max: secs(600) };
/// `--timeout` of mode, clear-errors and lights.
pub const TIMEOUT: DurationRange = DurationRange { min: Duration::ZERO, max: secs(600) };

/// A duration such as `2s`, `1500ms`, `1m30s`, or plain seconds (`2.5`), within `range`.
pub fn parse_duration(text: &str, range: DurationRange) -> Result<Duration, String> {
    let show = |duration: Duration| humantime::format_duration(duration).to_string();
    let accepted = format!("from {} to {}", show(range.min), show(range.max));
    let out_of_range = || format!("'{text}' is out of range: give a duration {accepted} (e.g. 2s, 500ms)");
    let duration = match text.trim().parse::<f64>() {
        // NaN, inf and negatives are numbers too, just not durations.
        Ok(seconds) if !(seconds >= 0.0 && seconds <= range.max.as_secs_f64()) => return Err(out_of_range()),
        Ok(seconds) => Duration::from_secs_f64(seconds),
        Err(_) => humantime::parse_duration(text.trim()).map_err(|error| {
            // `-2s` is a negative duration; `--linear` (taken as the value) is no duration at all.
            if text
                .trim_start()
                .strip_prefix('-')
                .is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_digit()))
            {
                out_of_range()
            } else {
                format!("'{text}' is not a duration such as 2s or 500ms ({error}); accepted: {accepted}")
            }
        })?,
    };
    if duration < range.min || duration > range.max {
        return Err(out_of_range());
    }
    Ok(duration)
}

/// A clap value parser for durations within `range`.
pub fn duration_in(range: DurationRange) -> impl Fn(&str) -> Result<Duration, String> + Clone + Send + Sync {
    move |text| parse_duration(text, range)
}

/// The numbers one option accepts, inclusive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NumberRange {
    pub min: f64,
    pub max: f64,
}

/// `drive --linear`, `--angular` (then capped by the limits).
pub const SPEED: NumberRange = NumberRange { min: -100.0, max: 100.0 };
/// Caps and accelerations: above zero.
pub const LIMIT: NumberRange = NumberRange { min: 0.001, max: 100.0 };
/// `--speed` of a replay (0: as fast as possible).
pub const REPLAY_SPEED: NumberRange = NumberRange { min: 0.0, max: 1000.0 };
/// `sim --battery`, volts: the TRACER's pack from empty to full.
pub const BATTERY: NumberRange = NumberRange { min: 18.0, max: 30.0 };
/// `sim --drain`.
pub const DRAIN: NumberRange = NumberRange { min: 0.0, max: 1_000_000.0 };

/// A finite number within `range`.
pub fn parse_number(text: &str, range: NumberRange) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(number) if number >= range.min && number <= range.max => Ok(number),
        _ => Err(format!("'{text}' is not a number from {} to {}", range.min, range.max)),
    }
}

/// A clap value parser for numbers within `range`.
pub fn number_in(range: NumberRange) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync {
    move |text| parse_number(text, range)
}

/// `--fault NAME[@TIME]`: the name among the simulator's faults, the time within [`RUN_TIME`].
fn parse_fault(text: &str) -> Result<crate::sim::ScheduledFault, String> {
    let fault: crate::sim::ScheduledFault = text.parse().map_err(|error| format!("{error}"))?;
    if fault.at > RUN_TIME.max {
        return Err(format!(
            "'{text}': the time is out of range: give one from 0s to {}",
            humantime::format_duration(RUN_TIME.max)
        ));
    }
    Ok(fault)
}

/// The simulator's fault names, for `--fault`'s completion (help leaves the long list out: `sim --help` lists
/// them with what each does).
fn fault_values() -> Vec<clap::builder::PossibleValue> {
    let faults = crate::sim::FaultKind::ALL.into_iter();
    faults.map(|fault| clap::builder::PossibleValue::new(fault.name()).help(fault.description())).collect()
}

/// `--sim-param NAME=VALUE`: a known name, its value within the allowed range.
fn parse_sim_param(text: &str) -> Result<crate::sim::SimParamSetting, String> {
    text.parse().map_err(|error| format!("{error}"))
}

/// The simulator's parameter names (`NAME=`), for `--sim-param`'s completion.
fn sim_param_values() -> Vec<clap::builder::PossibleValue> {
    let params = crate::sim::SIM_PARAMS.iter();
    params
        .map(|param| clap::builder::PossibleValue::new(format!("{}=", param.name)).help(param.meaning))
        .collect()
}

/// A value parser that parses with `parse` (clap shows its error text) and offers `values` to shell
/// completion, for values a plain enum cannot list (`--fault NAME@TIME`, `--msg` names).
#[derive(Clone, Copy)]
struct Completing<T> {
    parse: fn(&str) -> Result<T, String>,
    values: fn() -> Vec<clap::builder::PossibleValue>,
}

impl<T: Clone + Send + Sync + 'static> clap::builder::TypedValueParser for Completing<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<T, clap::Error> {
        self.parse.parse_ref(cmd, arg, value)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        Some(Box::new((self.values)().into_iter()))
    }
}

// How to reach the robot; the same for every subcommand (`decode` reads `--serial` as a capture file).
//
// Options of one link are refused with another (`--iface` with `--sim`): clap checks them among the options
// given on one side of the command name. What crosses it (`--sim monitor --iface can0`) and what one option
// needs (`--speed` needs `--replay`, `--baud` needs `--serial`) is checked after parsing
// (`LinkArgs::misuse`): clap evaluates a global option's `requires` on the command's own arguments only, so
// `--replay x.log monitor --speed 4` was refused. A plain comment,
// not a doc comment: clap would take a flattened struct's doc as the top-level `--help` description.
#[derive(Debug, Args)]
#[command(next_help_heading = LINK_HEADING)]
pub struct LinkArgs {
    /// CAN interface [default: $TRACERCTL_IFACE or can0]
    #[arg(long, global = true, value_name = "NAME", conflicts_with_all = ["serial", "sim", "replay"])]
    pub iface: Option<String>,

    /// RS232 port (e.g. /dev/ttyUSB0) instead of CAN; for `decode`, an RS232 capture (raw bytes or hex)
    #[arg(long, global = true, value_name = "PATH", conflicts_with_all = ["sim", "replay"])]
    pub serial: Vec<PathBuf>,

    /// Serial baud rate (with --serial) [default: 115200]
    #[arg(long, global = true, value_name = "BAUD", conflicts_with_all = ["sim", "replay", "iface"], value_parser = clap::value_parser!(u32).range(1..=4_000_000))]
    pub baud: Option<u32>,

    /// Drive an in-process virtual TRACER, not a robot
    #[arg(long, global = true, conflicts_with = "replay")]
    pub sim: bool,

    /// Simulator fault NAME[@TIME], with --sim or `sim` (e.g. estop@0s, motor1-comm@2s; repeatable; TIME from the start, at most 30 days; `tracerctl sim --help` lists them)
    #[arg(long = "fault", global = true, value_name = "NAME[@TIME]", value_parser = Completing { parse: parse_fault, values: fault_values }, hide_possible_values = true)]
    pub faults: Vec<crate::sim::ScheduledFault>,

    /// Simulator chassis parameter, with --sim or `sim` (e.g. dead-time=100ms, left-gain=0.95, track-width=0.38; repeatable; `tracerctl sim --help` lists them)
    #[arg(long = "sim-param", global = true, value_name = "NAME=VAL", value_parser = Completing { parse: parse_sim_param, values: sim_param_values }, hide_possible_values = true)]
    pub sim_params: Vec<crate::sim::SimParamSetting>,

    /// Play back a candump log as a read-only source (for monitor, dashboard)
    #[arg(long, global = true, value_name = "FILE")]
    pub replay: Option<PathBuf>,

    /// Replay speed factor (with --replay; 2 = twice as fast; 0 = as fast as possible; at most 1000) [default: 1]
    #[arg(long, global = true, value_name = "N", conflicts_with_all = ["sim", "serial", "iface"], allow_negative_numbers = true, value_parser = number_in(REPLAY_SPEED))]
    pub speed: Option<f64>,

    /// The link the configuration files name, below the link options and TRACERCTL_IFACE (not an option).
    #[arg(skip)]
    pub configured: ConfiguredLink,
}

/// The environment variable that names the default SocketCAN interface.
pub const IFACE_ENV: &str = "TRACERCTL_IFACE";

/// `$TRACERCTL_IFACE`, when set and not empty.
fn iface_from_env() -> Option<String> {
    std::env::var(IFACE_ENV).ok().filter(|name| !name.is_empty())
}
/// The RS232 rate of the TRACER.
pub const DEFAULT_BAUD: u32 = 115_200;

impl LinkArgs {
    /// The SocketCAN interface: `--iface`, else `$TRACERCTL_IFACE`, else can0. The variable is read here,
    /// not by clap, so that a default set in the environment never conflicts with `--sim` or `--serial`.
    pub fn iface(&self) -> String {
        self.iface
            .clone()
            .or_else(iface_from_env)
            .or_else(|| self.configured.iface.clone())
            .unwrap_or_else(|| "can0".to_string())
    }

    pub fn baud(&self) -> u32 {
        self.baud.or(self.configured.baud).unwrap_or(DEFAULT_BAUD)
    }

    pub fn speed(&self) -> f64 {
        self.speed.unwrap_or(1.0)
    }

    /// The live link these options choose.
    pub fn choice(&self) -> anyhow::Result<LinkChoice> {
        if self.sim {
            return Ok(LinkChoice::Sim);
        }
        if let Some(path) = &self.replay {
            // The range is checked by clap (`--speed`).
            return Ok(LinkChoice::Replay { path: path.clone(), speed: self.speed() });
        }
        match self.serial.as_slice() {
            // The files' serial port, unless `--iface` or TRACERCTL_IFACE chose CAN.
            [] => match &self.configured.serial {
                Some(path) if self.iface.is_none() && iface_from_env().is_none() => {
                    Ok(LinkChoice::Serial { path: path.clone(), baud: self.baud() })
                }
                _ => Ok(LinkChoice::SocketCan { iface: self.iface() }),
            },
            [path] => Ok(LinkChoice::Serial { path: path.clone(), baud: self.baud() }),
            _ => anyhow::bail!("give one --serial port for a live link"),
        }
    }

    /// An output of a live command (`monitor --log`, `dashboard --record`) that is the replayed log or the
    /// serial port: refused before it is created (exit 2).
    fn refuse_overwriting(&self, option: &str, output: Option<&std::path::Path>) -> anyhow::Result<()> {
        use commands::same_file::{refuse_overwriting, Named};
        let Some(path) = output else { return Ok(()) };
        let replay = self.replay.iter().map(|path| Named { option: "--replay", path });
        let serial = self.serial.iter().map(|path| Named { option: "--serial", path });
        refuse_overwriting(&replay.chain(serial).collect::<Vec<_>>(), &[Named { option, path }])
    }

    /// `decode` reads files: the options of live links do not apply (its `--serial` are captures).
    fn refuse_live(&self) -> anyhow::Result<()> {
        let live = [
            (self.sim, "--sim"),
            (self.replay.is_some(), "--replay"),
            (self.iface.is_some(), "--iface"),
            (self.baud.is_some(), "--baud"),
            (self.speed.is_some(), "--speed"),
            (!self.faults.is_empty(), "--fault"),
            (!self.sim_params.is_empty(), "--sim-param"),
        ];
        match live.iter().find(|(given, _)| *given) {
            Some((_, option)) => Err(usage(format!(
                "{option} is for live links; decode reads files (candump logs, or RS232 captures with --serial)"
            ))),
            None => Ok(()),
        }
    }
}

/// What each link option is for, added as a tip to clap's conflict and missing-argument errors.
const LINK_TIPS: &[(&str, &str)] = &[
    ("--speed", "--speed sets the replay speed and needs --replay; drive's speed is --linear (m/s) and --angular (rad/s)"),
    ("--iface", "--iface names a SocketCAN interface; it does not apply with --serial, --sim or --replay"),
    ("--baud", "--baud sets the rate of a --serial port; it does not apply to CAN, --sim or --replay"),
];

/// Parses the process's command line; on a usage error, prints clap's message (plus what the link
/// options involved are for, or the tracerctl spelling of a can-utils habit) and exits 2.
pub fn parse() -> Cli {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    try_parse_from(&args).unwrap_or_else(|error| error.exit())
}

/// The command line parsed and checked as [`parse`] does it, with the same tips in its usage errors.
pub fn try_parse_from(args: &[std::ffi::OsString]) -> Result<Cli, clap::Error> {
    parse_with_config(args)
        .and_then(|cli| match cli.link.misuse().or_else(|| interface_as_frame(&cli.command)) {
            Some(error) => Err(error),
            None => Ok(cli),
        })
        .map_err(|error| habit_tip(error, args).unwrap_or_else(|error| with_tips(error, args)))
}

/// The pairs of link options that exclude each other, by the rule of each option's `conflicts_with_all`.
const LINK_CONFLICTS: &[(&str, &str)] = &[
    ("--iface", "--serial"),
    ("--iface", "--sim"),
    ("--iface", "--replay"),
    ("--serial", "--sim"),
    ("--serial", "--replay"),
    ("--baud", "--sim"),
    ("--baud", "--replay"),
    ("--baud", "--iface"),
    ("--sim", "--replay"),
    ("--speed", "--sim"),
    ("--speed", "--serial"),
    ("--speed", "--iface"),
];

impl LinkArgs {
    /// A link option given with one it excludes, or without the one it needs, wherever each was given;
    /// the error clap gives for these, with the same tips.
    fn misuse(&self) -> Option<clap::Error> {
        use clap::error::{ContextKind, ContextValue, ErrorKind};
        let given = |option: &str| match option {
            "--iface" => self.iface.is_some(),
            "--serial" => !self.serial.is_empty(),
            "--baud" => self.baud.is_some(),
            "--sim" => self.sim,
            "--replay" => self.replay.is_some(),
            _ => self.speed.is_some(),
        };
        let needs = [("--speed", "--replay", "--replay <FILE>"), ("--baud", "--serial", "--serial <PATH>")];
        // What an option needs first: `--sim drive --speed 0.3` meant a drive speed, which the tip says.
        // The files' serial port is the `--serial` that `--baud` needs.
        let has = |needed: &str| given(needed) || (needed == "--serial" && self.configured.serial.is_some());
        if let Some((_, _, needed)) = needs.iter().find(|(option, needed, _)| given(option) && !has(needed)) {
            return Some(usage_error_with(
                ErrorKind::MissingRequiredArgument,
                None,
                vec![(ContextKind::InvalidArg, ContextValue::Strings(vec![needed.to_string()]))],
            ));
        }
        let (option, other) = LINK_CONFLICTS.iter().find(|(a, b)| given(a) && given(b))?;
        Some(usage_error_with(
            ErrorKind::ArgumentConflict,
            None,
            vec![
                (ContextKind::InvalidArg, ContextValue::String(option.to_string())),
                (ContextKind::PriorArg, ContextValue::String(other.to_string())),
            ],
        ))
    }
}

/// `send-raw can0 121#...`, as cansend is called: the interface given where the frames go.
fn interface_as_frame(command: &Command) -> Option<clap::Error> {
    let Command::SendRaw(args) = command else { return None };
    let first = args.frames.first().filter(|frame| looks_like_interface(frame))?;
    Some(habit_error("send-raw", first, None, interface_tip(first, "send-raw")))
}

/// `can0`, `vcan1`, `slcan0`: a name that ends in a digit and cannot be hex (so never an RS232 frame).
fn looks_like_interface(text: &str) -> bool {
    let bytes = text.as_bytes();
    (2..=15).contains(&bytes.len())
        && bytes[0].is_ascii_alphabetic()
        && bytes[bytes.len() - 1].is_ascii_digit()
        && bytes.iter().all(u8::is_ascii_alphanumeric)
        && !bytes.iter().all(u8::is_ascii_hexdigit)
}

fn interface_tip(name: &str, subcommand: &str) -> String {
    let subcommand = if subcommand.is_empty() { "COMMAND" } else { subcommand };
    format!(
        "the interface is `--iface {name}`: tracerctl --iface {name} {subcommand} (candump and cansend take it \
         as their first argument)"
    )
}

/// The tracerctl spelling of a can-utils habit clap does not know: an interface name as an argument
/// (`monitor can0`), `--interface can0`, and drive's `--time 2s` or `-d 2s`. The error, rebuilt with that
/// tip in place of clap's guess (`--time` is closest to `--sim`); anything else comes back unchanged.
fn habit_tip(error: clap::Error, args: &[std::ffi::OsString]) -> Result<clap::Error, clap::Error> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if !matches!(error.kind(), ErrorKind::UnknownArgument | ErrorKind::InvalidSubcommand) {
        return Err(error);
    }
    let invalid = [ContextKind::InvalidArg, ContextKind::InvalidSubcommand].into_iter().find_map(|kind| {
        match error.get(kind) {
            Some(ContextValue::String(invalid)) => Some(invalid.clone()),
            _ => None,
        }
    });
    let Some(invalid) = invalid else { return Err(error) };
    let args: Vec<&str> = args.iter().filter_map(|arg| arg.to_str()).collect();
    let (flag, inline) = invalid.split_once('=').map_or((invalid.as_str(), None), |(f, v)| (f, Some(v)));
    // The value after the flag, as the user typed it.
    let value = inline.map(str::to_string).or_else(|| {
        let at = args.iter().position(|arg| *arg == invalid.as_str())?;
        args.get(at + 1).filter(|value| !value.starts_with('-')).map(|value| value.to_string())
    });
    let value = value.or_else(|| {
        let prefix = format!("{flag}=");
        args.iter().find_map(|arg| arg.strip_prefix(&prefix)).map(str::to_string)
    });
    let top = command();
    let subcommand =
        args.iter().skip(1).find_map(|arg| top.find_subcommand(arg)).map_or("", |sub| sub.get_name());
    let (suggested, tip) = if looks_like_interface(&invalid) {
        (None, interface_tip(&invalid, subcommand))
    } else if flag == "--interface" {
        (Some("--iface"), interface_tip(value.as_deref().unwrap_or("NAME"), subcommand))
    } else if subcommand == "drive" && matches!(flag, "--time" | "-d") {
        let time = value.unwrap_or_else(|| "DURATION".to_string());
        (Some("--for"), format!("drive's time is `--for {time}` (or `--duration {time}`), e.g. 2s, 1500ms"))
    } else {
        return Err(error);
    };
    Ok(habit_error(subcommand, &invalid, suggested, tip))
}

/// An "unexpected argument" usage error (exit 2) with the tracerctl spelling as its tip.
fn habit_error(subcommand: &str, invalid: &str, suggested: Option<&str>, tip: String) -> clap::Error {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let mut context = vec![(ContextKind::InvalidArg, ContextValue::String(invalid.to_string()))];
    if let Some(suggested) = suggested {
        context.push((ContextKind::SuggestedArg, ContextValue::String(suggested.to_string())));
    }
    context.push((ContextKind::Suggested, ContextValue::StyledStrs(vec![tip.into()])));
    usage_error_with(ErrorKind::UnknownArgument, Some(subcommand), context)
}

/// A usage error as clap words it from `context`, with the usage line of `subcommand` (or the top level).
fn usage_error_with(
    kind: clap::error::ErrorKind,
    subcommand: Option<&str>,
    context: Vec<(clap::error::ContextKind, clap::error::ContextValue)>,
) -> clap::Error {
    use clap::error::{ContextKind, ContextValue};
    let mut top = command();
    top.build();
    let usage = match subcommand.and_then(|name| top.find_subcommand_mut(name)) {
        Some(sub) => sub.render_usage(),
        None => top.render_usage(),
    };
    let mut error = clap::Error::new(kind).with_cmd(&top);
    for (kind, value) in context {
        error.insert(kind, value);
    }
    error.insert(ContextKind::Usage, ContextValue::StyledStr(usage));
    error
}

fn with_tips(mut error: clap::Error, args: &[std::ffi::OsString]) -> clap::Error {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if !matches!(error.kind(), ErrorKind::ArgumentConflict | ErrorKind::MissingRequiredArgument) {
        return error;
    }
    let given = |flag: &str| {
        args.iter()
            .filter_map(|arg| arg.to_str())
            .any(|arg| arg == flag || arg.starts_with(&format!("{flag}=")))
    };
    let tips: Vec<clap::builder::StyledStr> =
        LINK_TIPS.iter().filter(|(flag, _)| given(flag)).map(|(_, tip)| (*tip).into()).collect();
    if !tips.is_empty() {
        error.insert(ContextKind::Suggested, ContextValue::StyledStrs(tips));
    }
    error
}

#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// Shell to generate completions for
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// The completion script of this command line for `shell`.
pub fn completion_script(shell: clap_complete::Shell) -> Vec<u8> {
    let mut out = Vec::new();
    clap_complete::generate(shell, &mut command(), "tracerctl", &mut out);
    out
}

const CONFIG_AFTER_HELP: &str = "\
Files, lowest precedence first: /etc/tracerctl/config.toml, then $XDG_CONFIG_HOME/tracerctl/config.toml
(~/.config/tracerctl/config.toml; on Windows %APPDATA%\\tracerctl\\config.toml only). TRACERCTL_CONFIG=FILE
reads that file only; TRACERCTL_CONFIG= (empty) reads none.

Top-level tables ([link], [drive], [battery], [record]) hold defaults; [profiles.NAME] tables override them
for one robot, chosen with --profile NAME or TRACERCTL_PROFILE. Keys are the long options' names with _ for -:
  [link]                  # the robot's link
  iface = \"can0\"          # or serial = \"/dev/ttyUSB0\", baud = 115200
  protocol = \"v2\"
  [drive]                 # drive's and the dashboard's caps and ramps
  max_linear = 0.5        # m/s; also max_angular, accel, decel (drive --help)
  key_timeout = \"300ms\"
  [battery]               # the low-battery threshold, volts
  warning_volts = 23.0
  [record]                # tracerctl record's options
  dir = \"/var/lib/tracerctl/can0\"
  triggers = [\"battery_voltage<23.0\"]
  [profiles.tracer-07]    # one robot's values over the tables above
  link.iface = \"can1\"
  drive.max_linear = 0.8

Precedence: command-line option > environment variable > profile > file > built-in default. A value from a
file is checked as its option is (errors name FILE:LINE:COLUMN); caps are clamped as the options' are.";

#[derive(Debug, Args)]
pub struct ConfigArgs {
    #[command(subcommand)]
    pub action: ConfigAction,
}

#[derive(Debug, Subcommand)]
pub enum ConfigAction {
    /// Every effective setting with its source: flag, env VAR, profile NAME (FILE:LINE), file FILE:LINE, default
    Show {
        /// Text, or JSON (docs/json.md)
        #[arg(long, short = 'f', value_enum, default_value_t = ReportFormatArg::Text)]
        format: ReportFormatArg,
    },
    /// The configuration files looked for, in order, and which exist (reads none of them)
    Path,
}

impl ConfigArgs {
    fn options(self, config: Configured) -> commands::config::Options {
        match self.action {
            ConfigAction::Show { format } => commands::config::Options::Show {
                report: config.report(),
                json: format == ReportFormatArg::Json,
            },
            ConfigAction::Path => commands::config::Options::Path {
                files: crate::config::file_states(&config.lookup),
                note: crate::config::lookup_note(&config.lookup),
            },
        }
    }
}

/// The configuration files as applied to a command line: what was read, the error that stops the command
/// (reported by [`run`], so that `config path` still works), and each key's effective value and source.
#[derive(Clone, Debug, Default)]
pub struct Configured {
    pub lookup: crate::config::Lookup,
    pub loaded: crate::config::Loaded,
    pub error: Option<crate::config::ConfigError>,
    /// Where the profile was chosen: `--profile` or `env TRACERCTL_PROFILE`.
    pub profile_from: Option<String>,
    pub rows: Vec<crate::config::Row>,
}

impl Configured {
    /// `battery.warning_volts`, else the manual's alarm voltage.
    /// `commission`'s thresholds: the built-in ones, with the `[commission]` keys the files set.
    fn commission_thresholds(&self) -> anyhow::Result<commands::commission::verdict::Thresholds> {
        let mut thresholds = commands::commission::verdict::Thresholds::default();
        for key in crate::config::KEYS.iter().filter(|key| key.table == "commission") {
            if let Some(crate::config::Value::Number(value)) =
                self.loaded.effective(key).map(|effective| &effective.setting.value)
            {
                thresholds.set(key.name, *value);
            }
        }
        let t = &thresholds;
        for (name, band) in [
            ("dead_time", t.dead_time_ms),
            ("rise_time", t.rise_time_ms),
            ("overshoot", t.overshoot_percent),
            ("gain_ratio", t.gain_ratio),
            ("heading_drift", t.heading_drift_deg_per_m),
            ("track_width", t.track_width_percent),
            ("odometer_scale", t.odometer_scale_percent),
            ("command_timeout", t.command_timeout_ms),
            ("internal_resistance", t.internal_resistance_ohm),
        ] {
            if band.warn > band.fail {
                return Err(usage(format!(
                    "commission.{name}: the warning limit ({}) is beyond the failing one ({}) (tracerctl config show)",
                    band.warn, band.fail
                )));
            }
        }
        Ok(thresholds)
    }

    fn battery_warning_volts(&self) -> f64 {
        let key = crate::config::Key::find("battery.warning_volts");
        match key.and_then(|key| self.loaded.effective(key)).map(|effective| &effective.setting.value) {
            Some(crate::config::Value::Number(volts)) => *volts,
            _ => crate::protocol::constants::volts(crate::protocol::constants::BATTERY_WARNING_DV),
        }
    }

    fn report(&self) -> crate::config::Report {
        let profile = self.loaded.profile.clone().zip(self.profile_from.clone());
        crate::config::Report {
            files: self.loaded.files.clone(),
            note: self.loaded.note.clone(),
            profile,
            rows: self.rows.clone(),
        }
    }
}

/// The link the configuration files name (one of `iface` and `serial`, and the rate).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ConfiguredLink {
    pub iface: Option<String>,
    pub serial: Option<PathBuf>,
    pub baud: Option<u32>,
}

/// An argument whose value came from a configuration file: its id, its key and where it was written.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigOrigin {
    pub arg: &'static str,
    pub key: String,
    pub at: crate::config::Location,
}

/// Parses `args` with the configuration files' values as the defaults of the arguments they set: parsed
/// once to learn the profile, the files read and checked by the options' own parsers, then parsed again
/// with those defaults, so that an option given (or its environment variable) still wins.
fn parse_with_config(args: &[std::ffi::OsString]) -> Result<Cli, clap::Error> {
    use clap::FromArgMatches;
    let first = command().try_get_matches_from(args)?;
    let lookup = crate::config::lookup();
    // An empty name is no profile (`TRACERCTL_PROFILE=` clears one set for the session).
    let mut profile = first.get_one::<String>("profile").cloned().filter(|name| !name.is_empty());
    let mut configured = Configured { lookup: lookup.clone(), ..Configured::default() };
    configured.profile_from = match first.value_source("profile").filter(|_| profile.is_some()) {
        Some(clap::parser::ValueSource::CommandLine) => Some("--profile".to_string()),
        Some(clap::parser::ValueSource::EnvVariable) => Some(format!("env {}", crate::config::PROFILE_ENV)),
        _ => None,
    };
    // The systemd unit's `record --instance NAME`: a profile of that name, when a file has one.
    if let Some(name) = instance_profile(&first, &lookup).filter(|_| profile.is_none()) {
        configured.profile_from = Some("record --instance".to_string());
        profile = Some(name);
    }
    let loaded = crate::config::load(&lookup, profile.as_deref()).and_then(|loaded| {
        check_config_values(&command(), &loaded)?;
        Ok(loaded)
    });
    let matches = match loaded {
        Ok(loaded) => {
            let matches = with_config_defaults(command(), &loaded).try_get_matches_from(args)?;
            configured.loaded = loaded;
            matches
        }
        Err(error) => {
            configured.error = Some(error);
            first
        }
    };
    let mut cli = Cli::from_arg_matches(&matches)?;
    configured.rows = config_rows(&matches, &configured.loaded);
    cli.link.configured = configured_link(&configured.loaded);
    let origins = |subcommand| config_origins(&matches, &configured.loaded, subcommand);
    match &mut cli.command {
        Command::Drive(args) => args.limits.from_config = origins("drive"),
        Command::Dashboard(args) => args.limits.from_config = origins("dashboard"),
        _ => {}
    }
    cli.config = configured;
    Ok(cli)
}

/// `record --instance NAME` when NAME is a profile of the configuration files.
fn instance_profile(matches: &clap::ArgMatches, lookup: &crate::config::Lookup) -> Option<String> {
    let name = matches.subcommand_matches("record")?.get_one::<String>("instance")?;
    let loaded = crate::config::load(lookup, None).ok()?;
    crate::config::profile::profile_names(&loaded.parsed).contains(name).then(|| name.clone())
}

/// The argument a key's target names, and the command that owns it.
fn config_target<'a>(
    top: &'a clap::Command,
    target: &crate::config::Target,
) -> Option<(&'a clap::Command, &'a clap::Arg)> {
    let owner = if target.subcommand.is_empty() { top } else { top.find_subcommand(target.subcommand)? };
    Some((owner, owner.get_arguments().find(|arg| arg.get_id() == target.arg)?))
}

/// Every value of every file (each profile's too) through the parser of each argument it goes to: the same
/// ranges and words as the option, at the value's `FILE:LINE:COLUMN`.
fn check_config_values(
    top: &clap::Command,
    loaded: &crate::config::Loaded,
) -> Result<(), crate::config::ConfigError> {
    for setting in loaded.all_settings() {
        for target in setting.key.targets {
            let Some((_, arg)) = config_target(top, target) else { continue };
            for text in setting.value.arg_texts(target.inverted) {
                // The option's parser on a positional argument of its own: nothing else of the command
                // (conflicts, requirements) is involved.
                let alone = clap::Arg::new("value")
                    .value_parser(arg.get_value_parser().clone())
                    .allow_hyphen_values(true);
                let check = clap::Command::new("config").no_binary_name(true).arg(alone);
                if let Err(error) = check.try_get_matches_from(["--", text.as_str()]) {
                    return Err(crate::config::ConfigError::content(format!(
                        "{}: {}: {}",
                        setting.at,
                        setting.key.dotted(),
                        parser_reason(&error, &text)
                    )));
                }
            }
        }
    }
    Ok(())
}

/// What a value parser said, without clap's framing (which names the stand-in argument).
fn parser_reason(error: &clap::Error, value: &str) -> String {
    use clap::error::{ContextKind, ContextValue};
    if let Some(source) = std::error::Error::source(error) {
        return source.to_string();
    }
    match (error.get(ContextKind::ValidValue), error.get(ContextKind::SuggestedValue)) {
        (Some(ContextValue::Strings(valid)), Some(ContextValue::String(suggested))) => {
            format!("'{value}' is not one of {} (did you mean {suggested}?)", valid.join(", "))
        }
        (Some(ContextValue::Strings(valid)), _) => format!("'{value}' is not one of {}", valid.join(", ")),
        _ => format!("'{value}' is not accepted"),
    }
}

/// The command with each effective value that is an argument's default (`Use::Default`) set as that
/// argument's default.
fn with_config_defaults(mut top: clap::Command, loaded: &crate::config::Loaded) -> clap::Command {
    for effective in &loaded.effective {
        let key = effective.setting.key;
        if key.usage != crate::config::Use::Default {
            continue;
        }
        for target in key.targets {
            if config_target(&top, target).is_none() {
                continue;
            }
            let texts = effective.setting.value.arg_texts(target.inverted);
            // A required option (`record --dir`) is satisfied by the file's value.
            let set = |arg: clap::Arg| arg.required(false).default_values(texts.clone());
            top = if target.subcommand.is_empty() {
                top.mut_arg(target.arg, set)
            } else {
                top.mut_subcommand(target.subcommand, |sub| sub.mut_arg(target.arg, set))
            };
        }
    }
    top
}

/// The link the effective settings name.
fn configured_link(loaded: &crate::config::Loaded) -> ConfiguredLink {
    use crate::config::{Key, Value};
    let value =
        |dotted| loaded.effective(Key::find(dotted)?).map(|effective| effective.setting.value.clone());
    ConfiguredLink {
        iface: match value("link.iface") {
            Some(Value::Text(iface)) => Some(iface),
            _ => None,
        },
        serial: match value("link.serial") {
            Some(Value::Text(path)) => Some(PathBuf::from(path)),
            _ => None,
        },
        baud: match value("link.baud") {
            Some(Value::Count(baud)) => u32::try_from(baud).ok(),
            _ => None,
        },
    }
}

/// The arguments of `subcommand` whose value is a configuration file's (their default, which the file set).
fn config_origins(
    matches: &clap::ArgMatches,
    loaded: &crate::config::Loaded,
    subcommand: &str,
) -> Vec<ConfigOrigin> {
    let Some(sub) = matches.subcommand_matches(subcommand) else { return Vec::new() };
    let mut origins = Vec::new();
    for effective in &loaded.effective {
        let key = effective.setting.key;
        for target in key.targets.iter().filter(|target| target.subcommand == subcommand) {
            let known = sub.ids().any(|id| id.as_str() == target.arg);
            if known && sub.value_source(target.arg) == Some(clap::parser::ValueSource::DefaultValue) {
                origins.push(ConfigOrigin {
                    arg: target.arg,
                    key: key.dotted(),
                    at: effective.setting.at.clone(),
                });
            }
        }
    }
    origins
}

/// Each key's effective value and its source, for `config show`: a global option given (or its `env`),
/// the key's own environment variable, the files, then the argument's built-in default.
fn config_rows(matches: &clap::ArgMatches, loaded: &crate::config::Loaded) -> Vec<crate::config::Row> {
    use crate::config::{Row, Source, KEYS};
    use clap::parser::ValueSource;
    let top = command();
    KEYS.iter()
        .map(|key| {
            let row = |values: Vec<String>, source| Row { key, values, source };
            let global = key.targets.iter().filter(|target| target.subcommand.is_empty());
            for target in global {
                let Some((_, arg)) = config_target(&top, target) else { continue };
                let known = matches.ids().any(|id| id.as_str() == target.arg);
                let raw = || -> Vec<String> {
                    let values = matches.get_raw(target.arg).into_iter().flatten();
                    values.map(|value| value.to_string_lossy().into_owned()).collect()
                };
                match known.then(|| matches.value_source(target.arg)).flatten() {
                    Some(ValueSource::CommandLine) => {
                        let flag = format!("--{}", arg.get_long().unwrap_or(target.arg));
                        return row(raw(), Source::Flag(flag));
                    }
                    Some(ValueSource::EnvVariable) => {
                        let variable = arg.get_env().map(|name| name.to_string_lossy().into_owned());
                        return row(raw(), Source::Env(variable.unwrap_or_default()));
                    }
                    _ => {}
                }
            }
            if let Some(variable) = key.env {
                if let Some(value) = std::env::var(variable).ok().filter(|value| !value.is_empty()) {
                    return row(vec![value], Source::Env(variable.to_string()));
                }
            }
            if let Some(effective) = loaded.effective(key) {
                let at = effective.setting.at.clone();
                let source = match &effective.profile {
                    Some(name) => Source::Profile { name: name.clone(), at },
                    None => Source::File { at },
                };
                return row(effective.setting.value.arg_texts(false), source);
            }
            row(built_in_default(&top, key), Source::Default)
        })
        .collect()
}

/// A key's default: its first argument's (a `--no-...` flag's inverted), else the key's fallback.
fn built_in_default(top: &clap::Command, key: &crate::config::Key) -> Vec<String> {
    for target in key.targets {
        let Some((_, arg)) = config_target(top, target) else { continue };
        let defaults: Vec<String> =
            arg.get_default_values().iter().map(|value| value.to_string_lossy().into_owned()).collect();
        match defaults.as_slice() {
            [] => {}
            [flag] if target.inverted => return vec![(flag != "true").to_string()],
            _ => return defaults,
        }
    }
    key.fallback.value().into_iter().collect()
}

/// `--fault` and `--sim-param` go to a simulator: `sim` itself or `--sim`'s (decode refuses them with the
/// live options).
fn refuse_simulator_options_without_one(link: &LinkArgs, command: &Command) -> anyhow::Result<()> {
    let simulator = link.sim || matches!(command, Command::Sim(_));
    if simulator || matches!(command, Command::Decode(_)) {
        return Ok(());
    }
    if !link.faults.is_empty() {
        return Err(usage(
            "--fault injects a fault into the simulator: add --sim (e.g. tracerctl --sim --fault estop@0s doctor), \
             or serve a simulator with `tracerctl sim --fault ...`",
        ));
    }
    if !link.sim_params.is_empty() {
        return Err(usage(
            "--sim-param sets a parameter of the simulator: add --sim (e.g. tracerctl --sim --sim-param dead-time=100ms \
             doctor), or serve a simulator with `tracerctl sim --sim-param ...`",
        ));
    }
    Ok(())
}

/// Runs the parsed command line: each command's settings (usage errors first), the global ones, then the
/// command. Returns the exit status.
pub fn run(cli: Cli) -> anyhow::Result<u8> {
    let Cli { protocol, color, link, command, profile: _, config } = cli;
    // A mistake in a configuration file stops every command but the one that says where the files are.
    if let Some(error) = config
        .error
        .clone()
        .filter(|_| !matches!(command, Command::Config(ConfigArgs { action: ConfigAction::Path })))
    {
        let code = if error.is_usage() { crate::exit::USAGE } else { crate::exit::FAILURE };
        return Err(crate::exit::Failure { code, message: error.message }.into());
    }
    refuse_simulator_options_without_one(&link, &command)?;
    let sim_faults = link.faults.clone();
    let sim_params = link.sim_params.clone();
    let battery_warning_volts = config.battery_warning_volts();
    let global = |link: LinkChoice| Global {
        link,
        color: color.into(),
        protocol: protocol.into(),
        sim_faults: sim_faults.clone(),
        sim_params: sim_params.clone(),
        battery_warning_volts,
    };
    // What `decode` and `completions` get: they open no link.
    let offline = || global(LinkChoice::SocketCan { iface: link.iface() });
    match command {
        Command::Decode(args) => {
            link.refuse_live()?;
            let serial = link.serial.clone();
            commands::decode::run(&offline(), &args.options(serial)?)
        }
        Command::Completions(args) => commands::completions::run(
            &offline(),
            &commands::completions::Options { script: completion_script(args.shell) },
        ),
        Command::Config(args) => commands::config::run(&offline(), &args.options(config)),
        Command::Monitor(args) => {
            let options = args.options()?;
            link.refuse_overwriting("--log", options.log.as_deref())?;
            commands::monitor::run(&global(link.choice()?), &options)
        }
        Command::Drive(args) => {
            let options = args.options()?;
            link.refuse_overwriting("--record", options.record.as_deref())?;
            commands::drive::run(&global(link.choice()?), &options)
        }
        Command::Commission(args) => commission(&link, &config, args, global),
        Command::Doctor(args) => {
            commands::doctor::run(&global(link.choice()?), &args.options(battery_warning_volts))
        }
        Command::Mode(args) => commands::mode::run(&global(link.choice()?), &args.options()),
        Command::ClearErrors(args) => commands::clear_errors::run(&global(link.choice()?), &args.options()),
        Command::Lights(args) => commands::lights::run(&global(link.choice()?), &args.options()),
        Command::SendRaw(args) => commands::send_raw::run(&global(link.choice()?), &args.options()),
        Command::Sim(args) => {
            let options = args.options(&link)?;
            commands::sim::run(&global(link.choice()?), &options)
        }
        Command::Report(args) => commands::report::run(&global(link.choice()?), &args.options()),
        Command::Dashboard(args) => {
            let options = args.options(battery_warning_volts)?;
            link.refuse_overwriting("--record", options.record.as_deref())?;
            commands::dashboard::run(&global(link.choice()?), &options)
        }
        Command::Record(args) => {
            // An instance that names a profile takes the profile's link (and settings), not its name.
            let profiled = args.instance.is_some() && config.loaded.profile == args.instance;
            let (options, instance) = args.options(&link, profiled)?;
            let global = global(match instance {
                Some(choice) => choice,
                None => link.choice()?,
            });
            record(&global, options)
        }
    }
}

/// `commission`: its outputs refused where they are an input, then the run.
fn commission(
    link: &LinkArgs,
    config: &Configured,
    args: CommissionArgs,
    global: impl Fn(LinkChoice) -> Global,
) -> anyhow::Result<u8> {
    use commands::same_file::{refuse_overwriting, Named};
    let options = args.options(config)?;
    let inputs: Vec<Named> = options.compare.iter().map(|path| Named { option: "--compare", path }).collect();
    let outputs: Vec<Named> = [("--record", &options.record), ("--plot", &options.plot)]
        .into_iter()
        .filter_map(|(option, path)| Some(Named { option, path: path.as_deref()? }))
        .collect();
    refuse_overwriting(&inputs, &outputs)?;
    link.refuse_overwriting("--record", options.record.as_deref())?;
    link.refuse_overwriting("--plot", options.plot.as_deref())?;
    commands::commission::run(&global(link.choice()?), &options)
}

/// `record`, its low-battery trigger at the configured warning voltage.
fn record(global: &Global, mut options: commands::record::Options) -> anyhow::Result<u8> {
    use commands::record::Action;
    if let Action::Record(settings) | Action::DryRun(settings) = &mut options.action {
        settings.triggers.battery_warning_volts = global.battery_warning_volts;
    }
    commands::record::run(global, &options)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ProtocolArg {
    /// Decide from the traffic
    Auto,
    /// CAN protocol V1 (older firmware, checksummed frames)
    V1,
    /// CAN protocol V2 (current firmware)
    V2,
}

impl From<ProtocolArg> for ProtocolHint {
    fn from(value: ProtocolArg) -> Self {
        match value {
            ProtocolArg::Auto => ProtocolHint::Auto,
            ProtocolArg::V1 => ProtocolHint::V1,
            ProtocolArg::V2 => ProtocolHint::V2,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ColorArg {
    /// Colour on a terminal, unless the NO_COLOR environment variable is set
    Auto,
    /// Colour even into a pipe or a file, even with NO_COLOR set
    Always,
    /// Never colour
    Never,
}

impl From<ColorArg> for ColorChoice {
    fn from(value: ColorArg) -> Self {
        match value {
            ColorArg::Auto => ColorChoice::Auto,
            ColorArg::Always => ColorChoice::Always,
            ColorArg::Never => ColorChoice::Never,
        }
    }
}

/// Message names accepted by `--msg`: every TRACER message plus the shapes of other frames.
pub const FILTER_NAMES: &[&str] = crate::output::filter::FrameShape::NAMES;

/// Every name `--msg` accepts: the messages, then the shapes of other frames.
fn msg_names() -> impl Iterator<Item = &'static str> {
    crate::protocol::message::MESSAGE_NAMES.iter().chain(FILTER_NAMES).copied()
}

/// The names `--msg` accepts, for completion.
fn msg_values() -> Vec<clap::builder::PossibleValue> {
    msg_names().map(clap::builder::PossibleValue::new).collect()
}

/// `--msg` in `--help` and the man pages: every name (`-h` gives an example; completions offer them all).
fn msg_long_help() -> String {
    let names: Vec<_> = msg_names().collect();
    format!("Only these messages (comma-separated), e.g. system_state,odometry. Names: {}", names.join(", "))
}

fn parse_msg_name(text: &str) -> Result<&'static str, String> {
    msg_names().find(|name| *name == text).ok_or_else(|| {
        let known: Vec<_> = msg_names().collect();
        format!("unknown message name '{text}'; known: {}", known.join(", "))
    })
}

fn parse_id(text: &str) -> Result<crate::protocol::FrameId, String> {
    crate::protocol::FrameId::parse(text.trim())
}

/// The clap command, for completions, man pages and tests.
pub fn command() -> clap::Command {
    <Cli as clap::CommandFactory>::command()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn definition_is_consistent() {
        command().debug_assert();
    }

    #[test]
    fn negative_speeds_and_durations_parse() {
        use clap::Parser;
        let cli = Cli::try_parse_from([
            "tracerctl",
            "drive",
            "--linear",
            "-0.5",
            "--angular",
            "-0.2",
            "--for",
            "1500ms",
        ])
        .unwrap();
        let Command::Drive(args) = cli.command else { panic!() };
        assert_eq!((args.linear, args.angular), (Some(-0.5), Some(-0.2)));
        assert_eq!(args.duration, Some(std::time::Duration::from_millis(1500)));
        assert_eq!(parse_duration("2.5", DRIVE_TIME), Ok(std::time::Duration::from_millis(2500)));
        assert!(parse_duration("soon", DRIVE_TIME).is_err());
        assert!(Cli::try_parse_from(["tracerctl", "lights"]).is_err(), "lights needs --front or --release");
        assert!(
            Cli::try_parse_from(["tracerctl", "lights", "--front", "custom", "--brightness", "101"]).is_err()
        );
    }

    #[test]
    fn reflow_joins_prose_and_keeps_tables_and_headings() {
        let text =
            "A paragraph wrapped\nby hand.\n\nKeys:\n  q  quit\n  ?  help\nAfter the table\ncontinued.";
        assert_eq!(
            reflow(text),
            "A paragraph wrapped by hand.\n\nKeys:\n  q  quit\n  ?  help\nAfter the table continued."
        );
    }

    #[test]
    fn ids_and_names_parse() {
        assert_eq!(parse_id("0x211"), Ok(crate::protocol::FrameId::Standard(0x211)));
        assert_eq!(parse_id("aa01"), Ok(crate::protocol::FrameId::Serial(0xAA01)));
        assert!(parse_id("0x").is_err());
        assert!(parse_id("zz").is_err());
        assert_eq!(parse_msg_name("odometry"), Ok("odometry"));
        assert!(parse_msg_name("odometer").unwrap_err().contains("known: motion_command"));
    }

    fn usage_error(args: &[&str]) -> String {
        let args: Vec<std::ffi::OsString> = args.iter().map(Into::into).collect();
        let error = try_parse_from(&args).expect_err("a usage error");
        assert_eq!(error.exit_code(), 2, "{error}");
        error.to_string()
    }

    #[test]
    fn durations_out_of_range_are_usage_errors_that_give_the_range() {
        // Each of these panicked (Duration::from_secs_f64 or Instant + d overflowing).
        for (args, range) in [
            (&["tracerctl", "drive", "--for", "1e20"][..], "from 0s to 1day"),
            (&["tracerctl", "sim", "--duration", "1e20"], "from 0s to 30days"),
            (&["tracerctl", "doctor", "--listen", "1e20"], "from 100ms to 10m"),
            (&["tracerctl", "monitor", "--duration", "1e19"], "from 0s to 30days"),
            (&["tracerctl", "doctor", "--listen", "1e19"], "from 100ms to 10m"),
            (&["tracerctl", "mode", "can", "--timeout", "1e20"], "from 0s to 10m"),
            (&["tracerctl", "clear-errors", "--timeout", "inf"], "from 0s to 10m"),
            (&["tracerctl", "lights", "--release", "--timeout", "nan"], "from 0s to 10m"),
            (&["tracerctl", "monitor", "--silence", "-1"], "from 0s to 1h"),
            (&["tracerctl", "drive", "--for", "-2s"], "from 0s to 1day"),
            (&["tracerctl", "drive", "--for", "25h"], "from 0s to 1day"),
            (&["tracerctl", "doctor", "--listen", "10ms"], "from 100ms to 10m"),
        ] {
            let message = usage_error(args);
            assert!(
                message.contains(&format!("out of range: give a duration {range}")),
                "{args:?}: {message}"
            );
        }
        assert!(usage_error(&["tracerctl", "drive", "--for", "soon"]).contains("accepted: from 0s to 1day"));
        assert!(usage_error(&["tracerctl", "drive", "--for", "--linear"])
            .contains("'--linear' is not a duration"));
        assert_eq!(parse_duration("24h", DRIVE_TIME), Ok(Duration::from_secs(86_400)));
        assert_eq!(parse_duration("0", DRIVE_TIME), Ok(Duration::ZERO));
        assert_eq!(parse_duration("100ms", LISTEN), Ok(Duration::from_millis(100)));
    }

    #[test]
    fn numbers_out_of_range_are_usage_errors() {
        for (args, expected) in [
            (&["tracerctl", "drive", "--linear", "nan"][..], "'nan' is not a number from -100 to 100"),
            (&["tracerctl", "drive", "--angular", "inf"], "'inf' is not a number from -100 to 100"),
            (&["tracerctl", "drive", "--max-linear", "-1"], "'-1' is not a number from 0.001 to 100"),
            (&["tracerctl", "dashboard", "--decel", "nan"], "'nan' is not a number from 0.001 to 100"),
            (&["tracerctl", "sim", "--battery", "5"], "'5' is not a number from 18 to 30"),
            (&["tracerctl", "sim", "--drain", "-1"], "'-1' is not a number from 0 to 1000000"),
            (
                &["tracerctl", "--replay", "x.log", "--speed", "nan", "monitor"],
                "'nan' is not a number from 0 to 1000",
            ),
            (&["tracerctl", "--serial", "/dev/ttyUSB0", "--baud", "0", "monitor"], "0 is not in 1..=4000000"),
        ] {
            let message = usage_error(args);
            assert!(message.contains(expected), "{args:?}: {message}");
        }
    }

    #[test]
    fn unknown_and_far_faults_are_usage_errors_naming_the_faults() {
        let message = usage_error(&["tracerctl", "sim", "--fault", "bogus"]);
        assert!(message.contains("known faults: estop, estop-release, motor1-overheat"), "{message}");
        let message = usage_error(&["tracerctl", "sim", "--fault", "estop@99999999999"]);
        assert!(message.contains("out of range: give one from 0s to 30days"), "{message}");
        use clap::Parser;
        let cli = Cli::try_parse_from(["tracerctl", "sim", "--fault", "estop@2s"]).unwrap();
        assert!(matches!(cli.command, Command::Sim(_)));
        assert_eq!(cli.link.faults[0].at, Duration::from_secs(2));
        // One option for `sim` and for `--sim`, before or after the command.
        let cli = Cli::try_parse_from(["tracerctl", "doctor", "--sim", "--fault", "motor1-comm@1s"]).unwrap();
        assert_eq!(cli.link.faults[0].fault, crate::sim::FaultKind::Motor1Comm);
    }

    #[test]
    fn link_options_of_another_link_are_usage_errors() {
        for args in [
            &["tracerctl", "--sim", "drive", "--speed", "0.3"][..],
            &["tracerctl", "drive", "--speed", "0.3"],
            &["tracerctl", "--iface", "can0", "--speed", "2", "monitor"],
            &["tracerctl", "--sim", "--iface", "can1", "monitor"],
            &["tracerctl", "--serial", "/dev/ttyUSB0", "--iface", "can1", "monitor"],
            &["tracerctl", "--replay", "x.log", "--iface", "can1", "monitor"],
            &["tracerctl", "--baud", "9600", "monitor"],
            &["tracerctl", "--sim", "--baud", "9600", "monitor"],
            &["tracerctl", "--replay", "x.log", "--baud", "9600", "monitor"],
            &["tracerctl", "monitor", "--raw", "--format", "json"],
            // The same across the command name.
            &["tracerctl", "--sim", "monitor", "--speed", "2"],
            &["tracerctl", "--sim", "monitor", "--iface", "can1"],
            &["tracerctl", "--serial", "/dev/ttyUSB0", "monitor", "--replay", "x.log"],
            &["tracerctl", "--sim", "monitor", "--baud", "9600"],
            &["tracerctl", "monitor", "--baud", "9600"],
            &["tracerctl", "--iface", "can0", "monitor", "--speed", "2"],
        ] {
            usage_error(args);
        }
        let ok = |args: &[&str]| {
            let args: Vec<std::ffi::OsString> = args.iter().map(Into::into).collect();
            try_parse_from(&args).unwrap_or_else(|error| panic!("{args:?}: {error}"))
        };
        let cli = ok(&["tracerctl", "--replay", "x.log", "--speed", "2", "monitor"]);
        assert_eq!(cli.link.speed(), 2.0);
        // A global option after the command sees one given before it (the README's example was refused:
        // "--replay not provided").
        assert_eq!(ok(&["tracerctl", "--replay", "x.log", "monitor", "--speed", "4"]).link.speed(), 4.0);
        assert_eq!(ok(&["tracerctl", "monitor", "--replay", "x.log", "--speed", "4"]).link.speed(), 4.0);
        assert_eq!(
            ok(&["tracerctl", "--serial", "/dev/ttyUSB0", "monitor", "--baud", "9600"]).link.baud(),
            9600
        );
        let cli = ok(&["tracerctl", "--serial", "/dev/ttyUSB0", "--baud", "9600", "monitor"]);
        assert_eq!(cli.link.baud(), 9600);
        assert_eq!(ok(&["tracerctl", "--sim", "monitor"]).link.baud(), DEFAULT_BAUD);
        assert_eq!(ok(&["tracerctl", "--iface", "vcan0", "monitor"]).link.iface(), "vcan0");
    }

    #[test]
    fn limits_that_contradict_each_other_are_usage_errors_naming_the_options() {
        use clap::Parser;
        let limits = |args: &[&str]| {
            let cli = Cli::try_parse_from(args).unwrap();
            let Command::Drive(args) = cli.command else { panic!() };
            args.limits.limits()
        };
        let error = limits(&["tracerctl", "drive", "--decel", "0.3"]).unwrap_err();
        assert_eq!(error.downcast_ref::<crate::exit::Failure>().map(|f| f.code), Some(crate::exit::USAGE));
        let error = error.to_string();
        assert!(error.contains("--decel (0.3 m/s²) must be at least --accel (0.5 m/s²)"), "{error}");
        let error = limits(&["tracerctl", "drive", "--angular-decel", "0.5"]).unwrap_err().to_string();
        assert_eq!(
            error,
            "--angular-decel (0.5 rad/s²) must be at least --angular-accel (1 rad/s²): braking is never weaker \
             than speeding up"
        );
        assert_eq!(
            limit_error_text(LimitError::NotPositive { name: LimitName::AngularAccel, value: f64::NAN }),
            "--angular-accel must be a positive number, not NaN"
        );
        let clamped = limits(&["tracerctl", "drive", "--max-linear", "9"]).unwrap();
        assert_eq!(clamped.max_linear, crate::protocol::message::LINEAR_LIMIT);
    }

    #[test]
    fn every_config_key_targets_an_argument_of_its_command() {
        let top = command();
        for key in crate::config::KEYS {
            for target in key.targets {
                let owner = target.subcommand.is_empty() || top.find_subcommand(target.subcommand).is_some();
                if owner {
                    assert!(
                        config_target(&top, target).is_some(),
                        "{}: no argument {target:?}",
                        key.dotted()
                    );
                } else {
                    // `record` is being written beside this (issue 31); its arguments pick the keys up when
                    // they exist, with these ids.
                    assert_eq!(target.subcommand, "record", "{}", key.dotted());
                }
            }
        }
    }

    fn loaded(text: &str, profile: Option<&str>) -> crate::config::Loaded {
        let file = crate::config::file::parse("c.toml", text).unwrap();
        let effective = crate::config::profile::resolve(std::slice::from_ref(&file), profile).unwrap();
        crate::config::Loaded { parsed: vec![file], effective, ..Default::default() }
    }

    #[test]
    fn config_values_become_defaults_that_options_beat() {
        use clap::FromArgMatches;
        let config =
            loaded("[drive]\nmax_linear = 0.8\nkey_timeout = \"300ms\"\n[link]\nprotocol = \"v1\"\n", None);
        check_config_values(&command(), &config).unwrap();
        let parse = |args: &[&str]| {
            let matches = with_config_defaults(command(), &config).try_get_matches_from(args).unwrap();
            (Cli::from_arg_matches(&matches).unwrap(), matches)
        };
        let (cli, matches) = parse(&["tracerctl", "drive", "--linear", "0.1"]);
        let Command::Drive(args) = cli.command else { panic!() };
        assert_eq!((args.limits.max_linear, args.limits.max_angular), (0.8, 0.5));
        assert_eq!(cli.protocol, ProtocolArg::V1);
        let origins = config_origins(&matches, &config, "drive");
        assert_eq!(origins.iter().map(|origin| origin.arg).collect::<Vec<_>>(), ["max_linear"]);
        assert_eq!(origins[0].at.to_string(), "c.toml:2:14");
        let (cli, _) = parse(&["tracerctl", "--protocol", "v2", "dashboard", "--max-linear", "0.2"]);
        let Command::Dashboard(args) = cli.command else { panic!() };
        assert_eq!(args.limits.max_linear, 0.2);
        assert_eq!(args.key_timeout, Some(Duration::from_millis(300)));
        assert_eq!(cli.protocol, ProtocolArg::V2);
        // The rows of `config show`: the option given, the file, the built-in default.
        let (_, matches) = parse(&["tracerctl", "--protocol", "v2", "config", "show"]);
        let rows = config_rows(&matches, &config);
        let source = |dotted: &str| {
            let row = rows.iter().find(|row| row.key.dotted() == dotted).unwrap();
            (row.values.join(" "), row.source.to_string())
        };
        assert_eq!(source("link.protocol"), ("v2".into(), "flag --protocol".into()));
        assert_eq!(source("drive.max_linear"), ("0.8".into(), "file c.toml:2".into()));
        assert_eq!(source("drive.decel"), ("1.5".into(), "default".into()));
        assert_eq!(source("record.default_triggers"), ("true".into(), "default".into()));
    }

    #[test]
    fn config_values_are_checked_by_the_options_parsers_in_every_profile() {
        let error = |text: &str| check_config_values(&command(), &loaded(text, None)).unwrap_err().message;
        assert_eq!(
            error("[profiles.unused]\ndrive.max_angular = 200"),
            "c.toml:2:21: drive.max_angular: '200' is not a number from 0.001 to 100"
        );
        assert_eq!(
            error("[link]\nprotocol = \"V2\""),
            "c.toml:2:12: link.protocol: 'V2' is not one of auto, v1, v2"
        );
        assert_eq!(
            error("[drive]\nmax_linear = nan"),
            "c.toml:2:14: drive.max_linear: 'NaN' is not a number from 0.001 to 100"
        );
        check_config_values(
            &command(),
            &loaded("[record]\nmax_incidents = 5\ndefault_triggers = false", None),
        )
        .unwrap();
    }

    #[test]
    fn limits_from_a_file_are_named_by_key_and_place() {
        let at = crate::config::Location { file: "c.toml".into(), line: 4, column: 9 };
        let origin = |arg, key: &str| ConfigOrigin { arg, key: key.into(), at: at.clone() };
        let braking = LimitError::BrakingWeaker { angular: false, decel: 0.3, accel: 0.5 };
        assert_eq!(
            limit_error_text_from(braking, &[origin("decel", "drive.decel")]),
            "c.toml:4:9: drive.decel (0.3 m/s²) must be at least --accel (0.5 m/s²): braking is never weaker than \
             speeding up"
        );
        let link = ConfiguredLink { serial: Some("/dev/ttyUSB9".into()), baud: Some(9600), iface: None };
        let mut args = LinkArgs {
            iface: None,
            serial: vec![],
            baud: None,
            sim: false,
            faults: vec![],
            sim_params: vec![],
            replay: None,
            speed: None,
            configured: link,
        };
        if std::env::var_os(IFACE_ENV).is_none() {
            assert!(matches!(args.choice().unwrap(), LinkChoice::Serial { baud: 9600, .. }));
        }
        args.iface = Some("can2".into());
        assert!(matches!(args.choice().unwrap(), LinkChoice::SocketCan { iface } if iface == "can2"));
        args.iface = None;
        args.sim = true;
        assert!(matches!(args.choice().unwrap(), LinkChoice::Sim));
        assert!(
            args.misuse().is_none(),
            "the file's serial port is not a --serial that conflicts with --sim"
        );
    }

    #[test]
    fn the_tip_says_what_the_option_is_for() {
        let error = usage_error(&["tracerctl", "--sim", "drive", "--speed", "0.3"]);
        assert!(
            error.contains("--speed sets the replay speed and needs --replay; drive's speed is --linear"),
            "{error}"
        );
        assert!(!error.contains("--baud sets"), "{error}");
    }

    #[test]
    fn can_utils_habits_get_the_tracerctl_spelling() {
        let iface = "the interface is `--iface can0`";
        for (args, tip) in [
            (&["tracerctl", "monitor", "can0"][..], iface),
            (&["tracerctl", "send-raw", "can0", "121#01031E0000000005"], iface),
            (&["tracerctl", "--interface", "can0", "monitor"], iface),
            (&["tracerctl", "monitor", "--interface", "can0"], iface),
            (&["tracerctl", "monitor", "--interface=can0"], iface),
            (&["tracerctl", "can0", "monitor"], iface),
            (&["tracerctl", "drive", "--linear", "0.2", "--time", "2s"], "drive's time is `--for 2s`"),
            (&["tracerctl", "drive", "--linear", "0.2", "-d", "2s"], "drive's time is `--for 2s`"),
        ] {
            let message = usage_error(args);
            assert!(message.contains(tip), "{args:?}: {message}");
            assert!(!message.contains("'--sim'"), "{args:?}: {message}");
        }
        let message = usage_error(&["tracerctl", "drive", "--time", "2s"]);
        assert!(message.contains("unexpected argument '--time' found"), "{message}");
        assert!(message.contains("a similar argument exists: '--for'"), "{message}");
        assert!(message.contains("Usage: tracerctl drive"), "{message}");
        let message = usage_error(&["tracerctl", "send-raw", "vcan1", "123#00"]);
        assert!(message.contains("unexpected argument 'vcan1' found"), "{message}");
        assert!(message.contains("the interface is `--iface vcan1`"), "{message}");
        // An RS232 frame in hex and other mistakes keep their own errors.
        assert!(!looks_like_interface("5AA50A550102000A00000000"));
        assert!(!looks_like_interface("beef1") && looks_like_interface("slcan0"));
        assert!(!usage_error(&["tracerctl", "monitor", "--bogus"]).contains("tip: the interface"));
    }
}
