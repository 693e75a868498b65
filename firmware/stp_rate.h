/*
 * stp_rate.h - the MAC4-STP's rate and output stage (stp_rate.c, inlined
 * into the tick, axis_disable and the level-5 handler): the step rate of
 * each tick, the creep phase and the trim, DIR/BOOST/TURBO, the pulse
 * interrupts.  Above stepper.h's helpers, which it uses; docs/stepper.md.
 */
#ifndef STP_RATE_H
#define STP_RATE_H
#include "inline.h"
#include "hal.h"
#include "card.h"
#include "stepper.h"
#include "stp_card.h"
#include "handover.h"


void stp_idle_output(unsigned n);             /* disabled or test mode */

/* The rate register for t = |distance| + carry Q16 steps in this tick: the
 * generator adds the rate once per clock, 400 clocks per tick (TURBO 4000),
 * so rate = t / clocks, the remainder carried to the next tick and the
 * rates sum up to the distance exactly; at or beyond lim (clocks << 16) the
 * register saturates and the carry is dropped.  (tests/unit/test_stepper.c) */
FW_INLINE void stp_load_rate(stp_t *s, uint32_t t)
{
    if (t < s->lim) {                            /* (the common case first: it falls through) */
        uint32_t qr = stp_divu16(t, s->clocks);
        s->carry = qr >> 16;
        s->rate = (uint16_t)qr;
    } else {
        s->carry = 0;
        s->rate = 0xFFFFu;
    }
}

/* The creep's pulses are counted by interrupt up to 1000 Hz (rate register
 * 1311, TURBO 131); faster, the tick reads the down-counter instead. */
#define STP_PULSE_IRQ_MAX_RATE 1311u
#define STP_PULSE_IRQ_MAX_RATE_TURBO 131u

/* The end of a creep phase or a trim: the generator and the down-counter
 * off if they run, the pulse interrupts off and acknowledged (stp_rate.c;
 * once per creep, out of line).  reg: AX_REG(n, 0). */
void creep_stop(axis_t *x, stp_t *s, uint32_t reg);

/* stp_edge() with the axis' pointers at hand (the tick's creep path). */
FW_INLINE int32_t edge_of(const axis_t *x, const stp_t *s, unsigned n, int32_t d)
{
    if (stp_conv & (1u << n))
        return stp_scale_call(pos_add(s->inc, d), s->ratio);   /* a creep's start, an index: a call */
    return pos_add(x->meas, (x->ustat & UB(REV_O)) ? -d : d);
}

/* The position now, re-reading the counter (the tick's reading is from its
 * start); external encoders keep the tick's value. */
FW_INLINE int32_t meas_now(const axis_t *x, const stp_t *s, unsigned n)
{
    if (x->mk != MK_COUNTER)
        return x->meas;
    uint32_t hi = hal_rd16(AX_REG(n, AX_CNT_HI));           /* latches LO */
    uint32_t raw = (hi << 16) | hal_rd16(AX_REG(n, AX_CNT_LO));
    int32_t d = (int32_t)((raw - x->counter) << 8) >> 8;
    return edge_of(x, s, n, d);
}

/* Tick: the ramp has ended on creep_from, the generator still runs at the
 * ramp's last rate (at most <ssf>): the missing steps into the pulse
 * down-counter at <lv>. */
FW_INLINE void creep_begin(axis_t *x, stp_t *s, unsigned n, uint32_t reg)
{
    hal_wr16(reg + AX_RATE, 0);                  /* no pulse while we count */
    s->rate = 0;
    int32_t cur = meas_now(x, s, n);
    int32_t miss = (int32_t)(x->target >> 16) - cur;
    if (s->creep == CREEP_REQ) {
        handover_segment_at_end(x);              /* the setpoint at the creep segment's end */
    }
    int8_t dir = miss < 0 ? -1 : 1;
    if (miss == 0) {
        s->creep = CREEP_DONE;
        return;
    }
    if (dir != s->dir && s->creep == CREEP_REQ) {
        s->creep = CREEP_WAIT;                   /* a reversal: stand still for one tick first */
        return;
    }
    uint32_t m = (uint32_t)(miss < 0 ? -miss : miss);
    s->creep_n = (uint16_t)(m > 0xFFFFu ? 0xFFFFu : m);
    s->counted = 0;
    s->hw_done = 0;
    s->creep_dir = dir;
    s->creep_base = cur;
    s->dir = dir;
    s->obits = (uint16_t)((s->obits & ~AX_CTRL_DIR) | stp_dir_bit(x, dir));
    s->carry = 0;
    hal_wr16(reg + AX_PULSES, s->creep_n);       /* exactly this many, then the output stops */
    axis_ctrl_set(x, (uint16_t)(x->ctrl | AX_CTRL_DONE_IE));
    s->creep_irq = s->lv_rate <= (s->clocks == STP_TICK_CLOCKS ? STP_PULSE_IRQ_MAX_RATE : STP_PULSE_IRQ_MAX_RATE_TURBO);
    if (s->creep_irq)
        axis_ctrl_set(x, (uint16_t)(x->ctrl | AX_CTRL_PULSE_IE));
    s->rate = s->lv_rate;                        /* DIR and rate go out in axis_output */
    s->creep = CREEP_RUN;
}

/* The creep phase and the trim while one is requested or running, inline
 * in the tick's rate stage with a constant n (its state and registers
 * constants, no call): 1 if the down-counter has the axis this tick
 * (setpoint and following error set), 2 if the setpoint moved under the
 * caller, 0 if nothing. */
FW_INLINE int creep_tick(axis_t *x, stp_t *s, unsigned n, unsigned phase, int32_t old_i, uint16_t old_f)
{
    uint32_t reg = AX_REG(n, 0);
    if (s->creep == CREEP_TRIM) {
        if (x->sp_i == old_i && x->sp_f == old_f && !(x->in & AX_IN_PDONE)) {
            axis_result_set(x, pos_add(old_i, old_f >= 0x8000u));
            return 1;                            /* the trim's pulses still to come */
        }
        creep_stop(x, s, reg);               /* done, or the profile moves on */
        return 0;
    }
    if (x->mode != M_POSITIONING || x->stop_then) {
        stp_creep_abort(n);                      /* a new mode, or a protective stop */
        return 2;
    }
    if (s->creep == CREEP_REQ && phase != 0)
        return 0;                                /* the ramp's last segment still runs */
    if (s->creep == CREEP_REQ || s->creep == CREEP_WAIT)
        creep_begin(x, s, n, reg);
    if (s->creep != CREEP_RUN)
        return 2;
    uint16_t left;
    if (s->hw_done || (x->in & AX_IN_PDONE)) {
        creep_stop(x, s, reg);
        s->creep = CREEP_DONE;
        left = 0;
    } else if (x->ctrl & AX_CTRL_PULSE_IE) {
        left = (uint16_t)(s->creep_n - s->counted);
    } else {
        left = hal_rd16(reg + AX_PULSES);
    }
    int32_t done = (int32_t)(s->creep_n - left);
    axis_result_set(x, pos_add(s->creep_base, s->creep_dir < 0 ? -done : done));
    return 1;
}

#define STP_TRIM_MAX 3              /* stp_trim_at: at most this many steps off the setpoint */

/* The setpoint stands still but the step counter is a step or two off it:
 * the generator's phase (docs/stepper.md).  Those steps at <lv>. */
FW_INLINE void stp_trim_at(const axis_t *x, stp_t *s, unsigned n)
{
    int32_t e = x->ferr;
    if (e < -STP_TRIM_MAX || e > STP_TRIM_MAX || s->creep != CREEP_IDLE) {
        s->rate = 0;
        return;
    }
    int8_t dir = e < 0 ? -1 : 1;
    s->dir = dir;
    s->obits = (uint16_t)((s->obits & ~AX_CTRL_DIR) | stp_dir_bit(x, dir));
    s->carry = 0;
    hal_wr16(AX_REG(n, AX_PULSES), (uint16_t)(e < 0 ? -e : e));
    s->creep = CREEP_TRIM;
    s->rate = s->lv_rate;
}

/* The rate for mag Q16 steps in direction dir (a constant): DIR, and no
 * remainder, when the direction is new. */
FW_INLINE void stp_rate_dir(const axis_t *x, stp_t *s, int8_t dir, uint32_t mag)
{
    if (dir != s->dir) {
        s->dir = dir;
        s->carry = 0;
        s->obits = (uint16_t)((s->obits & ~AX_CTRL_DIR) | stp_dir_bit(x, dir));
    }
    /* |d| <= 0x7FFFFFFF and the carry a 16-bit remainder: the sum cannot wrap */
    stp_load_rate(s, mag + s->carry);
}

/* The step rate for the distance from old_i/old_f to sp_i/sp_f, the
 * setpoint and following error (stp_rate below, without the creep phase).
 * Each test has its common case first: GCC lays a then-block out to fall
 * through, so the moving tick takes no branch back. */
FW_INLINE void stp_rate_on(axis_t *x, stp_t *s, unsigned n, int32_t old_i, uint16_t old_f,
                           int32_t sp_i, uint16_t sp_f)
{
    /* the setpoint of the last tick is where its steps have brought the
     * axis by now (the steps of this tick are still to come, 4.8.1) */
    int32_t di = pos_sub(sp_i, old_i);
    int32_t d;
    if ((uint32_t)di + 30000u <= 60000u)         /* the low word is sp_f's alone */
        d = (int32_t)(((uint32_t)di << 16) | sp_f) - (int32_t)old_f;
    else                                         /* a jump beyond 30000 steps: the largest rate */
        d = di > 0 ? 0x7FFFFFFF : -0x7FFFFFFF;
    int32_t sp = old_i;
    if ((int16_t)old_f < 0)                      /* rounded: a fraction of a half or more */
        sp = pos_add(sp, 1);
    axis_result_set(x, sp);
    if (d > 0) {                                 /* each direction with its constant */
        stp_rate_dir(x, s, 1, (uint32_t)d);
    } else if (d < 0) {
        stp_rate_dir(x, s, -1, (uint32_t)-d);
    } else if (x->ferr && !s->rate && !x->prof.vel && !(stp_conv & (1u << n))) {
        stp_trim_at(x, s, n);                    /* stand-still: the step counter must read the setpoint */
    } else {
        s->rate = 0;
    }
}

/* Every tick, modes with a profile (tick_stp.c stp_axis, after the setpoint
 * interpolation moved it on from old_i/old_f to sp_i/sp_f, both in
 * registers): the creep phase and the trim, else the step rate for this
 * tick's distance - on in the last direction, a new one, stand-still, a
 * jump - inlined with a constant n. */
FW_INLINE void stp_rate(axis_t *x, stp_t *s, unsigned n, unsigned phase, int32_t old_i, uint16_t old_f,
                        int32_t sp_i, uint16_t sp_f)
{
    if (s->creep == CREEP_IDLE) {                /* the common case first, as above */
        stp_rate_on(x, s, n, old_i, old_f, sp_i, sp_f);
        return;
    }
    int c = creep_tick(x, s, n, phase, old_i, old_f);
    if (c == 1)
        return;
    if (c == 2) {                                /* the setpoint moved under us: stand still */
        old_i = sp_i = x->sp_i;
        old_f = sp_f = x->sp_f;
    }
    stp_rate_on(x, s, n, old_i, old_f, sp_i, sp_f);
}

/* axis_output, every tick: DIR, BOOST, TURBO of AX_CTRL; returns the rate. */
FW_INLINE uint16_t stp_output(unsigned n, uint8_t mode, uint16_t *ctrl)
{
    stp_t *s = &stp_ax[n];
    PIN_PTR(s);
    if (mode == M_TEST || (mode == M_DISABLE && (s->rate | (s->obits & AX_CTRL_BOOST))))
        stp_idle_output(n);
    *ctrl = (uint16_t)((*ctrl & ~STP_OBITS) | s->obits);
    return s->rate;
}

/* Level 5 (fw_isr_axis): step pulses and the end of the pulse count, creep
 * phase.  Inline, and one copy per axis with constant addresses: no call,
 * no loop, no registers to save beyond the handler's own. */
FW_INLINE void stp_isr_axis(unsigned k, unsigned p)
{
    if (!(p & (0x11u << k)))
        return;
    stp_t *s = &stp_ax[k];
    axis_t *x = &axes[k];
    uint16_t ack = AX_CTRL_PULSE_ACK;
    if (p & (0x10u << k)) {                      /* the last one is out */
        ack = AX_CTRL_PULSE_ACK | AX_CTRL_DONE_ACK;
        axis_ctrl_set(x, (uint16_t)(x->ctrl & ~(AX_CTRL_PULSE_IE | AX_CTRL_DONE_IE)));
        s->counted = s->creep_n;
        s->hw_done = 1;
    } else {                                     /* every pulse: count it (5.6) */
        s->counted = (uint16_t)(s->creep_n - hal_rd16(AX_REG(k, AX_PULSES)));
    }
    hal_wr16(AX_REG(k, AX_CTRL), (uint16_t)(x->ctrl | ack));
}

FW_INLINE void stp_isr(uint16_t pending)
{
    unsigned prev = hal_irq_save();              /* the tick writes AX_CTRL too */
    unsigned p = ((unsigned)pending >> 4) & 0xFFu;  /* bits 0-3 pulse, 4-7 done */
    stp_isr_axis(0, p);
    stp_isr_axis(1, p);
    stp_isr_axis(2, p);
    stp_isr_axis(3, p);
    hal_irq_restore(prev);
}

#endif
