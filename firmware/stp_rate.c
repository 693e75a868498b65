/*
 * stp_rate.c - the MAC4-STP's step-rate stage: the rate register for a
 * tick's distance is stepper.h's stp_rate (inline in the tick); here the
 * creep phase of positioning (5.6, diagram 5.2) and the end of the trim at
 * stand-still, the output of a disabled or tested axis (5.13), ROUT.  The
 * STP's image alone links it (Makefile, FW_STP).
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "stepper.h"
#include "stp_rate.h"

#include "card.h"
#include "params.h"
#include "motion.h"
#include "stp_card.h"

/* The creep's pulses are counted by interrupt up to 1000 Hz (rate register
 * 1311, TURBO 131); faster, the tick reads the down-counter instead. */
#define PULSE_IRQ_MAX_RATE 1311u
#define PULSE_IRQ_MAX_RATE_TURBO 131u

/* stp_edge() with the axis' pointers at hand (the tick's creep path). */
FW_INLINE int32_t edge_of(const axis_t *x, const stp_t *s, unsigned n, int32_t d)
{
    if (stp_conv & (1u << n))
        return stp_scale_call(pos_add(s->inc, d), s->ratio);   /* a creep's start, an index: a call */
    return pos_add(x->meas, (x->ustat & UB(REV_O)) ? -d : d);
}

int32_t stp_edge(unsigned n, int32_t d) { return edge_of(&axes[n], &stp_ax[n], n, d); }

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

/* ---- the creep phase ------------------------------------------------------ */
static void creep_stop(axis_t *x, stp_t *s, uint32_t reg)   /* reg: AX_REG(n, 0) */
{
    if (s->creep == CREEP_RUN || s->creep == CREEP_TRIM) {
        hal_wr16(reg + AX_RATE, 0);
        hal_wr16(reg + AX_PULSES, 0);                       /* free running again */
        s->rate = 0;
        s->carry = 0;
    }
    axis_ctrl_set(x, (uint16_t)(x->ctrl & ~(AX_CTRL_PULSE_IE | AX_CTRL_DONE_IE)));
    hal_wr16(reg + AX_CTRL, (uint16_t)(x->ctrl | AX_CTRL_PULSE_ACK | AX_CTRL_DONE_ACK));
    s->creep = CREEP_IDLE;
    s->hw_done = 0;
}

/* A creep broken off (a new mode, a protective stop): the profile goes on
 * from where the steps are. */
void stp_creep_abort(unsigned n)
{
    uint8_t c = stp_ax[n].creep;
    creep_stop(&axes[n], &stp_ax[n], AX_REG(n, 0));
    if (c != CREEP_DONE)
        motion_hold(n);
}

/* Tick: the ramp has ended on creep_from, the generator still runs at the
 * ramp's last rate (at most <ssf>). */
FW_INLINE void creep_begin(axis_t *x, stp_t *s, unsigned n, uint32_t reg)
{
    hal_wr16(reg + AX_RATE, 0);                  /* no pulse while we count */
    s->rate = 0;
    int32_t cur = meas_now(x, s, n);
    int32_t miss = (int32_t)(x->target >> 16) - cur;
    if (s->creep == CREEP_REQ) {
        /* the profile's creep segment is the down-counter's: the setpoint is at its end */
        x->start_i = x->sp_i = x->end_i;
        x->start_f = x->sp_f = x->end_f;
        x->st_i = 0;
        x->st_f = 0;
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
    s->creep_irq = s->lv_rate <= (s->clocks == STP_TICK_CLOCKS ? PULSE_IRQ_MAX_RATE : PULSE_IRQ_MAX_RATE_TURBO);
    if (s->creep_irq)
        axis_ctrl_set(x, (uint16_t)(x->ctrl | AX_CTRL_PULSE_IE));
    s->rate = s->lv_rate;                        /* DIR and rate go out in axis_output */
    s->creep = CREEP_RUN;
}

/* Tick, while a creep or a trim is requested or running: 1 if the
 * down-counter has the axis this tick, 2 if the setpoint moved under the
 * caller, 0 if nothing. */
FW_INLINE int creep_tick(axis_t *x, stp_t *s, unsigned n, unsigned phase,
                                                            int32_t old_i, uint16_t old_f)
{
    uint32_t reg = AX_REG(n, 0);
    if (s->creep == CREEP_TRIM) {
        if (x->sp_i == old_i && x->sp_f == old_f && !(x->in & AX_IN_PDONE)) {
            axis_result_set(x, pos_add(old_i, old_f >= 0x8000u));
            return 1;                            /* the trim's pulses still to come */
        }
        creep_stop(x, s, reg);                   /* done, or the profile moves on */
        return 0;
    }
    if (x->mode != M_POSITIONING || x->stop_then) {
        stp_creep_abort(n);                          /* a new mode, or a protective stop */
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

/* The direction of the creep phase's pulses while they run (the profile
 * stands meanwhile): for the limit switches (motion_supervise). */
int stp_creep_dir(unsigned n)
{
    const stp_t *s = &stp_ax[n];
    return s->creep == CREEP_RUN ? s->creep_dir : 0;
}

/* creep_tick per axis, for the tick's rate stage (stepper.h stp_rate) */
FW_INLINE int creep_tick_at(unsigned n, unsigned phase, int32_t old_i, uint16_t old_f)
{
    axis_t *x = &axes[n];
    stp_t *s = &stp_ax[n];
    PIN_PTR(x);                                  /* fields at d16(An), not absolute addresses */
    PIN_PTR(s);
    return creep_tick(x, s, n, phase, old_i, old_f);
}
int stp_creep_tick_0(unsigned phase, int32_t old_i, uint16_t old_f) { return creep_tick_at(0, phase, old_i, old_f); }
int stp_creep_tick_1(unsigned phase, int32_t old_i, uint16_t old_f) { return creep_tick_at(1, phase, old_i, old_f); }
int stp_creep_tick_2(unsigned phase, int32_t old_i, uint16_t old_f) { return creep_tick_at(2, phase, old_i, old_f); }
int stp_creep_tick_3(unsigned phase, int32_t old_i, uint16_t old_f) { return creep_tick_at(3, phase, old_i, old_f); }

/* axis_output, disabled (with something to switch off) or in test mode. */
void stp_idle_output(unsigned n)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    if (x->mode == M_TEST) {
        /* 5.13: <da> in Hz straight to the generator, no profile, no USR */
        int32_t da = PAR(n, DA);
        s->rate = stp_rate_hz((uint32_t)(da < 0 ? -da : da));
        if (da)
            s->dir = da < 0 ? -1 : 1;
        s->obits = (uint16_t)((s->obits & AX_CTRL_TURBO) | (s->dir >= 0 ? AX_CTRL_DIR : 0));
        s->active = s->boost = s->boost_en = 0;
        return;
    }
    if (s->creep != CREEP_IDLE)
        creep_stop(x, s, AX_REG(n, 0));
    s->rate = 0;
    s->carry = 0;
    s->active = s->boost = s->boost_en = 0;
    s->obits &= (uint16_t)~AX_CTRL_BOOST;
}

/* ROUT in Steps/SP (table 6.2): the frequency of the moment x 32 ms,
 * rounded, 4 hz / 125 (|hz| <= 500 kHz: the quotient fits DIVU's 16 bits) */
int32_t stp_out_steps_sp(unsigned n)
{
    int32_t hz = stp_hz_now(n);
    uint32_t a = (uint32_t)(hz < 0 ? -hz : hz);
    int32_t q = (int32_t)(uint16_t)divu16(4u * a + 62u, 125u);
    return hz < 0 ? -q : q;
}
