//! The catalog against the codec (every row decodes, and encodes back to its identifier), and a scan of the
//! sources for identifiers written outside the catalog and the codec. The recipe "How to add a message" in
//! docs/architecture.md ends with these tests.

use std::path::Path;

use super::*;
use crate::protocol::can::{self, v1_checksum, ProtocolHint};
use crate::protocol::frame::CanFrame;
use crate::protocol::serial::{self, SerialFrame};
use crate::protocol::Decoded;
use crate::source_scan::{shipped_files, without_comments, without_test_items};

/// What the codec makes of an all-zero frame with this identifier on this wire (V1 with its checksum).
fn decode(id: FrameId, wire: Wire) -> Option<Decoded> {
    match id {
        FrameId::Serial(value) => {
            let [frame_type, command] = value.to_be_bytes();
            serial::decode(&SerialFrame { frame_type, command, payload: [0; 6], frame_id: 0 })
        }
        FrameId::Standard(value) => {
            let mut data = [0u8; 8];
            let hint = if wire == Wire::CanV1 {
                data[7] = v1_checksum(u32::from(value), &data);
                ProtocolHint::V1
            } else {
                ProtocolHint::V2
            };
            can::decode(&CanFrame::new(u32::from(value), &data).unwrap(), hint).ok().flatten()
        }
        FrameId::Extended(_) => None,
    }
}

/// The identifier the codec gives the message when it encodes it for this wire.
fn encode(decoded: &Decoded) -> FrameId {
    match decoded.wire {
        Wire::Serial => serial::encode(&decoded.message, 0).unwrap().frame_id(),
        Wire::CanV1 | Wire::CanV2 => can::encode(decoded).unwrap().frame_id(),
    }
}

/// Robot frames with no period, each for a reason: the RC state (not in the TRACER manuals, may never
/// come), the version reply (on request), and the V2 manual's name for 0x211 (firmware sends 0x211).
const APERIODIC_FEEDBACK: &[(FrameId, Wire)] = &[
    (FrameId::Standard(0x241), Wire::CanV2),
    (FrameId::Standard(0x41A), Wire::CanV2),
    (FrameId::Standard(0x151), Wire::CanV2),
];

#[test]
fn every_entry_has_a_codec_a_label_and_the_right_period() {
    for entry in CATALOG {
        let what = format!("{} on {}", entry.id, entry.wire.as_str());
        let decoded = decode(entry.id, entry.wire).unwrap_or_else(|| panic!("{what}: no codec decodes it"));
        assert_eq!(decoded.wire, entry.wire, "{what}");
        assert_eq!(decoded.message.name(), entry.name(), "{what}");
        // Encoding gives the identifier back (the V2 manual's 0x151 encodes as the 0x211 firmware sends).
        let expected = if entry.source == SYSTEM_STATE_MANUAL { FrameId::Standard(0x211) } else { entry.id };
        assert_eq!(encode(&decoded), expected, "{what}: encodes to another identifier");
        assert_eq!(decode(encode(&decoded), entry.wire), Some(decoded), "{what}: does not decode back");
        assert!(!entry.label.is_empty() && entry.label.len() <= 13, "{what}: label {:?}", entry.label);
        assert!(!entry.source.is_empty(), "{what}: no source");
        match entry.direction {
            Direction::ToRobot => assert_eq!(entry.period, None, "{what}: a command has no period"),
            Direction::FromRobot => assert_eq!(
                entry.period.is_none(),
                APERIODIC_FEEDBACK.contains(&(entry.id, entry.wire)),
                "{what}: robot feedback has a period unless listed in APERIODIC_FEEDBACK"
            ),
        }
        assert!(entry.period.is_none_or(|period| period >= Duration::from_millis(10)), "{what}");
    }
}

#[test]
fn directions_follow_the_message() {
    let commands = [
        MessageKind::MotionCommand,
        MessageKind::LightCommand,
        MessageKind::ControlModeCommand,
        MessageKind::FaultClear,
        MessageKind::VersionRequest,
    ];
    for entry in CATALOG {
        let to_robot = commands.contains(&entry.kind);
        assert_eq!(entry.direction == Direction::ToRobot, to_robot, "{} {}", entry.id, entry.name());
    }
}

/// The other way round: every identifier the codec decodes is in the catalog, on the wire it decodes to.
#[test]
fn every_identifier_the_codec_knows_is_catalogued() {
    let standard = (0..0x800u16).map(FrameId::Standard);
    let serial = [TYPE_CONTROL, TYPE_FEEDBACK]
        .into_iter()
        .flat_map(|frame_type| (0..=255).map(move |command| FrameId::serial(frame_type, command)));
    let mut known = 0;
    for id in standard.chain(serial) {
        let wires: &[Wire] =
            if matches!(id, FrameId::Serial(_)) { &[Wire::Serial] } else { &[Wire::CanV1, Wire::CanV2] };
        for &wire in wires {
            let Some(decoded) = decode(id, wire) else { continue };
            known += 1;
            let entry =
                entry(id, decoded.wire).unwrap_or_else(|| panic!("{id} decodes but is not catalogued"));
            assert_eq!(entry.name(), decoded.message.name(), "{id}");
        }
    }
    assert!(known >= CATALOG.len(), "the scan decoded {known} frames");
}

#[test]
fn identifiers_are_unique_per_wire() {
    for (i, entry) in CATALOG.iter().enumerate() {
        assert!(
            CATALOG[i + 1..].iter().all(|other| (other.id, other.wire) != (entry.id, entry.wire)),
            "{} twice on {}",
            entry.id,
            entry.wire.as_str()
        );
    }
}

#[test]
fn periodic_is_the_catalog_rows_with_a_period() {
    let expected: Vec<&Entry> = CATALOG.iter().filter(|entry| entry.period.is_some()).collect();
    assert_eq!(PERIODIC.iter().collect::<Vec<_>>(), expected);
    assert_eq!(PERIODIC.len(), 18);
    assert_eq!(
        periodic_frame(FrameId::Standard(0x261)).map(|p| (p.label, p.period)),
        Some(("driver 1", Some(Duration::from_millis(100))))
    );
    assert_eq!(periodic_frame(FrameId::Serial(0xAA07)).map(Entry::name), Some("light_state"));
    assert_eq!(periodic_frame(FrameId::Standard(0x151)).map(|p| p.wire), Some(Wire::CanV1));
    assert_eq!(periodic_frame(FrameId::Standard(0x111)), None);
    assert_eq!(periodic_frame(FrameId::Extended(0x211)), None);
    assert_eq!(label(FrameId::Standard(0x41A)), Some("version"));
    assert_eq!(label(FrameId::Serial(0x5501)), Some("motion cmd"));
}

// The scan: no catalog identifier written out in the shipped code outside the catalog and the codec.

/// Files that may spell identifiers: the catalog and the codec.
const CODEC: &[&str] = &[
    "src/protocol/can.rs",
    "src/protocol/serial.rs",
    "src/protocol/payload.rs",
    "src/protocol/codec.rs",
    "src/protocol/mode.rs",
    "src/protocol/catalog.rs",
    "src/protocol/constants.rs",
    "src/protocol/id.rs",
    "src/fuzzing.rs",
];

/// The catalog identifiers `line` writes out: hex literals (`0x211`, `0x0211`, `0xAA01`) and cansend frames
/// (`211#...`), each whole (not part of `0x2110`, `0x00000211` or `x211#`).
fn identifiers_in(line: &str) -> Vec<String> {
    let bytes = line.as_bytes();
    let word = |at: usize| bytes.get(at).is_some_and(|b| b.is_ascii_alphanumeric() || *b == b'_');
    let mut found = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        if (at > 0 && word(at - 1)) || !bytes[at].is_ascii_hexdigit() {
            at += 1;
            continue;
        }
        let start = at;
        while word(at) {
            at += 1;
        }
        let token = &line[start..at];
        let hex = match token.strip_prefix("0x").or_else(|| token.strip_prefix("0X")) {
            Some(digits) if digits.len() <= 4 => Some(digits),
            None if token.len() == 3 && bytes.get(at) == Some(&b'#') => Some(token),
            _ => None,
        };
        let value = hex.and_then(|digits| u32::from_str_radix(digits, 16).ok());
        if value.is_some_and(|value| CATALOG.iter().any(|entry| entry.id.value() == value)) {
            found.push(token.to_string());
        }
    }
    found
}

/// Every catalog identifier written out in shipped code outside the catalog and the codec, as
/// `file:line: literal`.
fn stray_identifiers(root: &Path) -> Vec<String> {
    let files = shipped_files(&root.join("src"));
    assert!(files.len() > 20, "the scan found the sources");
    let mut strays = Vec::new();
    for path in &files {
        let relative = path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        if CODEC.contains(&relative.as_str()) {
            continue;
        }
        let text = std::fs::read_to_string(path).unwrap();
        for (number, line) in without_comments(&without_test_items(&text)).lines().enumerate() {
            for literal in identifiers_in(line) {
                strays.push(format!("{relative}:{}: {literal}", number + 1));
            }
        }
    }
    strays
}

#[test]
fn identifiers_are_written_only_in_the_catalog_and_the_codec() {
    let strays = stray_identifiers(Path::new(env!("CARGO_MANIFEST_DIR")));
    assert!(
        strays.is_empty(),
        "identifiers belong in src/protocol/catalog.rs (or the codec); read them from there:\n{}",
        strays.join("\n")
    );
}

#[test]
fn the_scan_reads_code_and_strings_not_comments() {
    let text = "let a = 0x211; // 0x221\n/// 0x231\nlet b = \"0x441 = 0x00\"; /* 0x111 */ let c = '\"';\n\
                let d = \"// 0x421\"; let e = 0x2110 + 0x00000211 + x211 + 0x5501;\nsend(\"421#01\");";
    let found: Vec<String> = without_comments(text).lines().flat_map(identifiers_in).collect();
    assert_eq!(found, ["0x211", "0x441", "0x421", "0x5501", "421"]);
    assert_eq!(identifiers_in("0x0211 0xaa01 0X151"), ["0x0211", "0xaa01", "0X151"]);
    assert!(identifiers_in("0x12 0x7FF 211 ab211#").is_empty());
}
