//! SocketCAN link (Linux): kernel receive timestamps, error frames in words, socket drops counted, and
//! errors that say what to do.

use std::io;
use std::mem::{size_of, zeroed};
use std::os::fd::{AsRawFd, RawFd};
use std::ptr;
use std::sync::Arc;
use std::time::Duration;

use socketcan::{
    CanDataFrame, CanErrorFrame, CanRemoteFrame, CanSocket, EmbeddedFrame, ExtendedId, Id, Socket,
    SocketOptions, StandardId,
};

use super::can_interface::{self, Presence};
use super::{FrameRx, FrameTx, Link, LinkFrame, LinkKind, Received, RxStats};
use crate::candump::{Timestamp, TimestampKind};
use crate::protocol::frame::{EFF_MAX, ERR_FLAG};
use crate::protocol::{CanFrame, FrameKind, Wire};

use libc::{CAN_EFF_FLAG, CAN_RTR_FLAG};

struct SocketTx(Arc<CanSocket>);

impl FrameTx for SocketTx {
    fn send(&self, frame: &LinkFrame) -> io::Result<()> {
        let LinkFrame::Can(frame) = frame else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a serial frame cannot be sent on a CAN link",
            ));
        };
        self.0.write_frame(&to_socketcan(frame)?)
    }
}

/// Our frame as socketcan's, built by its own constructors (the identifier's kind from StandardId or
/// ExtendedId, the RTR and error flags by the frame type). An error frame goes out with all 8 bytes, as the
/// kernel writes error frames.
fn to_socketcan(frame: &CanFrame) -> io::Result<socketcan::CanFrame> {
    let id = || -> Option<Id> {
        if frame.is_extended() {
            ExtendedId::new(frame.id()).map(Id::Extended)
        } else {
            u16::try_from(frame.id()).ok().and_then(StandardId::new).map(Id::Standard)
        }
    };
    let built = match frame.kind() {
        FrameKind::Data => {
            id().and_then(|id| CanDataFrame::new(id, frame.data())).map(socketcan::CanFrame::Data)
        }
        FrameKind::Remote => {
            id().and_then(|id| CanRemoteFrame::new_remote(id, frame.len())).map(socketcan::CanFrame::Remote)
        }
        FrameKind::Error => {
            CanErrorFrame::new_error(frame.id(), frame.data()).ok().map(socketcan::CanFrame::Error)
        }
        FrameKind::Fd => {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "CAN FD frames are not sent on a classic link",
            ))
        }
    };
    // Our frames keep their identifiers and lengths within what these constructors take.
    built.ok_or_else(|| {
        io::Error::new(io::ErrorKind::InvalidInput, format!("{frame} is not a classic CAN frame"))
    })
}

/// The kernel's `can_frame` as our frame.
fn from_raw(raw: &libc::can_frame) -> Option<CanFrame> {
    let len = usize::from(raw.can_dlc.min(8));
    let id = raw.can_id;
    if id & ERR_FLAG != 0 {
        return CanFrame::new_error(id & EFF_MAX & !ERR_FLAG, &raw.data[..len]).ok();
    }
    let extended = id & CAN_EFF_FLAG != 0;
    let bare = if extended { id & EFF_MAX } else { id & 0x7FF };
    if id & CAN_RTR_FLAG != 0 {
        return CanFrame::new_remote(bare, extended, len as u8).ok();
    }
    if extended {
        CanFrame::new_extended(bare, &raw.data[..len]).ok()
    } else {
        CanFrame::new(bare, &raw.data[..len]).ok()
    }
}

struct SocketRx {
    socket: Arc<CanSocket>,
    stats: RxStats,
}

#[repr(C, align(8))]
struct ControlBuffer([u8; 256]);

impl SocketRx {
    /// One `recvmsg` with the kernel timestamp (SO_TIMESTAMPNS) and the drop counter (SO_RXQ_OVFL).
    fn receive(&mut self, fd: RawFd) -> io::Result<Option<Received>> {
        // SAFETY: can_frame and msghdr are plain integers, bytes and pointers, for which all zeros (null
        // pointers) is a valid value; every pointer the kernel reads is set below.
        let mut raw: libc::can_frame = unsafe { zeroed() };
        let mut iov =
            libc::iovec { iov_base: ptr::addr_of_mut!(raw).cast(), iov_len: size_of::<libc::can_frame>() };
        let mut control = ControlBuffer([0; 256]);
        // SAFETY: as above.
        let mut message: libc::msghdr = unsafe { zeroed() };
        message.msg_iov = &mut iov;
        message.msg_iovlen = 1;
        message.msg_control = control.0.as_mut_ptr().cast();
        message.msg_controllen = control.0.len() as _;
        // SAFETY: every pointer in `message` refers to live, correctly sized local buffers.
        let read = unsafe { libc::recvmsg(fd, &mut message, libc::MSG_DONTWAIT) };
        if read < 0 {
            let error = io::Error::last_os_error();
            return match error.kind() {
                io::ErrorKind::WouldBlock => Ok(None),
                _ => Err(explain_io(error, "")),
            };
        }
        if read as usize != size_of::<libc::can_frame>() {
            return Ok(None);
        }
        let mut ts = None;
        // SAFETY: walking the control messages the kernel wrote, with the libc helpers.
        let mut cmsg = unsafe { libc::CMSG_FIRSTHDR(&message) };
        while !cmsg.is_null() {
            // SAFETY: `cmsg` is non-null and was returned by CMSG_FIRSTHDR/CMSG_NXTHDR inside `control`.
            let (level, kind) = unsafe { ((*cmsg).cmsg_level, (*cmsg).cmsg_type) };
            // SAFETY: as above; CMSG_DATA only computes an address inside that header's message.
            let data = unsafe { libc::CMSG_DATA(cmsg) };
            if level == libc::SOL_SOCKET && kind == libc::SO_TIMESTAMPNS {
                // SAFETY: an SO_TIMESTAMPNS message holds one timespec; read unaligned, as the buffer may be.
                let spec = unsafe { ptr::read_unaligned(data.cast::<libc::timespec>()) };
                ts = Some(Timestamp {
                    secs: spec.tv_sec.max(0) as u64,
                    nanos: spec.tv_nsec.clamp(0, 999_999_999) as u32,
                    kind: TimestampKind::Absolute,
                });
            } else if level == libc::SOL_SOCKET && kind == libc::SO_RXQ_OVFL {
                // SAFETY: an SO_RXQ_OVFL message holds one u32.
                let dropped = unsafe { ptr::read_unaligned(data.cast::<u32>()) };
                self.stats.socket_drops = u64::from(dropped);
            }
            // SAFETY: `cmsg` is a header of `message`'s control buffer, as CMSG_NXTHDR requires.
            cmsg = unsafe { libc::CMSG_NXTHDR(&message, cmsg) };
        }
        let Some(frame) = from_raw(&raw) else { return Ok(None) };
        self.stats.frames += 1;
        if frame.kind() == FrameKind::Error {
            self.stats.error_frames += 1;
        }
        Ok(Some(Received { ts: ts.unwrap_or_else(super::now_timestamp), frame: LinkFrame::Can(frame) }))
    }
}

impl FrameRx for SocketRx {
    fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>> {
        let fd = self.socket.as_raw_fd();
        if let Some(received) = self.receive(fd)? {
            return Ok(Some(received));
        }
        let mut poll = libc::pollfd { fd, events: libc::POLLIN, revents: 0 };
        let millis = timeout.as_millis().clamp(1, i32::MAX as u128) as i32;
        // SAFETY: one valid pollfd.
        let ready = unsafe { libc::poll(&mut poll, 1, millis) };
        if ready < 0 {
            let error = io::Error::last_os_error();
            return if error.kind() == io::ErrorKind::Interrupted { Ok(None) } else { Err(error) };
        }
        if ready == 0 {
            return Ok(None);
        }
        self.receive(fd)
    }

    fn stats(&self) -> RxStats {
        self.stats
    }
}

/// Adds what to do to the errors a CAN socket can give.
pub fn explain_io(error: io::Error, iface: &str) -> io::Error {
    let name = if iface.is_empty() { "the interface" } else { iface };
    let hint = match error.raw_os_error() {
        Some(libc::ENETDOWN) if !iface.is_empty() => can_interface::down_message(iface),
        Some(libc::ENETDOWN) => {
            "the interface is down: bring it up with `sudo ip link set IFACE up type can \
                                 bitrate 500000` (a vcan: `sudo ip link set up IFACE`)"
                .to_string()
        }
        Some(libc::ENOBUFS) | Some(libc::EAGAIN) => {
            format!("{name}: {}", super::queue_full_meaning(LinkKind::SocketCan))
        }
        Some(libc::ENODEV) | Some(libc::ENXIO) => format!("{name} has disappeared (adapter unplugged?)"),
        _ => return error,
    };
    io::Error::new(error.kind(), format!("{hint} ({error})"))
}

/// Opens `iface`, checking in order: the kernel has CAN, the interface exists, is CAN, and is up.
pub fn open(iface: &str) -> anyhow::Result<Link> {
    can_interface::kernel_support().map_err(anyhow::Error::msg)?;
    match can_interface::presence(iface) {
        Presence::Missing => anyhow::bail!(can_interface::missing_message(iface)),
        Presence::NotCan => anyhow::bail!(can_interface::not_can_message(iface)),
        Presence::Can { .. } => {}
    }
    if !can_interface::is_up(iface) {
        anyhow::bail!(can_interface::down_message(iface));
    }
    let socket = CanSocket::open(iface).map_err(|error| match error.kind() {
        io::ErrorKind::PermissionDenied => anyhow::anyhow!(
            "permission denied opening a CAN socket on {iface} ({error}): run as a user allowed raw CAN sockets"
        ),
        _ => anyhow::anyhow!("cannot open CAN interface {iface}: {}", explain_io(error, iface)),
    })?;
    socket.set_error_filter_accept_all()?;
    // Never block a sender (the 50 Hz motion sender least of all): a full queue is reported as EAGAIN or
    // ENOBUFS and counted, and the frame is not sent (a motion command queued behind it would be stale).
    socket.set_nonblocking(true)?;
    socket.set_recv_timestamp(true)?;
    let enable: libc::c_int = 1;
    // SAFETY: setsockopt with a valid int option value.
    unsafe {
        libc::setsockopt(
            socket.as_raw_fd(),
            libc::SOL_SOCKET,
            libc::SO_RXQ_OVFL,
            ptr::addr_of!(enable).cast(),
            size_of::<libc::c_int>() as libc::socklen_t,
        );
    }
    let socket = Arc::new(socket);
    Ok(Link {
        name: iface.to_string(),
        kind: LinkKind::SocketCan,
        wire: Wire::CanV2,
        tx: Arc::new(SocketTx(Arc::clone(&socket))),
        rx: Box::new(SocketRx { socket, stats: RxStats::default() }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_convert_both_ways() {
        for frame in [
            CanFrame::new(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]).unwrap(),
            CanFrame::new_extended(0x123, &[0x11]).unwrap(),
            CanFrame::new_remote(0x7FF, false, 5).unwrap(),
            CanFrame::new_error(0x44, &[0, 0, 0, 0, 0, 0, 127, 0]).unwrap(),
        ] {
            let kernel = to_socketcan(&frame).unwrap();
            let raw: &libc::can_frame = kernel.as_ref();
            assert_eq!(from_raw(raw), Some(frame), "{frame}");
        }
    }

    /// The conversion before socketcan's constructors, kept as the reference they must match.
    fn zeroed_can_frame(frame: &CanFrame) -> libc::can_frame {
        // SAFETY: can_frame is plain integers and bytes, for which all zeros is a valid value.
        let mut raw: libc::can_frame = unsafe { zeroed() };
        raw.can_id = match frame.kind() {
            FrameKind::Data if frame.is_extended() => frame.id() | CAN_EFF_FLAG,
            FrameKind::Data => frame.id(),
            FrameKind::Remote => {
                frame.id() | CAN_RTR_FLAG | if frame.is_extended() { CAN_EFF_FLAG } else { 0 }
            }
            FrameKind::Error => frame.id() | ERR_FLAG,
            FrameKind::Fd => unreachable!("refused"),
        };
        raw.can_dlc = frame.len() as u8;
        raw.data[..frame.data().len()].copy_from_slice(frame.data());
        raw
    }

    fn fields(raw: &libc::can_frame) -> (u32, u8, u8, [u8; 8]) {
        (raw.can_id, raw.can_dlc, raw.len8_dlc, raw.data)
    }

    #[test]
    fn socketcan_constructors_build_the_frames_the_zeroed_can_frame_did() {
        for frame in [
            CanFrame::new(0x111, &[]).unwrap(),
            CanFrame::new(0x211, &[0, 0, 1, 3, 0, 0, 0, 0xB1]).unwrap(),
            CanFrame::new(0x7FF, &[0xAA, 0x55, 1]).unwrap(),
            CanFrame::new_extended(0x123, &[0x11]).unwrap(),
            CanFrame::new_extended(0x1FFF_FFFF, &[1, 2, 3, 4, 5, 6, 7, 8]).unwrap(),
            CanFrame::new_remote(0x7FF, false, 5).unwrap(),
            CanFrame::new_remote(0x0, false, 0).unwrap(),
            CanFrame::new_remote(0x18FF_0001, true, 8).unwrap(),
            CanFrame::new_error(0x44, &[0, 0, 0, 0, 0, 0, 127, 0]).unwrap(),
            CanFrame::new_error(0x1FFF_FFFF, &[0xFF; 8]).unwrap(),
        ] {
            let built = to_socketcan(&frame).unwrap();
            assert_eq!(fields(built.as_ref()), fields(&zeroed_can_frame(&frame)), "{frame}");
        }
    }

    #[test]
    fn a_short_error_frame_goes_out_with_8_bytes_and_fd_is_refused() {
        // The one difference from the zeroed can_frame: its length was the frame's, socketcan's is the
        // kernel's 8 for every error frame (the same identifier, the missing bytes zero as before).
        let short = CanFrame::new_error(0x40, &[0, 4]).unwrap();
        let built = to_socketcan(&short).unwrap();
        let (id, dlc, _, data) = fields(built.as_ref());
        let (old_id, old_dlc, _, old_data) = fields(&zeroed_can_frame(&short));
        assert_eq!((id, dlc, data), (old_id, 8, old_data));
        assert_eq!((id, old_dlc), (0x2000_0040, 2));

        let fd = CanFrame::new_fd(0x123, false, 0, &[0; 12]).unwrap();
        let error = to_socketcan(&fd).unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::InvalidInput);
        assert_eq!(error.to_string(), "CAN FD frames are not sent on a classic link");
    }

    #[test]
    fn a_kernel_without_can_gets_a_message_that_says_what_to_do() {
        // This machine's kernel has no CAN; on one with CAN the interface does not exist. Either way the
        // error names the fix.
        let error = open("tracerctl-no-such0").err().expect("cannot open").to_string();
        assert!(
            error.contains("modprobe can can-raw") || error.contains("ip -br link show type can"),
            "{error}"
        );
    }
}
