/* k_profile.c - witness kernel: the profile generator of firmware/profile.c. */
#include "witness.h"
#include "profile.c"

/* A Q16 quantity: up to 2^(16+bits), at least 1. */
static int64_t q16(w_rng_t *r, unsigned bits)
{
    uint32_t hi = w_rand(r), lo = w_rand(r), sh = 64u - 16u - w_rand(r) % (bits + 1u);
    uint64_t v = ((uint64_t)hi << 32 | lo) >> sh;
    return v ? (int64_t)v : 1;
}

W_KERNEL(profile)
{
    w_rng_t r;
    w_seed(&r, "profile");
    for (uint32_t n = 0; n < 2000; n++) {
        uint32_t a = w_edgy(&r), b = w_edgy(&r);
        int64_t v = (int64_t)q16(&r, 24), d = q16(&r, 24), rem = q16(&r, 32);
        w_begin("profile", "arith", n);
        w_u64((uint64_t)v);
        w_u64((uint64_t)d);
        w_u64((uint64_t)rem);
        w_u64(prof_umul32(a, b));
        w_u32((uint32_t)prof_must_brake(v, d, rem));
        if (v < 0x40000000 && d < 0x40000000 && rem <= 0xFFFFFFFFll)   /* the 32-bit test's domain */
            w_u32((uint32_t)prof_must_brake32((uint32_t)v, (uint32_t)d, (uint32_t)rem));
        w_end();
    }
    for (uint32_t n = 0; n < 300; n++) {
        prof_t p;
        p.pos = (int64_t)(int32_t)w_edgy(&r) * 65536;
        p.vel = (n & 3) ? 0 : (int64_t)(int32_t)(w_rand(&r) % 2001u) * 65536 - 1000 * 65536;
        int64_t target;
        if (n & 1) {                                   /* anywhere */
            target = (int64_t)(int32_t)w_edgy(&r) * 65536;
        } else {                                       /* a move that ends within the steps */
            uint32_t span = w_rand(&r);
            span >>= 8 + w_rand(&r) % 24u;
            target = p.pos + ((w_rand(&r) & 1) ? -(int64_t)span : (int64_t)span) * 65536;
        }
        target += (int64_t)(w_rand(&r) & 0xFFFFu);
        int64_t vmax = q16(&r, 23), acc = q16(&r, 12), dec = q16(&r, 12);
        uint32_t h = 0, k = 0;
        int done = 0;
        for (; k < 3000 && !done; k++) {
            done = prof_position(&p, target, vmax, acc, dec);
            h = (h << 5 | h >> 27) ^ (uint32_t)p.pos ^ (uint32_t)(p.vel >> 7);
            if (k < 8 || (k & 255u) == 0) {
                w_begin("profile", "position", n << 12 | k);
                w_u64((uint64_t)p.pos);
                w_u64((uint64_t)p.vel);
                w_end();
            }
        }
        w_begin("profile", "position_end", n);
        w_u32(k);
        w_u32((uint32_t)done);
        w_u32(h);
        w_u64((uint64_t)p.pos);
        w_u64((uint64_t)p.vel);
        w_end();
    }
    for (uint32_t n = 0; n < 300; n++) {
        prof_t p = {0, (int64_t)(int32_t)(w_rand(&r) % 20001u) * 4096 - 10000 * 4096};
        int64_t vt = (int64_t)(int32_t)(w_rand(&r) % 20001u) * 4096 - 10000 * 4096;
        int64_t acc = q16(&r, 10), dec = q16(&r, 10);
        uint32_t k = 0;
        int done = 0;
        for (; k < 2000 && !done; k++)
            done = prof_ramp(&p, vt, acc, dec);
        w_begin("profile", "ramp", n);
        w_u32(k);
        w_u32((uint32_t)done);
        w_u64((uint64_t)p.pos);
        w_u64((uint64_t)p.vel);
        w_end();
    }
}
