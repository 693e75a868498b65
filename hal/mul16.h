/*
 * mul16.h - the 68000's multiplies, 16 x 16 -> 32 (MULU.W / MULS.W).
 * GCC does not always see that a product of two zero- or sign-extended
 * 16-bit values fits one MULU.W and calls __mulsi3 instead; on the target
 * these say it in assembly, so the fixed-point kernels and the __mulsi3
 * helper itself can never recurse into a 32-bit multiply.
 */
#ifndef MUL16_H
#define MUL16_H
#include <stdint.h>
#include "inline.h"

static inline uint32_t mulu16(uint16_t a, uint16_t b)
{
#if defined(HAL_TARGET)
    uint32_t r = a;
    __asm__("mulu.w %1, %0" : "+d"(r) : "dmi"(b) : "cc");
    return r;
#else
    return (uint32_t)a * b;
#endif
}

static inline int32_t muls16(int16_t a, int16_t b)
{
#if defined(HAL_TARGET)
    /* a in the product's register as a word: MULS.W reads only its low
     * half, so no EXT.L before it */
    int32_t r;
    __asm__("muls.w %2, %0" : "=d"(r) : "0"(a), "dmi"(b) : "cc");
    return r;
#else
    return (int32_t)a * b;
#endif
}

/* DIVU.W: n / d in the low word, n % d in the high word, for d > 0 and a
 * quotient below 2^16 (the 68000 sets V and leaves n otherwise). */
static inline uint32_t divu16(uint32_t n, uint16_t d)
{
#if defined(HAL_TARGET)
    __asm__("divu.w %1, %0" : "+d"(n) : "dmi"(d) : "cc");
    return n;
#else
    return (n % d) << 16 | (n / d);
#endif
}

/* a * b, for a, b < 2^31, as two 32-bit words from MULU.W: one when both
 * factors fit 16 bits, two when a does. */
FW_INLINE void mulu31(uint32_t a, uint32_t b, uint32_t *hi, uint32_t *lo)
{
    uint16_t al = (uint16_t)a, bl = (uint16_t)b, bh = (uint16_t)(b >> 16);
    uint32_t ll = mulu16(al, bl);
    if (a < 0x10000u) {
        if (!bh) {
            *hi = 0;
            *lo = ll;
            return;
        }
        uint32_t m = mulu16(al, bh);
        uint32_t l = ll + (m << 16);
        *hi = (m >> 16) + (l < ll);
        *lo = l;
        return;
    }
    uint16_t ah = (uint16_t)(a >> 16);
    uint32_t mid = mulu16(ah, bl) + mulu16(al, bh);    /* < 2^32: a, b < 2^31 */
    uint32_t l = ll + (mid << 16);
    *hi = mulu16(ah, bh) + (mid >> 16) + (l < ll);
    *lo = l;
}

/* Keep a value in a data register.  GCC 12 for m68k turns (int16_t)(x >> 8)
 * of a 32-bit variable in memory into a word load at an odd offset, which a
 * 68000 answers with an address error; passing the value through here first
 * stops that. */
#if defined(HAL_TARGET)
#define IN_REG(x) __asm__("" : "+d"(x))
#else
#define IN_REG(x) ((void)0)
#endif

/* A condition the tick's common path does not meet (a limit, an encoder
 * error, a busy receiver): GCC -Os lays its branch out of the way, so the
 * common path falls through instead of jumping there and back. */
#define RARELY(c) __builtin_expect(!!(c), 0)

/* Pin a pointer in an address register: GCC 12 -Os for m68k would rather
 * recompute &axes[n] (a multiply by the struct size) at every use. */
#if defined(HAL_TARGET)
#define PIN_PTR(p) __asm__("" : "+a"(p))
#else
#define PIN_PTR(p) ((void)0)
#endif

#endif
