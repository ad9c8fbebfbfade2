/* TEST ONLY, never shipped: a stand-in for Windows' bcryptprimitives.dll under Debian 12's wine 8.0.
 *
 * Rust's standard library (1.78 and later) imports ProcessPrng from bcryptprimitives.dll, which Windows 10
 * and 11 have and wine 8.0 lacks: without it the loader refuses tracerctl.exe (c0000135). Placed beside the
 * .exe under test, this DLL gives ProcessPrng through advapi32's RtlGenRandom (SystemFunction036), which
 * wine has. The release archives never contain it (.ci/release checks).
 */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length)
{
    while (length > 0) {
        ULONG chunk = length > 0x10000000 ? 0x10000000 : (ULONG)length;
        if (!SystemFunction036(data, chunk))
            return FALSE;
        data += chunk;
        length -= chunk;
    }
    return TRUE;
}
