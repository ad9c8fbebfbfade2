//! Properties of the RS232 codec and stream decoder.

use proptest::prelude::*;
use tracerctl::protocol::id::{TYPE_CONTROL, TYPE_FEEDBACK};
use tracerctl::protocol::message::*;
use tracerctl::protocol::serial::*;

fn lights() -> impl Strategy<Value = Lights> {
    any::<[u8; 6]>().prop_map(|b| Lights {
        enable: b[0],
        front_mode: b[1],
        front_brightness: b[2],
        rear_mode: b[3],
        rear_brightness: b[4],
        count: b[5],
    })
}

/// Every message that has a serial form, with arbitrary field values (counts included: encode replaces them).
fn serial_message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (any::<[u8; 3]>(), any::<[i8; 3]>()).prop_map(|(b, p)| {
            Message::PercentMotionCommand(PercentMotionCommand {
                control_mode: b[0],
                fault_clear: b[1],
                linear_percent: p[0],
                angular_percent: p[1],
                lateral_percent: p[2],
                count: b[2],
            })
        }),
        lights().prop_map(Message::LightCommand),
        lights().prop_map(Message::LightState),
        (any::<[u8; 3]>(), any::<[u16; 2]>()).prop_map(|(b, w)| {
            Message::SystemState(SystemState {
                vehicle_state: b[0],
                control_mode: b[1],
                battery_decivolts: w[0],
                fault_code: w[1],
                count: b[2],
            })
        }),
        (any::<i16>(), any::<i16>(), any::<u8>()).prop_map(|(linear_mm_s, angular_mrad_s, count)| {
            Message::MotionState(MotionState { linear_mm_s, angular_mrad_s, count })
        }),
        (1u8..=2, any::<u16>(), any::<i16>(), any::<i8>(), any::<u8>()).prop_map(
            |(motor, c, rpm, t, count)| {
                Message::MotorDriverState(MotorDriverState {
                    motor,
                    current_deciamps: c,
                    rpm,
                    driver_temperature: t,
                    count,
                })
            }
        ),
    ]
}

fn with_count(message: Message, count: u8) -> Message {
    match message {
        Message::PercentMotionCommand(m) => {
            Message::PercentMotionCommand(PercentMotionCommand { count, ..m })
        }
        Message::LightCommand(l) => Message::LightCommand(Lights { count, ..l }),
        Message::LightState(l) => Message::LightState(Lights { count, ..l }),
        Message::SystemState(s) => Message::SystemState(SystemState { count, ..s }),
        Message::MotionState(s) => Message::MotionState(MotionState { count, ..s }),
        Message::MotorDriverState(m) => Message::MotorDriverState(MotorDriverState { count, ..m }),
        other => other,
    }
}

/// Bytes rich in the framing values, so false starts are common.
fn framing_byte() -> impl Strategy<Value = u8> {
    prop_oneof![
        3 => any::<u8>(),
        1 => prop::sample::select(vec![SOF1, SOF2, FRAME_LEN_BYTE, TYPE_CONTROL, TYPE_FEEDBACK]),
    ]
}

/// Noise made of frame-header fragments as well as single bytes: false candidates of every kind, often
/// overlapping each other and left unfinished at the end of the stream.
fn header_soup() -> impl Strategy<Value = Vec<u8>> {
    let piece = prop_oneof![
        2 => framing_byte().prop_map(|byte| vec![byte]),
        1 => Just(vec![SOF1, SOF2]),
        1 => prop::sample::select(vec![TYPE_CONTROL, TYPE_FEEDBACK])
            .prop_map(|frame_type| vec![SOF1, SOF2, FRAME_LEN_BYTE, frame_type]),
    ];
    prop::collection::vec(piece, 0..120).prop_map(|pieces| pieces.concat())
}

fn any_frame() -> impl Strategy<Value = SerialFrame> {
    (prop::sample::select(vec![TYPE_CONTROL, TYPE_FEEDBACK]), framing_byte(), any::<[u8; 6]>(), any::<u8>())
        .prop_map(|(frame_type, command, payload, frame_id)| SerialFrame {
            frame_type,
            command,
            payload,
            frame_id,
        })
}

/// A piece of a test stream, with what the decoder must report for it.
#[derive(Clone, Debug)]
enum Segment {
    /// Bytes that contain no `5A A5` pair of their own.
    Noise(Vec<u8>),
    Good(SerialFrame),
    /// A frame whose checksum byte is off by `delta` (non-zero).
    BadChecksum(SerialFrame, u8),
    /// A frame with this length byte instead of 0x0A.
    BadLength(SerialFrame, u8),
    /// A frame with this type byte instead of 0x55/0xAA.
    BadType(SerialFrame, u8),
}

/// A frame whose bytes after the start of frame hold no 0x5A, so no candidate starts inside it.
fn clean_frame() -> impl Strategy<Value = SerialFrame> {
    any_frame().prop_filter("0x5A after SOF", |frame| !frame.to_bytes()[2..].contains(&SOF1))
}

fn segment() -> impl Strategy<Value = Segment> {
    prop_oneof![
        4 => prop::collection::vec(framing_byte(), 0..24).prop_map(Segment::Noise),
        4 => any_frame().prop_map(Segment::Good),
        1 => (clean_frame(), 1u8..=255)
            .prop_filter("0x5A checksum", |(f, d)| f.to_bytes()[12].wrapping_add(*d) != SOF1)
            .prop_map(|(f, d)| Segment::BadChecksum(f, d)),
        1 => (clean_frame(), any::<u8>())
            .prop_filter("valid or 0x5A length", |(_, len)| ![FRAME_LEN_BYTE, SOF1].contains(len))
            .prop_map(|(f, len)| Segment::BadLength(f, len)),
        1 => (clean_frame(), any::<u8>())
            .prop_filter("valid or 0x5A type", |(_, t)| ![TYPE_CONTROL, TYPE_FEEDBACK, SOF1].contains(t))
            .prop_map(|(f, t)| Segment::BadType(f, t)),
    ]
}

/// What a stream built from segments must decode to.
#[derive(Debug, Default)]
struct Expected {
    stream: Vec<u8>,
    events: Vec<StreamEvent>,
    stats: StreamStats,
}

fn build(segments: &[Segment]) -> Expected {
    let mut expected = Expected::default();
    for segment in segments {
        let offset = expected.stream.len() as u64;
        let stats = &mut expected.stats;
        let bytes = match segment {
            Segment::Noise(noise) => {
                let mut noise = noise.clone();
                // Break `5A A5` pairs inside the noise and across its start (a bad candidate may end in 0x5A
                // only if it is a good frame, whose bytes are consumed anyway).
                let mut previous = expected.stream.last().copied();
                for byte in &mut noise {
                    if previous == Some(SOF1) && *byte == SOF2 {
                        *byte = 0;
                    }
                    previous = Some(*byte);
                }
                noise
            }
            Segment::Good(frame) => {
                stats.frames += 1;
                expected.events.push(StreamEvent::Frame { offset, frame: *frame });
                frame.to_bytes().to_vec()
            }
            Segment::BadChecksum(frame, delta) => {
                let mut bytes = frame.to_bytes();
                let computed = bytes[12];
                bytes[12] = computed.wrapping_add(*delta);
                stats.bad_checksum += 1;
                expected.events.push(StreamEvent::BadChecksum { offset, computed, found: bytes[12] });
                bytes.to_vec()
            }
            Segment::BadLength(frame, len) => {
                let mut bytes = frame.to_bytes();
                bytes[2] = *len;
                stats.bad_length += 1;
                bytes.to_vec()
            }
            Segment::BadType(frame, frame_type) => {
                let mut bytes = frame.to_bytes();
                bytes[3] = *frame_type;
                stats.bad_type += 1;
                bytes.to_vec()
            }
        };
        expected.stream.extend_from_slice(&bytes);
    }
    let stats = &mut expected.stats;
    stats.bytes = expected.stream.len() as u64;
    stats.skipped_bytes = stats.bytes - stats.frames * FRAME_SIZE as u64;
    expected
}

/// Splits `stream` at the given cut points (taken modulo its length) and feeds the pieces.
fn decode_chunked(stream: &[u8], cuts: &[usize]) -> (Vec<StreamEvent>, StreamStats) {
    let mut cuts: Vec<usize> = cuts.iter().map(|cut| cut % (stream.len() + 1)).collect();
    cuts.sort_unstable();
    let mut decoder = StreamDecoder::new();
    let mut events = Vec::new();
    let mut start = 0;
    for end in cuts.into_iter().chain([stream.len()]) {
        decoder.feed(&stream[start..end], |event| events.push(event));
        start = end;
    }
    (events, decoder.finish())
}

/// The framing rule written as the plainest possible scan: at each position not inside an accepted frame,
/// a candidate is `5A A5`, then length, type and checksum are checked in that order as far as bytes exist.
fn reference_scan(stream: &[u8]) -> (Vec<StreamEvent>, StreamStats) {
    let mut events = Vec::new();
    let mut stats = StreamStats { bytes: stream.len() as u64, ..StreamStats::default() };
    let mut at = 0;
    // Right after a good frame: skipping a byte now loses sync, unless the rest is a frame cut off by the
    // end of the stream.
    let mut in_sync = false;
    while at < stream.len() {
        let rest = &stream[at..];
        if rest.len() >= 2 && rest[..2] == [SOF1, SOF2] {
            if rest.len() > 2 && rest[2] != FRAME_LEN_BYTE {
                stats.bad_length += 1;
            } else if rest.len() > 3 && rest[3] != TYPE_CONTROL && rest[3] != TYPE_FEEDBACK {
                stats.bad_type += 1;
            } else if rest.len() >= FRAME_SIZE {
                match SerialFrame::from_bytes(&rest[..FRAME_SIZE]) {
                    Ok(frame) => {
                        events.push(StreamEvent::Frame { offset: at as u64, frame });
                        stats.frames += 1;
                        at += FRAME_SIZE;
                        in_sync = true;
                        continue;
                    }
                    Err(SerialError::BadChecksum { computed, found }) => {
                        stats.bad_checksum += 1;
                        events.push(StreamEvent::BadChecksum { offset: at as u64, computed, found });
                    }
                    Err(other) => panic!("header was checked: {other}"),
                }
            }
        }
        if in_sync && !unfinished_frame(rest) {
            stats.sync_losses += 1;
        }
        in_sync = false;
        stats.skipped_bytes += 1;
        at += 1;
    }
    (events, stats)
}

/// True when `rest` is shorter than a frame and every header byte it has is right.
fn unfinished_frame(rest: &[u8]) -> bool {
    rest.len() < FRAME_SIZE
        && rest[0] == SOF1
        && rest.get(1).is_none_or(|&b| b == SOF2)
        && rest.get(2).is_none_or(|&b| b == FRAME_LEN_BYTE)
        && rest.get(3).is_none_or(|&t| t == TYPE_CONTROL || t == TYPE_FEEDBACK)
}

proptest! {
    #[test]
    fn encode_decode_round_trip(message in serial_message(), frame_id in any::<u8>()) {
        let frame = encode(&message, frame_id).unwrap();
        prop_assert_eq!(frame.frame_id, frame_id);
        let bytes = frame.to_bytes();
        prop_assert_eq!(SerialFrame::from_bytes(&bytes), Ok(frame));
        let decoded = decode(&frame).unwrap();
        prop_assert_eq!(decoded, Decoded { wire: Wire::Serial, message: with_count(message, frame_id) });
        // And back to the same bytes.
        prop_assert_eq!(encode(&decoded.message, frame_id).unwrap().to_bytes(), bytes);
    }

    #[test]
    fn frame_bytes_round_trip(frame in any_frame()) {
        let bytes = frame.to_bytes();
        prop_assert_eq!(bytes[12], checksum(&bytes[..12]));
        prop_assert_eq!(SerialFrame::from_bytes(&bytes), Ok(frame));
        prop_assert_eq!(frame.id(), u16::from(frame.frame_type) << 8 | u16::from(frame.command));
    }

    #[test]
    fn stream_finds_every_inserted_frame(
        segments in prop::collection::vec(segment(), 0..16),
        cuts in prop::collection::vec(any::<usize>(), 0..12),
    ) {
        let expected = build(&segments);
        let (events, stats) = decode_chunked(&expected.stream, &cuts);
        prop_assert_eq!(&events, &expected.events);
        // Where sync is lost depends on the bytes at segment borders: the reference scan decides.
        let sync_losses = reference_scan(&expected.stream).1.sync_losses;
        prop_assert_eq!(stats, StreamStats { sync_losses, ..expected.stats });
        prop_assert_eq!(stats.bytes, stats.frames * 13 + stats.skipped_bytes);
    }

    #[test]
    fn stream_matches_reference_scan(
        stream in header_soup(),
        frames in prop::collection::vec((any::<usize>(), any_frame()), 0..6),
        cuts in prop::collection::vec(any::<usize>(), 0..12),
    ) {
        // Noise full of frame headers, with real frames spliced in at random places.
        let mut stream = stream;
        for (at, frame) in frames {
            let at = at % (stream.len() + 1);
            stream.splice(at..at, frame.to_bytes());
        }
        let (events, stats) = decode_chunked(&stream, &cuts);
        let one_byte = decode_chunked(&stream, &(0..stream.len()).collect::<Vec<_>>());
        prop_assert_eq!((&events, stats), (&one_byte.0, one_byte.1));
        let reference = reference_scan(&stream);
        prop_assert_eq!(&events, &reference.0);
        prop_assert_eq!(stats, reference.1);
        prop_assert_eq!(stats.bytes, stats.frames * 13 + stats.skipped_bytes);
    }

    #[test]
    fn stream_never_panics(
        stream in prop::collection::vec(any::<u8>(), 0..512),
        cuts in prop::collection::vec(any::<usize>(), 0..8),
    ) {
        let (events, stats) = decode_chunked(&stream, &cuts);
        prop_assert_eq!(stats.bytes, stream.len() as u64);
        prop_assert_eq!(stats.bytes, stats.frames * 13 + stats.skipped_bytes);
        let frames = events.iter().filter(|event| matches!(event, StreamEvent::Frame { .. })).count() as u64;
        prop_assert_eq!(frames, stats.frames);
    }

    #[test]
    fn from_bytes_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..40)) {
        let result = SerialFrame::from_bytes(&bytes);
        if bytes.len() != FRAME_SIZE {
            prop_assert!(result.is_err());
        }
        if let Ok(frame) = result {
            prop_assert_eq!(frame.to_bytes().to_vec(), bytes);
            // Decoding any valid frame is total too.
            let _ = decode(&frame);
        }
    }
}
