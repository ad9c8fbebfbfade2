#!/usr/bin/env bash
# Checks the Debian package built by `cargo deb --locked`: lintian finds no error and no warning; then installs
# it and checks it as a technician would use it: the binary's version, `man tracerctl`, bash completion of a
# subcommand, the zsh/fish completions and the docs in place; the recorder's service (issue 31): its template
# unit accepted by `systemd-analyze verify` for a CAN and a serial instance and not enabled, the configuration
# file a conffile of comments only, the system user tracerctl in dialout; then `dpkg -r` removes every file it
# installed but the conffile, and `dpkg -P` removes that, the recordings and the user.
# Run as root (CI does, from .ci/run):
#   bash tests/deb/check.sh [target/debian/tracerctl_*.deb]
set -euo pipefail
cd "$(dirname "$0")/../.."

fail() {
    printf 'DEB CHECK FAIL: %b\n' "$*" >&2
    exit 1
}
pass() { echo "DEB CHECK PASS: $*"; }

deb=${1:-}
if [ -z "$deb" ]; then
    debs=(target/debian/tracerctl_*.deb)
    [ -e "${debs[0]}" ] || fail "no package in target/debian/ (run: cargo deb --locked)"
    deb=${debs[-1]}
fi
version=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -n 1)

# The package's changelog (debian/changelog, installed as changelog.Debian.gz) starts with this version.
changelog_version=$(sed -n '1s/^tracerctl (\([^)]*\)).*/\1/p' debian/changelog)
[ "$changelog_version" = "$version-1" ] ||
    fail "debian/changelog's first entry is ${changelog_version:-missing}, the package is $version-1: add an entry"

# lintian, as Debian checks a package: every error and warning fails (the tags are printed). Info-level notes
# (I:) do not fail.
if ! command -v lintian >/dev/null; then
    apt-get update -q
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends lintian
fi
tags=$(lintian --tag-display-limit 0 "$deb" 2>&1) || true
errors=$(grep -c '^E: ' <<<"$tags" || true)
warnings=$(grep -c '^W: ' <<<"$tags" || true)
((errors == 0 && warnings == 0)) || fail "lintian: $errors errors, $warnings warnings:\n$tags"
pass "lintian $(lintian --version | awk '{print $2}'): 0 errors, 0 warnings"

# Docker-style images tell dpkg to drop man pages and docs (path-exclude): then `man tracerctl` cannot be
# checked, and saying so is better than a confusing failure.
if grep -rqs '^path-exclude=/usr/share/man' /etc/dpkg/dpkg.cfg.d/; then
    fail "dpkg is configured to drop /usr/share/man (see /etc/dpkg/dpkg.cfg.d/): man pages cannot be installed here"
fi
missing=()
command -v man >/dev/null || missing+=(man-db)
# systemd-analyze verify; adduser, which the package depends on.
command -v systemd-analyze >/dev/null || missing+=(systemd)
command -v adduser >/dev/null || missing+=(adduser)
if ((${#missing[@]})); then
    apt-get update -q
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

dpkg -i "$deb" >/dev/null || fail "dpkg -i $deb"
installed=$(dpkg -L tracerctl)

[ "$(command -v tracerctl)" = /usr/bin/tracerctl ] || fail "tracerctl is not /usr/bin/tracerctl: $(command -v tracerctl)"
got=$(/usr/bin/tracerctl --version)
[ "$got" = "tracerctl $version" ] || fail "--version says '$got', Cargo.toml says $version"
pass "/usr/bin/tracerctl --version: $got"

for page in tracerctl tracerctl-decode tracerctl-drive tracerctl-dashboard; do
    grep -qx "/usr/share/man/man1/$page.1.gz" <<<"$installed" || fail "$page.1.gz not installed"
done
rendered=$(MANPAGER=cat MANWIDTH=80 man tracerctl 2>&1) || fail "man tracerctl: $rendered"
grep -q "EXAMPLES" <<<"$rendered" || fail "man tracerctl has no EXAMPLES section:\n$rendered"
grep -q "tracerctl \[OPTIONS\] <COMMAND>" <<<"$rendered" || fail "man tracerctl has no synopsis:\n$rendered"
drive=$(MANPAGER=cat MANWIDTH=80 man tracerctl-drive 2>&1) || fail "man tracerctl-drive: $drive"
grep -q -- "--linear" <<<"$drive" || fail "man tracerctl-drive lacks --linear"
pass "man tracerctl renders ($(wc -l <<<"$rendered") lines), man tracerctl-drive lists --linear"

# Bash completion as bash-completion loads it: the file named after the command, its function bound to it.
completion=/usr/share/bash-completion/completions/tracerctl
[ -f "$completion" ] || fail "no $completion"
words=$(bash -c "source $completion
    COMP_WORDS=(tracerctl dec); COMP_CWORD=1; COMP_LINE='tracerctl dec'; COMP_POINT=\${#COMP_LINE}
    spec=\$(complete -p tracerctl) || exit 3
    function=\$(sed -n 's/.*-F \([^ ]*\).*/\1/p' <<<\"\$spec\")
    \"\$function\" tracerctl dec tracerctl
    printf '%s\n' \"\${COMPREPLY[@]}\"") || fail "bash completion did not run (exit $?)"
grep -qx decode <<<"$words" || fail "bash completion of 'tracerctl dec' offers: $words"
pass "bash completion: 'tracerctl dec<TAB>' offers decode"

for file in /usr/share/zsh/vendor-completions/_tracerctl /usr/share/fish/vendor_completions.d/tracerctl.fish \
    /usr/share/doc/tracerctl/tracer.dbc /usr/share/doc/tracerctl/README.md /usr/share/doc/tracerctl/json.md /usr/share/doc/tracerctl/foxglove.md /usr/share/doc/tracerctl/foxglove-layout.json; do
    [ -f "$file" ] || fail "$file not installed"
done
pass "zsh and fish completions, the DBC and the docs are installed"

# The recorder's service. The unit is the repository's, byte for byte, and not enabled (the instance names the
# link: only the administrator knows it).
unit=/usr/lib/systemd/system/tracerctl-record@.service
cmp -s "$unit" debian/tracerctl-record@.service || fail "$unit is not debian/tracerctl-record@.service"
wanted=$(find /etc/systemd/system -name 'tracerctl-record@*' 2>/dev/null)
[ -z "$wanted" ] || fail "the package enabled the template unit: $wanted"
# systemd-analyze verify loads each instance as systemd would (ExecStart's binary must exist, man:tracerctl(1)
# must open) and says nothing when all is well; an unknown or misspelt directive is a warning with exit 0, so
# any output fails.
for instance in can0 vcan0 dev-ttyUSB0; do
    said=$(systemd-analyze verify "tracerctl-record@$instance.service" 2>&1) ||
        fail "systemd-analyze verify tracerctl-record@$instance.service:\n$said"
    [ -z "$said" ] || fail "systemd-analyze verify tracerctl-record@$instance.service says:\n$said"
done
pass "systemd $(systemd-analyze --version | awk 'NR == 1 {print $2}'): systemd-analyze verify accepts tracerctl-record@can0, @vcan0 and @dev-ttyUSB0, nothing enabled"

config=/etc/tracerctl/config.toml
grep -qx " $config [0-9a-f]*" <<<"$(dpkg-query -W -f='${Conffiles}\n' tracerctl)" || fail "$config is not a conffile"
settings=$(grep -v -e '^[[:space:]]*#' -e '^[[:space:]]*$' "$config" || true)
[ -z "$settings" ] || fail "$config sets something, it must only show examples in comments:\n$settings"
pass "$config is a conffile of comments only"

# The system user: a system account with no home and no login, in its own group and in dialout (serial ports).
IFS=: read -r _ _ uid gid _ home shell <<<"$(getent passwd tracerctl)" || fail "no user tracerctl after install"
((uid < 1000)) || fail "tracerctl is not a system user: uid $uid"
[ "$(getent group "$gid" | cut -d: -f1)" = tracerctl ] || fail "tracerctl's primary group is gid $gid, not tracerctl"
[ "$home" = /nonexistent ] || fail "tracerctl's home is $home, not /nonexistent"
case $shell in */nologin | */false) ;; *) fail "tracerctl can log in: shell $shell" ;; esac
groups=$(id -nG tracerctl)
grep -qw dialout <<<"$groups" || fail "tracerctl is not in dialout: $groups"
pass "system user tracerctl (uid $uid, groups: $groups, shell $shell)"

# What a run and an administrator leave, for the purge to remove: a recording (StateDirectory=tracerctl/can0
# creates it, owned by tracerctl) and an enabled instance (systemctl enable works without a running systemd).
install -d -o tracerctl -g tracerctl /var/lib/tracerctl/can0/incidents/2026-01-01T00:00:00Z-estop
echo 'can0 111#00' >/var/lib/tracerctl/can0/incidents/2026-01-01T00:00:00Z-estop/frames.log
enabled=$(systemctl enable tracerctl-record@can0.service 2>&1) || fail "systemctl enable tracerctl-record@can0:\n$enabled"
[ -L /etc/systemd/system/multi-user.target.wants/tracerctl-record@can0.service ] ||
    fail "systemctl enable tracerctl-record@can0 made no link in multi-user.target.wants:\n$enabled"

dpkg -r tracerctl >/dev/null || fail "dpkg -r tracerctl"
left=()
while read -r path; do
    [ "$path" != "$config" ] || continue
    if [ -f "$path" ] || [ -L "$path" ]; then left+=("$path"); fi
done <<<"$installed"
((${#left[@]} == 0)) || fail "dpkg -r left files behind: ${left[*]}"
# Debian's rule: a remove keeps the configuration (and here the user and the recordings) for a reinstall.
[ -f "$config" ] || fail "dpkg -r removed the conffile $config"
getent passwd tracerctl >/dev/null || fail "dpkg -r removed the user tracerctl"
! command -v tracerctl >/dev/null || [ "$(command -v tracerctl)" != /usr/bin/tracerctl ] ||
    fail "/usr/bin/tracerctl still there after dpkg -r"
pass "dpkg -r removed all $(grep -c . <<<"$installed") paths' files but the conffile, kept the user"

dpkg -P tracerctl >/dev/null || fail "dpkg -P tracerctl"
for path in /etc/tracerctl /var/lib/tracerctl /etc/systemd/system/multi-user.target.wants/tracerctl-record@can0.service; do
    if [ -e "$path" ] || [ -L "$path" ]; then fail "dpkg -P left $path"; fi
done
! getent passwd tracerctl >/dev/null || fail "dpkg -P left the user tracerctl"
! getent group tracerctl >/dev/null || fail "dpkg -P left the group tracerctl"
! grep -qw tracerctl <<<"$(getent group dialout)" || fail "dpkg -P left tracerctl in dialout: $(getent group dialout)"
status=$(dpkg-query -W -f='${db:Status-Status}' tracerctl 2>/dev/null || true)
[ -z "$status" ] || [ "$status" = not-installed ] || fail "dpkg says tracerctl is $status after -P"
pass "dpkg -P removed the conffile, the recordings, the enabled instance, the user and the group"
