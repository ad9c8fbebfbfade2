//! RS232 link: 115200 8N1 `5A A5` frames through serialport, reading and writing at once.

use std::collections::VecDeque;
use std::io::{self, Read, Write};
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use parking_lot::Mutex;
use serialport::SerialPort;

use super::{now_timestamp, FrameRx, FrameTx, Link, LinkFrame, LinkKind, Received, RxStats};
use crate::protocol::serial::{StreamDecoder, StreamEvent};
use crate::protocol::Wire;

/// Writes must not stall the 50 Hz sender: a frame takes about 1.1 ms at 115200 baud, so a write that
/// cannot finish in 10 ms is facing a full queue (a peer that does not read), and waiting longer helps
/// nothing.
const WRITE_TIMEOUT: Duration = Duration::from_millis(10);

struct SerialTx(Mutex<Box<dyn SerialPort>>);

impl FrameTx for SerialTx {
    fn send(&self, frame: &LinkFrame) -> io::Result<()> {
        let LinkFrame::Serial(frame) = frame else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a CAN frame cannot be sent on a serial link",
            ));
        };
        let mut port = self.0.lock();
        // No flush: serialport's flush is tcdrain, which waits (holding this lock) until a peer that does not
        // read has taken everything, and the stop frames would wait behind it. The write times out instead.
        port.write_all(&frame.to_bytes())
    }

    fn pending(&self) -> Option<usize> {
        let port = self.0.lock();
        port.bytes_to_write().ok().map(|bytes| (bytes as usize).div_ceil(FRAME_LEN))
    }

    fn discard_pending(&self) -> usize {
        let port = self.0.lock();
        // TIOCOUTQ then TCOFLUSH. A pseudo-terminal reports 0 and flushes only what its peer's line
        // discipline has not taken yet; a UART or USB adapter reports and drops its whole queue.
        let queued = port.bytes_to_write().unwrap_or(0) as usize;
        let _ = port.clear(serialport::ClearBuffer::Output);
        queued.div_ceil(FRAME_LEN)
    }
}

/// Bytes in one RS232 frame.
const FRAME_LEN: usize = 13;
/// At the end, how long what is queued may take to leave before it is dropped (so that closing the port
/// does not wait the tty's 30 s closing time for a peer that does not read).
const CLOSE_DRAIN: Duration = Duration::from_millis(300);

impl Drop for SerialTx {
    fn drop(&mut self) {
        let port = self.0.lock();
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
        tx: Arc::new(SerialTx(Mutex::new(writer))),
        rx: Box::new(rx),
    })
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
    from_port(port, &name, false)
}

fn open_error(name: &str, error: serialport::Error) -> anyhow::Error {
    use serialport::ErrorKind;
    let exists = Path::new(name).exists();
    match error.kind() {
        // serialport reports NoDevice for EBUSY (another program set TIOCEXCL) and for the flock it takes on
        // the port: the port is there, and held.
        ErrorKind::NoDevice if exists => anyhow::anyhow!(
            "serial port {name} is busy: another program has it open ({error}); find it with `fuser -v {name}` \
             or `lsof {name}`, and close it (a terminal program such as minicom or screen, ModemManager, \
             another tracerctl)"
        ),
        ErrorKind::NoDevice | ErrorKind::Io(io::ErrorKind::NotFound) => anyhow::anyhow!(
            "serial port {name} does not exist ({error}): plug in the adapter and look for it with \
             `ls /dev/ttyUSB* /dev/ttyACM*` and `dmesg | tail`"
        ),
        ErrorKind::Io(io::ErrorKind::PermissionDenied) => anyhow::anyhow!(
            "permission denied opening {name}: add yourself to the dialout group \
             (`sudo usermod -aG dialout $USER`, then log in again)"
        ),
        _ => anyhow::anyhow!("cannot open serial port {name}: {error}"),
    }
}
