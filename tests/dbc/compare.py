#!/usr/bin/env python3
"""docs/tracer.dbc against tracerctl: the same log decoded by cantools and by `tracerctl decode --format json`
must give identical values for every field of every frame.

    python3 tests/dbc/compare.py [TRACERCTL]      (run by .ci/run after `pip install cantools`)

The log: a generated TRACER session (cargo run --example gen_log) plus frames for every other V2 message in
docs/tracer.dbc, with deterministic pseudo-random contents that cover signs, extremes and undefined enum values.
"""

import json
import os
import random
import subprocess
import sys
import tempfile

import cantools

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Fields tracerctl derives or adds beyond the frame's signals: fault names, and the motor number (in the ID).
DERIVED = {"faults", "driver_faults", "motor"}


def extra_frames(rng, count):
    """(id, data) for the messages the generated session does not contain."""
    frames = []
    for _ in range(count):
        frames.append((0x121, bytes([rng.randint(0, 1), rng.randint(0, 4), rng.randint(0, 100), 0, 0, 0, 0,
                                     rng.randint(0, 255)])))
        frames.append((0x241, bytes(rng.randint(0, 255) for _ in range(8))))
        frames.append((0x421, bytes([rng.randint(0, 4)])))
        frames.append((0x441, bytes([rng.randint(0, 3)])))
        frames.append((0x41A, bytes(rng.randint(0, 255) for _ in range(8))))
        frames.append((0x211, bytes([rng.randint(0, 3), rng.randint(0, 4)] + [rng.randint(0, 255) for _ in range(6)])))
        frames.append((0x111, bytes(rng.randint(0, 255) for _ in range(4)) + bytes(4)))
        frames.append((0x311, bytes(rng.randint(0, 255) for _ in range(8))))
        frames.append((0x261 + rng.randint(0, 1), bytes(rng.randint(0, 255) for _ in range(8))))
        frames.append((0x251 + rng.randint(0, 1), bytes(rng.randint(0, 255) for _ in range(8))))
    return frames


def same(json_value, dbc_value):
    """Whether tracerctl's JSON value and cantools' value say the same thing."""
    if isinstance(json_value, bool):
        return str(dbc_value) == ("true" if json_value else "false")
    if isinstance(json_value, str):
        if json_value.startswith("unknown_0x"):
            return not isinstance(dbc_value, str) and int(dbc_value) == int(json_value[len("unknown_0x"):], 16)
        if "." in json_value and json_value.replace(".", "").isdigit():  # version "major.minor"
            major, minor = (int(part) for part in json_value.split("."))
            return int(dbc_value) == (major << 8 | minor)
        return str(dbc_value) == json_value
    value = float(dbc_value)
    return abs(value - json_value) <= 1e-9 * max(1.0, abs(json_value))


def main():
    tracerctl = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target", "debug", "tracerctl")
    db = cantools.database.load_file(os.path.join(ROOT, "docs", "tracer.dbc"))
    with tempfile.TemporaryDirectory() as work:
        log = os.path.join(work, "session.log")
        subprocess.run(["cargo", "run", "--quiet", "--locked", "--example", "gen_log", "--", "20000", log],
                       cwd=ROOT, check=True)
        rng = random.Random(2026)
        with open(log, "a") as out:
            for index, (can_id, data) in enumerate(extra_frames(rng, 500)):
                out.write(f"(1700001000.{index:06d}) can0 {can_id:03X}#{data.hex().upper()}\n")
        decoded = subprocess.run([tracerctl, "decode", "--format", "json", log], capture_output=True, text=True,
                                 check=True).stdout.splitlines()
        with open(log) as lines:
            frames = [line.split()[2].split("#") for line in lines]

    assert len(decoded) == len(frames), f"{len(decoded)} JSON lines for {len(frames)} frames"
    compared = 0
    mismatches = []
    messages = set()
    for (id_text, data_text), line in zip(frames, decoded):
        obj = json.loads(line)
        dbc = db.decode_message(int(id_text, 16), bytes.fromhex(data_text))
        fields = {k: v for k, v in obj["fields"].items() if k not in DERIVED}
        messages.add(obj["msg"])
        if set(fields) != set(dbc) - {"request"}:
            mismatches.append(f"{id_text}#{data_text}: fields {sorted(fields)} vs DBC signals {sorted(dbc)}")
            continue
        for name, value in fields.items():
            compared += 1
            if not same(value, dbc[name]):
                mismatches.append(f"{id_text}#{data_text}: {name}: tracerctl {value!r}, cantools {dbc[name]!r}")
    print(f"compared {len(frames)} frames of {len(messages)} messages ({', '.join(sorted(messages))}): "
          f"{compared} field values")
    if mismatches:
        print(f"{len(mismatches)} MISMATCHES:")
        for mismatch in mismatches[:30]:
            print("  " + mismatch)
        sys.exit(1)
    print("DBC COMPARISON PASS: cantools and tracerctl agree on every value")


if __name__ == "__main__":
    main()
