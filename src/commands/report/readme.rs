//! README.txt, the bundle's own description, and report.json, its machine-readable twin: what each file
//! is, what was left out and why, and what a bundle never holds. Pure: made from the members' list.

use std::fmt::Write as _;

use serde_json::json;

use super::bundle::Omitted;

/// What the README and report.json say besides the files.
pub struct About<'a> {
    pub version: &'a str,
    pub created: &'a str,
    pub host: &'a str,
    pub link: &'a str,
    pub max_size: u64,
    /// The recorder's directory, or why there is none.
    pub recorder: Result<&'a str, &'a str>,
    /// (name, size, what it is), in bundle order.
    pub files: &'a [(String, u64, String)],
    pub left_out: &'a [Omitted],
    /// Other things not included, in words (older incidents beyond --incidents).
    pub notes: &'a [String],
}

/// `12.3 MB`, `512 B`: decimal units, as --max-size takes them.
pub fn size_text(bytes: u64) -> String {
    match bytes {
        0..1_000 => format!("{bytes} B"),
        1_000..1_000_000 => format!("{:.1} kB", bytes as f64 / 1e3),
        1_000_000..1_000_000_000 => format!("{:.1} MB", bytes as f64 / 1e6),
        _ => format!("{:.2} GB", bytes as f64 / 1e9),
    }
}

pub fn readme(about: &About) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "tracerctl support bundle");
    let _ = writeln!(out, "========================\n");
    let _ = writeln!(out, "Made by tracerctl {} on {} at {}.", about.version, about.host, about.created);
    let _ = writeln!(out, "Link: {}.", about.link);
    match about.recorder {
        Ok(dir) => {
            let _ = writeln!(out, "Recorder directory: {dir}.");
        }
        Err(why) => {
            let _ = writeln!(out, "Recorder directory: none ({why}).");
        }
    }
    let _ = writeln!(out, "Size cap: {} (--max-size).\n", size_text(about.max_size));
    let _ = writeln!(out, "Files:");
    let width = about.files.iter().map(|(name, ..)| name.len()).max().unwrap_or(0).max(12);
    let _ = writeln!(out, "  {:<width$}  what it is", "file");
    let _ = writeln!(out, "  {:<width$}  this file", "README.txt");
    let _ =
        writeln!(out, "  {:<width$}  the same in JSON: every file, what was left out and why", "report.json");
    for (name, size, what) in about.files {
        let _ = writeln!(out, "  {name:<width$}  {what} ({})", size_text(*size));
    }
    if about.left_out.is_empty() && about.notes.is_empty() {
        let _ = writeln!(out, "\nLeft out: nothing.");
    } else {
        let _ = writeln!(out, "\nLeft out:");
        for omitted in about.left_out {
            let _ = writeln!(out, "  {} ({}): {}", omitted.name, size_text(omitted.size), omitted.why);
        }
        for note in about.notes {
            let _ = writeln!(out, "  {note}");
        }
    }
    out.push_str(
        "\nNever in a bundle: environment variables, files from outside the recorder's directory (a home \
         directory in a path is written ~), anything about other processes.\n\
         \nReading it: `tracerctl decode FILE` reads every .log, .log.zst and incident folder here (and \
         `decode --summary` reports on it); can-utils read the .log files (after `zstd -d` for the ring's \
         segments); Foxglove opens the .mcap files.\n",
    );
    out
}

pub fn report_json(about: &About) -> serde_json::Value {
    let files: Vec<_> = about
        .files
        .iter()
        .map(|(name, size, what)| json!({"name": name, "size": size, "about": what}))
        .collect();
    let left_out: Vec<_> = about
        .left_out
        .iter()
        .map(|omitted| json!({"name": omitted.name, "size": omitted.size, "why": omitted.why}))
        .collect();
    let (dir, why) = match about.recorder {
        Ok(dir) => (Some(dir), None),
        Err(why) => (None, Some(why)),
    };
    json!({
        "tracerctl": about.version,
        "created": about.created,
        "host": about.host,
        "link": about.link,
        "max_size": about.max_size,
        "recorder_dir": dir,
        "no_recorder_dir": why,
        "files": files,
        "left_out": left_out,
        "notes": about.notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_written_in_decimal_units() {
        assert_eq!(size_text(999), "999 B");
        assert_eq!(size_text(1_500), "1.5 kB");
        assert_eq!(size_text(50_000_000), "50.0 MB");
        assert_eq!(size_text(2_000_000_000), "2.00 GB");
    }

    #[test]
    fn the_readme_lists_every_file_and_every_omission() {
        let files = [("doctor.txt".to_string(), 1200, "doctor's report".to_string())];
        let left_out = [Omitted {
            name: "recorder/ring/a.log.zst".into(),
            size: 2_000_000,
            why: "over the size cap".into(),
        }];
        let notes = ["3 older incidents (--incidents 5)".to_string()];
        let about = About {
            version: "0.1.0",
            created: "2026-11-28 13:41:00 UTC",
            host: "jetson",
            link: "can0 (SocketCAN)",
            max_size: 50_000_000,
            recorder: Err("no --dir given"),
            files: &files,
            left_out: &left_out,
            notes: &notes,
        };
        let text = readme(&about);
        assert!(text.contains("  doctor.txt    doctor's report (1.2 kB)\n"), "{text}");
        assert!(text.contains("  recorder/ring/a.log.zst (2.0 MB): over the size cap\n"), "{text}");
        assert!(text.contains("  3 older incidents (--incidents 5)\n"), "{text}");
        assert!(text.contains("Recorder directory: none (no --dir given)."), "{text}");
        let json = report_json(&about);
        assert_eq!(json["files"][0]["size"], 1200);
        assert_eq!(json["left_out"][0]["why"], "over the size cap");
        assert_eq!(json["recorder_dir"], serde_json::Value::Null);
    }
}
