#!/usr/bin/env python3
"""A TRACER on RS232 for the VM's check serial_stalled_peer (host side, stdlib only; the VM has no python).

serve: listens on a Unix socket that QEMU connects to as the chardev of the VM's fourth 16550 UART (ttyS3).
       Sends a system-status frame every 20 ms (normal, serial mode, 25.9 V, no fault; rolling frame id), and
       logs every byte it reads with a host timestamp. After it has read STALL_AFTER non-zero motion frames it
       stops reading for STALL_FOR seconds (a stalled USB-serial adapter): QEMU's writes to the socket then
       fail, the 16550 keeps its byte and its FIFO, and the guest's 8250 driver keeps what drive writes in its
       4 KiB transmit buffer (TIOCOUTQ). Then it reads on, and logs what arrives.
judge: reads that log and the check's files from the VM and prints one line
       CHECK serial_stalled_peer: PASS|FAIL <evidence>
       followed, on failure, by evidence lines starting with "  | ". Exit status 0 (pass) or 1 (fail).

Before the robot stops reading, QEMU's socket already holds what it could still take (its send buffer, ~280 bytes
of 1-byte writes): bytes the UART had already sent when its transmitter stalled. At the resume the robot asks the
socket how much it holds (FIONREAD) and logs it, so the judge can tell those bytes ("the wire") from what the
guest still held.
"""
import argparse
import fcntl
import os
import re
import socket
import struct
import sys
import termios
import threading
import time

FRAME = 13


def checksum(data):
    return sum(data) & 0xFF


def status_frame(frame_id):
    # 5A A5 0A AA 01: system status; normal (0), serial mode (2), 25.9 V (0x0103), fault code 0
    body = bytes([0x5A, 0xA5, 0x0A, 0xAA, 0x01, 0x00, 0x02, 0x01, 0x03, 0x00, 0x00, frame_id & 0xFF])
    return body + bytes([checksum(body)])


def frames(data):
    """(offset, frame bytes) of every valid frame in a byte stream; a candidate that fails is rescanned from
    its next byte (a frame cut by an output flush is skipped, the next one found). Also the skipped bytes."""
    out = []
    skipped = 0
    i = 0
    while i + FRAME <= len(data):
        c = data[i:i + FRAME]
        if c[0] == 0x5A and c[1] == 0xA5 and c[2] == 0x0A and c[3] in (0x55, 0xAA) and checksum(c[:12]) == c[12]:
            out.append((i, c))
            i += FRAME
        else:
            skipped += 1
            i += 1
    return out, skipped + max(0, len(data) - i)


def is_motion(frame):
    return frame[3] == 0x55 and frame[4] == 0x01


def moving(frame):
    # 55 01: control mode, fault clear, linear %, angular %, lateral %
    return frame[7] != 0 or frame[8] != 0 or frame[9] != 0


# ------------------------------------------------------------------------------------------------ serve

def serve(args):
    t0 = time.monotonic()
    log = open(args.log, "w", buffering=1)
    lock = threading.Lock()

    def event(text):
        with lock:
            log.write("%.6f %s\n" % (time.monotonic() - t0, text))

    try:
        os.unlink(args.socket)
    except FileNotFoundError:
        pass
    lsock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    lsock.bind(args.socket)
    lsock.listen(1)
    event("listen %s" % args.socket)
    lsock.settimeout(args.accept_timeout)
    try:
        conn, _ = lsock.accept()
    except socket.timeout:
        event("error: QEMU did not connect within %d s" % args.accept_timeout)
        return 1
    lsock.close()
    # What the robot sends while nobody in the VM reads ttyS3 must not pile up: a small send buffer, and a
    # frame that does not fit is dropped (a UART sends into the void when nobody listens).
    conn.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
    event("connect sndbuf(robot)=%d" % conn.getsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF))
    done = threading.Event()
    counts = {"sent": 0, "dropped": 0}

    def sender():
        frame_id = 0
        nxt = time.monotonic()
        while not done.is_set():
            try:
                conn.send(status_frame(frame_id), socket.MSG_DONTWAIT)
                counts["sent"] += 1
            except BlockingIOError:
                counts["dropped"] += 1
            except OSError as error:
                event("status send error: %s" % error)
                return
            frame_id = (frame_id + 1) & 0xFF
            nxt += 0.020
            delay = nxt - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            else:
                nxt = time.monotonic()

    threading.Thread(target=sender, daemon=True).start()

    buf = b""
    seen_moving = 0
    stalled = False
    rx = 0
    while True:
        try:
            data = conn.recv(4096)
        except OSError as error:
            event("recv error: %s" % error)
            break
        if not data:
            event("eof")
            break
        rx += len(data)
        event("rx %s" % data.hex())
        if stalled:
            continue
        # count the non-zero motion frames read so far; keep what may be the start of the next frame
        buf += data
        found, _ = frames(buf)
        seen_moving += sum(1 for _, f in found if is_motion(f) and moving(f))
        buf = buf[found[-1][0] + FRAME:] if found else buf[-(FRAME - 1):]
        if seen_moving >= args.stall_after:
            stalled = True
            event("stall moving=%d rx_bytes=%d for=%.1fs" % (seen_moving, rx, args.stall_for))
            time.sleep(args.stall_for)
            queued = struct.unpack("i", fcntl.ioctl(conn.fileno(), termios.FIONREAD, b"\0\0\0\0"))[0]
            event("resume socket_backlog=%d rx_bytes=%d" % (queued, rx))
    done.set()
    event("status frames sent=%d dropped=%d" % (counts["sent"], counts["dropped"]))
    return 0


# ------------------------------------------------------------------------------------------------ judge

def judge(args):
    fails = []
    evidence = []
    parsed = []
    stall = resume = None
    backlog = 0
    rx_at_stall = rx_at_resume = None
    status_line = ""
    try:
        with open(args.log) as f:
            lines = f.read().splitlines()
    except OSError as error:
        lines = []
        fails.append("no robot log (%s)" % error)
    stream = bytearray()
    chunk_at = []  # (offset of the chunk's first byte, host time)
    for line in lines:
        parts = line.split(" ", 2)
        if len(parts) < 2:
            continue
        t, kind = float(parts[0]), parts[1]
        rest = parts[2] if len(parts) > 2 else ""
        if kind == "rx":
            chunk_at.append((len(stream), t))
            stream += bytes.fromhex(rest)
        elif kind == "stall":
            stall = t
            rx_at_stall = len(stream)
        elif kind == "resume":
            resume = t
            rx_at_resume = len(stream)
            backlog = int(rest.split("socket_backlog=")[1].split()[0])
        elif kind == "status":
            status_line = rest
        elif kind.startswith("error") or kind.endswith("error:"):
            fails.append("robot: " + line)

    def time_of(offset):
        t = None
        for start, at in chunk_at:
            if start > offset:
                break
            t = at
        return t

    found, _ = frames(bytes(stream))
    # bytes that are no frame after the resume: frames cut by the output flush (before it: the echo of a fresh
    # port's default termios, before drive set it raw)
    skipped = frames(bytes(stream[rx_at_resume:]))[1] if rx_at_resume is not None else 0
    motion = [(off, f) for off, f in found if is_motion(f)]

    def vm_file(name):
        try:
            with open(os.path.join(args.vm_dir, name)) as f:
                return f.read()
        except OSError:
            return None

    vm_note = " ".join((vm_file("ser.vm") or "").split("\n")).strip()
    rc = (vm_file("ser.rc") or "").strip()
    # drive's report is on its stdout, its diagnostics on stderr: read both.
    outputs = [text for text in (vm_file("ser.out"), vm_file("ser.err")) if text is not None]
    output = "\n".join(outputs) if outputs else None
    report = ""
    held = discarded = 0
    if output is not None:
        for line in output.splitlines():
            if line.startswith("stopped after") or "motion frames sent" in line:
                report = line.strip()
        m = re.search(r"(\d+) held back while the link's output was not draining", output)
        held = int(m.group(1)) if m else 0
        m = re.search(r"(\d+) stale frames discarded before the stop frames", output)
        discarded = int(m.group(1)) if m else 0

    before = [(o, f) for o, f in motion if rx_at_stall is None or o < rx_at_stall]
    after = [(o, f) for o, f in motion if rx_at_resume is not None and o >= rx_at_resume]
    wire_end = (rx_at_resume or 0) + backlog
    on_wire = [(o, f) for o, f in after if o < wire_end]          # in the host socket at the resume
    from_vm = [(o, f) for o, f in after if o >= wire_end]          # still in the guest's UART at the resume
    first_zero = next((i for i, (_, f) in enumerate(from_vm) if not moving(f)), None)
    stale = sum(1 for _, f in from_vm[:first_zero] if moving(f)) if first_zero is not None else \
        sum(1 for _, f in from_vm if moving(f))
    zeros = sum(1 for _, f in from_vm if not moving(f))
    nz_after_zero = sum(1 for _, f in from_vm[first_zero:] if moving(f)) if first_zero is not None else 0
    wire_moving = sum(1 for _, f in on_wire if moving(f))
    lat = ""
    if first_zero is not None and resume is not None:
        tz = time_of(from_vm[first_zero][0])
        if tz is not None:
            lat = ", the first %.0f ms after the resume" % ((tz - resume) * 1000)
    moved_before = sum(1 for _, f in before if moving(f))

    if not lines:
        pass
    elif stall is None:
        fails.append("the robot never stalled: it read %d non-zero motion frames (wants %d); VM: %s"
                     % (moved_before, args.stall_after, vm_note or "no ser.vm"))
    elif resume is None:
        fails.append("the robot stalled but never resumed")
    if rc == "":
        fails.append("no exit status of drive from the VM (artifacts-sja1000/scn/ser.rc missing)")
    elif stall is not None and resume is not None:
        if stale > args.max_stale:
            fails.append("%d stale non-zero motion frames reached the robot after it read on, before the "
                         "first zero (limit %d: the 16-byte FIFO and one byte in flight)" % (stale, args.max_stale))
        if zeros == 0:
            fails.append("no zero motion frame reached the robot after it read on")
        if nz_after_zero:
            fails.append("%d non-zero motion frames after the first zero" % nz_after_zero)
        if rc != "130":
            fails.append("drive exit status %s (want 130 after SIGINT)" % rc)
        if discarded == 0:
            fails.append("drive's report counts no stale frames discarded before the stop frames")
        if "SIGINT during the stall" not in vm_note:
            fails.append("SIGINT was not sent while ttyS3's transmitter was stalled: %s" % vm_note)
    summary = ("robot read %d non-zero motion frames, stopped reading for %.1f s; at the resume QEMU's socket "
               "held %d bytes (%d frames already sent by the UART, %d moving); then from the guest: %d stale "
               "non-zero frames before the first zero, %d zero frames%s, %d non-zero after them; %d bytes "
               "skipped (frames cut by the flush); drive exit %s, %d held back, %d discarded; VM: %s"
               % (moved_before, (resume - stall) if (stall is not None and resume is not None) else 0,
                  backlog, len(on_wire), wire_moving, stale, zeros, lat, nz_after_zero, skipped, rc or "?",
                  held, discarded, vm_note or "-"))
    if fails:
        print("CHECK serial_stalled_peer: FAIL %s [%s]" % ("; ".join(fails), summary))
        evidence.append("drive's report: %s" % (report or "(none)"))
        evidence.append("robot: %s" % status_line)
        for line in (vm_file("ser.threads") or "").splitlines():
            evidence.append("drive's %s" % line.strip())
        evidence.append("motion frames from the guest after the resume (first 8, last 4):")
        shown = from_vm[:8] + ([(None, None)] if len(from_vm) > 12 else []) + from_vm[max(8, len(from_vm) - 4):]
        for off, f in shown:
            evidence.append("  ..." if f is None else "  @%d %s" % (off, f.hex(" ")))
        for line in evidence:
            print("  | " + line)
        return 1
    print("CHECK serial_stalled_peer: PASS %s; report: %s" % (summary, report))
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("serve")
    s.add_argument("--socket", required=True)
    s.add_argument("--log", required=True)
    s.add_argument("--stall-after", type=int, default=50, help="non-zero motion frames read before the stall")
    s.add_argument("--stall-for", type=float, default=3.0, help="seconds without reading")
    s.add_argument("--accept-timeout", type=int, default=120)
    j = sub.add_parser("judge")
    j.add_argument("--log", required=True)
    j.add_argument("--vm-dir", required=True, help="the scenario's files (artifacts-sja1000/scn)")
    j.add_argument("--stall-after", type=int, default=50)
    j.add_argument("--max-stale", type=int, default=3)
    args = p.parse_args()
    return serve(args) if args.cmd == "serve" else judge(args)


if __name__ == "__main__":
    sys.exit(main())
