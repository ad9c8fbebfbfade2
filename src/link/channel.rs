//! An in-process link: two connected endpoints (host and robot) over channels, for the simulator.

use std::io;
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::time::Duration;

use parking_lot::Mutex;

use super::{now_timestamp, FrameRx, FrameTx, Link, LinkFrame, LinkKind, Received, RxStats};
use crate::protocol::Wire;

struct ChannelTx(Mutex<Sender<Received>>);

impl FrameTx for ChannelTx {
    fn send(&self, frame: &LinkFrame) -> io::Result<()> {
        let received = Received { ts: now_timestamp(), frame: *frame };
        let sender = self.0.lock();
        sender
            .send(received)
            .map_err(|_| io::Error::new(io::ErrorKind::BrokenPipe, "the other end has stopped"))
    }
}

struct ChannelRx {
    receiver: Receiver<Received>,
    stats: RxStats,
}

impl FrameRx for ChannelRx {
    fn recv(&mut self, timeout: Duration) -> io::Result<Option<Received>> {
        match self.receiver.recv_timeout(timeout) {
            Ok(received) => {
                self.stats.frames += 1;
                Ok(Some(received))
            }
            Err(RecvTimeoutError::Timeout) => Ok(None),
            Err(RecvTimeoutError::Disconnected) => {
                Err(io::Error::new(io::ErrorKind::UnexpectedEof, "the other end has stopped"))
            }
        }
    }

    fn stats(&self) -> RxStats {
        self.stats
    }
}

/// Two connected links: what one sends, the other receives.
pub fn pair(wire: Wire, kind: LinkKind, name: &str) -> (Link, Link) {
    let (to_robot, robot_inbox) = mpsc::channel();
    let (to_host, host_inbox) = mpsc::channel();
    let host = Link {
        name: name.to_string(),
        kind,
        wire,
        tx: Arc::new(ChannelTx(Mutex::new(to_robot))),
        rx: Box::new(ChannelRx { receiver: host_inbox, stats: RxStats::default() }),
    };
    let robot = Link {
        name: name.to_string(),
        kind,
        wire,
        tx: Arc::new(ChannelTx(Mutex::new(to_host))),
        rx: Box::new(ChannelRx { receiver: robot_inbox, stats: RxStats::default() }),
    };
    (host, robot)
}
