//! Messages <-> RS232 frames (`5A A5` framing), and a stream decoder that finds frames in a byte stream.
//!
//! Every TRACER frame is 13 bytes: `5A A5 0A type command d0..d5 frame_id checksum`, the checksum being the
//! sum of the first 12 bytes mod 256 (TRACER user manual, RS232 protocol section).
//!
//! AgileX's own UART parser loses frames after a false start, trusts the length byte, and re-delivers the
//! previous frame when a checksum fails. `StreamDecoder` rescans every byte of a failed candidate, accepts
//! only length 0x0A, and reports a bad checksum as an event of its own.

use super::can::EncodeError;
use super::id::{
    CMD_LIGHT_CONTROL, CMD_LIGHT_STATUS, CMD_MOTION_CONTROL, CMD_MOTION_STATUS, CMD_MOTOR1_DRIVER,
    CMD_MOTOR2_DRIVER, CMD_SYSTEM_STATUS, TYPE_CONTROL, TYPE_FEEDBACK,
};
use super::message::*;
use super::payload::{self, Layout};

pub const SOF1: u8 = 0x5A;
pub const SOF2: u8 = 0xA5;
/// Every TRACER frame, checksum included.
pub const FRAME_SIZE: usize = 13;
/// The frame_len field: bytes from frame_len through frame_id (total minus 2 SOF bytes and the checksum).
pub const FRAME_LEN_BYTE: u8 = 0x0A;

const _: () = assert!(FRAME_LEN_BYTE as usize == FRAME_SIZE - 3);

/// Offsets inside a frame.
const AT_LEN: usize = 2;
const AT_TYPE: usize = 3;
const AT_COMMAND: usize = 4;
const AT_PAYLOAD: usize = 5;
const AT_FRAME_ID: usize = 11;
const AT_CHECKSUM: usize = 12;

/// Why bytes are not one valid TRACER frame.
#[derive(thiserror::Error, Debug, Clone, Copy, PartialEq, Eq)]
pub enum SerialError {
    #[error("need {FRAME_SIZE} bytes, got {got}")]
    TooShort { got: usize },
    #[error("{got} bytes: a TRACER frame is exactly {FRAME_SIZE}")]
    TooLong { got: usize },
    #[error("bad start of frame: 0x{:02X} 0x{:02X}, expected 0x5A 0xA5", found[0], found[1])]
    BadStart { found: [u8; 2] },
    #[error("length byte 0x{found:02X}: TRACER frames have 0x0A")]
    BadLength { found: u8 },
    #[error("frame type 0x{found:02X} is neither control (0x55) nor feedback (0xAA)")]
    BadType { found: u8 },
    #[error("checksum mismatch: computed 0x{computed:02X}, frame carries 0x{found:02X}")]
    BadChecksum { computed: u8, found: u8 },
}

/// Sum mod 256 of all given bytes (pass the first 12 bytes of a frame to get its checksum).
pub fn checksum(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |sum, byte| sum.wrapping_add(*byte))
}

/// Checks the header bytes present in `prefix`, so a stream can reject a candidate as soon as its first
/// wrong byte arrives. The start of frame is checked once both of its bytes are present.
fn check_header(prefix: &[u8]) -> Result<(), SerialError> {
    if let [first, second, ..] = *prefix {
        if [first, second] != [SOF1, SOF2] {
            return Err(SerialError::BadStart { found: [first, second] });
        }
    }
    if let Some(&found) = prefix.get(AT_LEN) {
        if found != FRAME_LEN_BYTE {
            return Err(SerialError::BadLength { found });
        }
    }
    if let Some(&found) = prefix.get(AT_TYPE) {
        if found != TYPE_CONTROL && found != TYPE_FEEDBACK {
            return Err(SerialError::BadType { found });
        }
    }
    Ok(())
}

/// One 13-byte frame, checksum verified/implied.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SerialFrame {
    pub frame_type: u8,
    pub command: u8,
    pub payload: [u8; 6],
    pub frame_id: u8,
}

impl SerialFrame {
    /// The frame on the wire, with its checksum computed.
    pub fn to_bytes(&self) -> [u8; FRAME_SIZE] {
        let mut bytes = [0u8; FRAME_SIZE];
        bytes[..AT_PAYLOAD].copy_from_slice(&[SOF1, SOF2, FRAME_LEN_BYTE, self.frame_type, self.command]);
        bytes[AT_PAYLOAD..AT_FRAME_ID].copy_from_slice(&self.payload);
        bytes[AT_FRAME_ID] = self.frame_id;
        bytes[AT_CHECKSUM] = checksum(&bytes[..AT_CHECKSUM]);
        bytes
    }

    /// Parses exactly one frame: checks its size, start of frame, length byte, type and checksum.
    /// The command id is not checked: unknown commands are valid frames that `decode` leaves raw.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, SerialError> {
        let got = bytes.len();
        let bytes: &[u8; FRAME_SIZE] = bytes.try_into().map_err(|_| {
            if got < FRAME_SIZE {
                SerialError::TooShort { got }
            } else {
                SerialError::TooLong { got }
            }
        })?;
        check_header(bytes)?;
        let computed = checksum(&bytes[..AT_CHECKSUM]);
        let found = bytes[AT_CHECKSUM];
        if computed != found {
            return Err(SerialError::BadChecksum { computed, found });
        }
        Ok(Self::from_checked(bytes))
    }

    /// The fields of a frame whose header and checksum were already checked.
    fn from_checked(bytes: &[u8; FRAME_SIZE]) -> Self {
        let mut payload = [0u8; 6];
        payload.copy_from_slice(&bytes[AT_PAYLOAD..AT_FRAME_ID]);
        Self { frame_type: bytes[AT_TYPE], command: bytes[AT_COMMAND], payload, frame_id: bytes[AT_FRAME_ID] }
    }

    /// `0xAA01`-style id used in output: type << 8 | command.
    pub fn id(&self) -> u16 {
        u16::from_be_bytes([self.frame_type, self.command])
    }

    pub fn frame_id(&self) -> super::FrameId {
        super::FrameId::serial(self.frame_type, self.command)
    }
}

/// Decodes a verified frame. `None` for unknown command ids: callers show those raw, they are not errors.
/// Reserved payload bytes are ignored; the frame id becomes the message's `count`.
pub fn decode(frame: &SerialFrame) -> Option<Decoded> {
    let layout = match (frame.frame_type, frame.command) {
        (TYPE_FEEDBACK, CMD_SYSTEM_STATUS) => Layout::SystemState,
        (TYPE_FEEDBACK, CMD_MOTION_STATUS) => Layout::MotionState,
        (TYPE_FEEDBACK, command @ (CMD_MOTOR1_DRIVER | CMD_MOTOR2_DRIVER)) => {
            Layout::MotorDriver(command - CMD_MOTOR1_DRIVER + 1)
        }
        (TYPE_FEEDBACK, CMD_LIGHT_STATUS) => Layout::LightState,
        (TYPE_CONTROL, CMD_MOTION_CONTROL) => Layout::MotionCommand,
        (TYPE_CONTROL, CMD_LIGHT_CONTROL) => Layout::LightCommand,
        _ => return None,
    };
    let message = payload::decode(layout, &frame.payload, frame.frame_id);
    Some(Decoded { wire: Wire::Serial, message })
}

/// Encodes a message for RS232 with `frame_id` in byte 11 (the message's own `count` is not used).
/// The inverse of `decode`. Messages with no serial form (the V2-only ones) are an error.
pub fn encode(message: &Message, frame_id: u8) -> Result<SerialFrame, EncodeError> {
    let Some((layout, payload, _)) = payload::encode(message) else {
        return Err(EncodeError { name: message.name(), wire: "serial" });
    };
    let (frame_type, command) = match layout {
        Layout::MotionCommand => (TYPE_CONTROL, CMD_MOTION_CONTROL),
        Layout::LightCommand => (TYPE_CONTROL, CMD_LIGHT_CONTROL),
        Layout::SystemState => (TYPE_FEEDBACK, CMD_SYSTEM_STATUS),
        Layout::MotionState => (TYPE_FEEDBACK, CMD_MOTION_STATUS),
        // TRACER has two motors; Scout's 0x05/0x06 for motors 3 and 4 are not TRACER frames.
        Layout::MotorDriver(motor) => (TYPE_FEEDBACK, CMD_MOTOR1_DRIVER + motor - 1),
        Layout::LightState => (TYPE_FEEDBACK, CMD_LIGHT_STATUS),
    };
    Ok(SerialFrame { frame_type, command, payload, frame_id })
}

/// Rolling frame ids as AgileX's SDK does: separate counters for motion and light control frames, +1 per
/// frame sent, wrapping 255 -> 0. Feedback frames (for simulators) get one counter per command likewise.
#[derive(Clone, Debug, Default)]
pub struct SerialEncoder {
    /// Next frame id, by [is feedback][command id & 7] (TRACER command ids are 1..=7).
    next_ids: [[u8; 8]; 2],
}

impl SerialEncoder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Encodes `message` with the next frame id of its kind; the counter only advances on success.
    pub fn encode_next(&mut self, message: &Message) -> Result<[u8; FRAME_SIZE], EncodeError> {
        let mut frame = encode(message, 0)?;
        let kind = usize::from(frame.frame_type == TYPE_FEEDBACK);
        let next = &mut self.next_ids[kind][usize::from(frame.command & 7)];
        frame.frame_id = *next;
        *next = next.wrapping_add(1);
        Ok(frame.to_bytes())
    }
}

/// What the stream decoder found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StreamEvent {
    /// `offset` = byte offset of the frame's first byte in the whole stream.
    Frame { offset: u64, frame: SerialFrame },
    /// A candidate with good SOF/length/type whose checksum failed; dropped. Its bytes are re-examined
    /// afterwards.
    BadChecksum { offset: u64, computed: u8, found: u8 },
}

/// Counters of a stream. After `finish`: `bytes == frames * 13 + skipped_bytes`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StreamStats {
    /// Bytes fed.
    pub bytes: u64,
    /// Valid frames delivered.
    pub frames: u64,
    /// Candidates with good SOF, length and type but a wrong checksum.
    pub bad_checksum: u64,
    /// Candidates (`5A A5`) whose length byte is not 0x0A.
    pub bad_length: u64,
    /// Candidates with good SOF and length whose type is neither 0x55 nor 0xAA.
    pub bad_type: u64,
    /// Bytes not part of any delivered frame (noise, rejected candidates, an unfinished frame at the end).
    pub skipped_bytes: u64,
    /// Times the stream lost frame sync: bytes had to be skipped right after a good frame (noise or a
    /// corrupted frame). Bytes before the first frame and an unfinished frame at the end are not losses.
    pub sync_losses: u64,
}

/// Incremental stream decoder: feed arbitrary chunks, get every valid frame.
///
/// Candidates are examined in stream order; a candidate that fails any check loses only its first byte and
/// the rest is rescanned, so a frame overlapping or following noise is found (unless the noise itself
/// passes as a valid frame covering its start). Results do not depend on how the stream is split into
/// chunks. Memory is one fixed 13-byte window; nothing is allocated.
#[derive(Clone, Debug, Default)]
pub struct StreamDecoder {
    /// The candidate under examination: the last `len` bytes fed, starting with SOF1 when not empty.
    window: [u8; FRAME_SIZE],
    len: usize,
    stats: StreamStats,
    /// The last thing examined was a good frame: skipping bytes now is a loss of sync.
    in_sync: bool,
}

impl StreamDecoder {
    pub fn new() -> Self {
        Self::default()
    }

    /// Feeds the next bytes of the stream; `on_event` gets every frame and bad checksum, in stream order.
    pub fn feed(&mut self, mut bytes: &[u8], mut on_event: impl FnMut(StreamEvent)) {
        while !bytes.is_empty() {
            if self.len == 0 {
                // Nothing pending: jump straight to the next possible start of frame.
                let junk = bytes.iter().position(|&b| b == SOF1).unwrap_or(bytes.len());
                self.stats.bytes += junk as u64;
                self.skip(junk);
                bytes = &bytes[junk..];
                if bytes.is_empty() {
                    break;
                }
            }
            let take = (FRAME_SIZE - self.len).min(bytes.len());
            self.window[self.len..self.len + take].copy_from_slice(&bytes[..take]);
            self.len += take;
            self.stats.bytes += take as u64;
            bytes = &bytes[take..];
            // Leaves fewer than 13 bytes pending, so every pass takes at least one byte.
            self.settle(&mut on_event);
        }
    }

    /// End of stream: bytes of an unfinished frame are counted as skipped; returns final stats.
    pub fn finish(&mut self) -> StreamStats {
        // The pending candidate can never complete; rescan its bytes as after any failed candidate so
        // rejections inside it are counted too. Fewer than 13 bytes remain, so no event can occur.
        // A stream cut off mid-frame has not lost sync.
        self.in_sync = false;
        while self.len > 0 {
            self.drop_front(1);
            self.settle(&mut |_| {});
        }
        self.stats
    }

    pub fn stats(&self) -> StreamStats {
        self.stats
    }

    /// Examines the window until it holds nothing or the incomplete start of a plausible frame.
    fn settle(&mut self, on_event: &mut impl FnMut(StreamEvent)) {
        loop {
            let junk = self.window[..self.len].iter().position(|&b| b == SOF1).unwrap_or(self.len);
            self.drop_front(junk);
            if self.len == 0 {
                return;
            }
            let offset = self.stats.bytes - self.len as u64;
            match check_header(&self.window[..self.len]) {
                Ok(()) if self.len < FRAME_SIZE => return,
                Ok(()) => {
                    let computed = checksum(&self.window[..AT_CHECKSUM]);
                    let found = self.window[AT_CHECKSUM];
                    if computed == found {
                        let frame = SerialFrame::from_checked(&self.window);
                        self.len = 0;
                        self.stats.frames += 1;
                        self.in_sync = true;
                        on_event(StreamEvent::Frame { offset, frame });
                        return;
                    }
                    self.stats.bad_checksum += 1;
                    on_event(StreamEvent::BadChecksum { offset, computed, found });
                }
                Err(SerialError::BadLength { .. }) => self.stats.bad_length += 1,
                Err(SerialError::BadType { .. }) => self.stats.bad_type += 1,
                // A lone 0x5A is too common in data to count.
                Err(_) => {}
            }
            // Failed candidate: give up only its first byte; a frame may start inside it.
            self.drop_front(1);
        }
    }

    fn drop_front(&mut self, count: usize) {
        self.window.copy_within(count..self.len, 0);
        self.len -= count;
        self.skip(count);
    }

    /// Counts skipped bytes; skipping right after a good frame is a loss of sync.
    fn skip(&mut self, count: usize) {
        if count > 0 && self.in_sync {
            self.stats.sync_losses += 1;
            self.in_sync = false;
        }
        self.stats.skipped_bytes += count as u64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::LightMode;

    fn bytes(text: &str) -> Vec<u8> {
        hex::decode(text.replace(' ', "")).unwrap()
    }

    fn frame(text: &str) -> SerialFrame {
        SerialFrame::from_bytes(&bytes(text)).unwrap()
    }

    /// Feeds `chunks` and returns the events and the final stats.
    fn run<'a>(chunks: impl IntoIterator<Item = &'a [u8]>) -> (Vec<StreamEvent>, StreamStats) {
        let mut decoder = StreamDecoder::new();
        let mut events = Vec::new();
        for chunk in chunks {
            decoder.feed(chunk, |event| events.push(event));
        }
        let stats = decoder.finish();
        assert_eq!(stats.bytes, stats.frames * 13 + stats.skipped_bytes, "{stats:?}");
        (events, stats)
    }

    const MANUAL: &str = "5A A5 0A 55 01 02 00 0A 00 00 00 00 6B";
    const BACK_10: &str = "5A A5 0A 55 01 02 00 F6 00 00 00 01 58";
    const LIGHT_50: &str = "5A A5 0A 55 02 01 03 32 00 00 00 00 96";

    #[test]
    fn manual_example_decodes_and_reencodes() {
        let frame = frame(MANUAL);
        assert_eq!(frame.id(), 0x5501);
        let decoded = decode(&frame).unwrap();
        assert_eq!(decoded.wire, Wire::Serial);
        let Message::PercentMotionCommand(cmd) = decoded.message else { panic!("{decoded:?}") };
        assert_eq!(cmd.control_mode, MODE_SERIAL);
        assert_eq!(cmd.fault_clear, 0);
        assert_eq!(cmd.linear_percent, 10);
        assert_eq!(cmd.linear_mm_s(), 150);
        assert_eq!(cmd.linear(), 0.15);
        assert_eq!(cmd.angular_percent, 0);
        assert_eq!(cmd.angular(), 0.0);
        assert_eq!(cmd.count, 0);
        assert_eq!(encode(&decoded.message, 0).unwrap().to_bytes().to_vec(), bytes(MANUAL));
    }

    #[test]
    fn reverse_and_light_examples_round_trip() {
        let back = decode(&frame(BACK_10)).unwrap().message;
        let Message::PercentMotionCommand(cmd) = back else { panic!("{back:?}") };
        assert_eq!((cmd.linear_percent, cmd.linear_mm_s(), cmd.count), (-10, -150, 1));
        assert_eq!(encode(&back, 1).unwrap().to_bytes().to_vec(), bytes(BACK_10));

        let light = decode(&frame(LIGHT_50)).unwrap().message;
        let expected = Lights { front_brightness: 50, ..Lights::front(LightMode::Custom, 50).unwrap() };
        assert_eq!(light, Message::LightCommand(expected));
        assert_eq!(encode(&light, 0).unwrap().to_bytes().to_vec(), bytes(LIGHT_50));
    }

    #[test]
    fn system_status_battery_and_faults() {
        // Normal, serial mode, 25.9 V (0x0103), driver over-temperature protection (byte 5 bit 6), id 7.
        let raw = bytes("5A A5 0A AA 01 00 02 01 03 00 40 07 01");
        let decoded = decode(&SerialFrame::from_bytes(&raw).unwrap()).unwrap();
        let Message::SystemState(state) = decoded.message else { panic!("{decoded:?}") };
        assert_eq!(state.vehicle_state, VEHICLE_NORMAL);
        assert_eq!(state.control_mode, MODE_SERIAL);
        assert_eq!(state.battery_decivolts, 259);
        assert_eq!(state.battery_voltage(), 25.9);
        assert_eq!(state.fault_code, 0x0040);
        assert_eq!(state.count, 7);
        let names: Vec<_> = state.faults(Wire::Serial).iter().map(|flag| flag.name).collect();
        assert_eq!(names, ["driver_overheat_protection"]);
        // Byte 4 is the high byte: 0x0800 is the battery warning of the V1/serial table.
        let warning = SystemState { fault_code: 0x0800, ..state };
        let names: Vec<_> = warning.faults(Wire::Serial).iter().map(|flag| flag.name).collect();
        assert_eq!(names, ["battery_undervoltage_warning"]);
    }

    #[test]
    fn feedback_frames_decode() {
        let motion = decode(&frame("5A A5 0A AA 02 FF 6A 00 64 00 00 03 85")).unwrap().message;
        assert_eq!(
            motion,
            Message::MotionState(MotionState { linear_mm_s: -150, angular_mrad_s: 100, count: 3 })
        );
        // Motor 2: 12.3 A, -1000 rpm, driver -5 °C.
        let motor = decode(&frame("5A A5 0A AA 04 00 7B FC 18 FB 00 09 4A")).unwrap().message;
        let expected = MotorDriverState {
            motor: 2,
            current_deciamps: 123,
            rpm: -1000,
            driver_temperature: -5,
            count: 9,
        };
        assert_eq!(motor, Message::MotorDriverState(expected));
        let light = decode(&frame("5A A5 0A AA 07 01 02 00 00 00 00 00 BD")).unwrap().message;
        let expected = Lights { enable: 1, front_mode: LIGHT_BREATH, ..Lights::default() };
        assert_eq!(light, Message::LightState(expected));
    }

    #[test]
    fn unknown_commands_are_frames_but_not_messages() {
        let unknown = SerialFrame { frame_type: TYPE_FEEDBACK, command: 0x05, payload: [1; 6], frame_id: 0 };
        let parsed = SerialFrame::from_bytes(&unknown.to_bytes()).unwrap();
        assert_eq!(parsed, unknown);
        assert_eq!(parsed.id(), 0xAA05);
        assert_eq!(decode(&parsed), None);
    }

    #[test]
    fn from_bytes_reports_what_is_wrong() {
        let good = bytes(MANUAL);
        let with = |at: usize, value: u8| {
            let mut raw = good.clone();
            raw[at] = value;
            SerialFrame::from_bytes(&raw).unwrap_err().to_string()
        };
        assert_eq!(with(12, 0x6C), "checksum mismatch: computed 0x6B, frame carries 0x6C");
        assert_eq!(with(2, 0x0B), "length byte 0x0B: TRACER frames have 0x0A");
        assert_eq!(with(3, 0x12), "frame type 0x12 is neither control (0x55) nor feedback (0xAA)");
        assert_eq!(with(1, 0x5A), "bad start of frame: 0x5A 0x5A, expected 0x5A 0xA5");
        let short = SerialFrame::from_bytes(&good[..12]).unwrap_err();
        assert_eq!(short, SerialError::TooShort { got: 12 });
        assert_eq!(short.to_string(), "need 13 bytes, got 12");
        let mut long = good.clone();
        long.push(0);
        assert_eq!(SerialFrame::from_bytes(&long), Err(SerialError::TooLong { got: 14 }));
        assert_eq!(SerialFrame::from_bytes(&[]), Err(SerialError::TooShort { got: 0 }));
    }

    #[test]
    fn checksum_is_sum_mod_256() {
        assert_eq!(checksum(&bytes(MANUAL)[..12]), 0x6B);
        assert_eq!(checksum(&[0xFF, 0x02]), 0x01);
        assert_eq!(checksum(&[]), 0);
    }

    #[test]
    fn v2_only_messages_have_no_serial_form() {
        let messages = [
            Message::MotionCommand(MotionCommand::STOP),
            Message::ControlModeCommand(MODE_CAN),
            Message::FaultClear(CLEAR_ALL),
            Message::VersionRequest,
            Message::RcState(RcState::default()),
            Message::MotorHighSpeed(MotorHighSpeed::default()),
            Message::MotorLowSpeed(MotorLowSpeed::default()),
            Message::Odometry(Odometry::default()),
            Message::VersionResponse(VersionResponse::default()),
            // TRACER has no motor 3.
            Message::MotorDriverState(MotorDriverState { motor: 3, ..MotorDriverState::default() }),
        ];
        for message in messages {
            let error = encode(&message, 0).unwrap_err();
            assert_eq!(error, EncodeError { name: message.name(), wire: "serial" });
        }
    }

    #[test]
    fn encoder_counts_motion_and_light_separately_and_wraps() {
        let motion =
            Message::PercentMotionCommand(PercentMotionCommand::from_si(MODE_SERIAL, 0.15, 0.0).unwrap());
        let light = Message::LightCommand(Lights::front(LightMode::Custom, 50).unwrap());
        let mut encoder = SerialEncoder::new();
        assert_eq!(encoder.encode_next(&motion).unwrap().to_vec(), bytes(MANUAL));
        assert_eq!(encoder.encode_next(&motion).unwrap()[11], 1);
        assert_eq!(encoder.encode_next(&light).unwrap().to_vec(), bytes(LIGHT_50));
        assert_eq!(encoder.encode_next(&motion).unwrap()[11], 2);
        // A refused message does not consume an id.
        assert!(encoder.encode_next(&Message::VersionRequest).is_err());
        assert_eq!(encoder.encode_next(&light).unwrap()[11], 1);
        for expected in 3..=255u8 {
            assert_eq!(encoder.encode_next(&motion).unwrap()[11], expected);
        }
        let wrapped = encoder.encode_next(&motion).unwrap();
        assert_eq!(wrapped[11], 0);
        assert_eq!(wrapped[12], checksum(&wrapped[..12]));
        assert_eq!(encoder.encode_next(&light).unwrap()[11], 2);
    }

    #[test]
    fn stream_resyncs_after_a_false_start() {
        let stream = bytes(&format!("5A {MANUAL}"));
        let (events, stats) = run([stream.as_slice()]);
        assert_eq!(events, [StreamEvent::Frame { offset: 1, frame: frame(MANUAL) }]);
        assert_eq!(stats, StreamStats { bytes: 14, frames: 1, skipped_bytes: 1, ..StreamStats::default() });
    }

    #[test]
    fn bad_checksum_is_reported_and_never_redelivers() {
        let good = frame(BACK_10);
        let stream = bytes(&format!("{MANUAL} 5A A5 0A 55 01 02 00 0A 00 00 00 00 6C {BACK_10}"));
        let (events, stats) = run([stream.as_slice()]);
        assert_eq!(
            events,
            [
                StreamEvent::Frame { offset: 0, frame: frame(MANUAL) },
                StreamEvent::BadChecksum { offset: 13, computed: 0x6B, found: 0x6C },
                StreamEvent::Frame { offset: 26, frame: good },
            ]
        );
        assert_eq!(stats.frames, 2);
        assert_eq!(stats.bad_checksum, 1);
        assert_eq!(stats.skipped_bytes, 13);
        assert_eq!(stats.sync_losses, 1);
    }

    #[test]
    fn frame_inside_a_bad_checksum_candidate_is_found() {
        // A truncated frame (7 bytes) runs into a good one: the candidate fails its checksum, the good
        // frame starting inside it is then found.
        let stream = bytes(&format!("5A A5 0A 55 01 02 00 {LIGHT_50}"));
        let (events, stats) = run([stream.as_slice()]);
        assert!(matches!(events[0], StreamEvent::BadChecksum { offset: 0, .. }), "{events:?}");
        assert_eq!(events[1..], [StreamEvent::Frame { offset: 7, frame: frame(LIGHT_50) }]);
        assert_eq!((stats.frames, stats.bad_checksum, stats.skipped_bytes), (1, 1, 7));
    }

    #[test]
    fn bad_length_and_type_resync_at_the_next_byte() {
        // Length 0x0B, then type 0x12, each followed directly by a real frame.
        let stream = bytes(&format!("5A A5 0B {MANUAL} 5A A5 0A 12 {LIGHT_50}"));
        let (events, stats) = run([stream.as_slice()]);
        assert_eq!(
            events,
            [
                StreamEvent::Frame { offset: 3, frame: frame(MANUAL) },
                StreamEvent::Frame { offset: 20, frame: frame(LIGHT_50) },
            ]
        );
        assert_eq!(
            stats,
            StreamStats {
                bytes: 33,
                frames: 2,
                bad_length: 1,
                bad_type: 1,
                skipped_bytes: 7,
                bad_checksum: 0,
                // The bad-type candidate right after the first frame; the bad length came before any frame.
                sync_losses: 1,
            }
        );
    }

    #[test]
    fn garbage_between_frames_is_counted_exactly() {
        let stream = bytes(&format!("00 FF A5 {MANUAL} 5A 0A 5A 5A 01 {BACK_10} 12 34"));
        let (events, stats) = run([stream.as_slice()]);
        let offsets: Vec<_> = events
            .iter()
            .map(|event| match event {
                StreamEvent::Frame { offset, .. } => *offset,
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(offsets, [3, 21]);
        assert_eq!(stats.skipped_bytes, 3 + 5 + 2);
        assert_eq!(stats.bytes, 36);
        // Noise before the first frame is not a loss; the runs after each frame are.
        assert_eq!(stats.sync_losses, 2);
    }

    #[test]
    fn sync_losses_count_runs_of_noise_after_good_frames_not_bytes() {
        let stream = bytes(&format!("{MANUAL} {MANUAL} 00 11 22 {MANUAL} {MANUAL} 33 {BACK_10} 5A A5"));
        for chunks in [stream.chunks(1).collect::<Vec<_>>(), vec![stream.as_slice()]] {
            let (events, stats) = run(chunks);
            assert_eq!(events.len(), 5);
            // Two runs of noise (3 bytes, 1 byte); the unfinished frame at the end is not a loss.
            assert_eq!((stats.sync_losses, stats.skipped_bytes), (2, 3 + 1 + 2));
        }
    }

    #[test]
    fn one_byte_chunks_equal_whole_feed() {
        let corrupt = "5A A5 0A 55 01 02 00 0A 00 00 00 00 6C";
        let stream =
            bytes(&format!("5A 5A {MANUAL} 5A A5 0B 00 {corrupt} {LIGHT_50} 5A A5 0A 12 {BACK_10} 5A A5 0A"));
        let whole = run([stream.as_slice()]);
        let single = run(stream.chunks(1));
        let uneven = run([&stream[..5], &stream[5..6], &stream[6..30], &stream[30..]]);
        assert_eq!(whole, single);
        assert_eq!(whole, uneven);
        assert_eq!(whole.1.frames, 3);
        assert_eq!(whole.1.bad_checksum, 1);
        assert_eq!(whole.1.bad_length, 1);
        assert_eq!(whole.1.bad_type, 1);
    }

    #[test]
    fn unfinished_frame_at_the_end_is_skipped() {
        let stream = bytes(&format!("{MANUAL} {BACK_10}"));
        let mut decoder = StreamDecoder::new();
        let mut frames = 0;
        decoder.feed(&stream[..20], |_| frames += 1);
        assert_eq!(frames, 1);
        assert_eq!(decoder.stats().skipped_bytes, 0);
        let stats = decoder.finish();
        assert_eq!(stats, StreamStats { bytes: 20, frames: 1, skipped_bytes: 7, ..StreamStats::default() });
    }

    #[test]
    fn finish_counts_rejections_inside_the_unfinished_candidate() {
        // The outer candidate never completes; the bad-length candidate at offset 5 is still counted.
        let stream = bytes("5A A5 0A 55 01 5A A5 0B 00");
        let (events, stats) = run([stream.as_slice()]);
        assert!(events.is_empty());
        assert_eq!(
            stats,
            StreamStats { bytes: 9, bad_length: 1, skipped_bytes: 9, ..StreamStats::default() }
        );
    }
}
