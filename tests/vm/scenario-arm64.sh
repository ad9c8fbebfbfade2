#!/bin/sh
# The arm64 scenario: the static aarch64 build of tracerctl on an emulated ARM computer (qemu-system-aarch64,
# machine virt, Cortex-A57, Debian's arm64 kernel), run by busybox sh inside the VM (tests/vm/run.sh --suite arm64).
# qemu-user cannot run the RS232 and terminal paths (it has no TCGETS2); a real kernel can. What is there:
#     vcan0     up; the simulator (tracerctl sim) runs on it for the vcan and dashboard checks
#     ttyS0     a PCI 16550A UART (QEMU pci-serial, the kernel's 8250_pci driver), wired on the host to the host's
#               own tracerctl sim --serial on a pseudo-terminal; the host logs every byte (tests/vm/arm64-host.py)
#     hvc0/hvc1 virtio consoles (real ttys with termios), connected to each other through the host: hvc1 is the
#               dashboard's terminal, hvc0 its other end (the keys are written there, the screen is read there)
#     "marks"   a virtio serial port: markers ("begin NAME", "sigint", "end NAME") and a timing witness, logged
#               by the host on the same clock as the UART's bytes
# Every check prints one line
#     CHECK <name>: PASS|FAIL <evidence>      (or HOST-CHECK <name>: ... for a verdict run.sh gives on the host)
# followed, on failure, by evidence lines starting with "  | ". The last line is "SCENARIO PASS" or "SCENARIO FAIL (...)".
#
# CAN timing is judged only from candump's kernel timestamps, with margins wide enough for TCG emulation.
# Frames 0x7F0-0x7F3 on vcan0 are the scenario's own: 7F0 capture start/end markers, 7F1 the moment a signal is sent
# or a key is typed (its data says which), 7F2 the moment the process had exited, 7F3 the timing witness (cangen
# every 10 ms).
# CHECKS (environment, comma-separated) selects checks by name; empty = all.
# The files of every check are kept in /tmp/scn (run.sh copies them to target/vm-arm64/artifacts-arm64/).

T=tracerctl
W=/tmp/scn
mkdir -p $W
N_PASS=0
N_FAIL=0
N_HOST=0 # checks whose verdict run.sh gives on the host (serial_drive, serial_sigint)
FAILED=""
CHECKS=${CHECKS:-}

# ------------------------------------------------------------------------------------------- framework
# (the same helpers as scenario.sh)

uptime_s() { cut -d' ' -f1 /proc/uptime; }

want() {
    [ -z "$CHECKS" ] && return 0
    case ",$CHECKS," in *",$1,"*) return 0 ;; esac
    return 1
}

EV=$W/evidence
ev() { echo "$*" >>$EV; }
ev_file() {
    f=$1
    max=${2:-24}
    [ -s "$f" ] || { echo "($f is empty or missing)" >>$EV; return; }
    n=$(wc -l <"$f")
    if [ "$n" -le "$max" ]; then
        cat "$f" >>$EV
    else
        half=$((max / 2))
        head -n $half "$f" >>$EV
        echo "... ($((n - max)) more lines) ..." >>$EV
        tail -n $half "$f" >>$EV
    fi
}

VERDICT=""
pass() { VERDICT="PASS $*"; }
fail() { VERDICT="FAIL $*"; }
host() { VERDICT="HOST $*"; } # judged by run.sh on the host, from the VM's files and the host's log

check() {
    want "$1" || return 0
    : >$EV
    VERDICT=""
    t0=$(uptime_s)
    "ck_$1"
    [ -n "$VERDICT" ] || VERDICT="FAIL the check reached no verdict"
    took="[at ${t0}s, took $(awk -v a="$t0" -v b="$(uptime_s)" 'BEGIN {printf "%.1f", b - a}')s]"
    case $VERDICT in
        HOST*) echo "HOST-CHECK $1: ${VERDICT#HOST } $took" ;;
        *) echo "CHECK $1: $VERDICT $took" ;;
    esac
    case $VERDICT in
        PASS*) N_PASS=$((N_PASS + 1)) ;;
        HOST*) N_HOST=$((N_HOST + 1)) ;;
        *)
            N_FAIL=$((N_FAIL + 1))
            FAILED="$FAILED $1"
            sed 's/^/  | /' $EV
            ;;
    esac
    reap_strays
}

# port_dev NAME: the device of the virtio serial port named NAME (/dev/vport0pN)
port_dev() {
    for p in /sys/class/virtio-ports/*; do
        [ "$(cat $p/name 2>/dev/null)" = "$1" ] && { echo /dev/${p##*/}; return 0; }
    done
    return 1
}
# the markers' port stays open (a virtio port opens once at a time); mark TEXT: a line for the host's log
MARKS=$(port_dev marks)
exec 7>$MARKS
mark() { echo "$*" >&7; }

# ------------------------------------------------------------------------------------------- candump helpers

CAP_PID=""
CAP_FILE=""
CAP_IFACE=""
# The witness candump must not lose frames: on a loaded host a starved candump overflowed the default socket
# buffer (212992 bytes, ~0.7 s of the simulator's traffic) and lost drive's stop frames, which the simulator got.
# -r: an 8 MiB receive buffer (SO_RCVBUFFORCE, as root) for candump's socket only.
CAP_RCVBUF=8388608
# cap_start FILE IFACE: candump -L IFACE > FILE in the background, returns once candump sees frames
cap_start() {
    CAP_FILE=$1
    CAP_IFACE=$2
    candump -r $CAP_RCVBUF -L "$CAP_IFACE" >"$CAP_FILE" 2>"$CAP_FILE.err" &
    CAP_PID=$!
    i=0
    while [ $i -lt 100 ]; do
        cansend "$CAP_IFACE" 7F0#5A
        grep -q " 7F0#5A\$" "$CAP_FILE" && return 0
        usleep 50000
        i=$((i + 1))
    done
    echo "WARN: candump on $CAP_IFACE did not start" >&2
    return 1
}
# cap_stop: send an end marker, wait until candump has logged it (so it has everything before it), stop candump
cap_stop() {
    [ -n "$CAP_PID" ] || return 0
    cansend "$CAP_IFACE" 7F0#E0
    i=0
    while [ $i -lt 100 ] && ! grep -q " 7F0#E0\$" "$CAP_FILE"; do
        usleep 50000
        i=$((i + 1))
    done
    kill -INT $CAP_PID 2>/dev/null
    wait $CAP_PID 2>/dev/null
    CAP_PID=""
}

# frames FILE [ID...]: "t_us ID DATA" per candump -L line (t_us: microseconds since the first line's second),
# only the given identifiers (all but the scenario's 7F0-7F3 markers if none given)
frames() {
    f=$1
    shift
    awk -v ids="$*" '
        BEGIN { n = split(ids, a, " "); for (i = 1; i <= n; i++) want[a[i]] = 1 }
        /^\([0-9]+\.[0-9]+\) / {
            ts = substr($1, 2, length($1) - 2)
            split(ts, b, ".")
            if (base == "") base = b[1]
            us = b[2]
            while (length(us) < 6) us = us "0"
            # ("1" us) - 1000000, not us + 0: busybox awk reads "030544" as octal (12644)
            t = (b[1] - base) * 1000000 + (("1" substr(us, 1, 6)) - 1000000)
            k = index($3, "#")
            id = substr($3, 1, k - 1)
            if (n == 0) { if (id !~ /^7F[0-3]$/) print t, id, substr($3, k + 1) }
            else if (id in want) print t, id, substr($3, k + 1)
        }' "$f"
}

# lines FILE ID...: the raw candump lines with these identifiers
lines() {
    f=$1
    shift
    ids=$(echo "$*" | tr ' ' '|')
    grep -E " ($ids)#" "$f"
}

# The witness: an independent sender (cangen, 0x7F3 every 10 ms) running during timing captures. When the whole VM
# stalls (the host deschedules QEMU), the witness falls silent too; a gap in a periodic frame that the witness
# shares is the VM's, not the program's, and is reported but not held against it.
WIT_PID=""
witness_start() { cangen vcan0 -I 7F3 -L 0 -g 10 >/dev/null 2>&1 & WIT_PID=$!; }
witness_stop() { stop "$WIT_PID"; WIT_PID=""; }

# cadence FILE.f ID LO HI MAXGAP: median period of ID within [LO, HI] ms, no gap over MAXGAP ms (except VM-wide
# stalls the witness shares), >= 8 gaps. Prints "ok ..." or "BAD ...".
cadence() {
    med=$(awk -v id="$2" '$2 == id {if (n++) printf "%.3f\n", ($1 - p) / 1000; p = $1}' "$1" | sort -n | awk '
        {g[NR] = $1} END {if (NR == 0) print -1; else print (NR % 2) ? g[(NR + 1) / 2] : (g[NR / 2] + g[NR / 2 + 1]) / 2}')
    awk -v id="$2" -v lo="$3" -v hi="$4" -v lim="$5" -v med="$med" '
        $2 == "7F3" {w[++nw] = $1; next}
        $2 == id {t[++n] = $1}
        END {
            j = 1; mx = 0; mn = -1; stalls = 0; list = ""
            for (i = 2; i <= n; i++) {
                g = (t[i] - t[i - 1]) / 1000
                if (mn < 0 || g < mn) mn = g
                excused = 0
                if (g > lim && nw > 0) {
                    while (j <= nw && w[j] <= t[i - 1]) j++
                    prev = t[i - 1]; sil = 0
                    for (k = j; k <= nw && w[k] < t[i]; k++) {if (w[k] - prev > sil) sil = w[k] - prev; prev = w[k]}
                    if (t[i] - prev > sil) sil = t[i] - prev
                    if (sil / 1000 >= g - 40) {excused = 1; stalls++; list = list sprintf(" %.0f", g)}
                }
                if (!excused && g > mx) mx = g
            }
            ng = n > 0 ? n - 1 : 0
            extra = stalls ? sprintf(" (+%d VM-wide stall(s) shared by the witness, ms:%s)", stalls, list) : ""
            ok = (ng >= 8 && med >= lo && med <= hi && mx < lim)
            printf "%s 0x%s n=%d median=%.1fms min=%.1fms max=%.1fms%s", ok ? "ok" : "BAD", id, n, med, mn, mx, extra
            if (!ok) printf " (want median %s-%s ms, max < %s ms, >= 9 frames)", lo, hi, lim
            print ""
        }' "$1"
}

within() { awk -v x="$1" -v lo="$2" -v hi="$3" 'BEGIN {exit !(x >= lo && x <= hi)}'; }

# v111 DATA: "linear_mm_s angular_mrad_s" of a 0x111 payload (int16 big-endian each)
v111() {
    echo "$1" | awk '
        function h(s,   i, v) {v = 0; for (i = 1; i <= length(s); i++) v = v * 16 + index("0123456789ABCDEF", substr(s, i, 1)) - 1; return v}
        function s16(v) {return v >= 32768 ? v - 65536 : v}
        {print s16(h(substr($1, 1, 4))), s16(h(substr($1, 5, 4)))}'
}

# ------------------------------------------------------------------------------------------- process helpers

# fg_run PIDFILE OUT ERR CMD...: run CMD in the foreground (default signal dispositions), its pid in PIDFILE first
fg_run() {
    pf=$1
    out=$2
    err=$3
    shift 3
    rm -f "$pf"
    sh -c 'echo $$ >"$0"; exec "$@"' "$pf" "$@" >"$out" 2>"$err"
}

wait_pidfile() {
    i=0
    while [ ! -s "$1" ] && [ $i -lt 200 ]; do usleep 50000; i=$((i + 1)); done
    cat "$1" 2>/dev/null
}

alive() { [ -n "$1" ] && kill -0 "$1" 2>/dev/null; }

wait_gone() {
    i=0
    while alive "$1"; do
        [ $i -ge $(($2 * 20)) ] && return 1
        usleep 50000
        i=$((i + 1))
    done
    return 0
}

# wait_grep FILE REGEX SECS [PID]: wait until FILE has a line matching REGEX; 1 on timeout or if PID died
wait_grep() {
    i=0
    while ! grep -qE "$2" "$1" 2>/dev/null; do
        [ $i -ge $(($3 * 20)) ] && return 1
        [ -n "$4" ] && ! alive "$4" && { grep -qE "$2" "$1" 2>/dev/null; return; }
        usleep 50000
        i=$((i + 1))
    done
    return 0
}

# reap_strays: kill tracerctl/can-utils processes a check left behind (not the simulator)
reap_strays() {
    for p in $(pidof tracerctl cangen cansend candump 2>/dev/null); do
        [ "$p" = "$SIM_PID" ] && continue
        pp=$(awk '/^PPid:/ {print $2}' /proc/$p/status 2>/dev/null)
        [ -n "$SIM_PID" ] && [ "$pp" = "$SIM_PID" ] && continue
        echo "NOTE: killing a process left behind: $p $(tr '\0' ' ' </proc/$p/cmdline 2>/dev/null)"
        kill -KILL $p 2>/dev/null
    done
}

stop() {
    alive "$1" || { wait "$1" 2>/dev/null; return 0; }
    kill -TERM "$1" 2>/dev/null
    wait_gone "$1" 5 || kill -KILL "$1" 2>/dev/null
    wait "$1" 2>/dev/null
}

# the virtual TRACER on vcan0
SIM_PID=""
SIM_UP=0
sim_start() {
    $T --iface vcan0 sim >$W/sim.out 2>$W/sim.err &
    SIM_PID=$!
    cap_start $W/sim_probe.log vcan0
    if wait_grep $W/sim_probe.log ' 211#' 15 $SIM_PID; then SIM_UP=1; else SIM_UP=0; fi
    cap_stop
}
sim_stop() {
    stop "$SIM_PID"
    SIM_PID=""
}
ev_sim() {
    [ "$SIM_UP" = 1 ] && return
    ev "the simulator ('$T --iface vcan0 sim') sent no 0x211 within 15 s; its stderr:"
    ev_file $W/sim.err 6
}

# run_cmd NAME CMD...: a short tracerctl command (30 s limit) with a capture of vcan0 around it; sets RC
run_cmd() {
    name=$1
    shift
    cap_start $W/$name.log vcan0
    timeout 30 "$@" >$W/$name.out 2>$W/$name.err
    RC=$?
    cap_stop
}

ev_cmd() {
    ev "\$ $2   (exit status $RC)"
    [ -s $W/$1.err ] && { ev "stderr:"; ev_file $W/$1.err 8; }
    [ -s $W/$1.out ] && { ev "stdout:"; ev_file $W/$1.out 8; }
}

# report_line FILE NAME: doctor's text line for check NAME ("PASS  battery  25.9 V")
report_line() { grep -E "^(PASS|WARN|FAIL|SKIP|INFO) +$2  " "$1" | head -n 1 | tr -s ' '; }
# doctor_verdict NAME FILE RC PASSES...: exit 0, every named check PASS, the Result line says drivable
doctor_verdict() {
    name=$1
    f=$2
    rc=$3
    shift 3
    notpass=""
    for c in "$@"; do
        case $(report_line "$f" "$c") in PASS*) ;; *) notpass="$notpass [$c: $(report_line "$f" "$c")]" ;; esac
    done
    result=$(grep '^Result:' "$f" | head -n 1)
    warns=$(grep -E '^WARN' "$f" | tr -s ' ' | tr '\n' ';')
    if [ "$rc" != 0 ]; then
        fail "exit status $rc (want 0, drivable): $result"
    elif [ -n "$notpass" ]; then
        fail "not PASS:$notpass"
    elif ! echo "$result" | grep -q 'can be driven'; then
        fail "the Result line does not say the robot can be driven: $result"
    else
        pass "exit 0; $(for c in "$@"; do printf '%s; ' "$(report_line "$f" "$c")"; done)${warns:+warnings: $warns }$result"
    fi
}

# ------------------------------------------------------------------------------------------- the machine

ck_platform() {
    m=$(uname -m)
    impl=$(awk -F': *' '/^CPU implementer/ {print $2; exit}' /proc/cpuinfo)
    part=$(awk -F': *' '/^CPU part/ {print $2; exit}' /proc/cpuinfo)
    # e_machine of the ELF header (offset 18, little-endian): 0xB7 = AArch64
    em=$(od -An -tx1 -j18 -N2 /usr/bin/$T | tr -d ' \n')
    v=$($T --version 2>&1)
    rc=$?
    # the guest has glibc's loader (for can-utils) and no musl loader: tracerctl running proves it needs none
    musl=$(ls /lib/ld-musl-* 2>/dev/null)
    if [ "$m" != aarch64 ]; then
        fail "uname -m is $m, not aarch64"
    elif [ "$em" != b700 ]; then
        fail "/usr/bin/$T has ELF machine $em, not b700 (AArch64)"
    elif [ $rc != 0 ]; then
        fail "$T --version: exit status $rc: $v"
    elif [ -n "$musl" ]; then
        fail "the guest has a musl loader ($musl): it cannot show that the binary needs none"
    else
        pass "uname -m $m, kernel $(uname -r); CPU implementer $impl part $part (0x41/0xd07: Arm Cortex-A57); /usr/bin/$T: ELF machine 0xB7 (AArch64), runs with no musl loader in the guest (static): $v"
    fi
}

# ------------------------------------------------------------------------------------------- vcan

ck_vcan_doctor() {
    [ -n "$SIM_PID" ] || sim_start
    cmd="$T --iface vcan0 --color never doctor --listen 1s"
    timeout 30 $cmd >$W/vdoc.out 2>$W/vdoc.err
    RC=$?
    doctor_verdict vcan_doctor $W/vdoc.out $RC "kernel CAN" interface "interface up" "frames arriving" protocol "system status" E-stop battery
    case $VERDICT in FAIL*) ev_cmd vdoc "$cmd"; ev_sim ;; esac
}

# monitor_verdict OUT ERR RC SOURCE ID MIN RATE_LO JUMPS: exit 0, >= MIN system_state lines with 25.9 V, all from
# SOURCE; their count bytes consecutive but for at most JUMPS breaks (nothing lost); the summary's rate of ID at
# least RATE_LO/s (0: not judged)
monitor_verdict() {
    n=$(grep -c "system_state .*battery_voltage=25.9V" $1)
    other=$(grep 'system_state' $1 | grep -vc " $4 ")
    jumps=$(sed -n 's/.*system_state .* count=\([0-9]*\).*/\1/p' $1 | awk 'NR > 1 && ($1 - p + 256) % 256 != 1 {j++} {p = $1} END {print j + 0}')
    row=$(cat $1 $2 | awk -v id="$5" '$1 == id && $2 == "system_state" {print; exit}' | tr -s ' ')
    rate=$(echo "$row" | awk '{print $4}')
    summary=$(cat $1 $2 | grep -m 1 'monitored ')
    if [ "$3" != 0 ]; then
        fail "exit status $3 (want 0 after --duration 2s)"
    elif [ "$n" -lt "$6" ]; then
        fail "$n system_state lines with battery_voltage=25.9V (want >= $6 in 2 s)"
    elif [ "$other" != 0 ]; then
        fail "$other system_state lines do not name $4"
    elif [ "$jumps" -gt "$8" ]; then
        fail "the count bytes of the system_state lines break $jumps times (at most $8): frames were lost"
    elif [ "$7" != 0 ] && { [ -z "$rate" ] || ! within "$rate" "$7" 65; }; then
        fail "the summary gives ${rate:-no} rate for $5 system_state (want $7-65/s): ${row:-no row}"
    else
        pass "exit 0; $n system_state lines with battery_voltage=25.9V from $4, count bytes consecutive ($jumps breaks), e.g. '$(grep -m 1 'system_state' $1 | cut -c 1-160)'; summary: $summary; $row"
    fi
}

ck_vcan_monitor() {
    [ -n "$SIM_PID" ] || sim_start
    cmd="$T --iface vcan0 --color never monitor --duration 2s"
    timeout 30 $cmd >$W/vmon.out 2>$W/vmon.err
    RC=$?
    # the simulator runs in the VM: 50/s by the VM's clock, nothing lost
    monitor_verdict $W/vmon.out $W/vmon.err $RC vcan0 0x211 50 35 0
    case $VERDICT in FAIL*) ev_cmd vmon "$cmd"; ev_sim ;; esac
}

# --- drive --linear 0.2 --for 1s, candump -L vcan0 the witness
VDRIVE_DONE=0
setup_vdrive() {
    [ $VDRIVE_DONE = 1 ] && return
    VDRIVE_DONE=1
    [ -n "$SIM_PID" ] && sim_stop
    sim_start # fresh: in standby
    witness_start
    run_cmd vdrive $T --iface vcan0 drive --linear 0.2 --for 1s
    VDRIVE_RC=$RC
    witness_stop
    frames $W/vdrive.log 111 421 >$W/vdrive.f
    frames $W/vdrive.log 111 211 7F3 >$W/vdrivew.f
    awk '$2 == "111"' $W/vdrive.f >$W/vdrive111.f
    lines $W/vdrive.log 111 421 >$W/vdrive.l
}
ev_vdrive() {
    RC=$VDRIVE_RC
    ev_cmd vdrive "$T --iface vcan0 drive --linear 0.2 --for 1s"
    ev_sim
    ev "candump -L vcan0 (111, 421):"
    ev_file $W/vdrive.l 20
}

ck_vcan_drive_period() {
    setup_vdrive
    r=$(cadence $W/vdrivew.f 111 15 25 100)
    case $r in
        ok*) pass "$r" ;;
        *) fail "$r"; ev_vdrive ;;
    esac
}

ck_vcan_drive_bytes() {
    setup_vdrive
    first421=$(awk '$2 == "421" && $3 == "01" {print NR; exit}' $W/vdrive.f)
    first111=$(awk '$2 == "111" {print NR; exit}' $W/vdrive.f)
    # every 0x111: linear 0..200 mm/s, angular and bytes 4-7 zero
    bad=$(awk '{print $3}' $W/vdrive111.f | while read -r d; do
        # shellcheck disable=SC2046 # split on purpose: the fields of one line
        set -- $(v111 "$d")
        if [ "$1" -lt 0 ] || [ "$1" -gt 200 ] || [ "${d#????}" != 000000000000 ]; then echo "$d"; fi
    done | head -n 3 | tr '\n' ' ')
    top=$(grep -c ' 00C8000000000000$' $W/vdrive111.f)
    nz=$(awk 'substr($3, 1, 4) != "0000"' $W/vdrive111.f | grep -c .)
    ramp=$(awk 'substr($3, 1, 4) != "0000" && s == "" {s = NR} $3 == "00C8000000000000" {print NR - s; exit}' $W/vdrive111.f)
    if [ -z "$first421" ]; then
        fail "no 421#01 (CAN command mode) was sent"
    elif [ -z "$first111" ] || [ "$first421" -gt "$first111" ]; then
        fail "no 0x111, or the first 0x111 came before 421#01"
    elif [ -n "$bad" ]; then
        fail "0x111 outside 0..200 mm/s or with angular/reserved bytes set: $bad"
    elif [ "$top" = 0 ]; then
        fail "no 0x111 at exactly 111#00C8000000000000 (200 mm/s); $nz non-zero"
    else
        pass "421#01 before the first 0x111; $nz moving 0x111, $top at 111#00C8000000000000 (0.2 m/s), reached after a ramp of $ramp frames; angular and bytes 4-7 always zero"
    fi
    case $VERDICT in FAIL*) ev_vdrive ;; esac
}

ck_vcan_drive_stops_at_zero() {
    setup_vdrive
    last=$(tail -n 1 $W/vdrive111.f | awk '{print $3}')
    zeros=$(awk '{z = ($3 == "0000000000000000") ? z + 1 : 0} END {print z + 0}' $W/vdrive111.f)
    span=$(awk 'NR == 1 {a = $1} {b = $1} END {printf "%.2f", (b - a) / 1e6}' $W/vdrive111.f)
    n=$(grep -c . $W/vdrive111.f)
    reported=$(cat $W/vdrive.out $W/vdrive.err | sed -n 's/^ *\([0-9]*\) motion frames sent.*/\1/p' | head -n 1)
    if [ "$VDRIVE_RC" != 0 ]; then
        fail "exit status $VDRIVE_RC"
    elif [ "$last" != "0000000000000000" ]; then
        fail "the last 0x111 is 111#$last, not 111#0000000000000000"
    elif ! within "$span" 0.8 5; then
        fail "0x111 frames span ${span} s by candump's clock (want about 1 s: 0.8-5)"
    elif [ "$reported" != "$n" ]; then
        fail "drive reports '${reported:-no count of} motion frames sent', candump saw $n"
    else
        pass "exit 0; $n 0x111 on the bus, as drive reports; the last is 111#$last ($zeros zero frames at the end); span ${span} s"
    fi
    case $VERDICT in FAIL*) ev_vdrive ;; esac
}

# --- SIGINT mid-drive (foreground: default dispositions), as scenario.sh's drive_sigint
MOVING=' 111#([1-9A-F][0-9A-F]{3}|0[1-9A-F][0-9A-F]{2}|00[1-9A-F][0-9A-F]|000[1-9A-F])'
ck_vcan_drive_sigint() {
    [ -n "$SIM_PID" ] || sim_start
    log=$W/vsig.log
    cap_start $log vcan0
    rm -f $W/vsig.note
    (
        pid=$(wait_pidfile $W/vsig.pid)
        wait_grep $log "$MOVING" 15 $pid || echo "no non-zero 0x111 within 15 s; sent SIGINT anyway;" >>$W/vsig.note
        sleep 1
        cansend vcan0 7F1#02
        kill -INT $pid 2>/dev/null || echo "the process had already exited before SIGINT" >>$W/vsig.note
        if ! wait_gone "$pid" 10; then
            echo "still running 10 s after SIGINT: killed with SIGKILL" >>$W/vsig.note
            kill -KILL $pid
        fi
    ) &
    helper=$!
    fg_run $W/vsig.pid $W/vsig.out $W/vsig.err $T --iface vcan0 drive --linear 0.2
    SIG_RC=$?
    cansend vcan0 7F2#02
    wait $helper
    cap_stop
    frames $log 111 7F1 7F2 >$W/vsig.f
    after=$(awk '$2 == "7F1" {m = $1; next} m != "" && $2 == "111" {printf "%d %s\n", ($1 - m) / 1000, $3}' $W/vsig.f)
    nbefore=$(awk '$2 == "7F1" {exit} $2 == "111" && substr($3, 1, 4) != "0000"' $W/vsig.f | grep -c .)
    firstzero=$(echo "$after" | awk '$2 == "0000000000000000" {print $1; exit}')
    nzafter=$(echo "$after" | awk 'z && $2 != "0000000000000000" {n++} $2 == "0000000000000000" {z = 1} END {print n + 0}')
    last=$(awk '$2 == "7F2" {exit} $2 == "111" {l = $3} END {print l}' $W/vsig.f)
    afterexit=$(awk '$2 == "7F2" {e = 1; next} e && $2 == "111"' $W/vsig.f | grep -c .)
    note=$(cat $W/vsig.note 2>/dev/null | tr '\n' ' ')
    if [ -n "$note" ]; then
        fail "$note(exit status $SIG_RC)"
    elif [ "$nbefore" = 0 ]; then
        fail "no moving 0x111 before SIGINT (exit status $SIG_RC)"
    elif [ -z "$firstzero" ]; then
        fail "no zero 0x111 after SIGINT (exit status $SIG_RC)"
    elif [ "$nzafter" != 0 ]; then
        fail "$nzafter moving 0x111 after the first zero that followed SIGINT"
    elif [ "$last" != "0000000000000000" ]; then
        fail "the last 0x111 before the exit is 111#$last, not zero (exit status $SIG_RC)"
    elif [ "$afterexit" != 0 ]; then
        fail "$afterexit 0x111 after the process had exited"
    elif [ "$SIG_RC" != 130 ]; then
        fail "exit status $SIG_RC (want 130 after SIGINT)"
    else
        pass "exit status 130; $nbefore moving 0x111 before SIGINT; first 111#0000000000000000 ${firstzero} ms after it; $(echo "$after" | grep -c .) 0x111 after it, the last zero, none after the exit"
    fi
    case $VERDICT in FAIL*)
        RC=$SIG_RC
        ev_cmd vsig "$T --iface vcan0 drive --linear 0.2   (then SIGINT)"
        ev_sim
        ev "candump -L vcan0 (111, signal marker 7F1, exit marker 7F2):"
        lines $log 111 7F1 7F2 >$W/vsig.l
        ev_file $W/vsig.l 20 ;;
    esac
}

# ------------------------------------------------------------------------------------------- RS232 on ttyS0

SER=/dev/ttyS0
# ser_tx: bytes ttyS0's driver has moved into the UART since boot (/proc/tty/driver/serial "tx:"). The host logs
# the same stream from byte 0, so a marker that carries tx=N sits exactly at byte N of it, however the host's
# scheduling bunched the marker and the UART's bytes together.
ser_tx() { sed -n 's/^0: .* tx:\([0-9]*\).*/\1/p' /proc/tty/driver/serial; }
smark() { mark "$* tx=$(ser_tx)"; }

# stalled FILE.f: the longest silence (ms) of the witness 0x7F3 in a frames file, from its first to its last frame
stalled() { awk '$2 == "7F3" {if (p != "" && $1 - p > m) m = $1 - p; p = $1} END {printf "%d", m / 1000}' "$1"; }

ck_serial_uart() {
    line=$(grep '^0: ' /proc/tty/driver/serial)
    drv=$(readlink /sys/class/tty/ttyS0/device/driver)
    dev=$(readlink /sys/class/tty/ttyS0/device)
    if ! echo "$line" | grep -q 'uart:16550A'; then
        fail "ttyS0 is not a 16550A: $line"
    elif [ "${drv##*/}" != serial ] || ! echo "$drv" | grep -q '/pci/'; then
        fail "ttyS0's driver is $drv, not the 8250 PCI driver (bus/pci/drivers/serial)"
    else
        pass "ttyS0: $(echo "$line" | tr -s ' '); driver ${drv#../../../../../}; device ${dev##*/}; $(stty -F $SER 2>&1 | head -n 1)"
    fi
}

# The robot runs on the host in real time: a VM the host stops for a while (a loaded host) hears less of it in
# doctor's 1 s than the robot sent. A witness (cangen 0x7F3 every 10 ms, captured in the VM) shows such stalls;
# a doctor run that failed while the VM stalled is run again, twice at most, and the line says so.
ck_serial_doctor() {
    [ -n "$SIM_PID" ] && sim_stop
    cmd="$T --serial $SER --color never doctor --listen 1s"
    notes=""
    attempt=1
    while :; do
        cap_start $W/sdoc.wit vcan0
        witness_start
        smark "begin serial_doctor"
        timeout 30 $cmd >$W/sdoc.out 2>$W/sdoc.err
        RC=$?
        smark "end serial_doctor"
        witness_stop
        cap_stop
        stall=$(frames $W/sdoc.wit 7F3 >$W/sdoc.wf; stalled $W/sdoc.wf)
        doctor_verdict serial_doctor $W/sdoc.out $RC "serial port" "frames arriving" "system status" E-stop faults battery
        if [ "${VERDICT%% *}" = PASS ] && ! grep -qE "^PASS +serial port +$SER open at 115200 baud, 8N1" $W/sdoc.out; then
            fail "the serial port line does not say $SER open at 115200 baud, 8N1: $(report_line $W/sdoc.out 'serial port')"
        fi
        case $VERDICT in PASS*) break ;; esac
        if [ "$stall" -lt 150 ] || [ $attempt -ge 3 ]; then break; fi
        notes="${notes}attempt $attempt failed while the VM stalled (the witness silent for $stall ms): $(grep '^Result' $W/sdoc.out); "
        cp $W/sdoc.out $W/sdoc.out.$attempt
        attempt=$((attempt + 1))
    done
    [ -n "$notes" ] && VERDICT="$VERDICT [$notes]"
    case $VERDICT in FAIL*)
        ev_cmd sdoc "$cmd   (the host's tracerctl sim --serial on the other end of ttyS0)"
        ev "the witness's longest silence during the run: $stall ms" ;;
    esac
}

ck_serial_monitor() {
    cmd="$T --serial $SER --color never monitor --duration 2s"
    smark "begin serial_monitor"
    timeout 30 $cmd >$W/smon.out 2>$W/smon.err
    RC=$?
    smark "end serial_monitor"
    # the simulator runs on the host: a VM the host stalls reads less in its 2 s, and the first frames may be the
    # last ones of the previous check's session (one break); 50/s is not judged here (the vcan checks do)
    monitor_verdict $W/smon.out $W/smon.err $RC $SER 0xAA01 20 0 1
    case $VERDICT in FAIL*) ev_cmd smon "$cmd" ;; esac
}

# The wire is judged on the host (arm64-host.py judge) from every byte that left ttyS0, between the markers.
# The witness for the host's clock: cangen's 0x7F3 every 10 ms, candump'ed into the markers' port.
ck_serial_drive() {
    witness_start
    candump -r $CAP_RCVBUF -L vcan0,7F3:7FF >&7 2>/dev/null &
    wp=$!
    usleep 200000
    smark "begin serial_drive"
    timeout 30 $T --serial $SER drive --linear 0.2 --for 1s >$W/serdrive.out 2>$W/serdrive.err
    rc=$?
    echo $rc >$W/serdrive.rc
    smark "end serial_drive"
    stop $wp
    witness_stop
    host "judged on the host from the bytes that left ttyS0 (drive exit $rc; $(grep -h 'motion frames sent' $W/serdrive.out $W/serdrive.err | tr -s ' '))"
}

ck_serial_sigint() {
    rm -f $W/sersig.note
    smark "begin serial_sigint"
    (
        pid=$(wait_pidfile $W/sersig.pid)
        # drive's status line once a second: full speed sent
        wait_grep $W/sersig.out 'sent \+0\.200' 15 $pid || echo "drive never reported 'sent +0.200'; SIGINT anyway;" >>$W/sersig.note
        usleep 300000
        smark "sigint"
        kill -INT $pid 2>/dev/null || echo "the process had already exited before SIGINT" >>$W/sersig.note
        if ! wait_gone "$pid" 10; then
            echo "still running 10 s after SIGINT: killed with SIGKILL" >>$W/sersig.note
            kill -KILL $pid
        fi
    ) &
    helper=$!
    fg_run $W/sersig.pid $W/sersig.out $W/sersig.err $T --serial $SER drive --linear 0.2
    rc=$?
    echo $rc >$W/sersig.rc
    wait $helper
    smark "end serial_sigint"
    host "judged on the host from the bytes that left ttyS0 (drive exit $rc$( [ -s $W/sersig.note ] && printf '; %s' "$(cat $W/sersig.note)"))"
}

# ------------------------------------------------------------------------------------------- the dashboard
# hvc1 (virtio console "tty") is the dashboard's terminal, a session of its own with hvc1 as its controlling tty;
# hvc0 ("term") is the other end: keys written there arrive on hvc1 (through the host), the screen comes back.
# Keys (src/dashboard/keys.rs): a (arm, asks first), y (yes), Up arrow ESC [ A (drive; a terminal repeats it while
# held: here every 40 ms), Space (zero at once), q (stop the robot and quit). Each key is preceded on vcan0 by
# 7F1#NN: 01 a, 02 y, 03 Up held, 04 Space, 05 Up held again, 06 q; 7F2#06 once the dashboard has exited.

TERMDEV=/dev/hvc0
TTYDEV=/dev/hvc1
SCREEN=$W/screen.raw

# key_hold N: the Up arrow N times, 40 ms apart (auto-repeat)
key_hold() {
    i=0
    while [ $i -lt $1 ]; do
        printf '\033[A' >&8
        usleep 40000
        i=$((i + 1))
    done
}

DASH_DONE=0
setup_dash() {
    [ $DASH_DONE = 1 ] && return
    DASH_DONE=1
    DASH_NOTE=""
    [ -n "$SIM_PID" ] && sim_stop
    sim_start # fresh: in standby
    # A virtio console's termios go back to the defaults (echo on) at every first open (TTY_DRIVER_RESET_TERMIOS):
    # open first, then set raw while open. An echo on either end would loop bytes between them through the host.
    exec 8<>$TERMDEV
    stty -F $TERMDEV raw -echo
    exec 9<$TTYDEV
    stty -F $TTYDEV raw -echo
    TTY_MODE=$(stty -F $TTYDEV 2>&1 | tr '\n' ' ' | tr -s ' ' | sed 's/.*time = [0-9]*; *//')
    # the terminal works: what is typed on hvc0 arrives on hvc1
    cat <&9 >$W/probe.in &
    pp=$!
    usleep 200000
    printf 'probe-42' >&8
    if wait_grep $W/probe.in 'probe-42' 10; then TERM_OK=1; else TERM_OK=0; fi
    kill $pp 2>/dev/null
    wait $pp 2>/dev/null
    exec 9<&-
    SAW_WATCHING=0
    SAW_PROMPT=0
    SAW_ARMED=0
    DASH_RC=""
    if [ $TERM_OK = 0 ]; then
        exec 8>&-
        sim_stop
        : >$SCREEN
        : >$W/dash.f
        : >$W/dash.l
        for k in 01 02 03 04 05 06; do : >$W/dash111.$k; done
        return
    fi
    cat $TERMDEV >$SCREEN &
    SCR_PID=$!
    cap_start $W/dash.log vcan0
    rm -f $W/dash.pid
    TERM=xterm setsid -c sh -c 'echo $$ >/tmp/scn/dash.pid; stty rows 40 cols 120; exec tracerctl --iface vcan0 dashboard --max-linear 0.5' \
        <$TTYDEV >$TTYDEV 2>$W/dash.err &
    DASH_SH=$!
    dpid=$(wait_pidfile $W/dash.pid)
    # crossterm asks whether the terminal reports key releases (ESC [ ? u) and for its attributes (ESC [ c);
    # answer the second as a terminal without the kitty protocol does (a VT220's attributes), so it does not wait
    # 2 s for an answer: key releases are then unknown, a held key is held while its repeats come
    DA_ANSWERED=0
    da=$(printf '\033[c')
    i=0
    while [ $i -lt 200 ] && alive $dpid; do
        if grep -qF "$da" $SCREEN 2>/dev/null; then
            printf '\033[?62;22c' >&8
            DA_ANSWERED=1
            break
        fi
        usleep 50000
        i=$((i + 1))
    done
    wait_grep $SCREEN 'WATCHING' 20 $dpid && SAW_WATCHING=1
    usleep 500000
    cansend vcan0 7F1#01
    printf 'a' >&8
    wait_grep $SCREEN 'Arm driving\?' 10 $dpid && SAW_PROMPT=1
    cansend vcan0 7F1#02
    printf 'y' >&8
    wait_grep $SCREEN 'ARMED' 10 $dpid && SAW_ARMED=1
    sleep 1
    cansend vcan0 7F1#03
    key_hold 30
    cansend vcan0 7F1#04
    printf ' ' >&8
    sleep 1
    cansend vcan0 7F1#05
    key_hold 20
    cansend vcan0 7F1#06
    printf 'q' >&8
    if ! wait_gone "$dpid" 10; then
        DASH_NOTE="still running 10 s after q: killed with SIGKILL; "
        kill -KILL "$dpid" 2>/dev/null
    fi
    wait $DASH_SH
    DASH_RC=$?
    cansend vcan0 7F2#06
    usleep 300000
    cap_stop
    kill $SCR_PID 2>/dev/null
    wait $SCR_PID 2>/dev/null
    exec 8>&-
    sim_stop
    frames $W/dash.log 111 421 121 441 7F1 7F2 >$W/dash.f
    lines $W/dash.log 111 421 121 441 7F1 7F2 >$W/dash.l
    # "t_ms_since_marker DATA" of the 0x111 after marker NN, up to the next 7F1/7F2
    for k in 01 02 03 04 05 06; do
        awk -v k="$k" '$2 == "7F1" || $2 == "7F2" {on = ($2 == "7F1" && $3 == k); if (on) m = $1; next}
            on && $2 == "111" {printf "%d %s\n", ($1 - m) / 1000, $3}' $W/dash.f >$W/dash111.$k
    done
}

ev_dash() {
    ev "dashboard: exit status $DASH_RC; ${DASH_NOTE}screen: $(wc -c <$SCREEN) bytes; WATCHING $SAW_WATCHING, 'Arm driving?' $SAW_PROMPT, ARMED $SAW_ARMED"
    ev "stderr:"
    ev_file $W/dash.err 6
    ev_sim
    ev "candump -L vcan0 (111, 421, 121, 441, key markers 7F1, exit marker 7F2), repeats folded:"
    awk '{print $3}' $W/dash.l | uniq -c | awk '{printf "%4d x %s\n", $1, $2}' >$W/dash.u
    ev_file $W/dash.u 40
}

nonzero() { awk 'substr($2, 1, 8) != "00000000"' "$1" | grep -c .; }

ck_dash_terminal() {
    setup_dash
    if [ "$TERM_OK" != 1 ]; then
        fail "'probe-42' written on $TERMDEV did not arrive on $TTYDEV within 10 s (read: '$(cat $W/probe.in)')"
    elif [ "$SAW_WATCHING" != 1 ]; then
        fail "the dashboard on $TTYDEV did not draw WATCHING within 20 s"
    else
        pass "$TTYDEV, a virtio console, is a tty (stty: $TTY_MODE); typed on $TERMDEV, read on $TTYDEV; the dashboard drew $(wc -c <$SCREEN) bytes on it, WATCHING among them; its attribute query $( [ $DA_ANSWERED = 1 ] && echo 'answered (VT220, no kitty protocol)' || echo 'not seen')"
    fi
    case $VERDICT in FAIL*) ev_dash ;; esac
}

ck_dash_arm() {
    setup_dash
    # nothing sent before y; after y: 421#01 before the first 0x111, and only zero 0x111 until the drive key
    before=$(awk '$2 == "7F1" && $3 == "02" {exit} $2 != "7F1"' $W/dash.f | grep -c .)
    t421=$(awk '$2 == "7F1" && $3 == "02" {m = 1; next} m && $2 == "421" {print NR; exit}' $W/dash.f)
    t111=$(awk '$2 == "7F1" && $3 == "02" {m = 1; next} m && $2 == "111" {print NR; exit}' $W/dash.f)
    m421=$(awk '$2 == "7F1" && $3 == "02" {m = 1; next} m && $2 == "421" {print $3; exit}' $W/dash.f)
    n=$(grep -c . $W/dash111.02)
    nz=$(nonzero $W/dash111.02)
    if [ "$SAW_PROMPT" != 1 ]; then
        fail "a did not show 'Arm driving?' within 10 s"
    elif [ "$SAW_ARMED" != 1 ]; then
        fail "y did not show ARMED within 10 s"
    elif [ "$before" != 0 ]; then
        fail "$before frames were sent before y (watching sends nothing)"
    elif [ -z "$t421" ] || [ "$m421" != 01 ]; then
        fail "no 421#01 (command mode) after y"
    elif [ -z "$t111" ] || [ "$t111" -lt "$t421" ]; then
        fail "no 0x111 after y, or the first came before 421#01"
    elif [ "$n" -lt 10 ] || [ "$nz" != 0 ]; then
        fail "$n 0x111 between y and the drive key, $nz of them moving (want >= 10, all zero)"
    else
        pass "a showed 'Arm driving?', y showed ARMED; nothing sent before y; then 421#01, then $n zero 0x111 until the drive key"
    fi
    case $VERDICT in FAIL*) ev_dash ;; esac
}

ck_dash_drive() {
    setup_dash
    first=$(awk 'substr($2, 1, 4) != "0000" {print $1 " ms: 111#" $2; exit}' $W/dash111.03)
    top=$(grep -c ' 0096000000000000$' $W/dash111.03)
    bad=$(awk '{print $2}' $W/dash111.03 | while read -r d; do
        # shellcheck disable=SC2046 # split on purpose: the fields of one line
        set -- $(v111 "$d")
        if [ "$1" -lt 0 ] || [ "$1" -gt 150 ] || [ "${d#????}" != 000000000000 ]; then echo "$d"; fi
    done | head -n 3 | tr '\n' ' ')
    nz=$(nonzero $W/dash111.03)
    if [ -z "$first" ]; then
        fail "no moving 0x111 after the Up arrow (held 1.2 s)"
    elif [ -n "$bad" ]; then
        fail "0x111 outside 0..150 mm/s forward or with angular/reserved bytes set: $bad"
    elif [ "$top" = 0 ]; then
        fail "$nz moving 0x111, none at 111#0096000000000000 (0.15 m/s: speed scale 3 of 10 x --max-linear 0.5)"
    else
        pass "first moving 0x111 $first after the key; $nz moving, $top at 111#0096000000000000 (0.15 m/s = scale 0.3 x 0.5 m/s); angular and bytes 4-7 zero"
    fi
    case $VERDICT in FAIL*) ev_dash ;; esac
}

# after_stop FILE: "first-zero-ms moving-before-it moving-after-it count"
after_stop() {
    awk '{z = (substr($2, 1, 8) == "00000000")} z && f == "" {f = $1} !z && f == "" {b++} !z && f != "" {a++} END {print (f == "" ? "-" : f), b + 0, a + 0, NR}' "$1"
}

ck_dash_space_stops() {
    setup_dash
    # shellcheck disable=SC2046 # split on purpose: the fields of one line
    set -- $(after_stop $W/dash111.04)
    fz=$1
    nb=$2
    na=$3
    n=$4
    if [ "$fz" = - ]; then
        fail "no zero 0x111 after Space ($n 0x111 before the next key)"
    elif [ "$fz" -gt 500 ]; then
        fail "the first zero 0x111 came $fz ms after Space (want < 500 ms: the key's way through the host included)"
    elif [ "$na" != 0 ]; then
        fail "$na moving 0x111 after the first zero, before the next key"
    elif [ "$n" -lt 20 ]; then
        fail "only $n 0x111 in the second after Space (armed: zeros at 50 Hz)"
    else
        pass "first 111#0000000000000000 $fz ms after Space ($nb moving before it: $(awk 'substr($2, 1, 8) == "00000000" {exit} {printf "%s ", $2}' $W/dash111.04)); then only zeros, $n 0x111 until the next key (still armed)"
    fi
    case $VERDICT in FAIL*) ev_dash ;; esac
}

ck_dash_quit_stops() {
    setup_dash
    again=$(nonzero $W/dash111.05)
    # shellcheck disable=SC2046 # split on purpose: the fields of one line
    set -- $(after_stop $W/dash111.06)
    fz=$1
    na=$3
    last=$(awk '$2 == "7F2" {exit} $2 == "111" {l = $3} END {print l}' $W/dash.f)
    afterexit=$(awk '$2 == "7F2" {e = 1; next} e && $2 == "111"' $W/dash.f | grep -c .)
    restored=0
    grep -q '\[?1049l' $SCREEN && restored=1
    if [ -n "$DASH_NOTE" ]; then
        fail "$DASH_NOTE(exit status $DASH_RC)"
    elif [ "$again" = 0 ]; then
        fail "the Up arrow after Space did not drive again (no moving 0x111)"
    elif [ "$fz" = - ]; then
        fail "no zero 0x111 after q"
    elif [ "$fz" -gt 500 ]; then
        fail "the first zero 0x111 came $fz ms after q (want < 500 ms: the key's way through the host included)"
    elif [ "$na" != 0 ]; then
        fail "$na moving 0x111 after the first zero that followed q"
    elif [ "$last" != 0000000000000000 ] || [ "$afterexit" != 0 ]; then
        fail "the last 0x111 before the exit is 111#$last; $afterexit 0x111 after the exit"
    elif [ "$DASH_RC" != 0 ]; then
        fail "exit status $DASH_RC (want 0 after q)"
    elif [ $restored = 0 ]; then
        fail "the screen never left the alternate screen (no ESC [?1049l)"
    else
        pass "the Up arrow drove again after Space ($again moving 0x111); after q the first zero in $fz ms, nothing moving after it, the last 0x111 zero, none after the exit; exit 0, alternate screen left; stderr: $(tr '\n' ' ' <$W/dash.err | cut -c 1-160)"
    fi
    case $VERDICT in FAIL*) ev_dash ;; esac
}

# ------------------------------------------------------------------------------------------- run

echo "SCENARIO START at uptime $(uptime_s)s; tracerctl: $($T --version 2>&1 | head -n 1); $(uname -m); marks on $MARKS"

check platform

check vcan_doctor
check vcan_monitor
check vcan_drive_period
check vcan_drive_bytes
check vcan_drive_stops_at_zero
check vcan_drive_sigint
[ -n "$SIM_PID" ] && sim_stop

check serial_uart
check serial_doctor
check serial_monitor
check serial_drive
check serial_sigint

check dash_terminal
check dash_arm
check dash_drive
check dash_space_stops
check dash_quit_stops
[ -n "$SIM_PID" ] && sim_stop

echo "SCENARIO END at uptime $(uptime_s)s: $N_PASS passed, $N_FAIL failed, $N_HOST to be judged on the host"
if [ $N_FAIL = 0 ] && [ $((N_PASS + N_HOST)) -gt 0 ]; then
    echo "SCENARIO PASS"
else
    [ $N_FAIL = 0 ] && echo "no check was selected (CHECKS=$CHECKS)"
    echo "SCENARIO FAIL ($N_FAIL failed:$FAILED)"
fi
