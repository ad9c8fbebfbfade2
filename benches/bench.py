#!/usr/bin/env python3
"""Reproduces the decode table in docs/performance.md ("Decode against the tools (issue 14)").

    python3 benches/bench.py [--sizes 1000000,100000000] [--runs 5] [--big-runs 3]
                             [--slow-max-lines 1000000] [--bin PATH] [--no-build] [--out FILE]

Builds the release binary and the log generator (unless --no-build or --bin), generates TRACER candump logs
of each size into bench-data/ (never committed; a 100 M-line log is about 4.6 GB), then times, in the same
run and on the same files: `wc -l`, cantools (`cantools decode --single-line` with docs/tracer.dbc),
python-can's CanutilsLogReader (parse only), can-utils' log2asc (a C converter, no decoding), and
`tracerctl decode` with one thread (`-j1`) and all cores (`-jN`) for --summary, json, text and csv.
`-jN` is measured only when `tracerctl decode --help` lists `--threads` (n/a otherwise).

Wall time is the best of --runs runs (--big-runs for logs above 10 M lines), output to /dev/null; the runs
are interleaved (one run of every tool, then the next round), so a slow spell of a shared machine slows
every tool of a round alike instead of one tool's runs. cantools, python-can and log2asc run once after the
rounds (they take minutes and are far from the ratios that matter). Peak memory is the maximum resident set
size from /usr/bin/time. cantools and python-can are skipped on logs above --slow-max-lines lines (cantools
would take hours on 100 M lines). Prints one Markdown table: lines/s, time relative to `wc -l` in the same run,
peak memory per size, and whether memory stays flat (largest / smallest log within 1.2x).

A second table times `tracerctl decode -j1` and `-jN` on the same frames written as Vector ASC and as PEAK
trc 2.1 (converted here from the smallest log; --no-other-formats skips it), for --summary and json.
Needs: cargo, /usr/bin/time; optional: pip install cantools python-can; apt-get install can-utils.
"""

import argparse
import os
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "bench-data")
GEN = os.path.join(ROOT, "target", "release", "examples", "gen_log")
DBC = os.path.join(ROOT, "docs", "tracer.dbc")
BIG = 10_000_000
MODES = [("--summary", ["--summary"]), ("json", ["-f", "json"]), ("text", ["-f", "text"]), ("csv", ["-f", "csv"])]
PYTHON_CAN_READER = "import can,sys\nn=sum(1 for _ in can.CanutilsLogReader(sys.argv[1]))\nprint(n)"


def run_once(command, stdin_path=None):
    """Wall seconds and peak RSS (KiB) of one run, output discarded."""
    with open(stdin_path or os.devnull, "rb") as stdin:
        start = time.perf_counter()
        done = subprocess.run(["/usr/bin/time", "-f", "%M"] + command, stdin=stdin,
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=True)
        elapsed = time.perf_counter() - start
    return elapsed, int(done.stderr.decode().strip().splitlines()[-1])


def log_with(lines):
    path = os.path.join(DATA, f"tracer-{lines}.log")
    if not os.path.exists(path):
        print(f"generating {path}", file=sys.stderr, flush=True)
        subprocess.run([GEN, str(lines), path + ".part"], check=True)
        os.rename(path + ".part", path)
    return path


def converted(lines, kind):
    """The candump log of `lines` lines written as Vector ASC or PEAK trc 2.1: the same frames and stamps."""
    source = log_with(lines)
    path = os.path.join(DATA, f"tracer-{lines}.{kind}")
    if os.path.exists(path):
        return path
    print(f"converting {source} to {path}", file=sys.stderr, flush=True)
    first = None
    with open(source) as lines_in, open(path + ".part", "w") as out:
        if kind == "asc":
            out.write("date Tue Nov 24 10:00:00.000 2026\nbase hex  timestamps absolute\ninternal events logged\n"
                      "Begin Triggerblock Tue Nov 24 10:00:00.000 2026\n   0.000000 Start of measurement\n")
        else:
            out.write(";$FILEVERSION=2.1\n;$STARTTIME=46350.4166666667\n;$COLUMNS=N,O,T,B,I,d,R,L,D\n;\n")
        for number, line in enumerate(lines_in, 1):
            stamp, _iface, frame = line.split()[:3]
            ident, data = frame.split("#")
            micros = int(stamp[1:-1].replace(".", ""))
            first = micros if first is None else first
            offset = micros - first
            data_bytes = " ".join(data[i:i + 2] for i in range(0, len(data), 2))
            length = len(data) // 2
            if kind == "asc":
                name = f"{int(ident, 16):X}" + ("x" if len(ident) == 8 else "")
                out.write(f"{offset // 1_000_000:4}.{offset % 1_000_000:06} 1  {name:<15} Rx   d {length} {data_bytes}\n")
            else:
                ident = ident.zfill(8 if len(ident) == 8 else 4)
                out.write(f"{number:7} {offset // 1000:13}.{offset % 1000:03} DT 1 {ident:>9} Rx -  {length}    "
                          f"{data_bytes}\n")
        if kind == "asc":
            out.write("End TriggerBlock\n")
    os.rename(path + ".part", path)
    return path


def other_formats(binary, cores, lines, runs):
    """Markdown rows: tracerctl -j1 and -jN on the log written as ASC and as trc, interleaved, best of `runs`."""
    out = ["| input | mode | -j1: lines/s | -j1: peak memory | "
           f"-j{cores}: lines/s | -j{cores}: peak memory | -j{cores} / -j1 |", "|---|---|---|---|---|---|---|"]
    for kind, label in [("asc", "Vector ASC"), ("trc", "PEAK trc 2.1")]:
        path = converted(lines, kind)
        for mode, args in MODES[:2]:
            best = {}
            for _ in range(max(1, runs)):
                for jobs in (1, cores):
                    seconds, rss = run_once([binary, "decode", "--no-progress", f"-j{jobs}", *args, path])
                    old = best.get(jobs, (seconds, rss))
                    best[jobs] = (min(old[0], seconds), max(old[1], rss))
            (one, one_rss), (many, many_rss) = best[1], best[cores]
            out.append(f"| {label} ({os.path.getsize(path) // 1_000_000} MB) | {mode} | {lines / one / 1e6:.2f} M | "
                       f"{one_rss / 1024:.1f} MiB | {lines / many / 1e6:.2f} M | {many_rss / 1024:.1f} MiB | "
                       f"{one / many:.2f}x |")
            print(out[-1], file=sys.stderr, flush=True)
    return out


def threads_supported(binary):
    help_text = subprocess.run([binary, "decode", "--help"], capture_output=True, text=True).stdout
    return "--threads" in help_text


def python_has(module):
    return subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True).returncode == 0


def python_version(module):
    done = subprocess.run([sys.executable, "-c", f"import {module}; print({module}.__version__)"],
                          capture_output=True, text=True)
    return done.stdout.strip()


# How a row is run: in every round, once after the rounds, or once and only on logs up to --slow-max-lines.
ROUNDS, ONCE, ONCE_SMALL = "rounds", "once", "once on small logs"


def contenders(binary, cores, jobs):
    """(tool, mode, command(path) or a reason it is not measured, how it runs) for every row of the table."""
    rows = [("wc -l", "count lines", lambda p: ["wc", "-l", p], ROUNDS)]
    for label, args in MODES:
        one = ["-j1"] if jobs else []
        rows.append(("tracerctl -j1", label, lambda p, a=args, o=one: [binary, "decode", "--no-progress", *o, *a, p],
                     ROUNDS))
        if jobs:
            command = lambda p, a=args: [binary, "decode", "--no-progress", f"-j{cores}", *a, p]  # noqa: E731
        else:
            command = "n/a (no --threads in this build)"
        rows.append((f"tracerctl -j{cores}", label, command, ROUNDS))
    if shutil.which("log2asc"):
        rows.append(("can-utils log2asc", "log -> ASC, no decoding",
                     lambda p: ["log2asc", "-I", p, "-O", "/dev/null", "can0"], ONCE))
    else:
        rows.append(("can-utils log2asc", "log -> ASC", "not installed", ONCE))
    if python_has("cantools"):
        rows.append((f"cantools {python_version('cantools')}", "decode --single-line",
                     lambda p: [sys.executable, "-m", "cantools", "decode", "--single-line", DBC], ONCE_SMALL))
    else:
        rows.append(("cantools", "decode", "not installed", ONCE_SMALL))
    if python_has("can"):
        rows.append((f"python-can {python_version('can')}", "CanutilsLogReader, parse only",
                     lambda p: [sys.executable, "-c", PYTHON_CAN_READER, p], ONCE_SMALL))
    else:
        rows.append(("python-can", "CanutilsLogReader", "not installed", ONCE_SMALL))
    return rows


def measure(rows, sizes, options):
    """{(row index, size): (seconds, rss KiB) or a reason}."""
    results = {}
    for size in sizes:
        path = log_with(size)
        runs = options.runs if size <= BIG else options.big_runs
        for index, (_, _, command, how) in enumerate(rows):
            if isinstance(command, str):
                results[index, size] = command
            elif how == ONCE_SMALL and size > options.slow_max_lines:
                results[index, size] = "skipped (--slow-max-lines)"
        # Rounds: every tool once per round, the best time and the largest memory kept.
        in_rounds = [i for i, row in enumerate(rows) if row[3] == ROUNDS and (i, size) not in results]
        for round_number in range(max(1, runs)):
            for index in in_rounds:
                seconds, rss = run_once(rows[index][2](path))
                best = results.get((index, size), (seconds, rss))
                results[index, size] = (min(best[0], seconds), max(best[1], rss))
            print(f"{size:>12,} round {round_number + 1} of {runs} done", file=sys.stderr, flush=True)
        for index, (tool, mode, command, how) in enumerate(rows):
            if (index, size) not in results:
                stdin_path = path if tool.startswith("cantools") else None
                results[index, size] = run_once(command(path), stdin_path)
            print(f"{size:>12,} {tool} {mode}: {results[index, size]}", file=sys.stderr, flush=True)
    return results


def table(rows, sizes, results):
    def short(n):
        return f"{n // 1_000_000} M" if n % 1_000_000 == 0 else f"{n:,}"

    head = ["tool", "mode"]
    for size in sizes:
        head += [f"{short(size)}: lines/s", f"{short(size)}: x `wc -l`", f"{short(size)}: peak memory"]
    if len(sizes) > 1:
        head.append(f"memory {short(sizes[-1])} / {short(sizes[0])}")
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for index, (tool, mode, _, _) in enumerate(rows):
        cells = [tool, mode]
        for size in sizes:
            result, wc = results[index, size], results[0, size]
            if isinstance(result, str):
                cells += [result, "", ""]
                continue
            seconds, rss = result
            cells += [f"{size / seconds / 1e6:.2f} M", f"{seconds / wc[0]:.1f}x", f"{rss / 1024:.1f} MiB"]
        measured = [results[index, s] for s in sizes if not isinstance(results[index, s], str)]
        if len(sizes) > 1:
            if len(measured) == len(sizes):
                ratio = measured[-1][1] / measured[0][1]
                cells.append(f"{ratio:.2f}x ({'flat' if ratio <= 1.2 else 'grows'})")
            else:
                cells.append("")
        out.append("| " + " | ".join(cells) + " |")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", default="1000000,100000000",
                        help="comma-separated log sizes in lines (default 1000000,100000000)")
    parser.add_argument("--runs", type=int, default=5, help="runs per measurement, best kept (default 5)")
    parser.add_argument("--big-runs", type=int, default=3, help=f"runs on logs above {BIG:,} lines (default 3)")
    parser.add_argument("--slow-max-lines", type=int, default=1_000_000,
                        help="run cantools and python-can only on logs up to this many lines (default 1000000)")
    parser.add_argument("--bin", help="the tracerctl binary to time (default: build target/release/tracerctl)")
    parser.add_argument("--no-build", action="store_true", help="do not run cargo build first")
    parser.add_argument("--out", default=os.path.join(DATA, "results.md"), help="where the table is written")
    parser.add_argument("--no-other-formats", action="store_true",
                        help="skip the second table (the smallest log as Vector ASC and PEAK trc)")
    options = parser.parse_args()
    sizes = sorted(int(s.replace("_", "")) for s in options.sizes.split(","))
    binary = options.bin or os.path.join(ROOT, "target", "release", "tracerctl")
    os.makedirs(DATA, exist_ok=True)
    if not options.no_build:
        targets = ["--example", "gen_log"] + ([] if options.bin else ["--bin", "tracerctl"])
        subprocess.run(["cargo", "build", "--release", "--locked", *targets], cwd=ROOT, check=True)

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    rows = contenders(binary, cores, threads_supported(binary))
    results = measure(rows, sizes, options)
    out = table(rows, sizes, results)
    out.append("")
    out.append(f"How to reproduce: `python3 benches/bench.py --sizes {','.join(str(s) for s in sizes)} "
               f"--runs {options.runs} --big-runs {options.big_runs}` ({cores} cores; best of {options.runs} runs, "
               f"{options.big_runs} on logs above {BIG // 1_000_000} M lines, interleaved; log2asc, cantools and "
               "python-can once; output to /dev/null).")
    if not options.no_other_formats and threads_supported(binary):
        out.append("")
        out.append(f"The {sizes[0]:,}-line log as Vector ASC and PEAK trc 2.1 (the same frames and stamps):")
        out.append("")
        out += other_formats(binary, cores, sizes[0], options.runs)
    print("\n".join(out))
    with open(options.out, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
