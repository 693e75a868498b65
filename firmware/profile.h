/*
 * profile.h - the profile generator's arithmetic (manual 5.6, 4.8.4):
 * trapezoidal or triangular moves and velocity ramps, one step per
 * profile sampling period SP.  Positions and velocities are 64-bit Q16
 * (1/65536 increment or step; velocity per SP), so <sf>-scaled fractional
 * velocities (4.8.4) keep their bits.  Only 16x16 multiplies, no division.
 */
#ifndef PROFILE_H
#define PROFILE_H
#include <stdint.h>
#include "mul16.h"

typedef struct {
    int64_t pos;    /* Q16 */
    int64_t vel;    /* Q16 per SP, signed */
} prof_t;

/* One SP of a move to target with speed limit vmax, acceleration acc and
 * braking ramp dec (all > 0, Q16).  Lands exactly on target; returns 1
 * once there with velocity 0. */
int prof_position(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec);
/* The same, told that from a rest beyond `free` (> 0) no speed up to vmax
 * needs braking yet (prof_free_distance): the braking test is skipped
 * there, with the same result. */
int prof_position_free(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec, int64_t free);
/* The same for vmax, acc and dec below 2^30 (Q16 per SP), told so: in 32
 * bits while the rest to go is below 2^31 (the braking phase, short moves). */
int prof_position_fit(prof_t *p, int64_t target, int32_t vmax, int32_t acc, int32_t dec, int64_t free);
/* The same step in 64 bits throughout: the reference the 32-bit path of
 * prof_position_free() is tested against, and its fallback. */
int prof_position_ref(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec, int64_t free);
/* The step prof_position_free() takes far from the target (rest beyond
 * `free`) at most at vmax towards it: accelerate by acc up to vmax, no test.
 * Returns 0 where that does not apply (nothing changed), 1 when it moved p.
 * Inline: it is the profile generator's common case. */
static inline int prof_cruise(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t free)
{
    if (free <= 0)
        return 0;
    int64_t rem = target - p->pos, v = p->vel, up;
    if (rem > free && v >= 0 && v <= vmax) {
        up = v + acc < vmax ? v + acc : vmax;
        if (up > 0 && up < rem) {
            p->vel = up;
            p->pos += up;
            return 1;
        }
    } else if (-rem > free && v <= 0 && -v <= vmax) {
        up = -v + acc < vmax ? -v + acc : vmax;
        if (up > 0 && up < -rem) {
            p->vel = -up;
            p->pos -= up;
            return 1;
        }
    }
    return 0;
}
/* prof_cruise for vmax and acc below 2^30 and free >= vmax (so that the
 * step never reaches the target), told the limits hi = target - free and
 * lo = target + free (rest beyond free: pos < hi, or pos > lo going back):
 * the speeds in 32 bits, one 64-bit comparison, the same result.  Returns
 * the step taken (0: does not apply, nothing changed). */
static inline int32_t prof_cruise32(prof_t *p, int64_t hi, int64_t lo, int32_t vmax, int32_t acc)
{
    int32_t v = (int32_t)p->vel, up;
    if (p->vel != v)
        return 0;
    if (p->pos < hi && v >= 0 && v <= vmax) {
        up = v < vmax - acc ? v + acc : vmax;
        if (up > 0) {
            p->vel = up;
            p->pos += up;
            return up;
        }
    } else if (p->pos > lo && v <= 0 && -v <= vmax) {
        up = -v < vmax - acc ? -v + acc : vmax;
        if (up > 0) {
            p->vel = -up;
            p->pos -= up;
            return -up;
        }
    }
    return 0;
}
/* The largest rest from which prof_must_brake(v, dec, rest) may still be 1
 * for some 0 <= v <= vmax; beyond it it is 0.  Main loop: it divides. */
int64_t prof_free_distance(int64_t vmax, int64_t dec);
/* One SP of a velocity ramp towards vt: acc while the speed grows, dec
 * while it falls.  Returns 1 when vel == vt. */
int prof_ramp(prof_t *p, int64_t vt, int64_t acc, int64_t dec);
/* Would a stop from speed v (>= 0) with ramp dec cover at least rem?
 * Exposed for the tests. */
int prof_must_brake(int64_t v, int64_t dec, int64_t rem);
/* The same for 0 <= v, dec < 2^30 and rem < 2^32: (v8 (v8 + d8)) >> 1 >=
 * d8 r8 is v8 (v8 + d8) >= d8 (2 r8), and nothing saturates in this range;
 * two or three MULU.W (mulu31) instead of two 32 x 32 products. */
static inline __attribute__((always_inline)) int prof_must_brake32(uint32_t v, uint32_t dec, uint32_t rem)
{
    uint32_t v8 = v >> 8, d8 = dec >> 8, r8 = rem >> 8;
    if (d8 == 0)
        d8 = 1;
    uint32_t h1, l1, h2, l2;
    mulu31(v8, v8 + d8, &h1, &l1);
    mulu31(d8, r8 << 1, &h2, &l2);
    return h1 > h2 || (h1 == h2 && l1 >= l2);
}
uint64_t prof_umul32(uint32_t a, uint32_t b);

#endif
