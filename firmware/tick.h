/*
 * tick.h - what the two ticks share (tick_servo.c: INC/SSI, tick_stp.c:
 * STP) and the one output stage of an axis, which the tick and axis.c
 * (axis_disable: the outputs at once) use.  Inline: the ticks take them
 * with a constant axis number, as absolute register addresses.
 */
#ifndef TICK_H
#define TICK_H
#include "inline.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "stepper.h"
#include "stp_rate.h"

/* The tick's own braking ramp starts (motion.c brake_now, masked) at the
 * Q16 setpoint q16 and speed v of the moment ... */
static inline void brake_start(axis_t *x, int64_t q16, int32_t v)
{
    x->br_posh = q16 + BR_HALF;
    x->br_v = v;
}

/* ... and the tick steps it: the speed of this tick, br_dec closer to
 * 0 ... */
FW_INLINE int32_t brake_slower(const axis_t *x)
{
    int32_t v = x->br_v, dv = x->br_dec;
    if (v > 0)
        v = v > dv ? v - dv : 0;
    else if (v < 0)
        v = v < -dv ? v + dv : 0;
    return v;
}

/* ... and the step at that speed. */
FW_INLINE void brake_step(axis_t *x, int32_t v)
{
    x->br_v = v;
    x->br_posh += v;
}

/* The output stage's one write of AX_CTRL and AX_DAC, with their copies
 * ctrl and out: the tick's (tick_stp.c's running axis, axis_output_x) ... */
FW_INLINE void axis_output_write(axis_t *x, unsigned n, uint16_t ctrl, int32_t out)
{
    axis_ctrl_set(x, ctrl);
    x->out = (int16_t)out;
    hal_wr16(AX_REG(n, AX_CTRL), ctrl);
    hal_wr16(AX_REG(n, AX_DAC), (uint16_t)out);
}

/* ... the DAC alone (tick_servo.c: /EN follows the mode, axis_mode_card) ... */
FW_INLINE void axis_dac_write(axis_t *x, unsigned n, int16_t out)
{
    x->out = out;
    hal_wr16(AX_REG(n, AX_DAC), (uint16_t)out);
}

/* ... and both off at a reset (card.c, before the timer runs; Tables 2.2,
 * 2.6, 2.12: /EN open, DAC 0 V or no pulses, DIR and BOOST open collector). */
FW_INLINE void axis_output_off(axis_t *x, unsigned n)
{
    axis_ctrl_set(x, 0);
    x->out = 0;
    hal_wr16(AX_REG(n, AX_CTRL), 0);
    hal_wr16(AX_REG(n, AX_DAC), 0);
}

/* The outputs of axis n: /EN from the mode, and the DAC word (INC/SSI) or,
 * on the STP, DIR, BOOST, TURBO and the step rate register prepared by
 * stp_rate.h (stp_output; `out` is not used: the rate is exact to the Q16
 * step); x is axes[n]. */
FW_INLINE void axis_output_x(axis_t *x, unsigned n, int32_t out)
{
    uint16_t ctrl = (uint16_t)(x->ctrl & ~AX_CTRL_EN);
    if (x->mode != M_DISABLE)
        ctrl |= AX_CTRL_EN;
    if (MAC4_CARD == MAC4_CARD_STP)
        out = stp_output(n, x->mode, &ctrl);
    axis_output_write(x, n, ctrl, out);
}

/* ... of axis n, the axis looked up */
FW_INLINE void axis_output_at(unsigned n, int32_t out)
{
    /* a constant n (the ticks): an absolute address; else the table, not a
     * multiply by sizeof(axis_t) */
    axis_t *x = __builtin_constant_p(n) ? &axes[n] : axis_at[n];
    PIN_PTR(x);
    axis_output_x(x, n, out);
}

#endif
