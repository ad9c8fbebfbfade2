#!/usr/bin/env bash
# TEST ONLY: builds OUTDIR/bcryptprimitives.dll, the ProcessPrng stand-in that lets Rust programs load
# under Debian 12's wine 8.0 (see bcryptprimitives.c). Usage: bash tests/wine/stand-in.sh OUTDIR
set -euo pipefail
[ $# -eq 1 ] || { echo "usage: $0 OUTDIR" >&2; exit 2; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
mkdir -p "$1"
x86_64-w64-mingw32-gcc -O2 -shared -s -o "$1/bcryptprimitives.dll" "$here/bcryptprimitives.c" -ladvapi32
