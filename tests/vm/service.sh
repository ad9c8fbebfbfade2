#!/usr/bin/env bash
# The recorder's service under a real systemd: a QEMU VM (the kernel tests/vm/run.sh downloads and caches)
# whose initramfs holds this host's systemd, the unit debian/tracerctl-record@.service unchanged, the user
# tracerctl, vcan and a serial port owned by dialout; systemd boots it and tests/vm/service/scenario.sh runs
# `systemctl enable --now tracerctl-record@vcan0` and friends, checking what systemd made of the unit.
#
# Run as root on Debian 12, after tests/vm/run.sh (CI does):
#   bash tests/vm/service.sh [--bin target/release/tracerctl | --stand-in] [--unit FILE] [--prepare]
# --stand-in: tests/vm/service/stand-in-recorder plays `tracerctl record` (candump on the link, a report of
# what the sandbox allows): the unit is checked before the recorder exists. Without it, the binary must have
# `record`. --prepare: install the packages it needs, and exit. Exit status 0 every check passed, 1 a check
# failed, 3 the environment could not be set up.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
work=${TRACERCTL_VM_WORK:-$repo/target/vm}
bin=$repo/target/release/tracerctl
stand_in=0
prepare=0
unit=$repo/debian/tracerctl-record@.service
while [ $# -gt 0 ]; do
    case $1 in
        --bin) bin=${2:?--bin needs a path}; shift 2 ;;
        --stand-in) stand_in=1; shift ;;
        --prepare) prepare=1; shift ;;
        # another unit file in place of debian/tracerctl-record@.service (to see a check fail)
        --unit) unit=${2:?--unit needs a file}; shift 2 ;;
        *) echo "service.sh: unknown argument: $1" >&2; exit 2 ;;
    esac
done
die() { printf '\nVM SERVICE ERROR: %s\n' "$*" >&2; exit 3; }
[ "$(id -u)" -eq 0 ] || die "run as root"
kdir=$work/kernel
if [ ! -s "$kdir/vmlinuz" ] || [ ! -s "$kdir/modules/vcan.ko" ]; then
    die "no kernel in $kdir: run tests/vm/run.sh first (it downloads it)"
fi
# Installed when missing (a fresh machine: CI installs nothing for this step before it).
missing=()
for pair in qemu-system-x86_64:qemu-system-x86 cpio:cpio candump:can-utils cansend:can-utils ip:iproute2 \
    /usr/lib/systemd/systemd:systemd systemd-escape:systemd journalctl:systemd; do
    command -v "${pair%%:*}" >/dev/null || missing+=("${pair#*:}")
done
if [ ${#missing[@]} -gt 0 ]; then
    mapfile -t missing < <(printf '%s\n' "${missing[@]}" | sort -u)
    { DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"; } >&2 ||
        die "apt-get install ${missing[*]} failed"
fi
[ $prepare = 0 ] || exit 0
if [ $stand_in = 0 ]; then
    [ -x "$bin" ] || die "no tracerctl at $bin (cargo build --release --locked, or --bin)"
    "$bin" record --help >/dev/null 2>&1 || die "$bin has no 'record' command: use --stand-in"
fi

root=$work/initramfs-service
rm -rf "$root"
# merged /usr as on Debian 12 (its systemd package names /lib/systemd/...); busybox keeps a /bin of its own
mkdir -p "$root"/{bin,usr/bin,usr/sbin,usr/lib/modules/can,usr/lib64,proc,sys,dev,tmp,run,etc/systemd/system,var/lib,newroot}
ln -s usr/lib "$root/lib"
ln -s usr/lib64 "$root/lib64"
ln -s usr/sbin "$root/sbin"
cp /bin/busybox "$root/bin/busybox"
for m in can can-raw can-dev vcan; do cp "$kdir/modules/$m.ko" "$root/usr/lib/modules/can/"; done

# a program and every library ldd lists, at the same paths (the loader included)
add_libs() {
    local lib
    while read -r lib; do
        if [ -z "$lib" ] || [ -e "$root$lib" ]; then continue; fi
        mkdir -p "$root$(dirname "$lib")"
        cp -L "$lib" "$root$lib"
    done < <(LC_ALL=C ldd "$1" 2>/dev/null | awk '/=>/ && $3 ~ /^\// {print $3; next} $1 ~ /^\// {print $1}')
}
add_prog() { install -D -m 755 "$1" "$root$2"; add_libs "$1"; }
# systemd as Debian installs it: every file of its packages, then the libraries of each program in them
for pkg in systemd libsystemd-shared libsystemd0; do
    dpkg -L "$pkg" 2>/dev/null | while read -r path; do
        if [ -f "$path" ] && [ ! -L "$path" ]; then install -D -m "$(stat -c %a "$path")" "$path" "$root$path"
        elif [ -L "$path" ]; then mkdir -p "$root$(dirname "$path")"; cp -a "$path" "$root$path"; fi
    done
done
while read -r elf; do add_libs "$elf"; done < <(find "$root/usr" -type f -perm -u+x | sed "s#^$root##" | while read -r p; do
    file -b "$p" 2>/dev/null | grep -q ELF && echo "$p"; done)
for p in candump cansend; do add_prog "$(command -v $p)" "/usr/bin/$p"; done
add_prog "$(command -v ip)" /usr/sbin/ip

# the recorder and its unit, as the package installs them
if [ $stand_in = 1 ]; then
    install -m 755 "$here/service/stand-in-recorder" "$root/usr/bin/tracerctl"
    echo stand-in >"$root/etc/recorder-kind"
else
    add_prog "$bin" /usr/bin/tracerctl
    echo tracerctl >"$root/etc/recorder-kind"
fi
install -D -m 644 "$unit" "$root/usr/lib/systemd/system/tracerctl-record@.service"
install -D -m 644 "$repo/debian/config.toml" "$root/etc/tracerctl/config.toml"

# users as postinst leaves them (adduser --system --group, in dialout)
cat >"$root/etc/passwd" <<'P'
root:x:0:0:root:/root:/bin/sh
tracerctl:x:101:101::/nonexistent:/usr/sbin/nologin
nobody:x:65534:65534:nobody:/nonexistent:/usr/sbin/nologin
P
cat >"$root/etc/group" <<'G'
root:x:0:
dialout:x:20:tracerctl
systemd-journal:x:999:
tracerctl:x:101:
nogroup:x:65534:
G
printf 'passwd: files\ngroup: files\nshadow: files\n' >"$root/etc/nsswitch.conf"
cp /usr/lib/os-release "$root/usr/lib/os-release"
ln -sf ../usr/lib/os-release "$root/etc/os-release"
: >"$root/etc/machine-id"
mkdir -p "$root/home/someone" && echo secret >"$root/home/someone/file"

# the scenario as a oneshot, the only thing the default target wants
install -m 755 "$here/service/scenario.sh" "$root/scenario.sh"
cat >"$root/etc/systemd/system/vm-scenario.service" <<'U'
[Unit]
Description=tracerctl service scenario
After=basic.target systemd-journald.service
[Service]
Type=oneshot
ExecStart=/bin/sh /scenario.sh
StandardOutput=tty
StandardError=tty
TTYPath=/dev/ttyS0
U
cat >"$root/etc/systemd/system/vm.target" <<'U'
[Unit]
Description=tracerctl service VM
Wants=vm-scenario.service
U
ln -s vm.target "$root/etc/systemd/system/default.target"

cat >"$root/init" <<'I'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/usr/sbin:/usr/bin:/sbin:/bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
exec </dev/console >/dev/console 2>&1
echo "VM: init at uptime $(cut -d' ' -f1 /proc/uptime)s, kernel $(uname -r)"
for m in can can-raw can-dev vcan; do insmod /lib/modules/can/$m.ko || echo "VM SETUP FAIL: insmod $m"; done
ip link add dev vcan0 type vcan && ip link set up vcan0 || echo "VM SETUP FAIL: vcan0"
chgrp dialout /dev/ttyS2 /dev/ttyS3 && chmod 660 /dev/ttyS2 /dev/ttyS3
# systemd on a real mount (its namespaces want one), as after an initramfs
mount -t tmpfs -o mode=755 tmpfs /newroot
for d in bin sbin usr etc lib lib64 var home scenario.sh; do cp -a /$d /newroot/ 2>/dev/null; done
mkdir -p /newroot/proc /newroot/sys /newroot/dev /newroot/run /newroot/tmp
umount /proc /sys
umount /dev 2>/dev/null
exec switch_root /newroot /usr/lib/systemd/systemd
I
chmod 755 "$root/init"
(cd "$root" && find . -print0 | cpio --null -o -H newc --quiet | gzip -1) >"$work/initrd-service.gz"
echo "initramfs: $(du -h "$work/initrd-service.gz" | cut -f1), recorder: $(cat "$root/etc/recorder-kind")"

console=$work/console-service.log
set +e
timeout -k 10 300 qemu-system-x86_64 -accel tcg -m 768 -smp 1 -nographic -no-reboot -nic none \
    -serial mon:stdio -serial null -serial null -serial null \
    -kernel "$kdir/vmlinuz" -initrd "$work/initrd-service.gz" \
    -append "console=ttyS0 quiet panic=-1 systemd.show_status=error" </dev/null 2>&1 | tr -d '\r' | tee "$console"
set -e
echo
echo "================ VM service summary"
grep -E '^(CHECK|INFO) ' "$console" || true
if grep -qx 'SCENARIO PASS' "$console"; then echo "VM SERVICE PASS"; exit 0; fi
if grep -q '^SCENARIO FAIL' "$console"; then echo "VM SERVICE FAIL: $(grep '^SCENARIO FAIL' "$console")"; exit 1; fi
tail -n 30 "$console"
die "the VM stopped without a SCENARIO marker"
