#!/usr/bin/env bash
# The black box's cost: `tracerctl record` fed a generated TRACER log replayed at real time, at the robot's
# normal ~500 frames/s and at a saturated 500 kbit/s bus (~4,500 frames/s), for DURATION seconds each; CPU
# (user + system) over the run, peak memory, frames recorded and lost, ring bytes. The figures include reading
# and parsing the replayed log, which a live link does not pay.
#
#   bash benches/record_bench.sh [BIN] [DURATION]     (default: target/release/tracerctl, 60)
set -euo pipefail
bin=${1:-target/release/tracerctl}
seconds=${2:-60}
[ -x "$bin" ] || { echo "record_bench.sh: no binary at $bin (cargo build --release)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# gen_log writes 370 frames per second of log time: 600,000 lines are 27 minutes of it.
cargo run --release --locked -q --example gen_log -- 600000 "$work/session.log"
for rate in 500 4500; do
    speed=$(python3 -c "print(round($rate / 370.0, 3))")
    dir=$work/rec-$rate
    /usr/bin/time -f "%U %S %M" -o "$work/time" timeout -s TERM "$seconds" \
        "$bin" --replay "$work/session.log" --speed "$speed" record --dir "$dir" 2>"$work/stderr" || true
    read -r user system peak < <(tail -1 "$work/time")
    python3 - "$dir/status.json" "$rate" "$seconds" "$user" "$system" "$peak" "$(du -sb "$dir/ring" | cut -f1)" <<'PY'
import json, sys
path, rate, seconds, user, system, peak, ring = sys.argv[1:]
status = json.load(open(path))
seconds = float(seconds)
cpu = (float(user) + float(system)) / seconds * 100
print(f"{rate} frames/s: {status['frames_recorded']} frames in {seconds:.0f} s "
      f"({status['frames_recorded'] / seconds:.0f}/s), lost {status['frames_lost']}; "
      f"CPU {cpu:.2f} % of a core (user {user} s, system {system} s); peak RSS {int(peak) / 1024:.1f} MiB; "
      f"ring {int(ring) / 1024:.0f} KiB ({int(ring) / seconds / 1024:.1f} KiB/s)")
PY
done
