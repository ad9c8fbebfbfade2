//! The firmware version query, both ways AgileX firmware has answered it (protocol-notes 2.13): the
//! Scout V2 manual's request (`VersionRequest`, answered by one `VersionResponse` of four `major.minor`
//! numbers) and the SDK's newer text query on [`ID_VERSION_TEXT`] (answered by frames of eight ASCII
//! characters). Which one TRACER firmware implements is not documented, so both are asked and whichever
//! answers is reported; a robot that answers neither is said to, never guessed at.

use super::can::{self, encode_v2};
use super::id::ID_VERSION_TEXT;
use super::message::VersionResponse;
use super::{CanFrame, Message, ProtocolHint};

/// The SDK stops reading the text answer at this many characters (ten frames).
pub const TEXT_LIMIT: usize = 80;

/// The two requests, in the order they are sent: the manual's, then the SDK's text query.
pub fn requests() -> [CanFrame; 2] {
    let manual = encode_v2(&Message::VersionRequest).expect("the version request has a V2 encoding");
    let text = CanFrame::new(ID_VERSION_TEXT, &[0x01]).expect("a standard identifier, one byte");
    [manual, text]
}

/// What the robot answered to the version requests so far.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct VersionAnswer {
    /// The numeric answer, with the frame it came in.
    pub response: Option<(VersionResponse, CanFrame)>,
    /// The text answer's characters (non-printable bytes as spaces), at most [`TEXT_LIMIT`].
    text: String,
    text_frames: usize,
}

impl VersionAnswer {
    /// Takes any received frame; keeps those that answer a version request. A text request (DLC 1, from
    /// another host or our own echo) is not an answer: the answers carry eight bytes.
    pub fn observe(&mut self, frame: &CanFrame) {
        if !frame.is_standard_data() {
            return;
        }
        if frame.id() == ID_VERSION_TEXT {
            if frame.len() == 8 && self.text.len() < TEXT_LIMIT {
                self.text.extend(frame.data().iter().map(|&byte| printable(byte)));
                self.text_frames += 1;
            }
            return;
        }
        if let Ok(Some(decoded)) = can::decode(frame, ProtocolHint::V2) {
            if let Message::VersionResponse(response) = decoded.message {
                self.response = Some((response, *frame));
            }
        }
    }

    /// True once nothing more is expected: the numeric answer, or the whole text.
    pub fn is_complete(&self) -> bool {
        self.response.is_some() || self.text.len() >= TEXT_LIMIT
    }

    /// True when anything answered.
    pub fn answered(&self) -> bool {
        self.response.is_some() || self.text_frames > 0
    }

    /// The text answer, trimmed; `None` when no text frame came.
    pub fn text(&self) -> Option<&str> {
        (self.text_frames > 0).then(|| self.text.trim())
    }

    /// The answers in words, one line each: `controller hw 1.0, driver hw 1.0, controller sw 1.2, driver
    /// sw 1.3 (41A#0100010001020103)` and `text "..." (N frames)`. Empty when nothing answered.
    pub fn describe(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some((response, frame)) = &self.response {
            lines.push(format!("{} ({frame})", describe_response(response)));
        }
        if let Some(text) = self.text() {
            let frames = self.text_frames;
            lines.push(format!("text \"{text}\" ({frames} frame{})", if frames == 1 { "" } else { "s" }));
        }
        lines
    }
}

/// `controller hw 1.0, driver hw 1.0, controller sw 1.2, driver sw 1.3`.
pub fn describe_response(response: &VersionResponse) -> String {
    format!(
        "controller hw {}, driver hw {}, controller sw {}, driver sw {}",
        major_minor(response.controller_hw),
        major_minor(response.driver_hw),
        major_minor(response.controller_sw),
        major_minor(response.driver_sw)
    )
}

/// `1.2` from `0x0102`: the high byte is the major number.
pub fn major_minor(version: u16) -> String {
    format!("{}.{}", version >> 8, version & 0xFF)
}

/// As the SDK reads the text: printable ASCII kept, anything else a space.
fn printable(byte: u8) -> char {
    if byte.is_ascii_graphic() || byte == b' ' {
        char::from(byte)
    } else {
        ' '
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame from cansend syntax (`ID#HEX`).
    fn frame(text: &str) -> CanFrame {
        let (id, data) = text.split_once('#').unwrap();
        CanFrame::new(u32::from_str_radix(id, 16).unwrap(), &hex::decode(data).unwrap()).unwrap()
    }

    #[test]
    fn both_requests_are_sent_as_the_documents_give_them() {
        let [manual, text] = requests();
        assert_eq!(manual.to_string(), "411#01");
        assert_eq!(text.to_string(), "4A1#01");
    }

    #[test]
    fn the_numeric_answer_is_read_with_its_frame() {
        let mut answer = VersionAnswer::default();
        assert!(!answer.answered());
        answer.observe(&frame("211#00000103000000B1"));
        assert!(!answer.answered());
        answer.observe(&frame("41A#0100020001020103"));
        assert!(answer.is_complete());
        assert_eq!(
            answer.describe(),
            ["controller hw 1.0, driver hw 2.0, controller sw 1.2, driver sw 1.3 (41A#0100020001020103)"]
        );
    }

    #[test]
    fn the_text_answer_is_collected_to_eighty_characters_and_requests_are_not_answers() {
        let mut answer = VersionAnswer::default();
        answer.observe(&frame("4A1#01"));
        assert!(!answer.answered(), "a request is one byte");
        // "HW:V1.0 " then "SW:\x01V2.3\0": a control byte and a NUL become spaces.
        answer.observe(&frame("4A1#48573A56312E3020"));
        answer.observe(&frame("4A1#53573A0156322E33"));
        assert_eq!(answer.text(), Some("HW:V1.0 SW: V2.3"));
        assert!(!answer.is_complete());
        for _ in 0..12 {
            answer.observe(&frame("4A1#4141414141414141"));
        }
        assert!(answer.is_complete());
        assert_eq!(answer.text.len(), TEXT_LIMIT);
        assert_eq!(answer.describe()[0].rsplit('(').next(), Some("10 frames)"));
    }

    #[test]
    fn remote_and_short_frames_are_no_answer() {
        let mut answer = VersionAnswer::default();
        answer.observe(&CanFrame::new_remote(ID_VERSION_TEXT, false, 8).unwrap());
        answer.observe(&frame("41A#0100"));
        assert_eq!(answer, VersionAnswer::default());
        assert_eq!(major_minor(0x0A0B), "10.11");
    }
}
