/*
 * stp_rate.c - the MAC4-STP's step-rate stage: the rate register for a
 * tick's distance is stp_rate.h's stp_rate and the creep phase's tick part
 * stp_rate.h's creep_tick (both inline in the tick); here the end of a
 * creep phase (5.6, diagram 5.2) or of the trim, its abort, the output of a
 * disabled or tested axis (5.13).  The STP's image alone links it
 * (Makefile, FW_STP).
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

int32_t stp_edge(unsigned n, int32_t d) { return edge_of(&axes[n], &stp_ax[n], n, d); }

/* ---- the creep phase: its tick part is stp_rate.h's (creep_tick) ----------- */
void creep_stop(axis_t *x, stp_t *s, uint32_t reg)   /* reg: AX_REG(n, 0) */
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

/* The direction of the creep phase's pulses while they run (the profile
 * stands meanwhile): for the limit switches (motion_supervise). */
int stp_creep_dir(unsigned n)
{
    const stp_t *s = &stp_ax[n];
    return s->creep == CREEP_RUN ? s->creep_dir : 0;
}

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
