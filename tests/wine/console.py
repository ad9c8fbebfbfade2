#!/usr/bin/env python3
"""Runs a command on a new pseudo-terminal, as if typed in a terminal window: wine then gives the Windows
program a console (its Ctrl-C handling and GenerateConsoleCtrlEvent need one).

Usage: console.py TRANSCRIPT TIMEOUT_S COMMAND [ARG...]
  TRANSCRIPT  everything the terminal showed (the command's own redirections go elsewhere)
Exit status: the command's (128 + N for a signal N); 124 after TIMEOUT_S (the command is killed). Test-only.
"""
import os
import pty
import select
import signal
import sys
import time


def main():
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    transcript, timeout, command = sys.argv[1], float(sys.argv[2]), sys.argv[3:]
    pid, master = pty.fork()
    if pid == 0:
        os.execvp(command[0], command)
    deadline = time.monotonic() + timeout
    seen = b""
    status = None
    while status is None:
        ready, _, _ = select.select([master], [], [], 0.1)
        if ready:
            try:
                seen += os.read(master, 65536)
            except OSError:
                pass
        done, wait_status = os.waitpid(pid, os.WNOHANG)
        if done:
            status = wait_status
        elif time.monotonic() > deadline:
            os.killpg(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            open(transcript, "wb").write(seen)
            return 124
    open(transcript, "wb").write(seen)
    code = os.waitstatus_to_exitcode(status)
    return 128 - code if code < 0 else code


if __name__ == "__main__":
    sys.exit(main())
