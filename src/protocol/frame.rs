//! The project's own CAN frame type: small, `Copy`, and free of any socket library's types, so the
//! protocol module stays pure and the candump reader, the links and the simulator all share it.

use std::fmt;

use super::id::FrameId;

/// Largest standard (11-bit) identifier.
pub const SFF_MAX: u32 = 0x7FF;
/// Largest extended (29-bit) identifier.
pub const EFF_MAX: u32 = 0x1FFF_FFFF;
/// Bit 29 of a raw SocketCAN id marks an error frame.
pub const ERR_FLAG: u32 = 0x2000_0000;
/// Largest payload of a classic CAN frame.
pub const CC_MAX_LEN: usize = 8;
/// Largest payload of a CAN FD frame.
pub const FD_MAX_LEN: usize = 64;
/// Payload lengths a CAN FD frame may have.
pub const FD_LENGTHS: [u8; 16] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64];

/// What kind of frame this is. Only `Data` frames carry TRACER messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameKind {
    /// Classic CAN data frame (0..=8 bytes).
    Data,
    /// Classic CAN remote-transmission request; `len` is the requested length, no data.
    Remote,
    /// A SocketCAN error frame; `id` holds the error-class bits (without `ERR_FLAG`).
    Error,
    /// CAN FD frame (0..=64 bytes, lengths from `FD_LENGTHS`).
    Fd,
}

/// Why a frame could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    #[error("identifier 0x{id:X} does not fit in 11 bits (standard frame)")]
    StandardIdTooLarge { id: u32 },
    #[error("identifier 0x{id:X} does not fit in 29 bits (extended frame)")]
    ExtendedIdTooLarge { id: u32 },
    #[error("{len} data bytes: a classic CAN frame carries at most 8")]
    TooLong { len: usize },
    #[error("{len} data bytes is not a valid CAN FD length (0-8, 12, 16, 20, 24, 32, 48, 64)")]
    BadFdLength { len: usize },
    #[error("raw DLC {dlc:X} is only meaningful with 8 data bytes and must be 9..F")]
    BadRawDlc { dlc: u8 },
}

/// A CAN frame as seen on the bus or in a log.
///
/// Invariants (enforced by the constructors): `id` fits the frame format; `len` fits the kind;
/// bytes of `data` past `len` are zero, so derived equality compares only real content.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct CanFrame {
    id: u32,
    extended: bool,
    kind: FrameKind,
    len: u8,
    /// Raw DLC 9..=15 of a classic 8-byte frame (candump's `_X` suffix), 0 when absent.
    raw_dlc: u8,
    /// CAN FD flags nibble (BRS=1, ESI=2, FDF=4); 0 for classic frames.
    fd_flags: u8,
    data: [u8; FD_MAX_LEN],
}

impl CanFrame {
    /// A classic data frame with a standard (11-bit) identifier.
    pub fn new(id: u32, data: &[u8]) -> Result<Self, FrameError> {
        if id > SFF_MAX {
            return Err(FrameError::StandardIdTooLarge { id });
        }
        Self::build(id, false, FrameKind::Data, data)
    }

    /// A classic data frame with an extended (29-bit) identifier.
    pub fn new_extended(id: u32, data: &[u8]) -> Result<Self, FrameError> {
        if id > EFF_MAX {
            return Err(FrameError::ExtendedIdTooLarge { id });
        }
        Self::build(id, true, FrameKind::Data, data)
    }

    /// A remote-transmission request asking for `len` bytes.
    pub fn new_remote(id: u32, extended: bool, len: u8) -> Result<Self, FrameError> {
        check_id(id, extended)?;
        if len as usize > CC_MAX_LEN {
            return Err(FrameError::TooLong { len: len as usize });
        }
        let mut frame = Self::build(id, extended, FrameKind::Remote, &[])?;
        frame.len = len;
        Ok(frame)
    }

    /// A SocketCAN error frame; `class` is the error-class mask (bit 29 already removed).
    pub fn new_error(class: u32, data: &[u8]) -> Result<Self, FrameError> {
        Self::build(class & EFF_MAX, true, FrameKind::Error, data)
    }

    /// A CAN FD frame; `flags` is the candump flags nibble.
    pub fn new_fd(id: u32, extended: bool, flags: u8, data: &[u8]) -> Result<Self, FrameError> {
        check_id(id, extended)?;
        if !FD_LENGTHS.contains(&(data.len().min(255) as u8)) || data.len() > FD_MAX_LEN {
            return Err(FrameError::BadFdLength { len: data.len() });
        }
        let mut frame = Self {
            id,
            extended,
            kind: FrameKind::Fd,
            len: data.len() as u8,
            raw_dlc: 0,
            fd_flags: flags & 0x0F,
            data: [0; FD_MAX_LEN],
        };
        frame.data[..data.len()].copy_from_slice(data);
        Ok(frame)
    }

    /// Record the raw DLC (9..=15) of a classic 8-byte data or remote frame.
    pub fn with_raw_dlc(mut self, dlc: u8) -> Result<Self, FrameError> {
        let eligible = matches!(self.kind, FrameKind::Data | FrameKind::Remote) && self.len == 8;
        if !eligible || !(9..=15).contains(&dlc) {
            return Err(FrameError::BadRawDlc { dlc });
        }
        self.raw_dlc = dlc;
        Ok(self)
    }

    /// Makes this frame, in place, a classic data frame of the first `len` bytes of `payload` (the rest
    /// of `payload` is ignored). The log parser's hot path rewrites one frame for every line: a frame
    /// built and returned was copied through the stack several times (measured: a fifth of `-j1
    /// --summary`'s time, much of it loads stalled on the narrower stores just made).
    #[inline(always)]
    pub fn set_classic_data(
        &mut self,
        id: u32,
        extended: bool,
        payload: [u8; CC_MAX_LEN],
        len: usize,
    ) -> Result<(), FrameError> {
        check_id(id, extended)?;
        if len > CC_MAX_LEN {
            return Err(FrameError::TooLong { len });
        }
        // The bytes past `len` stay zero: those of `payload` are masked off, and those past 8 are zero
        // already unless this was a longer (FD) frame.
        if usize::from(self.len) > CC_MAX_LEN {
            self.data = [0; FD_MAX_LEN];
        }
        let keep = u64::MAX.checked_shr(8 * (CC_MAX_LEN - len) as u32).unwrap_or(0);
        let payload = (u64::from_le_bytes(payload) & keep).to_le_bytes();
        if let Some(first) = self.data.first_chunk_mut::<CC_MAX_LEN>() {
            *first = payload;
        }
        self.id = id;
        self.extended = extended;
        self.kind = FrameKind::Data;
        self.len = len as u8;
        self.raw_dlc = 0;
        self.fd_flags = 0;
        Ok(())
    }

    fn build(id: u32, extended: bool, kind: FrameKind, data: &[u8]) -> Result<Self, FrameError> {
        if data.len() > CC_MAX_LEN {
            return Err(FrameError::TooLong { len: data.len() });
        }
        let mut frame = Self {
            id,
            extended,
            kind,
            len: data.len() as u8,
            raw_dlc: 0,
            fd_flags: 0,
            data: [0; FD_MAX_LEN],
        };
        frame.data[..data.len()].copy_from_slice(data);
        Ok(frame)
    }

    /// The identifier (11 or 29 bits; error-class bits for error frames).
    pub fn id(&self) -> u32 {
        self.id
    }
    /// The identifier with its kind (standard or extended), printed and ordered one way (an error frame's is
    /// its error-class bits, as an extended identifier).
    pub fn frame_id(&self) -> FrameId {
        if self.is_extended() {
            FrameId::Extended(self.id & EFF_MAX)
        } else {
            FrameId::standard(self.id)
        }
    }
    /// True for 29-bit identifiers (error frames are always extended).
    pub fn is_extended(&self) -> bool {
        self.extended
    }
    pub fn kind(&self) -> FrameKind {
        self.kind
    }
    /// Payload length; for remote frames the requested length.
    pub fn len(&self) -> usize {
        self.len as usize
    }
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The payload (empty for remote frames).
    pub fn data(&self) -> &[u8] {
        match self.kind {
            FrameKind::Remote => &[],
            _ => &self.data[..self.len as usize],
        }
    }
    /// Raw DLC 9..=15 if the log recorded one.
    pub fn raw_dlc(&self) -> Option<u8> {
        (self.raw_dlc != 0).then_some(self.raw_dlc)
    }
    /// CAN FD flags nibble.
    pub fn fd_flags(&self) -> u8 {
        self.fd_flags
    }
    /// True for a classic data frame with a standard identifier: the only kind a TRACER sends.
    pub fn is_standard_data(&self) -> bool {
        self.kind == FrameKind::Data && !self.extended
    }

    /// Write the frame in candump/cansend syntax (`211#00000103000000B1`), as `candump -L` does.
    pub fn write_cansend(&self, out: &mut impl fmt::Write) -> fmt::Result {
        const HEX: &[u8; 16] = b"0123456789ABCDEF";
        match self.kind {
            FrameKind::Error => write!(out, "{:08X}#", self.id | ERR_FLAG)?,
            _ if self.extended => write!(out, "{:08X}#", self.id)?,
            _ => write!(out, "{:03X}#", self.id)?,
        }
        match self.kind {
            FrameKind::Remote => {
                out.write_char('R')?;
                if self.len > 0 {
                    write!(out, "{}", self.len)?;
                }
                if let Some(dlc) = self.raw_dlc() {
                    write!(out, "_{dlc:X}")?;
                }
                return Ok(());
            }
            FrameKind::Fd => write!(out, "#{:X}", self.fd_flags)?,
            FrameKind::Data | FrameKind::Error => {}
        }
        for byte in self.data() {
            out.write_char(HEX[(byte >> 4) as usize] as char)?;
            out.write_char(HEX[(byte & 0xF) as usize] as char)?;
        }
        if let Some(dlc) = self.raw_dlc() {
            write!(out, "_{dlc:X}")?;
        }
        Ok(())
    }
}

fn check_id(id: u32, extended: bool) -> Result<(), FrameError> {
    match extended {
        false if id > SFF_MAX => Err(FrameError::StandardIdTooLarge { id }),
        true if id > EFF_MAX => Err(FrameError::ExtendedIdTooLarge { id }),
        _ => Ok(()),
    }
}

/// An empty classic data frame with identifier 0: a slot to be rewritten (see
/// [`CanFrame::set_classic_data`]).
impl Default for CanFrame {
    fn default() -> Self {
        Self {
            id: 0,
            extended: false,
            kind: FrameKind::Data,
            len: 0,
            raw_dlc: 0,
            fd_flags: 0,
            data: [0; FD_MAX_LEN],
        }
    }
}

impl fmt::Display for CanFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write_cansend(f)
    }
}

impl fmt::Debug for CanFrame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CanFrame({self})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn of_can_frames() {
        let standard = CanFrame::new(0x211, &[]).unwrap();
        assert_eq!(standard.frame_id(), FrameId::Standard(0x211));
        let extended = CanFrame::new_extended(0x1234ABCD, &[]).unwrap();
        assert_eq!(extended.frame_id(), FrameId::Extended(0x1234ABCD));
        assert_eq!(extended.frame_id().value(), 0x1234ABCD);
    }

    /// A frame rewritten in place equals the one built new, whatever it was before (a longer FD frame, a
    /// remote request, an error frame), and the payload bytes past the length are dropped.
    #[test]
    fn a_frame_rewritten_in_place_equals_a_new_one() {
        let payload = [0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88];
        let before = [
            CanFrame::default(),
            CanFrame::new_fd(0x123, true, 0x5, &[0xEE; 64]).unwrap(),
            CanFrame::new_remote(0x7FF, false, 8).unwrap().with_raw_dlc(12).unwrap(),
            CanFrame::new_extended(0x1FFF_FFFF, &payload).unwrap(),
            CanFrame::new_error(0x80, &payload).unwrap(),
        ];
        for start in before {
            for len in 0..=CC_MAX_LEN {
                for (id, extended) in [(0x211, false), (0x7FF, false), (0x1234_5678, true)] {
                    let mut frame = start;
                    frame.set_classic_data(id, extended, payload, len).unwrap();
                    let new = match extended {
                        false => CanFrame::new(id, &payload[..len]),
                        true => CanFrame::new_extended(id, &payload[..len]),
                    };
                    assert_eq!(Ok(frame), new, "{start:?} {len} {id:#x}");
                    assert!(frame.data[len..].iter().all(|&byte| byte == 0), "{frame:?}");
                }
            }
            let mut frame = start;
            assert!(frame.set_classic_data(0x800, false, payload, 8).is_err());
            assert!(frame.set_classic_data(0x211, false, payload, 9).is_err());
            assert_eq!(frame, start, "a refused rewrite leaves the frame as it was");
        }
    }

    #[test]
    fn cansend_syntax_round_trips_every_kind() {
        let cases = [
            (CanFrame::new(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]).unwrap(), "211#00000103000000B1"),
            (CanFrame::new(0x123, &[]).unwrap(), "123#"),
            (CanFrame::new_extended(0x123, &[0x11]).unwrap(), "00000123#11"),
            (CanFrame::new_remote(0x123, false, 5).unwrap(), "123#R5"),
            (CanFrame::new_remote(0x123, false, 0).unwrap(), "123#R"),
            (CanFrame::new_error(0x4, &[0, 8, 0, 0, 0, 0, 0x78, 0]).unwrap(), "20000004#0008000000007800"),
            (CanFrame::new_fd(0x151, false, 5, &[1, 2]).unwrap(), "151##50102"),
            (CanFrame::new(0x123, &[0x11; 8]).unwrap().with_raw_dlc(0xE).unwrap(), "123#1111111111111111_E"),
        ];
        for (frame, text) in cases {
            assert_eq!(frame.to_string(), text);
        }
    }

    #[test]
    fn constructors_reject_out_of_range_values() {
        assert_eq!(CanFrame::new(0x800, &[]), Err(FrameError::StandardIdTooLarge { id: 0x800 }));
        assert_eq!(CanFrame::new(0x1, &[0; 9]), Err(FrameError::TooLong { len: 9 }));
        assert!(CanFrame::new_extended(0x2000_0000, &[]).is_err());
        assert_eq!(CanFrame::new_fd(1, false, 4, &[0; 9]), Err(FrameError::BadFdLength { len: 9 }));
        assert!(CanFrame::new(1, &[0; 7]).unwrap().with_raw_dlc(9).is_err());
        assert!(CanFrame::new(1, &[0; 8]).unwrap().with_raw_dlc(8).is_err());
    }

    #[test]
    fn remote_frames_have_no_payload_but_keep_their_length() {
        let frame = CanFrame::new_remote(0x7FF, false, 8).unwrap();
        assert_eq!(frame.len(), 8);
        assert!(frame.data().is_empty());
    }
}
