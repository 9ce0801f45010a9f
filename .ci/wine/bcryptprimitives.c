/* A stand-in for Windows' bcryptprimitives.dll, for the tests of the
 * Windows release under Wine only (.ci/release-windows puts it in the test's
 * Wine prefix; the zip never holds it). Rust's std on Windows imports
 * ProcessPrng from that DLL (Windows 10 and later have it), and Debian's
 * Wine 8.0 has none, so the shipped polyturn.exe cannot start there. It
 * answers ProcessPrng with BCryptGenRandom (bcrypt.dll, which Wine has),
 * the system's generator. ProcessPrng's contract (Microsoft's
 * bcryptprimitives documentation): fills the buffer, always returns TRUE. */
#include <windows.h>
#include <bcrypt.h>

BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len)
{
    while (len > 0) {
        ULONG n = len > 0x40000000 ? 0x40000000 : (ULONG)len;
        if (!BCRYPT_SUCCESS(BCryptGenRandom(NULL, data, n, BCRYPT_USE_SYSTEM_PREFERRED_RNG)))
            return FALSE;
        data += n;
        len -= n;
    }
    return TRUE;
}
