//! RS232 link: 115200 8N1 `5A A5` frames through serialport, reading and writing at once.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use parking_lot::Mutex;
use serialport::SerialPort;

#[cfg(not(windows))]
use super::serial_access::device_access;
use super::serial_access::{permission_denied_text, DeviceAccess};
use super::{now_timestamp, Discarded, FrameRx, FrameTx, Link, LinkFrame, LinkKind, Received, RxStats};
use crate::protocol::serial::{StreamDecoder, StreamEvent};
use crate::protocol::Wire;

/// Writes must not stall the 50 Hz sender: a frame takes about 1.1 ms at 115200 baud, so a write that
/// cannot finish in 10 ms is facing a full queue (a peer that does not read), and waiting longer helps
/// nothing.
const WRITE_TIMEOUT: Duration = Duration::from_millis(10);

struct SerialTx {
    port: Mutex<Box<dyn SerialPort>>,
    /// The terminal side of a pseudo-terminal (the simulator, socat, a test's fake robot), not a UART.
    pseudo_terminal: bool,
}

impl FrameTx for SerialTx {
    fn send(&self, frame: &LinkFrame) -> io::Result<()> {
        let LinkFrame::Serial(frame) = frame else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a CAN frame cannot be sent on a serial link",
            ));
        };
        let mut port = self.port.lock();
        // No flush: serialport's flush is tcdrain, which waits (holding this lock) until a peer that does not
        // read has taken everything, and the stop frames would wait behind it. The write times out instead.
        port.write_all(&frame.to_bytes())
    }

    fn pending(&self) -> Option<usize> {
        let port = self.port.lock();
        port.bytes_to_write().ok().map(|bytes| (bytes as usize).div_ceil(FRAME_LEN))
    }

    fn discard_pending(&self) -> Discarded {
        let port = self.port.lock();
        // TIOCOUTQ then TCOFLUSH. A UART or USB adapter reports and drops its whole queue. A pseudo-terminal
        // reports 0 and drops what its peer's line discipline has not taken in yet: the backlog of a peer that
        // stopped reading, but also frames just written to a peer that reads (slowly, on a loaded machine),
        // which nothing can count, so the discard is reported as uncounted rather than as none.
        let queued = port.bytes_to_write().unwrap_or(0) as usize;
        let _ = port.clear(serialport::ClearBuffer::Output);
        Discarded { frames: queued.div_ceil(FRAME_LEN), uncounted: self.pseudo_terminal }
    }
}

/// Bytes in one RS232 frame.
const FRAME_LEN: usize = 13;
/// At the end, how long what is queued may take to leave before it is dropped (so that closing the port
/// does not wait the tty's 30 s closing time for a peer that does not read).
const CLOSE_DRAIN: Duration = Duration::from_millis(300);

impl Drop for SerialTx {
    fn drop(&mut self) {
        let port = self.port.lock();
        let deadline = std::time::Instant::now() + CLOSE_DRAIN;
        let queued = || port.bytes_to_write().is_ok_and(|queued| queued > 0);
        while queued() && std::time::Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        // Only a queue the driver reports as stuck: a pseudo-terminal reports none, and what it still holds
        // (the stop frames, for a peer that reads later) must not be thrown away.
        if queued() {
            let _ = port.clear(serialport::ClearBuffer::Output);
        }
    }
}

struct SerialRx {
    port: Box<dyn SerialPort>,
    decoder: StreamDecoder,
    ready: VecDeque<Received>,
    buffer: Vec<u8>,
    stats: RxStats,
    /// A pseudo-terminal master reports EIO while no one has the other end open: wait, don't fail.
    tolerate_hangup: bool,
}

impl FrameRx for SerialRx {
    fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>> {
        if let Some(received) = self.ready.pop_front() {
            return Ok(Some(received));
        }
        self.port.set_timeout(timeout.max(Duration::from_millis(1))).map_err(io::Error::from)?;
        let read = match self.port.read(&mut self.buffer) {
            Ok(0) => return Ok(None),
            Ok(read) => read,
            Err(error) if error.kind() == io::ErrorKind::TimedOut => return Ok(None),
            // A signal (Ctrl-C, SIGTERM, SIGHUP) interrupted the wait (poll is never restarted): not a link
            // failure. The caller looks at its signal flag and ends with 128 + the signal.
            Err(error) if error.kind() == io::ErrorKind::Interrupted => return Ok(None),
            // A pseudo-terminal with nobody on the other side reports a hang-up (EIO, or POLLHUP which
            // serialport turns into BrokenPipe): wait for a client instead of failing.
            Err(error)
                if self.tolerate_hangup
                    && (error.kind() == io::ErrorKind::BrokenPipe
                        || error.raw_os_error() == Some(libc::EIO)) =>
            {
                std::thread::sleep(timeout.min(Duration::from_millis(20)));
                return Ok(None);
            }
            Err(error) => return Err(error),
        };
        let ts = now_timestamp();
        let (ready, stats) = (&mut self.ready, &mut self.stats);
        self.decoder.feed(&self.buffer[..read], |event| match event {
            StreamEvent::Frame { frame, .. } => {
                stats.frames += 1;
                ready.push_back(Received { ts, frame: LinkFrame::Serial(frame) });
            }
            StreamEvent::BadChecksum { .. } => stats.serial_bad_checksum += 1,
        });
        let stream = self.decoder.stats();
        self.stats.serial_skipped_bytes = stream.skipped_bytes;
        self.stats.serial_bytes = stream.bytes;
        self.stats.serial_sync_losses = stream.sync_losses;
        Ok(self.ready.pop_front())
    }

    fn stats(&self) -> RxStats {
        self.stats
    }
}

/// Wraps an open port (a real one, or one end of a pseudo-terminal pair).
pub fn from_port(port: Box<dyn SerialPort>, name: &str, tolerate_hangup: bool) -> anyhow::Result<Link> {
    let mut writer = port.try_clone().map_err(|error| anyhow::anyhow!("cannot share {name}: {error}"))?;
    writer.set_timeout(WRITE_TIMEOUT)?;
    let rx = SerialRx {
        port,
        decoder: StreamDecoder::new(),
        ready: VecDeque::new(),
        buffer: vec![0; 4096],
        stats: RxStats::default(),
        tolerate_hangup,
    };
    Ok(Link {
        name: name.to_string(),
        kind: LinkKind::Serial,
        wire: Wire::Serial,
        tx: Arc::new(SerialTx {
            pseudo_terminal: is_pseudo_terminal(writer.name()),
            port: Mutex::new(writer),
        }),
        rx: Box::new(rx),
    })
}

/// Whether `path` is the terminal side of a UNIX98 pseudo-terminal (character devices of majors 136-143).
fn is_pseudo_terminal(path: Option<String>) -> bool {
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::{FileTypeExt, MetadataExt};
        path.and_then(|path| std::fs::metadata(path).ok()).is_some_and(|metadata| {
            metadata.file_type().is_char_device() && (136..=143).contains(&libc::major(metadata.rdev()))
        })
    }
    #[cfg(not(target_os = "linux"))]
    {
        path.is_some_and(|path| path.starts_with("/dev/pts/"))
    }
}

/// Opens a serial port at `baud`, 8N1, no flow control, with errors that say what to do.
pub fn open(path: &Path, baud: u32) -> anyhow::Result<Link> {
    let name = path.display().to_string();
    let port = serialport::new(name.clone(), baud)
        .data_bits(serialport::DataBits::Eight)
        .parity(serialport::Parity::None)
        .stop_bits(serialport::StopBits::One)
        .flow_control(serialport::FlowControl::None)
        .timeout(Duration::from_millis(100))
        .open()
        .map_err(|error| open_error(&name, error))?;
    // Until serialport set raw mode, the port had the kernel's default settings, ECHO on: what the robot sent
    // in that moment is queued to go back to it (seen on an emulated 16550: 128 bytes of echoed status frames
    // before a `doctor` that sends nothing). Dropped before the UART sends them.
    let _ = port.clear(serialport::ClearBuffer::Output);
    from_port(port, &name, false)
}

fn open_error(name: &str, error: serialport::Error) -> anyhow::Error {
    #[cfg(windows)]
    let text = {
        // serialport's error kind does not tell a missing port from a held one: a plain open of the same
        // device says which, by its Windows error code.
        let device = if name.starts_with('\\') { name.to_string() } else { format!(r"\\.\{name}") };
        let probe = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .open(device)
            .err()
            .and_then(|error| error.raw_os_error());
        let ports = serialport::available_ports()
            .ok()
            .map(|ports| ports.into_iter().map(|port| port.port_name).collect::<Vec<_>>());
        windows_open_error_text(name, error.kind(), &error.to_string(), probe, ports.as_deref())
    };
    #[cfg(not(windows))]
    let text = {
        let path = Path::new(name);
        let access = match error.kind() {
            serialport::ErrorKind::Io(io::ErrorKind::PermissionDenied) => device_access(path),
            _ => None,
        };
        unix_open_error_text(name, error.kind(), &error.to_string(), path.exists(), access.as_ref())
    };
    anyhow::anyhow!(text)
}

/// Why `name` could not be opened, on Linux and the other Unixes: `exists` is whether the path is there,
/// `access` the device's owner, group and mode when the error is a permission denied.
#[cfg_attr(windows, allow(dead_code))]
fn unix_open_error_text(
    name: &str,
    kind: serialport::ErrorKind,
    error: &str,
    exists: bool,
    access: Option<&DeviceAccess>,
) -> String {
    use serialport::ErrorKind;
    match kind {
        // serialport reports NoDevice for EBUSY (another program set TIOCEXCL) and for the flock it takes on
        // the port: the port is there, and held.
        ErrorKind::NoDevice if exists => format!(
            "serial port {name} is busy: another program has it open ({error}); find it with `fuser -v {name}` \
             or `lsof {name}`, and close it (a terminal program such as minicom or screen, ModemManager, \
             another tracerctl)"
        ),
        ErrorKind::NoDevice | ErrorKind::Io(io::ErrorKind::NotFound) => format!(
            "serial port {name} does not exist ({error}): plug in the adapter and look for it with \
             `ls /dev/ttyUSB* /dev/ttyACM*` and `dmesg | tail`"
        ),
        ErrorKind::Io(io::ErrorKind::PermissionDenied) => permission_denied_text(name, access),
        _ => format!("cannot open serial port {name}: {error}"),
    }
}

/// Windows' error codes that tell why a device did not open.
const ERROR_FILE_NOT_FOUND: i32 = 2;
const ERROR_PATH_NOT_FOUND: i32 = 3;
const ERROR_ACCESS_DENIED: i32 = 5;

/// Why `name` (COM3, `\\.\COM10`) could not be opened, on Windows. serialport reports ERROR_FILE_NOT_FOUND and
/// ERROR_ACCESS_DENIED alike as NoDevice: `probe` is the error code of a plain open of the same device, if it
/// failed too. Windows opens a COM port for one program at a time and refuses the next with access denied.
/// `ports` are the COM ports Windows lists now (None when it could not list them); without a probe, a port
/// that is listed yet cannot be opened is taken to be held by another program.
#[cfg_attr(not(windows), allow(dead_code))]
fn windows_open_error_text(
    name: &str,
    kind: serialport::ErrorKind,
    error: &str,
    probe: Option<i32>,
    ports: Option<&[String]>,
) -> String {
    use serialport::ErrorKind;
    let device_manager = "Device Manager, under Ports (COM & LPT)";
    let busy = format!(
        "serial port {name} is in use by another program ({error}): Windows lets one program at a time open a \
         COM port; close the other one (a terminal program such as PuTTY or Tera Term, a serial monitor, \
         another tracerctl) and try again"
    );
    match kind {
        ErrorKind::NoDevice | ErrorKind::Io(io::ErrorKind::NotFound | io::ErrorKind::PermissionDenied) => {
            let bare = |port: &str| {
                port.trim_start_matches(r"\\.\").trim_start_matches(r"\\?\").to_ascii_uppercase()
            };
            let listed = ports.map(|ports| ports.iter().any(|port| bare(port) == bare(name)));
            let missing = match (probe, listed) {
                (Some(ERROR_ACCESS_DENIED), _) => false,
                (Some(ERROR_FILE_NOT_FOUND | ERROR_PATH_NOT_FOUND), _) => true,
                (_, Some(listed)) => !listed,
                (_, None) => {
                    return format!(
                        "serial port {name} could not be opened ({error}): it does not exist, or another \
                         program has it open; look for it in {device_manager}, and close any other program \
                         using it (PuTTY, Tera Term, a serial monitor, another tracerctl)"
                    )
                }
            };
            if !missing {
                return busy;
            }
            let Some(ports) = ports else {
                return format!(
                    "serial port {name} does not exist ({error}): plug in the adapter and look for its COM \
                     number in {device_manager}"
                );
            };
            // COM2 before COM10.
            let mut ports = ports.to_vec();
            ports.sort_by_key(|port| {
                let split = port.find(|c: char| c.is_ascii_digit()).unwrap_or(port.len());
                (port[..split].to_string(), port[split..].parse::<u32>().unwrap_or(u32::MAX))
            });
            let present = match ports.as_slice() {
                [] => "Windows lists no COM port now".to_string(),
                [port] => format!("the only COM port now is {port}"),
                ports => format!("the COM ports now are {}", ports.join(", ")),
            };
            format!(
                "serial port {name} does not exist ({error}): {present}; plug in the adapter and look for \
                 its COM number in {device_manager}"
            )
        }
        _ => format!("cannot open serial port {name}: {error}"),
    }
}

// The texts of both systems, tested on each (they are pure).
#[cfg(test)]
mod open_error_tests {
    use serialport::ErrorKind;

    use super::*;

    const NOT_FOUND: &str = "The system cannot find the file specified.";
    const DENIED: &str = "Access is denied.";

    fn ports(names: &[&str]) -> Vec<String> {
        names.iter().map(|name| name.to_string()).collect()
    }

    #[test]
    fn linux_texts_name_the_device_files_and_the_tools() {
        let busy = unix_open_error_text("/dev/ttyUSB0", ErrorKind::NoDevice, "busy", true, None);
        assert_eq!(
            busy,
            "serial port /dev/ttyUSB0 is busy: another program has it open (busy); find it with \
             `fuser -v /dev/ttyUSB0` or `lsof /dev/ttyUSB0`, and close it (a terminal program such as minicom \
             or screen, ModemManager, another tracerctl)"
        );
        let missing =
            "serial port /dev/ttyUSB9 does not exist (gone): plug in the adapter and look for it with \
                       `ls /dev/ttyUSB* /dev/ttyACM*` and `dmesg | tail`";
        for kind in [ErrorKind::NoDevice, ErrorKind::Io(io::ErrorKind::NotFound)] {
            assert_eq!(unix_open_error_text("/dev/ttyUSB9", kind, "gone", false, None), missing);
        }
        let denied = unix_open_error_text(
            "/dev/x",
            ErrorKind::Io(io::ErrorKind::PermissionDenied),
            "EACCES",
            true,
            None,
        );
        assert_eq!(denied, permission_denied_text("/dev/x", None));
        let other = unix_open_error_text("/dev/x", ErrorKind::InvalidInput, "bad baud", true, None);
        assert_eq!(other, "cannot open serial port /dev/x: bad baud");
        for text in [busy, missing.to_string()] {
            assert!(!text.contains("Device Manager") && !text.contains("COM"), "{text}");
        }
    }

    const BUSY: &str = "serial port COM3 is in use by another program (Access is denied.): Windows lets one \
                        program at a time open a COM port; close the other one (a terminal program such as \
                        PuTTY or Tera Term, a serial monitor, another tracerctl) and try again";

    #[test]
    fn windows_access_denied_is_a_port_in_use() {
        let text = |probe, ports: Option<&[String]>| {
            windows_open_error_text("COM3", ErrorKind::NoDevice, DENIED, probe, ports)
        };
        assert_eq!(text(Some(ERROR_ACCESS_DENIED), Some(&ports(&["COM1", "COM3"]))), BUSY);
        // The probe decides, whatever the list says or whether there is one.
        assert_eq!(text(Some(ERROR_ACCESS_DENIED), Some(&ports(&["COM1"]))), BUSY);
        assert_eq!(text(Some(ERROR_ACCESS_DENIED), None), BUSY);
        // Without a probe (the port opened the second time), a listed port is taken to be held.
        assert_eq!(text(None, Some(&ports(&["COM3"]))), BUSY);
        // However the name is written.
        for name in ["com3", r"\\.\COM3", r"\\.\com3"] {
            let text =
                windows_open_error_text(name, ErrorKind::NoDevice, DENIED, None, Some(&ports(&["COM3"])));
            assert!(text.contains("is in use by another program"), "{text}");
        }
    }

    #[test]
    fn windows_a_missing_port_names_the_ports_there_are_and_device_manager() {
        let text = |name, probe, ports: Option<&[String]>| {
            windows_open_error_text(name, ErrorKind::NoDevice, NOT_FOUND, probe, ports)
        };
        assert_eq!(
            text("COM7", Some(ERROR_FILE_NOT_FOUND), Some(&ports(&["COM10", "COM4", "COM1"]))),
            "serial port COM7 does not exist (The system cannot find the file specified.): the COM ports now are \
             COM1, COM4, COM10; plug in the adapter and look for its COM number in Device Manager, under Ports \
             (COM & LPT)"
        );
        let one = text("COM7", Some(ERROR_FILE_NOT_FOUND), Some(&ports(&["COM4"])));
        assert!(one.contains(": the only COM port now is COM4; plug in"), "{one}");
        let none = text("COM7", Some(ERROR_PATH_NOT_FOUND), Some(&[]));
        assert!(none.contains(": Windows lists no COM port now; plug in"), "{none}");
        // Not found, even if a stale list still has it.
        assert!(
            text("COM4", Some(ERROR_FILE_NOT_FOUND), Some(&ports(&["COM4"]))).contains("COM4 does not exist")
        );
        // Without a probe: not listed is missing; COM13 is not COM3.
        assert!(text("COM13", None, Some(&ports(&["COM3"]))).contains("COM13 does not exist"));
        assert_eq!(
            text("COM7", Some(ERROR_FILE_NOT_FOUND), None),
            "serial port COM7 does not exist (The system cannot find the file specified.): plug in the adapter \
             and look for its COM number in Device Manager, under Ports (COM & LPT)"
        );
        let io = windows_open_error_text(
            "COM7",
            ErrorKind::Io(io::ErrorKind::NotFound),
            NOT_FOUND,
            None,
            Some(&[]),
        );
        assert_eq!(io, none);
    }

    #[test]
    fn windows_without_a_probe_or_a_port_list_says_both_causes() {
        let text = windows_open_error_text("COM7", ErrorKind::NoDevice, DENIED, None, None);
        assert_eq!(
            text,
            "serial port COM7 could not be opened (Access is denied.): it does not exist, or another program has \
             it open; look for it in Device Manager, under Ports (COM & LPT), and close any other program using \
             it (PuTTY, Tera Term, a serial monitor, another tracerctl)"
        );
    }

    #[test]
    fn windows_texts_name_nothing_of_linux() {
        let texts = [
            windows_open_error_text("COM3", ErrorKind::NoDevice, DENIED, Some(ERROR_ACCESS_DENIED), None),
            windows_open_error_text("COM7", ErrorKind::NoDevice, NOT_FOUND, None, Some(&ports(&["COM3"]))),
            windows_open_error_text("COM7", ErrorKind::NoDevice, DENIED, None, None),
            windows_open_error_text(
                "COM3",
                ErrorKind::Io(io::ErrorKind::Other),
                "The parameter is incorrect.",
                None,
                None,
            ),
        ];
        for text in &texts {
            for linux in ["/dev/", "dmesg", "dialout", "fuser", "lsof", "usermod"] {
                assert!(!text.contains(linux), "{linux} in {text}");
            }
        }
        assert_eq!(texts[3], "cannot open serial port COM3: The parameter is incorrect.");
    }
}

// Every test here needs a pseudo-terminal pair.
#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use crate::protocol::codec::Codec;
    use crate::protocol::message::MotionCommand;

    /// Everything the peer side of `master` can read within `wait` after the last byte.
    fn read_all(master: &mut serialport::TTYPort, wait: Duration) -> usize {
        master.set_timeout(wait).unwrap();
        let mut buffer = [0u8; 4096];
        let mut total = 0;
        while let Ok(read @ 1..) = master.read(&mut buffer) {
            total += read;
        }
        total
    }

    /// A peer that stopped reading: 400 frames (5,200 bytes) written, more than its line discipline holds
    /// (4,095 bytes). The discard drops the rest, and TIOCOUTQ said 0 throughout: before this was fixed the
    /// report said "0 discarded" while 85 frames were dropped. Now the discard says it could not count.
    #[test]
    fn a_pseudo_terminal_discard_is_reported_as_uncounted() {
        let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
        let link = from_port(Box::new(slave), "pty", false).unwrap();
        let mut codec = Codec::new(Wire::Serial);
        for _ in 0..400 {
            link.tx.send(&codec.motion(MotionCommand::STOP)).unwrap();
        }
        // Let the kernel move what fits into the peer's line discipline.
        std::thread::sleep(Duration::from_millis(50));
        let discarded = link.tx.discard_pending();
        let arrived = read_all(&mut master, Duration::from_millis(100));
        assert!(
            arrived < 400 * FRAME_LEN,
            "the flush dropped what the peer had not taken in ({arrived} bytes)"
        );
        assert_eq!(discarded, Discarded { frames: 0, uncounted: true });
    }

    /// The race behind the fault suite's `garbage_flood_with_feedback` failure under load: frames just written
    /// to a peer that reads are still in the peer's flip buffer when the stop flushes, and are dropped (frame
    /// ids did not roll by one, yet the report said "0 discarded"). Whatever the race does, a frame that does
    /// not arrive is covered by an uncounted discard.
    #[test]
    fn frames_a_pseudo_terminal_flush_drops_are_never_reported_as_none() {
        for round in 0..20 {
            let (mut master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
            let link = from_port(Box::new(slave), "pty", false).unwrap();
            let mut codec = Codec::new(Wire::Serial);
            for _ in 0..3 {
                link.tx.send(&codec.motion(MotionCommand::STOP)).unwrap();
            }
            let discarded = link.tx.discard_pending();
            let arrived = read_all(&mut master, Duration::from_millis(20));
            assert!(
                arrived == 3 * FRAME_LEN || discarded.uncounted,
                "round {round}: {arrived} bytes, {discarded:?}"
            );
        }
    }

    #[test]
    fn only_pseudo_terminals_are_taken_for_pseudo_terminals() {
        let (_master, slave) = serialport::TTYPort::pair().expect("a pseudo-terminal pair");
        assert!(is_pseudo_terminal(slave.name()));
        assert!(!is_pseudo_terminal(Some("/dev/null".into())));
        assert!(!is_pseudo_terminal(Some("/nonexistent/ttyUSB0".into())));
        assert!(!is_pseudo_terminal(None));
    }
}
