#!/usr/bin/env python3
"""Judges the VM check `mcap_session` on the host (run.sh calls it): a simulator session recorded by
`tracerctl monitor --log session.mcap` while candump logged the same bus.

    python3 tests/mcap/vm_session.py DIR      (DIR: the VM's files, target/vm/artifacts/scn)

Prints one `CHECK mcap_session: PASS|FAIL ...` line (and `  | ` evidence lines on failure), as the VM's checks do:
  * the MCAP is finished (summary present: monitor ended on SIGTERM) and every message validates (verify.py);
  * its /tracer/raw frames, as ID#DATA, are exactly a contiguous run of what candump logged, in order;
  * the injected fault is logged on /tracer/events (a battery warning, set), the drive's commands are on
    /tracer/motion_command (+0.200 m/s, then zero), and the dead-reckoned pose ends ahead of where it began.
Needs: pip install mcap jsonschema.
"""

import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def verdict(ok, text, evidence=()):
    print(f"CHECK mcap_session: {'PASS' if ok else 'FAIL'} {text}")
    for line in evidence:
        print(f"  | {line}")
    return 0 if ok else 1


def bus_frames(path):
    """ID#DATA of every candump -L line but the scenario's 7F0-7F3 markers."""
    frames = []
    with open(path, encoding="utf-8", errors="replace") as log:
        for line in log:
            parts = line.split()
            if len(parts) >= 3 and parts[0].startswith("(") and "#" in parts[2]:
                ident = parts[2].split("#", 1)[0]
                if not (len(ident) == 3 and ident.upper().startswith("7F") and ident[2] in "0123"):
                    frames.append(parts[2].upper())
    return frames


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[3].strip(), file=sys.stderr)
        return 2
    directory = sys.argv[1]
    mcap_path = os.path.join(directory, "session.mcap")
    bus_path = os.path.join(directory, "mcap_bus.log")
    try:
        import verify  # the same reader and schema checks as the tests' files
    except ImportError as error:
        return verdict(False, f"cannot load Foxglove's reader ({error}): pip install mcap jsonschema")
    if not (os.path.exists(mcap_path) and os.path.exists(bus_path)):
        return verdict(False, f"missing {mcap_path} or {bus_path}")

    failures, _ = verify.check_file(mcap_path)
    channels, _, messages, _, _ = verify.read_all(mcap_path, killed=False)
    topic = {channel.id: channel.topic for channel in channels.values()}
    by_topic = {}
    for message in messages:
        by_topic.setdefault(topic[message.channel_id], []).append(json.loads(message.data))

    def id_data(raw):
        ident = raw["id"][2:].upper()
        return f"{ident}#{raw['data'].upper()}"

    recorded = [id_data(raw) for raw in by_topic.get("/tracer/raw", [])]
    bus = bus_frames(bus_path)
    run_at = next((i for i in range(len(bus) - len(recorded) + 1) if bus[i:i + len(recorded)] == recorded), None)
    if len(recorded) < 100 or run_at is None:
        failures.append(f"the MCAP's {len(recorded)} raw frames are not a contiguous run of candump's {len(bus)}")

    events = by_topic.get("/tracer/events", [])
    battery = [e["message"] for e in events if "battery" in e["message"].lower()]
    if not battery:
        failures.append(f"no battery event on /tracer/events ({len(events)} events: "
                        f"{[e['message'] for e in events][:5]})")
    commands = [m["linear_velocity"] for m in by_topic.get("/tracer/motion_command", [])]
    if 0.2 not in commands or not commands or commands[-1] != 0:
        failures.append(f"motion commands do not reach +0.200 m/s and end at zero: {sorted(set(commands))}")
    poses = [p["pose"]["position"]["x"] for p in by_topic.get("/tracer/pose", [])]
    if not poses or poses[-1] - poses[0] < 0.2:
        failures.append(f"the pose did not move forward: {len(poses)} poses, x from "
                        f"{poses[0] if poses else None} to {poses[-1] if poses else None}")

    if failures:
        return verdict(False, failures[0], failures[1:] + [f"files: {mcap_path}, {bus_path}"])
    return verdict(True, f"{len(recorded)} frames = candump lines {run_at + 1}-{run_at + len(recorded)} of "
                         f"{len(bus)}, in order; events: {battery[0]!r}; commands up to +0.200 m/s then 0; "
                         f"pose x {poses[0]:.2f} -> {poses[-1]:.2f} m; {len(messages)} messages valid")


if __name__ == "__main__":
    sys.exit(main())
