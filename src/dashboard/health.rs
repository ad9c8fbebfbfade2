//! What the dashboard shows of the live analysis (`health::Analyzer`): the latest dead time and the
//! battery's internal resistance, once the drive has given them. Pure: built from a `health::Report`.

use crate::health::{BatteryEstimate, Report};

/// The figures shown, at the resolution shown (the view is hashed to decide a redraw); `None` until
/// measured (nothing is shown then, never a guess).
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct HealthView {
    /// The dead time of the latest step that had one, whole ms.
    pub dead_time_ms: Option<u32>,
    pub battery: Option<BatteryView>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BatteryView {
    pub internal_resistance_milliohm: u32,
    pub open_circuit_decivolts: u16,
    pub load_steps: usize,
}

impl HealthView {
    pub fn of(report: &Report) -> Self {
        // `as` saturates: a nonsense figure shows as the largest, never panics.
        let dead_time_ms =
            report.steps.iter().rev().find_map(|step| step.dead_time_ms).map(|ms| ms.round() as u32);
        let battery = match report.battery {
            BatteryEstimate::Measured {
                internal_resistance_ohm, open_circuit_voltage_v, load_steps, ..
            } => Some(BatteryView {
                internal_resistance_milliohm: (internal_resistance_ohm * 1000.0).round() as u32,
                open_circuit_decivolts: (open_circuit_voltage_v * 10.0).round() as u16,
                load_steps,
            }),
            BatteryEstimate::NotMeasurable(_) => None,
        };
        Self { dead_time_ms, battery }
    }

    /// `dead time 40 ms`
    pub fn dead_time_text(&self) -> Option<String> {
        self.dead_time_ms.map(|ms| format!("dead time {ms} ms"))
    }

    /// `R 0.120 Ω · OCV 25.9 V (9 steps)`
    pub fn battery_text(&self) -> Option<String> {
        self.battery.map(|battery| {
            let (milliohm, decivolts) =
                (battery.internal_resistance_milliohm, battery.open_circuit_decivolts);
            format!(
                "R {}.{:03} Ω · OCV {}.{} V ({} steps)",
                milliohm / 1000,
                milliohm % 1000,
                decivolts / 10,
                decivolts % 10,
                battery.load_steps
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::health::{Axis, Geometry, StepResponse};

    fn step(dead_time_ms: Option<f64>) -> StepResponse {
        StepResponse {
            axis: Axis::Linear,
            at_us: 0,
            from: 0.0,
            to: 0.3,
            dead_time_ms,
            rise_time_ms: None,
            overshoot_percent: None,
        }
    }

    fn report(steps: Vec<StepResponse>, battery: BatteryEstimate) -> Report {
        Report {
            steps,
            braking: Vec::new(),
            symmetry: None,
            geometry: Geometry::default(),
            command_timeout: None,
            battery,
            steps_not_listed: 0,
            braking_not_listed: 0,
            command_frames: 0,
        }
    }

    #[test]
    fn nothing_is_shown_before_it_is_measured() {
        let view =
            HealthView::of(&report(Vec::new(), BatteryEstimate::NotMeasurable("no current frames".into())));
        assert_eq!(view, HealthView::default());
        assert_eq!((view.dead_time_text(), view.battery_text()), (None, None));
    }

    #[test]
    fn the_latest_step_with_a_dead_time_and_a_measured_battery_are_shown() {
        let battery = BatteryEstimate::Measured {
            internal_resistance_ohm: 0.12,
            spread_ohm: 0.01,
            open_circuit_voltage_v: 25.94,
            load_steps: 9,
        };
        let view = HealthView::of(&report(vec![step(Some(40.0)), step(Some(62.4)), step(None)], battery));
        assert_eq!(view.dead_time_text().as_deref(), Some("dead time 62 ms"));
        assert_eq!(view.battery_text().as_deref(), Some("R 0.120 Ω · OCV 25.9 V (9 steps)"));
    }
}
