/*
 * processprng.c - a stand-in bcryptprimitives.dll for Wine 8.0 (test only).
 *
 * Why this exists: Rust >= 1.78 programs for Windows get their random bytes
 * (HashMap keys, getrandom) from bcryptprimitives.dll!ProcessPrng, which every
 * Windows 10+ system has. Wine 8.0 (the version Debian 12 ships) lacks that
 * export (it was added in Wine 8.13), so kuka-bridge.exe fails to load under
 * it. This DLL exports ProcessPrng on top of RtlGenRandom
 * (advapi32!SystemFunction036) and is copied into the test prefix's
 * windows/system32 by installer/test-wine.sh.
 *
 * It is never shipped: real Windows and Wine >= 8.13 need nothing. The MSI
 * does not contain it.
 *
 * Build: x86_64-w64-mingw32-gcc -O2 -shared -o bcryptprimitives.dll \
 *            processprng.c processprng.def -ladvapi32
 */
#include <windows.h>

/* advapi32!SystemFunction036, a.k.a. RtlGenRandom. */
BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

/* BOOL WINAPI ProcessPrng(PBYTE pbData, SIZE_T cbData); always returns TRUE
 * on Windows; we fill the buffer in chunks because RtlGenRandom takes a ULONG
 * length. */
BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len)
{
    while (len > 0) {
        ULONG chunk = len > 0x40000000 ? 0x40000000 : (ULONG)len;
        if (!SystemFunction036(data, chunk))
            return FALSE;
        data += chunk;
        len -= chunk;
    }
    return TRUE;
}

BOOL WINAPI DllMain(HINSTANCE inst, DWORD reason, LPVOID reserved)
{
    (void)inst; (void)reason; (void)reserved;
    return TRUE;
}
