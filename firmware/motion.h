/* motion.h - modes, profile generator and protective reactions (motion.c and
 * its stages, motion_priv.h). */
#ifndef MOTION_H
#define MOTION_H
#include "inline.h"
#include <stdint.h>
#include "card.h"
#include "stepper.h"            /* stp_plan_t */

/* What an E sets up from its parameters, computed before its masked
 * commit (motion_start): the target from the position of the moment, with
 * interrupts masked (motion_plan_target, from the written <ap>); the gains
 * and <trt> from the activated parameters, and on the STP <ssf> on the rate
 * grid and the creep's rate, unmasked (motion_plan). */
typedef struct {
    servo_gains_t gains;
    uint16_t trt_periods;
    int64_t target;
    int32_t ed_t;           /* <ed> per tick^2, for MRE's ramp (motion_start) */
    stp_plan_t stp;
} motion_plan_t;
void motion_plan_target(unsigned n, uint8_t mode, motion_plan_t *p);
void motion_plan(unsigned n, motion_plan_t *p);
void motion_start(unsigned n, uint8_t mode, uint8_t from, const motion_plan_t *p);  /* at E, interrupts masked */
/* After each command, unmasked: the velocities of the moves it started
 * (vq_compute), which only the main loop reads. */
extern uint8_t motion_vq_due;
void motion_after_command_do(void);
static inline void motion_after_command(void)
{
    if (motion_vq_due)
        motion_after_command_do();
}
void motion_hold(unsigned n);                 /* setpoint := actual position, at rest */
void motion_emergency(unsigned n, uint8_t then);  /* ramp <ed> from the next tick on, then STOP_* */
void motion_drive_fault(unsigned n);          /* ramp <ed>, disable when the setpoint stands (6.3.4) */
void motion_brake(unsigned n);                /* ramp <pd> from the next tick on (stop bits) */
void motion_profile_tick(unsigned n);         /* main loop, once per SP: the next segment */
void motion_supervise(unsigned n);            /* main loop, after every tick: index, protection */
int motion_busy(unsigned n);                  /* a move that off-fly waits for (5.15) */
int motion_at_rest(unsigned n);

/* Nothing for motion_supervise() to do after this tick: no brake under way,
 * no index latched, no limit bit, the following error within <mf> and a
 * linear axis within its software limits (or a protective stop already
 * running).  The common case, tested inline by card_supervise(); it must
 * stay a subset of what motion_supervise() would leave alone. */
FW_INLINE int motion_quiet(const axis_t *x)
{
    if (x->braking || (x->ustat & (UB(HWL_P) | UB(HWL_N) | UB(SWL_P) | UB(SWL_N))))
        return 0;
    if ((x->in & AX_IN_IDX) && !x->idx_seen &&
        (x->mode == M_SEARCH_IDX_C || x->mode == M_SEARCH_IDX || x->mode == M_HOME))
        return 0;                                 /* an index latched during a search */
    if (x->stop_then)
        return !x->stop_settle;                   /* a stop waiting for rest: stop_watch() */
    int32_t mf = x->mf;
    if (x->ferr > mf || x->ferr < -mf)
        return 0;
    return !x->linear || (x->pos <= x->lp && x->pos >= x->ln);
}

#endif
