//! `decode --plot FILE.svg`: the time series a technician looks at, drawn as stacked SVG panels.
//!
//! Memory is bounded whatever the log size: every series is reduced by min/max bucketing to at most
//! `MAX_POINTS` points, and at most `MAX_MARKERS` event markers are kept (the rest are counted).

use std::path::Path;

use anyhow::{Context, Result};
use plotters::prelude::*;

use crate::candump::Timestamp;
use crate::output::Event;
use crate::protocol::message::Message;

/// At most this many points per series are drawn (pairs of min and max per bucket).
const MAX_POINTS: usize = 4000;
/// Series with fewer points than this also get a dot per sample.
const SPARSE_POINTS: usize = 100;
/// At most this many event markers are drawn.
const MAX_MARKERS: usize = 100;
/// Battery thresholds drawn as dashed lines: warning, fault, cut-off (V).
const BATTERY_THRESHOLDS: [(f64, &str); 3] = [(22.5, "warning"), (22.0, "fault"), (21.5, "cut-off")];
const SIZE: (u32, u32) = (1200, 1500);
const ESTOP_COLOR: RGBColor = RGBColor(220, 0, 0);
const ESTOP_RELEASED_COLOR: RGBColor = RGBColor(0, 150, 0);
const FAULT_COLOR: RGBColor = RGBColor(230, 120, 0);
const M2_COLOR: RGBColor = RGBColor(200, 0, 160);

/// One min/max bucket of consecutive samples.
#[derive(Clone, Copy, Debug)]
struct Bucket {
    min: (f64, f64),
    max: (f64, f64),
    samples: u64,
}

impl Bucket {
    fn new(point: (f64, f64)) -> Self {
        Self { min: point, max: point, samples: 1 }
    }

    fn add(&mut self, point: (f64, f64)) {
        if point.1 < self.min.1 {
            self.min = point;
        }
        if point.1 > self.max.1 {
            self.max = point;
        }
        self.samples += 1;
    }

    fn merge(self, later: Bucket) -> Bucket {
        Bucket {
            min: if later.min.1 < self.min.1 { later.min } else { self.min },
            max: if later.max.1 > self.max.1 { later.max } else { self.max },
            samples: self.samples + later.samples,
        }
    }
}

/// A time series reduced by min/max bucketing: each bucket holds `stride` samples and keeps its extremes,
/// so spikes survive; when the buckets fill up, neighbours merge and the stride doubles.
#[derive(Debug)]
pub struct Series {
    buckets: Vec<Bucket>,
    current: Option<Bucket>,
    stride: u64,
}

impl Default for Series {
    fn default() -> Self {
        Self { buckets: Vec::new(), current: None, stride: 1 }
    }
}

impl Series {
    pub fn push(&mut self, t: f64, value: f64) {
        let point = (t, value);
        match &mut self.current {
            Some(bucket) => bucket.add(point),
            None => self.current = Some(Bucket::new(point)),
        }
        if self.current.is_some_and(|bucket| bucket.samples >= self.stride) {
            self.buckets.extend(self.current.take());
            if self.buckets.len() >= MAX_POINTS / 2 {
                let merged: Vec<Bucket> = self
                    .buckets
                    .chunks(2)
                    .map(|pair| if pair.len() == 2 { pair[0].merge(pair[1]) } else { pair[0] })
                    .collect();
                self.buckets = merged;
                self.stride *= 2;
            }
        }
    }

    /// The points to draw, in input order: at most `MAX_POINTS`.
    pub fn points(&self) -> Vec<(f64, f64)> {
        let mut points = Vec::with_capacity(self.buckets.len() * 2 + 2);
        for bucket in self.buckets.iter().chain(self.current.as_ref()) {
            let (first, second) = if bucket.min.0 <= bucket.max.0 {
                (bucket.min, bucket.max)
            } else {
                (bucket.max, bucket.min)
            };
            points.push(first);
            if second != first {
                points.push(second);
            }
        }
        points
    }

    fn is_empty(&self) -> bool {
        self.buckets.is_empty() && self.current.is_none()
    }

    fn range(&self) -> Option<(f64, f64)> {
        self.buckets.iter().chain(self.current.as_ref()).fold(None, |range, bucket| {
            let (lo, hi) = range.unwrap_or((bucket.min.1, bucket.max.1));
            Some((lo.min(bucket.min.1), hi.max(bucket.max.1)))
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    pub t: f64,
    pub label: String,
    kind: MarkerKind,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum MarkerKind {
    Estop,
    EstopReleased,
    Fault,
}

/// Everything collected for the plot.
#[derive(Debug, Default)]
pub struct Plot {
    start: Option<Timestamp>,
    /// Frames with a plottable value but no timestamp.
    pub untimed: u64,
    pub battery: Series,
    pub linear_cmd: Series,
    pub linear_meas: Series,
    pub angular_cmd: Series,
    pub angular_meas: Series,
    pub rpm: [Series; 2],
    pub current: [Series; 2],
    pub markers: Vec<Marker>,
    pub markers_not_drawn: u64,
    estop: Option<bool>,
    /// Fault bits already marked, per fault table (CAN V2; CAN V1 and RS232).
    faults_seen: [u16; 2],
}

impl Plot {
    pub fn event(&mut self, event: &Event) {
        let Ok(Some(decoded)) = &event.decoded else { return };
        let plottable = matches!(
            decoded.message,
            Message::SystemState(_)
                | Message::MotionCommand(_)
                | Message::PercentMotionCommand(_)
                | Message::MotionState(_)
                | Message::MotorHighSpeed(_)
                | Message::MotorDriverState(_)
        );
        if !plottable {
            return;
        }
        let Some(ts) = event.ts else {
            self.untimed += 1;
            return;
        };
        let start = *self.start.get_or_insert(ts);
        let t = ts.as_secs_f64() - start.as_secs_f64();
        match decoded.message {
            Message::SystemState(state) => {
                self.battery.push(t, state.battery_voltage());
                let estop = state.is_estop();
                if self.estop != Some(estop) && (self.estop.is_some() || estop) {
                    let (label, kind) = if estop {
                        ("E-stop", MarkerKind::Estop)
                    } else {
                        ("E-stop released", MarkerKind::EstopReleased)
                    };
                    self.mark(t, label.to_string(), kind);
                }
                self.estop = Some(estop);
                let faults = state.faults(decoded.wire);
                let table = usize::from(decoded.wire != crate::protocol::message::Wire::CanV2);
                let new = faults.bits & !self.faults_seen[table];
                if new != 0 {
                    self.faults_seen[table] |= new;
                    let fresh = crate::protocol::faults::Flags::new(faults.table, new);
                    for info in fresh.iter() {
                        self.mark(t, info.name.to_string(), MarkerKind::Fault);
                    }
                }
            }
            Message::MotionCommand(cmd) => {
                self.linear_cmd.push(t, cmd.linear());
                self.angular_cmd.push(t, cmd.angular());
            }
            Message::PercentMotionCommand(cmd) => {
                self.linear_cmd.push(t, cmd.linear());
                self.angular_cmd.push(t, cmd.angular());
            }
            Message::MotionState(state) => {
                self.linear_meas.push(t, state.linear());
                self.angular_meas.push(t, state.angular());
            }
            Message::MotorHighSpeed(motor) if matches!(motor.motor, 1 | 2) => {
                let index = usize::from(motor.motor - 1);
                self.rpm[index].push(t, f64::from(motor.rpm));
                self.current[index].push(t, f64::from(motor.current_deciamps) / 10.0);
            }
            Message::MotorDriverState(motor) if matches!(motor.motor, 1 | 2) => {
                let index = usize::from(motor.motor - 1);
                self.rpm[index].push(t, f64::from(motor.rpm));
                self.current[index].push(t, f64::from(motor.current_deciamps) / 10.0);
            }
            _ => {}
        }
    }

    fn mark(&mut self, t: f64, label: String, kind: MarkerKind) {
        if self.markers.len() < MAX_MARKERS {
            self.markers.push(Marker { t, label, kind });
        } else {
            self.markers_not_drawn += 1;
        }
    }

    /// True when no timestamped value was collected.
    pub fn is_empty(&self) -> bool {
        self.start.is_none()
    }

    /// Draws the panels and writes the SVG file; notes on standard error what could not be plotted.
    pub fn write(&self, path: &Path) -> Result<()> {
        if self.is_empty() {
            eprintln!(
                "tracerctl: --plot: nothing to plot (no timestamped battery, speed or motor frames{}); \
                 writing empty panels to {}",
                if self.untimed > 0 {
                    format!("; {} frames without timestamps", self.untimed)
                } else {
                    "".into()
                },
                path.display()
            );
        } else if self.untimed > 0 {
            eprintln!("tracerctl: --plot: {} frames without timestamps were not plotted", self.untimed);
        }
        if self.markers_not_drawn > 0 {
            eprintln!("tracerctl: --plot: {} further event markers were not drawn", self.markers_not_drawn);
        }
        let svg = self.render().context("cannot draw the plot")?;
        std::fs::write(path, svg).with_context(|| format!("cannot write {}", path.display()))
    }

    /// The SVG document.
    pub fn render(&self) -> Result<String> {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            root.fill(&WHITE)?;
            let panels = root.split_evenly((5, 1));
            let (start, end) = self.time_span();
            let battery_thresholds: Vec<(Vec<(f64, f64)>, String)> = BATTERY_THRESHOLDS
                .iter()
                .map(|&(volts, name)| (vec![(start, volts), (end, volts)], format!("{volts:.1} V {name}")))
                .collect();
            self.panel(
                &panels[0],
                "Battery voltage",
                "V",
                &[(&self.battery, "battery (V)", BLUE)],
                &battery_thresholds,
                true,
            )?;
            self.panel(
                &panels[1],
                "Linear speed",
                "m/s",
                &[
                    (&self.linear_cmd, "commanded linear (m/s)", BLUE),
                    (&self.linear_meas, "measured linear (m/s)", RED),
                ],
                &[],
                false,
            )?;
            self.panel(
                &panels[2],
                "Angular speed",
                "rad/s",
                &[
                    (&self.angular_cmd, "commanded angular (rad/s)", BLUE),
                    (&self.angular_meas, "measured angular (rad/s)", RED),
                ],
                &[],
                false,
            )?;
            self.panel(
                &panels[3],
                "Motor speed",
                "rpm",
                &[(&self.rpm[0], "rpm M1", BLUE), (&self.rpm[1], "rpm M2", M2_COLOR)],
                &[],
                false,
            )?;
            self.panel(
                &panels[4],
                "Motor current",
                "A",
                &[(&self.current[0], "current M1 (A)", BLUE), (&self.current[1], "current M2 (A)", M2_COLOR)],
                &[],
                false,
            )?;
            root.present()?;
        }
        Ok(svg)
    }

    /// The time axis: from 0 (the first timestamp) or earlier, should a later input's clock go backwards.
    fn time_span(&self) -> (f64, f64) {
        let all = [
            &self.battery,
            &self.linear_cmd,
            &self.linear_meas,
            &self.angular_cmd,
            &self.angular_meas,
            &self.rpm[0],
            &self.rpm[1],
            &self.current[0],
            &self.current[1],
        ];
        let times = all
            .iter()
            .flat_map(|series| series.points().into_iter().map(|p| p.0))
            .chain(self.markers.iter().map(|m| m.t));
        let (start, end) = times.fold((0.0, 0.0), |(lo, hi): (f64, f64), t| (lo.min(t), hi.max(t)));
        (start, if end > start { end } else { start + 1.0 })
    }

    /// One panel: the series with a legend, dashed reference lines, and a vertical line per event marker
    /// (labelled in the top panel only).
    fn panel(
        &self,
        area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
        title: &str,
        unit: &str,
        series: &[(&Series, &str, RGBColor)],
        references: &[(Vec<(f64, f64)>, String)],
        label_markers: bool,
    ) -> Result<()> {
        let (start, end) = self.time_span();
        let x_range = start..end;
        let mut range =
            series.iter().filter_map(|(s, _, _)| s.range()).fold(None, |acc: Option<(f64, f64)>, r| {
                Some(acc.map_or(r, |(lo, hi)| (lo.min(r.0), hi.max(r.1))))
            });
        for (points, _) in references {
            for &(_, y) in points {
                range = Some(range.map_or((y, y), |(lo, hi)| (lo.min(y), hi.max(y))));
            }
        }
        let (lo, hi) = range.unwrap_or((0.0, 1.0));
        let pad = if hi > lo { (hi - lo) * 0.08 } else { 1.0 };
        let y_range = (lo - pad)..(hi + pad);

        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(28)
            .y_label_area_size(60)
            .build_cartesian_2d(x_range, y_range.clone())?;
        chart.configure_mesh().x_desc("time (s)").y_desc(unit).light_line_style(WHITE).draw()?;

        for (points, label) in references {
            let style = BLACK.mix(0.5).stroke_width(1);
            chart
                .draw_series(DashedLineSeries::new(points.iter().copied(), 6, 4, style))?
                .label(label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
        }
        for &(data, label, color) in series {
            if data.is_empty() {
                continue;
            }
            let points = data.points();
            if points.len() < SPARSE_POINTS {
                // A line through one or two samples is invisible or misleading: show the samples too.
                chart.draw_series(points.iter().map(|&point| Circle::new(point, 2, color.filled())))?;
            }
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(1)))?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
        }
        for (index, marker) in self.markers.iter().enumerate() {
            let color = match marker.kind {
                MarkerKind::Estop => ESTOP_COLOR,
                MarkerKind::EstopReleased => ESTOP_RELEASED_COLOR,
                MarkerKind::Fault => FAULT_COLOR,
            };
            let line = PathElement::new(
                vec![(marker.t, y_range.start), (marker.t, y_range.end)],
                color.stroke_width(2),
            );
            chart.draw_series(std::iter::once(line))?;
            if label_markers {
                let style = ("sans-serif", 12).into_font().color(&color);
                // Staggered downwards so labels of events close in time do not overlap.
                let offset = (4, 2 + 14 * (index % 6) as i32);
                let label = EmptyElement::at((marker.t, y_range.end))
                    + Text::new(marker.label.clone(), offset, style);
                chart.draw_series(std::iter::once(label))?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_stays_bounded_and_keeps_spikes() {
        let mut series = Series::default();
        for i in 0..1_000_000u32 {
            let value = if i == 777_777 { 100.0 } else { f64::from(i % 10) };
            series.push(f64::from(i), value);
        }
        let points = series.points();
        assert!(points.len() <= MAX_POINTS, "{} points", points.len());
        assert!(points.len() > MAX_POINTS / 4, "{} points", points.len());
        assert!(points.iter().any(|p| p.1 == 100.0), "the spike survives");
        assert!(points.windows(2).all(|w| w[0].0 <= w[1].0), "in time order");
    }

    #[test]
    fn short_series_is_kept_whole() {
        let mut series = Series::default();
        for i in 0..10 {
            series.push(f64::from(i), f64::from(i * i));
        }
        assert_eq!(series.points().len(), 10);
    }
}
