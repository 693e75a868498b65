/*
 * runtime.c - the integer helpers GCC calls for 32-bit multiply and divide.
 * Debian's m68k-linux-gnu libgcc.a is built for the 68020: its __divsi3
 * uses BSR.L and its helpers assume 32-bit MULU/DIVU, which a 68000 lacks
 * (docs/interpretations.md).  These are plain C compiled with -m68000, so
 * they use only MULU.W and shifts.  The firmware avoids them in interrupts.
 */
#include <stdint.h>
#include "runtime.h"
#include "mul16.h"

uint32_t rt_mul32(uint32_t a, uint32_t b)
{
    uint16_t al = (uint16_t)a, ah = (uint16_t)(a >> 16);
    uint16_t bl = (uint16_t)b, bh = (uint16_t)(b >> 16);
    uint32_t lo = mulu16(al, bl);
    uint16_t cross = (uint16_t)(mulu16(al, bh) + mulu16(ah, bl));
    return lo + ((uint32_t)cross << 16);
}

uint32_t rt_udivmod32(uint32_t n, uint32_t d, uint32_t *rem)
{
    if (d == 0) {            /* C leaves it undefined; never trap the card */
        if (rem)
            *rem = n;
        return 0xFFFFFFFFu;
    }
    uint32_t q = 0, r;
    if (d < 0x10000u) {
        /* two DIVU.W (__udivsi3 about 670 cycles with its calls, not 3 400
         * for a bit loop): the high word, then the remainder and the low
         * word, each quotient < 2^16 */
        uint32_t hi = divu16(n >> 16, (uint16_t)d);
        uint32_t lo = divu16((hi & 0xFFFF0000u) | (n & 0xFFFFu), (uint16_t)d);
        q = hi << 16 | (lo & 0xFFFFu);
        r = lo >> 16;
    } else if (d & 0x80000000u) {
        q = n >= d;
        r = q ? n - d : n;
    } else {
        /* the quotient is below 2^16: sixteen steps, r < 2 d < 2^32 */
        r = n >> 16;
        for (int i = 15; i >= 0; i--) {
            r = (r << 1) | ((n >> i) & 1u);
            if (r >= d) {
                r -= d;
                q |= (uint32_t)1 << i;
            }
        }
    }
    if (rem)
        *rem = r;
    return q;
}

int32_t rt_div32(int32_t n, int32_t d)
{
    uint32_t un = n < 0 ? 0u - (uint32_t)n : (uint32_t)n;
    uint32_t ud = d < 0 ? 0u - (uint32_t)d : (uint32_t)d;
    uint32_t q = rt_udivmod32(un, ud, 0);
    return (int32_t)(((n < 0) != (d < 0)) ? 0u - q : q);
}

int32_t rt_mod32(int32_t n, int32_t d)
{
    uint32_t un = n < 0 ? 0u - (uint32_t)n : (uint32_t)n;
    uint32_t ud = d < 0 ? 0u - (uint32_t)d : (uint32_t)d;
    uint32_t r;
    rt_udivmod32(un, ud, &r);
    return (int32_t)(n < 0 ? 0u - r : r);
}

/* 64-bit shifts by a variable count (GCC calls these at -Os). */
uint64_t rt_lshr64(uint64_t a, unsigned b)
{
    uint32_t hi = (uint32_t)(a >> 32), lo = (uint32_t)a;
    b &= 63u;
    if (b >= 32)
        return hi >> (b - 32);
    if (b == 0)
        return a;
    return ((uint64_t)(hi >> b) << 32) | ((lo >> b) | (hi << (32 - b)));
}

uint64_t rt_shl64(uint64_t a, unsigned b)
{
    uint32_t hi = (uint32_t)(a >> 32), lo = (uint32_t)a;
    b &= 63u;
    if (b >= 32)
        return (uint64_t)(lo << (b - 32)) << 32;
    if (b == 0)
        return a;
    return ((uint64_t)((hi << b) | (lo >> (32 - b))) << 32) | (uint32_t)(lo << b);
}

int64_t rt_ashr64(int64_t a, unsigned b)
{
    b &= 63u;
    if (a >= 0)
        return (int64_t)rt_lshr64((uint64_t)a, b);
    return (int64_t)~rt_lshr64(~(uint64_t)a, b);   /* floor, as >> on negatives */
}

#ifdef HAL_TARGET
int64_t __ashrdi3(int64_t a, int b);
int64_t __ashldi3(int64_t a, int b);
uint64_t __lshrdi3(uint64_t a, int b);
int64_t __ashrdi3(int64_t a, int b) { return rt_ashr64(a, (unsigned)b); }
int64_t __ashldi3(int64_t a, int b) { return (int64_t)rt_shl64((uint64_t)a, (unsigned)b); }
uint64_t __lshrdi3(uint64_t a, int b) { return rt_lshr64(a, (unsigned)b); }

uint32_t __mulsi3(uint32_t a, uint32_t b);
uint32_t __udivsi3(uint32_t n, uint32_t d);
uint32_t __umodsi3(uint32_t n, uint32_t d);
int32_t __divsi3(int32_t n, int32_t d);
int32_t __modsi3(int32_t n, int32_t d);

uint32_t __mulsi3(uint32_t a, uint32_t b) { return rt_mul32(a, b); }
uint32_t __udivsi3(uint32_t n, uint32_t d) { return rt_udivmod32(n, d, 0); }
uint32_t __umodsi3(uint32_t n, uint32_t d)
{
    uint32_t r;
    rt_udivmod32(n, d, &r);
    return r;
}
int32_t __divsi3(int32_t n, int32_t d) { return rt_div32(n, d); }
int32_t __modsi3(int32_t n, int32_t d) { return rt_mod32(n, d); }
#endif

#ifdef HAL_TARGET
/* A freestanding compiler may still emit calls to these four. */
#include <stddef.h>
void *memcpy(void *dst, const void *src, size_t n);
void *memmove(void *dst, const void *src, size_t n);
void *memset(void *dst, int c, size_t n);
int memcmp(const void *a, const void *b, size_t n);

/* Long moves where both ends are even (the 68000 needs no more for a
 * MOVE.L), bytes for the rest: a 64-byte struct cleared in about 950
 * cycles with the call, not 2 760.  No loop here may be turned back into a
 * call of itself. */
#define RT_NO_LIBCALL __attribute__((optimize("no-tree-loop-distribute-patterns")))

RT_NO_LIBCALL void *memcpy(void *dst, const void *src, size_t n)
{
    uint8_t *d = dst;
    const uint8_t *s = src;
    if (n >= 8 && !(((uintptr_t)d | (uintptr_t)s) & 1u)) {
        uint32_t *dl = (uint32_t *)(void *)d;
        const uint32_t *sl = (const uint32_t *)(const void *)s;
        for (size_t k = n >> 2; k; k--)
            *dl++ = *sl++;
        d = (uint8_t *)dl;
        s = (const uint8_t *)sl;
        n &= 3u;
    }
    while (n--)
        *d++ = *s++;
    return dst;
}

RT_NO_LIBCALL void *memmove(void *dst, const void *src, size_t n)
{
    uint8_t *d = dst;
    const uint8_t *s = src;
    if (d < s) {
        while (n--)
            *d++ = *s++;
    } else {
        while (n--)
            d[n] = s[n];
    }
    return dst;
}

RT_NO_LIBCALL void *memset(void *dst, int c, size_t n)
{
    uint8_t *d = dst;
    if (n >= 8 && !((uintptr_t)d & 1u)) {
        uint32_t w = (uint8_t)c;
        w |= w << 8;
        w |= w << 16;
        uint32_t *dl = (uint32_t *)(void *)d;
        for (size_t k = n >> 2; k; k--)
            *dl++ = w;
        d = (uint8_t *)dl;
        n &= 3u;
    }
    while (n--)
        *d++ = (uint8_t)c;
    return dst;
}

RT_NO_LIBCALL int memcmp(const void *a, const void *b, size_t n)
{
    const uint8_t *x = a, *y = b;
    for (; n; n--, x++, y++)
        if (*x != *y)
            return *x < *y ? -1 : 1;
    return 0;
}
#endif
