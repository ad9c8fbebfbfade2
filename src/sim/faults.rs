//! Faults and events the simulator can inject (`--fault NAME[@TIME]`), and the latched protections.

use std::fmt;
use std::str::FromStr;
use std::time::Duration;

/// Something that happens to the robot: a fault, or the operator acting on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FaultKind {
    /// E-stop pressed: vehicle state 1, stopped at once, commands ignored.
    EStop,
    /// E-stop released: normal again, in standby (the host must send 0x421 again).
    EStopRelease,
    /// Motor 1's driver heats to 70 °C: over-temperature protection latches.
    Motor1Overheat,
    Motor2Overheat,
    /// Over-current protection latches on both drivers (a stall).
    Overcurrent,
    Motor1Overcurrent,
    Motor2Overcurrent,
    /// Driver 1 loses its CAN link for a moment: communication fault latches.
    Motor1Comm,
    Motor2Comm,
    /// Battery drops to 22.4 V open-circuit: under-voltage warning.
    BatteryWarning,
    /// Battery drops to 21.9 V: under-voltage fault (the robot beeps but still drives; a load that sags it
    /// to the cut-off for 1 s cuts drive power off).
    BatteryLow,
    /// Battery drops to 21.4 V: cut-off, drive power off.
    BatteryEmpty,
    /// A fresh battery at `battery_start_v`: every battery bit and the cut-off clear.
    BatteryOk,
    /// The RC transmitter's link is lost: RC-disconnected bit, motion stops.
    RcLost,
    /// The RC link is back.
    RcRestore,
    /// SWB to the middle (implies the transmitter is on): RC mode, host motion ignored.
    SwbMiddle,
    /// SWB to the top: command mode allowed again (from standby: the host must send 0x421).
    SwbTop,
    /// Another controller takes the robot's mode: a second host selects its own link's command mode (on a
    /// CAN robot an RS232 host, mode 2; on an RS232 robot a CAN host, 0x421 = 1). Motion from this link
    /// stops, and for [`OTHER_HOST_HOLD`] this link cannot select its mode back.
    OtherHost,
}

/// How long after `other-host` the robot ignores this link's mode selection (CAN 0x421, the RS232 motion
/// frame's mode 2): the other host's commands for that long. Ten 20 ms reports say the other mode, even to
/// a host that selects its mode with every frame, as RS232 does (standby could not show there: RS232 reads
/// mode 0 as RC).
pub const OTHER_HOST_HOLD: Duration = Duration::from_millis(200);

impl FaultKind {
    /// Every fault, in the order help text lists them.
    pub const ALL: [FaultKind; 18] = [
        FaultKind::EStop,
        FaultKind::EStopRelease,
        FaultKind::Motor1Overheat,
        FaultKind::Motor2Overheat,
        FaultKind::Overcurrent,
        FaultKind::Motor1Overcurrent,
        FaultKind::Motor2Overcurrent,
        FaultKind::Motor1Comm,
        FaultKind::Motor2Comm,
        FaultKind::BatteryWarning,
        FaultKind::BatteryLow,
        FaultKind::BatteryEmpty,
        FaultKind::BatteryOk,
        FaultKind::RcLost,
        FaultKind::RcRestore,
        FaultKind::SwbMiddle,
        FaultKind::SwbTop,
        FaultKind::OtherHost,
    ];

    /// The `--fault` name.
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::EStop => "estop",
            FaultKind::EStopRelease => "estop-release",
            FaultKind::Motor1Overheat => "motor1-overheat",
            FaultKind::Motor2Overheat => "motor2-overheat",
            FaultKind::Overcurrent => "overcurrent",
            FaultKind::Motor1Overcurrent => "motor1-overcurrent",
            FaultKind::Motor2Overcurrent => "motor2-overcurrent",
            FaultKind::Motor1Comm => "motor1-comm",
            FaultKind::Motor2Comm => "motor2-comm",
            FaultKind::BatteryWarning => "battery-warning",
            FaultKind::BatteryLow => "battery-low",
            FaultKind::BatteryEmpty => "battery-empty",
            FaultKind::BatteryOk => "battery-ok",
            FaultKind::RcLost => "rc-lost",
            FaultKind::RcRestore => "rc-restore",
            FaultKind::SwbMiddle => "swb-middle",
            FaultKind::SwbTop => "swb-top",
            FaultKind::OtherHost => "other-host",
        }
    }

    /// One line for help text.
    pub fn description(self) -> &'static str {
        match self {
            FaultKind::EStop => "press the E-stop: stops at once, commands ignored",
            FaultKind::EStopRelease => "release the E-stop: standby until command mode again",
            FaultKind::Motor1Overheat => "driver 1 at 70 C: over-temperature protection latches",
            FaultKind::Motor2Overheat => "driver 2 at 70 C: over-temperature protection latches",
            FaultKind::Overcurrent => "over-current protection latches on both drivers",
            FaultKind::Motor1Overcurrent => "over-current protection latches on driver 1",
            FaultKind::Motor2Overcurrent => "over-current protection latches on driver 2",
            FaultKind::Motor1Comm => "driver 1 communication lost: latches until cleared",
            FaultKind::Motor2Comm => "driver 2 communication lost: latches until cleared",
            FaultKind::BatteryWarning => "battery to 22.4 V: under-voltage warning",
            FaultKind::BatteryLow => "battery to 21.9 V: under-voltage; heavy loads cut off",
            FaultKind::BatteryEmpty => "battery to 21.4 V: cut off until battery-ok",
            FaultKind::BatteryOk => "fresh battery at the start voltage",
            FaultKind::RcLost => "RC transmitter link lost: motion stops",
            FaultKind::RcRestore => "RC transmitter link back",
            FaultKind::SwbMiddle => "SWB to the middle: RC mode, host commands ignored",
            FaultKind::SwbTop => "RC switch SWB to the top: command mode allowed",
            FaultKind::OtherHost => "another host takes the mode (CAN vs RS232) for 200 ms",
        }
    }

    /// Every name, comma-separated, for error messages.
    pub fn names() -> String {
        Self::ALL.iter().map(|fault| fault.name()).collect::<Vec<_>>().join(", ")
    }
}

/// The fault language for `sim --help` (and so its man page): every fault with what it does, the
/// `--fault NAME[@TIME]` syntax, and the names typed on standard input at run time.
pub fn fault_help() -> String {
    let width = FaultKind::ALL.iter().map(|fault| fault.name().len()).max().unwrap_or(0);
    let mut text =
        String::from("Faults (--fault NAME[@TIME], or a NAME typed on standard input while it runs):\n");
    for fault in FaultKind::ALL {
        text.push_str(&format!("  {:width$}  {}\n", fault.name(), fault.description()));
    }
    text.push_str(
        "\n\
         TIME counts from the start: 2s, 1.5s, 500ms, 1m 30s or plain seconds (2, 0.25); without\n\
         @TIME the fault is there from the start. Names are case-insensitive; _ may stand for -.\n\
         \n\
         At run time, type one NAME per line on standard input: it acts at once (no @TIME), and\n\
         each line is answered on stderr (`sim: injected estop`, or why it was not understood).\n\
         For example, `estop` then `estop-release`, or `motor1-comm` and clear it with\n\
         `tracerctl --iface vcan0 clear-errors` from another terminal.\n\
         \n\
         The same faults work on the in-process simulator of every command:\n  \
         tracerctl --sim --fault estop@0s doctor\n  \
         tracerctl --sim --fault motor1-comm@1s dashboard\n\
         docs/sim.md says what each fault sets on the wire.",
    );
    text
}

impl fmt::Display for FaultKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why a `--fault` argument was not understood.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FaultParseError {
    #[error("unknown fault {0:?}; known faults: {known}", known = FaultKind::names())]
    UnknownFault(String),
    #[error("bad time {time:?} in {arg:?}: {reason} (use e.g. 2s, 1.5s, 500ms or plain seconds)")]
    BadTime { arg: String, time: String, reason: String },
}

impl FromStr for FaultKind {
    type Err = FaultParseError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let wanted = s.trim().to_ascii_lowercase().replace('_', "-");
        Self::ALL
            .into_iter()
            .find(|fault| fault.name() == wanted)
            .ok_or_else(|| FaultParseError::UnknownFault(s.trim().to_string()))
    }
}

/// A fault to inject at a time since the start of the simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ScheduledFault {
    pub at: Duration,
    pub fault: FaultKind,
}

/// `--fault` syntax: `NAME[@TIME]`; TIME in humantime (`10s`, `1.5s`, `500ms`, `1m 30s`) or plain seconds
/// (`2`, `0.25`); without `@` the fault is there from the start.
impl FromStr for ScheduledFault {
    type Err = FaultParseError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (name, at) = match s.split_once('@') {
            Some((name, time)) => (name, parse_time(s, time)?),
            None => (s, Duration::ZERO),
        };
        Ok(ScheduledFault { at, fault: name.parse()? })
    }
}

fn parse_time(arg: &str, time: &str) -> Result<Duration, FaultParseError> {
    let bad = |reason: String| FaultParseError::BadTime { arg: arg.into(), time: time.into(), reason };
    let time = time.trim();
    if time.is_empty() {
        return Err(bad("nothing after '@'".into()));
    }
    if time.bytes().all(|b| b.is_ascii_digit() || b == b'.') {
        let seconds: f64 = time.parse().map_err(|_| bad("not a number".into()))?;
        return Duration::try_from_secs_f64(seconds).map_err(|e| bad(e.to_string()));
    }
    humantime::parse_duration(time).map_err(|e| bad(e.to_string()))
}

impl fmt::Display for ScheduledFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}@{}", self.fault, humantime::format_duration(self.at))
    }
}

/// Protections of one motor driver that latch until the host clears them (manual footnote [3]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Latches {
    pub overheat: bool,
    pub overcurrent: bool,
    pub comm: bool,
}

impl Latches {
    pub fn any(self) -> bool {
        self.overheat || self.overcurrent || self.comm
    }
}

/// What a fault-clear request asks for, from either link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct ClearRequest {
    /// Motor 1, motor 2.
    pub motors: [bool; 2],
    pub overheat: bool,
    pub overcurrent: bool,
    pub comm: bool,
}

impl ClearRequest {
    const ALL_KINDS: Self = Self { motors: [true; 2], overheat: true, overcurrent: true, comm: true };

    /// CAN 0x441: 0 everything, 1 motor 1, 2 motor 2; other codes clear nothing.
    pub fn from_can(code: u8) -> Option<Self> {
        match code {
            0 => Some(Self::ALL_KINDS),
            1 => Some(Self { motors: [true, false], ..Self::ALL_KINDS }),
            2 => Some(Self { motors: [false, true], ..Self::ALL_KINDS }),
            _ => None,
        }
    }

    /// RS232 / V1 fault-clear codes: 3/4 motor 1/2 communication, 7 driver over-temperature, 8 over-current.
    /// Codes 1 and 2 (battery) have nothing latched to clear; 0 means none; 5, 6 are motors TRACER lacks.
    pub fn from_serial(code: u8) -> Option<Self> {
        let none = Self { motors: [true; 2], overheat: false, overcurrent: false, comm: false };
        match code {
            3 => Some(Self { motors: [true, false], comm: true, ..none }),
            4 => Some(Self { motors: [false, true], comm: true, ..none }),
            7 => Some(Self { overheat: true, ..none }),
            8 => Some(Self { overcurrent: true, ..none }),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_are_unique() {
        for fault in FaultKind::ALL {
            assert_eq!(fault.name().parse::<FaultKind>(), Ok(fault));
            assert_eq!(FaultKind::ALL.iter().filter(|f| f.name() == fault.name()).count(), 1);
        }
        assert_eq!("Motor1_Overheat".parse::<FaultKind>(), Ok(FaultKind::Motor1Overheat));
    }

    #[test]
    fn schedule_syntax() {
        let parse = |s: &str| s.parse::<ScheduledFault>();
        assert_eq!(
            parse("motor1-overheat@10s"),
            Ok(ScheduledFault { at: Duration::from_secs(10), fault: FaultKind::Motor1Overheat })
        );
        assert_eq!(parse("motor2-comm@1.5s").unwrap().at, Duration::from_millis(1500));
        assert_eq!(parse("estop@2").unwrap().at, Duration::from_secs(2));
        assert_eq!(parse("estop@0.25").unwrap().at, Duration::from_millis(250));
        assert_eq!(parse("rc-lost@500ms").unwrap().at, Duration::from_millis(500));
        assert_eq!(parse("overcurrent@1m 4s").unwrap().at, Duration::from_secs(64));
        assert_eq!(
            parse("battery-low").unwrap(),
            ScheduledFault { at: Duration::ZERO, fault: FaultKind::BatteryLow }
        );
        assert_eq!(parse("battery-low@0s").unwrap().at, Duration::ZERO);
    }

    #[test]
    fn display_parses_back() {
        for text in ["estop@2s", "motor2-comm@1s 500ms", "battery-ok@0s"] {
            let fault: ScheduledFault = text.parse().unwrap();
            assert_eq!(fault.to_string().parse::<ScheduledFault>(), Ok(fault));
        }
        assert_eq!("estop@2".parse::<ScheduledFault>().unwrap().to_string(), "estop@2s");
    }

    #[test]
    fn errors_say_what_is_wrong() {
        let err = "motor3-overheat@1s".parse::<ScheduledFault>().unwrap_err();
        assert_eq!(err, FaultParseError::UnknownFault("motor3-overheat".into()));
        let text = err.to_string();
        assert!(text.starts_with("unknown fault \"motor3-overheat\"; known faults: estop, estop-release,"));
        assert!(text.contains("motor1-overheat") && text.ends_with("other-host"), "{text}");

        for bad in ["estop@", "estop@soon", "estop@-1", "estop@1.2.3", "estop@5 parsecs"] {
            let err = bad.parse::<ScheduledFault>().unwrap_err();
            assert!(matches!(err, FaultParseError::BadTime { .. }), "{bad}: {err:?}");
            assert!(err.to_string().contains("use e.g. 2s"), "{err}");
        }
        assert!(matches!("".parse::<ScheduledFault>(), Err(FaultParseError::UnknownFault(_))));
        assert!(matches!("@1s".parse::<ScheduledFault>(), Err(FaultParseError::UnknownFault(_))));
    }

    #[test]
    fn clear_codes() {
        assert_eq!(ClearRequest::from_can(0).unwrap().motors, [true, true]);
        assert_eq!(ClearRequest::from_can(2).unwrap().motors, [false, true]);
        assert_eq!(ClearRequest::from_can(3), None);
        let comm2 = ClearRequest::from_serial(4).unwrap();
        assert!(comm2.comm && !comm2.overheat && !comm2.overcurrent && comm2.motors == [false, true]);
        assert!(ClearRequest::from_serial(7).unwrap().overheat);
        assert!(ClearRequest::from_serial(8).unwrap().overcurrent);
        for code in [0, 1, 2, 5, 6, 9, 255] {
            assert_eq!(ClearRequest::from_serial(code), None, "{code}");
        }
    }
}
