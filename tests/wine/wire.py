#!/usr/bin/env python3
"""What the .exe put on the wire, from relay.py's capture: every RS232 frame (5A A5, 13 bytes on TRACER,
checksum checked), when it left, and the motion commands (type 0x55, id 0x01) among them.

Usage: wire.py CAPTURE EVENTS [SINCE]
  SINCE  a wall-clock time (s): also say what was sent after it (the Ctrl-C)
Prints one line of key=value facts for tests/wine/run.sh. Test-only.
"""
import sys


def frames(data):
    """(offset, bytes) of each well-formed frame, resynchronising on 5A A5 like the robot does."""
    i = 0
    while i + 13 <= len(data):
        if data[i] == 0x5A and data[i + 1] == 0xA5:
            length = data[i + 2]
            end = i + 3 + length
            if length == 10 and end <= len(data) and sum(data[i:end - 1]) & 0xFF == data[end - 1]:
                yield i, data[i:end]
                i = end
                continue
        i += 1


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    data = open(sys.argv[1], "rb").read()
    chunks = []
    for line in open(sys.argv[2]):
        at, offset, length = line.split()
        chunks.append((float(at), int(offset), int(length)))
    since = float(sys.argv[3]) if len(sys.argv) == 4 else None

    def sent_at(offset):
        for at, start, length in chunks:
            if start <= offset < start + length:
                return at
        return None

    motion = []
    total = 0
    for offset, frame in frames(data):
        total += 1
        if frame[3] == 0x55 and frame[4] == 0x01:
            # Payload: control mode, fault clear, linear %, angular %, 2 reserved, frame id; percent signed.
            linear = int.from_bytes(frame[7:8], "big", signed=True)
            angular = int.from_bytes(frame[8:9], "big", signed=True)
            motion.append((sent_at(offset), linear, angular))
    moving = [m for m in motion if m[1] or m[2]]
    trailing_zero = 0
    for m in reversed(motion):
        if m[1] or m[2]:
            break
        trailing_zero += 1
    facts = {
        "bytes": len(data),
        "frames": total,
        "motion": len(motion),
        "moving": len(moving),
        "moving_linear_percent": sorted({m[1] for m in moving}),
        "last": "zero" if motion and not (motion[-1][1] or motion[-1][2]) else ("moving" if motion else "none"),
        "trailing_zero": trailing_zero,
    }
    if since is not None:
        after = [m for m in motion if m[0] is not None and m[0] >= since]
        facts["after_signal"] = len(after)
        facts["moving_after_signal"] = sum(1 for m in after if m[1] or m[2])
        # A frame already on its way when the signal came may arrive just after it; later ones must be zero.
        facts["moving_100ms_after_signal"] = sum(1 for m in after if (m[1] or m[2]) and m[0] >= since + 0.1)
        facts["zero_after_signal"] = sum(1 for m in after if not (m[1] or m[2]))
        last_moving = max((m[0] for m in moving if m[0] is not None), default=None)
        facts["last_moving_ms_after_signal"] = (
            "none" if last_moving is None else round((last_moving - since) * 1000))
    print(" ".join(f"{key}={str(value).replace(' ', '')}" for key, value in facts.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
