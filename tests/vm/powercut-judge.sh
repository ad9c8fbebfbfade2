#!/usr/bin/env bash
# The host's verdict of the power-cut suite (run.sh --suite powercut): check powercut_fsynced.
#   powercut-judge.sh IMAGE WITNESS OUTDIR TRACERCTL
# IMAGE: the VM's ext4 disk as QEMU left it when the monitor's `quit` ended the VM mid-recording (not touched:
# a copy is repaired); WITNESS: what candump -L vcan0 in the VM streamed out through ttyS2 until the cut;
# OUTDIR: where the files go; TRACERCTL: the binary the VM ran (it runs here too: same architecture).
# After e2fsck has replayed the journal (what the next mount would do), the recorder's directory is copied out
# with debugfs and judged: every segment reads with zstd and with `tracerctl decode` (0 rejected lines), the ring
# is a contiguous run of what the witness saw (nothing lost inside it, nothing altered), and it reaches to at most
# SYNC_EVERY + BATCH_EVERY (10 s + 0.5 s, src/commands/record/writer.rs and recording.rs) before the cut (the
# witness's last frame). Prints one line "CHECK powercut_fsynced: PASS|FAIL ..." and evidence lines "  | ...".
set -u
image=$1 witness=$2 out=$3 bin=$4
limit_us=10500000
rm -rf "$out"
mkdir -p "$out"
ev=$out/evidence
: >"$ev"
evl() { printf '  | %s\n' "$*" >>"$ev"; }
verdict() {
    echo "CHECK powercut_fsynced: $*"
    case $1 in FAIL) cat "$ev" ;; esac
    exit 0
}

cp --sparse=always "$image" "$out/disk.img"
e2fsck -fy "$out/disk.img" >"$out/e2fsck.log" 2>&1
fsck_rc=$?
evl "e2fsck -fy (exit $fsck_rc): $(grep -iE 'journal|recover|clean|fix|files' "$out/e2fsck.log" | head -n 4 | tr '\n' ' ')"
# exit 0: clean; 1: errors corrected (the journal's replay alone is reported so by some versions); more: trouble
[ $fsck_rc -le 1 ] || verdict FAIL "e2fsck -fy could not repair the file system after the cut (exit $fsck_rc)"
debugfs -R "rdump /rec $out" "$out/disk.img" >"$out/debugfs.log" 2>&1
[ -d "$out/rec/ring" ] || verdict FAIL "no /rec/ring on the disk after the cut: $(head -c 300 "$out/debugfs.log")"

tr -d '\r' <"$witness" | grep -E '^\([0-9]{10}\.[0-9]{6}\) vcan0 [0-9A-F]{3,8}#' >"$out/witness.log"
nwit=$(grep -c . "$out/witness.log")
[ "$nwit" -gt 1000 ] || verdict FAIL "the witness holds $nwit frames: the run cannot be judged"

# every segment: zstd, and tracerctl decode
: >"$out/ring.log"
nseg=0
segs=""
bad=""
for s in $(ls "$out/rec/ring/"*.log.zst 2>/dev/null); do
    nseg=$((nseg + 1))
    name=${s##*/}
    bytes=$(stat -c %s "$s")
    zstd -dcq "$s" >"$out/$name.txt" 2>"$out/$name.zstd-err"
    zrc=$?
    # whole lines only (a frame cut by the power cut may leave the start of a line)
    grep -E '^\([0-9]{10}\.[0-9]{6}\) vcan0 [0-9A-F]{3,8}#(R[0-8]?|([0-9A-F]{2}){0,8})$' "$out/$name.txt" >>"$out/ring.log"
    nl=$(grep -c . "$out/$name.txt")
    "$bin" decode --summary -f json "$s" >"$out/$name.decode.json" 2>"$out/$name.decode.err"
    drc=$?
    rej=$(sed -n 's/.*"rejected_lines": *\([0-9][0-9]*\).*/\1/p' "$out/$name.decode.json" | head -n 1)
    fr=$(sed -n 's/^  "frames": *\([0-9][0-9]*\).*/\1/p' "$out/$name.decode.json" | head -n 1) # the top level's
    segs="$segs $name: $bytes B, $nl lines (zstd exit $zrc), decode exit $drc, ${fr:-?} frames, ${rej:-?} rejected;"
    evl "$name: $bytes bytes; zstd -d exit $zrc ($nl lines) $(head -c 160 "$out/$name.zstd-err" | tr '\n' ' '); tracerctl decode --summary exit $drc: ${fr:-?} frames, ${rej:-?} rejected lines $(tail -n 2 "$out/$name.decode.err" | tr '\n' ' ' | head -c 240)"
    if [ $zrc != 0 ] || [ $drc != 0 ] || [ "${rej:-x}" != 0 ] || [ "${fr:-x}" != "$nl" ]; then bad="$bad $name"; fi
done
nring=$(grep -c . "$out/ring.log")
[ "$nseg" -gt 0 ] && [ "$nring" -gt 0 ] || verdict FAIL "the ring on the disk holds no frame ($nseg segments)"

# the ring, a contiguous run of the witness (whole lines: the same kernel receive stamps)
first=$(head -n 1 "$out/ring.log")
found=""
for pos in $(grep -nxF "$first" "$out/witness.log" | cut -d: -f1); do
    tail -n +"$pos" "$out/witness.log" | head -n "$nring" | cmp -s - "$out/ring.log" && { found=$pos; break; }
done
us() { sed -n 's/^(\([0-9]*\)\.\([0-9]*\)).*/\1\2/p' | sed 's/^0*//'; }
cut_us=$(tail -n 1 "$out/witness.log" | us)
last_us=$(tail -n 1 "$out/ring.log" | us)
first_us=$(head -n 1 "$out/ring.log" | us)
lost_us=$((cut_us - last_us))
lost_s=$(awk -v u="$lost_us" 'BEGIN {printf "%.2f", u / 1e6}')
span_s=$(awk -v u="$((last_us - first_us))" 'BEGIN {printf "%.1f", u / 1e6}')
after=$(awk -v n="$nwit" -v f="${found:-0}" -v r="$nring" 'BEGIN {print n - (f + r - 1)}')
evl "witness: $nwit frames, the last: $(tail -n 1 "$out/witness.log")"
evl "ring: $nring frames from $(head -n 1 "$out/ring.log" | cut -c1-19) to $(tail -n 1 "$out/ring.log")"
evl "status.json after the cut: $(tr -s ' \n' ' ' <"$out/rec/status.json" 2>/dev/null | head -c 300)"
if [ -n "$bad" ]; then
    verdict FAIL "segments that do not read whole (zstd -d, tracerctl decode with 0 rejected lines, as many frames as lines):$bad"
elif [ -z "$found" ]; then
    verdict FAIL "the ring's $nring frames are not a contiguous run of the $nwit frames the witness saw (a hole, or altered lines)"
elif [ "$lost_us" -gt "$limit_us" ]; then
    verdict FAIL "the ring ends $lost_s s before the cut (the witness's last frame): more than SYNC_EVERY 10 s + 0.5 s of batching"
else
    verdict PASS "after e2fsck (exit $fsck_rc): $nseg segments read whole with zstd and tracerctl decode (0 rejected lines):$segs the ring's $nring frames ($span_s s) are frames $found-$((found + nring - 1)) of the $nwit the witness saw, in order; it ends $lost_s s before the cut ($after frames lost; limit 10.5 s)"
fi
