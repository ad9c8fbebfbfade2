#!/usr/bin/env bash
# Checks the Debian package built by `cargo deb --locked`: lintian finds no error and no warning; then installs
# it and checks it as a technician would use it: the binary's version, `man tracerctl`, bash completion of a
# subcommand, the zsh/fish completions and the docs in place; then `dpkg -r` removes every file it installed.
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
if ! command -v man >/dev/null; then
    apt-get update -q
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends man-db
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

dpkg -r tracerctl >/dev/null || fail "dpkg -r tracerctl"
left=()
while read -r path; do
    if [ -f "$path" ] || [ -L "$path" ]; then left+=("$path"); fi
done <<<"$installed"
((${#left[@]} == 0)) || fail "dpkg -r left files behind: ${left[*]}"
! command -v tracerctl >/dev/null || [ "$(command -v tracerctl)" != /usr/bin/tracerctl ] ||
    fail "/usr/bin/tracerctl still there after dpkg -r"
pass "dpkg -r removed all $(grep -c . <<<"$installed") paths' files"
