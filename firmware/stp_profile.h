/*
 * stp_profile.h - the MAC4-STP profile's 32-bit path (every card), inline
 * for its two users: stp_position (stp_profile.c) and the STP card's
 * positioning, stp_positioning (stepper.c).
 */
#ifndef STP_PROFILE_H
#define STP_PROFILE_H
#include "inline.h"
#include <stdint.h>
#include "profile.h"

static inline int64_t mag64(int64_t v) { return v < 0 ? -v : v; }

/* ---- the same in 32 bits ---------------------------------------------------
 * A move with less than 2^32 to go (Q16: 65536 steps) and speeds and ramps
 * below 2^30 (16384 steps per SP) needs no 64-bit arithmetic: stp_position()
 * and stp_positioning() take this path then, with exactly the results of the
 * 64-bit one (a 64-bit add or compare is a few instructions on the 68000; a
 * 64-bit product prof_umul32(), a shift by a variable amount a helper call). */
#define STP_R30 0x40000000u

/* stp_must_brake() for 0 <= u, dec < 2^30, rem < 2^32, ssf >= 1. */
FW_INLINE int stp_must_brake32(int32_t u, int32_t dec, uint32_t rem, int32_t ssf)
{
    if (u <= ssf)
        return 0;
    if (rem <= (uint32_t)ssf)
        return 1;
    return prof_must_brake32((uint32_t)u, (uint32_t)dec, rem - (uint32_t)ssf);
}

/* One SP of stp_position(): the distance to go as sign (neg) and magnitude
 * rem, the other values within 0 (vel: -2^30) .. 2^30, 1 <= ssf (see
 * stp_position for the rules). */
FW_INLINE int stp_position32(prof_t *p, uint32_t rem, int neg, int32_t vel,
                                                                 int32_t vmax, int32_t acc, int32_t dec, int32_t ssf)
{
    if (rem == 0 && vel <= ssf && vel >= -ssf) { /* landed: the stop */
        p->vel = 0;
        return 1;
    }
    int32_t vprev = neg ? -vel : vel;
    int32_t v = vprev;
    if (v < 0) {
        int32_t m = -v;
        if (m <= ssf) {
            m = 0;
        } else {
            m -= dec;
            if (m < ssf)
                m = ssf;
        }
        v = -m;
    } else if (v == 0) {
        v = ssf < vmax ? ssf : vmax;
        if ((uint32_t)v > rem)
            v = (int32_t)rem;
    } else {
        int32_t up = v;
        if (v < vmax) {
            up = v + acc;
            if (up > vmax)
                up = vmax;
        } else if (v > vmax) {
            up = v - dec;
            if (up < vmax)
                up = vmax;
        }
        if (!stp_must_brake32(up, dec, rem, ssf)) {
            v = up;
        } else if (v <= vmax && !stp_must_brake32(v, dec, rem, ssf)) {
            /* cruise */
        } else {
            int32_t floor = ssf < v ? ssf : v;
            v -= dec;
            if (v < floor)
                v = floor;
        }
        /* v >= 0 here */
        if ((uint32_t)v >= rem && v <= ssf && (rem > 0 || vprev <= ssf))
            v = (int32_t)rem;
    }
    int32_t nv = neg ? -v : v;
    p->vel = nv;
    p->pos += nv;
    return v >= 0 && (uint32_t)v == rem && nv <= ssf && nv >= -ssf;
}

/* The 32-bit path's arguments, if the move is within its range: the
 * distance within +-(2^32 - 1) (65535 steps), vel within +-2^30, the
 * others within 0 .. 2^30 and ssf >= 1. */
#define HI32(v) ((uint32_t)((uint64_t)(v) >> 32))
FW_INLINE int stp_args32(const prof_t *p, int64_t target, int64_t vmax,
                                                             int64_t acc, int64_t dec, int64_t ssf, uint32_t *rem,
                                                             int *neg, int32_t *a)
{
    uint64_t r = (uint64_t)(target - p->pos);
    uint32_t hi = HI32(r), lo = (uint32_t)r;
    if (hi == 0) {
        *neg = 0;
        *rem = lo;
    } else if (hi == 0xFFFFFFFFu && lo != 0) {
        *neg = 1;
        *rem = 0u - lo;
    } else {
        return 0;
    }
    uint32_t vl = (uint32_t)p->vel;
    if (HI32(p->vel) != 0u - (vl >> 31))      /* the sign extension of the low word */
        return 0;
    a[0] = (int32_t)vl;
    a[1] = (int32_t)vmax;
    a[2] = (int32_t)acc;
    a[3] = (int32_t)dec;
    a[4] = (int32_t)ssf;
    uint32_t out = HI32(vmax) | HI32(acc) | HI32(dec) | HI32(ssf) |
                   (((uint32_t)a[1] | (uint32_t)a[2] | (uint32_t)a[3] | (uint32_t)a[4]) >> 30) |
                   ((vl + STP_R30) >> 31);
    return out == 0 && a[4] != 0;
}

#endif
