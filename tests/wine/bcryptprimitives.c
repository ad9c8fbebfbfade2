/*
 * TEST-ONLY stand-in for bcryptprimitives.dll: never shipped, never put beside a real user's tracerctl.exe.
 *
 * Rust's standard library (1.78 and later) imports ProcessPrng from bcryptprimitives.dll, which Windows 10
 * and 11 have. Debian 12's wine 8.0 does not export it, so the .exe does not even load there. This DLL,
 * placed next to the .exe (or the test executables) under wine only, supplies the one function with
 * RtlGenRandom (advapi32's SystemFunction036), which wine implements.
 *
 * Built by tests/wine/stand-in.sh OUTDIR.
 */
#include <windows.h>

/* RtlGenRandom: ntsecapi.h declares it as SystemFunction036; declared here so no other header is needed. */
BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

/* ProcessPrng fills `data` with `len` random bytes and, as on Windows, always returns TRUE. */
__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len)
{
    while (len > 0) {
        ULONG chunk = len > 0x40000000 ? 0x40000000 : (ULONG)len;
        if (!SystemFunction036(data, chunk)) {
            /* Windows' ProcessPrng cannot fail; a test-only stand-in that could not fill the buffer stops here
             * rather than hand out predictable bytes. */
            ExitProcess(99);
        }
        data += chunk;
        len -= chunk;
    }
    return TRUE;
}
