#!/bin/sh
# TEST-ONLY: builds OUTDIR/bcryptprimitives.dll, a stand-in that exports ProcessPrng (which Rust's std imports
# and Debian 12's wine 8.0 lacks) so that tracerctl.exe and the test executables load under that wine.
# Never ship it: Windows 10 and 11 have the real DLL. See tests/wine/bcryptprimitives.c.
#
# Usage: tests/wine/stand-in.sh OUTDIR      (CC overrides the compiler: x86_64-w64-mingw32-gcc)
set -eu
if [ "$#" -ne 1 ]; then
    echo "usage: $0 OUTDIR" >&2
    exit 2
fi
out=$1
here=$(cd "$(dirname "$0")" && pwd)
cc=${CC:-x86_64-w64-mingw32-gcc}
if ! command -v "$cc" >/dev/null 2>&1; then
    echo "$0: $cc not found (apt-get install gcc-mingw-w64-x86-64)" >&2
    exit 3
fi
mkdir -p "$out"
# -static-libgcc: the DLL needs nothing but kernel32 and advapi32, which wine has.
"$cc" -shared -O2 -s -static-libgcc -Wall -Wextra -Werror \
    -o "$out/bcryptprimitives.dll" "$here/bcryptprimitives.c" -ladvapi32
