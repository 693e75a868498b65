/*
 * stp_profile.c - the MAC4-STP's profile arithmetic (every card; unit-tested
 * natively, tests/unit/test_stepper.c): the start/stop frequency rule of the
 * ramps and of positioning (5.14), the increment/step ratio (4.4.2.3) and
 * <ssf> on the rate register's grid.  The card's stages: stepper.c (the
 * axis: measurement, motion, status) and stp_rate.c (the step rate).
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "stepper.h"
#include "stp_profile.h"

int stp_ramp(prof_t *p, int64_t vt, int64_t acc, int64_t dec, int64_t ssf)
{
    int64_t v = p->vel;
    if (ssf < 1)
        ssf = 1;
    if (v == vt) {
        p->pos += v;
        return 1;
    }
    if (v == 0) {                                /* start: the first step is <ssf> */
        int64_t m = mag64(vt);
        if (m > ssf)
            m = ssf;
        v = vt < 0 ? -m : m;
    } else if (vt == 0 || (v < 0) != (vt < 0)) { /* to stand-still (or a reversal) */
        int64_t m = mag64(v);
        if (m <= ssf) {
            m = 0;                               /* the last step: stop from <ssf> */
        } else {
            m -= dec;
            if (m < ssf)
                m = ssf;
        }
        v = v < 0 ? -m : m;
    } else {
        return prof_ramp(p, vt, acc, dec);       /* between two speeds, one direction */
    }
    p->vel = v;
    p->pos += v;
    return v == vt;
}

/* Must a move at speed u (> ssf) start braking now, so that it comes down
 * to ssf with dec before the target?  Braking with a floor at ssf covers
 * less than braking to 0, so prof_must_brake() with one SP at ssf as margin
 * is on the safe side. */
static int stp_must_brake(int64_t u, int64_t dec, int64_t rem, int64_t ssf)
{
    if (u <= ssf)
        return 0;                                /* stops at once */
    if (rem <= ssf)
        return 1;
    return prof_must_brake(u, dec, rem - ssf);
}


int stp_position(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec, int64_t ssf)
{
    if (ssf < 1)
        ssf = 1;
    uint32_t r;
    int n32;
    int32_t a[5];
    if (stp_args32(p, target, vmax, acc, dec, ssf, &r, &n32, a))
        return stp_position32(p, r, n32, a[0], a[1], a[2], a[3], a[4]);
    int64_t rem = target - p->pos;
    if (rem == 0 && mag64(p->vel) <= ssf) {      /* landed: the stop */
        p->vel = 0;
        return 1;
    }
    int neg = rem < 0;
    if (neg)
        rem = -rem;
    int64_t vprev = neg ? -p->vel : p->vel;      /* speed towards the target */
    int64_t v = vprev;
    if (v < 0) {                                 /* moving away: stop, then come back */
        int64_t m = -v;
        if (m <= ssf) {
            m = 0;
        } else {
            m -= dec;
            if (m < ssf)
                m = ssf;
        }
        v = -m;
    } else if (v == 0) {                         /* start with <ssf> (or <pv> if lower) */
        v = ssf < vmax ? ssf : vmax;
        if (v > rem)
            v = rem;
    } else {
        int64_t up = prof_up(v, vmax, acc, dec);
        if (!stp_must_brake(up, dec, rem, ssf)) {
            v = up;
        } else if (v <= vmax && !stp_must_brake(v, dec, rem, ssf)) {
            /* cruise */
        } else {
            int64_t floor = ssf < v ? ssf : v;   /* brake down to <ssf>, not below */
            v -= dec;
            if (v < floor)
                v = floor;
        }
        /* land exactly, and only from at most <ssf>: a target too near to
         * stop at (a new one on the fly) is passed, and approached again */
        if (v >= rem && v <= ssf && (rem > 0 || vprev <= ssf))
            v = rem;
    }
    p->vel = neg ? -v : v;
    p->pos += p->vel;
    /* on target: vel stays this SP's speed (at most ssf), so that a new
     * target the other way round stops first instead of reversing at once */
    return p->pos == target && mag64(p->vel) <= ssf;
}

uint32_t stp_ratio_q16(uint32_t ms, uint32_t es, int *exact)
{
    uint32_t den = es << 2;                      /* 4 <es> increments per <ms> steps */
    *exact = 0;
    if (den == 0 || ms / den > 0xFFFFu)
        return 0xFFFFFFFFu;
    uint32_t q = ms / den, r = ms % den, f = 0;
    for (unsigned i = 0; i < 17; i++) {          /* 16 fraction bits and one to round */
        r <<= 1;
        f <<= 1;
        if (r >= den) {
            r -= den;
            f |= 1u;
        }
    }
    *exact = r == 0 && !(f & 1u);
    uint32_t v = (q << 16) + (f >> 1);
    if (f & 1u)
        v = v == 0xFFFFFFFFu ? v : v + 1u;
    return v;
}

int64_t stp_ssf_grid(int64_t ssf, int turbo)
{
    /* one rate LSB for a whole SP of four ticks, in Q16 steps per SP */
    uint32_t lsb = 4u * (turbo ? STP_TICK_CLOCKS_TURBO : STP_TICK_CLOCKS);
    if (ssf > 0x7FFFFFFF)
        ssf = 0x7FFFFFFF;
    uint32_t q = (uint32_t)ssf / lsb;
    return (int64_t)((q ? q : 1u) * lsb);
}

int32_t stp_scale_call(int32_t c, uint32_t ratio_q16) { return stp_scale(c, ratio_q16); }

uint16_t stp_rate_hz(uint32_t hz)
{
    if (hz >= STP_CLK_HZ)
        return 0xFFFFu;
    return (uint16_t)stp_divu16(hz << 15, 25000u);   /* hz x 65536 / 50000, rounded down */
}
