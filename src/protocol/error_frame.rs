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

#[cfg(test)]
mod tests {
    use super::*;

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
