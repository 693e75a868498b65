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
    int32_t r = a;
    __asm__("muls.w %1, %0" : "+d"(r) : "dmi"(b) : "cc");
    return r;
#else
    return (int32_t)a * b;
#endif
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

/* Pin a pointer in an address register: GCC 12 -Os for m68k would rather
 * recompute &axes[n] (a multiply by the struct size) at every use. */
#if defined(HAL_TARGET)
#define PIN_PTR(p) __asm__("" : "+a"(p))
#else
#define PIN_PTR(p) ((void)0)
#endif

#endif
