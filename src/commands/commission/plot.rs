//! `--plot FILE.svg`: one panel per step that ran, each with the commanded speed, the measured speed and
//! the two wheel speeds (from the odometers) over the step's time. Hand-written SVG 1.1, no dependency.
//! Pure: the samples in, the document out.

use std::fmt::Write as _;

use super::measure::Sample;
use crate::health::plan::{Action, Step};

const WIDTH: f64 = 900.0;
const PANEL_HEIGHT: f64 = 170.0;
const TOP: f64 = 40.0;
const LEFT: f64 = 60.0;
const RIGHT: f64 = 20.0;
/// Wheel speeds are odometer differences over at least this long, µs (1 mm steps at 20 ms are 0.05 m/s).
const WHEEL_WINDOW_US: i64 = 100_000;

/// The series of a panel: class, colour, legend.
const SERIES: [(&str, &str, &str); 4] = [
    ("commanded", "#1f77b4", "commanded"),
    ("measured", "#d62728", "measured (motion state)"),
    ("left-wheel", "#2ca02c", "left wheel (odometer)"),
    ("right-wheel", "#ff7f0e", "right wheel (odometer)"),
];

/// A series of (µs, value) points.
type Series = Vec<(i64, f64)>;

/// One step's window on the recording's clock.
pub struct Window<'a> {
    pub step: &'a Step,
    pub from_us: i64,
    pub to_us: i64,
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Spin steps are drawn in rad/s (commanded and measured angular speed), the others in m/s.
fn angular(step: &Step) -> bool {
    matches!(step.action, Action::Command { linear, angular } if linear == 0.0 && angular != 0.0)
        || step.name.contains("spin")
}

/// Wheel speeds from successive odometer readings, at least [`WHEEL_WINDOW_US`] apart.
fn wheel_speeds(samples: &[Sample]) -> (Series, Series) {
    let odometers: Vec<(i64, f64, f64)> = samples
        .iter()
        .filter_map(|sample| match *sample {
            Sample::Odometer { at_us, left, right } => Some((at_us, left, right)),
            _ => None,
        })
        .collect();
    let (mut left, mut right) = (Vec::new(), Vec::new());
    let mut base = 0;
    for (at, reading) in odometers.iter().enumerate() {
        while at > base + 1 && reading.0 - odometers[base + 1].0 >= WHEEL_WINDOW_US {
            base += 1;
        }
        let start = odometers[base];
        let span = reading.0 - start.0;
        if span >= WHEEL_WINDOW_US {
            let seconds = span as f64 / 1e6;
            let middle = start.0 + span / 2;
            left.push((middle, (reading.1 - start.1) / seconds));
            right.push((middle, (reading.2 - start.2) / seconds));
        }
    }
    (left, right)
}

/// The SVG document.
pub fn svg(title: &str, windows: &[Window<'_>], samples: &[Sample]) -> String {
    let (left_wheel, right_wheel) = wheel_speeds(samples);
    let height = TOP + PANEL_HEIGHT * windows.len().max(1) as f64 + 10.0;
    let mut out = String::new();
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{WIDTH}" height="{height}" viewBox="0 0 {WIDTH} {height}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(out, r#"<title>{}</title>"#, escape(title));
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(out, r#"<text x="{LEFT}" y="16" font-size="13">{}</text>"#, escape(title));
    for (number, (_, colour, legend)) in SERIES.iter().enumerate() {
        let x = LEFT + number as f64 * 190.0;
        let _ = writeln!(
            out,
            r#"<line x1="{x}" y1="28" x2="{}" y2="28" stroke="{colour}" stroke-width="2"/><text x="{}" y="32">{legend}</text>"#,
            x + 20.0,
            x + 25.0
        );
    }
    for (number, window) in windows.iter().enumerate() {
        let top = TOP + PANEL_HEIGHT * number as f64;
        panel(&mut out, window, top, samples, (&left_wheel, &right_wheel));
    }
    out.push_str("</svg>\n");
    out
}

fn panel(out: &mut String, window: &Window<'_>, top: f64, samples: &[Sample], wheels: (&Series, &Series)) {
    let spin = angular(window.step);
    let inside = |at: i64| at >= window.from_us && at <= window.to_us;
    let pick = |want_command: bool| -> Vec<(i64, f64)> {
        samples
            .iter()
            .filter_map(|sample| match (*sample, want_command) {
                (Sample::Command { at_us, linear, angular }, true)
                | (Sample::Motion { at_us, linear, angular }, false) => {
                    Some((at_us, if spin { angular } else { linear }))
                }
                _ => None,
            })
            .filter(|(at, _)| inside(*at))
            .collect()
    };
    let series: [Series; 4] = [
        pick(true),
        pick(false),
        wheels.0.iter().copied().filter(|(at, _)| inside(*at)).collect(),
        wheels.1.iter().copied().filter(|(at, _)| inside(*at)).collect(),
    ];
    let peak = series.iter().flatten().map(|(_, value)| value.abs()).fold(0.1_f64, f64::max) * 1.1;
    let (plot_top, plot_height) = (top + 18.0, PANEL_HEIGHT - 40.0);
    let plot_width = WIDTH - LEFT - RIGHT;
    let span = (window.to_us - window.from_us).max(1) as f64;
    let x = |at: i64| LEFT + (at - window.from_us) as f64 / span * plot_width;
    let y = |value: f64| plot_top + plot_height / 2.0 - value / peak * plot_height / 2.0;
    let unit = if spin { "rad/s (wheels m/s)" } else { "m/s" };
    let _ = writeln!(out, r#"<g class="panel" data-step="{}">"#, escape(window.step.name));
    let _ = writeln!(
        out,
        r#"<text x="{LEFT}" y="{}" font-size="12">{} ({:.1} s, {unit})</text>"#,
        top + 13.0,
        escape(window.step.name),
        span / 1e6
    );
    let _ = writeln!(
        out,
        r##"<rect x="{LEFT}" y="{plot_top}" width="{plot_width}" height="{plot_height}" fill="none" stroke="#999"/>"##
    );
    let zero = y(0.0);
    let _ = writeln!(
        out,
        r##"<line x1="{LEFT}" y1="{zero:.1}" x2="{:.1}" y2="{zero:.1}" stroke="#ccc"/>"##,
        LEFT + plot_width
    );
    for (value, anchor) in [(peak, plot_top + 4.0), (-peak, plot_top + plot_height)] {
        let _ =
            writeln!(out, r#"<text x="{}" y="{anchor:.1}" text-anchor="end">{value:+.2}</text>"#, LEFT - 4.0);
    }
    for ((class, colour, _), points) in SERIES.iter().zip(&series) {
        let mut path = String::new();
        for (at, value) in points {
            let _ = write!(path, "{:.1},{:.1} ", x(*at), y(*value));
        }
        let _ = writeln!(
            out,
            r#"<polyline class="series {class}" fill="none" stroke="{colour}" stroke-width="1.5" points="{}"/>"#,
            path.trim_end()
        );
    }
    out.push_str("</g>\n");
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn a_panel_per_step_with_four_series_and_wheel_speeds_from_the_odometers() {
        let forward = Step {
            name: "forward <1>",
            action: Action::Command { linear: 0.3, angular: 0.0 },
            duration: Duration::from_secs(1),
        };
        let spin = Step {
            name: "spin left",
            action: Action::Command { linear: 0.0, angular: 0.5 },
            duration: Duration::from_secs(1),
        };
        let mut samples = Vec::new();
        for tick in 0..100_i64 {
            let at_us = tick * 20_000;
            samples.push(Sample::Command { at_us, linear: 0.3, angular: 0.0 });
            samples.push(Sample::Motion { at_us: at_us + 5000, linear: 0.3, angular: 0.0 });
            samples.push(Sample::Odometer {
                at_us: at_us + 6000,
                left: 0.3 * at_us as f64 / 1e6,
                right: 0.3 * at_us as f64 / 1e6,
            });
        }
        let (left, _) = wheel_speeds(&samples);
        assert!(left.iter().all(|(_, speed)| (speed - 0.3).abs() < 1e-9), "{left:?}");
        let windows = [
            Window { step: &forward, from_us: 0, to_us: 1_000_000 },
            Window { step: &spin, from_us: 1_000_000, to_us: 2_000_000 },
        ];
        let svg = svg("commission & test", &windows, &samples);
        assert_eq!(svg.matches(r#"<g class="panel""#).count(), 2);
        assert_eq!(svg.matches(r#"<polyline class="series"#).count(), 8);
        assert!(svg.contains(r#"data-step="forward &lt;1&gt;""#));
        assert!(svg.contains("<title>commission &amp; test</title>"));
        assert!(svg.trim_end().ends_with("</svg>"));
    }
}
