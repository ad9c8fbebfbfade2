#!/usr/bin/env python3
"""A TRACER on RS232 for the VM's checks serial_stalled_peer and commission_serial_stalled (host side, stdlib
only; the VM has no python).

serve: listens on a Unix socket that QEMU connects to as the chardev of the VM's fourth 16550 UART (ttyS3).
       Sends a system-status frame every 20 ms (normal, serial mode, 25.9 V, no fault; rolling frame id), and
       logs every byte it reads with a host timestamp. After it has read STALL_AFTER non-zero motion frames it
       stops reading for STALL_FOR seconds (a stalled USB-serial adapter): QEMU's writes to the socket then
       fail, the 16550 keeps its byte and its FIFO, and the guest's 8250 driver keeps what drive writes in its
       4 KiB transmit buffer (TIOCOUTQ). Then it reads on, and logs what arrives.
       Sessions: the robot starts in the session serial_stalled_peer (status frames only). The line
       "@session NAME" written to ttyS3 starts the session NAME given by --session NAME:AFTER:FOR: its own
       count of motion frames and its own stall, and a chassis that follows the commands read (a motion-state
       frame after each status frame; speed toward the command at 1 m/s^2 and 2 rad/s^2, zero when no command
       was read for 500 ms, the robot's command timeout), as commission needs to drive. The log names each
       session; each judge reads its own. --commission-stall-for FOR registers commission_stall_<step> for
       each stall of COMMISSION_STALLS (one in each step of commission's plan: 30 moving frames into a moving
       step, a few zero frames into a standing one).
judge: reads that log and the check's files from the VM and prints one line
       CHECK NAME: PASS|FAIL <evidence>   (--check serial_stalled_peer, the default, or commission_serial_stalled)
       followed, on failure, by evidence lines starting with "  | ". Exit status 0 (pass) or 1 (fail).

Before the robot stops reading, QEMU's socket already holds what it could still take (its send buffer, ~280 bytes
of 1-byte writes): bytes the UART had already sent when its transmitter stalled. At the resume the robot asks the
socket how much it holds (FIONREAD) and logs it, so the judge can tell those bytes ("the wire") from what the
guest still held.
"""
import argparse
import fcntl
import json
import os
import re
import shutil
import socket
import struct
import sys
import tempfile
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


def signed(byte):
    return byte - 256 if byte > 127 else byte


def motion_state_frame(frame_id, linear_mm_s, angular_mrad_s):
    # 5A A5 0A AA 02: motion state, linear mm/s and angular mrad/s (big-endian, signed)
    lin = int(round(linear_mm_s)) & 0xFFFF
    ang = int(round(angular_mrad_s)) & 0xFFFF
    body = bytes([0x5A, 0xA5, 0x0A, 0xAA, 0x02, lin >> 8, lin & 0xFF, ang >> 8, ang & 0xFF, 0, 0, frame_id & 0xFF])
    return body + bytes([checksum(body)])


class Chassis:
    """Follows the last motion command read: toward its speed at ACCEL, to zero once no command came for
    TIMEOUT (the robot's own command timeout). Percent commands: 100 % = 1.5 m/s, 0.7853 rad/s."""
    ACCEL = 1000.0          # mm/s per s
    ANGULAR_ACCEL = 2000.0  # mrad/s per s
    TIMEOUT = 0.5

    def __init__(self):
        self.lock = threading.Lock()
        self.target = (0.0, 0.0)
        self.speed = (0.0, 0.0)
        self.last_command = None

    def command(self, frame, now):
        with self.lock:
            self.target = (signed(frame[7]) * 15.0, signed(frame[8]) * 7.853)
            self.last_command = now

    def tick(self, now, dt):
        with self.lock:
            if self.last_command is None or now - self.last_command > self.TIMEOUT:
                self.target = (0.0, 0.0)

            def toward(value, goal, rate):
                step = rate * dt
                return goal if abs(goal - value) <= step else value + (step if goal > value else -step)
            self.speed = (toward(self.speed[0], self.target[0], self.ACCEL),
                          toward(self.speed[1], self.target[1], self.ANGULAR_ACCEL))
            return self.speed


# ------------------------------------------------------------------------------------------------ serve

MARKER = re.compile(rb"@session ([a-z0-9_]+)\n")
FIRST_SESSION = "serial_stalled_peer"


def serve(args):
    t0 = time.monotonic()
    log = open(args.log, "w", buffering=1)
    lock = threading.Lock()

    def event(text):
        with lock:
            log.write("%.6f %s\n" % (time.monotonic() - t0, text))

    # session -> (moving frames read, then zero frames read, before the stall; seconds stalled)
    sessions = {}
    for spec in args.session:
        name, after, stall_for = spec.split(":")
        sessions[name] = (int(after), 0, float(stall_for))
    if args.commission_stall_for is not None:
        for step, after, zeros in COMMISSION_STALLS:
            sessions["commission_stall_" + commission_tag(step)] = (after, zeros, args.commission_stall_for)
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
    chassis = Chassis()
    # the chassis answers (motion-state frames) only in the sessions that ask for it
    following = threading.Event()

    def send(frame):
        # one frame per send: a Unix stream socket takes a small write whole or not at all
        try:
            conn.send(frame, socket.MSG_DONTWAIT)
            counts["sent"] += 1
        except BlockingIOError:
            counts["dropped"] += 1

    def sender():
        frame_id = 0
        nxt = time.monotonic()
        last = nxt
        while not done.is_set():
            now = time.monotonic()
            linear, angular = chassis.tick(now, now - last)
            last = now
            try:
                send(status_frame(frame_id))
                if following.is_set():
                    send(motion_state_frame(frame_id, linear, angular))
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
    tail = b""
    seen_moving = 0
    seen_zeros = 0
    stalled = False
    stall_after, zeros_after, stall_for = args.stall_after, 0, args.stall_for
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
        now = time.monotonic()
        rx += len(data)
        event("rx %s" % data.hex())
        tail = (tail + data)[-64:]
        marker = MARKER.search(tail)
        if marker:
            name = marker.group(1).decode()
            tail = tail[marker.end():]
            if name not in sessions:
                event("error: unknown session %s" % name)
                continue
            stall_after, zeros_after, stall_for = sessions[name]
            buf, seen_moving, seen_zeros, stalled = b"", 0, 0, False
            chassis.__init__()
            following.set()
            event("session %s stall_after=%d zeros_after=%d stall_for=%.1f"
                  % (name, stall_after, zeros_after, stall_for))
            continue
        # the chassis follows every motion frame read; until the stall the non-zero ones are counted, and once
        # there were stall_after of them, the zero ones
        buf += data
        found, _ = frames(buf)
        for _, f in found:
            if is_motion(f):
                chassis.command(f, now)
                if stalled:
                    continue
                if moving(f):
                    seen_moving += 1
                elif seen_moving >= stall_after:
                    seen_zeros += 1
        buf = buf[found[-1][0] + FRAME:] if found else buf[-(FRAME - 1):]
        if not stalled and seen_moving >= stall_after and seen_zeros >= zeros_after:
            stalled = True
            event("stall moving=%d zeros=%d rx_bytes=%d for=%.1fs" % (seen_moving, seen_zeros, rx, stall_for))
            time.sleep(stall_for)
            queued = struct.unpack("i", fcntl.ioctl(conn.fileno(), termios.FIONREAD, b"\0\0\0\0"))[0]
            event("resume socket_backlog=%d rx_bytes=%d" % (queued, rx))
    done.set()
    event("status frames sent=%d dropped=%d" % (counts["sent"], counts["dropped"]))
    return 0


# ------------------------------------------------------------------------------------------------ judge

class Session:
    """One session's part of the robot's log: the bytes read (with the host time of each chunk), the stall and
    the resume."""

    def __init__(self, path, name):
        self.lines = []
        self.errors = []
        self.stream = bytearray()
        self.chunk_at = []  # (offset of the chunk's first byte, host time)
        self.stall = self.resume = None
        self.backlog = 0
        self.rx_at_stall = self.rx_at_resume = None
        self.status_line = ""
        self.missing = None
        try:
            with open(path) as f:
                every = f.read().splitlines()
        except OSError as error:
            every = []
            self.missing = "no robot log (%s)" % error
        current = FIRST_SESSION
        for line in every:
            parts = line.split(" ", 2)
            if len(parts) < 2:
                continue
            t, kind = float(parts[0]), parts[1]
            rest = parts[2] if len(parts) > 2 else ""
            if kind == "session":
                current = rest.split()[0]
                continue
            # the robot's own lines (connect, the final count, errors) belong to every session
            if current != name and kind in ("rx", "stall", "resume"):
                continue
            self.lines.append(line)
            if kind == "rx":
                self.chunk_at.append((len(self.stream), t))
                self.stream += bytes.fromhex(rest)
            elif kind == "stall":
                self.stall = t
                self.rx_at_stall = len(self.stream)
            elif kind == "resume":
                self.resume = t
                self.rx_at_resume = len(self.stream)
                self.backlog = int(rest.split("socket_backlog=")[1].split()[0])
            elif kind == "status":
                self.status_line = rest
            elif kind.startswith("error") or kind.endswith("error:"):
                self.errors.append("robot: " + line)

    def time_of(self, offset):
        t = None
        for start, at in self.chunk_at:
            if start > offset:
                break
            t = at
        return t


def judge(args):
    if args.check == "commission_serial_stalled":
        return judge_commission(args)
    fails = []
    evidence = []
    log = Session(args.log, FIRST_SESSION)
    if log.missing:
        fails.append(log.missing)
    fails += log.errors
    lines, stream, time_of = log.lines, log.stream, log.time_of
    stall, resume, backlog, status_line = log.stall, log.resume, log.backlog, log.status_line
    rx_at_stall, rx_at_resume = log.rx_at_stall, log.rx_at_resume

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


# ------------------------------------------------------------------------------------------------ commission

# What the stop rules allow commission (docs/commission.md "Safety rules", docs/architecture.md "Stop rules" 6;
# src/control/sender.rs BACKLOG_LIMIT): once the UART's transmitter stands still, the 16550 takes at most its
# 16-byte FIFO and the byte in its transmitter, the 8250 driver's queue (TIOCOUTQ) at most two frames before
# the sender holds motion back (it never queues behind a backlog of 2 frames), and the guard ends the drive
# within the period the first frame is held back in: after the frame in transmission when the transmitter
# stood still, at most 3 more moving frames (one every 20 ms) are written, and the first stop frame within
# 2 periods of the last one (+10 ms for TCG).
COMMISSION_MAX_MOVING_AFTER_STALL = 3
COMMISSION_STOP_AFTER_LAST_MOVING = 0.050
# In a standing step the frames before the first held back are zeros too: everything commission writes after
# the frame in transmission (at most 3 frames, then the stop frames) within the same two bounds.
COMMISSION_STANDING_END = COMMISSION_MAX_MOVING_AFTER_STALL * 0.020 + COMMISSION_STOP_AFTER_LAST_MOVING
# After the robot reads on, beyond the socket's backlog: what the 16550 held (17 bytes: one whole frame besides
# the rest of the one in transmission) may arrive before the stop frames, stale.
COMMISSION_MAX_STALE = 1
# commission's plan at --max-linear 0.6 (`commission --dry-run`), and the figures a full run measures for each
# step (a run on the simulator); a step finished before the stall must keep them.
COMMISSION_PLAN = ["settle", "forward", "brake after forward", "back", "brake after back", "spin left",
                   "brake after spin left", "spin right", "brake after spin right"]
_MOVING = ("dead_time_ms", "rise_time_ms", "overshoot_percent")
COMMISSION_FIGURES = {
    "forward": _MOVING,
    "brake after forward": ("braking_time_ms", "braking_distance_m", "deceleration_mps2"),
    "back": _MOVING,
    "brake after back": ("braking_time_ms", "braking_distance_m", "deceleration_mps2"),
    "spin left": _MOVING,
    "brake after spin left": ("braking_time_ms", "braking_angle_rad", "angular_deceleration_radps2"),
    "spin right": _MOVING,
}
# The check's stalls, one commission each: the step, the moving frames read, then the zero frames read before
# the stall. Commission writes 85, 84, 151 and 151 moving frames in the four moving steps: a stall 30 moving
# frames into each, and in the standing steps (settle 1 s, each brake 2 s, 50 zero frames a second) a few
# moving frames before the end of the step before (its count may differ by one) and 5 (settle) or 30 zero
# frames in (QEMU's socket takes ~21 more frames before the transmitter stands still).
COMMISSION_STALLS = [
    ("settle", 0, 5), ("forward", 30, 0), ("brake after forward", 80, 30), ("back", 114, 0),
    ("brake after back", 164, 30), ("spin left", 199, 0), ("brake after spin left", 315, 30),
    ("spin right", 350, 0), ("brake after spin right", 466, 30),
]
COMMISSION_MOVING_STEPS = ("forward", "back", "spin left", "spin right")


def commission_tag(step):
    """The session's and the VM's files' name for the stall in `step`: com_<tag>.* and commission_stall_<tag>."""
    return step.replace(" ", "_")
RECORD_LINE = re.compile(r"^([0-9A-Fa-f]{26}) # \((\d+\.\d+)\)")


def recorded_motion(text):
    """(guest time, frame) of every motion frame commission wrote, from its --record file, in order."""
    out = []
    for line in (text or "").splitlines():
        m = RECORD_LINE.match(line)
        if m:
            frame = bytes.fromhex(m.group(1))
            if is_motion(frame):
                out.append((float(m.group(2)), frame))
    return out


def judge_commission(args):
    """Every stall of COMMISSION_STALLS, one line for the check: PASS when each passed."""
    name = "commission_serial_stalled"
    results = [judge_commission_stall(args, step, after, zeros) for step, after, zeros in COMMISSION_STALLS]
    failed = [(step, fails) for step, fails, _, _ in results if fails]
    summary = " || ".join("%s: %s" % (step, summary) for step, _, summary, _ in results)
    if failed:
        print("CHECK %s: FAIL %s [%s]" % (name, "; ".join("%s: %s" % (step, "; ".join(fails))
                                                          for step, fails in failed), summary))
        for step, fails, _, evidence in results:
            if fails:
                for line in evidence:
                    print("  | %s: %s" % (step, line))
        return 1
    missed = commission_judge_attacks(args)
    if missed:
        print("CHECK %s: FAIL the judge passed a run it must fail: %s [%s]" % (name, "; ".join(missed), summary))
        return 1
    print("CHECK %s: PASS %d stalls, one in each step (and the judge fails this run's files altered: %d ways): %s"
          % (name, len(results), len(COMMISSION_ATTACKS), summary))
    return 0


# The judge's own proof, on altered copies of this run's files of one stall (step, how, the failure it must
# report): a standing step's last frame written 200 ms late, a moving frame written in a standing step.
COMMISSION_ATTACKS = [
    ("settle", "late", "commission wrote its last frame"),
    ("brake after forward", "moving", "moving frames written in a standing step"),
]


def commission_judge_attacks(args):
    """Runs the judge on each of COMMISSION_ATTACKS; what it did not fail as it must (empty: every one)."""
    missed = []
    for step, how, words in COMMISSION_ATTACKS:
        _, after, zeros = next(stall for stall in COMMISSION_STALLS if stall[0] == step)
        prefix = "com_%s." % commission_tag(step)
        with tempfile.TemporaryDirectory() as copy:
            for file in os.listdir(args.vm_dir):
                if file.startswith(prefix):
                    shutil.copy(os.path.join(args.vm_dir, file), copy)
            record = os.path.join(copy, prefix + "rec")
            with open(record) as f:
                lines = f.read().splitlines()
            motion = []
            for i, line in enumerate(lines):
                m = RECORD_LINE.match(line)
                if m and is_motion(bytes.fromhex(m.group(1))):
                    motion.append((i, m, bytes.fromhex(m.group(1))))
            if len(motion) < 4:
                missed.append("%s: too few motion frames in %s to alter" % (step, prefix + "rec"))
                continue
            if how == "late":
                i, m, _ = motion[-1]
                lines[i] = "%s # (%.9f)%s" % (m.group(1), float(m.group(2)) + 0.2, line_tail(lines[i]))
            else:
                # the fourth last (before the three stop frames: among those written after the stall) moves
                i, _, _ = motion[-4]
                lines[i] = next(f for _, _, f in motion if moving(f)).hex().upper() + lines[i][26:]
            with open(record, "w") as f:
                f.write("\n".join(lines) + "\n")
            altered = argparse.Namespace(**dict(vars(args), vm_dir=copy))
            _, fails, _, _ = judge_commission_stall(altered, step, after, zeros)
            if not any(words in fail for fail in fails):
                missed.append("%s, %s: %s" % (step, how, "; ".join(fails) or "passed"))
    return missed


def line_tail(line):
    """What follows the time in a --record line (the port's name)."""
    return line[line.index(")") + 1:]


def judge_commission_stall(args, stall_step, stall_after, zeros_after):
    """One commission whose robot stalled in `stall_step`, after `stall_after` moving frames and then
    `zeros_after` zero ones: (step, the failures, the summary, the evidence lines)."""
    tag = commission_tag(stall_step)
    moving_step = stall_step in COMMISSION_MOVING_STEPS
    fails = []
    log = Session(args.log, "commission_stall_" + tag)
    if log.missing:
        fails.append(log.missing)
    fails += log.errors

    def vm_file(file):
        try:
            with open(os.path.join(args.vm_dir, file)) as f:
                return f.read()
        except OSError:
            return None

    prefix = "com_%s." % tag
    finished = COMMISSION_PLAN[:COMMISSION_PLAN.index(stall_step)]
    vm_note = " ".join((vm_file(prefix + "vm") or "").split("\n")).strip()
    rc = (vm_file(prefix + "rc") or "").strip()
    try:
        report = json.loads(vm_file(prefix + "out") or "")
    except ValueError:
        report = None
    sent = recorded_motion(vm_file(prefix + "rec"))

    found, _ = frames(bytes(log.stream))
    received = [(off, f) for off, f in found if is_motion(f)]
    stalled = log.stall is not None and log.resume is not None
    wire_end = (log.rx_at_resume or 0) + log.backlog
    # frames whose first byte left the UART before its transmitter stood still (in the socket at the latest
    # at the resume), and what the guest still held
    left = [f for off, f in received if off < wire_end] if stalled else [f for _, f in received]
    held = [(off, f) for off, f in received if off >= wire_end] if stalled else []
    skipped = frames(bytes(log.stream[wire_end:]))[1] if stalled else 0
    figures = {}
    if log.stall is None:
        fails.append("the robot never stalled: it read fewer than its %d non-zero motion frames and %d zero ones "
                     "after them; VM: %s" % (stall_after, zeros_after, vm_note or "no %svm" % prefix))
    elif log.resume is None:
        fails.append("the robot stalled but never resumed")
    if not sent:
        fails.append("no motion frame in commission's recording (artifacts-sja1000/scn/%srec)" % prefix)

    # what reached the robot against what commission wrote: the first frames unaltered and in order, then
    # the 16550's stale frames, a gap (what the flush dropped), then the last frames written (the stop frames)
    n = len(left)
    if [f for _, f in sent[:n]] != left:
        i = next((i for i, (_, f) in enumerate(sent[:n]) if f != left[i]), min(n, len(sent)))
        fails.append("the %d motion frames the robot read before the stall are not the first %d commission wrote "
                     "(first difference at frame %d)" % (n, n, i))
    stale_n = 0
    while stale_n < len(held) and n + stale_n < len(sent) and held[stale_n][1] == sent[n + stale_n][1]:
        stale_n += 1
    rest = [f for _, f in held[stale_n:]]
    gap_at = len(sent) - len(rest)
    if stalled and sent and ([f for _, f in sent[gap_at:]] != rest or gap_at < n + stale_n):
        fails.append("what arrived after the resume (%d frames) is not the stale frames followed by the last "
                     "frames commission wrote" % len(held))
    flushed = max(0, gap_at - n - stale_n)

    # commission's own clock (its recording): the frame in transmission when the transmitter stood still,
    # the moving frames written after it, the first stop frame
    timing = ""
    if stalled and 0 < n <= len(sent):
        t_stall, stall_frame = sent[n - 1]
        after = sent[n:]
        moving_after = [(t, f) for t, f in after if moving(f)]
        first_zero = next(((t, f) for t, f in after if not moving(f)), None)
        t_last = moving_after[-1][0] if moving_after else t_stall
        if moving(stall_frame) != moving_step:
            fails.append("the transmitter stood still while commission sent %s (the stall is in %s): %s"
                         % ("a moving frame" if moving(stall_frame) else "zero", stall_step, stall_frame.hex(" ")))
        if moving_step:
            if len(moving_after) > COMMISSION_MAX_MOVING_AFTER_STALL:
                fails.append("%d moving frames written after the UART's transmitter stood still (limit %d: its "
                             "FIFO, then 2 frames queued)" % (len(moving_after), COMMISSION_MAX_MOVING_AFTER_STALL))
            if first_zero is None:
                fails.append("commission wrote no zero frame after the stall")
            elif first_zero[0] - t_last > COMMISSION_STOP_AFTER_LAST_MOVING:
                fails.append("the first stop frame was written %.0f ms after the last moving one (limit %.0f ms)"
                             % ((first_zero[0] - t_last) * 1000, COMMISSION_STOP_AFTER_LAST_MOVING * 1000))
            if first_zero is not None and any(moving(f) for t, f in after if t >= first_zero[0]):
                fails.append("commission wrote moving frames after its first stop frame")
            timing = ("after the frame in transmission when the UART stood still (written at +0 ms) commission "
                      "wrote %d moving frames, the last at +%.0f ms, its first stop frame at %s; "
                      % (len(moving_after), (t_last - t_stall) * 1000,
                         "+%.0f ms" % ((first_zero[0] - t_stall) * 1000) if first_zero else "never"))
        else:
            # standing: nothing but zeros, and everything (the frames before the first one held back, then the
            # stop frames) written within both bounds after the frame in transmission
            if moving_after:
                fails.append("%d moving frames written in a standing step" % len(moving_after))
            if not after:
                fails.append("commission wrote no frame after the stall (no stop frames)")
            elif after[-1][0] - t_stall > COMMISSION_STANDING_END:
                fails.append("commission wrote its last frame %.0f ms after the frame in transmission when the "
                             "UART stood still (limit %.0f ms)" % ((after[-1][0] - t_stall) * 1000,
                                                                   COMMISSION_STANDING_END * 1000))
            timing = ("after the frame in transmission when the UART stood still (written at +0 ms) commission "
                      "wrote %d zero frames, the last at %s; "
                      % (len(after), "+%.0f ms" % ((after[-1][0] - t_stall) * 1000) if after else "-"))

    # after the resume, beyond the socket's backlog: the stale frames, then zeros only
    from_vm = [f for _, f in held]
    first_zero = next((i for i, f in enumerate(from_vm) if not moving(f)), None)
    stale = sum(1 for f in from_vm[:first_zero] if moving(f))
    zeros = sum(1 for f in from_vm if not moving(f))
    nz_after_zero = sum(1 for f in from_vm[first_zero:] if moving(f)) if first_zero is not None else 0
    lat = ""
    if first_zero is not None and log.resume is not None:
        tz = log.time_of(held[first_zero][0])
        if tz is not None:
            lat = ", the first %.0f ms after the resume" % ((tz - log.resume) * 1000)
    if stalled:
        if stale > COMMISSION_MAX_STALE:
            fails.append("%d stale non-zero motion frames reached the robot after it read on, before the first "
                         "zero (limit %d: the 16550's FIFO)" % (stale, COMMISSION_MAX_STALE))
        if zeros == 0:
            fails.append("no zero motion frame reached the robot after it read on")
        if nz_after_zero:
            fails.append("%d non-zero motion frames after the first zero" % nz_after_zero)
    if received and moving(received[-1][1]):
        fails.append("the last motion frame the robot read moves: %s" % received[-1][1].hex(" "))

    # the exit status and the report
    abort = (report or {}).get("abort") or {}
    steps = (report or {}).get("steps") or []
    ran = [s.get("name") for s in steps if s.get("run") is True]
    if rc != "1":
        fails.append("commission exit status %s (want 1: the serial peer stalled)" % (rc or "unknown"))
    if report is None:
        fails.append("no JSON report on commission's stdout")
    else:
        if report.get("verdict") != "aborted" or abort.get("reason") != "peer_stalled":
            fails.append("the report's verdict %r, abort %r (want aborted, peer_stalled)"
                         % (report.get("verdict"), abort.get("reason")))
        if "not draining" not in (abort.get("message") or ""):
            fails.append("the abort's message does not say 'not draining': %r" % abort.get("message"))
        if report.get("exit_status") != 1:
            fails.append("the report's exit_status %r (want 1)" % report.get("exit_status"))
        if stalled and report.get("stop_confirmed") is not True:
            fails.append("stop_confirmed %r although the robot read on within the 2 s the stop frames get"
                         % report.get("stop_confirmed"))
        want = COMMISSION_PLAN[:COMMISSION_PLAN.index(stall_step) + 1]
        if ran != want or [s.get("name") for s in steps] != COMMISSION_PLAN:
            fails.append("steps run %s: want %s (the stall's step last)" % (ran, ", ".join(want)))
        for f in report.get("figures") or []:
            figures[(f.get("name"), f.get("step"))] = f.get("value")
        for step in finished:
            for figure in COMMISSION_FIGURES.get(step, ()):
                if figures.get((figure, step)) is None:
                    fails.append("%s of %s (finished before the stall) has no value" % (figure, step))
        never = [s.get("name") for s in steps if s.get("run") is not True]
        valued = ["%s of %s" % key for key, value in figures.items() if key[1] in never and value is not None]
        if valued:
            fails.append("figures of steps never begun have values: %s" % ", ".join(valued))
    stop = (report or {}).get("stop") or ""
    m = re.search(r"(\d+) stale frames discarded before the stop frames", stop)
    discarded = int(m.group(1)) if m else 0
    m = re.search(r"(\d+) held back", stop)
    held_back = int(m.group(1)) if m else 0
    if report is not None and discarded == 0:
        fails.append("the report counts no stale frames discarded before the stop frames: %r" % stop)
    elif stalled and report is not None and discarded != flushed:
        # TIOCOUTQ counts the bytes the driver held: every frame with bytes among them never arrived whole
        fails.append("the report counts %d frames discarded, but %d of the frames commission wrote never reached "
                     "the robot" % (discarded, flushed))

    kept = ", ".join("%s %s %.3g" % (step, figure, figures[(figure, step)])
                     for step in finished for figure in COMMISSION_FIGURES.get(step, ())[:1]
                     if figures.get((figure, step)) is not None)
    summary = ("robot read %d motion frames (%d moving), stopped reading for %.1f s; at the resume QEMU's socket "
               "held %d bytes; %sthen from the guest: %d stale non-zero frames before the first zero, %d zero "
               "frames%s, %d non-zero after them; %d frames flushed (the report: %d discarded, %d held back); "
               "%d bytes skipped; exit %s; abort %s: %s; steps run: %s; kept: %s; VM: %s"
               % (len(left), sum(1 for f in left if moving(f)),
                  (log.resume - log.stall) if stalled else 0, log.backlog, timing, stale, zeros, lat,
                  nz_after_zero, flushed, discarded, held_back, skipped, rc or "?", abort.get("reason"),
                  (abort.get("message") or "")[:160], ", ".join(ran), kept or "-", vm_note or "-"))
    evidence = ["commission's stop: %s" % (stop or "(none)"), "robot: %s" % log.status_line]
    err = (vm_file(prefix + "err") or "").strip().splitlines()
    evidence += ["commission's stderr: %s" % line for line in err[-4:]]
    evidence.append("motion frames from the guest after the resume (first 8):")
    evidence += ["  @%d %s" % (off, f.hex(" ")) for off, f in held[:8]]
    evidence.append("the last 8 motion frames commission wrote (its recording):")
    evidence += ["  %.6f %s" % (t, f.hex(" ")) for t, f in sent[-8:]]
    return stall_step, fails, summary, evidence


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("serve")
    s.add_argument("--socket", required=True)
    s.add_argument("--log", required=True)
    s.add_argument("--stall-after", type=int, default=50, help="non-zero motion frames read before the stall")
    s.add_argument("--stall-for", type=float, default=3.0, help="seconds without reading")
    s.add_argument("--accept-timeout", type=int, default=120)
    s.add_argument("--session", action="append", default=[], metavar="NAME:AFTER:FOR",
                   help="a session started by '@session NAME' on the line: stall after AFTER moving frames for "
                        "FOR seconds; its chassis follows the commands")
    s.add_argument("--commission-stall-for", type=float, metavar="FOR",
                   help="the sessions commission_stall_<step> of COMMISSION_STALLS, each stalling FOR seconds")
    j = sub.add_parser("judge")
    j.add_argument("--log", required=True)
    j.add_argument("--vm-dir", required=True, help="the scenario's files (artifacts-sja1000/scn)")
    j.add_argument("--check", default=FIRST_SESSION, choices=[FIRST_SESSION, "commission_serial_stalled"])
    j.add_argument("--stall-after", type=int, default=50)
    j.add_argument("--max-stale", type=int, default=3)
    args = p.parse_args()
    return serve(args) if args.cmd == "serve" else judge(args)


if __name__ == "__main__":
    sys.exit(main())
