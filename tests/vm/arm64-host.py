#!/usr/bin/env python3
"""The host side of the arm64 suite (tests/vm/run.sh --suite arm64); python3, stdlib only (the VM has none).

serve: listens on four Unix sockets that QEMU connects to as chardevs, and starts the host's own (x86)
       `tracerctl sim --serial PTY` on a pseudo-terminal it creates:
         rs232  the VM's PCI 16550 UART (ttyS0, the kernel's 8250 driver): bytes from the guest go to the
                simulator's pseudo-terminal, the simulator's bytes go back to the guest. Both directions are
                logged with host timestamps: the log is the witness of what left the guest's UART.
                The simulator talks all the time; a closed UART loses what arrives. So what it sends reaches
                the guest only while a check has ttyS0 open (between the markers "begin serial_*" and
                "end serial_*"): queued here while QEMU cannot take it (a slow or stalled VM), up to 2 s of it;
                outside, and whatever is still queued at "end", it is discarded (counted in the log).
         term   a virtio console (hvc0): the guest's "terminal emulator". What the guest writes there (the keys)
                goes to the dashboard's terminal; what the dashboard draws comes back here (the screen).
         tty    a virtio console (hvc1): the terminal the dashboard runs on (a real tty with termios).
         marks  a virtio serial port: the scenario's markers ("begin NAME tx=N", "sigint tx=N", "end NAME tx=N")
                and the timing witness (candump -L lines of a cangen 0x7F3 every 10 ms), logged on the same
                clock as the UART's bytes. tx=N is ttyS0's transmit counter when the marker was written: the
                marker sits at byte N of the UART's stream, which stays exact when the host's scheduling
                delivers the marker and the UART's bytes together.
       Log lines: "<seconds> <kind> <payload>"; kinds tx (guest -> robot, hex), rx (robot -> guest, hex),
       key, scr (hex), mark (text), info.
judge: reads that log and the scenario's files (artifacts-arm64/scn) and prints a CHECK line per host-judged
       check (serial_drive, serial_sigint), followed on failure by evidence lines starting with "  | ".
"""
import argparse
import fcntl
import os
import selectors
import signal
import socket
import subprocess
import sys
import time
import tty

FRAME = 13
# robot -> guest: what may wait here while the port is open and QEMU cannot take it (2 s of 250 frames/s)
RX_QUEUE_MAX = 500 * FRAME


def checksum(data):
    return sum(data) & 0xFF


def frames(data):
    """(offset, frame) of every valid 13-byte frame in a byte stream, and the bytes that are in none."""
    out = []
    skipped = 0
    i = 0
    while i + FRAME <= len(data):
        c = data[i:i + FRAME]
        if c[0] == 0x5A and c[1] == 0xA5 and c[2] == 0x0A and c[3] in (0x55, 0xAA) and checksum(c[:12]) == c[12]:
            out.append((i, bytes(c)))
            i += FRAME
        else:
            skipped += 1
            i += 1
    return out, skipped + max(0, len(data) - i)


# ------------------------------------------------------------------------------------------------ serve

def serve(args):
    t0 = time.monotonic()
    log = open(args.log, "w", buffering=1)

    def event(kind, text=""):
        log.write("%.6f %s %s\n" % (time.monotonic() - t0, kind, text))

    names = ("rs232", "term", "tty", "marks")
    listeners = {}
    for name in names:
        path = os.path.join(args.dir, name + ".sock")
        try:
            os.unlink(path)
        except FileNotFoundError:
            pass
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        s.bind(path)
        s.listen(1)
        listeners[name] = s

    # the simulator on a pseudo-terminal of our own: we hold the master, it opens the slave as its serial port
    master, slave = os.openpty()
    tty.setraw(slave)
    slave_path = os.ttyname(slave)
    fl = fcntl.fcntl(master, fcntl.F_GETFL)
    fcntl.fcntl(master, fcntl.F_SETFL, fl | os.O_NONBLOCK)
    sim_out = open(args.sim_out, "w")
    sim = subprocess.Popen([args.sim_bin, "sim", "--serial", slave_path], stdin=subprocess.DEVNULL,
                           stdout=sim_out, stderr=subprocess.STDOUT)
    # the slave stays open here too: the master would read EIO whenever the simulator has it closed
    event("info", "sim pid %d on %s: %s sim --serial %s" % (sim.pid, slave_path, args.sim_bin, slave_path))

    stop = {"now": False}

    def on_term(signum, frame):
        stop["now"] = True

    signal.signal(signal.SIGTERM, on_term)
    signal.signal(signal.SIGINT, on_term)

    sel = selectors.DefaultSelector()
    for name, s in listeners.items():
        sel.register(s, selectors.EVENT_READ, ("listen", name))
    sel.register(master, selectors.EVENT_READ, ("pty", None))
    with open(os.path.join(args.dir, "ready"), "w") as f:
        f.write("%s\n" % slave_path)

    conns = {}
    counts = {"rx_sent": 0, "rx_closed": 0, "rx_overrun": 0, "scr_dropped": 0, "tx": 0}
    marks_buf = b""
    rx = {"open": False, "queue": bytearray()}
    deadline = time.monotonic() + args.accept_timeout

    def rs232_flush():
        """Send what the simulator said to QEMU, as much as its socket takes now; wait for writability else."""
        c = conns.get("rs232")
        if c is None:
            return
        q = rx["queue"]
        while q:
            try:
                n = c.send(bytes(q[:4096]), socket.MSG_DONTWAIT)
            except (BlockingIOError, InterruptedError):
                break
            except OSError:
                n = 0
            if n <= 0:
                break
            event("rx", bytes(q[:n]).hex())
            counts["rx_sent"] += n
            del q[:n]
        sel.modify(c, selectors.EVENT_READ | (selectors.EVENT_WRITE if q else 0), ("conn", "rs232"))

    def rs232_read():
        """Read what the guest's UART sent; False when nothing was there (or at EOF)."""
        c = conns.get("rs232")
        if c is None:
            return False
        try:
            data = c.recv(65536, socket.MSG_DONTWAIT)
        except BlockingIOError:
            return False
        except ConnectionResetError:  # QEMU exited
            data = b""
        except OSError as error:
            event("info", "rs232 recv error: %s" % error)
            data = b""
        if not data:
            event("info", "rs232 eof")
            sel.unregister(c)
            del conns["rs232"]
            return False
        counts["tx"] += len(data)
        event("tx", data.hex())
        view = memoryview(data)
        while view:
            try:
                n = os.write(master, view)
                view = view[n:]
            except BlockingIOError:
                time.sleep(0.001)
        return True

    while not stop["now"]:
        if len(conns) < len(names) and time.monotonic() > deadline:
            event("info", "error: QEMU connected only %s within %d s" % (sorted(conns), args.accept_timeout))
            break
        if sim.poll() is not None:
            event("info", "error: the simulator exited with status %s" % sim.returncode)
            break
        for key, mask in sel.select(timeout=0.5):
            kind, name = key.data
            if kind == "listen":
                c, _ = key.fileobj.accept()
                key.fileobj.close()
                sel.unregister(key.fileobj)
                if name == "rs232":
                    c.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4096)
                conns[name] = c
                sel.register(c, selectors.EVENT_READ, ("conn", name))
                event("info", "connected %s" % name)
            elif kind == "pty":
                try:
                    data = os.read(master, 65536)
                except (BlockingIOError, InterruptedError):
                    continue
                except OSError as error:  # EIO: the simulator closed the port
                    event("info", "pty read error: %s" % error)
                    sel.unregister(master)
                    continue
                if not rx["open"] or "rs232" not in conns:
                    counts["rx_closed"] += len(data)
                    continue
                room = RX_QUEUE_MAX - len(rx["queue"])
                if room < len(data):
                    counts["rx_overrun"] += len(data) - max(room, 0)
                    data = data[:max(room, 0)]
                rx["queue"] += data
                rs232_flush()
            elif name == "rs232":
                if mask & selectors.EVENT_WRITE:
                    rs232_flush()
                if mask & selectors.EVENT_READ:
                    rs232_read()
            else:
                c = key.fileobj
                try:
                    data = c.recv(65536)
                except ConnectionResetError:  # QEMU exited
                    data = b""
                except OSError as error:
                    event("info", "%s recv error: %s" % (name, error))
                    data = b""
                if not data:
                    event("info", "%s eof" % name)
                    sel.unregister(c)
                    del conns[name]
                    continue
                if name == "term":  # keys typed on the guest's terminal -> the dashboard's tty
                    event("key", data.hex())
                    if "tty" in conns:
                        conns["tty"].sendall(data)
                elif name == "tty":  # the dashboard's screen -> the guest's terminal (dropped if it does not read)
                    event("scr", data.hex())
                    if "term" in conns:
                        try:
                            n = conns["term"].send(data, socket.MSG_DONTWAIT)
                        except (BlockingIOError, OSError):
                            n = 0
                        counts["scr_dropped"] += len(data) - n
                elif name == "marks":
                    # everything the UART sent before this marker was written is in the rs232 socket by now
                    while rs232_read():
                        pass
                    marks_buf += data
                    *lines, marks_buf = marks_buf.split(b"\n")
                    for line in lines:
                        text = line.decode("utf-8", "replace").rstrip("\r")
                        event("mark", text)
                        # a check opens ttyS0 after "begin serial_*" and has closed it before "end serial_*"
                        if text.startswith("begin serial_"):
                            rx["open"] = True
                        elif text.startswith("end serial_"):
                            rx["open"] = False
                            counts["rx_closed"] += len(rx["queue"])
                            del rx["queue"][:]
                            if "rs232" in conns:
                                rs232_flush()
    event("info", "counts %s" % " ".join("%s=%d" % kv for kv in sorted(counts.items())))
    if sim.poll() is None:
        sim.send_signal(signal.SIGINT)
        try:
            sim.wait(5)
        except subprocess.TimeoutExpired:
            sim.kill()
            sim.wait()
    event("info", "sim exit status %s" % sim.returncode)
    return 0


# ------------------------------------------------------------------------------------------------ judge

class Log:
    def __init__(self, path):
        self.tx = bytearray()
        self.tx_at = []  # (offset of a chunk's first byte, host time)
        self.marks = []  # (host time, text, offset in tx at that moment)
        self.witness = []  # host times of witness lines (candump -L of 0x7F3)
        self.info = []
        with open(path) as f:
            for line in f:
                parts = line.rstrip("\n").split(" ", 2)
                if len(parts) < 2:
                    continue
                t, kind = float(parts[0]), parts[1]
                rest = parts[2] if len(parts) > 2 else ""
                if kind == "tx":
                    self.tx_at.append((len(self.tx), t))
                    self.tx += bytes.fromhex(rest)
                elif kind == "mark":
                    if " 7F3#" in rest:
                        self.witness.append(t)
                    else:
                        # "TEXT tx=N": at byte N of the UART's stream (ttyS0's counter); else where it was logged
                        text, offset = rest.strip(), len(self.tx)
                        head, _, tail = text.rpartition(" tx=")
                        if head and tail.isdigit():
                            text, offset = head, int(tail)
                        self.marks.append((t, text, offset))
                elif kind == "info":
                    self.info.append(rest)

    def time_of(self, offset):
        """Host time of the chunk holding byte `offset`."""
        t = None
        for start, at in self.tx_at:
            if start > offset:
                break
            t = at
        return t

    def mark(self, text):
        for m in self.marks:
            if m[1] == text:
                return m
        return None


def is_motion(f):
    return f[3] == 0x55 and f[4] == 0x01


def moving(f):
    return f[7] != 0 or f[8] != 0 or f[9] != 0


def hexf(f):
    return f.hex(" ").upper()


def cadence(times, witness, lo, hi, limit):
    """(ok, text): median gap within [lo, hi] ms, no gap over limit ms except VM-wide stalls the witness shares."""
    gaps = [(b - a) * 1000 for a, b in zip(times, times[1:])]
    if len(gaps) < 8:
        return False, "only %d frames" % len(times)
    med = sorted(gaps)[len(gaps) // 2]
    worst = 0
    stalls = []
    for (a, b), g in zip(zip(times, times[1:]), gaps):
        if g > limit and witness:
            inside = [w for w in witness if a < w < b]
            pts = [a] + inside + [b]
            silence = max((y - x) * 1000 for x, y in zip(pts, pts[1:]))
            if silence >= g - 40:
                stalls.append(g)
                continue
        worst = max(worst, g)
    ok = lo <= med <= hi and worst < limit
    text = "n=%d median=%.1fms min=%.1fms max=%.1fms" % (len(times), med, min(gaps), worst)
    if stalls:
        text += " (+%d VM-wide stall(s) shared by the witness, ms: %s)" % (
            len(stalls), " ".join("%.0f" % g for g in stalls))
    if not ok:
        text += " (want median %d-%d ms, max < %d ms)" % (lo, hi, limit)
    return ok, text


def segment(log, name):
    """(begin mark, end mark, frames found between them with their host times, skipped bytes) or None."""
    b, e = log.mark("begin " + name), log.mark("end " + name)
    if b is None or e is None:
        return None
    data = bytes(log.tx[b[2]:e[2]])
    found, skipped = frames(data)
    out = [(b[2] + off, f, log.time_of(b[2] + off + FRAME - 1)) for off, f in found]
    return b, e, out, skipped


def vm_file(vm_dir, name):
    try:
        with open(os.path.join(vm_dir, name)) as f:
            return f.read().strip()
    except OSError:
        return None


def reported_frames(vm_dir, name):
    """drive's output (stdout and stderr) and the N of its 'N motion frames sent' (None if absent)."""
    out = (vm_file(vm_dir, name + ".out") or "") + "\n" + (vm_file(vm_dir, name + ".err") or "")
    for line in out.splitlines():
        words = line.split()
        if len(words) > 3 and words[1:4] == ["motion", "frames", "sent"] and words[0].isdigit():
            return out, int(words[0])
    return out, None


def count_check(motion, reported, fails):
    """On RS232 the mode request is a zero-speed motion frame that drive counts apart ("mode frames"): the wire
    holds exactly one more motion frame than drive reports, and the first one is zero."""
    if reported is None:
        fails.append("drive's report gives no 'N motion frames sent'")
        return "no count reported"
    if len(motion) != reported + 1:
        fails.append("%d motion frames on the wire, drive reports %d sent (+ 1 mode request expected)"
                     % (len(motion), reported))
        return "drive reports %d sent" % reported
    if moving(motion[0][1]):
        fails.append("the first motion frame (the mode request) moves: %s" % hexf(motion[0][1]))
    return "the %d drive reports sent + the mode request, a zero frame it counts apart" % reported


def judge_drive(log, vm_dir, want_pct):
    fails = []
    ev = []
    seg = segment(log, "serial_drive")
    rc = vm_file(vm_dir, "serdrive.rc")
    if seg is None:
        return "FAIL no 'begin/end serial_drive' markers in the host log (did the check run?)", ev
    _, _, fr, skipped = seg
    motion = [(o, f, t) for o, f, t in fr if is_motion(f)]
    other = [f for _, f, _ in fr if not is_motion(f)]
    nz = [f for _, f, _ in motion if moving(f)]
    pcts = sorted({f[7] for _, f, _ in motion})
    bad_mode = [f for _, f, _ in motion if f[5] != 0x02 or f[6] != 0]
    bad_rest = [f for _, f, _ in motion if f[8] != 0 or f[9] != 0 or f[10] != 0 or f[7] > want_pct]
    ids = [f[11] for _, f, _ in motion]
    id_jumps = sum(1 for a, b in zip(ids, ids[1:]) if b != (a + 1) & 0xFF)
    times = [t for _, _, t in motion]
    ok_c, ctext = cadence(times, log.witness, 15, 25, 100)
    if not ok_c and len(times) > 8:
        # A VM that the host stops now and then (a loaded host) sends its UART's bytes in bursts when it runs
        # again: the gaps on the host's clock are then QEMU's. When the witness shows such stalls, the mean
        # period over the whole drive is what can be judged.
        inside = [w for w in log.witness if times[0] <= w <= times[-1]]
        pts = [times[0]] + inside + [times[-1]]
        silence = max((b - a) * 1000 for a, b in zip(pts, pts[1:]))
        mean = (times[-1] - times[0]) * 1000 / (len(times) - 1)
        if inside and silence >= 60 and 15 <= mean <= 25:
            ok_c = True
            ctext += ("; the VM stalled (the witness silent up to %.0f ms): bursts on the host's clock, judged by "
                      "the mean period instead, %.1f ms" % (silence, mean))
    trailing = 0
    for _, f, _ in reversed(motion):
        if moving(f):
            break
        trailing += 1
    span = (motion[-1][2] - motion[0][2]) if motion else 0
    out, reported = reported_frames(vm_dir, "serdrive")
    if rc != "0":
        fails.append("drive exit status %s (want 0)" % rc)
    if skipped:
        fails.append("%d bytes on the wire are in no valid frame" % skipped)
    if other:
        fails.append("%d frames other than motion commands (first %s)" % (len(other), hexf(other[0])))
    if not motion:
        fails.append("no motion frame (5A A5 0A 55 01 ...) left the guest's UART")
    else:
        if bad_mode:
            fails.append("%d motion frames without serial mode 02 / fault clear 00 (first %s)" % (len(bad_mode), hexf(bad_mode[0])))
        if bad_rest:
            fails.append("%d motion frames with angular, lateral or reserved bytes set or linear above %d %% (first %s)"
                         % (len(bad_rest), want_pct, hexf(bad_rest[0])))
        if want_pct not in pcts:
            fails.append("linear never reached %d %% (0x%02X; 0.2 m/s of 1.5 m/s full scale): values %s"
                         % (want_pct, want_pct, pcts))
        if id_jumps:
            fails.append("the frame id does not count up by one %d times" % id_jumps)
        if not ok_c:
            fails.append("cadence: " + ctext)
        if moving(motion[-1][1]):
            fails.append("the last motion frame moves: %s" % hexf(motion[-1][1]))
        if not 0.8 <= span <= 5:
            fails.append("motion frames span %.2f s by the host's clock (want about 1 s: 0.8-5)" % span)
    counted = count_check(motion, reported, fails) if motion else "-"
    summary = ("%d motion frames on the wire (%s), all 5A A5 0A 55 01 02 00 LL 00 00 00 id sum with frame ids "
               "counting up; %d moving, linear %% LL %s; %s; %d zero frames at the end; span %.2f s; drive exit %s"
               % (len(motion), counted, len(nz), " ".join("%d" % p for p in pcts), ctext, trailing, span, rc))
    if fails:
        ev.append("motion frames on the wire (host time, bytes), first 6 and last 6:")
        shown = motion[:6] + ([None] if len(motion) > 12 else []) + motion[max(6, len(motion) - 6):]
        for m in shown:
            ev.append("  ..." if m is None else "  %.3f %s" % (m[2], hexf(m[1])))
        ev.append("drive's output: " + " / ".join(out.split("\n")[-6:]))
        return "FAIL %s [%s]" % ("; ".join(fails), summary), ev
    return "PASS " + summary, ev


def judge_sigint(log, vm_dir):
    fails = []
    ev = []
    seg = segment(log, "serial_sigint")
    rc = vm_file(vm_dir, "sersig.rc")
    sig = log.mark("sigint")
    if seg is None:
        return "FAIL no 'begin/end serial_sigint' markers in the host log (did the check run?)", ev
    _, _, fr, skipped = seg
    motion = [(o, f, t) for o, f, t in fr if is_motion(f)]
    if sig is None:
        return "FAIL no 'sigint' marker in the host log: the signal was not sent", ev
    before = [(o, f, t) for o, f, t in motion if o < sig[2]]
    after = [(o, f, t) for o, f, t in motion if o >= sig[2]]
    moving_before = sum(1 for _, f, _ in before if moving(f))
    first_zero = next((i for i, (_, f, _) in enumerate(after) if not moving(f)), None)
    nz_after_zero = sum(1 for _, f, _ in after[first_zero:] if moving(f)) if first_zero is not None else 0
    stale = first_zero if first_zero is not None else len(after)
    # host clock, for the record only: a loaded host delivers the marker and the UART's bytes in bursts
    lat = (after[first_zero][2] - sig[0]) * 1000 if first_zero is not None else None
    _, reported = reported_frames(vm_dir, "sersig")
    counted = count_check(motion, reported, fails) if motion else "-"
    if rc != "130":
        fails.append("drive exit status %s (want 130 after SIGINT)" % rc)
    if moving_before == 0:
        fails.append("no moving motion frame before the signal")
    if first_zero is None:
        fails.append("no zero motion frame after the signal")
    elif stale > 5:
        fails.append("%d moving frames left the UART after the signal before the first zero (limit 5: 100 ms of "
                     "frames already written, or a late stop)" % stale)
    if nz_after_zero:
        fails.append("%d moving frames after the first zero" % nz_after_zero)
    if motion and moving(motion[-1][1]):
        fails.append("the last motion frame moves: %s" % hexf(motion[-1][1]))
    if skipped:
        fails.append("%d bytes on the wire are in no valid frame" % skipped)
    summary = ("%d moving frames before SIGINT (ttyS0's transmit counter at the signal places it in the stream); "
               "after it %d moving (already on their way) then %d zero frames, the first %s after the signal by the "
               "host's clock, nothing moving after; last %s; %d motion frames on the wire (%s); drive exit %s"
               % (moving_before, stale, len(after) - stale, "%.0f ms" % lat if lat is not None else "-",
                  hexf(motion[-1][1]) if motion else "-", len(motion), counted, rc))
    if fails:
        ev.append("motion frames on the wire around the signal (host time relative to it, bytes):")
        around = before[-4:] + after[:8]
        for _, f, t in around:
            ev.append("  %+8.1f ms %s" % ((t - sig[0]) * 1000, hexf(f)))
        ev.append("drive's stderr: " + (vm_file(vm_dir, "sersig.err") or "(none)").replace("\n", " / ")[:400])
        return "FAIL %s [%s]" % ("; ".join(fails), summary), ev
    return "PASS " + summary, ev


def judge(args):
    try:
        log = Log(args.log)
    except OSError as error:
        for name in args.checks.split(","):
            print("CHECK %s: FAIL no host log (%s)" % (name, error))
        return 1
    failed = 0
    judges = {"serial_drive": lambda: judge_drive(log, args.vm_dir, args.want_percent),
              "serial_sigint": lambda: judge_sigint(log, args.vm_dir)}
    for name in args.checks.split(","):
        verdict, ev = judges[name]()
        print("CHECK %s: %s" % (name, verdict))
        if verdict.startswith("FAIL"):
            failed += 1
            for info in log.info:
                if "error" in info:
                    ev.append("helper: " + info)
            for line in ev:
                print("  | " + line)
    return 1 if failed else 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("serve")
    s.add_argument("--dir", required=True, help="where the sockets go")
    s.add_argument("--log", required=True)
    s.add_argument("--sim-bin", required=True, help="the host's tracerctl (runs `sim --serial PTY`)")
    s.add_argument("--sim-out", required=True, help="the simulator's output")
    s.add_argument("--accept-timeout", type=int, default=120)
    j = sub.add_parser("judge")
    j.add_argument("--log", required=True)
    j.add_argument("--vm-dir", required=True, help="the scenario's files (artifacts-arm64/scn)")
    j.add_argument("--checks", default="serial_drive,serial_sigint", help="which host-judged checks ran")
    j.add_argument("--want-percent", type=int, default=13, help="linear %% of drive --linear 0.2")
    args = p.parse_args()
    return serve(args) if args.cmd == "serve" else judge(args)


if __name__ == "__main__":
    sys.exit(main())
