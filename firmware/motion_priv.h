/*
 * motion_priv.h - what the motion files share among themselves, not for
 * use outside them (motion.h is the interface): the profile generator's
 * velocity cache, the tick's brake hand-back, the ramp of every mode.
 *   motion.c            a mode set up at E, the velocity cache, the brakes,
 *                       the protective stops: begun, watched, ended
 *   motion_profile.c    the profile generator, once per SP: the next segment
 *   motion_justify.c    its justification modes (5.7-5.10)
 *   motion_supervise.c  after every tick: index latch, protective reactions
 */
#ifndef MOTION_PRIV_H
#define MOTION_PRIV_H
#include "inline.h"
#include "card.h"
#include "params.h"
#include "profile.h"
#include "stepper.h"

#define Q16(x) ((int64_t)(x) * 65536)

static inline int64_t meas_q(unsigned n) { return Q16(axes[n].meas); }
static inline int at_rest(const axis_t *x) { return x->prof.vel == 0 && !x->braking; }

/* the card variant's hooks (vq, ramp, ...), which use the above */
#include "motion_card.h"

void vq_compute(unsigned n);                   /* the cached vq() values (axis_t q_*) */

/* The cached vq() values: recomputed when a parameter of the axis changed
 * (par_gen), TURBO changed (STP, 4.1.3: x10; vq_turbo), and at E (the
 * cruise limits follow the target). */
FW_INLINE void vq_refresh_x(axis_t *x, unsigned n)
{
    if (x->q_gen != par_gen[n] || x->q_turbo != vq_turbo(x))
        vq_compute(n);
}
#define vq_refresh(n) vq_refresh_x(axis_at[n], (n))

int64_t target_of(unsigned n, int32_t user);   /* a user position (with <ao>) as a target */
void arm_index(unsigned n);                    /* the index latch for a search */
void brake_done(axis_t *x);                    /* the tick's brake stands: the profile goes on */
void stop_done(unsigned n);                    /* a protective stop has ended */
/* 4.8.1: the stop that reacts to a following error, which the supervision
 * has raised (motion_supervise.c): its guard raises nothing more. */
FW_INLINE void motion_emergency_ferr(unsigned n)
{
    motion_emergency(n, STOP_DISABLE);
    axis_at[n]->stop_ferr = 1;
}
/* The move of the mode in force is complete, or not yet (the profile
 * generator's steps, motion_profile.c, motion_justify.c): what motion_busy
 * and off-fly wait for; motion_start clears it at E. */
FW_INLINE void mode_done(axis_t *x, int done)
{
    x->done = (uint8_t)done;
}
/* A justification mode has found its edge at position edge (motion_justify.c). */
FW_INLINE void edge_found(axis_t *x, int32_t edge)
{
    x->edge = edge;
}
/* The index latched during a search at the position edge (motion_supervise.c). */
FW_INLINE void index_latched(axis_t *x, int32_t edge)
{
    x->edge = edge;
    x->idx_seen = 1;
}
void pos_end_check(unsigned n);                /* 5.6: <tr> for <trt> (motion_profile.c) */
/* ... the SP in a row within <tr> of the target, which motion_start zeroes at E */
FW_INLINE void trt_count_step(axis_t *x) { x->trt_count++; }
FW_INLINE void trt_count_reset(axis_t *x) { x->trt_count = 0; }

void justify_modes(unsigned n);                /* one SP of 5.7-5.10 (motion_justify.c) */
/* The phase of a justification mode (5.7, 5.9, 5.10: the steps of each
 * diagram), which motion_start zeroes at E (motion_justify.c). */
FW_INLINE void justify_phase(axis_t *x, uint8_t phase)
{
    axis_phase_set(x, phase);                   /* card.h: the byte is the STP's creep's too */
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
 * STOP_SETTLE_TICKS have passed.  1: the stop has ended.  Inline in
 * motion_supervise, after every tick of the stop, as it was there. */
FW_INLINE int stop_watch(axis_t *x, unsigned n)
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

#endif
