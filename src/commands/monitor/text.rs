//! The monitor's words: durations as people read them, CAN error frames in plain English. Pure.

use std::time::Duration;

use crate::protocol::error_frame::ErrorFrame;

/// `bus off; controller: rx passive, tx passive; tx errors 128, rx errors 0`
pub(super) fn describe_error_frame(error: &ErrorFrame) -> String {
    let words = |names: &mut dyn Iterator<Item = &'static str>| {
        names.map(|name| name.replace('_', " ")).collect::<Vec<_>>().join(", ")
    };
    let mut text = words(&mut error.class_names());
    if text.is_empty() {
        text.push_str("no error class set");
    }
    if error.controller != 0 {
        text.push_str("; controller: ");
        text.push_str(&words(&mut error.controller_names()));
    }
    if let Some((tx, rx)) = error.counters {
        text.push_str(&format!("; tx errors {tx}, rx errors {rx}"));
    }
    if error.is_bus_off() {
        text.push_str(" (the controller has stopped: check wiring, termination and bitrate)");
    }
    text
}

/// `100 ms`, `1.25 s`
pub(super) fn human(duration: Duration) -> String {
    if duration < Duration::from_secs(1) {
        format!("{} ms", duration.as_millis())
    } else {
        format!("{:.2} s", duration.as_secs_f64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_below_a_second_in_milliseconds_above_in_seconds() {
        assert_eq!(human(Duration::from_millis(999)), "999 ms");
        assert_eq!(human(Duration::from_millis(1250)), "1.25 s");
    }
}
