#!/usr/bin/env bash
# Real SocketCAN tests for tracerctl in a tiny QEMU VM (the host kernel may have no CAN at all).
# Four suites: vcan (the default: scenario.sh on vcan0/vcan1), sja1000 (scenario-sja1000.sh on three emulated
# Kvaser PCI boards, SJA1000 controllers driven by the kernel's real sja1000/kvaser_pci drivers) and arm64
# (scenario-arm64.sh: the aarch64 build on an emulated ARM computer, qemu-system-aarch64 with Debian's arm64
# kernel: vcan, RS232 over an emulated 16550 UART to the host's simulator, the dashboard on a virtio console),
# powercut (scenario-powercut.sh: the recorder on an ext4 disk, the VM ended mid-recording by QEMU's `quit`),
# commission (scenario.sh's commission abort matrix alone, on vcan with two CPUs).
#
# Run as root on Debian 12 (CI, or a developer machine):
#     bash tests/vm/run.sh [--suite sja1000|arm64|powercut|commission] [options]
# See tests/vm/README.md for what it does and what each check proves.
set -euo pipefail

usage() {
    cat <<'EOF'
Usage: tests/vm/run.sh [options]

  --suite NAME      vcan (default: scenario.sh on vcan0, vcan1), sja1000 (scenario-sja1000.sh on can0-can2,
                    emulated SJA1000 controllers with the kernel's sja1000/kvaser_pci drivers; two CPUs),
                    arm64 (scenario-arm64.sh: the aarch64 musl build in qemu-system-aarch64, Debian's arm64
                    kernel; vcan, RS232 on an emulated 16550 to the host's simulator, the dashboard on a tty),
                    powercut (scenario-powercut.sh: the recorder on an ext4 virtio disk, the VM ended by
                    the QEMU monitor's quit mid-recording; the disk judged on the host by powercut-judge.sh)
                    or commission (scenario.sh's commission abort matrix alone, on vcan; two CPUs)
                    (also: TRACERCTL_VM_SUITE)
  --bin PATH        use this tracerctl binary instead of building one (also: TRACERCTL_BIN); arm64: a static
                    aarch64 build (default: cargo build --release --locked --target aarch64-unknown-linux-musl)
  --host-bin PATH   (arm64) the host's tracerctl, which runs the RS232 simulator (default: cargo build
                    --release --locked; also: TRACERCTL_HOST_BIN)
  --work DIR        work and cache directory (default: <repo>/target/vm, <repo>/target/vm-arm64 for arm64;
                    also: TRACERCTL_VM_WORK)
  --checks LIST     run only these checks (comma-separated names, see tests/vm/README.md)
  --timeout SECS    kill the VM after this many seconds (default 600)
  --smp N           virtual CPUs (default 2 for sja1000 and commission, 1 for the others; also: TRACERCTL_VM_SMP)
  --prepare         only install the host packages and download the kernel (arm64: and the guest's
                    userland) the suite needs, then exit: nothing is built or booted (CI prepares every suite
                    in the background while it lints)
  --refresh-kernel  resolve and download the kernel package again (default: reuse the cached one); arm64: the
                    guest's busybox, can-utils and libc packages too
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
work=${TRACERCTL_VM_WORK:-}
bin=${TRACERCTL_BIN:-}
host_bin=${TRACERCTL_HOST_BIN:-}
checks=${TRACERCTL_VM_CHECKS:-}
vm_timeout=600
smp=${TRACERCTL_VM_SMP:-}
suite=${TRACERCTL_VM_SUITE:-vcan}
refresh_kernel=0
prepare=0
self_test=0
fake_bugs=""

while [ $# -gt 0 ]; do
    case $1 in
        --suite) suite=${2:?--suite needs a name: vcan, sja1000, arm64, powercut or commission}; shift 2 ;;
        --suite=*) suite=${1#--suite=}; shift ;;
        --bin) bin=${2:?--bin needs a path}; shift 2 ;;
        --host-bin) host_bin=${2:?--host-bin needs a path}; shift 2 ;;
        --work) work=${2:?--work needs a directory}; shift 2 ;;
        --checks) checks=${2:?--checks needs a list}; shift 2 ;;
        --timeout) vm_timeout=${2:?--timeout needs seconds}; shift 2 ;;
        --smp) smp=${2:?--smp needs a number}; shift 2 ;;
        --refresh-kernel) refresh_kernel=1; shift ;;
        --prepare) prepare=1; shift ;;
        --self-test) self_test=1; shift ;;
        --self-test=*) self_test=1; fake_bugs=${1#--self-test=}; shift ;;
        -h | --help) usage; exit 0 ;;
        *) echo "run.sh: unknown argument: $1" >&2; usage >&2; exit 2 ;;
    esac
done
# what differs between the suites: architecture, scenario, modules (insmod order), qemu devices, default CPUs,
# file names
arch=amd64
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
        # (a job-control shell needs a controlling terminal); ttyS3: the RS232 robot (serial_stalled_peer,
        # commission_serial_stalled), connected below when one of them runs
        qemu_serial_extra=(-serial null)
        sfx=-sja1000
        # two CPUs: a flooding sender on one outruns the receiver on the other (RX FIFO overruns)
        : "${smp:=2}"
        ;;
    commission)
        # The vcan suite's scenario for commission's abort matrix (default: CI's 13 runs; --checks
        # commission_abort_matrix_full: all 117). Two CPUs: the keys' way in (nc, telnetd, the pty) then
        # does not wait behind the simulator, candump and commission for the one CPU (scenario.sh, CM_CAUSES).
        scenario=scenario.sh
        modules="can can-raw can-dev vcan"
        qemu_devices=()
        qemu_serial_extra=()
        sfx=-commission
        : "${smp:=2}"
        : "${checks:=commission_abort_matrix}"
        ;;
    powercut)
        scenario="scenario-powercut.sh"
        # vcan, and a virtio disk with ext4 (the modules in the order insmod needs them)
        modules="can can-raw can-dev vcan virtio_ring virtio virtio_pci_legacy_dev virtio_pci_modern_dev virtio_pci
            virtio_blk crc16 mbcache jbd2 crc32c_generic ext4"
        # the disk (made below with mkfs.ext4), the monitor the host sends `quit` to, and ttyS2: the witness
        # (candump -L vcan0 in the VM) streamed to a host file, outside what the cut can lose
        qemu_devices=()
        qemu_serial_extra=()
        sfx=-powercut
        : "${smp:=1}"
        ;;
    arm64)
        arch=arm64
        scenario="scenario-arm64.sh"
        # virtio_mmio, virtio_console: the virtio serial ports (the dashboard's terminal, markers, artifacts)
        modules="can can-raw can-dev vcan virtio_mmio virtio_console"
        qemu_devices=()
        qemu_serial_extra=()
        sfx=-arm64
        : "${smp:=1}"
        ;;
    *) echo "run.sh: --suite takes vcan, sja1000, arm64, powercut or commission, not '$suite'" >&2; exit 2 ;;
esac
if [ -z "$work" ]; then
    if [ $arch = arm64 ]; then work=$repo/target/vm-arm64; else work=$repo/target/vm; fi
fi
if [ -n "$host_bin" ] && [ $arch != arm64 ]; then
    echo "run.sh: --host-bin is for the arm64 suite only" >&2
    exit 2
fi
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
if [ $arch = amd64 ]; then
    host_cmds="qemu-system-x86_64:qemu-system-x86 candump:can-utils cansend:can-utils cangen:can-utils
        canplayer:can-utils cpio:cpio ip:iproute2 gzip:gzip ldd:libc-bin dpkg-deb:dpkg zstd:zstd"
    # the power-cut suite makes the VM's disk (mkfs.ext4), reads it after the cut (e2fsck replays the journal as
    # a mount would, debugfs copies the files out) and sends the monitor's quit (python3)
    if [ "$suite" = powercut ]; then host_cmds="$host_cmds mkfs.ext4:e2fsprogs debugfs:e2fsprogs python3:python3-minimal"; fi
else
    # the guest's programs come from arm64 packages (downloaded, never installed); readelf lists their libraries
    # (ldd cannot run foreign binaries); python3 runs the host side (arm64-host.py)
    host_cmds="qemu-system-aarch64:qemu-system-arm cpio:cpio gzip:gzip dpkg-deb:dpkg python3:python3-minimal
        aarch64-linux-gnu-readelf:binutils-aarch64-linux-gnu"
fi
for pair in $host_cmds; do
    cmd=${pair%%:*}
    command -v "$cmd" >/dev/null 2>&1 || need_pkgs+=("${pair#*:}")
done
# the sja1000 suite's RS232 robot (serial-robot.py) runs on the host
if [ "$suite" = sja1000 ]; then command -v python3 >/dev/null 2>&1 || need_pkgs+=(python3-minimal); fi
# a dynamic busybox (package "busybox") would not run in the VM without its libraries: insist on the static one
if [ $arch = amd64 ] && { [ ! -x /bin/busybox ] || LC_ALL=C ldd /bin/busybox 2>&1 | grep -q '=>'; }; then
    need_pkgs+=(busybox-static)
fi

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
for pair in $host_cmds; do
    command -v "${pair%%:*}" >/dev/null 2>&1 || die "${pair%%:*} is still missing after installing packages"
done
if [ $arch = amd64 ]; then
    log "host tools: $(dpkg-query -W -f='${Package} ${Version}, ' qemu-system-x86 busybox-static can-utils iproute2 cpio zstd 2>/dev/null)"
else
    log "host tools: $(dpkg-query -W -f='${Package} ${Version}, ' qemu-system-arm binutils-aarch64-linux-gnu cpio python3-minimal 2>/dev/null)"
fi

# package downloads (never installed): into $work/debs, as root so apt's _apt sandbox warning is silenced
dl() {
    (cd "$work/debs" && apt-get -o APT::Sandbox::User=root download -qq "$1" 2>&1) ||
        die "apt-get download $1 failed: is a Debian repository with $1 configured?"
}
# candidate PKG: the version apt would take ("" if none)
candidate() {
    local v
    v=$(apt-cache policy "$1" 2>/dev/null | awk '/Candidate:/ {print $2}')
    [ "$v" = "(none)" ] && v=""
    printf '%s' "$v"
}
# the arm64 suite's packages are Debian's arm64 builds: dpkg must know the architecture, and apt its lists
pq="" # the package qualifier for apt: "" or ":arm64"
if [ $arch = arm64 ]; then pq=":arm64"; fi
foreign_arch() {
    [ $arch = arm64 ] || return 0
    if ! dpkg --print-foreign-architectures | grep -qx arm64; then
        log "dpkg --add-architecture arm64 (for apt-get download of arm64 packages; nothing arm64 is installed)"
        dpkg --add-architecture arm64 || die "dpkg --add-architecture arm64 failed"
        apt_updated=0
    fi
    [ -n "$(candidate busybox-static:arm64)" ] || apt_update
    [ -n "$(candidate busybox-static:arm64)" ] || die "apt knows no arm64 packages even after apt-get update (does the mirror carry arm64?)"
}

# ---------------------------------------------------------------- kernel (downloaded, never installed on the host)
if [ $arch = amd64 ]; then
    kdir=$work/kernel
    # the x86 suites' modules
    kmods="can can-raw can-dev vcan sja1000 kvaser_pci virtio_ring virtio virtio_pci_legacy_dev virtio_pci_modern_dev
        virtio_pci virtio_blk crc16 mbcache jbd2 crc32c_generic ext4"
else
    kdir=$work/kernel-arm64
    kmods="can can-raw can-dev vcan virtio_mmio virtio_console"
fi
kernel_cached() {
    [ -s "$kdir/vmlinuz" ] && [ -s "$kdir/version" ] || return 1
    for m in $kmods; do [ -s "$kdir/modules/$m.ko" ] || return 1; done
}
if [ $refresh_kernel -eq 1 ] || ! kernel_cached; then
    unpacked=$work/debs/unpacked-$arch
    rm -rf "$kdir" "$unpacked"
    mkdir -p "$work/debs" "$kdir/modules"
    foreign_arch
    apt_update
    meta_ver=$(candidate "linux-image-$arch$pq")
    [ -n "$meta_ver" ] || die "apt-cache knows no linux-image-$arch$pq (are Debian's main sources configured?)"
    # apt-get download names files package_version_arch.deb, with an epoch's ':' written as %3a
    meta_deb=$work/debs/linux-image-${arch}_${meta_ver//:/%3a}_${arch}.deb
    if [ ! -f "$meta_deb" ]; then
        log "apt-get download linux-image-$arch$pq ($meta_ver)"
        dl "linux-image-$arch$pq=$meta_ver"
    fi
    [ -f "$meta_deb" ] || die "apt-get download linux-image-$arch$pq=$meta_ver did not produce $meta_deb"
    # Depends: linux-image-6.1.0-56-amd64 (= 6.1.192-2)
    depends=$(dpkg-deb -f "$meta_deb" Depends)
    dep=$(printf '%s\n' "$depends" | sed 's/[,|]/\n/g' | sed 's/^ *//' | grep -E "^linux-image-[0-9][^ ]*-$arch( |\$)" | head -n 1 || true)
    [ -n "$dep" ] || die "no versioned linux-image-*-$arch in the Depends of $(basename "$meta_deb"): $depends"
    kpkg=${dep%% *}
    kver=$(printf '%s' "$dep" | sed -n 's/.*(= *\([^)]*\)).*/\1/p')
    [ -n "$kver" ] || kver=$(candidate "$kpkg$pq")
    [ -n "$kver" ] || die "apt-cache knows no $kpkg$pq (needed by linux-image-$arch $meta_ver)"
    kdeb=$work/debs/${kpkg}_${kver//:/%3a}_${arch}.deb
    if [ ! -f "$kdeb" ]; then
        log "apt-get download $kpkg$pq=$kver"
        dl "$kpkg$pq=$kver"
    fi
    [ -f "$kdeb" ] || die "apt-get download $kpkg$pq=$kver did not produce $kdeb"
    log "unpacking $(basename "$kdeb") with dpkg -x"
    dpkg -x "$kdeb" "$unpacked" || die "dpkg -x $kdeb failed"
    images=("$unpacked/boot"/vmlinuz-*)
    [ -f "${images[0]}" ] || die "no boot/vmlinuz-* in $kdeb"
    vmlinuz=${images[0]}
    cp "$vmlinuz" "$kdir/vmlinuz"
    # The modules the suites use, decompressed on the host (busybox insmod needs plain .ko)
    for m in $kmods; do
        src=$(find "$unpacked/lib/modules" "$unpacked/usr/lib/modules" \
            \( -name "$m.ko" -o -name "$m.ko.xz" -o -name "$m.ko.zst" -o -name "$m.ko.gz" \) 2>/dev/null | head -1 || true)
        [ -n "$src" ] || die "module $m.ko not found in $kdeb (kernel built without CONFIG_CAN / CONFIG_CAN_VCAN / CONFIG_CAN_KVASER_PCI / CONFIG_VIRTIO_CONSOLE as modules?)"
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
    rm -rf "$unpacked"
fi
log "kernel: $(cat "$kdir/version")"

# ---------------------------------------------------------------- the arm64 guest's userland (downloaded, unpacked)
# busybox (static), can-utils (dynamic) and the C library it needs, from Debian's arm64 packages
ul_pkgs="busybox-static can-utils libc6"
uld=$work/userland-arm64
if [ $arch = arm64 ]; then
    if [ $refresh_kernel -eq 1 ] || [ ! -s "$uld/versions" ] || [ ! -x "$uld/bin/busybox" ] || [ ! -x "$uld/usr/bin/candump" ]; then
        rm -rf "$uld"
        mkdir -p "$work/debs" "$uld"
        foreign_arch
        apt_update
        : >"$work/debs/userland-versions"
        for p in $ul_pkgs; do
            v=$(candidate "$p:arm64")
            [ -n "$v" ] || die "apt-cache knows no $p:arm64"
            deb=$work/debs/${p}_${v//:/%3a}_arm64.deb
            if [ ! -f "$deb" ]; then
                log "apt-get download $p:arm64=$v"
                dl "$p:arm64=$v"
            fi
            [ -f "$deb" ] || die "apt-get download $p:arm64=$v did not produce $deb"
            dpkg -x "$deb" "$uld" || die "dpkg -x $deb failed"
            echo "$p:arm64 $v" >>"$work/debs/userland-versions"
        done
        mv "$work/debs/userland-versions" "$uld/versions"
    fi
    log "arm64 userland: $(tr '\n' ' ' <"$uld/versions")"
fi
if [ $prepare = 1 ]; then
    log "prepared: the $suite suite's packages, kernel$([ $arch = arm64 ] && echo ' and userland')"
    exit 0
fi

# ---------------------------------------------------------------- tracerctl
# where cargo puts its builds (CARGO_TARGET_DIR, or build.target-dir in a cargo config)
target_dir() {
    local tdir
    tdir=$(cd "$repo" || exit 0
        cargo metadata --format-version 1 --no-deps 2>/dev/null | sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p' || true)
    tdir=${tdir:-${CARGO_TARGET_DIR:-$repo/target}}
    case $tdir in /*) ;; *) tdir=$repo/$tdir ;; esac
    printf '%s' "$tdir"
}
host_build() { # the release build for this machine (the x86 suites' binary, the arm64 suite's simulator): $built
    log "cargo build --release --locked"
    (cd "$repo" && cargo build --release --locked) || die "cargo build --release --locked failed"
    built=$(target_dir)/release/tracerctl
}
if [ -z "$bin" ] && [ $arch = amd64 ]; then
    host_build
    bin=$built
elif [ -z "$bin" ]; then
    # the cross build for the ARM computers: a static musl binary (.cargo/config.toml names the linker)
    if ! command -v aarch64-linux-gnu-gcc >/dev/null 2>&1; then
        apt_update
        log "apt-get install gcc-aarch64-linux-gnu (the linker of the aarch64 build)"
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends gcc-aarch64-linux-gnu libc6-dev-arm64-cross \
            >"$work/apt-install.log" 2>&1 || die "apt-get install gcc-aarch64-linux-gnu failed (log: $work/apt-install.log)"
    fi
    if command -v rustup >/dev/null 2>&1 && ! rustup target list --installed 2>/dev/null | grep -qx aarch64-unknown-linux-musl; then
        log "rustup target add aarch64-unknown-linux-musl"
        rustup target add aarch64-unknown-linux-musl || die "rustup target add aarch64-unknown-linux-musl failed"
    fi
    log "cargo build --release --locked --target aarch64-unknown-linux-musl"
    (cd "$repo" && cargo build --release --locked --target aarch64-unknown-linux-musl) ||
        die "cargo build --release --locked --target aarch64-unknown-linux-musl failed"
    bin=$(target_dir)/aarch64-unknown-linux-musl/release/tracerctl
fi
[ -x "$bin" ] || die "no tracerctl binary at $bin"
if [ $arch = amd64 ]; then
    log "tracerctl: $bin ($("$bin" --version 2>/dev/null || echo 'version unknown'))"
else
    # the guest has no C library for it: it must be an aarch64 binary without a program interpreter
    machine=$(LC_ALL=C aarch64-linux-gnu-readelf -h "$bin" 2>/dev/null | awk -F: '/Machine:/ {gsub(/^ +/, "", $2); print $2}')
    [ "$machine" = AArch64 ] || die "$bin is not an aarch64 binary (readelf: Machine '${machine:-not an ELF file}')"
    if LC_ALL=C aarch64-linux-gnu-readelf -l "$bin" 2>/dev/null | grep -q 'Requesting program interpreter'; then
        die "$bin is dynamically linked: the arm64 suite needs a static build (--target aarch64-unknown-linux-musl)"
    fi
    if [ -z "$host_bin" ]; then
        host_build
        host_bin=$built
    fi
    [ -x "$host_bin" ] || die "no host tracerctl binary at $host_bin (--host-bin)"
    log "tracerctl (aarch64, static): $bin; the host's simulator: $host_bin ($("$host_bin" --version 2>/dev/null || echo 'version unknown'))"
fi

# ---------------------------------------------------------------- initramfs
root=$work/initramfs$sfx
rm -rf "$root"
mkdir -p "$root"/{bin,sbin,usr/bin,usr/sbin,proc,sys,dev,tmp,run,etc,lib/modules/can}
if [ $arch = amd64 ]; then cp /bin/busybox "$root/bin/busybox"; else cp "$uld/bin/busybox" "$root/bin/busybox"; fi
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
# arm64: the same from the unpacked arm64 packages ($uld), with the libraries their ELF headers name (NEEDED,
# recursively) and the program interpreter, looked up in the multiarch directories; symlinks resolved inside $uld
ul_copy() { # $1 absolute path inside the VM (and inside $uld)
    local p=$1 src=$uld$1 t n=0
    [ -e "$root$p" ] && return 0
    while [ -L "$src" ] && [ $n -lt 20 ]; do
        t=$(readlink "$src")
        case $t in /*) src=$uld$t ;; *) src=$(dirname "$src")/$t ;; esac
        n=$((n + 1))
    done
    [ -f "$src" ] || die "$p is not in the arm64 packages unpacked in $uld"
    install -D -m 755 "$src" "$root$p"
}
add_prog_arm64() { # $1 path inside $uld and inside the VM
    local p=$1 interp lib d found
    ul_copy "$p"
    interp=$(LC_ALL=C aarch64-linux-gnu-readelf -l "$uld$p" | sed -n 's/.*Requesting program interpreter: \(.*\)]/\1/p')
    [ -z "$interp" ] || ul_copy "$interp"
    for lib in $(LC_ALL=C aarch64-linux-gnu-readelf -d "$uld$p" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
        found=""
        for d in /lib/aarch64-linux-gnu /usr/lib/aarch64-linux-gnu /lib /usr/lib; do
            if [ -e "$uld$d/$lib" ]; then found=$d/$lib; break; fi
        done
        [ -n "$found" ] || die "$p needs $lib, which is in none of the arm64 packages ($ul_pkgs)"
        [ -e "$root$found" ] || add_prog_arm64 "$found"
    done
}
if [ $arch = arm64 ]; then
    install -D -m 755 "$bin" "$root/usr/bin/tracerctl"
    for p in candump cansend cangen; do add_prog_arm64 "/usr/bin/$p"; done
elif [ $self_test = 1 ]; then
    log "SELF-TEST: /usr/bin/tracerctl is tests/vm/selftest/fake-tracerctl${fake_bugs:+ with bugs: $fake_bugs}"
    add_prog "$bin" /usr/bin/tracerctl.real
    install -m 755 "$here/selftest/fake-tracerctl" "$root/usr/bin/tracerctl"
else
    add_prog "$bin" /usr/bin/tracerctl
fi
if [ $arch = amd64 ]; then
    for p in candump cansend cangen canplayer; do add_prog "$(command -v $p)" "/usr/bin/$p"; done
    add_prog "$(command -v ip)" /usr/sbin/ip
    # the recorder's ring segments are zstd files: the record_* checks read them with zstd itself
    add_prog "$(command -v zstd)" /usr/bin/zstd
fi
cp "$here/$scenario" "$root/scenario.sh"
printf 'CHECKS=%s\nFAKE_BUGS=%s\n' "$checks" "$fake_bugs" >"$root/etc/scenario.env"
echo "$modules" >"$root/etc/modules"
# the interfaces the scenario starts with
if [ "$suite" = vcan ] || [ "$suite" = commission ] || [ "$suite" = powercut ]; then
    cat >"$root/etc/net-setup" <<'EOF'
for i in vcan0 vcan1; do
    { ip link add dev $i type vcan && ip link set up $i; } || { echo "VM SETUP FAIL: cannot create $i"; halt_vm; }
done
echo "VM: vcan0 and vcan1 up at uptime $(cut -d' ' -f1 /proc/uptime)s"
EOF
elif [ "$suite" = arm64 ]; then
    # busybox's ip creates the vcan link (no iproute2 in this guest); the virtio ports appear asynchronously
    cat >"$root/etc/net-setup" <<'EOF'
{ ip link add name vcan0 type vcan && ip link set up vcan0; } || { echo "VM SETUP FAIL: cannot create vcan0"; halt_vm; }
i=0
while [ $i -lt 200 ]; do
    n=$(cat /sys/class/virtio-ports/*/name 2>/dev/null | grep -cxE 'term|tty|marks|artifacts')
    [ "$n" = 4 ] && break
    usleep 50000
    i=$((i + 1))
done
[ "$n" = 4 ] || { echo "VM SETUP FAIL: the virtio ports term, tty, marks, artifacts did not all appear ($(cat /sys/class/virtio-ports/*/name 2>/dev/null | tr '\n' ' '))"; halt_vm; }
echo "VM: vcan0 up, virtio ports $(for p in /sys/class/virtio-ports/*; do printf '%s=%s ' "$(cat $p/name)" "${p##*/}"; done)at uptime $(cut -d' ' -f1 /proc/uptime)s"
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
echo "VM: init at uptime $(cut -d' ' -f1 /proc/uptime)s, kernel $(uname -r) $(uname -m), $(nproc) cpu"
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
# the scenario's files (captures, outputs) go to the host as a tar.gz, through a port of their own: the virtio
# serial port named "artifacts" (arm64), else the second serial port (x86)
arts=""
for p in /sys/class/virtio-ports/*; do [ "$(cat $p/name 2>/dev/null)" = artifacts ] && arts=/dev/${p##*/}; done
if [ -z "$arts" ] && [ -e /dev/ttyS1 ] && stty -F /dev/ttyS1 raw -echo 2>/dev/null; then arts=/dev/ttyS1; fi
if [ -n "$arts" ]; then
    tar -c -C /tmp scn $(cd /tmp && ls m.log 2>/dev/null) | gzip -1 >$arts
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
# The sja1000 suite's RS232 robot (checks serial_stalled_peer, commission_serial_stalled): serial-robot.py listens on a Unix socket before
# the VM starts, QEMU connects to it as the chardev of a fourth 16550 UART (ttyS3); run.sh judges its log after.
robot_pid=""
robot_log=$work/robot$sfx.log
host_checks=$work/host-checks$sfx.log
rm -f "$robot_log" "$host_checks"
want_check() { [ -z "$checks" ] || case ",$checks," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }
if [ "$suite" = sja1000 ]; then
    if want_check serial_stalled_peer || want_check commission_serial_stalled; then
        robot_sock=$work/robot$sfx.sock
        rm -f "$robot_sock"
        # commission_serial_stalled: sessions of their own (the scenario starts them), stalling 30 moving frames
        # into each moving step of `commission --max-linear 0.6` for 1.5 s (the stop frames get 2 s to leave)
        python3 "$here/serial-robot.py" serve --socket "$robot_sock" --log "$robot_log" --stall-after 50 --stall-for "${TRACERCTL_VM_SERIAL_STALL:-3}" \
            --commission-stall-for "${TRACERCTL_VM_COMMISSION_STALL:-1.5}" \
            >"$work/robot$sfx.out" 2>&1 &
        robot_pid=$!
        for _ in $(seq 100); do [ -S "$robot_sock" ] && break; sleep 0.05; done
        [ -S "$robot_sock" ] || die "the RS232 robot (serial-robot.py) did not listen on $robot_sock: $(cat "$work/robot$sfx.out")"
        qemu_serial_extra+=(-chardev "socket,id=robot,path=$robot_sock" -serial chardev:robot)
    else
        qemu_serial_extra+=(-serial null)
    fi
fi
# The arm64 suite's host side (arm64-host.py serve): the x86 simulator on a pseudo-terminal behind the guest's
# PCI 16550 (ttyS0), the two ends of the dashboard's terminal (virtio consoles hvc0, hvc1), the markers' port;
# Unix sockets in a short directory of their own (a socket path has at most 107 bytes), removed at exit.
helper_pid=""
host_log=$work/host$sfx.log
if [ "$suite" = arm64 ]; then
    sockdir=$(mktemp -d /tmp/tracerctl-vm.XXXXXX)
    trap 'if [ -n "$helper_pid" ]; then kill "$helper_pid" 2>/dev/null || true; fi; rm -rf "$sockdir"' EXIT
    rm -f "$host_log"
    python3 "$here/arm64-host.py" serve --dir "$sockdir" --log "$host_log" --sim-bin "$host_bin" \
        --sim-out "$work/sim-host$sfx.log" >"$work/host$sfx.out" 2>&1 &
    helper_pid=$!
    for _ in $(seq 100); do [ -s "$sockdir/ready" ] && break; sleep 0.05; done
    [ -s "$sockdir/ready" ] || die "the host side (arm64-host.py serve) did not start: $(cat "$work/host$sfx.out")"
    log "host side: $host_bin sim --serial $(cat "$sockdir/ready") behind the guest's ttyS0; log $host_log"
    qemu=(qemu-system-aarch64 -M virt -cpu cortex-a57 -accel tcg -m 512 -smp "$smp" -nographic -no-reboot -nic none
        -serial mon:stdio
        -chardev "socket,id=rs232,path=$sockdir/rs232.sock" -device "pci-serial,chardev=rs232"
        -device virtio-serial-device
        -chardev "socket,id=term,path=$sockdir/term.sock" -device "virtconsole,chardev=term,name=term"
        -chardev "socket,id=tty,path=$sockdir/tty.sock" -device "virtconsole,chardev=tty,name=tty"
        -chardev "socket,id=marks,path=$sockdir/marks.sock" -device "virtserialport,chardev=marks,name=marks"
        -chardev "file,id=arts,path=$arts.tar.gz" -device "virtserialport,chardev=arts,name=artifacts"
        -kernel "$kdir/vmlinuz" -initrd "$work/initrd$sfx.gz" -append "console=ttyAMA0 quiet panic=-1")
else
    # The power-cut suite: an ext4 disk made here, the monitor the cut is sent to, the witness's port (ttyS2), and
    # a watcher that sends `quit` once the scenario says "POWERCUT NOW" (0-1 s later, at a random moment)
    cut_pid=""
    if [ "$suite" = powercut ]; then
        disk=$work/disk$sfx.img
        monitor=$work/monitor$sfx.sock
        witness=$work/witness$sfx.log
        cut_log=$work/cut$sfx.log
        rm -f "$disk" "$monitor" "$witness" "$cut_log"
        truncate -s 64M "$disk"
        mkfs.ext4 -q -F -L tracerctl-rec "$disk" || die "mkfs.ext4 $disk failed"
        qemu_devices+=(-drive "file=$disk,format=raw,if=virtio,cache=writeback" -monitor "unix:$monitor,server=on,wait=off")
        qemu_serial_extra+=(-serial "file:$witness")
        (
            : >"$console"
            until grep -q '^POWERCUT NOW' "$console" 2>/dev/null; do sleep 0.1; done
            sleep "0.$((RANDOM % 10))$((RANDOM % 10))"
            echo "quit sent at $(date -u +%H:%M:%S.%N) (host clock)" >"$cut_log"
            python3 -c 'import socket, sys, time
s = socket.socket(socket.AF_UNIX)
s.connect(sys.argv[1])
s.sendall(b"quit\n")
time.sleep(2)' "$monitor" >>"$cut_log" 2>&1
        ) &
        cut_pid=$!
    fi
    qemu=(qemu-system-x86_64 -accel tcg -m 512 -smp "$smp" -nographic -no-reboot -nic none
        ${qemu_devices[@]+"${qemu_devices[@]}"}
        -serial mon:stdio -serial "file:$arts.tar.gz" ${qemu_serial_extra[@]+"${qemu_serial_extra[@]}"}
        -kernel "$kdir/vmlinuz" -initrd "$work/initrd$sfx.gz" -append "console=ttyS0 quiet panic=-1")
fi
log "booting the VM ($suite suite, ${qemu[0]}, TCG, $smp CPU, timeout ${vm_timeout}s); console: $console"
t_vm=$(date +%s.%N)
set +e
# line by line (tr's output to a pipe is block-buffered otherwise): the power-cut watcher reads the console as it comes
unbuffer=()
if [ "$suite" = powercut ]; then unbuffer=(stdbuf -oL); fi
timeout -k 10 "$vm_timeout" "${qemu[@]}" </dev/null 2>&1 | ${unbuffer[@]+"${unbuffer[@]}"} tr -d '\r' | tee "$console"
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
if [ "$suite" = powercut ]; then
    kill "$cut_pid" 2>/dev/null || true
    wait "$cut_pid" 2>/dev/null || true
    if grep -q '^POWERCUT NOW' "$console" && [ -s "$cut_log" ]; then
        log "the power was cut: $(head -n 1 "$cut_log"); judging $disk (a copy, repaired) against $witness"
        bash "$here/powercut-judge.sh" "$disk" "$witness" "$work/judged$sfx" "$bin" >"$host_checks" 2>&1 || true
    fi
fi
if [ -n "$robot_pid" ]; then
    kill "$robot_pid" 2>/dev/null || true
    wait "$robot_pid" 2>/dev/null || true
    if grep -q '^HOST-CHECK serial_stalled_peer:' "$console"; then
        python3 "$here/serial-robot.py" judge --log "$robot_log" --vm-dir "$arts/scn" --stall-after 50 \
            >>"$host_checks" 2>&1 || true
        log "serial_stalled_peer judged on the host from $robot_log and $arts/scn/ser.*"
    fi
    if grep -q '^HOST-CHECK commission_serial_stalled:' "$console"; then
        python3 "$here/serial-robot.py" judge --check commission_serial_stalled --log "$robot_log" --vm-dir "$arts/scn" \
            >>"$host_checks" 2>&1 || true
        log "commission_serial_stalled judged on the host from $robot_log and $arts/scn/com_*"
    fi
fi
if [ -n "$helper_pid" ]; then
    kill "$helper_pid" 2>/dev/null || true
    wait "$helper_pid" 2>/dev/null || true
    helper_pid=""
    host_names=$(sed -n 's/^HOST-CHECK \([a-z0-9_]*\):.*/\1/p' "$console" | paste -sd, -)
    if [ -n "$host_names" ]; then
        python3 "$here/arm64-host.py" judge --log "$host_log" --vm-dir "$arts/scn" --checks "$host_names" \
            >>"$host_checks" 2>&1 || true
        log "$host_names judged on the host from $host_log and $arts/scn/"
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
    die "the VM could not set itself up: $(grep '^VM SETUP FAIL' "$console" | head -1)"
fi
if [ "$suite" = powercut ] && [ "$n_pass" -gt 0 ] && [ "$n_fail" -eq 0 ]; then
    echo "VM SUITE PASS"
    exit 0
elif [ "$suite" = powercut ] && [ "$n_fail" -gt 0 ]; then
    echo "VM SUITE FAIL: powercut_fsynced"
    exit 1
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
