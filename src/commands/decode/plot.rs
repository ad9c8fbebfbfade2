//! `decode --plot FILE.svg`: the time series a technician looks at, drawn as stacked SVG panels.
//!
//! Memory is bounded whatever the log size: every series is reduced by min/max bucketing to at most
//! `MAX_POINTS` points, and at most `MAX_MARKERS` event markers are kept (the rest are counted).

use std::path::Path;

use anyhow::{Context, Result};
use plotters::prelude::*;

use crate::candump::Timestamp;
use crate::output::Event;
use crate::protocol::constants;
use crate::protocol::message::Message;

/// At most this many points per series are drawn (pairs of min and max per bucket).
const MAX_POINTS: usize = 4000;
/// Series with fewer points than this also get a dot per sample.
const SPARSE_POINTS: usize = 100;
/// At most this many event markers are drawn.
const MAX_MARKERS: usize = 100;
/// Battery thresholds drawn as dashed lines: warning, fault, cut-off (V).
const SIZE: (u32, u32) = (1200, 1500);
const ESTOP_COLOR: RGBColor = RGBColor(220, 0, 0);
const ESTOP_RELEASED_COLOR: RGBColor = RGBColor(0, 150, 0);
const FAULT_COLOR: RGBColor = RGBColor(230, 120, 0);
const M2_COLOR: RGBColor = RGBColor(200, 0, 160);

/// `--plot FILE`: the plot is SVG, so a name ending in another image format (`x.png`) is a usage error,
/// found before any input is read.
pub fn check_path(path: &Path) -> Result<()> {
    let Some(extension) = path.extension() else { return Ok(()) };
    if extension.eq_ignore_ascii_case("svg") {
        return Ok(());
    }
    Err(crate::exit::Failure {
        code: crate::exit::USAGE,
        message: format!(
            "--plot {}: the plot is written as SVG; give a file name ending in .svg",
            path.display()
        ),
    }
    .into())
}

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
            crate::say!(
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
            crate::say!("tracerctl: --plot: {} frames without timestamps were not plotted", self.untimed);
        }
        if self.markers_not_drawn > 0 {
            crate::say!("tracerctl: --plot: {} further event markers were not drawn", self.markers_not_drawn);
        }
        let (svg, unlabeled) = self.render().context("cannot draw the plot")?;
        if unlabeled > 0 {
            crate::say!(
                "tracerctl: --plot: {unlabeled} event labels left out where events crowd (every event still has \
                 its line: red E-stop, green E-stop released, orange fault)"
            );
        }
        std::fs::write(path, svg).with_context(|| format!("cannot write {}", path.display()))
    }

    /// The SVG document, and how many event labels found no room.
    fn render(&self) -> Result<(String, usize)> {
        let mut svg = String::new();
        let unlabeled;
        {
            let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
            root.fill(&WHITE)?;
            let panels = root.split_evenly((5, 1));
            let (start, end) = self.time_span();
            let battery_thresholds: Vec<(Vec<(f64, f64)>, String)> = constants::BATTERY_THRESHOLDS
                .iter()
                .map(|&(decivolts, name)| {
                    let volts = constants::volts(decivolts);
                    (vec![(start, volts), (end, volts)], format!("{volts:.1} V {name}"))
                })
                .collect();
            unlabeled = self.panel(
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
        Ok((svg, unlabeled))
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
    /// (labelled in the top panel only). Returns how many labels were left out for lack of room.
    fn panel(
        &self,
        area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
        title: &str,
        unit: &str,
        series: &[(&Series, &str, RGBColor)],
        references: &[(Vec<(f64, f64)>, String)],
        label_markers: bool,
    ) -> Result<usize> {
        let (start, end) = self.time_span();
        let x_range = start..end;
        let lanes = if label_markers {
            self.label_lanes_in(area, start, end)
        } else {
            vec![None; self.markers.len()]
        };
        let y_range = y_range(area, value_range(series, references), &lanes);

        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 16))
            .margin(MARGIN_PX)
            .x_label_area_size(X_LABEL_AREA_PX)
            .y_label_area_size(Y_LABEL_AREA_PX)
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
        self.draw_markers(&mut chart, &y_range, &lanes)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        Ok(lanes.iter().filter(|lane| lane.is_none()).count() * usize::from(label_markers))
    }

    /// The label lane of each event marker at the top of the plot (`None`: no room left for its label).
    fn label_lanes_in(
        &self,
        area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
        start: f64,
        end: f64,
    ) -> Vec<Option<usize>> {
        let (width, _) = area.dim_in_pixel();
        let (plot_left, plot_right) = (MARGIN_PX + Y_LABEL_AREA_PX, width as i32 - MARGIN_PX);
        let spans: Vec<(i32, i32)> = self
            .markers
            .iter()
            .map(|marker| {
                let share = (marker.t - start) / (end - start);
                let x = plot_left + (share * f64::from(plot_right - plot_left)).round() as i32;
                (x, x + LABEL_OFFSET_PX + LABEL_CHAR_PX * marker.label.chars().count() as i32)
            })
            .collect();
        label_lanes(&spans, LABEL_LANES)
    }

    /// A vertical line per event marker, then the labels that found a lane, on a pale box (after all lines,
    /// so the lines of neighbouring events do not cross them).
    fn draw_markers(
        &self,
        chart: &mut ChartContext<
            SVGBackend,
            Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
        >,
        y_range: &std::ops::Range<f64>,
        lanes: &[Option<usize>],
    ) -> Result<()> {
        let color_of = |marker: &Marker| match marker.kind {
            MarkerKind::Estop => ESTOP_COLOR,
            MarkerKind::EstopReleased => ESTOP_RELEASED_COLOR,
            MarkerKind::Fault => FAULT_COLOR,
        };
        for marker in &self.markers {
            let line = PathElement::new(
                vec![(marker.t, y_range.start), (marker.t, y_range.end)],
                color_of(marker).stroke_width(2),
            );
            chart.draw_series(std::iter::once(line))?;
        }
        for (marker, lane) in self.markers.iter().zip(lanes) {
            let Some(lane) = lane else { continue };
            let color = color_of(marker);
            let style = ("sans-serif", 12).into_font().color(&color);
            let (x, y) = (LABEL_OFFSET_PX, 2 + LABEL_LANE_PX * *lane as i32);
            let width = LABEL_CHAR_PX * marker.label.chars().count() as i32;
            let label = EmptyElement::at((marker.t, y_range.end))
                + Rectangle::new([(x - 1, y), (x + width, y + LABEL_LANE_PX - 1)], WHITE.mix(0.85).filled())
                + Text::new(marker.label.clone(), (x, y), style);
            chart.draw_series(std::iter::once(label))?;
        }
        Ok(())
    }
}

/// The lowest and highest value of the series and the reference lines ((0, 1) when there is none).
fn value_range(series: &[(&Series, &str, RGBColor)], references: &[(Vec<(f64, f64)>, String)]) -> (f64, f64) {
    let mut range = series
        .iter()
        .filter_map(|(s, _, _)| s.range())
        .fold(None, |acc: Option<(f64, f64)>, r| Some(acc.map_or(r, |(lo, hi)| (lo.min(r.0), hi.max(r.1)))));
    for (points, _) in references {
        for &(_, y) in points {
            range = Some(range.map_or((y, y), |(lo, hi)| (lo.min(y), hi.max(y))));
        }
    }
    range.unwrap_or((0.0, 1.0))
}

/// The y axis: the values with padding, and above them a band for the event labels' lanes (the data range
/// is pushed down below them).
fn y_range(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    (lo, hi): (f64, f64),
    lanes: &[Option<usize>],
) -> std::ops::Range<f64> {
    let pad = if hi > lo { (hi - lo) * 0.08 } else { 1.0 };
    let (_, height) = area.dim_in_pixel();
    let plot_height = (height as i32 - 2 * MARGIN_PX - X_LABEL_AREA_PX - CAPTION_PX).max(1);
    let band_px = lanes.iter().flatten().max().map_or(0, |lane| 4 + LABEL_LANE_PX * (*lane as i32 + 1));
    // The band's share of the height, reserved above the data and its normal padding.
    let band = f64::from(band_px.min(plot_height * 2 / 3)) / f64::from(plot_height);
    let top = (hi + pad - (lo - pad) * band) / (1.0 - band);
    (lo - pad)..top
}

/// Panel geometry in pixels: margin, axis label areas, and the caption's height (16 px text and its gap).
const MARGIN_PX: i32 = 8;
const X_LABEL_AREA_PX: i32 = 28;
const Y_LABEL_AREA_PX: i32 = 60;
const CAPTION_PX: i32 = 26;
/// Rows of event labels under the top of the top panel, and the label geometry (12 px sans-serif).
const LABEL_LANES: usize = 6;
const LABEL_LANE_PX: i32 = 14;
const LABEL_OFFSET_PX: i32 = 4;
/// A generous average glyph width, so estimated labels are never narrower than drawn ones.
const LABEL_CHAR_PX: i32 = 7;
/// Space kept between two labels in one lane.
const LABEL_GAP_PX: i32 = 6;

/// Gives each label (its horizontal pixel span) the first lane in which it does not overlap a label
/// placed before it, in left-to-right order; `None` when every lane is taken there.
fn label_lanes(spans: &[(i32, i32)], lanes: usize) -> Vec<Option<usize>> {
    let mut order: Vec<usize> = (0..spans.len()).collect();
    order.sort_by_key(|&index| spans[index].0);
    let mut lane_end = vec![i32::MIN; lanes];
    let mut assigned = vec![None; spans.len()];
    for index in order {
        let (start, end) = spans[index];
        if let Some(lane) = lane_end.iter().position(|&taken| taken < start) {
            lane_end[lane] = end + LABEL_GAP_PX;
            assigned[index] = Some(lane);
        }
    }
    assigned
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_take_the_first_free_lane_and_are_left_out_when_all_are_taken() {
        // Three labels 100 px wide, 10 px apart: each needs its own lane; a fourth far right reuses lane 0.
        let spans = [(0, 100), (10, 110), (20, 120), (300, 400)];
        assert_eq!(label_lanes(&spans, 6), [Some(0), Some(1), Some(2), Some(0)]);
        // Two lanes only: the third is left out.
        assert_eq!(label_lanes(&spans, 2), [Some(0), Some(1), None, Some(0)]);
        // Order of the input does not matter: lanes follow the x position.
        assert_eq!(label_lanes(&[(300, 400), (0, 100)], 1), [Some(0), Some(0)]);
        // A label starting inside the gap after another is not put in its lane.
        assert_eq!(label_lanes(&[(0, 100), (104, 150)], 2), [Some(0), Some(1)]);
    }

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
