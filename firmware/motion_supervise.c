/*
 * motion_supervise.c - the profile generator's side of the supervision
 * after every tick (supervise.c calls motion_supervise unless motion_quiet):
 * the index latch of the searches, the protective reactions (4.8, 6.3) and
 * the end of a protective stop, with the guards of a stop that waits for
 * the mechanics at rest.
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "motion.h"
#include "motion_priv.h"

/* A protective stop has ramped down (and, if it waits for it, the mechanics
 * stand): what follows it (4.8). */
void stop_done(unsigned n)
{
    axis_t *x = axis_at[n];
    if (x->stop_then == STOP_HOLD) {
        axis_set_mode(n, M_BRAKE);
    } else {
        uint8_t then = x->stop_then;
        axis_disable(n);
        if (then == STOP_DEINIT)
            x->ustat &= ~UB(INIT);
    }
    x->stop_then = STOP_NONE;
    x->stop_settle = 0;
    x->done = 1;
}

/* After every tick of a stop that waits for the mechanics (stop_settle):
 * the loop brakes them to rest and holds the braked setpoint; the axis is
 * disabled once the measured speed has stayed near 0 for STOP_REST_TICKS.
 * The guards against a loop that cannot stop them (6.3.9: a reversed or
 * frozen encoder, a motor that cannot follow <ed>): /EN opens at once, with
 * ferr_f and 163, when the following error grows beyond its value at the
 * start of the stop plus <mf>/2, or beyond that value in STOP_GROW_TICKS
 * ticks in a row without the mechanics slowing down, when the axis measures no motion with more than <mf>
 * still to go, or when twice the ticks of the setpoint's ramp plus
 * STOP_SETTLE_TICKS have passed.  1: the stop has ended. */
static int stop_watch(axis_t *x, unsigned n)
{
    if (x->stop_ticks < UINT16_MAX)
        x->stop_ticks++;
    int32_t e = x->ferr < 0 ? -x->ferr : x->ferr, av = x->vel < 0 ? -x->vel : x->vel;
    /* growing instead of shrinking: beyond its start, tick after tick, and
     * the mechanics not slowing down (an overshoot slows down; a loop with
     * its sign reversed speeds up or runs at its limit) */
    if (e > x->stop_f0 && e > x->stop_flast + STOP_REST_VEL && av + STOP_REST_VEL >= x->stop_vlast)
        x->stop_grow++;
    else
        x->stop_grow = 0;
    x->stop_flast = e;
    x->stop_vlast = av;
    int over = e > x->stop_fmax || x->stop_grow >= STOP_GROW_TICKS;
    if (!over && x->braking)
        return 0;                                /* the setpoint's ramp runs */
    if (!over) {
        int32_t v = x->vel;
        if (v <= STOP_REST_VEL && v >= -STOP_REST_VEL) {
            /* standing with more than <mf> to go: the feedback does not follow
             * the output (frozen or stuck encoder, a jammed motor) */
            over = e > x->mf;
            if (!over && ++x->stop_rest >= STOP_REST_TICKS) {
                stop_done(n);                    /* at rest: now disable */
                return 1;
            }
        } else {
            x->stop_rest = 0;
        }
        if (!over && x->stop_ticks <= x->stop_limit)
            return 0;
    }
    /* runaway or too slow: open /EN now, a following error - but not a
     * second one when the stop is the following error's own reaction: that
     * was raised once, and a C during the braking has acknowledged it */
    if (!x->stop_ferr)
        axis_error(n, UB(FERR_F), ERR_LOGICAL);
    stop_done(n);
    return 1;
}

/* ---- after every tick, in the main loop --------------------------------
 * What the tick measured, checked before the main loop does anything else
 * (card_supervise): the index latch of the searches and the protective
 * reactions.  They act through the profile generator's ramps, whose next SP
 * is still ahead, and through axis_disable(), which opens /EN at once: the
 * reaction is within the servo period of the event, as in the tick. */
void motion_supervise(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    if (x->mode == M_DISABLE || x->mode == M_TEST)
        return;
    if (x->braking && x->br_v == 0) {            /* the tick's ramp has ended: act now */
        brake_done(x);                           /* (a stop waiting for rest: its time bound) */
        if (!x->stop_settle && x->stop_then)
            stop_done(n);
        if (x->mode == M_DISABLE)
            return;
    }
    if (x->stop_settle && stop_watch(x, n))
        return;                                  /* disabled */
    /* the index latch, for the searches (the rare bit first) */
    if ((x->in & AX_IN_IDX) && !x->idx_seen &&
        (x->mode == M_SEARCH_IDX_C || x->mode == M_SEARCH_IDX || (x->mode == M_HOME && x->phase == 3))) {
        uint32_t hi = hal_rd16(AX_REG(n, AX_IDX_HI));
        uint32_t raw = (hi << 16) | hal_rd16(AX_REG(n, AX_IDX_LO));
        int32_t d = (int32_t)((raw - x->counter) << 8) >> 8;   /* 24-bit counter */
        x->edge = index_edge_card(x, n, d);      /* STP: increments -> steps */
        x->idx_seen = 1;
    }

    /* protective reactions (4.8, 6.3) */
    if (!x->stop_then) {
        int32_t mf = x->mf;
        if (x->ferr > mf || x->ferr < -mf) {     /* 4.8.1, 6.3.9 */
            axis_error(n, UB(FERR_F), ERR_LOGICAL);
            motion_emergency(n, STOP_DISABLE);
            x->stop_ferr = 1;                    /* raised once: its guard raises nothing more */
        } else if (x->linear && (x->pos > x->lp || x->pos < x->ln)) {
            x->ustat |= x->pos > x->lp ? UB(SWL_P) : UB(SWL_N);
            axis_error(n, UB(LOGO_F), ERR_LOGICAL);   /* 4.3.1.1: braked and disabled; C first (6.3) */
            motion_emergency(n, STOP_DISABLE);
        } else if (x->ustat & (UB(HWL_P) | UB(HWL_N))) {
            /* hardware limits stop motion into the switch, not out of it, in
             * every mode (test mode: supervise.c axis_inputs); find edge may run into the one
             * limit switch it looks for (<dl> 1, 2), to its edge */
            int64_t v = x->prof.vel;
            int dir = v > 0 ? 1 : v < 0 ? -1 : 0;
            if (!dir)
                dir = creep_dir_card(n);         /* STP: the creep phase's pulses (5.6): the profile stands */
            uint32_t into = x->ustat & (dir > 0 ? UB(HWL_P) : dir < 0 ? UB(HWL_N) : 0);
            if (x->mode == M_FIND_EDGE) {
                int32_t dl = PAR(n, DL);
                into &= ~(dl == 1 ? UB(HWL_N) : dl == 2 ? UB(HWL_P) : 0);
            }
            if (into) {
                axis_error(n, UB(LOGO_F), ERR_LOGICAL);   /* C first (6.3), then out of the switch */
                motion_emergency(n, STOP_HOLD);
            }
        }
    }
    if ((x->ustat & (UB(SWL_P) | UB(SWL_N))) && x->pos >= x->ln && x->pos <= x->lp)
        x->ustat &= ~(UB(SWL_P) | UB(SWL_N));
}
