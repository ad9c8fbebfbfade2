#!/usr/bin/env bash
# The arm64 suite: the static aarch64 tracerctl on an emulated ARM computer (qemu-system-aarch64, machine virt,
# Cortex-A57, TCG), where qemu-user cannot go: real termios (RS232, the dashboard's terminal) and real SocketCAN.
# Debian's arm64 kernel, busybox, can-utils and iproute2 are downloaded (apt-get download, never installed on
# the host) and packed with the binary into an initramfs; tests/vm/scenario-arm64.sh runs inside.
#
#   bash tests/vm/arm64.sh [--bin AARCH64_TRACERCTL] [--host-bin X86_TRACERCTL] [--timeout SECS]
#
# The VM has three serial lines: the console (PL011), /dev/ttyS0 (an emulated PCI 16550) to a virtual TRACER
# that the host's tracerctl serves (`sim --serial` on QEMU's pty; QEMU logs every byte the guest sends, the
# wire judged below), and /dev/ttyS1 (a second 16550) on a Unix socket where tests/vm/dashboard-keys.py types
# the operator's keys. Root on Debian 12 (it installs packages). Exit status: 0 every check passed, 1 a check
# failed, 2 usage, 3 the environment could not be set up (packages, kernel, VM).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
work=${TRACERCTL_VM_ARM64_WORK:-$repo/target/vm-arm64}
bin=""
host_bin=""
vm_timeout=900
while [ $# -gt 0 ]; do
    case $1 in
        --bin) bin=${2:?--bin needs a path}; shift 2 ;;
        --host-bin) host_bin=${2:?--host-bin needs a path}; shift 2 ;;
        --timeout) vm_timeout=${2:?--timeout needs seconds}; shift 2 ;;
        -h | --help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "arm64.sh: unknown argument: $1" >&2; exit 2 ;;
    esac
done
case $vm_timeout in '' | *[!0-9]*) echo "arm64.sh: --timeout needs whole seconds" >&2; exit 2 ;; esac

started=$(date +%s)
log() { printf '[arm64 %3ds] %s\n' "$(($(date +%s) - started))" "$*"; }
die() { printf '\nARM64 SUITE ERROR: %s\n' "$*" >&2; exit 3; }
[ "$(id -u)" -eq 0 ] || die "run as root (apt-get, and the initramfs needs device nodes)"
mkdir -p "$work"

# ---------------------------------------------------------------- host packages
need=()
for pair in qemu-system-aarch64:qemu-system-arm cpio:cpio python3:python3-minimal readelf:binutils gzip:gzip xz:xz-utils; do
    command -v "${pair%%:*}" >/dev/null 2>&1 || need+=("${pair#*:}")
done
if ((${#need[@]})); then
    apt-get update -qq || die "apt-get update failed"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null ||
        die "apt-get install ${need[*]} failed"
fi

# ---------------------------------------------------------------- arm64 packages (downloaded, unpacked, cached)
debs=$work/debs
unpacked=$work/unpacked
packages=(linux-image-arm64 busybox-static can-utils iproute2 libc6 libbpf1 libelf1 libmnl0 libbsd0 libmd0 libcap2
    zlib1g libzstd1)
if [ ! -s "$work/ready" ]; then
    rm -rf "$debs" "$unpacked"
    mkdir -p "$debs"
    if ! dpkg --print-foreign-architectures | grep -qx arm64; then
        log "dpkg --add-architecture arm64 (to download arm64 packages; nothing arm64 is installed)"
        dpkg --add-architecture arm64
    fi
    apt-get update -qq || die "apt-get update failed"
    # The metapackage names the versioned kernel package.
    kernel=$(apt-cache depends linux-image-arm64:arm64 | sed -n 's/^ *Depends: \(linux-image-[0-9][^:]*-arm64\).*/\1/p' | head -n 1)
    [ -n "$kernel" ] || die "apt-cache names no kernel package for linux-image-arm64:arm64"
    wanted=("$kernel:arm64")
    for package in "${packages[@]:1}"; do wanted+=("$package:arm64"); done
    log "apt-get download ${wanted[*]}"
    (cd "$debs" && apt-get -o APT::Sandbox::User=root download -qq "${wanted[@]}") || die "apt-get download failed"
    for deb in "$debs"/*.deb; do dpkg -x "$deb" "$unpacked" || die "dpkg -x $deb"; done
    date >"$work/ready"
fi
vmlinuz=$(find "$unpacked/boot" -name 'vmlinuz-*' | head -n 1)
[ -n "$vmlinuz" ] || die "no vmlinuz in the arm64 kernel package"

# ---------------------------------------------------------------- binaries
if [ -z "$bin" ]; then
    bin=$repo/target/aarch64-unknown-linux-musl/release/tracerctl
    log "cargo build --release --locked --target aarch64-unknown-linux-musl"
    (cd "$repo" && cargo build --release --locked --quiet --target aarch64-unknown-linux-musl) || die "build failed"
fi
if [ -z "$host_bin" ]; then
    host_bin=$repo/target/release/tracerctl
    log "cargo build --release --locked (the host's virtual TRACER and the wire's decoder)"
    (cd "$repo" && cargo build --release --locked --quiet) || die "host build failed"
fi
[ -x "$bin" ] && [ -x "$host_bin" ] || die "missing binary: $bin or $host_bin"
file -b "$bin" | grep -q 'ARM aarch64' || die "$bin is not an aarch64 binary: $(file -b "$bin")"

# ---------------------------------------------------------------- initramfs
initramfs=$work/initramfs
rm -rf "$initramfs"
mkdir -p "$initramfs"/{bin,usr/bin,lib/modules,proc,sys,dev,tmp}
cp "$unpacked/bin/busybox" "$initramfs/bin/"
cp "$unpacked/bin/ip" "$initramfs/bin/ip"
for tool in candump cansend; do cp "$unpacked/usr/bin/$tool" "$initramfs/usr/bin/"; done
cp "$bin" "$initramfs/bin/tracerctl"
# The libraries of ip and can-utils (the loader included), at the paths they are looked up at.
for dir in lib/aarch64-linux-gnu usr/lib/aarch64-linux-gnu; do
    mkdir -p "$initramfs/$dir"
    cp -a "$unpacked/$dir/." "$initramfs/$dir/"
done
cp -a "$unpacked/lib/ld-linux-aarch64.so.1" "$initramfs/lib/" 2>/dev/null || true
for dependent in bin/ip usr/bin/candump; do
    for needed in $(readelf -d "$initramfs/$dependent" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p'); do
        [ -n "$(find "$initramfs" -name "$needed" | head -n 1)" ] || die "$dependent needs $needed, not in the packages"
    done
done
for module in can can-raw can-dev vcan; do
    source=$(find "$unpacked/lib/modules" "$unpacked/usr/lib/modules" -name "$module.ko*" 2>/dev/null | head -n 1 || true)
    [ -n "$source" ] || die "module $module not in the arm64 kernel package"
    case $source in
        *.ko) cp "$source" "$initramfs/lib/modules/$module.ko" ;;
        *.ko.xz) xz -dc "$source" >"$initramfs/lib/modules/$module.ko" ;;
        *.ko.zst) zstd -qdc "$source" >"$initramfs/lib/modules/$module.ko" ;;
        *.ko.gz) gzip -dc "$source" >"$initramfs/lib/modules/$module.ko" ;;
    esac
done
cp "$here/scenario-arm64.sh" "$initramfs/scenario.sh"
cat >"$initramfs/init" <<'EOF'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin:/usr/bin:/sbin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
mount -t tmpfs tmp /tmp
for module in can can-raw can-dev vcan; do insmod /lib/modules/$module.ko || echo "insmod $module failed"; done
ip link add dev vcan0 type vcan && ip link set up vcan0
echo "SCENARIO BEGIN"
sh /scenario.sh
echo "SCENARIO DONE"
poweroff -f
EOF
chmod 755 "$initramfs/init" "$initramfs/scenario.sh"
(cd "$initramfs" && find . | cpio -H newc -o --quiet | gzip -1 >"$work/initramfs.cpio.gz")
log "initramfs: $(du -h "$work/initramfs.cpio.gz" | cut -f1) (tracerctl $(stat -c %s "$bin") bytes)"

# ---------------------------------------------------------------- boot
console=$work/console.log
wire=$work/rs232-wire.bin
dash_sock=$work/dashboard.sock
rm -f "$console" "$wire" "$dash_sock" "$work/qemu.err" "$work/screen.bin"
pids=()
cleanup() { for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done; }
trap cleanup EXIT

log "qemu-system-aarch64 -M virt -cpu cortex-a57 (TCG), $(basename "$vmlinuz")"
timeout "$vm_timeout" qemu-system-aarch64 -M virt -cpu cortex-a57 -accel tcg -m 512 -smp 1 -nographic -no-reboot \
    -nic none -kernel "$vmlinuz" -initrd "$work/initramfs.cpio.gz" \
    -append "console=ttyAMA0 quiet panic=-1" \
    -chardev "pty,id=rs232,logfile=$wire" -device "pci-serial,chardev=rs232" \
    -chardev "socket,id=dash,path=$dash_sock,server=on,wait=off" -device "pci-serial,chardev=dash" \
    </dev/null >"$console" 2>"$work/qemu.err" &
qemu=$!
pids+=("$qemu")

# QEMU names the pty it made for the RS232 line; the host's virtual TRACER serves on it.
for _ in $(seq 100); do
    pty=$(sed -n 's/.*char device redirected to \(\/dev\/pts\/[0-9]*\) (label rs232).*/\1/p' "$console" "$work/qemu.err" | head -n 1)
    [ -n "$pty" ] && break
    sleep 0.1
done
[ -n "${pty:-}" ] || die "QEMU did not say which pty it made: $(cat "$work/qemu.err")"
"$host_bin" sim --serial "$pty" >"$work/host-sim.log" 2>&1 &
pids+=("$!")
python3 "$here/dashboard-keys.py" --socket "$dash_sock" --screen "$work/screen.bin" >"$work/keys.log" 2>&1 &
pids+=("$!")

tail -n +1 -f "$console" --pid "$qemu" | grep --line-buffered -E '^(CHECK|  \||SCENARIO|DASHBOARD|SERIAL)' || true
wait "$qemu" || true
grep -q 'SCENARIO DONE' "$console" || die "the VM did not finish the scenario (console: $console; $(tail -n 5 "$console"))"

# ---------------------------------------------------------------- the RS232 wire, judged here
# What the guest's UART sent during `drive --linear 0.2 --for 1s`: motion commands at 0.2 m/s, the last zero.
"$host_bin" decode --format json --serial "$wire" >"$work/wire.jsonl" 2>"$work/wire.err" || true
wire_status=0
python3 - "$work/wire.jsonl" "$wire" >"$work/wire.check" <<'EOF' || wire_status=$?
import json, sys
speeds = []
for line in open(sys.argv[1]):
    record = json.loads(line)
    if record.get("msg") == "motion_command":
        speeds.append(record["fields"]["linear_velocity"])
# RS232 carries whole percent of 1.5 m/s: 0.2 m/s is 13 %, 0.195 m/s
moving = sum(1 for s in speeds if abs(s - 0.195) < 1e-9)
# doctor and monitor send no motion; the drive's frames are the moving ones and the zeros around them
ok = moving >= 20 and speeds and speeds[-1] == 0.0
print(f"CHECK serial_drive_wire: {'PASS' if ok else 'FAIL'} {len(speeds)} motion frames on the UART's wire, "
      f"{moving} at 0.195 m/s (13 %), the last at {speeds[-1] if speeds else 'none'} m/s")
# doctor and monitor ran first on this line: watching, they send no frame; every frame on the wire is the
# drive's. The bytes that are no frame at all are the kernel's echo of what the robot sent before the first
# open put the port in raw mode (ECHO is on by default; the flush after open cannot catch it here, where the
# emulated UART sends at once): counted in the evidence, not frames the robot would take.
others = [r["msg"] for r in map(json.loads, open(sys.argv[1])) if r.get("msg") != "motion_command"]
data = open(sys.argv[2], "rb").read()
frames = len(speeds) * 13
quiet = not others
print(f"CHECK serial_watch_sent_nothing: {'PASS' if quiet else 'FAIL'} frames other than the drive's: "
      f"{sorted(set(others)) or 'none'}; {len(data)} bytes, {frames} in the drive's motion frames, "
      f"{len(data) - frames} echoed by the kernel before raw mode")
sys.exit(0 if ok and quiet else 1)
EOF
cat "$work/wire.check"
[ $wire_status = 0 ] || sed 's/^/  | /' "$work/wire.err" | head -n 10

log "VM and checks done"
if grep -q '^SCENARIO PASS' "$console" && [ $wire_status = 0 ]; then
    echo "ARM64 SUITE PASS ($(grep -c '^CHECK' "$console") checks in the VM, serial_drive_wire on the host)"
    exit 0
fi
echo "ARM64 SUITE FAIL: $(grep '^CHECK.*: FAIL' "$console" "$work/wire.check" | sed 's/: FAIL.*//; s/.*CHECK //' | tr '\n' ' ')" >&2
exit 1
