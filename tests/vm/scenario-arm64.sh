#!/bin/sh
# The arm64 suite's checks, run by /init inside the emulated ARM computer (tests/vm/arm64.sh builds it): the
# static aarch64 tracerctl on the kernel's real SocketCAN (vcan0, can-utils' candump as the witness), on an
# emulated 16550 UART (/dev/ttyS0) to a virtual TRACER on the host, and its dashboard on a second UART
# (/dev/ttyS1) whose keys a host script types. Prints "CHECK name: PASS|FAIL evidence" per check; the host
# judges the RS232 wire from QEMU's log of the UART and prints those checks itself.
export PATH=/bin:/usr/bin:/sbin
export TERM=xterm-256color NO_COLOR=1
failed=""
count=0

check() { # NAME PASS|FAIL EVIDENCE [FILE...]: FILEs are shown as evidence on failure
    name=$1 verdict=$2 evidence=$3
    shift 3
    count=$((count + 1))
    echo "CHECK $name: $verdict $evidence"
    if [ "$verdict" != PASS ]; then
        failed="$failed $name"
        for file in "$@"; do tail -n 15 "$file" 2>/dev/null | sed 's/^/  | /'; done
    fi
}

# The linear speeds of the 0x111 motion frames of a candump -L log, in mm/s, one a line.
speeds() { sed -n 's/.* 111#\(....\).*/\1/p' "$1" | while read -r hex; do
    value=$((0x$hex))
    [ "$value" -ge 32768 ] && value=$((value - 65536))
    echo "$value"
done; }

record() { candump -L vcan0 >"$1" 2>/dev/null & echo $! >/tmp/candump.pid; sleep 0.5; }
stop_record() { sleep 0.3; kill "$(cat /tmp/candump.pid)" 2>/dev/null; wait "$(cat /tmp/candump.pid)" 2>/dev/null; }

# ---------------------------------------------------------------- the binary and the machine
version=$(tracerctl --version 2>&1)
machine=$(uname -m)
case "$version/$machine" in
    "tracerctl "*/aarch64) check arm_binary PASS "$version on $machine, kernel $(uname -r)" ;;
    *) check arm_binary FAIL "'$version' on '$machine'" ;;
esac

# ---------------------------------------------------------------- SocketCAN (vcan0) with the simulator
tracerctl --iface vcan0 sim >/tmp/sim.out 2>&1 &
sim=$!
sleep 3

tracerctl --iface vcan0 doctor >/tmp/doctor.out 2>&1
status=$?
if [ $status = 0 ] && grep -q 'Result: the robot can be driven' /tmp/doctor.out; then
    check vcan_doctor PASS "exit 0, $(grep -c '^PASS' /tmp/doctor.out) checks passed"
else
    check vcan_doctor FAIL "exit $status" /tmp/doctor.out
fi

tracerctl --iface vcan0 monitor --format json -n 100 >/tmp/monitor.out 2>/tmp/monitor.err
status=$?
lines=$(grep -c '"msg":"system_state"' /tmp/monitor.out)
if [ $status = 0 ] && [ "$lines" -ge 5 ]; then
    check vcan_monitor PASS "exit 0, 100 frames as JSON, $lines system_state"
else
    check vcan_monitor FAIL "exit $status, $lines system_state lines" /tmp/monitor.out /tmp/monitor.err
fi

record /tmp/drive.log
tracerctl --iface vcan0 drive --linear 0.2 --for 1s >/tmp/drive.out 2>&1
status=$?
stop_record
speeds /tmp/drive.log >/tmp/drive.speeds
moving=$(grep -c '^200$' /tmp/drive.speeds)
last=$(tail -n 1 /tmp/drive.speeds)
mode_first=$(grep -n -m 1 -E ' (421#01|111#)' /tmp/drive.log | grep -c '421#01')
if [ $status = 0 ] && [ "$moving" -ge 20 ] && [ "$last" = 0 ] && [ "$mode_first" = 1 ]; then
    check vcan_drive PASS "exit 0; 421#01 first, $moving frames at 200 mm/s of $(wc -l </tmp/drive.speeds), the last 0"
else
    check vcan_drive FAIL "exit $status; $moving frames at 200 mm/s, last ${last:-none}, 421 first: $mode_first" /tmp/drive.out /tmp/drive.log
fi

record /tmp/sigint.log
tracerctl --iface vcan0 drive --linear 0.2 --for 30s >/tmp/sigint.out 2>&1 &
drive=$!
sleep 3
kill -INT $drive
wait $drive
status=$?
stop_record
speeds /tmp/sigint.log >/tmp/sigint.speeds
moving=$(grep -c '^200$' /tmp/sigint.speeds)
last=$(tail -n 1 /tmp/sigint.speeds)
if [ $status = 130 ] && [ "$moving" -ge 20 ] && [ "$last" = 0 ]; then
    check vcan_drive_sigint PASS "exit 130; $moving frames at 200 mm/s, then zero, the last frame 0"
else
    check vcan_drive_sigint FAIL "exit $status; $moving frames at 200 mm/s, last ${last:-none}" /tmp/sigint.out /tmp/sigint.log
fi

# ---------------------------------------------------------------- the dashboard on a serial terminal
# /dev/ttyS1's other end is a host script: it waits for the screen, then types a (arm), y, holds Up, presses
# Space while still holding Up, and quits with q.
record /tmp/dash.log
echo "DASHBOARD START"
# A session of its own with ttyS1 as its controlling terminal, 100x30 as a terminal window would be.
setsid sh -c 'stty rows 30 cols 100 && exec tracerctl --iface vcan0 dashboard 2>/tmp/dash.err' </dev/ttyS1 >/dev/ttyS1 2>&1 &
dash=$!
waited=0
while kill -0 $dash 2>/dev/null && [ $waited -lt 90 ]; do sleep 1; waited=$((waited + 1)); done
if kill -0 $dash 2>/dev/null; then kill -INT $dash; sleep 2; fi
wait $dash
status=$?
echo "DASHBOARD END"
stop_record
speeds /tmp/dash.log >/tmp/dash.speeds
moving=$(grep -c -v '^0$' /tmp/dash.speeds)
# The last moving frame and what follows it: Space is zero at once, not a ramp down.
last_moving=$(grep -v '^0$' /tmp/dash.speeds | tail -n 1)
zeros_after=$(awk '$1 != 0 {z = 0; next} {z++} END {print z + 0}' /tmp/dash.speeds)
if [ $status = 0 ] && [ "$moving" -ge 10 ] && [ "${last_moving:-0}" -ge 100 ] && [ "$zeros_after" -ge 25 ]; then
    check dashboard_session PASS "exit 0; $moving moving frames, the last at $last_moving mm/s, then $zeros_after zero frames to the end (Space: zero at once while Up was still held; q)"
else
    check dashboard_session FAIL "exit $status; $moving moving frames, last moving ${last_moving:-none} mm/s, $zeros_after zeros after it" /tmp/dash.err /tmp/dash.log
fi

kill $sim 2>/dev/null

# ---------------------------------------------------------------- RS232 over the emulated UART
# /dev/ttyS0's other end is a virtual TRACER on the host (x86 tracerctl sim --serial); QEMU logs what the UART
# sends, and the host judges that wire after the VM has stopped.
tracerctl --serial /dev/ttyS0 doctor >/tmp/sdoctor.out 2>&1
status=$?
if [ $status = 0 ] && grep -q 'Result: the robot can be driven' /tmp/sdoctor.out; then
    check serial_doctor PASS "exit 0 over /dev/ttyS0, $(grep -c '^PASS' /tmp/sdoctor.out) checks passed"
else
    check serial_doctor FAIL "exit $status" /tmp/sdoctor.out
fi

tracerctl --serial /dev/ttyS0 monitor -n 50 >/tmp/smonitor.out 2>/tmp/smonitor.err
status=$?
lines=$(grep -c 'system_state' /tmp/smonitor.out)
if [ $status = 0 ] && [ "$lines" -ge 5 ]; then
    check serial_monitor PASS "exit 0, 50 frames, $lines system_state"
else
    check serial_monitor FAIL "exit $status, $lines system_state" /tmp/smonitor.out /tmp/smonitor.err
fi

echo "SERIAL DRIVE START"
tracerctl --serial /dev/ttyS0 drive --linear 0.2 --for 1s >/tmp/sdrive.out 2>&1
status=$?
echo "SERIAL DRIVE END"
if [ $status = 0 ] && grep -q 'last command +0.000 m/s' /tmp/sdrive.out; then
    check serial_drive_exit PASS "exit 0, $(grep -o '[0-9]* motion frames sent' /tmp/sdrive.out) (the wire: serial_drive_wire, judged on the host)"
else
    check serial_drive_exit FAIL "exit $status" /tmp/sdrive.out
fi

echo "HOST-CHECK serial_drive_wire"
if [ -n "$failed" ]; then
    echo "SCENARIO FAIL ($(echo $failed | wc -w) of $count failed:$failed)"
else
    echo "SCENARIO PASS ($count checks)"
fi
