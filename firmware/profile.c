#include "profile.h"
#include "mul16.h"

/* 32 x 32 -> 64 unsigned from four MULU.W (the 68000 has no 32-bit multiply). */
uint64_t prof_umul32(uint32_t a, uint32_t b)
{
    uint16_t ah = (uint16_t)(a >> 16), al = (uint16_t)a, bh = (uint16_t)(b >> 16), bl = (uint16_t)b;
    uint64_t hh = mulu16(ah, bh), hl = mulu16(ah, bl), lh = mulu16(al, bh), ll = mulu16(al, bl);
    return (hh << 32) + (hl << 16) + (lh << 16) + ll;
}

static uint32_t sat32(int64_t x) { return x > 0xFFFFFFFFll ? 0xFFFFFFFFu : (uint32_t)x; }

/* Stopping from v in steps v-d, v-2d, ... covers about v^2/(2d) + v/2.
 * Brake when v^2 + v d >= 2 d rem, compared in Q8 (the low 8 fraction
 * bits do not change the decision by more than a step). */
int prof_must_brake(int64_t v, int64_t dec, int64_t rem)
{
    uint32_t v8 = sat32(v >> 8), d8 = sat32(dec >> 8), r8 = sat32(rem >> 8);
    if (d8 == 0)
        d8 = 1;
    uint32_t vd = v8 + d8 < v8 ? 0xFFFFFFFFu : v8 + d8;
    uint64_t lhs = prof_umul32(v8, vd);
    uint64_t rhs = prof_umul32(d8, r8);
    return (lhs >> 1) >= rhs;                   /* lhs >= 2 rhs, without overflowing 2 rhs */
}

int64_t prof_free_distance(int64_t vmax, int64_t dec)
{
    /* prof_must_brake is 0 iff d8 r8 > (v8 (v8 + d8)) / 2, i.e. r8 >= q with
     * q = half / d8 + 1; it grows with v, so vmax decides for every v below.
     * No division: half >> (bits of d8 - 1) is at least half / d8, at most
     * twice it, so the distance is safe and at most twice the braking one. */
    uint32_t v8 = sat32(vmax >> 8), d8 = sat32(dec >> 8);
    if (d8 == 0)
        d8 = 1;
    uint32_t vd = v8 + d8 < v8 ? 0xFFFFFFFFu : v8 + d8;
    unsigned k = 0;
    while ((d8 >> k) > 1u)
        k++;
    uint64_t q = (prof_umul32(v8, vd) >> 1 >> k) + 1;
    if (q > 0xFFFFFFFFull)
        return INT64_MAX;                          /* never free */
    return (int64_t)(q << 8) - 1;                  /* rem > this <=> sat32(rem >> 8) >= q */
}

int prof_position(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec)
{
    return prof_position_free(p, target, vmax, acc, dec, 0);
}

/* ---- the same step in 32 bits ----------------------------------------------
 * Less than 2^32 to go (Q16: 65 536 increments), speeds and ramps below
 * 2^30: the braking phase of every move and whole short moves need no 64-bit
 * arithmetic, and the braking test is two or three MULU.W (mulu31) instead
 * of two 32 x 32 products (prof_step32 in profile.h).  The results are those
 * of the 64-bit step (prof_position_ref, tests/unit/test_profile.c compares
 * them). */
#define R30 0x40000000

void prof_lim32(prof_lim32_t *l, int32_t vmax, int32_t acc, int32_t dec, int64_t free)
{
    l->vmax = vmax;
    l->acc = acc;
    l->dec = dec;
    l->d8 = prof_d8((uint32_t)dec);
    l->free32 = free > 0 && free < 0xFFFFFFFFll ? (uint32_t)free : 0xFFFFFFFFu;
    l->free = free;
}

int prof_position_fit(prof_t *p, int64_t target, const prof_lim32_t *l)
{
    int64_t rem = target - p->pos;
    int32_t step;
    if (prof_fits32(p, rem))
        return prof_step32(p, rem, l, &step);
    return prof_position_ref(p, target, l->vmax, l->acc, l->dec, l->free);
}

int prof_position_free(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec, int64_t free)
{
    if (prof_cruise(p, target, vmax, acc, free))
        return 0;
    if (vmax < R30 && acc < R30 && dec < R30) {
        prof_lim32_t l;
        prof_lim32(&l, (int32_t)vmax, (int32_t)acc, (int32_t)dec, free);
        return prof_position_fit(p, target, &l);
    }
    return prof_position_ref(p, target, vmax, acc, dec, free);
}

int prof_position_ref(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec, int64_t free)
{
    int64_t rem = target - p->pos;
    if (rem == 0 && p->vel == 0)
        return 1;
    int neg = rem < 0;
    if (neg)
        rem = -rem;
    int64_t v = neg ? -p->vel : p->vel;          /* speed towards the target */
    if (v < 0) {                                 /* moving away: turn round first */
        v += dec;
        if (v > 0)
            v = 0;
    } else {
        /* the fastest of accelerate / hold / brake from which a stop with
         * <dec> still ends at the target: u (u + dec) <= 2 dec rem */
        int quick = free > 0 && rem > free && v <= vmax;   /* no braking test needed */
        int64_t up = prof_up(v, vmax, acc, dec);
        if (up > 0 && (quick || !prof_must_brake(up, dec, rem))) {
            v = up;
        } else if (v > 0 && v <= vmax && (quick || !prof_must_brake(v, dec, rem))) {
            /* cruise */
        } else {
            v -= dec;
            if (v < dec)
                v = dec;                         /* creep: never stop short */
        }
        if (v > rem)
            v = rem;                             /* land exactly */
        if (v <= 0)
            v = rem < dec ? rem : dec;
    }
    p->vel = neg ? -v : v;
    p->pos += p->vel;
    if (p->pos == target) {
        p->vel = 0;
        return 1;
    }
    return 0;
}

int prof_ramp(prof_t *p, int64_t vt, int64_t acc, int64_t dec)
{
    int64_t v = p->vel;
    if (v == vt) {
        p->pos += v;
        return 1;
    }
    int growing = (v >= 0 && vt > v) || (v <= 0 && vt < v);
    if ((v > 0 && vt < 0) || (v < 0 && vt > 0))
        growing = 0;                             /* reversing: brake to zero first */
    int64_t step = growing ? acc : dec;
    if (vt > v) {
        v += step;
        if (v > vt)
            v = vt;
        if (!growing && p->vel < 0 && v > 0)
            v = 0;
    } else {
        v -= step;
        if (v < vt)
            v = vt;
        if (!growing && p->vel > 0 && v < 0)
            v = 0;
    }
    p->vel = v;
    p->pos += v;
    return v == vt;
}
