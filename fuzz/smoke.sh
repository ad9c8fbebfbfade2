#!/usr/bin/env bash
# Fuzz smoke run (called by .ci/run): installs cargo-afl if needed, builds the afl targets, runs each for a
# bounded number of executions from the committed seeds, and fails if any run finds a crash or a hang (the
# input is printed as hex, with the panic it causes). docs/testing.md ("Fuzzing") has the long-run command.
#
#   FUZZ_SMOKE_EXECS    executions per target (default 20000)
#   FUZZ_SMOKE_SECONDS  time cap per target, whichever comes first (default 20)
#   FUZZ_SMOKE_TARGETS  space-separated subset of the targets (default: all of fuzz/src/bin)
set -euo pipefail
cd "$(dirname "$0")"

execs=${FUZZ_SMOKE_EXECS:-20000}
seconds=${FUZZ_SMOKE_SECONDS:-20}
targets=${FUZZ_SMOKE_TARGETS:-$(cd src/bin && ls -- *.rs | sed 's/\.rs$//' | tr '\n' ' ')}

if ! command -v cargo-afl >/dev/null; then
    # Builds AFL++ from the source bundled in the crate (needs a C compiler and make; no download).
    cargo install cargo-afl --locked
fi
# cargo-afl builds AFL++ when it is installed; a new toolchain needs it built again.
if ! config=$(cargo afl config --build 2>&1) && ! grep -q "already built" <<<"$config"; then
    printf '%s\n' "$config" >&2
    exit 1
fi

echo "cargo-afl ready: $SECONDS s"
# --target (the host's own triple): cargo-afl's RUSTFLAGS then reach only the code afl runs, not the build
# scripts and proc macros, which are built once, plainly. codegen-units=16 (ours come last, so they win over
# cargo-afl's 1) splits the tracerctl crate across both cores. Measured here: 298 s -> 160 s alone, 195 s in
# CI; the same executions per second and paths found.
host=$(rustc -vV | sed -n 's/^host: //p')
# The smoke's executions are bounded, not its time: opt-level 1 (AFL_OPT_LEVEL, cargo-afl's own setting;
# its default is 3) built in 161 s, not 191 s, and the runs took 26 s, not 24.
export AFL_OPT_LEVEL=${AFL_OPT_LEVEL:-1}
if ! RUSTFLAGS="${RUSTFLAGS:-} -C codegen-units=16" cargo afl build --release --locked --target "$host"; then
    # fuzz/ has its own lock file: a dependency added to the main crate must be added to it too.
    echo "If cargo says the lock file needs to be updated: cargo update --manifest-path fuzz/Cargo.toml" \
        "--workspace, and commit fuzz/Cargo.lock" >&2
    exit 1
fi
echo "targets built: $SECONDS s"

# A container has no core dump handler to wait for, no CPU frequency governor to check, and no terminal.
export AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_SKIP_CPUFREQ=1 AFL_NO_UI=1 AFL_NO_AFFINITY=1 AFL_FAST_CAL=1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failed=()
start=$SECONDS
for target in $targets; do
    binary=target/$host/release/$target
    # -t: 1 s per input is far above any target's need; only a real hang reaches it.
    cargo afl fuzz -i "seeds/$target" -o "$out/$target" -E "$execs" -V "$seconds" -t 1000 -- "$binary" \
        >"$out/$target.log" 2>&1 || { tail -n 40 "$out/$target.log"; failed+=("$target (afl-fuzz failed)"); continue; }
    stats=$out/$target/default/fuzzer_stats
    stat() { sed -n "s/^$1 *: //p" "$stats"; }
    printf '%-16s %8s execs  %5s paths  %s crashes  %s hangs\n' \
        "$target" "$(stat execs_done)" "$(stat corpus_count)" "$(stat saved_crashes)" "$(stat saved_hangs)"
    for kind in crashes hangs; do
        inputs=("$out/$target/default/$kind"/id:*)
        [[ -e ${inputs[0]} ]] || continue
        failed+=("$target: ${#inputs[@]} $kind")
        # The first few are enough to reproduce; the rest are usually the same defect.
        for input in "${inputs[@]:0:3}"; do
            echo "--- $target: $kind input $(basename "$input"), as hex:"
            od -An -tx1 -v "$input"
            echo "--- what it does (fuzz/$binary < input):"
            timeout 5 "$binary" <"$input" 2>&1 | head -n 12 || true
        done
    done
done
echo "fuzz runs: $((SECONDS - start)) s; the whole smoke: $SECONDS s"
if ((${#failed[@]})); then
    printf 'fuzz smoke failed: %s\n' "${failed[@]}" >&2
    echo "Make each input a regression test: fuzz/regressions/<target>/<name> (docs/testing.md)." >&2
    exit 1
fi
echo "fuzz smoke: no crash, no hang"
