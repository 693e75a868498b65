/*
 * motion_priv.h - what the motion files share among themselves, not for
 * use outside them (motion.h is the interface): the profile generator's
 * velocity cache, the tick's brake hand-back, the ramp of every mode.
 *   motion.c            a mode set up at E, the velocity cache, the brakes,
 *                       the protective stops begun
 *   motion_profile.c    the profile generator, once per SP: the next segment
 *   motion_justify.c    its justification modes (5.7-5.10)
 *   motion_supervise.c  after every tick: index latch, protective reactions,
 *                       the end of a stop
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
void stop_done(unsigned n);                    /* a protective stop has ended (motion_supervise.c) */
void pos_end_check(unsigned n);                /* 5.6: <tr> for <trt> (motion_profile.c) */

void justify_modes(unsigned n);                /* one SP of 5.7-5.10 (motion_justify.c) */

#endif
