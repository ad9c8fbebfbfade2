#!/usr/bin/env python3
"""tracerctl's ASC and trc readers against python-can's (issue 28): every frame python-can reads from each
file given, with its time on the clock (ASCReader(relative_timestamp=False): the `date` line; TRCReader:
`;$STARTTIME`), is the frame `tracerctl decode -f json` writes, in order: time to the microsecond,
identifier, data, error frame or not. Run with TZ=UTC: ASC dates are local time, for both readers.

Usage: compare_python_can.py TRACERCTL FILE...
"""

import json
import subprocess
import sys

import can


def python_can(path):
    if path.endswith(".asc"):
        reader = can.ASCReader(path, relative_timestamp=False)
    else:
        reader = can.TRCReader(path)
    frames = []
    for msg in reader:
        if msg.is_error_frame:
            # python-can writes an error frame to candump logs as 20000080# and eight zero bytes.
            frames.append((round(msg.timestamp * 1e6), "0x20000080", "0000000000000000"))
        else:
            frames.append((round(msg.timestamp * 1e6), f"0x{msg.arbitration_id:X}", msg.data.hex().upper()))
    return frames


def tracerctl(binary, path):
    out = subprocess.run([binary, "decode", "-f", "json", path], check=True, capture_output=True, text=True)
    frames = []
    for line in out.stdout.splitlines():
        event = json.loads(line)
        frames.append((event["ts_ns"] // 1000, event["id"], event["data"]))
    return frames


def main():
    binary, paths = sys.argv[1], sys.argv[2:]
    failed = False
    for path in paths:
        theirs, ours = python_can(path), tracerctl(binary, path)
        if theirs != ours or not ours:
            failed = True
            print(f"{path}: python-can and tracerctl differ", file=sys.stderr)
            for pair in zip(theirs, ours):
                print(f"  python-can {pair[0]}\n  tracerctl  {pair[1]}", file=sys.stderr)
            print(f"  ({len(theirs)} frames against {len(ours)})", file=sys.stderr)
        else:
            errors = sum(1 for frame in ours if frame[1] == "0x20000080")
            print(f"{path}: {len(ours)} frames ({errors} error frames) the same as python-can's, from {ours[0][0]} us")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
