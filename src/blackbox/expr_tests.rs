use super::*;
use crate::protocol::faults::Flags;
use crate::protocol::message::{Message, MotorHighSpeed, SystemState};
use crate::protocol::{Decoded, Wire};

fn parse(text: &str) -> Expression {
    text.parse().unwrap_or_else(|error| panic!("{text}: {error}"))
}

fn error(text: &str) -> ExpressionError {
    text.parse::<Expression>().expect_err(text)
}

/// The value of `field` in `decoded`, as the watcher finds it.
fn value_of(decoded: &Decoded, field: FieldName) -> Value {
    let mut found = None;
    for_each_field(decoded, |f| {
        if f.name == field {
            found = Some(f.value);
        }
    });
    found.unwrap_or_else(|| panic!("no {field:?}"))
}

fn system(vehicle_state: u8, control_mode: u8, battery_decivolts: u16, fault_code: u16) -> Decoded {
    let state = SystemState { vehicle_state, control_mode, battery_decivolts, fault_code, count: 0 };
    Decoded { wire: Wire::CanV2, message: Message::SystemState(state) }
}

fn holds(text: &str, decoded: &Decoded) -> bool {
    let expression = parse(text);
    let Target::Field { name, kinds } = expression.target() else {
        panic!("{text} is not a field expression")
    };
    assert_ne!(kinds & kind_bit(decoded.message.kind()), 0, "{text}: the message does not carry the field");
    expression.holds(&value_of(decoded, name))
}

#[test]
fn numbers_compare_exactly_at_the_threshold() {
    let at_23 = system(0, 1, 230, 0);
    assert!(!holds("battery_voltage<23.0", &at_23));
    assert!(holds("battery_voltage<=23", &at_23));
    assert!(holds("battery_voltage>=23.00", &at_23));
    assert!(holds("battery_voltage = 23", &at_23));
    assert!(!holds("battery_voltage!=23.0", &at_23));
    assert!(holds("battery_voltage>22.9", &at_23));
    assert!(holds("battery_voltage<23.05", &at_23));
    assert!(!holds("battery_voltage<22.99999999999999999", &at_23), "17 decimals, no float rounding");
    let motor = Decoded {
        wire: Wire::CanV2,
        message: Message::MotorHighSpeed(MotorHighSpeed {
            motor: 2,
            rpm: -120,
            current_deciamps: 162,
            pulse_count: 0,
        }),
    };
    assert!(holds("current>15", &motor));
    assert!(holds("motor_current>15", &motor), "the issue's spelling");
    assert!(holds("rpm<-100", &motor));
    assert!(holds("rpm>=-0x78", &motor));
    assert!(holds("motor=2", &motor));
    assert!(holds("motor_high_speed.current>16.1", &motor));
}

#[test]
fn names_flags_and_codes() {
    let rc = system(0, 3, 250, 0x0400);
    assert!(holds("control_mode=rc", &rc));
    assert!(holds("CONTROL_MODE = RC", &rc), "names are not case-sensitive");
    assert!(!holds("control_mode!=rc", &rc));
    assert!(holds("control_mode=3", &rc), "a number compares the raw byte");
    assert!(holds("control_mode>=2", &rc));
    assert!(holds("vehicle_state=normal", &rc));
    assert!(holds("faults=rc_disconnected", &rc));
    assert!(!holds("faults!=rc_disconnected", &rc));
    assert!(!holds("faults=battery_undervoltage_warning", &rc));
    assert!(!holds("faults=none", &rc));
    assert!(holds("fault_code=0x400", &rc));
    assert!(holds("faults=none", &system(0, 1, 250, 0)));
    // An undefined mode byte has no name: never equal to one, always different.
    let odd = system(0, 7, 250, 0);
    assert!(!holds("control_mode=rc", &odd));
    assert!(holds("control_mode!=rc", &odd));
    // The same flag name is a different bit on V1/RS232: each table's own bit is tested.
    let serial = Decoded { wire: Wire::Serial, message: system(0, 2, 224, 0x0800).message };
    assert!(holds("faults=battery_undervoltage_warning", &serial));
    assert!(!holds("faults=battery_undervoltage_warning", &system(0, 1, 224, 0x0800)));
}

#[test]
fn identifiers_compare_within_their_kind() {
    let id = parse("id=0x441");
    assert_eq!(id.target(), Target::Id);
    assert!(id.matches_id(FrameId::Standard(0x441)));
    assert!(!id.matches_id(FrameId::Extended(0x441)));
    assert!(!id.matches_id(FrameId::Standard(0x421)));
    assert!(parse("id = 441").matches_id(FrameId::Standard(0x441)), "hex, as --id reads it");
    assert!(parse("id=0xAA01").matches_id(FrameId::Serial(0xAA01)));
    let below = parse("id<0x200");
    assert!(below.matches_id(FrameId::Standard(0x151)));
    assert!(!below.matches_id(FrameId::Standard(0x211)));
    assert!(!below.matches_id(FrameId::Extended(0x100)), "another kind of identifier is never below");
    assert!(parse("id!=0x211").matches_id(FrameId::Extended(0x211)));
    assert_eq!(id.text(), "id=0x441");
}

#[test]
fn every_field_of_the_schema_can_be_watched() {
    let schema = schema();
    let names: Vec<&str> = schema.iter().map(|field| field.name.as_str()).collect();
    assert_eq!(names.len(), ALL_FIELD_NAMES.len(), "{names:?}");
    for field in &schema {
        let example = match field.shape {
            Shape::Number => "1",
            Shape::Bool => "true",
            Shape::Version => "1.2",
            Shape::Name => names_of(field.name).first().copied().unwrap_or("no names"),
            Shape::Flags => flag_names(field.name).first().copied().unwrap_or("no flags"),
        };
        let text = format!("{}={example}", field.name.as_str());
        text.parse::<Expression>().unwrap_or_else(|error| panic!("{error}"));
    }
    // One shape per field, whatever message carries it.
    for decoded in one_of_each_message() {
        for_each_field(&decoded, |f| {
            let known = schema.iter().find(|known| known.name == f.name).unwrap();
            assert_eq!(known.shape, shape_of(&f.value), "{:?}", f.name);
        });
    }
    assert_eq!(names_of(FieldName::ControlMode), ["standby", "can", "serial", "rc"]);
    assert_eq!(names_of(FieldName::Swb), ["middle", "up", "down"]);
}

#[test]
fn versions_and_booleans() {
    let version = parse("controller_sw>=1.2");
    assert!(version.holds(&Value::Version(0x0102)));
    assert!(version.holds(&Value::Version(0x010A)), "1.10 is after 1.2");
    assert!(!version.holds(&Value::Version(0x0101)));
    assert!(parse("enabled=true").holds(&Value::Bool(true)));
    assert!(parse("enabled!=0").holds(&Value::Bool(true)));
    let flags = Value::Flags(Flags::new(FlagTable::DriverState, 0x10));
    assert!(parse("driver_faults=can_disconnected").holds(&flags));
    assert!(parse("motor_low_speed.driver_faults=can_disconnected").holds(&flags));
}

#[test]
fn errors_say_where_and_why() {
    let cases: &[(&str, usize, &str)] = &[
        ("", 0, "empty trigger: write FIELD OP VALUE"),
        ("   ", 3, "empty trigger"),
        ("<23", 0, "expected a field name, found '<'"),
        ("battery_voltag<23", 0, "unknown field \"battery_voltag\"; did you mean battery_voltage?"),
        ("  voltage>1", 2, "did you mean"),
        ("xyzzy=1", 0, "known fields: id, vehicle_state, control_mode,"),
        (
            "battery_voltage",
            15,
            "expected an operator (<, <=, >, >=, =, !=) after battery_voltage, found nothing",
        ),
        ("battery_voltage ~ 2", 16, "expected an operator"),
        ("battery_voltage<", 16, "expected a value after <"),
        (
            "battery_voltage < low",
            18,
            "battery_voltage takes a number (such as 23.0, -1.5 or 0x10), not \"low\"",
        ),
        ("battery_voltage<23 volts", 19, "unexpected \"volts\" after the value"),
        ("control_mode=rcc", 13, "\"rcc\" is not a control_mode name; its names: standby, can, serial, rc"),
        ("control_mode>rc", 12, "control_mode compares with = or != only, not >"),
        ("faults=rc_lost", 7, "\"rc_lost\" is not a faults flag;"),
        ("faults=motor1_comm", 7, "did you mean motor1_comm_fault?"),
        ("enabled=yes", 8, "enabled takes true or false"),
        ("controller_sw>1.x", 14, "takes a version such as 1.2"),
        ("id=0xZZ", 3, "id takes an identifier"),
        ("system_state.current>1", 13, "system_state has no field current; its fields: vehicle_state,"),
        ("system_stat.battery_voltage<1", 0, "unknown message \"system_stat\"; did you mean system_state?"),
        ("system_state.id=1", 0, "id is the frame's identifier"),
        ("rpm>99999999999999999999", 4, "rpm takes a number"),
        ("rpm>1.2.3", 4, "rpm takes a number"),
    ];
    for (text, offset, reason) in cases {
        let error = error(text);
        assert_eq!(error.offset, *offset, "{text:?}: {error}");
        assert!(error.reason.contains(reason), "{text:?}: {:?} lacks {reason:?}", error.reason);
        assert!(error.to_string().starts_with(&format!("trigger {text:?}, at byte {offset}: ")), "{error}");
    }
}

#[test]
fn near_names_are_suggested_and_far_ones_listed() {
    assert_eq!(nearest("curent", ALL_FIELD_NAMES), ["current"]);
    assert_eq!(nearest("voltage", ALL_FIELD_NAMES), ["driver_voltage", "battery_voltage"]);
    assert!(nearest("zz", ALL_FIELD_NAMES).is_empty());
    assert_eq!(edit_distance("kitten", "sitting"), 3);
    assert_eq!(edit_distance("", "abc"), 3);
    assert_eq!(or_list(&["a", "b", "c"]), "a, b or c");
}

#[test]
fn numbers_are_read_exactly() {
    let fixed = |mantissa, scale| Some(Fixed { mantissa, scale });
    assert_eq!(read_number("23.0"), fixed(230, 1));
    assert_eq!(read_number("-1.5"), fixed(-15, 1));
    assert_eq!(read_number("+.5"), fixed(5, 1));
    assert_eq!(read_number("0x1F"), fixed(31, 0));
    assert_eq!(read_number("-0x10"), fixed(-16, 0));
    for bad in ["", "-", ".", "1e3", "0x", "1.2.3", "0x12345678901234567", "12345678901234567890"] {
        assert_eq!(read_number(bad), None, "{bad}");
    }
    assert_eq!(
        Fixed { mantissa: 225, scale: 1 }.compare(Fixed { mantissa: 22500, scale: 3 }),
        Ordering::Equal
    );
    assert_eq!(read_version("1.2"), Some(0x0102));
    assert_eq!(read_version("3"), Some(0x0300));
    assert_eq!(read_version("256.1"), None);
}
