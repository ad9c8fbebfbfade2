//! Short constant texts (field keys) kept in fixed-size blocks: appending one copies the whole block, a
//! couple of vector moves instead of a `memcpy` call, and trims the output back to the text's length.
//! The JSON and text writers append a key per field, several per line. [`push_short`] does the same for
//! any short text: musl's `memcpy` starts with `rep movsq`, tens of cycles for a handful of bytes, and
//! JSON output of the static musl build ran 1.8x slower than glibc's through it (docs/performance.md).

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
        push_short(out, self.as_bytes());
    }
}

/// Appends `bytes`: up to [`BLOCK`] bytes with two overlapping fixed-size moves (no `memcpy` call), longer
/// ones with `extend_from_slice`.
#[inline(always)]
pub fn push_short(out: &mut Vec<u8>, bytes: &[u8]) {
    let len = bytes.len();
    if len > BLOCK {
        return out.extend_from_slice(bytes);
    }
    out.reserve(len);
    let src = bytes.as_ptr();
    // SAFETY: `reserve` left room for `len` bytes after the vector's end. Each pair of moves reads inside
    // `bytes` (a head and a tail of at least the move's size) and writes the same offsets inside that room,
    // together covering every byte of `0..len` at least once, so the `len` bytes counted are initialised.
    unsafe {
        let dst = out.as_mut_ptr().add(out.len());
        match len {
            16.. => move_head_and_tail::<16>(src, dst, len),
            8..=15 => move_head_and_tail::<8>(src, dst, len),
            4..=7 => move_head_and_tail::<4>(src, dst, len),
            1..=3 => {
                *dst = *src;
                *dst.add(len / 2) = *src.add(len / 2);
                *dst.add(len - 1) = *src.add(len - 1);
            }
            0 => {}
        }
        out.set_len(out.len() + len);
    }
}

/// Copies bytes `0..N` and `len-N..len` from `src` to `dst`.
///
/// # Safety
/// `N <= len`, `src` readable and `dst` writable for `len` bytes.
#[inline(always)]
unsafe fn move_head_and_tail<const N: usize>(src: *const u8, dst: *mut u8, len: usize) {
    // SAFETY: both moves lie within the `len` bytes the caller vouches for.
    unsafe {
        let head = src.cast::<[u8; N]>().read_unaligned();
        let tail = src.add(len - N).cast::<[u8; N]>().read_unaligned();
        dst.cast::<[u8; N]>().write_unaligned(head);
        dst.add(len - N).cast::<[u8; N]>().write_unaligned(tail);
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

    #[test]
    fn short_copies_equal_extend_from_slice_at_every_length_and_offset() {
        let source: Vec<u8> = (0..80u8).map(|byte| byte.wrapping_mul(37).wrapping_add(1)).collect();
        for len in 0..=BLOCK + 8 {
            for already in [0, 1, 7, 31] {
                let mut expected = vec![b'x'; already];
                expected.extend_from_slice(&source[3..3 + len]);
                let mut out = vec![b'x'; already];
                out.shrink_to_fit();
                push_short(&mut out, &source[3..3 + len]);
                assert_eq!(out, expected, "len {len} after {already}");
            }
        }
    }
}
