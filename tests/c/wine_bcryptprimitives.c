/*
 * Test-only stand-in for Windows' bcryptprimitives.dll under Wine 8, which lacks it.
 *
 * Rust's standard library (1.78 and later) on Windows imports ProcessPrng from
 * bcryptprimitives.dll for its random numbers (HashMap seeds); Windows 10 and later have it,
 * Wine 8 does not, so a DLL built by today's Rust fails to load there. This DLL exports
 * ProcessPrng and forwards to BCryptGenRandom (which Wine has). It is copied into a Wine
 * prefix's system32 to run the Windows FMU binaries under Wine; it is never shipped.
 *
 * Build: x86_64-w64-mingw32-gcc -shared -o bcryptprimitives.dll wine_bcryptprimitives.c -lbcrypt
 */
#include <windows.h>
#include <bcrypt.h>

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    return BCRYPT_SUCCESS(BCryptGenRandom(NULL, data, (ULONG)length,
                                          BCRYPT_USE_SYSTEM_PREFERRED_RNG));
}
