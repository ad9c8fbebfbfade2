#!/usr/bin/env python3
"""A witness between tracerctl.exe (under wine) and `tracerctl sim --pty`: a new pseudo-terminal for wine's
COM port, relayed byte for byte to the simulator's, with every byte the .exe writes recorded.

Usage: relay.py PEER_PTY NAME_FILE CAPTURE EVENTS
  PEER_PTY   the simulator's terminal side (the `PTY /dev/pts/N` that `sim --pty` printed)
  NAME_FILE  written with the new terminal's path (for HKLM\\Software\\Wine\\Ports) once it is ready
  CAPTURE    the raw bytes the .exe wrote, in order (`tracerctl decode --serial CAPTURE` reads them)
  EVENTS     one line per chunk the .exe wrote: wall-clock time (s), byte offset in CAPTURE, length
Runs until SIGTERM or SIGINT. Test-only (tests/wine/run.sh).
"""
import os
import select
import signal
import sys
import termios
import time
import tty


def main():
    if len(sys.argv) != 5:
        print(__doc__, file=sys.stderr)
        return 2
    peer_path, name_file, capture_path, events_path = sys.argv[1:]
    peer = os.open(peer_path, os.O_RDWR | os.O_NOCTTY)
    tty.setraw(peer, termios.TCSANOW)
    master, slave = os.openpty()
    tty.setraw(slave, termios.TCSANOW)
    name = os.ttyname(slave)
    # The simulator's feedback must never block the relay (and with it the .exe's bytes) while nobody reads it.
    os.set_blocking(master, False)
    # Keep the slave open: without a holder, the master reads EIO between the .exe's opens.
    running = [True]

    def stop(*_):
        running[0] = False

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    with open(capture_path, "wb", buffering=0) as capture, open(events_path, "w", buffering=1) as events:
        with open(name_file + ".tmp", "w") as out:
            out.write(name + "\n")
        os.rename(name_file + ".tmp", name_file)
        offset = 0
        while running[0]:
            try:
                ready, _, _ = select.select([master, peer], [], [], 0.2)
            except InterruptedError:
                continue
            for fd in ready:
                try:
                    data = os.read(fd, 4096)
                except OSError:
                    # EIO: the other side is closed for now.
                    time.sleep(0.01)
                    continue
                if not data:
                    continue
                if fd == master:
                    now = time.time()
                    capture.write(data)
                    events.write(f"{now:.6f} {offset} {len(data)}\n")
                    offset += len(data)
                    os.write(peer, data)  # the simulator always reads
                else:
                    try:
                        os.write(master, data)
                    except (BlockingIOError, OSError):
                        pass  # nobody reads the feedback now: the simulator sends more every 20 ms
    os.close(slave)
    return 0


if __name__ == "__main__":
    sys.exit(main())
