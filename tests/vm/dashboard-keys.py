#!/usr/bin/env python3
"""The operator at the arm64 suite's dashboard (host side, stdlib only).

QEMU serves the VM's second 16550 UART (/dev/ttyS1, the dashboard's terminal) on a Unix socket. This script
connects, waits until the dashboard has drawn its screen, then types as a person would: `a` (arm: "Arm
driving?"), `y`, Up held (a terminal's auto-repeat: ESC [ A every 30 ms) for 3 s, Space while Up is still
held, Up held 1 s more (a held key must not resume), then nothing for 1.5 s, then `q`. The keys are those of
src/dashboard/keys.rs. Everything the dashboard draws is saved to --screen for the evidence.
"""
import argparse
import os
import socket
import sys
import threading
import time

UP = b"\x1b[A"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--socket", required=True)
    parser.add_argument("--screen", required=True)
    parser.add_argument("--wait", type=float, default=600.0, help="seconds to wait for the screen")
    args = parser.parse_args()

    deadline = time.monotonic() + 30
    while True:
        try:
            sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            sock.connect(args.socket)
            break
        except OSError:
            if time.monotonic() > deadline:
                sys.exit(f"dashboard-keys: cannot connect to {args.socket}")
            time.sleep(0.2)

    seen = bytearray()
    answered = []
    drawn = threading.Event()

    def reader():
        with open(args.screen, "wb") as screen:
            while True:
                try:
                    chunk = sock.recv(65536)
                except OSError:
                    return
                if not chunk:
                    return
                screen.write(chunk)
                screen.flush()
                if not drawn.is_set():
                    seen.extend(chunk)
                    # A terminal answers the primary device attributes query (crossterm asks it, after the
                    # kitty keyboard query, to learn whether kitty's protocol is there: it is not, here).
                    if b"\x1b[c" in seen and not answered:
                        sock.sendall(b"\x1b[?62;22c")
                        answered.append(True)
                    if b"WATCHING" in seen:
                        drawn.set()

    thread = threading.Thread(target=reader, daemon=True)
    thread.start()
    if not drawn.wait(args.wait):
        sys.exit("dashboard-keys: the dashboard never drew WATCHING")
    time.sleep(1.0)

    def hold_up(seconds, then=None, at=None):
        end = time.monotonic() + seconds
        sent_then = False
        start = time.monotonic()
        while time.monotonic() < end:
            if then is not None and not sent_then and time.monotonic() - start >= at:
                sock.sendall(then)
                sent_then = True
            sock.sendall(UP)
            time.sleep(0.03)

    sock.sendall(b"a")
    time.sleep(1.5)
    sock.sendall(b"y")
    time.sleep(2.0)
    hold_up(3.0)
    # Space while Up repeats on: zero at once, and the held key does not drive again. The self-test
    # (TRACERCTL_VM_NO_SPACE=1) leaves Space out: the check must then fail (a release brakes down a ramp).
    space = None if os.environ.get("TRACERCTL_VM_NO_SPACE") == "1" else b" "
    hold_up(1.0, then=space, at=0.0)
    time.sleep(1.5)
    sock.sendall(b"q")
    thread.join(timeout=60)


if __name__ == "__main__":
    main()
