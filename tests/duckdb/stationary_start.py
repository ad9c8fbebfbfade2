#!/usr/bin/env python3
"""DuckDB reads decode's JSON lines and CSV of a log that starts standing still with float speed columns.

    python3 tests/duckdb/stationary_start.py target/debug/tracerctl      (CI, after `cargo test`)

DuckDB's read_json_auto and read_csv_auto (like Spark's inference) type a column from its first rows (20,480 by
default). A log that starts with the robot parked has only zero speeds, currents and odometers there: written as
`0`, the columns became BIGINT and every later 0.15 m/s was lost. Written as `0.0`, they are DOUBLE.

The log: 30,000 frames in four kinds (motion state, motor 1 and 2 feedback, odometry), all zero, then the robot
drives at 0.15 m/s with 1.5 A in motor 1 and its left odometer at 0.15 m. Checked in both formats: the columns'
types are DOUBLE and the moving rows read back 0.15 / 1.5. Exits 1 with the failures. Needs: pip install duckdb.
"""

import os
import subprocess
import sys
import tempfile

import duckdb

STANDING = 30_000
MOVING = 100
FLOAT_FIELDS = ["linear_velocity", "angular_velocity", "current", "left_wheel_odometer", "right_wheel_odometer"]


def frame(index, moving):
    """One candump -l line; the kinds take turns."""
    speed, current, odometer = (150, 15, 150) if moving else (0, 0, 0)
    kind = index % 4
    if kind == 0:
        can_id, data = "221", speed.to_bytes(2, "big") + bytes(6)
    elif kind in (1, 2):
        motor_current = current if kind == 1 else 0
        can_id, data = f"25{kind}", bytes(2) + motor_current.to_bytes(2, "big") + bytes(4)
    else:
        can_id, data = "311", odometer.to_bytes(4, "big", signed=True) + bytes(4)
    stamp = 1_700_000_000 + index * 0.005
    return f"({stamp:.6f}) can0 {can_id}#{data.hex().upper()}\n"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    binary = sys.argv[1]
    failures = []
    with tempfile.TemporaryDirectory() as directory:
        log = os.path.join(directory, "parked-then-driving.log")
        with open(log, "w") as out:
            for index in range(STANDING + MOVING):
                out.write(frame(index, index >= STANDING))
        outputs = {}
        for form in ("json", "csv"):
            outputs[form] = os.path.join(directory, f"decoded.{form}")
            subprocess.run([binary, "decode", "--format", form, "-o", outputs[form], log], check=True)
        connection = duckdb.connect()

        relation = connection.sql(f"SELECT unnest(fields) FROM read_json_auto('{outputs['json']}')")
        json_types = dict(zip(relation.columns, map(str, relation.types)))
        relation = connection.sql(f"SELECT * FROM read_csv_auto('{outputs['csv']}')")
        csv_types = dict(zip(relation.columns, map(str, relation.types)))
        for form, types in (("json", json_types), ("csv", csv_types)):
            for name in FLOAT_FIELDS:
                if types.get(name) != "DOUBLE":
                    failures.append(f"{form}: column {name} is {types.get(name)}, not DOUBLE")

        json_max = connection.sql(
            f"SELECT max(fields.linear_velocity), max(fields.current), max(fields.left_wheel_odometer), "
            f"count(*) FROM read_json_auto('{outputs['json']}')").fetchall()[0]
        csv_max = connection.sql(
            f"SELECT max(linear_velocity), max(current), max(left_wheel_odometer), count(*) "
            f"FROM read_csv_auto('{outputs['csv']}')").fetchall()[0]
        expected = (0.15, 1.5, 0.15, STANDING + MOVING)
        for form, got in (("json", json_max), ("csv", csv_max)):
            if tuple(got) != expected:
                failures.append(f"{form}: max speed, current, odometer and rows read {tuple(got)}, expected {expected}")
    for failure in failures:
        print(f"DUCKDB FAIL: {failure}", file=sys.stderr)
    if failures:
        sys.exit(1)
    print(f"duckdb {duckdb.__version__}: JSON and CSV of {STANDING} standing frames then {MOVING} moving: "
          f"{', '.join(FLOAT_FIELDS)} are DOUBLE; the moving rows read {expected[:3]}")


if __name__ == "__main__":
    main()
