#!/usr/bin/env bash
# Real SocketCAN tests for tracerctl in a tiny QEMU VM (the host kernel may have no CAN at all).
# Two suites: vcan (the default: scenario.sh on vcan0/vcan1) and sja1000 (scenario-sja1000.sh on three emulated
# Kvaser PCI boards, SJA1000 controllers driven by the kernel's real sja1000/kvaser_pci drivers).
#
# Run as root on Debian 12 (CI, or a developer machine):   bash tests/vm/run.sh [--suite sja1000] [options]
# See tests/vm/README.md for what it does and what each check proves.
set -euo pipefail

usage() {
    cat <<'EOF'
Usage: tests/vm/run.sh [options]

  --suite NAME      vcan (default: scenario.sh on vcan0, vcan1) or sja1000 (scenario-sja1000.sh on can0-can2,
                    emulated SJA1000 controllers with the kernel's sja1000/kvaser_pci drivers; two CPUs)
                    (also: TRACERCTL_VM_SUITE)
  --bin PATH        use this tracerctl binary instead of building one (also: TRACERCTL_BIN)
  --work DIR        work and cache directory (default: <repo>/target/vm; also: TRACERCTL_VM_WORK)
  --checks LIST     run only these checks (comma-separated names, see tests/vm/README.md)
  --timeout SECS    kill the VM after this many seconds (default 600)
  --smp N           virtual CPUs (default 1 for vcan, 2 for sja1000; also: TRACERCTL_VM_SMP)
  --refresh-kernel  resolve and download the kernel package again (default: reuse the cached one)
  --self-test[=BUGS] (vcan suite) run the scenario against tests/vm/selftest/fake-tracerctl (can-utils posing as
                    tracerctl; decode goes to the real binary) to prove the checks can pass; BUGS, a
                    comma-separated list of faults for the fake to inject, proves they fail
  -h, --help        this help

Exit status: 0 every check passed, 1 a check failed, 2 usage error,
3 the environment could not be set up (packages, kernel, build, VM did not boot or finish).
EOF
}

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
work=${TRACERCTL_VM_WORK:-$repo/target/vm}
bin=${TRACERCTL_BIN:-}
checks=${TRACERCTL_VM_CHECKS:-}
vm_timeout=600
smp=${TRACERCTL_VM_SMP:-}
suite=${TRACERCTL_VM_SUITE:-vcan}
refresh_kernel=0
self_test=0
fake_bugs=""

while [ $# -gt 0 ]; do
    case $1 in
        --suite) suite=${2:?--suite needs a name: vcan or sja1000}; shift 2 ;;
        --suite=*) suite=${1#--suite=}; shift ;;
        --bin) bin=${2:?--bin needs a path}; shift 2 ;;
        --work) work=${2:?--work needs a directory}; shift 2 ;;
        --checks) checks=${2:?--checks needs a list}; shift 2 ;;
        --timeout) vm_timeout=${2:?--timeout needs seconds}; shift 2 ;;
        --smp) smp=${2:?--smp needs a number}; shift 2 ;;
        --refresh-kernel) refresh_kernel=1; shift ;;
        --self-test) self_test=1; shift ;;
        --self-test=*) self_test=1; fake_bugs=${1#--self-test=}; shift ;;
        -h | --help) usage; exit 0 ;;
        *) echo "run.sh: unknown argument: $1" >&2; usage >&2; exit 2 ;;
    esac
done
# what differs between the suites: scenario, modules (insmod order), qemu devices, default CPUs, file names
case $suite in
    vcan)
        scenario=scenario.sh
        modules="can can-raw can-dev vcan"
        qemu_devices=()
        qemu_serial_extra=()
        sfx=""
        : "${smp:=1}"
        ;;
    sja1000)
        scenario="scenario-sja1000.sh"
        modules="can can-raw can-dev sja1000 kvaser_pci"
        # one CAN bus (the name must not be canbus0: a property of another device model has that name),
        # three controllers on it: can0 (tracerctl), can1 (the simulator, the witness candump), can2 (markers)
        qemu_devices=(-object "can-bus,id=cbus0")
        for _ in 1 2 3; do qemu_devices+=(-device "kvaser_pci,canbus=cbus0"); done
        # ttyS2 (after the console ttyS0 and the artifacts' ttyS1): a terminal for the SIGTSTP checks
        # (a job-control shell needs a controlling terminal); ttyS3: the RS232 robot (serial_stalled_peer),
        # connected below when that check runs
        qemu_serial_extra=(-serial null)
        sfx=-sja1000
        # two CPUs: a flooding sender on one outruns the receiver on the other (RX FIFO overruns)
        : "${smp:=2}"
        ;;
    *) echo "run.sh: --suite takes vcan or sja1000, not '$suite'" >&2; exit 2 ;;
esac
if [ "$suite" != vcan ] && [ $self_test = 1 ]; then
    echo "run.sh: --self-test exists for the vcan suite only" >&2
    exit 2
fi
case $vm_timeout in '' | *[!0-9]*) echo "run.sh: --timeout needs a whole number of seconds" >&2; exit 2 ;; esac
case $smp in '' | *[!0-9]* | 0) echo "run.sh: --smp needs a positive number" >&2; exit 2 ;; esac
case $checks in *[!a-z0-9_,]*) echo "run.sh: --checks takes names like smoke_cansend,decode_captured" >&2; exit 2 ;; esac
case $fake_bugs in *[!a-z0-9,-]*) echo "run.sh: --self-test=BUGS takes names like drive-no-zero,sim-slow" >&2; exit 2 ;; esac

t_start=$(date +%s)
log() { printf '[vm %3ds] %s\n' "$(($(date +%s) - t_start))" "$*"; }
die() {
    printf '\nVM SUITE ERROR: %s\n' "$*" >&2
    exit 3
}

[ "$(id -u)" -eq 0 ] || die "run as root (it installs packages with apt-get and creates /dev/console in the initramfs)"
mkdir -p "$work"
work=$(cd "$work" && pwd)

# ---------------------------------------------------------------- host packages
# command -> Debian package that provides it
need_pkgs=()
for pair in qemu-system-x86_64:qemu-system-x86 candump:can-utils cansend:can-utils cangen:can-utils \
    canplayer:can-utils cpio:cpio ip:iproute2 gzip:gzip ldd:libc-bin dpkg-deb:dpkg; do
    cmd=${pair%%:*}
    command -v "$cmd" >/dev/null 2>&1 || need_pkgs+=("${pair#*:}")
done
# the sja1000 suite's RS232 robot (serial-robot.py) runs on the host
if [ "$suite" = sja1000 ]; then command -v python3 >/dev/null 2>&1 || need_pkgs+=(python3-minimal); fi
# a dynamic busybox (package "busybox") would not run in the VM without its libraries: insist on the static one
if [ ! -x /bin/busybox ] || LC_ALL=C ldd /bin/busybox 2>&1 | grep -q '=>'; then need_pkgs+=(busybox-static); fi

apt_updated=0
apt_update() {
    if [ $apt_updated -eq 0 ]; then
        log "apt-get update"
        apt-get update -qq || die "apt-get update failed (no network or no Debian repository configured?)"
        apt_updated=1
    fi
}

if [ ${#need_pkgs[@]} -gt 0 ]; then
    mapfile -t need_pkgs < <(printf '%s\n' "${need_pkgs[@]}" | sort -u)
    apt_update
    log "apt-get install ${need_pkgs[*]}"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need_pkgs[@]}" >"$work/apt-install.log" 2>&1 || {
        tail -n 20 "$work/apt-install.log" >&2
        die "apt-get install ${need_pkgs[*]} failed (log: $work/apt-install.log)"
    }
fi
for cmd in qemu-system-x86_64 candump cansend cangen canplayer cpio ip; do
    command -v "$cmd" >/dev/null 2>&1 || die "$cmd is still missing after installing packages"
done
log "host tools: $(dpkg-query -W -f='${Package} ${Version}, ' qemu-system-x86 busybox-static can-utils iproute2 cpio 2>/dev/null)"

# ---------------------------------------------------------------- kernel (downloaded, never installed on the host)
kdir=$work/kernel
if [ $refresh_kernel -eq 1 ] || [ ! -s "$kdir/vmlinuz" ] || [ ! -s "$kdir/version" ] || [ ! -s "$kdir/modules/vcan.ko" ] || [ ! -s "$kdir/modules/kvaser_pci.ko" ]; then
    rm -rf "$kdir" "$work/debs/unpacked"
    mkdir -p "$work/debs" "$kdir/modules"
    apt_update
    dl() { # download a package into $work/debs (as root, so apt's _apt sandbox warning is silenced)
        (cd "$work/debs" && apt-get -o APT::Sandbox::User=root download -qq "$1" 2>&1) ||
            die "apt-get download $1 failed: is a Debian repository with linux-image-amd64 configured?"
    }
    meta_ver=$(apt-cache policy linux-image-amd64 | awk '/Candidate:/ {print $2}')
    if [ -z "$meta_ver" ] || [ "$meta_ver" = "(none)" ]; then
        die "apt-cache knows no linux-image-amd64 (are Debian's main sources configured?)"
    fi
    # apt-get download names files package_version_arch.deb, with an epoch's ':' written as %3a
    meta_deb=$work/debs/linux-image-amd64_${meta_ver//:/%3a}_amd64.deb
    if [ ! -f "$meta_deb" ]; then
        log "apt-get download linux-image-amd64 ($meta_ver)"
        dl "linux-image-amd64=$meta_ver"
    fi
    [ -f "$meta_deb" ] || die "apt-get download linux-image-amd64=$meta_ver did not produce $meta_deb"
    # Depends: linux-image-6.1.0-56-amd64 (= 6.1.192-2)
    depends=$(dpkg-deb -f "$meta_deb" Depends)
    dep=$(printf '%s\n' "$depends" | sed 's/[,|]/\n/g' | sed 's/^ *//' | grep -E '^linux-image-[0-9][^ ]*-amd64( |$)' | head -n 1 || true)
    [ -n "$dep" ] || die "no versioned linux-image-*-amd64 in the Depends of $(basename "$meta_deb"): $depends"
    kpkg=${dep%% *}
    kver=$(printf '%s' "$dep" | sed -n 's/.*(= *\([^)]*\)).*/\1/p')
    [ -n "$kver" ] || kver=$(apt-cache policy "$kpkg" | awk '/Candidate:/ {print $2}')
    if [ -z "$kver" ] || [ "$kver" = "(none)" ]; then
        die "apt-cache knows no $kpkg (needed by linux-image-amd64 $meta_ver)"
    fi
    kdeb=$work/debs/${kpkg}_${kver//:/%3a}_amd64.deb
    if [ ! -f "$kdeb" ]; then
        log "apt-get download $kpkg=$kver"
        dl "$kpkg=$kver"
    fi
    [ -f "$kdeb" ] || die "apt-get download $kpkg=$kver did not produce $kdeb"
    log "unpacking $(basename "$kdeb") with dpkg -x"
    dpkg -x "$kdeb" "$work/debs/unpacked" || die "dpkg -x $kdeb failed"
    images=("$work/debs/unpacked/boot"/vmlinuz-*)
    [ -f "${images[0]}" ] || die "no boot/vmlinuz-* in $kdeb"
    vmlinuz=${images[0]}
    cp "$vmlinuz" "$kdir/vmlinuz"
    # The modules both suites use, decompressed on the host (busybox insmod needs plain .ko)
    for m in can can-raw can-dev vcan sja1000 kvaser_pci; do
        src=$(find "$work/debs/unpacked/lib/modules" "$work/debs/unpacked/usr/lib/modules" \
            \( -name "$m.ko" -o -name "$m.ko.xz" -o -name "$m.ko.zst" -o -name "$m.ko.gz" \) 2>/dev/null | head -1 || true)
        [ -n "$src" ] || die "module $m.ko not found in $kdeb (kernel built without CONFIG_CAN / CONFIG_CAN_VCAN / CONFIG_CAN_KVASER_PCI as modules?)"
        case $src in
            *.ko) cp "$src" "$kdir/modules/$m.ko" ;;
            *.ko.gz) gzip -dc "$src" >"$kdir/modules/$m.ko" ;;
            *.ko.xz)
                command -v xz >/dev/null || { apt_update; apt-get install -y -qq --no-install-recommends xz-utils >/dev/null || die "cannot install xz-utils"; }
                xz -dc "$src" >"$kdir/modules/$m.ko" ;;
            *.ko.zst)
                command -v zstd >/dev/null || { apt_update; apt-get install -y -qq --no-install-recommends zstd >/dev/null || die "cannot install zstd"; }
                zstd -qdc "$src" >"$kdir/modules/$m.ko" ;;
        esac
    done
    echo "$kpkg $kver ($(basename "$vmlinuz"))" >"$kdir/version"
    rm -rf "$work/debs/unpacked"
fi
log "kernel: $(cat "$kdir/version")"

# ---------------------------------------------------------------- tracerctl
if [ -z "$bin" ]; then
    log "cargo build --release --locked"
    (cd "$repo" && cargo build --release --locked) || die "cargo build --release --locked failed"
    # where cargo put it (CARGO_TARGET_DIR, or build.target-dir in a cargo config)
    tdir=$(cd "$repo" || exit 0
        cargo metadata --format-version 1 --no-deps 2>/dev/null | sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p' || true)
    bin=${tdir:-${CARGO_TARGET_DIR:-$repo/target}}/release/tracerctl
    case $bin in /*) ;; *) bin=$repo/$bin ;; esac
fi
[ -x "$bin" ] || die "no tracerctl binary at $bin"
log "tracerctl: $bin ($("$bin" --version 2>/dev/null || echo 'version unknown'))"

# ---------------------------------------------------------------- initramfs
root=$work/initramfs$sfx
rm -rf "$root"
mkdir -p "$root"/{bin,sbin,usr/bin,usr/sbin,proc,sys,dev,tmp,run,etc,lib/modules/can}
cp /bin/busybox "$root/bin/busybox"
for m in $modules; do cp "$kdir/modules/$m.ko" "$root/lib/modules/can/"; done
# the kernel opens /dev/console for init; /init reopens it from devtmpfs anyway, in case mknod is not allowed here
mknod -m 600 "$root/dev/console" c 5 1 2>/dev/null || log "mknod not permitted: /init opens the console from devtmpfs"

# copy a dynamically linked program and every library ldd lists, at the same absolute paths (loader included)
add_prog() { # $1 source path, $2 path inside the VM
    local src=$1 dst=$2 lib
    install -D -m 755 "$src" "$root$dst"
    while read -r lib; do
        [ -n "$lib" ] || continue
        [ -e "$root$lib" ] && continue
        [ -e "$lib" ] || die "ldd $src lists $lib, which does not exist"
        mkdir -p "$root$(dirname "$lib")"
        cp -L "$lib" "$root$lib"
    done < <(LC_ALL=C ldd "$src" 2>/dev/null | awk '/=>/ && $3 ~ /^\// {print $3; next} $1 ~ /^\// {print $1}')
}
if [ $self_test = 1 ]; then
    log "SELF-TEST: /usr/bin/tracerctl is tests/vm/selftest/fake-tracerctl${fake_bugs:+ with bugs: $fake_bugs}"
    add_prog "$bin" /usr/bin/tracerctl.real
    install -m 755 "$here/selftest/fake-tracerctl" "$root/usr/bin/tracerctl"
else
    add_prog "$bin" /usr/bin/tracerctl
fi
for p in candump cansend cangen canplayer; do add_prog "$(command -v $p)" "/usr/bin/$p"; done
add_prog "$(command -v ip)" /usr/sbin/ip
cp "$here/$scenario" "$root/scenario.sh"
printf 'CHECKS=%s\nFAKE_BUGS=%s\n' "$checks" "$fake_bugs" >"$root/etc/scenario.env"
echo "$modules" >"$root/etc/modules"
# the interfaces the scenario starts with
if [ "$suite" = vcan ]; then
    cat >"$root/etc/net-setup" <<'EOF'
for i in vcan0 vcan1; do
    { ip link add dev $i type vcan && ip link set up $i; } || { echo "VM SETUP FAIL: cannot create $i"; halt_vm; }
done
echo "VM: vcan0 and vcan1 up at uptime $(cut -d' ' -f1 /proc/uptime)s"
EOF
else
    # iproute2's ip by its path: busybox sh runs its own applets first, and busybox's ip knows no "type can"
    cat >"$root/etc/net-setup" <<'EOF'
for i in can0 can1 can2; do
    { /usr/sbin/ip link set $i type can bitrate 500000 && /usr/sbin/ip link set $i up; } ||
        { echo "VM SETUP FAIL: cannot set up $i at 500000 bit/s ($(/usr/sbin/ip -br link 2>&1 | tr '\n' ' '))"; halt_vm; }
done
echo "VM: can0, can1, can2 (sja1000, 500000 bit/s) up at uptime $(cut -d' ' -f1 /proc/uptime)s"
EOF
fi

cat >"$root/init" <<'EOF'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/tmp
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev 2>/dev/null
exec </dev/console >/dev/console 2>&1
mount -t tmpfs tmpfs /tmp
echo "VM: init at uptime $(cut -d' ' -f1 /proc/uptime)s, kernel $(uname -r), $(nproc) cpu"
halt_vm() { echo "VM: poweroff at uptime $(cut -d' ' -f1 /proc/uptime)s"; sync; poweroff -f; }
for m in $(cat /etc/modules); do
    insmod /lib/modules/can/$m.ko || { echo "VM SETUP FAIL: insmod $m.ko"; halt_vm; }
done
ip link set lo up
. /etc/net-setup
. /etc/scenario.env
export CHECKS FAKE_BUGS
sh /scenario.sh
echo "VM: scenario exit status $?"
# the scenario's files (captures, outputs) go to the host through the second serial port, as a tar.gz
if [ -e /dev/ttyS1 ] && stty -F /dev/ttyS1 raw -echo 2>/dev/null; then
    tar -c -C /tmp scn $(cd /tmp && ls m.log 2>/dev/null) | gzip -1 >/dev/ttyS1
    echo "VM: artifacts sent at uptime $(cut -d' ' -f1 /proc/uptime)s"
fi
halt_vm
EOF
chmod 755 "$root/init" "$root/scenario.sh"

(cd "$root" && find . -print0 | cpio --null -o -H newc --quiet | gzip -1) >"$work/initrd$sfx.gz" || die "packing the initramfs failed"
log "initramfs: $(du -h "$work/initrd$sfx.gz" | cut -f1)"

# ---------------------------------------------------------------- boot
console=$work/console$sfx.log
arts=$work/artifacts$sfx
rm -f "$arts.tar.gz"
rm -rf "$arts"
# The sja1000 suite's RS232 robot (check serial_stalled_peer): serial-robot.py listens on a Unix socket before
# the VM starts, QEMU connects to it as the chardev of a fourth 16550 UART (ttyS3); run.sh judges its log after.
robot_pid=""
robot_log=$work/robot$sfx.log
host_checks=$work/host-checks$sfx.log
rm -f "$robot_log" "$host_checks"
want_check() { [ -z "$checks" ] || case ",$checks," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }
if [ "$suite" = sja1000 ]; then
    if want_check serial_stalled_peer; then
        robot_sock=$work/robot$sfx.sock
        rm -f "$robot_sock"
        python3 "$here/serial-robot.py" serve --socket "$robot_sock" --log "$robot_log" --stall-after 50 --stall-for "${TRACERCTL_VM_SERIAL_STALL:-3}" \
            >"$work/robot$sfx.out" 2>&1 &
        robot_pid=$!
        for _ in $(seq 100); do [ -S "$robot_sock" ] && break; sleep 0.05; done
        [ -S "$robot_sock" ] || die "the RS232 robot (serial-robot.py) did not listen on $robot_sock: $(cat "$work/robot$sfx.out")"
        qemu_serial_extra+=(-chardev "socket,id=robot,path=$robot_sock" -serial chardev:robot)
    else
        qemu_serial_extra+=(-serial null)
    fi
fi
log "booting the VM ($suite suite, TCG, $smp CPU, timeout ${vm_timeout}s); console: $console"
t_vm=$(date +%s.%N)
set +e
timeout -k 10 "$vm_timeout" qemu-system-x86_64 -accel tcg -m 512 -smp "$smp" -nographic -no-reboot -nic none \
    ${qemu_devices[@]+"${qemu_devices[@]}"} \
    -serial mon:stdio -serial "file:$arts.tar.gz" ${qemu_serial_extra[@]+"${qemu_serial_extra[@]}"} \
    -kernel "$kdir/vmlinuz" -initrd "$work/initrd$sfx.gz" -append "console=ttyS0 quiet panic=-1" \
    </dev/null 2>&1 | tr -d '\r' | tee "$console"
qemu_rc=${PIPESTATUS[0]}
set -e
vm_secs=$(awk -v a="$t_vm" -v b="$(date +%s.%N)" 'BEGIN {printf "%.1f", b - a}')

# ---------------------------------------------------------------- verdict
if [ -s "$arts.tar.gz" ] && mkdir -p "$arts" &&
    tar -xzf "$arts.tar.gz" -C "$arts" 2>/dev/null; then
    log "the VM's files (captures, outputs of every check): $arts/"
fi
# checks judged on the host: the scenario ran them (a HOST-CHECK line) and left its files in the artifacts
: >"$host_checks"
if [ -n "$robot_pid" ]; then
    kill "$robot_pid" 2>/dev/null || true
    wait "$robot_pid" 2>/dev/null || true
    if grep -q '^HOST-CHECK serial_stalled_peer:' "$console"; then
        python3 "$here/serial-robot.py" judge --log "$robot_log" --vm-dir "$arts/scn" --stall-after 50 \
            >"$host_checks" 2>&1 || true
        log "serial_stalled_peer judged on the host from $robot_log and $arts/scn/ser.*"
    fi
fi
if grep -q '^HOST-CHECK mcap_session:' "$console" && [ $self_test = 1 ]; then
    echo "CHECK mcap_session: PASS not judged in the self-test (the fake writes no MCAP)" >>"$host_checks"
elif grep -q '^HOST-CHECK mcap_session:' "$console"; then
    python3 "$here/../mcap/vm_session.py" "$arts/scn" >>"$host_checks" 2>&1 || true
    log "mcap_session judged on the host from $arts/scn/session.mcap and mcap_bus.log"
fi
echo
echo "================ VM suite summary ($suite)"
grep -hE '^CHECK [a-z0-9_]+: (PASS|FAIL)' "$console" "$host_checks" || true
n_pass=$(cat "$console" "$host_checks" | grep -cE '^CHECK [a-z0-9_]+: PASS' || true)
n_fail=$(cat "$console" "$host_checks" | grep -cE '^CHECK [a-z0-9_]+: FAIL' || true)
n_host_fail=$(grep -cE '^CHECK [a-z0-9_]+: FAIL' "$host_checks" || true)
echo "checks: $n_pass passed, $n_fail failed; VM ran ${vm_secs}s (qemu exit $qemu_rc); total $(($(date +%s) - t_start))s"
grep -E '^VM: (init|poweroff)' "$console" || true

if [ "$n_fail" -gt 0 ]; then
    echo
    echo "================ failed checks and their evidence"
    awk '/^CHECK [a-z0-9_]+: FAIL/ {show = 1; print; next}
         /^CHECK |^HOST-CHECK |^SCENARIO |^== / {show = 0}
         show && /^  [|] / {print}' "$console" "$host_checks"
fi
if grep -q '^VM SETUP FAIL' "$console"; then
    die "the VM could not set up SocketCAN: $(grep '^VM SETUP FAIL' "$console" | head -1)"
fi
if grep -qx 'SCENARIO PASS' "$console" && [ "$n_host_fail" -gt 0 ]; then
    echo "VM SUITE FAIL: judged on the host: $(grep -E '^CHECK [a-z0-9_]+: FAIL' "$host_checks" | cut -d: -f1 | sed 's/^CHECK //' | tr '\n' ' ')"
    exit 1
fi
if grep -qx 'SCENARIO PASS' "$console"; then
    echo "VM SUITE PASS"
    exit 0
fi
if grep -qE '^SCENARIO FAIL' "$console"; then
    echo "VM SUITE FAIL: $(grep -E '^SCENARIO FAIL' "$console" | tail -1)"
    exit 1
fi
if [ "$qemu_rc" -eq 124 ] || [ "$qemu_rc" -eq 137 ]; then
    echo "--- last console lines:"; tail -n 30 "$console"
    die "the VM did not finish within ${vm_timeout}s (no SCENARIO marker)"
fi
echo "--- last console lines:"; tail -n 30 "$console"
die "the VM stopped without a SCENARIO marker (qemu exit status $qemu_rc)"
