//! `tracerctl decode --plot FILE.svg`: the SVG is parsed for its series, legends and event markers.

use std::io::Write;
use std::path::Path;

use crate::util::{data, stderr, stdout, tracerctl};

/// What the tests look at in the SVG: every polyline and every text element.
struct Svg {
    /// (stroke colour, stroke width, number of points).
    polylines: Vec<(String, String, usize)>,
    /// (fill colour, text).
    texts: Vec<(String, String)>,
    circles: usize,
    size: usize,
}

fn attribute(tag: &str, name: &str) -> String {
    let key = format!(" {name}=\"");
    let start = tag.find(&key).unwrap_or_else(|| panic!("no {name} in {tag}")) + key.len();
    let len = tag[start..].find('"').expect("closing quote");
    tag[start..start + len].to_string()
}

fn parse(path: &Path) -> Svg {
    let text = std::fs::read_to_string(path).expect("SVG written");
    assert!(text.starts_with("<svg "), "an SVG document: {}", &text[..text.len().min(80)]);
    assert!(text.trim_end().ends_with("</svg>"), "complete SVG");
    let mut svg = Svg { polylines: Vec::new(), texts: Vec::new(), circles: 0, size: text.len() };
    for (index, _) in text.match_indices("<polyline ") {
        let end = index + text[index..].find("/>").expect("polyline closed");
        let tag = &text[index..end];
        let points = attribute(tag, "points").split_whitespace().count();
        svg.polylines.push((attribute(tag, "stroke"), attribute(tag, "stroke-width"), points));
    }
    for (index, _) in text.match_indices("<text ") {
        let open_end = index + text[index..].find('>').expect("text tag closed");
        let close = open_end + text[open_end..].find("</text>").expect("text element closed");
        let tag = &text[index..open_end];
        svg.texts.push((attribute(tag, "fill"), text[open_end + 1..close].trim().to_string()));
    }
    svg.circles = text.matches("<circle ").count();
    svg
}

impl Svg {
    fn has_text(&self, wanted: &str) -> bool {
        self.texts.iter().any(|(_, text)| text == wanted)
    }

    fn text_color(&self, wanted: &str) -> &str {
        &self.texts.iter().find(|(_, text)| text == wanted).unwrap_or_else(|| panic!("no label {wanted}")).0
    }

    /// Polylines of one colour and width (1: series, 2: legend samples and event markers).
    fn lines(&self, color: &str, width: &str) -> Vec<usize> {
        self.polylines.iter().filter(|(c, w, _)| c == color && w == width).map(|(_, _, n)| *n).collect()
    }
}

const SERIES_LEGENDS: [&str; 9] = [
    "battery (V)",
    "commanded linear (m/s)",
    "measured linear (m/s)",
    "commanded angular (rad/s)",
    "measured angular (rad/s)",
    "rpm M1",
    "rpm M2",
    "current M1 (A)",
    "current M2 (A)",
];

#[test]
fn plot_of_session_log_has_series_thresholds_and_event_markers() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("session.svg");
    let log = data("tracer_session.log");
    let output = tracerctl().arg("decode").arg("--plot").arg(&out).arg(&log).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(stdout(&output).lines().count(), 15, "frames are still printed");
    let svg = parse(&out);

    for title in ["Battery voltage", "Linear speed", "Angular speed", "Motor speed", "Motor current"] {
        assert!(svg.has_text(title), "panel {title}");
    }
    // The session has no motor 2 frame: its legend entries are left out.
    for legend in SERIES_LEGENDS.iter().filter(|legend| !legend.contains("M2")) {
        assert!(svg.has_text(legend), "legend {legend}");
    }
    assert!(!svg.has_text("rpm M2"));
    for threshold in ["22.5 V warning", "22.0 V fault", "21.5 V cut-off"] {
        assert!(svg.has_text(threshold), "threshold {threshold}");
    }

    // Series are 1-px polylines: battery (blue, six 0x211 frames), measured speeds (red, two 0x221).
    let blue = svg.lines("#0000FF", "1");
    assert!(blue.contains(&6), "battery polyline of 6 points: {blue:?}");
    let red = svg.lines("#FF0000", "1");
    assert_eq!(red, vec![2, 2], "measured linear and angular");
    // One 0x111 command and one 0x251 frame: single samples get dots.
    assert!(svg.circles >= 4, "{} circles", svg.circles);

    // Markers: labelled once, a vertical line in each of the five panels, each kind its own colour.
    assert_eq!(svg.text_color("E-stop"), "#DC0000");
    assert_eq!(svg.text_color("battery_undervoltage_warning"), "#E67800");
    assert_eq!(svg.text_color("E-stop released"), "#009600");
    for color in ["#DC0000", "#E67800", "#009600"] {
        let markers = svg.lines(color, "2");
        assert_eq!(markers, vec![2; 5], "{color} marker in every panel");
    }
    assert!(svg.size < 300_000, "{} bytes", svg.size);
}

#[test]
fn plot_works_with_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("summary.svg");
    let log = data("tracer_session.log");
    let output =
        tracerctl().arg("decode").arg("--summary").arg("--plot").arg(&out).arg(&log).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stdout(&output).starts_with("Input"), "the summary is printed");
    let svg = parse(&out);
    assert!(svg.has_text("battery (V)") && svg.has_text("E-stop"));
}

#[test]
fn plot_without_timestamps_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("untimed.svg");
    let output =
        tracerctl().arg("decode").arg("--plot").arg(&out).arg("211#00000103000000B1").output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stderr(&output).contains("nothing to plot"), "{}", stderr(&output));
    assert!(stderr(&output).contains("1 frames without timestamps"), "{}", stderr(&output));
    let svg = parse(&out);
    assert!(svg.has_text("Battery voltage"), "empty panels still drawn");
    assert!(svg.lines("#0000FF", "1").is_empty());
}

/// A candump -L log of `ticks` 20 ms periods: 0x111, 0x211, 0x221, 0x251, 0x252 each. The battery drains
/// from 25.9 V to 21.9 V (the warning bit below 22.5 V), and an E-stop is pressed for 100 periods.
fn write_long_log(path: &Path, ticks: u64) {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    for tick in 0..ticks {
        let micros = 1_700_000_000_000_000u64 + tick * 20_000;
        let ts = format!("({}.{:06}) can0", micros / 1_000_000, micros % 1_000_000);
        let decivolts = 259 - (tick * 40 / ticks) as u16;
        let faults: u16 = if decivolts < 225 { 0x0200 } else { 0 };
        let estop = u8::from((20_000..20_100).contains(&tick));
        let phase = tick as f64 / 3000.0 * std::f64::consts::TAU;
        let linear = (1200.0 * phase.sin()) as i16;
        let angular = (500.0 * (phase * 2.0).sin()) as i16;
        let rpm = linear * 3;
        let current = (linear / 20).unsigned_abs() as i16 + (tick % 7) as i16;
        let count = tick as u8;
        writeln!(out, "{ts} 111#{:04X}{:04X}00000000", linear, angular).unwrap();
        writeln!(out, "{ts} 211#{estop:02X}01{decivolts:04X}{faults:04X}00{count:02X}").unwrap();
        writeln!(out, "{ts} 221#{:04X}{:04X}00000000", linear - 10, angular + 5).unwrap();
        writeln!(out, "{ts} 251#{:04X}{:04X}00000000", rpm, current).unwrap();
        writeln!(out, "{ts} 252#{:04X}{:04X}00000000", rpm + 40, current + 3).unwrap();
    }
    out.flush().unwrap();
}

#[test]
fn plot_of_200k_lines_stays_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("long.log");
    write_long_log(&log, 40_000);
    let out = dir.path().join("long.svg");
    let output =
        tracerctl().arg("decode").arg("--summary").arg("--plot").arg(&out).arg(&log).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stdout(&output).contains("200000 frames"), "{}", stdout(&output));
    let svg = parse(&out);
    assert!(svg.size < 2_000_000, "SVG of {} bytes", svg.size);
    for legend in SERIES_LEGENDS {
        assert!(svg.has_text(legend), "legend {legend}");
    }
    let series: Vec<usize> = svg.polylines.iter().filter(|(_, w, _)| w == "1").map(|(_, _, n)| *n).collect();
    let long: Vec<usize> = series.iter().copied().filter(|&n| n > 100).collect();
    assert_eq!(long.len(), 9, "nine downsampled series: {series:?}");
    assert!(long.iter().all(|&n| (1000..=4000).contains(&n)), "downsampled: {long:?}");
    assert!(svg.has_text("E-stop") && svg.has_text("E-stop released"));
    assert!(svg.has_text("battery_undervoltage_warning"));
}

#[test]
fn crowded_event_labels_never_overlap_and_the_ones_left_out_are_counted() {
    // 10 s of status every 20 ms with the E-stop toggled every 100 ms: 99 events, far too close for labels.
    let mut log = String::new();
    for frame in 0..500u32 {
        let t = f64::from(frame) * 0.02;
        let estop = (frame / 5) % 2;
        log.push_str(&format!("({t:.6}) can0 211#{estop:02X}000103000000{:02X}\n", frame % 256));
    }
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("crowded.log");
    std::fs::write(&input, log).unwrap();
    let out = dir.path().join("crowded.svg");
    let output =
        tracerctl().arg("decode").arg("--summary").arg("--plot").arg(&out).arg(&input).output().unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let errors = stderr(&output);
    let left_out: usize = errors
        .split("--plot: ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|count| count.parse().ok())
        .unwrap_or_else(|| panic!("a count of labels left out: {errors}"));
    assert!(errors.contains("event labels left out where events crowd"), "{errors}");

    // Label boxes (x, y, estimated width at 7 px a character) of the marker texts.
    let text = std::fs::read_to_string(&out).unwrap();
    let mut boxes = Vec::new();
    for (index, _) in text.match_indices("<text ") {
        let open_end = index + text[index..].find('>').unwrap();
        let close = open_end + text[open_end..].find("</text>").unwrap();
        let label = text[open_end + 1..close].trim();
        if label == "E-stop" || label == "E-stop released" {
            let tag = &text[index..open_end];
            let x: f64 = attribute(tag, "x").parse().unwrap();
            let y: f64 = attribute(tag, "y").parse().unwrap();
            boxes.push((x, y, 7.0 * label.len() as f64));
        }
    }
    assert_eq!(boxes.len() + left_out, 99, "every event is labelled or counted as left out");
    assert!(boxes.len() >= 6, "the lanes are used: {} labels", boxes.len());
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            let same_lane = (a.1 - b.1).abs() < 1.0;
            let overlap = a.0 < b.0 + b.2 && b.0 < a.0 + a.2;
            assert!(!(same_lane && overlap), "labels overlap: {a:?} {b:?}");
        }
    }
    // Every event still has its line in each of the five panels.
    let svg = parse(&out);
    assert_eq!(svg.lines("#DC0000", "2").len() + svg.lines("#009600", "2").len(), 99 * 5);
}
