//! Named fault and status bits with a severity and a one-line action for the technician.
//!
//! The raw value always stays available to callers; these tables only give it words. Bits a manual leaves
//! undefined are still reported (as `reserved_byteN_bitM`), never dropped.

use std::fmt;

/// How serious a set bit is. The one order every consumer reads (`Ord`, worst last): Info < Warning < Unknown
/// < Fault < Protection. A bit no document defines is worth a look but is not known to stop the robot, so it
/// sits above a warning and below a fault: the dashboard lists it after faults, doctor warns, and it does not
/// make the robot undrivable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    /// A state worth knowing, not a problem (e.g. a motor driver disabled in standby).
    Info,
    /// Clears by itself when the condition goes away.
    Warning,
    /// A bit no document defines.
    Unknown,
    /// The robot will not move, or stops, while the bit is set.
    Fault,
    /// Latched protection: stays set until the host clears it (V1/RS232: the fault-clear code carried in the
    /// motion command, codes 7 and 8).
    Protection,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Fault => "fault",
            Severity::Protection => "protection",
            Severity::Unknown => "unknown",
        }
    }

    /// The robot will not move while a bit of this severity is set (a fault, or a latched protection).
    pub fn blocks_driving(self) -> bool {
        self >= Severity::Fault
    }

    /// Anything above a plain state: worth showing as a problem (warning, unknown bit, fault, protection).
    pub fn is_problem(self) -> bool {
        self > Severity::Info
    }
}

impl fmt::Display for Severity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One named bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FlagInfo {
    /// Bit mask within the field (a u16 `fault_code` = byte4 << 8 | byte5, or the u8 driver state).
    pub mask: u16,
    /// Stable snake_case name, used in JSON, CSV and text output.
    pub name: &'static str,
    pub severity: Severity,
    /// What the bit means, in words.
    pub meaning: &'static str,
    /// What the technician should do.
    pub action: &'static str,
}

/// Which document defines the bits of a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FlagTable {
    /// System-state fault bytes of TRACER CAN protocol V2 (0x211, and 0x151 read as V2).
    SystemV2,
    /// System-state fault bytes of CAN protocol V1 (0x151 with checksum) and RS232 system status.
    SystemV1Serial,
    /// Motor-driver state byte of 0x261/0x262.
    DriverState,
}

const fn flag(
    mask: u16,
    name: &'static str,
    severity: Severity,
    meaning: &'static str,
    action: &'static str,
) -> FlagInfo {
    FlagInfo { mask, name, severity, meaning, action }
}

/// TRACER V2 manual, table 3.2 (0x211 byte 4). Byte 4 is the high byte of `fault_code`.
pub static SYSTEM_V2: &[FlagInfo] = &[
    flag(
        0x0100,
        "battery_undervoltage_fault",
        Severity::Fault,
        "battery below the 22 V protection voltage",
        "charge or replace the battery; motion is cut below 21.5 V",
    ),
    flag(
        0x0200,
        "battery_undervoltage_warning",
        Severity::Warning,
        "battery below the 22.5 V alarm voltage",
        "finish the task and charge soon",
    ),
    flag(
        0x0400,
        "rc_disconnected",
        Severity::Fault,
        "RC transmitter disconnection protection",
        "switch the RC transmitter on (or fully off) and check its range; if the bit stays set, clear it (tracerctl clear-errors)",
    ),
];

/// CAN V1 (0x151) and RS232 system status, "Description of Failure Information" in the manual.
pub static SYSTEM_V1_SERIAL: &[FlagInfo] = &[
    flag(
        0x0100,
        "can_checksum_error",
        Severity::Warning,
        "a CAN control command arrived with a bad checksum",
        "check the host's V1 checksum and the bus wiring/termination",
    ),
    flag(
        0x0200,
        "driver_overheat_warning",
        Severity::Warning,
        "motor driver above 55 C",
        "reduce speed and let the drivers cool",
    ),
    flag(
        0x0400,
        "motor_overcurrent_warning",
        Severity::Warning,
        "motor current above 15 A RMS",
        "reduce speed or payload",
    ),
    flag(
        0x0800,
        "battery_undervoltage_warning",
        Severity::Warning,
        "battery below the 22.5 V alarm voltage",
        "finish the task and charge soon",
    ),
    flag(
        0x0001,
        "battery_undervoltage_fault",
        Severity::Fault,
        "battery below the 22 V protection voltage",
        "charge or replace the battery",
    ),
    flag(
        0x0002,
        "battery_overvoltage_fault",
        Severity::Fault,
        "battery over-voltage",
        "disconnect the charger; check the battery and charger",
    ),
    flag(
        0x0004,
        "motor1_comm_fault",
        Severity::Fault,
        "no communication with motor driver 1",
        "check motor 1's driver cable and power; then send fault-clear code 3 (motor 1 communication)",
    ),
    flag(
        0x0008,
        "motor2_comm_fault",
        Severity::Fault,
        "no communication with motor driver 2",
        "check motor 2's driver cable and power; then send fault-clear code 4 (motor 2 communication)",
    ),
    flag(
        0x0010,
        "motor3_comm_fault",
        Severity::Fault,
        "no communication with motor driver 3 (not fitted on TRACER)",
        "unexpected on TRACER: check the firmware model",
    ),
    flag(
        0x0020,
        "motor4_comm_fault",
        Severity::Fault,
        "no communication with motor driver 4 (not fitted on TRACER)",
        "unexpected on TRACER: check the firmware model",
    ),
    flag(
        0x0040,
        "driver_overheat_protection",
        Severity::Protection,
        "motor driver above 65 C: output limited, motion commands ignored",
        "stop, let the drivers cool, then send fault-clear code 7 (driver over-temperature)",
    ),
    flag(
        0x0080,
        "motor_overcurrent_protection",
        Severity::Protection,
        "motor current above 20 A RMS: motion commands ignored",
        "check for a jammed wheel or overload, then send fault-clear code 8 (over-current)",
    ),
];

/// 0x261/0x262 byte 5. The TRACER manual defines only bit 4; the others follow AgileX's SDK masks
/// and the Scout/Hunter V2 manuals, which share the frame.
pub static DRIVER_STATE: &[FlagInfo] = &[
    flag(
        0x01,
        "input_voltage_low",
        Severity::Warning,
        "driver supply voltage low (SDK layout)",
        "check the battery voltage and the driver's power wiring",
    ),
    flag(
        0x02,
        "motor_overheat",
        Severity::Warning,
        "motor over-temperature (SDK layout)",
        "reduce speed and let the motor cool",
    ),
    flag(
        0x04,
        "driver_overcurrent",
        Severity::Warning,
        "driver over-current (SDK layout)",
        "reduce speed or payload; check for a jammed wheel",
    ),
    flag(
        0x08,
        "driver_overheat",
        Severity::Warning,
        "driver over-temperature (SDK layout)",
        "reduce speed and let the driver cool",
    ),
    flag(
        0x10,
        "can_disconnected",
        Severity::Fault,
        "driver lost CAN communication with the controller (TRACER manual)",
        "check the internal CAN wiring to this driver and power-cycle; if the bit stays set, clear it (tracerctl clear-errors motor1 or motor2)",
    ),
    flag(
        0x20,
        "driver_fault",
        Severity::Fault,
        "driver error (SDK layout)",
        "clear it (tracerctl clear-errors motor1 or motor2); power-cycle if it returns",
    ),
    flag(
        0x40,
        "driver_disabled",
        Severity::Info,
        "driver not enabled (SDK layout; normal in standby)",
        "switch to command mode before driving (tracerctl mode can; drive and the dashboard do it themselves)",
    ),
    flag(0x80, "driver_reset", Severity::Info, "driver reset (SDK layout)", "none; report it if it repeats"),
];

/// Names for bits no table defines, so unknown bits are reported rather than lost.
static RESERVED_NAMES: [&str; 16] = [
    "reserved_byte5_bit0",
    "reserved_byte5_bit1",
    "reserved_byte5_bit2",
    "reserved_byte5_bit3",
    "reserved_byte5_bit4",
    "reserved_byte5_bit5",
    "reserved_byte5_bit6",
    "reserved_byte5_bit7",
    "reserved_byte4_bit0",
    "reserved_byte4_bit1",
    "reserved_byte4_bit2",
    "reserved_byte4_bit3",
    "reserved_byte4_bit4",
    "reserved_byte4_bit5",
    "reserved_byte4_bit6",
    "reserved_byte4_bit7",
];
static RESERVED_DRIVER_NAMES: [&str; 8] = [
    "reserved_bit0",
    "reserved_bit1",
    "reserved_bit2",
    "reserved_bit3",
    "reserved_bit4",
    "reserved_bit5",
    "reserved_bit6",
    "reserved_bit7",
];

impl FlagTable {
    pub fn entries(self) -> &'static [FlagInfo] {
        match self {
            FlagTable::SystemV2 => SYSTEM_V2,
            FlagTable::SystemV1Serial => SYSTEM_V1_SERIAL,
            FlagTable::DriverState => DRIVER_STATE,
        }
    }

    /// Number of bits in the field.
    pub fn width(self) -> u32 {
        match self {
            FlagTable::DriverState => 8,
            _ => 16,
        }
    }

    /// Everything known about one bit (bit 0 = least significant), defined or not.
    pub fn info(self, bit: u32) -> FlagInfo {
        let mask = 1u16 << bit;
        if let Some(info) = self.entries().iter().find(|info| info.mask == mask) {
            return *info;
        }
        let name = match self {
            FlagTable::DriverState => RESERVED_DRIVER_NAMES[bit as usize & 7],
            _ => RESERVED_NAMES[bit as usize & 15],
        };
        flag(
            mask,
            name,
            Severity::Unknown,
            "bit not defined by the TRACER documentation",
            "note the raw value and report it with the firmware version",
        )
    }
}

/// A set of bits read from a frame, with the table that names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Flags {
    pub table: FlagTable,
    pub bits: u16,
}

impl Flags {
    pub fn new(table: FlagTable, bits: u16) -> Self {
        Self { table, bits }
    }

    pub fn is_empty(&self) -> bool {
        self.bits == 0
    }

    /// Every set bit, least significant first, named (unknown bits as `reserved_*`).
    pub fn iter(&self) -> impl Iterator<Item = FlagInfo> + '_ {
        let table = self.table;
        let bits = self.bits;
        (0..table.width()).filter(move |bit| bits & (1 << bit) != 0).map(move |bit| table.info(bit))
    }

    /// The most serious severity among the set bits.
    pub fn worst(&self) -> Option<Severity> {
        self.iter().map(|info| info.severity).max()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn v2_battery_bits_live_in_byte4() {
        let flags = Flags::new(FlagTable::SystemV2, 0x0300);
        let names: Vec<_> = flags.iter().map(|f| f.name).collect();
        assert_eq!(names, ["battery_undervoltage_fault", "battery_undervoltage_warning"]);
        assert_eq!(flags.worst(), Some(Severity::Fault));
    }

    #[test]
    fn undefined_bits_are_named_not_dropped() {
        // A real Bunker Mini in E-stop reported fault bytes 00 80.
        let flags = Flags::new(FlagTable::SystemV2, 0x0080);
        let only = flags.iter().collect::<Vec<_>>();
        assert_eq!(only.len(), 1);
        assert_eq!(only[0].name, "reserved_byte5_bit7");
        assert_eq!(only[0].severity, Severity::Unknown);
    }

    #[test]
    fn one_order_worst_last() {
        use Severity::*;
        let mut all = [Protection, Unknown, Info, Fault, Warning];
        all.sort();
        assert_eq!(all, [Info, Warning, Unknown, Fault, Protection]);
        let blocking: Vec<_> = all.iter().filter(|s| s.blocks_driving()).collect();
        assert_eq!(blocking, [&Fault, &Protection]);
        let problems: Vec<_> = all.iter().filter(|s| s.is_problem()).collect();
        assert_eq!(problems, [&Warning, &Unknown, &Fault, &Protection]);
    }

    #[test]
    fn an_unknown_bit_is_worse_than_a_warning_not_than_a_fault() {
        // Warning (0x0200) + undefined byte 5 bit 7 (0x0080): the unknown bit is the worst.
        assert_eq!(Flags::new(FlagTable::SystemV2, 0x0280).worst(), Some(Severity::Unknown));
        // Fault (0x0100) + the undefined bit: the fault is the worst (it used to be the unknown bit).
        assert_eq!(Flags::new(FlagTable::SystemV2, 0x0180).worst(), Some(Severity::Fault));
    }

    #[test]
    fn v1_protections_are_latched() {
        let flags = Flags::new(FlagTable::SystemV1Serial, 0x00C0);
        assert!(flags.iter().all(|f| f.severity == Severity::Protection));
    }

    #[test]
    fn every_table_entry_is_a_single_distinct_bit() {
        for table in [FlagTable::SystemV2, FlagTable::SystemV1Serial, FlagTable::DriverState] {
            let mut seen = 0u16;
            for info in table.entries() {
                assert_eq!(info.mask.count_ones(), 1, "{}", info.name);
                assert_eq!(seen & info.mask, 0, "{} duplicated", info.name);
                assert!(info.mask.trailing_zeros() < table.width());
                seen |= info.mask;
            }
        }
    }
}
