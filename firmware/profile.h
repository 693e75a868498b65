/*
 * profile.h - the profile generator's arithmetic (manual 5.6, 4.8.4):
 * trapezoidal or triangular moves and velocity ramps, one step per
 * profile sampling period SP.  Positions and velocities are 64-bit Q16
 * (1/65536 increment or step; velocity per SP), so <sf>-scaled fractional
 * velocities (4.8.4) keep their bits.  Only 16x16 multiplies, no division.
 */
#ifndef PROFILE_H
#define PROFILE_H
#include "inline.h"
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
/* The limits of a move for the 32-bit step, computed once per change of
 * <pv>, <pa>, <pd> (prof_lim32): vmax, acc, dec below 2^30 (Q16 per SP);
 * d8 the braking test's dec >> 8 (at least 1); free32 the rest beyond which
 * no braking test is needed, or 2^32 - 1 (none within 32 bits); free the
 * same for the 64-bit fallback (0: unknown). */
typedef struct {
    int32_t vmax, acc, dec;
    uint32_t d8;
    uint32_t free32;
    int64_t free;
} prof_lim32_t;
void prof_lim32(prof_lim32_t *l, int32_t vmax, int32_t acc, int32_t dec, int64_t free);
/* The same step for limits below 2^30, told so: in 32 bits (prof_step32)
 * while the rest to go is below 2^32 (the braking phase, moves of up to
 * 65 535 increments or steps, a change of course near the target). */
int prof_position_fit(prof_t *p, int64_t target, const prof_lim32_t *l);
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
/* The speed to try next from v (>= 0) towards the target: v + acc up to
 * vmax, or down to vmax by dec where <pv> was lowered on the fly (the 64-bit
 * steps: prof_position_ref, the STP's positioning step; prof_step32 has it
 * in 32 bits). */
static inline int64_t prof_up(int64_t v, int64_t vmax, int64_t acc, int64_t dec)
{
    if (v < vmax)
        return v + acc < vmax ? v + acc : vmax;
    if (v > vmax)
        return v - dec > vmax ? v - dec : vmax;
    return v;
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
/* prof_must_brake for 0 <= v < 2^30, rem < 2^32 and d8 = max(dec >> 8, 1),
 * dec < 2^30: (v8 (v8 + d8)) >> 1 >= d8 r8 is v8 (v8 + d8) >= d8 (2 r8), and
 * nothing saturates in this range; two or three MULU.W (mulu31) instead of
 * two 32 x 32 products.  It grows with v: where it holds for v it holds for
 * every faster speed. */
FW_INLINE int prof_brake_d8(uint32_t v, uint32_t d8, uint32_t rem)
{
    uint32_t v8 = v >> 8, r8 = rem >> 8, vd = v8 + d8;
    if (vd < 0x10000u && r8 < 0x800000u) {
        /* the usual range (speeds and ramps below 256 per SP, rests below
         * 2^15): v8 (v8 + d8) is one MULU.W, d8 (2 r8) two, below 2^40 */
        uint32_t l = mulu16((uint16_t)v8, (uint16_t)vd), r2 = r8 << 1;
        uint32_t rl = mulu16((uint16_t)d8, (uint16_t)r2);
        if (r2 < 0x10000u)
            return l >= rl;
        uint32_t rh = mulu16((uint16_t)d8, (uint16_t)(r2 >> 16));
        if (rh >> 16)
            return 0;                            /* d8 (2 r8) >= 2^32 > l */
        uint32_t r = (rh << 16) + rl;
        return r >= rl && l >= r;                /* (a carry: >= 2^32) */
    }
    uint32_t h1, l1, h2, l2;
    mulu31(v8, v8 + d8, &h1, &l1);
    mulu31(d8, r8 << 1, &h2, &l2);
    return h1 > h2 || (h1 == h2 && l1 >= l2);
}
FW_INLINE uint32_t prof_d8(uint32_t dec)
{
    return dec >> 8 ? dec >> 8 : 1u;
}
FW_INLINE int prof_must_brake32(uint32_t v, uint32_t dec, uint32_t rem)
{
    return prof_brake_d8(v, prof_d8(dec), rem);
}

/* Does prof_step32 apply: rem = target - pos within +-(2^32 - 1), the
 * velocity within +-2^30? */
FW_INLINE int prof_fits32(const prof_t *p, int64_t rem)
{
    /* by the words: a 64-bit comparison is a dozen 68000 instructions */
    int32_t rh = (int32_t)(rem >> 32), vh = (int32_t)(p->vel >> 32);
    uint32_t rl = (uint32_t)rem, vl = (uint32_t)p->vel;
    if (rh != 0 && (rh != -1 || rl == 0))
        return 0;
    return vh == 0 ? vl < 0x40000000u : vh == -1 && vl > 0xC0000000u;
}

/* One SP of prof_position_ref() where prof_fits32(p, rem), rem = target -
 * pos, with the speeds in 32 bits and the rest as its sign and 32-bit
 * magnitude, with the limits of prof_lim32: the same result (the unit test
 * compares them).  *step is the SP's motion (below 2^30 either way); returns
 * 1 on landing.  One braking test per SP while accelerating or braking:
 * where the speed of the moment must brake, a faster one must too.  Inline:
 * the profile generator's braking and landing step. */
FW_INLINE int prof_step32(prof_t *p, int64_t rem64, const prof_lim32_t *l,
                                                             int32_t *step)
{
    int32_t vel = (int32_t)p->vel;
    int neg = rem64 < 0;
    uint32_t rem = neg ? 0u - (uint32_t)rem64 : (uint32_t)rem64;   /* |rest| < 2^32 */
    if (rem == 0 && vel == 0) {
        *step = 0;
        return 1;
    }
    int32_t v = neg ? -vel : vel;                /* speed towards the target */
    int32_t dec = l->dec;
    if (v < 0) {                                 /* moving away: turn round first */
        v += dec;
        if (v > 0)
            v = 0;
    } else {
        int32_t vmax = l->vmax, up = v;
        int quick = rem > l->free32 && v <= vmax;   /* no braking test needed */
        uint32_t d8 = l->d8;
        if (v < vmax) {
            up = v + l->acc;
            if (up > vmax)
                up = vmax;
        } else if (v > vmax) {                   /* <pv> lowered on the fly */
            up = v - dec;
            if (up < vmax)
                up = vmax;
        }
        /* the fastest of accelerate / hold / brake from which a stop with
         * <dec> still ends at the target */
        int brake;
        if (quick)
            brake = up <= 0;
        else if (up > v && v > 0)                /* accelerating: test v first */
            brake = prof_brake_d8((uint32_t)v, d8, rem) ? 1 : (prof_brake_d8((uint32_t)up, d8, rem) ? (up = v, 0) : 0);
        else if (up > 0 && !prof_brake_d8((uint32_t)up, d8, rem))
            brake = 0;
        else
            brake = 1;                           /* (v: the same test, or v > vmax, or v = 0) */
        if (brake) {
            v -= dec;
            if (v < dec)
                v = dec;                         /* creep: never stop short */
        } else {
            v = up;
        }
        if (v > 0 && (uint32_t)v > rem)
            v = (int32_t)rem;                    /* land exactly (rem < v < 2^30) */
        if (v <= 0)
            v = rem < (uint32_t)dec ? (int32_t)rem : dec;
    }
    int landed = v >= 0 && (uint32_t)v == rem;
    int32_t s = neg ? -v : v;
    *step = s;
    p->pos += s;
    p->vel = landed ? 0 : s;
    return landed;
}
uint64_t prof_umul32(uint32_t a, uint32_t b);

#endif
