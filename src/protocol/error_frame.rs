//! SocketCAN error frames in words (linux/can/error.h), so technicians see "bus-off", not 0x40.

use super::frame::{CanFrame, FrameKind};

/// Error classes carried in the identifier of an error frame.
pub static ERROR_CLASSES: &[(u32, &str)] = &[
    (0x001, "tx_timeout"),
    (0x002, "lost_arbitration"),
    (0x004, "controller_problem"),
    (0x008, "protocol_violation"),
    (0x010, "transceiver_problem"),
    (0x020, "no_ack"),
    (0x040, "bus_off"),
    (0x080, "bus_error"),
    (0x100, "controller_restarted"),
    (0x200, "error_counters"),
];

/// Controller status in data byte 1 when the class has `controller_problem`.
pub static CONTROLLER_STATUS: &[(u8, &str)] = &[
    (0x01, "rx_overflow"),
    (0x02, "tx_overflow"),
    (0x04, "rx_warning"),
    (0x08, "tx_warning"),
    (0x10, "rx_passive"),
    (0x20, "tx_passive"),
    (0x40, "back_to_error_active"),
];

const CLASS_CONTROLLER: u32 = 0x004;
const CLASS_COUNTERS: u32 = 0x200;

/// An error frame, decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ErrorFrame {
    pub classes: u32,
    pub controller: u8,
    /// Transmit and receive error counters, when the frame carries them.
    pub counters: Option<(u8, u8)>,
}

impl ErrorFrame {
    /// `None` unless `frame` is an error frame.
    pub fn from_frame(frame: &CanFrame) -> Option<Self> {
        if frame.kind() != FrameKind::Error {
            return None;
        }
        let data = frame.data();
        let byte = |i: usize| data.get(i).copied().unwrap_or(0);
        let classes = frame.id();
        let controller = if classes & CLASS_CONTROLLER != 0 { byte(1) } else { 0 };
        let counters = (classes & (CLASS_COUNTERS | CLASS_CONTROLLER) != 0 && data.len() >= 8)
            .then(|| (byte(6), byte(7)));
        Some(Self { classes, controller, counters })
    }

    /// Names of the error classes set.
    pub fn class_names(&self) -> impl Iterator<Item = &'static str> + '_ {
        ERROR_CLASSES.iter().filter(|(mask, _)| self.classes & mask != 0).map(|(_, name)| *name)
    }

    /// Names of the controller status bits set.
    pub fn controller_names(&self) -> impl Iterator<Item = &'static str> + '_ {
        CONTROLLER_STATUS.iter().filter(|(mask, _)| self.controller & mask != 0).map(|(_, name)| *name)
    }

    pub fn is_bus_off(&self) -> bool {
        self.classes & 0x040 != 0
    }
}

/// Error frames counted by class and by controller status: how a report lists them (never as identifiers).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ErrorTally {
    pub frames: u64,
    pub classes: [u64; 10],
    pub controller: [u64; 7],
    pub bus_off: u64,
}

impl ErrorTally {
    pub fn add(&mut self, error: &ErrorFrame) {
        self.frames += 1;
        for (count, (mask, _)) in self.classes.iter_mut().zip(ERROR_CLASSES) {
            *count += u64::from(error.classes & mask != 0);
        }
        for (count, (mask, _)) in self.controller.iter_mut().zip(CONTROLLER_STATUS) {
            *count += u64::from(error.controller & mask != 0);
        }
        self.bus_off += u64::from(error.is_bus_off());
    }

    /// `controller_problem x153 (rx_overflow x153), error_counters x153`, most frequent first.
    pub fn describe(&self) -> String {
        let mut classes: Vec<(u64, &str)> = self
            .classes
            .iter()
            .zip(ERROR_CLASSES)
            .filter(|(count, _)| **count > 0)
            .map(|(count, (_, name))| (*count, *name))
            .collect();
        classes.sort_by_key(|(count, _)| std::cmp::Reverse(*count));
        let controller: Vec<String> = self
            .controller
            .iter()
            .zip(CONTROLLER_STATUS)
            .filter(|(count, _)| **count > 0)
            .map(|(count, (_, name))| format!("{name} x{count}"))
            .collect();
        let parts: Vec<String> = classes
            .iter()
            .map(|(count, name)| {
                if *name == "controller_problem" && !controller.is_empty() {
                    format!("{name} x{count} ({})", controller.join(", "))
                } else {
                    format!("{name} x{count}")
                }
            })
            .collect();
        if parts.is_empty() {
            "no error class set".to_string()
        } else {
            parts.join(", ")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tally_lists_classes_with_the_controller_status_never_identifiers() {
        let mut tally = ErrorTally::default();
        // What an SJA1000 sends on an RX FIFO overrun: controller problem (rx overflow) with counters.
        let overrun = CanFrame::new_error(0x204, &[0, 0x01, 0, 0, 0, 0, 0, 0]).unwrap();
        for _ in 0..3 {
            tally.add(&ErrorFrame::from_frame(&overrun).unwrap());
        }
        tally.add(&ErrorFrame::from_frame(&CanFrame::new_error(0x40, &[]).unwrap()).unwrap());
        assert_eq!(tally.frames, 4);
        assert_eq!(tally.bus_off, 1);
        assert_eq!(tally.describe(), "controller_problem x3 (rx_overflow x3), error_counters x3, bus_off x1");
        assert!(!tally.describe().contains("0x204"));
    }

    #[test]
    fn controller_problem_with_counters() {
        // From a real `candump -e` capture: tx-error-warning, tx counter 120.
        let frame = CanFrame::new_error(0x4, &[0, 0x08, 0, 0, 0, 0, 120, 0]).unwrap();
        let error = ErrorFrame::from_frame(&frame).unwrap();
        assert_eq!(error.class_names().collect::<Vec<_>>(), ["controller_problem"]);
        assert_eq!(error.controller_names().collect::<Vec<_>>(), ["tx_warning"]);
        assert_eq!(error.counters, Some((120, 0)));
        assert!(!error.is_bus_off());
    }

    #[test]
    fn bus_off_without_data() {
        let frame = CanFrame::new_error(0x40, &[]).unwrap();
        let error = ErrorFrame::from_frame(&frame).unwrap();
        assert!(error.is_bus_off());
        assert_eq!(error.counters, None);
        assert!(ErrorFrame::from_frame(&CanFrame::new(0x40, &[]).unwrap()).is_none());
    }
}
