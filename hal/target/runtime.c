/*
 * runtime.c - the integer helpers GCC calls for 32-bit multiply and divide.
 * Debian's m68k-linux-gnu libgcc.a is built for the 68020: its __divsi3
 * uses BSR.L and its helpers assume 32-bit MULU/DIVU, which a 68000 lacks
 * (docs/interpretations.md).  These are plain C compiled with -m68000, so
 * they use only MULU.W and shifts.  The firmware avoids them in interrupts.
 */
#include <stdint.h>
#include "runtime.h"

uint32_t rt_mul32(uint32_t a, uint32_t b)
{
    uint16_t al = (uint16_t)a, ah = (uint16_t)(a >> 16);
    uint16_t bl = (uint16_t)b, bh = (uint16_t)(b >> 16);
    uint32_t lo = (uint32_t)al * bl;
    uint16_t cross = (uint16_t)((uint32_t)al * bh + (uint32_t)ah * bl);
    return lo + ((uint32_t)cross << 16);
}

uint32_t rt_udivmod32(uint32_t n, uint32_t d, uint32_t *rem)
{
    if (d == 0) {            /* C leaves it undefined; never trap the card */
        if (rem)
            *rem = n;
        return 0xFFFFFFFFu;
    }
    uint32_t q = 0, r = 0;
    for (int i = 31; i >= 0; i--) {
        r = (r << 1) | ((n >> i) & 1u);
        if (r >= d) {
            r -= d;
            q |= (uint32_t)1 << i;
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

#ifdef HAL_TARGET
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

void *memcpy(void *dst, const void *src, size_t n)
{
    uint8_t *d = dst;
    const uint8_t *s = src;
    while (n--)
        *d++ = *s++;
    return dst;
}

void *memmove(void *dst, const void *src, size_t n)
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

void *memset(void *dst, int c, size_t n)
{
    uint8_t *d = dst;
    while (n--)
        *d++ = (uint8_t)c;
    return dst;
}

int memcmp(const void *a, const void *b, size_t n)
{
    const uint8_t *x = a, *y = b;
    for (; n; n--, x++, y++)
        if (*x != *y)
            return *x < *y ? -1 : 1;
    return 0;
}
#endif
