#!/bin/sh
# The power-cut scenario (tests/vm/run.sh --suite powercut), run by busybox sh inside the test VM. The VM has a
# virtio disk /dev/vda, an ext4 file system made on the host (mkfs.ext4). The recorder records the simulator on
# vcan0 into /mnt/rec (15 s segments) while candump -L vcan0 streams every frame to the host through ttyS2 (the
# witness, outside the VM). PC_OPEN_S (13) seconds into the third segment the scenario prints "POWERCUT NOW" and waits: the host then ends QEMU with
# the monitor's `quit`, without a shutdown, a sync or an unmount (a power cut: what the guest's kernel held in
# memory is lost). run.sh judges on the host what the disk holds (check powercut_fsynced): the VM never finishes.
#
# CHECKS (environment): empty or containing powercut_fsynced.

T=tracerctl
PC_OPEN_S=${PC_OPEN_S:-13}
uptime_s() { cut -d' ' -f1 /proc/uptime; }
alive() { [ -n "$1" ] && kill -0 "$1" 2>/dev/null; }
give_up() {
    echo "CHECK powercut_fsynced: FAIL $*"
    echo "SCENARIO FAIL (1 failed: powercut_fsynced)"
    exit 1
}

echo "SCENARIO START at uptime $(uptime_s)s; tracerctl: $($T --version 2>&1 | head -n 1)"
case ",${CHECKS:-powercut_fsynced}," in *,powercut_fsynced,*) ;; *) echo "no check was selected (CHECKS=$CHECKS)"; echo "SCENARIO FAIL (0 failed:)"; exit 1 ;; esac

mkdir -p /mnt
# Only what the recorder fsyncs may survive: the journal commits every 60 s (not 5) and dirty pages are written back
# after 60 s (not 30): without its fsyncs (every SYNC_EVERY = 10 s, and when a segment closes) the open segment's
# data would still be in memory at the cut, and lost
echo 6000 >/proc/sys/vm/dirty_expire_centisecs
echo 6000 >/proc/sys/vm/dirty_writeback_centisecs
mount -t ext4 -o commit=60 /dev/vda /mnt || give_up "cannot mount /dev/vda (ext4) on /mnt: $(cat /proc/partitions | tr '\n' ' ')"
echo "VM: $(grep ' /mnt ' /proc/mounts)"
mkdir -p /mnt/rec

# the witness: every frame, to the host as it is received (a tty: candump's output is line-buffered)
stty -F /dev/ttyS2 raw -echo 115200 || give_up "cannot set up ttyS2 (the witness's port)"
candump -L vcan0 >/dev/ttyS2 2>/tmp/witness.err &
wit=$!
$T --iface vcan0 sim >/tmp/sim.out 2>/tmp/sim.err &
sim=$!
sleep 1
alive $sim || give_up "the simulator did not start: $(tail -n 3 /tmp/sim.err | tr '\n' ' ')"
# segments of 15 s: two are closed (and fsynced) before the cut, the open one is only fsynced every 10 s
$T --iface vcan0 record --dir /mnt/rec --segment 15s 2>&1 | sed 's/^/RECORDER: /' &
sleep 3
pidof tracerctl >/dev/null || give_up "no tracerctl running"
echo "VM: recording since uptime ~$(uptime_s)s; the cut comes ${PC_OPEN_S}s after the third segment appears"
# the cut comes PC_OPEN_S seconds into the third segment: longer than SYNC_EVERY, so only the recorder's periodic
# fsync (not a segment's closing) keeps the open segment's older part
diag() { echo "VM: +$(($(date +%s) - t0))s: $(grep -E '^Dirty:' /proc/meminfo | tr -s ' '); vda $(awk '{print $5 " writes"}' /sys/block/vda/stat); ring: $(ls -l /mnt/rec/ring | tail -n +2 | awk '{printf "%s %s B; ", $NF, $5}')"; }
t0=$(date +%s)
i=0
while [ "$(ls /mnt/rec/ring | grep -c '\.log\.zst$')" -lt 3 ] && [ $i -lt 120 ]; do
    sleep 1
    i=$((i + 1))
    [ $((i % 5)) = 0 ] && diag
done
[ $i -lt 120 ] || give_up "no third segment after 120 s: $(ls -l /mnt/rec/ring | tr '\n' ' ')"
diag
i=0
while [ $i -lt "$PC_OPEN_S" ]; do
    sleep 1
    i=$((i + 1))
    [ $((i % 5)) = 0 ] && diag
done
alive $wit || give_up "the witness candump stopped: $(cat /tmp/witness.err)"
echo "VM: ring before the cut: $(ls -l /mnt/rec/ring | tail -n +2 | awk '{printf "%s %s B; ", $NF, $5}')"
echo "VM: at the cut: $(grep -E '^(Dirty|Writeback):' /proc/meminfo | tr -s ' \n' ' '); vda writes $(awk '{print $5 " requests, " $7 " sectors"}' /sys/block/vda/stat); vm.dirty_expire_centisecs $(cat /proc/sys/vm/dirty_expire_centisecs)"
echo "HOST-CHECK powercut_fsynced: judged on the host after the cut"
echo "POWERCUT NOW at uptime $(uptime_s)s"
# the host ends QEMU now; nothing below should run
sleep 600
give_up "still running 600 s after POWERCUT NOW: the host never cut the power"
