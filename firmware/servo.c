#include "servo.h"
#include "mul16.h"

/* the output range in force, in LSB and in Q8 (servo_filter) */
static void set_range(servo_gains_t *g, int16_t hi, int16_t lo)
{
    g->out_hi = hi;
    g->out_lo = lo;
    g->u2_hi = (int32_t)hi * 256;
    g->u2_lo = (int32_t)lo * 256;
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
    /* <ga> <ze> < 2^23 (0..32767 x 0..255), split for two MULS.W */
    uint32_t gz = mulu16((uint16_t)ga, (uint16_t)ze);
    g->gzh = (int16_t)(gz >> 8);
    g->gzl = (int16_t)(gz & 0xFFu);
    g->ki_mask = (int16_t)((1u << (kisc & 15)) - 1u);
    g->sw_lim = 0;
    set_range(g, SERVO_OUT_MAX, SERVO_OUT_MIN);
    g->full = ze != 0 || po != 0 || ki != 0;
}

void servo_set_limit(servo_gains_t *g, int32_t sw)
{
    if (sw >= SERVO_SW_FULL) {
        g->sw_lim = 0;
        set_range(g, SERVO_OUT_MAX, SERVO_OUT_MIN);
    } else {
        int16_t m = (int16_t)(sw < 0 ? 0 : sw);
        g->sw_lim = (int16_t)(m + 1);
        set_range(g, m, (int16_t)-m);
    }
    g->full = g->ze != 0 || g->po != 0 || g->ki != 0 || g->sw_lim != 0;
}

void servo_reset(servo_state_t *s)
{
    s->u1 = 0;
    s->u2 = 0;
    s->u2_res = 0;
    s->e_prev = 0;
}

int16_t servo_step_full(servo_state_t *s, const servo_gains_t *g, int32_t e32)
{
    return servo_filter(s, g, e32);
}
