//! Short constant texts (field keys) kept in fixed-size blocks: appending one copies the whole block, a
//! couple of vector moves instead of a `memcpy` call, and trims the output back to the text's length.
//! The JSON and text writers append a key per field, several per line.

use crate::protocol::fields::ALL_FIELD_NAMES;

/// A block's size: the longest field key (`"right_wheel_odometer":`, 23 bytes) fits.
const BLOCK: usize = 32;

#[derive(Clone, Copy, Debug)]
pub struct ShortText {
    block: [u8; BLOCK],
    len: u8,
}

impl ShortText {
    /// `prefix`, `text` and `suffix` in one block; a text longer than a block fails the build (const
    /// evaluation of the tables below).
    pub const fn new(prefix: &str, text: &str, suffix: &str) -> Self {
        let mut block = [0u8; BLOCK];
        let mut len = 0;
        let parts = [prefix.as_bytes(), text.as_bytes(), suffix.as_bytes()];
        let mut part = 0;
        while part < parts.len() {
            let bytes = parts[part];
            let mut index = 0;
            while index < bytes.len() {
                assert!(len < BLOCK, "a short text is longer than its block");
                block[len] = bytes[index];
                len += 1;
                index += 1;
            }
            part += 1;
        }
        Self { block, len: len as u8 }
    }

    pub fn as_bytes(&self) -> &[u8] {
        &self.block[..usize::from(self.len)]
    }

    #[inline(always)]
    pub fn push_to(&self, out: &mut Vec<u8>) {
        let len = out.len();
        out.extend_from_slice(&self.block);
        out.truncate(len + usize::from(self.len));
    }
}

/// `prefix + name + suffix` for every field name, indexed by [`crate::protocol::FieldName::column`].
pub const fn field_keys(prefix: &str, suffix: &str) -> [ShortText; ALL_FIELD_NAMES.len()] {
    let mut keys = [ShortText { block: [0; BLOCK], len: 0 }; ALL_FIELD_NAMES.len()];
    let mut index = 0;
    while index < keys.len() {
        keys[index] = ShortText::new(prefix, ALL_FIELD_NAMES[index], suffix);
        index += 1;
    }
    keys
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_the_names_with_their_prefix_and_suffix() {
        let keys = field_keys(",\"", "\":");
        for (key, name) in keys.iter().zip(ALL_FIELD_NAMES) {
            assert_eq!(key.as_bytes(), format!(",\"{name}\":").as_bytes());
            let mut out = b"before".to_vec();
            key.push_to(&mut out);
            assert_eq!(out, format!("before,\"{name}\":").as_bytes());
        }
        assert_eq!(ShortText::new("", "", "").as_bytes(), b"");
    }
}
