#!/usr/bin/env bash
# Two builds of tracerctl decoding the same log in one run, alternating so that a change of load on the
# machine falls on both alike: summary and JSON, -j1 and all cores. Prints the median wall time of each and
# the ratio B/A. Used for the musl vs glibc table in docs/performance.md:
#   cargo build --release --locked && cargo build --release --locked --target x86_64-unknown-linux-musl
#   cargo run --release --example gen_log -- 10000000 /tmp/bench10m.log
#   bash benches/compare_builds.sh target/release/tracerctl \
#       target/x86_64-unknown-linux-musl/release/tracerctl /tmp/bench10m.log [ROUNDS]
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 BIN_A BIN_B LOG [ROUNDS]" >&2; exit 2; }
a=$1 b=$2 log=$3 rounds=${4:-5}
lines=$(wc -l <"$log")
cores=$(nproc)
modes=("--summary -j1" "--summary -j$cores" "--format json -j1" "--format json -j$cores")

seconds() { # wall seconds of one decode, output discarded
    local start end
    start=$(date +%s.%N)
    # shellcheck disable=SC2086 # the mode is a list of options
    "$1" decode $2 "$log" >/dev/null
    end=$(date +%s.%N)
    echo "$end - $start" | bc -l
}
median() { sort -g | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }

printf '%s lines; A = %s; B = %s; %s rounds, alternating\n' "$lines" "$a" "$b" "$rounds"
printf '| mode | A s | A M lines/s | B s | B M lines/s | B/A time |\n|---|---|---|---|---|---|\n'
for mode in "${modes[@]}"; do
    ta=() tb=()
    for _ in $(seq "$rounds"); do
        ta+=("$(seconds "$a" "$mode")")
        tb+=("$(seconds "$b" "$mode")")
    done
    ma=$(printf '%s\n' "${ta[@]}" | median)
    mb=$(printf '%s\n' "${tb[@]}" | median)
    awk -v m="$mode" -v a="$ma" -v b="$mb" -v n="$lines" \
        'BEGIN {printf "| `%s` | %.3f | %.1f | %.3f | %.1f | %.2f |\n", m, a, n/a/1e6, b, n/b/1e6, b/a}'
done
