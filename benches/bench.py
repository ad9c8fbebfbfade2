#!/usr/bin/env python3
"""Reproduces the decode numbers in docs/performance.md.

    python3 benches/bench.py [LINES]        (default 1,000,000; a log 10x larger checks flat memory)

Builds the release binary and the log generator, generates TRACER candump logs (cached in bench-data/),
then times `tracerctl decode` (--summary, json, text, csv) against the tools people use today on the same
log: cantools (`cantools decode` with benches/tracer-bench.dbc), python-can's CanutilsLogReader, and
can-utils' log2asc (a C parser that converts without decoding). Wall time is the best of three runs; peak
memory is the maximum resident set size reported by /usr/bin/time.
Needs: cargo, /usr/bin/time; optional: pip install cantools python-can; apt-get install can-utils.
"""

import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "bench-data")
BIN = os.path.join(ROOT, "target", "release", "tracerctl")
GEN = os.path.join(ROOT, "target", "release", "examples", "gen_log")


def run_once(command, stdin_path=None):
    """Wall seconds and peak RSS (KiB) of one run, output discarded."""
    stdin = open(stdin_path, "rb") if stdin_path else subprocess.DEVNULL
    start = time.perf_counter()
    done = subprocess.run(["/usr/bin/time", "-f", "%M"] + command, stdin=stdin,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=True)
    elapsed = time.perf_counter() - start
    rss = int(done.stderr.decode().strip().splitlines()[-1])
    return elapsed, rss


def best_of(command, runs=3, stdin_path=None):
    results = [run_once(command, stdin_path) for _ in range(runs)]
    return min(r[0] for r in results), max(r[1] for r in results)


def log_with(lines):
    path = os.path.join(DATA, f"tracer-{lines}.log")
    if not os.path.exists(path):
        subprocess.run([GEN, str(lines), path], check=True)
    return path


def row(tool, mode, lines, seconds, rss_kib):
    rate = lines / seconds
    return f"| {tool} | {mode} | {lines:,} | {seconds:.3f} | {rate / 1e6:.2f} M | {rss_kib / 1024:.1f} MiB |"


def main():
    lines = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    os.makedirs(DATA, exist_ok=True)
    subprocess.run(["cargo", "build", "--release", "--locked", "--bin", "tracerctl", "--example", "gen_log"],
                   cwd=ROOT, check=True)
    small, big = log_with(lines), log_with(lines * 10)
    out = ["| tool | mode | lines | seconds | lines/s | peak memory |", "|---|---|---|---|---|---|"]
    modes = [("--summary", ["--summary"]), ("json", ["-f", "json"]), ("text", ["-f", "text"]), ("csv", ["-f", "csv"])]
    for path, count in [(small, lines), (big, lines * 10)]:
        for label, args in modes:
            seconds, rss = best_of([BIN, "decode", "--no-progress", *args, path])
            out.append(row("tracerctl", label, count, seconds, rss))
            print(out[-1], flush=True)

    # The same log through other tools, on a slice small enough for the slow ones.
    slice_lines = min(lines, 200_000)
    slice_path = os.path.join(DATA, f"tracer-slice-{slice_lines}.log")
    with open(small, "rb") as src, open(slice_path, "wb") as dst:
        for _ in range(slice_lines):
            dst.write(src.readline())
    seconds, rss = best_of([BIN, "decode", "--no-progress", "-f", "text", slice_path])
    out.append(row("tracerctl", "text", slice_lines, seconds, rss))
    dbc = os.path.join(ROOT, "docs", "tracer.dbc")
    try:
        import cantools  # noqa: F401
        seconds, rss = best_of([sys.executable, "-m", "cantools", "decode", "--single-line", dbc], 1, slice_path)
        out.append(row(f"cantools {cantools.__version__}", "decode --single-line", slice_lines, seconds, rss))
    except ImportError:
        out.append("| cantools | not installed | | | | |")
    try:
        import can
        script = "import can,sys\nn=sum(1 for _ in can.CanutilsLogReader(sys.argv[1]))\nprint(n)"
        seconds, rss = best_of([sys.executable, "-c", script, slice_path], 1)
        out.append(row(f"python-can {can.__version__}", "CanutilsLogReader (parse only)", slice_lines, seconds, rss))
    except ImportError:
        out.append("| python-can | not installed | | | | |")
    if shutil.which("log2asc"):
        seconds, rss = best_of(["log2asc", "-I", small, "-O", "/dev/null", "can0"])
        out.append(row("can-utils log2asc", "log -> ASC (parse + print, no decode)", lines, seconds, rss))
    print()
    print("\n".join(out))
    with open(os.path.join(DATA, "results.md"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
