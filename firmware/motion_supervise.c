/*
 * motion_supervise.c - the profile generator's side of the supervision
 * after every tick (supervise.c calls motion_supervise unless motion_quiet):
 * the index latch of the searches and the protective reactions (4.8, 6.3);
 * the end of a protective stop and its guards are motion.c's, which owns
 * the stop (stop_done; motion_priv.h stop_watch, inlined here).
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "motion.h"
#include "motion_priv.h"

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
        index_latched(x, index_edge_card(x, n, d));   /* STP: increments -> steps */
    }

    /* protective reactions (4.8, 6.3) */
    if (!x->stop_then) {
        int32_t mf = x->mf;
        if (x->ferr > mf || x->ferr < -mf) {     /* 4.8.1, 6.3.9 */
            axis_error(n, UB(FERR_F), ERR_LOGICAL);
            motion_emergency_ferr(n);            /* raised once: its guard raises nothing more */
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
