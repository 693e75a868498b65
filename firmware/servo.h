/*
 * servo.h - the position controller of MAC4-INC/SSI (manual 5.16): a
 * lead/lag filter with a parallel integrator,
 *
 *   u1(k) = K e(k) - K A e(k-1) - B u1(k-1)
 *   u2(k) = C e(k-1) + u2(k-1)          (limited: anti wind-up)
 *   u(k)  = u1(k) + u2(k)               -> 12-bit DAC, saturated
 *
 * with <ga> = 4K, <ze> = 256A, <po> = 256B, <ki> = 256C and <ki_sc> right
 * shifts of the integral coefficient (C = <ki> / (256 * 2^<ki_sc>)).
 *
 * Fixed point, 68000-friendly: only 16x16->32 multiplies (MULS.W), no
 * division in the tick.  u1 and u2 are carried in 1/256 DAC LSB (Q8); the
 * integrator keeps the bits its shift drops in a residual, so it does not
 * drift.  The following error is limited to what can matter: K*|e| at
 * most 2^16 LSB (32 times full scale), computed once per gain set.
 *
 * Torque (force) limitation <sw> (diagram 5.12): the magnitude of the
 * output is at most <sw> DAC LSB (and the integrator, its anti wind-up,
 * with it); 2048 = the DAC's whole range, no limitation.
 * tests/unit/test_servo.c holds the double-precision reference.
 */
#ifndef SERVO_H
#define SERVO_H
#include "inline.h"
#include <stdint.h>

typedef struct {
    int16_t ga, ze, po, ki;
    uint8_t kisc;
    uint8_t full;           /* derived: <ze>, <po> or <ki> set, or a limit (servo_step_full) */
    int16_t e_lim;          /* derived: |e| limit so that K*|e| <= 2^16 LSB */
    int16_t sw_lim;         /* <sw> + 1 below the DAC range (output within -sw..sw), 0: none */
    /* derived for the general filter, so that its tick needs no shift by a
     * variable and one MULS.W less (servo_set_gains, servo_set_limit): */
    int16_t gzh, gzl;       /* <ga> <ze> = gzh 2^8 + gzl, 0 <= gzl < 2^8 (gzh < 2^15) */
    int16_t ki_mask;        /* 2^<ki_sc> - 1: the integrator's residual */
    int16_t out_hi, out_lo; /* the output range: 2047/-2048, or <sw>/-<sw> */
    int32_t u2_hi, u2_lo;   /* the same in Q8, the integrator's bounds */
} servo_gains_t;

typedef struct {
    int32_t u1;             /* Q8 */
    int32_t u2;             /* Q8, limited to the DAC range */
    int32_t u2_res;         /* integrator bits below Q8, < 2^kisc */
    int16_t e_prev;         /* e(k-1), limited */
} servo_state_t;

#define SERVO_OUT_MAX 2047
#define SERVO_OUT_MIN (-2048)

/* The filter's gains; clears any output limit (servo_set_limit after it). */
void servo_set_gains(servo_gains_t *g, int32_t ga, int32_t ze, int32_t po, int32_t ki, int32_t kisc);
/* Torque (force) limitation <sw>: |output| <= sw DAC LSB; sw >= SERVO_SW_FULL
 * (the default) leaves the whole DAC range.  After servo_set_gains. */
#define SERVO_SW_FULL 2048
void servo_set_limit(servo_gains_t *g, int32_t sw);
void servo_reset(servo_state_t *s);
/* The general filter, every term: servo_filter() out of line (servo.c). */
int16_t servo_step_full(servo_state_t *s, const servo_gains_t *g, int32_t e);

#define SERVO_U1_MAX ((1l << 23) - 1)

#include "mul16.h"

/* e within +-e_lim, one unsigned compare on the common path (0 < e_lim <
 * 2^15, so e + e_lim wraps only from beyond the limit).  The limit is
 * loaded and extended once, in a data register (IN_REG: without it GCC 12
 * copies the word first, 20 cycles a tick more); 2 e_lim is an ADD.L, not
 * a field: servo_gains_t stays 32 bytes, eight long moves where the main
 * loop copies it with interrupts masked (axis_set_gains). */
FW_INLINE int16_t servo_e_limited(const servo_gains_t *g, int32_t e32)
{
    uint32_t lim = (uint32_t)(int32_t)g->e_lim;
    IN_REG(lim);
    uint32_t t = (uint32_t)e32 + lim;   /* e32's register: e is t - lim again */
    if (RARELY(t > lim + lim))
        return (int16_t)((int32_t)(t - lim) < 0 ? 0u - lim : lim);
    return (int16_t)(t - lim);
}

/* The general filter, inline for the tick (servo_step).  In Q8:
 *   u1 = 64 ga e - floor(ga ze e' / 4) - floor(po u1' / 256), within 2^23;
 *   u2 += floor(r / 2^kisc) of r = residual + ki e', the rest the residual,
 *        u2 within the output range;
 *   u  = (u1 + u2 + 128) >> 8, saturated to the output range
 * (tests/unit/test_servo.c holds it bit for bit against that definition in
 * 64 bits).  |ga e| <= 2^18 (e_lim), so |ga ze e'| < 2^26: the K A e' term
 * is 64 gzh e' + floor(gzl e' / 4) in two MULS.W (the second by a byte:
 * MULS.W takes 38 cycles plus 2 per bit change of its source), each product
 * within 32 bits; po u1' as hi 256 + lo, 0 <= lo < 256.  Each MULS.W is up
 * to 70 cycles, so a zero term costs none. */
FW_INLINE int16_t servo_filter(servo_state_t *s, const servo_gains_t *g,
                                                                  int32_t e32)
{
    int16_t e = servo_e_limited(g, e32);
    int16_t ep = s->e_prev;
    s->e_prev = e;
    int32_t u1 = muls16(e, g->ga);
    if (g->ze)                      /* one shift for both: |ga e - gzh e'| < 2^19 */
        u1 = (u1 - muls16(g->gzh, ep)) * 64 - (muls16(ep, g->gzl) >> 2);
    else
        u1 *= 64;
    if (g->po) {
        int32_t a = s->u1;
        IN_REG(a);
        u1 -= muls16((int16_t)(a >> 8), g->po) + (muls16((int16_t)(a & 0xFF), g->po) >> 8);
    }
    int32_t u2 = s->u2;
    if (g->ki) {
        int32_t r = s->u2_res + muls16(g->ki, ep);
        s->u2_res = r & g->ki_mask;                  /* r - floor(r / 2^kisc) 2^kisc */
        u2 += r >> g->kisc;
    }
    if (u2 > g->u2_hi)                               /* anti wind-up: u2 alone never */
        u2 = g->u2_hi;                               /* beyond the output range */
    else if (u2 < g->u2_lo)
        u2 = g->u2_lo;
    s->u2 = u2;
    s->u1 = u1;
    /* An output within its range (u2_lo/u2_hi: the range in Q8) means
     * |u1| < 2^21, so u1's bound below cannot apply: one compare on the
     * common path. */
    int32_t t = u1 + u2 + 128;
    if ((uint32_t)(t - g->u2_lo) <= (uint32_t)(g->u2_hi - g->u2_lo) + 255u)
        return (int16_t)(t >> 8);
    /* bound the lag state to 2^15 LSB (Q8: 2^23), 16 times full scale: the
     * DAC is saturated long before, and the bound keeps po u1 in MULS.W.
     * A u1 beyond it saturates the output to the same side as the bounded
     * one would (|u2| <= 2^19), so the output is the side of t. */
    if ((uint32_t)u1 + (uint32_t)SERVO_U1_MAX > 2u * SERVO_U1_MAX)
        s->u1 = u1 < 0 ? -SERVO_U1_MAX : SERVO_U1_MAX;
    return (t >> 8) > g->out_hi ? g->out_hi : g->out_lo;   /* to DAC LSB, rounded */
}

/* One sampling period: the DAC word for following error e.  Inline, for the
 * tick: with <ze> = <po> = <ki> = 0 (the defaults and the manual's examples
 * but one) and no <sw> limit the filter is K e plus the frozen integrator,
 * one MULS.W; the result is bit for bit what servo_step_full() gives for
 * those gains.  Everything else (a limit included) is servo_filter(). */
FW_INLINE int16_t servo_step_k(servo_state_t *s, const servo_gains_t *g,
                                                                  int32_t e32)
{
    int16_t e = servo_e_limited(g, e32);
    s->e_prev = e;
    /* <ga> the MULS.W's source: its time follows the source's bits, and a
     * gain has fewer bit changes than a following error */
    int32_t u1 = muls16(e, g->ga) * 64;
    s->u1 = u1;
    /* u = (u1 + u2 + 128) >> 8 as ((u1 + u2) >> 4) + 8, then >> 4 (the same
     * floor): w fits a word exactly when u is within the DAC range, one
     * compare on the common path.  There |u1| < 2^21 (u2 is kept within
     * the range), so u1's bound below cannot apply. */
    int32_t w = ((u1 + s->u2) >> 4) + 8;
    if (w == (int16_t)w)
        return (int16_t)((int16_t)w >> 4);
    /* Saturated.  A u1 beyond its bound saturates the output to the same
     * side as the bounded u1 would (|u2| <= 2^19): the side of w. */
    if ((uint32_t)u1 + (uint32_t)SERVO_U1_MAX > 2u * SERVO_U1_MAX)
        s->u1 = u1 < 0 ? -SERVO_U1_MAX : SERVO_U1_MAX;
    return w < 0 ? SERVO_OUT_MIN : SERVO_OUT_MAX;
}

FW_INLINE int16_t servo_step(servo_state_t *s, const servo_gains_t *g,
                                                                int32_t e32)
{
    return g->full ? servo_step_full(s, g, e32) : servo_step_k(s, g, e32);
}

#endif
