//! The doctor's findings and how they are printed: one line per check as it completes (text), or one
//! JSON object at the end. Pure: the writer is passed in.

use std::fmt;
use std::io::{self, Write};

use serde_json::json;

use crate::output::palette;
use crate::signals::Caught;

/// The result of one check. Ordered from good to bad.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Outcome {
    Pass,
    /// Not checked, because an earlier check failed or the link cannot tell.
    Skip,
    /// The robot can be driven, but something deserves attention.
    Warn,
    /// The robot cannot be driven until this is fixed.
    Fail,
}

impl Outcome {
    pub fn as_str(self) -> &'static str {
        match self {
            Outcome::Pass => "PASS",
            Outcome::Skip => "SKIP",
            Outcome::Warn => "WARN",
            Outcome::Fail => "FAIL",
        }
    }

    /// The palette's colour: green, dim, yellow, bold red.
    fn color(self) -> &'static str {
        match self {
            Outcome::Pass => palette::PASS.as_str(),
            Outcome::Skip => palette::SKIPPED.as_str(),
            Outcome::Warn => palette::WARNING.as_str(),
            Outcome::Fail => palette::FAILED.as_str(),
        }
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One check: what was looked at, what was found, and what to do about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Check {
    /// Stable snake_case identifier, for scripts (`kernel_can`, `estop`, ...).
    pub id: &'static str,
    /// Short name shown in the text output.
    pub title: &'static str,
    pub outcome: Outcome,
    pub finding: String,
    /// What to do; given with every WARN and FAIL.
    pub action: Option<String>,
}

impl Check {
    pub fn pass(id: &'static str, title: &'static str, finding: impl Into<String>) -> Self {
        Self { id, title, outcome: Outcome::Pass, finding: finding.into(), action: None }
    }

    pub fn warn(
        id: &'static str,
        title: &'static str,
        finding: impl Into<String>,
        action: impl Into<String>,
    ) -> Self {
        Self { id, title, outcome: Outcome::Warn, finding: finding.into(), action: Some(action.into()) }
    }

    pub fn fail(
        id: &'static str,
        title: &'static str,
        finding: impl Into<String>,
        action: impl Into<String>,
    ) -> Self {
        Self { id, title, outcome: Outcome::Fail, finding: finding.into(), action: Some(action.into()) }
    }

    pub fn skip(id: &'static str, title: &'static str, reason: impl Into<String>) -> Self {
        Self { id, title, outcome: Outcome::Skip, finding: reason.into(), action: None }
    }
}

/// Output format of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReportFormat {
    /// One line per check, then the verdict
    Text,
    /// One JSON object (docs/json.md)
    Json,
}

/// Width of the title column.
const TITLE_WIDTH: usize = 18;

/// Collects checks and prints them: text as each arrives, JSON once at the end.
pub struct Report<'a, W: Write> {
    out: &'a mut W,
    format: ReportFormat,
    color: bool,
    link: String,
    checks: Vec<Check>,
    /// The signal that cut the probe short: what it would have shown is unknown.
    interrupted: Option<&'static str>,
}

impl<'a, W: Write> Report<'a, W> {
    pub fn new(out: &'a mut W, format: ReportFormat, color: bool, link: impl Into<String>) -> Self {
        Self { out, format, color, link: link.into(), checks: Vec::new(), interrupted: None }
    }

    /// Prints a heading line (text only).
    pub fn heading(&mut self, text: &str) -> io::Result<()> {
        if self.format == ReportFormat::Text {
            writeln!(self.out, "{text}")?;
            self.out.flush()?;
        }
        Ok(())
    }

    pub fn add(&mut self, check: Check) -> io::Result<()> {
        if self.format == ReportFormat::Text {
            self.out.write_all(text_line(&check, self.color).as_bytes())?;
            self.out.flush()?;
        }
        self.checks.push(check);
        Ok(())
    }

    pub fn checks(&self) -> &[Check] {
        &self.checks
    }

    /// A signal (`SIGINT`) cut the probe short: the verdict says its result is unknown.
    pub fn interrupt(&mut self, caught: Caught) {
        self.interrupted = Some(caught.name());
    }

    /// True when no check failed.
    pub fn drivable(&self) -> bool {
        self.checks.iter().all(|check| check.outcome != Outcome::Fail)
    }

    /// Prints the verdict (text) or the whole report (JSON); returns whether the robot can be driven.
    pub fn finish(self, probed: bool) -> io::Result<bool> {
        let drivable = self.drivable();
        let count = |outcome| self.checks.iter().filter(|check| check.outcome == outcome).count();
        let (failures, warnings) = (count(Outcome::Fail), count(Outcome::Warn));
        match self.format {
            ReportFormat::Text => writeln!(self.out, "{}", verdict(&self.checks, probed, self.interrupted))?,
            ReportFormat::Json => {
                let checks: Vec<_> = self
                    .checks
                    .iter()
                    .map(|check| {
                        json!({
                            "id": check.id,
                            "title": check.title,
                            "status": check.outcome.as_str().to_ascii_lowercase(),
                            "finding": check.finding,
                            "action": check.action,
                        })
                    })
                    .collect();
                // Unknown (null) when the probe was cut short and nothing else failed.
                let known_drivable =
                    if drivable && self.interrupted.is_some() { json!(null) } else { json!(drivable) };
                let report = json!({
                    "link": self.link,
                    "probe": probed,
                    "drivable": known_drivable,
                    "interrupted": self.interrupted,
                    "failures": failures,
                    "warnings": warnings,
                    "checks": checks,
                });
                writeln!(self.out, "{report}")?;
            }
        }
        self.out.flush()?;
        Ok(drivable)
    }
}

/// `PASS  frames arriving  512 frames in 1.0 s`, then `      -> what to do` for WARN and FAIL.
pub fn text_line(check: &Check, color: bool) -> String {
    let status = if color {
        format!("{}{}{}", check.outcome.color(), check.outcome, palette::RESET.as_str())
    } else {
        check.outcome.to_string()
    };
    let mut line = format!("{status}  {:<TITLE_WIDTH$} {}\n", check.title, check.finding);
    if let Some(action) = &check.action {
        line.push_str(&format!("      -> {action}\n"));
    }
    line
}

/// The last line: whether the robot can be driven, and which checks stand in the way.
pub fn verdict(checks: &[Check], probed: bool, interrupted: Option<&str>) -> String {
    let failed: Vec<&str> =
        checks.iter().filter(|check| check.outcome == Outcome::Fail).map(|check| check.title).collect();
    let warnings = checks.iter().filter(|check| check.outcome == Outcome::Warn).count();
    let warned = match warnings {
        0 => String::new(),
        1 => " (1 warning)".to_string(),
        n => format!(" ({n} warnings)"),
    };
    if let (true, Some(signal)) = (failed.is_empty(), interrupted) {
        return format!(
            "Result: unknown: the probe was interrupted by {signal}{warned}, so whether the robot takes commands was \
             not found out. Run `doctor --probe` again."
        );
    }
    if failed.is_empty() {
        let how =
            if probed { "commands were accepted" } else { "add --probe to test that commands are accepted" };
        format!("Result: the robot can be driven{warned}; {how}.")
    } else {
        format!(
            "Result: the robot cannot be driven: {}{warned}. Fix the FAIL lines in order.",
            failed.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_lines_align_and_give_the_action() {
        let check = Check::fail("estop", "E-stop", "pressed", "release both E-stop buttons");
        assert_eq!(
            text_line(&check, false),
            "FAIL  E-stop             pressed\n      -> release both E-stop buttons\n"
        );
        assert_eq!(
            text_line(&Check::pass("battery", "battery", "25.9 V"), false),
            "PASS  battery            25.9 V\n"
        );
        assert!(text_line(&check, true).starts_with("\x1b[1;31mFAIL\x1b[0m  E-stop"));
    }

    #[test]
    fn verdict_names_the_failed_checks_and_counts_warnings() {
        let checks = [
            Check::pass("frames", "frames arriving", "ok"),
            Check::warn("battery", "battery", "22.3 V", "charge soon"),
            Check::fail("estop", "E-stop", "pressed", "release"),
            Check::fail("faults", "faults", "motor", "clear"),
        ];
        assert_eq!(
            verdict(&checks, false, None),
            "Result: the robot cannot be driven: E-stop, faults (1 warning). Fix the FAIL lines in order."
        );
        assert_eq!(
            verdict(&checks[..2], true, None),
            "Result: the robot can be driven (1 warning); commands were accepted."
        );
    }

    #[test]
    fn json_report_is_one_object_with_every_check() {
        let mut out = Vec::new();
        let mut report = Report::new(&mut out, ReportFormat::Json, false, "can0");
        report.add(Check::pass("frames", "frames arriving", "512 frames")).unwrap();
        report.add(Check::fail("estop", "E-stop", "pressed", "release")).unwrap();
        assert!(!report.finish(false).unwrap());
        let value: serde_json::Value = serde_json::from_slice(&out).unwrap();
        assert_eq!(value["link"], "can0");
        assert_eq!(value["drivable"], false);
        assert_eq!(value["failures"], 1);
        assert_eq!(value["checks"][1]["id"], "estop");
        assert_eq!(value["checks"][1]["status"], "fail");
        assert_eq!(value["checks"][1]["action"], "release");
        assert_eq!(value["checks"][0]["action"], serde_json::Value::Null);
    }
}
