//! Every identifier the tool knows, on every wire (CAN V2, CAN V1, RS232), in one table: what it carries,
//! which way it goes, how often the robot sends it, the short label the dashboard shows, and where the
//! protocol notes (docs/protocol.md, the TRACER user manual v2.0.0) describe it. Protocol detection, monitor's
//! staleness check and the dashboard's link panel read it; `catalog_tests.rs` checks every row against the
//! codec. Adding a message: see "How to add a message" in docs/architecture.md.

use std::time::Duration;

use super::id::{
    FrameId, CMD_LIGHT_CONTROL, CMD_LIGHT_STATUS, CMD_MOTION_CONTROL, CMD_MOTION_STATUS, CMD_MOTOR1_DRIVER,
    CMD_MOTOR2_DRIVER, CMD_SYSTEM_STATUS, ID_CONTROL_MODE, ID_FAULT_CLEAR, ID_LIGHT_COMMAND, ID_LIGHT_STATE,
    ID_MOTION_COMMAND, ID_MOTION_STATE, ID_MOTOR1_HIGH_SPEED, ID_MOTOR1_LOW_SPEED, ID_MOTOR2_HIGH_SPEED,
    ID_MOTOR2_LOW_SPEED, ID_ODOMETRY, ID_RC_STATE, ID_SYSTEM_STATE, ID_SYSTEM_STATE_MANUAL,
    ID_V1_LIGHT_COMMAND, ID_V1_LIGHT_STATE, ID_V1_MOTION_COMMAND, ID_V1_MOTION_STATE, ID_V1_MOTOR1,
    ID_V1_MOTOR2, ID_V1_SYSTEM_STATE, ID_VERSION_REQUEST, ID_VERSION_RESPONSE, TYPE_CONTROL, TYPE_FEEDBACK,
};
use super::message::{MessageKind, Wire};

/// Which way a frame goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Commands and requests a host sends.
    ToRobot,
    /// Feedback and replies the robot sends.
    FromRobot,
}

/// One identifier on one wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    pub id: FrameId,
    pub wire: Wire,
    /// What the codec decodes it to (its `Message::name`).
    pub kind: MessageKind,
    pub direction: Direction,
    /// How often the robot sends it; `None` for commands, replies and feedback with no documented period.
    pub period: Option<Duration>,
    /// A short label for the dashboard's link panel.
    pub label: &'static str,
    /// Where it is described: the manual's table or section, and docs/protocol.md's section.
    pub source: &'static str,
}

impl Entry {
    /// The decoded message's name (`system_state`), as monitor and JSON print it.
    pub fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// How long the identifier may be silent before it is stale: [`STALE_PERIODS`] periods.
    pub fn stale_after(&self) -> Option<Duration> {
        self.period.map(|period| period * STALE_PERIODS)
    }
}

/// A periodic frame is stale after this many periods without it (monitor's warnings, the dashboard).
pub const STALE_PERIODS: u32 = 5;

const fn command(
    id: FrameId,
    wire: Wire,
    kind: MessageKind,
    label: &'static str,
    source: &'static str,
) -> Entry {
    Entry { id, wire, kind, direction: Direction::ToRobot, period: None, label, source }
}

const fn periodic(
    id: FrameId,
    wire: Wire,
    kind: MessageKind,
    period_ms: u64,
    label: &'static str,
    source: &'static str,
) -> Entry {
    let period = Some(Duration::from_millis(period_ms));
    Entry { id, wire, kind, direction: Direction::FromRobot, period, label, source }
}

/// Robot frames with no period: replies, and feedback whose period (or presence) is not documented.
const fn aperiodic(
    id: FrameId,
    wire: Wire,
    kind: MessageKind,
    label: &'static str,
    source: &'static str,
) -> Entry {
    Entry { id, wire, kind, direction: Direction::FromRobot, period: None, label, source }
}

use MessageKind as K;
use Wire::{CanV1 as V1, CanV2 as V2, Serial};

const SYSTEM_STATE_MANUAL: &str =
    "manual Table 3.1 prints 0x151 for V2 system state; firmware sends 0x211 (protocol.md 2.6)";

/// Every identifier the tool knows. V1's period is not documented: the slower 100 ms, so nothing is called
/// stale early. CAN and RS232 identifiers do not overlap (RS232 ones are above 0x7FF). 0x151 is on two rows:
/// V1's system state (periodic), and the V2 manual's name for 0x211 (no period of its own).
pub const CATALOG: &[Entry] = &[
    // CAN V2 (manual 3.3.1; 0x261/0x262 every 100 ms).
    command(
        FrameId::standard(ID_MOTION_COMMAND),
        V2,
        K::MotionCommand,
        "motion cmd",
        "manual Table 3.4; protocol.md 2.2",
    ),
    command(
        FrameId::standard(ID_LIGHT_COMMAND),
        V2,
        K::LightCommand,
        "light cmd",
        "manual Table 3.5; protocol.md 2.3",
    ),
    command(
        FrameId::standard(ID_CONTROL_MODE),
        V2,
        K::ControlModeCommand,
        "mode cmd",
        "manual Table 3.7; protocol.md 2.4",
    ),
    command(
        FrameId::standard(ID_FAULT_CLEAR),
        V2,
        K::FaultClear,
        "clear cmd",
        "manual Table 3.8; protocol.md 2.5",
    ),
    command(
        FrameId::standard(ID_VERSION_REQUEST),
        V2,
        K::VersionRequest,
        "version req",
        "Scout V2 manual; protocol.md 2.12",
    ),
    periodic(
        FrameId::standard(ID_SYSTEM_STATE),
        V2,
        K::SystemState,
        20,
        "system",
        "CN manual Table 3.1; protocol.md 2.6",
    ),
    periodic(
        FrameId::standard(ID_MOTION_STATE),
        V2,
        K::MotionState,
        20,
        "motion",
        "manual Table 3.3; protocol.md 2.7",
    ),
    periodic(
        FrameId::standard(ID_LIGHT_STATE),
        V2,
        K::LightState,
        20,
        "lights",
        "manual Table 3.6; protocol.md 2.3",
    ),
    periodic(
        FrameId::standard(ID_MOTOR1_HIGH_SPEED),
        V2,
        K::MotorHighSpeed,
        20,
        "motor 1",
        "manual Table 3.10; protocol.md 2.9",
    ),
    periodic(
        FrameId::standard(ID_MOTOR2_HIGH_SPEED),
        V2,
        K::MotorHighSpeed,
        20,
        "motor 2",
        "manual Table 3.10; protocol.md 2.9",
    ),
    periodic(
        FrameId::standard(ID_ODOMETRY),
        V2,
        K::Odometry,
        20,
        "odometry",
        "manual Table 3.9; protocol.md 2.11",
    ),
    periodic(
        FrameId::standard(ID_MOTOR1_LOW_SPEED),
        V2,
        K::MotorLowSpeed,
        100,
        "driver 1",
        "manual Table 3.11; protocol.md 2.10",
    ),
    periodic(
        FrameId::standard(ID_MOTOR2_LOW_SPEED),
        V2,
        K::MotorLowSpeed,
        100,
        "driver 2",
        "manual Table 3.11; protocol.md 2.10",
    ),
    aperiodic(
        FrameId::standard(ID_RC_STATE),
        V2,
        K::RcState,
        "rc",
        "AgileX SDK only, not in the manuals; protocol.md 2.8",
    ),
    aperiodic(
        FrameId::standard(ID_VERSION_RESPONSE),
        V2,
        K::VersionResponse,
        "version",
        "Scout V2 manual; protocol.md 2.12",
    ),
    aperiodic(FrameId::standard(ID_SYSTEM_STATE_MANUAL), V2, K::SystemState, "system", SYSTEM_STATE_MANUAL),
    // CAN V1 (Chinese manual v1.1; protocol.md 3.2).
    command(
        FrameId::standard(ID_V1_MOTION_COMMAND),
        V1,
        K::MotionCommand,
        "V1 motion cmd",
        "CN manual v1.1; protocol.md 3.2",
    ),
    command(
        FrameId::standard(ID_V1_LIGHT_COMMAND),
        V1,
        K::LightCommand,
        "V1 light cmd",
        "CN manual v1.1; protocol.md 3.2",
    ),
    periodic(
        FrameId::standard(ID_V1_MOTION_STATE),
        V1,
        K::MotionState,
        100,
        "V1 motion",
        "CN manual v1.1; protocol.md 3.2",
    ),
    periodic(
        FrameId::standard(ID_V1_LIGHT_STATE),
        V1,
        K::LightState,
        100,
        "V1 lights",
        "CN manual v1.1; protocol.md 3.2",
    ),
    periodic(
        FrameId::standard(ID_V1_SYSTEM_STATE),
        V1,
        K::SystemState,
        100,
        "system",
        "CN manual v1.1; protocol.md 3.2",
    ),
    periodic(
        FrameId::standard(ID_V1_MOTOR1),
        V1,
        K::MotorHighSpeed,
        100,
        "V1 motor 1",
        "CN manual v1.1; protocol.md 3.2",
    ),
    periodic(
        FrameId::standard(ID_V1_MOTOR2),
        V1,
        K::MotorHighSpeed,
        100,
        "V1 motor 2",
        "CN manual v1.1; protocol.md 3.2",
    ),
    // RS232 (manual 3.4.2; protocol.md 4.2): type << 8 | command.
    command(FrameId::serial(TYPE_CONTROL, CMD_MOTION_CONTROL), Serial, K::MotionCommand, "motion cmd", RS232),
    command(FrameId::serial(TYPE_CONTROL, CMD_LIGHT_CONTROL), Serial, K::LightCommand, "light cmd", RS232),
    periodic(FrameId::serial(TYPE_FEEDBACK, CMD_SYSTEM_STATUS), Serial, K::SystemState, 20, "system", RS232),
    periodic(FrameId::serial(TYPE_FEEDBACK, CMD_MOTION_STATUS), Serial, K::MotionState, 20, "motion", RS232),
    periodic(
        FrameId::serial(TYPE_FEEDBACK, CMD_MOTOR1_DRIVER),
        Serial,
        K::MotorHighSpeed,
        20,
        "motor 1",
        RS232,
    ),
    periodic(
        FrameId::serial(TYPE_FEEDBACK, CMD_MOTOR2_DRIVER),
        Serial,
        K::MotorHighSpeed,
        20,
        "motor 2",
        RS232,
    ),
    periodic(FrameId::serial(TYPE_FEEDBACK, CMD_LIGHT_STATUS), Serial, K::LightState, 20, "lights", RS232),
];

const RS232: &str = "manual 3.4.2; protocol.md 4.2";

const PERIODIC_COUNT: usize = {
    let (mut count, mut at) = (0, 0);
    while at < CATALOG.len() {
        count += CATALOG[at].period.is_some() as usize;
        at += 1;
    }
    count
};

/// The catalog's periodic robot frames, in catalog order: what monitor watches for staleness.
pub static PERIODIC: [Entry; PERIODIC_COUNT] = {
    let mut periodic = [CATALOG[0]; PERIODIC_COUNT];
    let (mut count, mut at) = (0, 0);
    while at < CATALOG.len() {
        if CATALOG[at].period.is_some() {
            periodic[count] = CATALOG[at];
            count += 1;
        }
        at += 1;
    }
    periodic
};

/// The periodic frame with this identifier, if it is one.
pub fn periodic_frame(id: FrameId) -> Option<&'static Entry> {
    PERIODIC.iter().find(|entry| entry.id == id)
}

/// The dashboard's label for an identifier the catalog knows.
pub fn label(id: FrameId) -> Option<&'static str> {
    CATALOG.iter().find(|entry| entry.id == id).map(|entry| entry.label)
}

/// The entry for this identifier on this wire.
pub fn entry(id: FrameId, wire: Wire) -> Option<&'static Entry> {
    CATALOG.iter().find(|entry| entry.id == id && entry.wire == wire)
}

/// The identifier that carries this kind of message on this wire (the first row: 0x211 before the manual's
/// 0x151 on V2), printed the one way: `0x231`, `0xAA07`. For messages to read in words ("0x231 shows ...").
pub fn identifier_of(kind: MessageKind, wire: Wire) -> Option<FrameId> {
    CATALOG.iter().find(|entry| entry.kind == kind && entry.wire == wire).map(|entry| entry.id)
}

/// [`identifier_of`] for messages: the identifier (`0x421`, `0xAA01`), or the message's name where `wire`
/// has no such frame.
pub fn identifier_text(kind: MessageKind, wire: Wire) -> String {
    identifier_of(kind, wire).map_or_else(|| kind.name().replace('_', " "), |id| id.to_string())
}

/// Every identifier carrying one of `kinds` on `wire`, in catalog order, for messages: `0x251, 0x252`.
pub fn identifiers_text(kinds: &[MessageKind], wire: Wire) -> String {
    let ids: Vec<String> = CATALOG
        .iter()
        .filter(|entry| entry.wire == wire && kinds.contains(&entry.kind))
        .map(|entry| entry.id.to_string())
        .collect();
    ids.join(", ")
}

/// The commands a host sends to drive or change the robot (not requests such as the version query), on
/// every wire: another node sending one is another controller.
pub fn host_commands() -> impl Iterator<Item = &'static Entry> {
    CATALOG
        .iter()
        .filter(|entry| entry.direction == Direction::ToRobot && entry.kind != MessageKind::VersionRequest)
}

/// A set of standard CAN identifiers, built from the catalog at compile time (so the decoder's checks are
/// one bit test).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StandardIds([u64; 32]);

impl StandardIds {
    pub const fn contains(&self, id: u32) -> bool {
        id < 0x800 && self.0[(id >> 6) as usize] & (1 << (id & 63)) != 0
    }

    /// The identifiers of `wire`'s rows that no row of another wire uses, leaving out the kinds in `except`.
    pub const fn only_on(wire: Wire, except: &[MessageKind]) -> Self {
        let mut bits = [0u64; 32];
        let mut at = 0;
        while at < CATALOG.len() {
            let entry = CATALOG[at];
            if let FrameId::Standard(id) = entry.id {
                if entry.wire as u8 == wire as u8
                    && !kind_in(entry.kind, except)
                    && !on_another_wire(id, wire)
                {
                    bits[(id >> 6) as usize] |= 1 << (id & 63);
                }
            }
            at += 1;
        }
        Self(bits)
    }
}

const fn kind_in(kind: MessageKind, kinds: &[MessageKind]) -> bool {
    let mut at = 0;
    while at < kinds.len() {
        if kinds[at] as u8 == kind as u8 {
            return true;
        }
        at += 1;
    }
    false
}

const fn on_another_wire(id: u16, wire: Wire) -> bool {
    let mut at = 0;
    while at < CATALOG.len() {
        let entry = CATALOG[at];
        if let FrameId::Standard(other) = entry.id {
            if other == id && entry.wire as u8 != wire as u8 {
                return true;
            }
        }
        at += 1;
    }
    false
}

#[cfg(test)]
#[path = "catalog_tests.rs"]
mod tests;
