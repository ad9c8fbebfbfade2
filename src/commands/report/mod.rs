//! `tracerctl report`: the support bundle, one `tracerctl-report-HOST-TIME.tar.gz` to send the vendor.
//! It holds the doctor's report (text and JSON), the firmware version when the robot answers the version
//! query, the protocol and rates, the recorder's fault timeline, its last incidents and the last minutes
//! of its ring (under a size cap, newest first, what was left out said), the frames of a listen the report
//! recorded itself when no recorder runs, and the host facts. README.txt inside says what each file is.
//!
//! Nothing from the environment, no home directory in a path (written `~`), nothing from other processes,
//! no file from outside the recorder's directory. The bundle never replaces an existing file (unless
//! `--force`), an input, or anything in the recorder's directory.
//!
//! Exit status 0 when the bundle is written (whatever the doctor found: it is in the bundle), 1 when it
//! could not be, 2 for a usage error.

mod bundle;
pub mod host;
mod readme;
pub mod recorded;
mod robot;

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use anyhow::Result;

use super::{usage, Global};
use crate::exit::SUCCESS;
use crate::link::LinkChoice;
use bundle::{Member, Omitted};
use recorded::Recorded;

/// Where the recorder keeps its ring and incidents unless told otherwise (the service's directory).
pub const DEFAULT_DIR: &str = "/var/lib/tracerctl/record";

/// README.txt and report.json are written last (they list what was written); room is kept for each.
const INDEX_RESERVE: u64 = 64 * 1024;

/// `tracerctl report`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// The bundle's file (a directory: the default name in it); `None`: the default name here.
    pub output: Option<PathBuf>,
    /// Replace an existing file of that name.
    pub force: bool,
    /// The recorder's directory; `None`: [`DEFAULT_DIR`] when it exists.
    pub dir: Option<PathBuf>,
    pub probe: bool,
    /// How long to listen (the doctor's listen, and the frames kept when no recorder runs).
    pub listen: Duration,
    /// The cap on the bundle's size, in bytes.
    pub max_size: u64,
    /// How many incidents, newest first.
    pub incidents: usize,
    /// How many minutes of the ring.
    pub ring_minutes: u64,
}

pub fn run(global: &Global, options: &Options) -> Result<u8> {
    if options.probe && matches!(global.link, LinkChoice::Replay { .. }) {
        return Err(usage("--probe sends commands and needs a live link; --replay is read-only"));
    }
    let now = SystemTime::now().duration_since(UNIX_EPOCH).unwrap_or(Duration::ZERO).as_secs();
    let now = i64::try_from(now).unwrap_or(i64::MAX);
    let host = host::host_name();
    let output = output_path(options, &host, now);
    let dir = recorder_dir(options)?;
    refuse_output(global, options, &output, dir.as_deref())?;

    let redact = Redactor::new();
    let recorded = dir.as_deref().map(recorded::scan);
    let running = dir.as_deref().and_then(recorder_running);
    let budget = bundle::tar_budget(options.max_size);
    // The listen is kept when no recorder is known to be recording; a quarter of the cap at most.
    let record = (running != Some(true)).then(|| usize::try_from(budget / 4).unwrap_or(usize::MAX));
    crate::say!(
        "tracerctl: report: listening {} on {}{}",
        humantime::format_duration(options.listen),
        redact.text(&describe_link(&global.link)),
        if record.is_some() { " (the frames are kept: no recorder is running)" } else { "" }
    );
    let live = robot::Live {
        doctor: crate::commands::doctor::Options {
            probe: options.probe,
            listen: options.listen,
            format: crate::commands::doctor::report::ReportFormat::Text,
            battery_warning_volts: global.battery_warning_volts,
        },
        record,
    };
    let findings = robot::examine(global, &live)?;
    for note in &findings.notes {
        crate::say!("tracerctl: {}", redact.text(note));
    }

    let (essentials, notes) = essentials(global, options, &findings, recorded.as_ref(), &redact);
    let used = essentials.iter().map(|m| bundle::tar_bytes(m.size)).sum::<u64>() + 2 * INDEX_RESERVE;
    let candidates = recorded.as_ref().map(|r| candidates(r, options)).unwrap_or_default();
    let (chosen, mut left_out) = choose(candidates, used, budget, options.max_size);

    let mut writer =
        bundle::Writer::create(&output, options.force, &folder_name(&output), now.unsigned_abs())?;
    let mut files = Vec::new();
    for member in essentials.iter().chain(&chosen) {
        match writer.add(member)? {
            Ok(_) => files.push((member.name.clone(), member.size, member.about.clone())),
            Err(omitted) => left_out.push(omitted),
        }
    }
    let created = recorded::readable_utc(now);
    let dir_text = dir.as_ref().map(|dir| redact.text(&dir.display().to_string()));
    let link_text = redact.text(&describe_link(&global.link));
    let about = readme::About {
        version: env!("CARGO_PKG_VERSION"),
        created: &created,
        host: &host,
        link: &link_text,
        max_size: options.max_size,
        recorder: dir_text.as_deref().ok_or("no --dir given and none in /var/lib/tracerctl/record"),
        files: &files,
        left_out: &left_out,
        notes: &notes,
    };
    writer.add(&Member::made("README.txt", readme::readme(&about).into_bytes(), ""))?.ok();
    let json = format!("{:#}\n", readme::report_json(&about));
    writer.add(&Member::made("report.json", json.into_bytes(), ""))?.ok();
    let size = writer.finish()?;

    tell_left_out(&left_out, &notes);
    crate::say!(
        "tracerctl: report: wrote {}: {} files, {}",
        output.display(),
        files.len() + 2,
        readme::size_text(size)
    );
    if size > options.max_size {
        crate::say!(
            "tracerctl: the bundle is over --max-size {}: what every bundle holds takes that much already",
            readme::size_text(options.max_size)
        );
    }
    // The path for scripts; stderr said it already, so a closed stdout loses nothing.
    use std::io::Write as _;
    let _ = writeln!(std::io::stdout(), "{}", output.display());
    Ok(SUCCESS)
}

/// `-o FILE`, the default name in `-o DIR`, or the default name here: `tracerctl-report-HOST-TIME.tar.gz`.
fn output_path(options: &Options, host: &str, now: i64) -> PathBuf {
    let default_name = format!("tracerctl-report-{host}-{}.tar.gz", recorded::compact_utc(now));
    match &options.output {
        Some(path) if path.is_dir() => path.join(&default_name),
        Some(path) => path.clone(),
        None => PathBuf::from(&default_name),
    }
}

/// What every bundle holds (host facts, doctor, robot, the listen, the timeline), and what to say about
/// what it could not hold.
fn essentials(
    global: &Global,
    options: &Options,
    findings: &robot::Findings,
    recorded: Option<&Recorded>,
    redact: &Redactor,
) -> (Vec<Member>, Vec<String>) {
    let mut essentials = vec![
        Member::made(
            "host.txt",
            redact.bytes(host::facts(&global.link).as_bytes()),
            "host facts: tracerctl, OS release, kernel, CAN driver and modules, ip link, serial port",
        ),
        Member::made("doctor.txt", redact.bytes(&findings.doctor_text), "`tracerctl doctor` on the link, as it prints it"),
        Member::made("doctor.json", redact.bytes(&findings.doctor_json), "the same, `doctor --format json` (docs/json.md)"),
        Member::made(
            "robot.txt",
            redact.bytes(findings.robot_text.as_bytes()),
            "the firmware version (or why there is none), the protocol, frames per identifier against their periods",
        ),
        Member::made("robot.json", redact.bytes(format!("{}\n", findings.robot_json).as_bytes()), "the same in JSON"),
    ];
    let mut notes = Vec::new();
    if let Some(listen) = &findings.listen {
        let form = match global.link {
            LinkChoice::Serial { .. } => "RS232 frames in hex as `decode --serial` reads them",
            _ => "candump -L",
        };
        let about = format!(
            "the {} listen's {} frames, {form} (received and sent), recorded by the report as no recorder was \
             running",
            humantime::format_duration(options.listen),
            listen.frames
        );
        essentials.push(Member::made("listen.log", listen.bytes.clone(), about));
        if listen.dropped > 0 {
            notes.push(format!(
                "listen.log: the last {} frames of the listen (over a quarter of --max-size)",
                listen.dropped
            ));
        }
    }
    if let Some(recorded) = recorded {
        essentials.push(Member::made(
            "recorder/timeline.txt",
            timeline(recorded, options.incidents).into_bytes(),
            "the fault timeline: every incident in the recorder's directory, newest first",
        ));
        notes.extend(recorded.problems.iter().map(|problem| redact.text(problem)));
        let older = recorded.incidents.len().saturating_sub(options.incidents);
        if older > 0 {
            notes.push(format!(
                "{older} older incident(s): only the newest {} are taken (--incidents)",
                options.incidents
            ));
        }
    }
    (essentials, notes)
}

/// The candidates that fit under the cap (sorted by name, as they go into the bundle) and those left out.
fn choose(candidates: Vec<Member>, used: u64, budget: u64, max_size: u64) -> (Vec<Member>, Vec<Omitted>) {
    let sizes: Vec<u64> = candidates.iter().map(|m| m.size).collect();
    let taken = bundle::fit(used, &sizes, budget);
    let mut left_out = Vec::new();
    let mut chosen = Vec::new();
    for (member, fits) in candidates.into_iter().zip(taken) {
        if fits {
            chosen.push(member);
        } else {
            let why = format!("over the size cap (--max-size {})", readme::size_text(max_size));
            left_out.push(Omitted { name: member.name, size: member.size, why });
        }
    }
    chosen.sort_by(|a, b| a.name.cmp(&b.name));
    (chosen, left_out)
}

/// The recorder's directory: `--dir` (which must exist), else the default one if it exists.
fn recorder_dir(options: &Options) -> Result<Option<PathBuf>> {
    match &options.dir {
        Some(dir) if dir.is_dir() => Ok(Some(dir.clone())),
        Some(dir) => Err(usage(format!("--dir {}: no such directory (the recorder's --dir)", dir.display()))),
        None => Ok(Path::new(DEFAULT_DIR).is_dir().then(|| PathBuf::from(DEFAULT_DIR))),
    }
}

/// Refuses (usage error) a bundle that would replace an existing file without `--force`, an input (the
/// replayed log, the serial port), or anything in the recorder's directory.
fn refuse_output(global: &Global, options: &Options, output: &Path, dir: Option<&Path>) -> Result<()> {
    use super::same_file::{refuse_overwriting, Named};
    let mut inputs = Vec::new();
    match &global.link {
        LinkChoice::Replay { path, .. } => inputs.push(Named { option: "--replay", path }),
        LinkChoice::Serial { path, .. } => inputs.push(Named { option: "--serial", path }),
        _ => {}
    }
    refuse_overwriting(&inputs, &[Named { option: "-o", path: output }])?;
    if let Some(dir) = dir {
        let parent = output.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if let (Ok(parent), Ok(dir)) = (parent.canonicalize(), dir.canonicalize()) {
            if parent.starts_with(&dir) {
                return Err(usage(format!(
                    "-o {}: the bundle would be written into the recorder's directory {}; write it elsewhere",
                    output.display(),
                    dir.display()
                )));
            }
        }
    }
    if !options.force && std::fs::symlink_metadata(output).is_ok() {
        return Err(usage(format!(
            "{} exists: give another name with -o, or --force to replace it",
            output.display()
        )));
    }
    Ok(())
}

/// The folder inside the bundle: the file's name without `.tar.gz` or `.tgz`.
fn folder_name(output: &Path) -> String {
    let name = output
        .file_name()
        .map_or_else(|| "tracerctl-report".to_string(), |n| n.to_string_lossy().into_owned());
    let stem = name.strip_suffix(".tar.gz").or_else(|| name.strip_suffix(".tgz")).unwrap_or(&name);
    if stem.is_empty() {
        "tracerctl-report".to_string()
    } else {
        stem.to_string()
    }
}

/// The recorder's directory's files that may go in, in order of preference: its status, the newest
/// incidents' summaries, their candump frames, the ring's last minutes (newest first), their MCAP files.
fn candidates(recorded: &Recorded, options: &Options) -> Vec<Member> {
    let mut summaries = Vec::new();
    let mut frames = Vec::new();
    let mut mcaps = Vec::new();
    for incident in recorded.incidents.iter().take(options.incidents) {
        let (when, cause) = incident.when_and_cause();
        for file in &incident.files {
            let name = format!("recorder/incidents/{}/{}", incident.name, file.name);
            let what = match file.name.as_str() {
                "incident.json" => "the incident: cause, time, the decoded state at the trigger",
                "summary.txt" => "`decode --summary` of the incident's window",
                "summary.json" => "the same in JSON",
                "frames.log" => "the window's frames, candump -L",
                "frames.mcap" => "the window's frames, MCAP (Foxglove)",
                _ => "a file of the incident",
            };
            let member =
                Member::file(name, &file.path, file.size, format!("{what}; incident of {when}, {cause}"));
            if file.name.ends_with(".mcap") {
                mcaps.push(member);
            } else if file.name.starts_with("frames") {
                frames.push(member);
            } else {
                summaries.push(member);
            }
        }
    }
    let mut ring: Vec<Member> = recorded::ring_window(&recorded.ring, options.ring_minutes)
        .into_iter()
        .rev()
        .map(|index| {
            let segment = &recorded.ring[index];
            let start = segment.start.map(recorded::readable_utc).unwrap_or_default();
            Member::file(
                format!("recorder/ring/{}", segment.file.name),
                &segment.file.path,
                segment.file.size,
                format!("ring segment from {start}: candump -L lines, zstd"),
            )
        })
        .collect();
    let mut all = Vec::new();
    if let Some(status) = &recorded.status {
        all.push(Member::file(
            "recorder/status.json",
            &status.path,
            status.size,
            "the recorder's status file",
        ));
    }
    all.append(&mut summaries);
    all.append(&mut frames);
    all.append(&mut ring);
    all.append(&mut mcaps);
    all
}

/// Every incident of the directory, newest first: when, the causes, and whether it is in the bundle.
fn timeline(recorded: &Recorded, taken: usize) -> String {
    use std::fmt::Write as _;
    let mut out = format!("{} incident(s), newest first\n", recorded.incidents.len());
    for (index, incident) in recorded.incidents.iter().enumerate() {
        let (when, cause) = incident.when_and_cause();
        let included = if index < taken { "in the bundle" } else { "not taken (--incidents)" };
        let _ = writeln!(out, "{when}  {cause:<24} {included}");
    }
    out
}

/// Says on stderr what was left out (the README says it too).
fn tell_left_out(left_out: &[Omitted], notes: &[String]) {
    if !left_out.is_empty() {
        let total: u64 = left_out.iter().map(|omitted| omitted.size).sum();
        let names: Vec<&str> = left_out.iter().take(5).map(|omitted| omitted.name.as_str()).collect();
        let more =
            if left_out.len() > 5 { format!(" and {} more", left_out.len() - 5) } else { String::new() };
        crate::say!(
            "tracerctl: left out of the bundle: {} file(s), {} ({}): {}{more}",
            left_out.len(),
            readme::size_text(total),
            left_out[0].why,
            names.join(", ")
        );
    }
    for note in notes {
        crate::say!("tracerctl: not in the bundle: {note}");
    }
}

fn describe_link(choice: &LinkChoice) -> String {
    match choice {
        LinkChoice::SocketCan { iface } => format!("{iface} (SocketCAN)"),
        LinkChoice::Serial { path, baud } => format!("{} (RS232, {baud} baud)", path.display()),
        LinkChoice::Sim => "the in-process virtual TRACER (--sim)".to_string(),
        LinkChoice::Replay { path, .. } => format!("{} (replay)", path.display()),
    }
}

/// Whether a recorder holds the directory's lock now: `Some(true)` when one does, `Some(false)` when the
/// lock is free or absent, `None` where it cannot be told.
#[cfg(unix)]
fn recorder_running(dir: &Path) -> Option<bool> {
    use std::os::fd::AsRawFd;
    let Ok(file) = std::fs::File::open(dir.join("recorder.lock")) else { return Some(false) };
    // SAFETY: `file` is open for the whole call; a shared, non-blocking lock attempt changes nothing when
    // refused, and is released when the file closes at the end of this function.
    let result = unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_SH | libc::LOCK_NB) };
    Some(result != 0 && std::io::Error::last_os_error().raw_os_error() == Some(libc::EWOULDBLOCK))
}

#[cfg(not(unix))]
fn recorder_running(_dir: &Path) -> Option<bool> {
    None
}

/// Home directories in made text, written `~`: `$HOME` and this user's home in /etc/passwd (read only to
/// be left out).
struct Redactor {
    homes: Vec<String>,
}

impl Redactor {
    fn new() -> Self {
        let mut homes: Vec<String> = std::env::var("HOME").ok().into_iter().chain(passwd_home()).collect();
        homes.retain(|home| home.trim_end_matches('/').len() > 1);
        homes.iter_mut().for_each(|home| *home = home.trim_end_matches('/').to_string());
        // The longest first: one home inside another is replaced whole.
        homes.sort_by_key(|home| std::cmp::Reverse(home.len()));
        homes.dedup();
        Self { homes }
    }

    fn text(&self, text: &str) -> String {
        self.homes.iter().fold(text.to_string(), |text, home| text.replace(home.as_str(), "~"))
    }

    fn bytes(&self, bytes: &[u8]) -> Vec<u8> {
        match std::str::from_utf8(bytes) {
            Ok(text) => self.text(text).into_bytes(),
            Err(_) => self.text(&String::from_utf8_lossy(bytes)).into_bytes(),
        }
    }
}

/// This user's home directory as /etc/passwd gives it.
#[cfg(unix)]
fn passwd_home() -> Option<String> {
    // SAFETY: getuid has no preconditions and cannot fail.
    let uid = unsafe { libc::getuid() };
    let table = std::fs::read_to_string("/etc/passwd").ok()?;
    table.lines().find_map(|line| {
        let fields: Vec<&str> = line.split(':').collect();
        (fields.len() >= 6 && fields[2].parse() == Ok(uid)).then(|| fields[5].to_string())
    })
}

#[cfg(not(unix))]
fn passwd_home() -> Option<String> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_folder_is_the_file_name_without_its_extension() {
        assert_eq!(
            folder_name(Path::new("/tmp/tracerctl-report-a-20261128T134100Z.tar.gz")),
            "tracerctl-report-a-20261128T134100Z"
        );
        assert_eq!(folder_name(Path::new("b.tgz")), "b");
        assert_eq!(folder_name(Path::new("c.bin")), "c.bin");
        assert_eq!(folder_name(Path::new(".tar.gz")), "tracerctl-report");
    }

    #[test]
    fn homes_are_written_as_a_tilde_the_longest_first() {
        let redactor = Redactor { homes: vec!["/home/ann/inner".to_string(), "/home/ann".to_string()] };
        assert_eq!(redactor.text("a /home/ann/inner/x and /home/ann/y"), "a ~/x and ~/y");
        assert_eq!(redactor.bytes(b"/home/ann\xff"), "~\u{fffd}".as_bytes());
    }
}
