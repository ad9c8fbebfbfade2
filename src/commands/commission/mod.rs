//! `tracerctl commission`: the acceptance test drive a field team runs on delivery, after repairs and every
//! month (docs/commission.md). The flow: open the link and watch (nothing sent); the doctor's checks, and no
//! drive unless they pass; the plan, its bounds, duration and the free space it needs; the operator's
//! confirmation on the terminal (or `--yes`); then the plan's steps on the 50 Hz sender under drive's guard
//! (strict) and the keyboard; zeros on every way out; the report.
//!
//! The measurement is the session's tap ([`crate::session::FrameTap`]): exactly the frames and stamps the
//! `--record` recording holds, so `decode --summary` of it gives the same figures.
//!
//! The folder: [`verdict`] (figures and thresholds, pure), [`report`] (text and JSON, pure), [`compare`]
//! (`--compare`, pure), [`plot`] (`--plot`, pure), [`measure`] (the tap's state), [`keys`] (the keyboard in
//! raw mode), [`run`] (the steps).

pub mod compare;
mod keys;
pub mod measure;
pub mod plot;
pub mod report;
mod run;
pub mod verdict;

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, SystemTime};

use anyhow::{Context as _, Result};
use parking_lot::Mutex;

use super::doctor::{self, report::Outcome, report::ReportFormat};
use super::drive::{self, check_before_driving, End, WATCHDOG};
use super::live;
use super::Global;
use crate::control::limits::Limits;
use crate::control::sender::{MotionSender, PERIOD};
use crate::exit::{Failure, FAILURE, MEASURED_FAIL, SUCCESS, USAGE};
use crate::health::plan::{self, PlanOptions, Step};
use crate::link::LinkChoice;
use crate::output::Format;
use crate::protocol::Codec;
use crate::session::{Direction, FrameTap, Journaling, Session};
use keys::{Keyboard, Press};
use measure::Measurement;
use report::{Abort, Parameters, Record};
use verdict::Thresholds;

/// How long the doctor listens before the drive.
const DOCTOR_LISTEN: Duration = Duration::from_secs(1);

/// `tracerctl commission`'s settings.
#[derive(Clone, Debug)]
pub struct Options {
    /// The caps (m/s, rad/s) and `--include timeout`.
    pub plan: PlanOptions,
    /// Drive without asking.
    pub yes: bool,
    /// Print the plan and exit: no link, nothing sent.
    pub dry_run: bool,
    pub record: Option<PathBuf>,
    pub format: Format,
    pub plot: Option<PathBuf>,
    pub save: Option<PathBuf>,
    pub compare: Option<PathBuf>,
    pub thresholds: Thresholds,
    pub battery_warning_volts: f64,
}

/// The caps as the sender gets them. The step IS the measurement: the acceleration and the deceleration
/// let the sender reach any capped command in one 20 ms period, so its ramp does not shape the step the
/// robot is given (a ramp would be measured instead of the robot). The caps stay: nothing beyond
/// `--max-linear` / `--max-angular` (themselves within the protocol's limits) is ever sent.
pub fn step_limits(options: &PlanOptions) -> Result<Limits> {
    let max_linear = options.max_linear.min(plan::MAX_LINEAR);
    let capped = Limits { max_linear, max_angular: options.max_angular, ..Limits::default() }
        .validated()
        .map_err(|error| Failure { code: USAGE, message: error.to_string() })?;
    let per_period = |cap: f64| cap / PERIOD.as_secs_f64();
    Ok(Limits {
        linear_accel: per_period(capped.max_linear),
        linear_decel: per_period(capped.max_linear),
        angular_accel: per_period(capped.max_angular),
        angular_decel: per_period(capped.max_angular),
        ..capped
    })
}

/// The plan within the caps, and what it asks for.
fn planned(options: &Options) -> Result<(Limits, Vec<Step>, Parameters)> {
    let limits = step_limits(&options.plan)?;
    let plan_options =
        PlanOptions { max_linear: limits.max_linear, max_angular: limits.max_angular, ..options.plan };
    let steps = plan::steps(&plan_options);
    let parameters = Parameters {
        max_linear: limits.max_linear,
        max_angular: limits.max_angular,
        include_timeout: options.plan.include_timeout,
        duration_s: plan::duration(&steps).as_secs_f64(),
        free_space_m: plan::FREE_SPACE_M,
    };
    Ok((limits, steps, parameters))
}

pub fn run(global: &Global, options: &Options) -> Result<u8> {
    let (limits, steps, parameters) = planned(options)?;
    let mut stdout = std::io::stdout();
    if options.dry_run {
        let text = report::plan_text(None, &parameters, &steps);
        match options.format {
            Format::Json => writeln!(stdout, "{}", plan_json(&parameters, &steps))?,
            _ => write!(stdout, "{text}")?,
        }
        return Ok(SUCCESS);
    }
    let old = options.compare.as_deref().map(read_old).transpose()?;
    let terminal = refuse_before_opening(global, options)?;
    // Signals first: a Ctrl-C while the link opens or the doctor listens ends the command cleanly.
    let context = drive::Context::listen()?;
    let measurement = Arc::new(Mutex::new(Measurement::new(global.protocol)));
    let tap: FrameTap = {
        let measurement = Arc::clone(&measurement);
        Arc::new(move |received, direction: Direction| measurement.lock().observe(received, direction))
    };
    let journal =
        Journaling { record: options.record.as_deref().map(|path| (path, "commission")), tap: Some(tap) };
    let doctor_options = doctor::Options {
        probe: false,
        listen: DOCTOR_LISTEN,
        format: ReportFormat::Text,
        battery_warning_volts: options.battery_warning_volts,
    };
    let diagnosis = doctor::diagnose(global, &doctor_options, || live::open_journaled(global, journal))?;
    if options.format == Format::Text {
        stdout.write_all(&diagnosis.render(ReportFormat::Text)?)?;
    }
    if let Some(caught) = context.signal.caught() {
        crate::say!("tracerctl: {} before driving: nothing was sent", caught.name());
        return Ok(caught.exit_status());
    }
    let failed: Vec<&str> = diagnosis
        .checks
        .iter()
        .filter(|check| check.outcome == Outcome::Fail)
        .map(|check| check.title)
        .collect();
    let Some(session) = diagnosis.session.filter(|_| failed.is_empty()) else {
        return Err(Failure::not_done(format!(
            "not driving: the doctor's checks failed ({}); nothing was sent",
            failed.join(", ")
        ))
        .into());
    };
    let plan_text = report::plan_text(Some(&session.name), &parameters, &steps);
    match options.format {
        Format::Json => keys::say_line(plan_text.trim_end()),
        _ => write!(stdout, "{plan_text}")?,
    }
    stdout.flush()?;
    let keyboard = if terminal { Some(Keyboard::start()?) } else { None };
    if let (false, Some(keyboard)) = (options.yes, &keyboard) {
        if let Some(status) = confirm(keyboard, &context.signal)? {
            return Ok(status);
        }
    }
    let start = Start { limits, steps: &steps, parameters, keyboard, measurement: &measurement };
    execute(session, options, &context, start, old)
}

/// What is refused before the link opens (nothing sent); whether standard input is a terminal.
fn refuse_before_opening(global: &Global, options: &Options) -> Result<bool> {
    if let Some(dir) = &options.save {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create --save {}", dir.display()))?;
    }
    let terminal = std::io::stdin().is_terminal();
    if !options.yes && !terminal {
        return Err(Failure {
            code: USAGE,
            message: "commission asks the operator on the terminal before it moves the robot: run it on a \
                      terminal, or give --yes (nothing was sent)"
                .to_string(),
        }
        .into());
    }
    if matches!(global.link, LinkChoice::Replay { .. }) {
        return Err(Failure {
            code: USAGE,
            message: "--replay is read-only: commission drives the robot and needs a live link (--iface, \
                      --serial or --sim)"
                .to_string(),
        }
        .into());
    }
    Ok(terminal)
}

/// The plan as `--dry-run --format json` prints it.
fn plan_json(parameters: &Parameters, steps: &[Step]) -> serde_json::Value {
    serde_json::json!({
        "type": "commission_plan",
        "parameters": {
            "max_linear_mps": parameters.max_linear,
            "max_angular_radps": parameters.max_angular,
            "include_timeout": parameters.include_timeout,
            "duration_s": parameters.duration_s,
            "free_space_m": parameters.free_space_m,
        },
        "steps": steps.iter().map(|step| serde_json::json!({
            "name": step.name,
            "action": report::action_words(step.action),
            "duration_s": step.duration.as_secs_f64(),
        })).collect::<Vec<_>>(),
    })
}

/// An earlier record for `--compare`, read before anything moves.
fn read_old(path: &Path) -> Result<(String, serde_json::Value)> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read --compare {}", path.display()))?;
    let value: serde_json::Value = serde_json::from_str(&text).map_err(|error| {
        Failure::data(format!("{}:{}:{}: not JSON: {error}", path.display(), error.line(), error.column()))
    })?;
    compare::check_old(&value).map_err(|why| Failure::data(format!("{}: {why}", path.display())))?;
    Ok((path.display().to_string(), value))
}

/// Asks the operator; `Some(exit status)` when the answer is not yes (nothing was sent).
fn confirm(keyboard: &Keyboard, signal: &crate::signals::SignalFlag) -> Result<Option<u8>> {
    use crate::dashboard::keys::{key_name, Action};
    keys::say_line(&format!(
        "Start the drive? {} starts it; any other key cancels. Once it runs, any key stops it at once.",
        key_name(Action::Yes)
    ));
    loop {
        if let Some(caught) = signal.caught() {
            keys::say_line(&format!("tracerctl: {}: nothing was sent", caught.name()));
            return Ok(Some(caught.exit_status()));
        }
        match keyboard.wait(Duration::from_millis(100)) {
            None => {}
            Some(Press::Yes) => return Ok(None),
            Some(Press::Interrupt(caught)) => {
                keys::say_line(&format!("tracerctl: {}: nothing was sent", caught.name()));
                return Ok(Some(caught.exit_status()));
            }
            Some(Press::Other(key)) => {
                return Err(Failure::not_done(format!(
                    "not driving: cancelled at the prompt ({key}); nothing was sent"
                ))
                .into())
            }
            Some(Press::Closed(why)) => {
                return Err(Failure::not_done(format!(
                    "not driving: the terminal went away ({why}); nothing was sent"
                ))
                .into())
            }
        }
    }
}

/// What the drive starts with.
struct Start<'a> {
    limits: Limits,
    steps: &'a [Step],
    parameters: Parameters,
    keyboard: Option<Keyboard>,
    measurement: &'a Arc<Mutex<Measurement>>,
}

/// The drive, the stop, then the report from what the recording holds.
fn execute(
    session: Session,
    options: &Options,
    context: &drive::Context,
    start: Start<'_>,
    old: Option<(String, serde_json::Value)>,
) -> Result<u8> {
    let mut stdout = std::io::stdout();
    if let Some(status) = check_before_driving(&session, options.format, false, &mut stdout, &context.signal)?
    {
        return Ok(status);
    }
    context.refuse_if_suspended()?;
    let started_utc = humantime::format_rfc3339_seconds(SystemTime::now()).to_string();
    let sender = MotionSender::start(session.tx.clone(), Codec::new(session.wire()), start.limits, WATCHDOG)?;
    context.arm(&sender);
    let driven = run::Drive {
        session: &session,
        sender: &sender,
        signal: &context.signal,
        keyboard: start.keyboard.as_ref(),
        timeout_fail: Duration::from_secs_f64(options.thresholds.command_timeout_ms.fail / 1000.0),
        progress: options.format == Format::Text,
    }
    .run(start.steps);
    let stats = sender.stop();
    context.disarm();
    drop(start.keyboard);
    // A signal that came as the last step ended still cut it short.
    let end = driven.end.or_else(|| context.signal.caught().map(End::Signal));
    let elapsed = driven.started.elapsed().as_secs_f64();
    let stop = drive::stop_report(&stats, &driven.follow, &session);
    let link = session.name.clone();
    let abort = end
        .as_ref()
        .map(|end| Abort { reason: end.name(), message: end.words(elapsed, &driven.follow, &link) });
    // Everything sent and received is in the recording now and through the tap: the analysis is complete.
    let finished = session.finish();
    if let Some(loss) = &finished.recording {
        crate::say!("tracerctl: {loss}");
    }
    for note in &finished.notes {
        crate::say!("tracerctl: {note}");
    }
    let (analysis, samples) = {
        let measurement = start.measurement.lock();
        (measurement.analyzer().report(), measurement.samples.clone())
    };
    let mut figures = verdict::figures(&analysis, &driven.steps, &options.thresholds, driven.observed);
    // The last step begun was cut short when the drive ended early.
    let completed = if end.is_some() { driven.begun.saturating_sub(1) } else { driven.begun };
    figures.extend(verdict::missing(start.steps, &driven.steps, completed, &analysis));
    let exit_status = match &end {
        Some(end) => end.exit_status(),
        None if !stats.stop_confirmed() => FAILURE,
        None if verdict::worst(&figures) == verdict::Verdict::Fail => MEASURED_FAIL,
        None => SUCCESS,
    };
    let record = Record {
        link,
        started_utc,
        parameters: start.parameters,
        thresholds: options.thresholds,
        plan: start.steps.to_vec(),
        begun: driven.begun,
        figures,
        abort,
        stop: stop.clone(),
        stop_confirmed: stats.stop_confirmed(),
        exit_status,
        recording: options.record.as_ref().map(|path| path.display().to_string()),
    };
    write_outputs(options, &record, &driven.steps, &samples, old.as_ref())?;
    finish(end.as_ref(), &record, &stop)
}

/// The report on stdout, and the plot, the saved record and the comparison.
fn write_outputs(
    options: &Options,
    record: &Record,
    times: &verdict::StepTimes,
    samples: &[measure::Sample],
    old: Option<&(String, serde_json::Value)>,
) -> Result<()> {
    let mut stdout = std::io::stdout();
    let json = report::json(record);
    match options.format {
        Format::Json => writeln!(stdout, "{json}")?,
        _ => write!(stdout, "{}", report::text(record))?,
    }
    if let Some(path) = &options.plot {
        let windows = windows(record, times, samples);
        let title = format!("tracerctl commission: {}, {}", record.link, record.started_utc);
        std::fs::write(path, plot::svg(&title, &windows, samples))
            .with_context(|| format!("cannot write --plot {}", path.display()))?;
    }
    if let Some(dir) = &options.save {
        let saved = save(dir, &record.link, &json)?;
        crate::say!("tracerctl: saved {}", saved.display());
    }
    if let Some((label, old)) = old {
        let changes = compare::changes(old, &json, &options.thresholds);
        match options.format {
            Format::Json => keys::say_line(compare::text(label, &changes).trim_end()),
            _ => write!(stdout, "{}", compare::text(label, &changes))?,
        }
    }
    Ok(stdout.flush()?)
}

/// The exit: an abort is an error with its reason (stderr), a signal its own status.
fn finish(end: Option<&End>, record: &Record, stop: &[String]) -> Result<u8> {
    match (end, &record.abort) {
        (Some(End::Signal(caught)), _) => {
            crate::say!("tracerctl: commission stopped by {}: {}", caught.name(), stop.join("; "));
            Ok(caught.exit_status())
        }
        (Some(_), Some(abort)) => Err(Failure {
            code: record.exit_status,
            message: format!("commission aborted: {}; {}", abort.message, stop.join("; ")),
        }
        .into()),
        _ if record.exit_status == FAILURE => {
            Err(Failure { code: FAILURE, message: format!("commission: {}", stop.join("; ")) }.into())
        }
        _ => Ok(record.exit_status),
    }
}

/// Each step that ran, on the recording's clock, for the plot.
fn windows<'a>(
    record: &'a Record,
    times: &verdict::StepTimes,
    samples: &[measure::Sample],
) -> Vec<plot::Window<'a>> {
    let last_sample = samples
        .iter()
        .map(|sample| match *sample {
            measure::Sample::Command { at_us, .. }
            | measure::Sample::Motion { at_us, .. }
            | measure::Sample::Odometer { at_us, .. } => at_us,
        })
        .max()
        .unwrap_or(0);
    record
        .plan
        .iter()
        .zip(&times.starts)
        .enumerate()
        .map(|(number, (step, (_, from_us)))| {
            let planned_end = from_us + i64::try_from(step.duration.as_micros()).unwrap_or(i64::MAX / 2);
            let to_us = times
                .starts
                .get(number + 1)
                .map_or(planned_end.min(last_sample.max(*from_us)), |next| next.1);
            plot::Window { step, from_us: *from_us, to_us }
        })
        .collect()
}

/// `--save DIR`: DIR/<link>-<UTC time>.json, never overwriting (a second record of the same second gets
/// `-2`, `-3`, ...).
fn save(dir: &Path, link: &str, json: &serde_json::Value) -> Result<PathBuf> {
    let name: String = link
        .rsplit(['/', '\\'])
        .next()
        .unwrap_or(link)
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
        .collect();
    let stamp = humantime::format_rfc3339_seconds(SystemTime::now()).to_string().replace(':', "");
    let text = format!("{json:#}\n");
    for attempt in 1..1000 {
        let suffix = if attempt == 1 { String::new() } else { format!("-{attempt}") };
        let path = dir.join(format!("{name}-{stamp}{suffix}.json"));
        match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(mut file) => {
                file.write_all(text.as_bytes())
                    .with_context(|| format!("cannot write {}", path.display()))?;
                return Ok(path);
            }
            Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(error) => return Err(error).with_context(|| format!("cannot create {}", path.display())),
        }
    }
    anyhow::bail!("cannot find a free name in {} for the record", dir.display())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sender_reaches_any_capped_step_in_one_period_and_never_beyond_the_caps() {
        let limits =
            step_limits(&PlanOptions { max_linear: 9.0, max_angular: 0.5, include_timeout: false }).unwrap();
        assert_eq!(limits.max_linear, plan::MAX_LINEAR, "the pattern's cap (below the protocol's)");
        let step = crate::control::ramp_step((0.0, 0.0), (0.3, -0.5), &limits, PERIOD);
        assert_eq!(step, (0.3, -0.5), "one period: the step is sent as a step");
        assert_eq!(
            crate::control::ramp_step((0.0, 0.0), (5.0, 5.0), &limits, PERIOD),
            (plan::MAX_LINEAR, 0.5)
        );
        assert_eq!(crate::control::ramp_step((0.3, 0.5), (0.0, 0.0), &limits, PERIOD), (0.0, 0.0));
    }

    #[test]
    fn saved_records_never_overwrite_each_other() {
        let dir = tempfile::tempdir().unwrap();
        let json = serde_json::json!({"type": "commission"});
        let first = save(dir.path(), "/dev/ttyUSB0", &json).unwrap();
        let second = save(dir.path(), "/dev/ttyUSB0", &json).unwrap();
        assert_ne!(first, second);
        let name = first.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with("ttyUSB0-") && name.ends_with("Z.json") && !name.contains(':'), "{name}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }
}
