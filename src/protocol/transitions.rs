//! What changed from one status frame to the next: control mode, vehicle state (E-stop), and each fault or
//! driver-state bit set or cleared. Pure; `decode --summary` and the MCAP event channel read the same
//! tracker, so a change is detected one way.

use super::faults::{FlagInfo, FlagTable, Flags};
use super::message::{Decoded, Message, Wire};

/// A value that changed: `previous` is `None` at the first frame that carries it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Change<T> {
    pub previous: Option<T>,
    pub current: T,
}

/// One change found in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transition {
    /// The control-mode code, with the wire that names it.
    ControlMode(Change<(u8, Wire)>),
    /// The vehicle-state byte (1 is E-stop).
    VehicleState(Change<u8>),
    /// A fault or status bit went from clear (or unknown, at the first frame) to set. `motor`: `None` for the
    /// system state, the motor number for a driver-state byte.
    BitSet { motor: Option<u8>, info: FlagInfo },
    /// A bit set in the previous frame is clear now.
    BitCleared { motor: Option<u8>, info: FlagInfo },
}

/// The last status seen, to compare the next frame with.
#[derive(Clone, Debug)]
pub struct StatusTracker {
    mode: Option<(u8, Wire)>,
    vehicle: Option<u8>,
    system_bits: u16,
    /// The driver-state byte per motor number.
    driver_bits: [u8; 256],
}

impl Default for StatusTracker {
    fn default() -> Self {
        Self { mode: None, vehicle: None, system_bits: 0, driver_bits: [0; 256] }
    }
}

impl StatusTracker {
    /// The control mode changed (compared by code), or was seen for the first time.
    pub fn control_mode(&mut self, code: u8, wire: Wire) -> Option<Change<(u8, Wire)>> {
        let previous = self.mode.replace((code, wire));
        (previous.map(|(previous, _)| previous) != Some(code))
            .then_some(Change { previous, current: (code, wire) })
    }

    /// The vehicle state changed, or was seen for the first time.
    pub fn vehicle_state(&mut self, state: u8) -> Option<Change<u8>> {
        let previous = self.vehicle.replace(state);
        (previous != Some(state)).then_some(Change { previous, current: state })
    }

    /// Every change `decoded` brings, in a fixed order: mode, vehicle state, bits set, bits cleared.
    pub fn observe(&mut self, decoded: &Decoded, mut visit: impl FnMut(Transition)) {
        match decoded.message {
            Message::SystemState(state) => {
                if let Some(change) = self.control_mode(state.control_mode, decoded.wire) {
                    visit(Transition::ControlMode(change));
                }
                if let Some(change) = self.vehicle_state(state.vehicle_state) {
                    visit(Transition::VehicleState(change));
                }
                let flags = state.faults(decoded.wire);
                let previous = std::mem::replace(&mut self.system_bits, flags.bits);
                bit_changes(flags.table, previous, flags.bits, None, &mut visit);
            }
            Message::MotorLowSpeed(motor) => {
                let slot = &mut self.driver_bits[usize::from(motor.motor)];
                let previous = std::mem::replace(slot, motor.driver_state);
                let bits = u16::from(motor.driver_state);
                bit_changes(FlagTable::DriverState, previous.into(), bits, Some(motor.motor), &mut visit);
            }
            _ => {}
        }
    }
}

fn bit_changes(
    table: FlagTable,
    previous: u16,
    bits: u16,
    motor: Option<u8>,
    visit: &mut impl FnMut(Transition),
) {
    if previous == bits {
        return;
    }
    for info in Flags::new(table, bits & !previous).iter() {
        visit(Transition::BitSet { motor, info });
    }
    for info in Flags::new(table, previous & !bits).iter() {
        visit(Transition::BitCleared { motor, info });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::message::{MotorLowSpeed, SystemState};

    fn system(vehicle_state: u8, control_mode: u8, fault_code: u16) -> Decoded {
        let state = SystemState { vehicle_state, control_mode, fault_code, ..SystemState::default() };
        Decoded { wire: Wire::CanV2, message: Message::SystemState(state) }
    }

    fn changes(tracker: &mut StatusTracker, decoded: &Decoded) -> Vec<Transition> {
        let mut seen = Vec::new();
        tracker.observe(decoded, |transition| seen.push(transition));
        seen
    }

    #[test]
    fn the_first_status_is_a_change_and_a_repeat_is_none() {
        let mut tracker = StatusTracker::default();
        let first = changes(&mut tracker, &system(0, 1, 0));
        assert_eq!(first.len(), 2, "{first:?}");
        assert_eq!(first[0], Transition::ControlMode(Change { previous: None, current: (1, Wire::CanV2) }));
        assert_eq!(first[1], Transition::VehicleState(Change { previous: None, current: 0 }));
        assert!(changes(&mut tracker, &system(0, 1, 0)).is_empty());
    }

    #[test]
    fn a_fault_bit_is_set_once_then_cleared_once() {
        let mut tracker = StatusTracker::default();
        changes(&mut tracker, &system(0, 1, 0));
        let set = changes(&mut tracker, &system(1, 1, 0x0002));
        assert_eq!(set.len(), 2, "{set:?}");
        assert_eq!(set[0], Transition::VehicleState(Change { previous: Some(0), current: 1 }));
        let Transition::BitSet { motor: None, info } = set[1] else { panic!("{set:?}") };
        assert_eq!(info, FlagTable::SystemV2.info(1));
        assert!(changes(&mut tracker, &system(1, 1, 0x0002)).is_empty());
        let cleared = changes(&mut tracker, &system(1, 1, 0));
        assert_eq!(cleared, [Transition::BitCleared { motor: None, info: FlagTable::SystemV2.info(1) }]);
    }

    #[test]
    fn driver_bits_are_tracked_per_motor() {
        let mut tracker = StatusTracker::default();
        let motor = |motor, driver_state| Decoded {
            wire: Wire::CanV2,
            message: Message::MotorLowSpeed(MotorLowSpeed {
                motor,
                driver_state,
                ..MotorLowSpeed::default()
            }),
        };
        assert_eq!(changes(&mut tracker, &motor(1, 0x01)).len(), 1);
        assert!(changes(&mut tracker, &motor(2, 0)).is_empty());
        let cleared = changes(&mut tracker, &motor(1, 0));
        assert_eq!(
            cleared,
            [Transition::BitCleared { motor: Some(1), info: FlagTable::DriverState.info(0) }]
        );
    }
}
