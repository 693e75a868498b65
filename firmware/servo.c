#include "servo.h"
#include "mul16.h"

#define U1_MAX SERVO_U1_MAX

static inline int32_t muls(int16_t a, int16_t b) { return muls16(a, b); }

/* (a * b) >> 8 for |a| < 2^31 and |b| < 2^15, exact floor, in two MULS.W:
 * a = hi * 256 + lo with 0 <= lo < 256. */
static int32_t mul_q8(int32_t a, int16_t b)
{
    IN_REG(a);
    int16_t hi = (int16_t)(a >> 8);
    int16_t lo = (int16_t)(a & 0xFF);
    return muls(hi, b) + (muls(lo, b) >> 8);
}

/* (a * b) >> 2, same conditions: keeps the K A e' term to 1/256 LSB. */
static int32_t mul_q2(int32_t a, int16_t b)
{
    IN_REG(a);
    int16_t hi = (int16_t)(a >> 8);
    int16_t lo = (int16_t)(a & 0xFF);
    return muls(hi, b) * 64 + (muls(lo, b) >> 2);
}

void servo_set_gains(servo_gains_t *g, int32_t ga, int32_t ze, int32_t po, int32_t ki, int32_t kisc)
{
    g->ga = (int16_t)ga;
    g->ze = (int16_t)ze;
    g->po = (int16_t)po;
    g->ki = (int16_t)ki;
    g->kisc = (uint8_t)kisc;
    /* K |e| <= 2^16 LSB  <=>  |e| <= 2^18 / ga (main loop: the division is
     * done here, once per E, never in the tick) */
    int32_t lim = ga > 8 ? (int32_t)(uint16_t)divu16(1ul << 18, (uint16_t)ga) : 32767;   /* (DIVU.W: <ga> > 8) */
    g->e_lim = (int16_t)(lim > 32767 ? 32767 : lim < 1 ? 1 : lim);
    g->sw_lim = 0;
    g->full = ze != 0 || po != 0 || ki != 0;
}

void servo_set_limit(servo_gains_t *g, int32_t sw)
{
    if (sw >= SERVO_SW_FULL)
        g->sw_lim = 0;
    else
        g->sw_lim = (int16_t)((sw < 0 ? 0 : sw) + 1);
    g->full = g->ze != 0 || g->po != 0 || g->ki != 0 || g->sw_lim != 0;
}

void servo_reset(servo_state_t *s)
{
    s->u1 = 0;
    s->u2 = 0;
    s->u2_res = 0;
    s->e_prev = 0;
}

/* The end of servo_step_full() under a torque limit <sw>: the integrator
 * (anti wind-up) and the output within -sw..sw. */
static int16_t limited_output(servo_state_t *s, const servo_gains_t *g, int16_t e, int32_t u1, int32_t u2)
{
    int32_t sw = g->sw_lim - 1, sw8 = sw * 256;
    if (u2 > sw8)
        u2 = sw8;
    else if (u2 < -sw8)
        u2 = -sw8;
    s->u2 = u2;
    s->e_prev = e;
    int32_t u = (u1 + u2 + 128) >> 8;
    if (u > sw)
        u = sw;
    else if (u < -sw)
        u = -sw;
    return (int16_t)u;
}

int16_t servo_step_full(servo_state_t *s, const servo_gains_t *g, int32_t e32)
{
    int16_t e = (int16_t)(e32 > g->e_lim ? g->e_lim : e32 < -g->e_lim ? -g->e_lim : e32);
    int16_t ep = s->e_prev;

    /* u1 in Q8: K e = ga e / 4 -> 64 ga e;  K A e' = ga ze e' / 1024 -> ga (ze e') / 4;
     * B u1' = po u1' / 256.  |ga e| <= 2^18, |ze e'| <= 2^23. */
    /* zero terms (the manual's examples have <po> = 0, often <ki> = 0) cost
     * no multiply: on a 68000 each MULS.W is up to 70 cycles */
    int32_t u1 = muls(g->ga, e) * 64;
    if (g->ze)
        u1 -= mul_q2(muls(g->ze, ep), g->ga);        /* ga ze e' / 4 */
    if (g->po)
        u1 -= mul_q8(s->u1, g->po);
    /* bound the lag state to 2^15 LSB (Q8: 2^23), 16 times full scale: the
     * DAC is saturated long before, and the bound keeps po * u1 in MULS.W */
    if (u1 > U1_MAX)
        u1 = U1_MAX;
    else if (u1 < -U1_MAX)
        u1 = -U1_MAX;
    s->u1 = u1;

    /* u2 in Q8: C e' = ki e' / (256 2^kisc) LSB = (ki e' >> kisc) in Q8;
     * the residual keeps what the shift drops */
    int32_t u2 = s->u2;
    if (g->ki) {
        int32_t r = s->u2_res + muls(g->ki, ep);
        int32_t q = r >> g->kisc;
        s->u2_res = r - (int32_t)((uint32_t)q << g->kisc);
        u2 += q;
    }
    if (g->sw_lim)
        return limited_output(s, g, e, u1, u2);
    if (u2 > (int32_t)SERVO_OUT_MAX * 256)       /* anti wind-up: u2 alone never */
        u2 = (int32_t)SERVO_OUT_MAX * 256;       /* beyond the DAC range */
    else if (u2 < (int32_t)SERVO_OUT_MIN * 256)
        u2 = (int32_t)SERVO_OUT_MIN * 256;
    s->u2 = u2;
    s->e_prev = e;

    int32_t u = (u1 + u2 + 128) >> 8;             /* to DAC LSB, rounded */
    if (u > SERVO_OUT_MAX)
        u = SERVO_OUT_MAX;
    else if (u < SERVO_OUT_MIN)
        u = SERVO_OUT_MIN;
    return (int16_t)u;
}
