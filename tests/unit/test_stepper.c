/* The MAC4-STP arithmetic (firmware/stp_profile.c) and rate stage (stepper.h,
 * stp_rate.c): the <ssf> rule of the profile (5.14), the increment/step ratio
 * (4.4.2.3), the rate register and the frequency it gives.  Built for the STP
 * (UNIT_CARD_test_stepper, tests/unit/unit.mk). */
#include "unit_support.h"
#include <stdlib.h>
#include "stepper.h"
#include "stp_rate.h"

_Static_assert(MAC4_CARD == MAC4_CARD_STP, "the STP's rate stage: built with MAC4_CARD 2 (unit.mk)");


static int64_t mag(int64_t v) { return v < 0 ? -v : v; }

/* The rule on a sequence of SP velocities: from 0 at most ssf, to 0 from
 * at most ssf, no reversal without a 0 between, and otherwise the ramps. */
static void check_step(int64_t v0, int64_t v1, int64_t ssf, int64_t acc, int64_t dec)
{
    int64_t lim = acc > dec ? acc : dec;
    if (ssf > lim)
        lim = ssf;                             /* landing from ssf */
    if (v0 == 0 || v1 == 0)
        assert_true(mag(v1 - v0) <= ssf);
    else
        assert_true((v0 > 0) == (v1 > 0));
    if (v0 != 0 && v1 != 0)
        assert_true(mag(v1 - v0) <= lim);
}

/* ---- positioning ------------------------------------------------------ */
static long stp_move(prof_t *p, int64_t to, int64_t vmax, int64_t acc, int64_t dec, int64_t ssf)
{
    long n = 0;
    int64_t lastv = p->vel, before = p->pos;
    int done;
    do {
        done = stp_position(p, to, vmax, acc, dec, ssf);
        n++;
        assert_true(n < 10000000);
        int64_t v = p->pos - before;           /* this SP's speed, the landing's too */
        before = p->pos;
        check_step(lastv, v, ssf, acc, dec);
        lastv = v;
    } while (!done);
    check_step(lastv, 0, ssf, acc, dec);      /* the stop after the landing */
    assert_true(p->pos == to && mag(p->vel) <= ssf);
    assert_true(stp_position(p, to, vmax, acc, dec, ssf) && p->vel == 0 && p->pos == to);
    return n;
}

static void position_lands_exactly_with_the_ssf_rule(void **st)
{
    (void)st;
    for (int i = 0; i < 3000; i++) {
        int64_t from = (int32_t)rnd32() >> 6, to = (int32_t)rnd32() >> 6;
        int64_t vmax = Q(1 + rnd32() % 1600) + (rnd32() & 0xFFFF);
        int64_t acc = Q(rnd32() % 50) + (rnd32() & 0xFFFF) + 1;
        int64_t dec = Q(rnd32() % 50) + (rnd32() & 0xFFFF) + 1;
        int64_t ssf = Q(rnd32() % 40) + (rnd32() & 0xFFFF) + 1;
        if (llabs(to - from) > 2000000)
            to = from + (to > from ? 2000000 : -2000000);
        prof_t p = {Q(from), 0};
        stp_move(&p, Q(to), vmax, acc, dec, ssf);
    }
}

static void position_starts_with_ssf_and_brakes_to_it(void **st)
{
    (void)st;
    /* the 7.2 motor: ssf 30 Hz = 0.96 steps/SP; pv 400 Hz, ramps 25 Hz/SP */
    int64_t ssf = 62915, vmax = 838861, acc = 52429, dec = 52429;
    prof_t p = {0, 0};
    stp_position(&p, Q(1990), vmax, acc, dec, ssf);
    assert_true(p.vel == ssf);                 /* the first speed is ssf */
    int64_t prev = 0, lastmoving = 0;
    long at_floor = 0;
    int done;
    do {
        int64_t before = p.pos;
        done = stp_position(&p, Q(1990), vmax, acc, dec, ssf);
        int64_t v = p.pos - before;
        if (v == ssf && prev > ssf)
            at_floor = 1;                      /* the braking ramp came down to ssf */
        if (v)
            lastmoving = v;
        prev = v;
    } while (!done);
    assert_true(at_floor);
    assert_true(lastmoving <= ssf);
    /* pv below ssf: starts and stops at pv */
    prof_t q = {0, 0};
    stp_position(&q, Q(100), ssf / 2, acc, dec, ssf);
    assert_true(q.vel == ssf / 2);
    stp_move(&q, Q(100), ssf / 2, acc, dec, ssf);
}

static void position_new_targets_on_the_fly(void **st)
{
    (void)st;
    for (int i = 0; i < 2000; i++) {
        int64_t vmax = Q(1 + rnd32() % 300), acc = Q(1 + rnd32() % 20), dec = Q(1 + rnd32() % 20);
        int64_t ssf = Q(1 + rnd32() % 10);
        prof_t p = {0, 0};
        int64_t lastv = 0, to = Q((int32_t)rnd32() >> 14);
        for (int k = 0; k < 200; k++) {
            if (rnd32() % 40 == 0)
                to = Q((int32_t)rnd32() >> 14);   /* a new target, near or behind */
            int64_t before = p.pos;
            stp_position(&p, to, vmax, acc, dec, ssf);
            check_step(lastv, p.pos - before, ssf, acc, dec);
            lastv = p.pos - before;
        }
        if (lastv != p.vel)                    /* it has just landed: the stop */
            check_step(lastv, 0, ssf, acc, dec);
        stp_move(&p, to, vmax, acc, dec, ssf);
    }
}

/* ---- ramps ---------------------------------------------------------- */
static void ramps_obey_ssf(void **st)
{
    (void)st;
    for (int i = 0; i < 3000; i++) {
        int64_t acc = Q(rnd32() % 30) + 1 + (rnd32() & 0xFFFF), dec = Q(rnd32() % 30) + 1 + (rnd32() & 0xFFFF);
        int64_t ssf = Q(rnd32() % 20) + 1 + (rnd32() & 0xFFFF);
        prof_t p = {0, 0};
        int64_t lastv = 0;
        for (int k = 0; k < 60; k++) {
            int64_t vt = (int64_t)((int32_t)rnd32() >> 8);
            if (rnd32() % 3 == 0)
                vt = 0;
            for (int j = 0; j < 400; j++) {
                int done = stp_ramp(&p, vt, acc, dec, ssf);
                check_step(lastv, p.vel, ssf, acc, dec);
                lastv = p.vel;
                if (done)
                    break;
            }
        }
    }
    /* from stand-still the first speed is ssf, the last before it too */
    prof_t p = {0, 0};
    stp_ramp(&p, Q(100), Q(10), Q(10), Q(3));
    assert_true(p.vel == Q(3));
    stp_ramp(&p, Q(100), Q(10), Q(10), Q(3));
    assert_true(p.vel == Q(13));
    while (!stp_ramp(&p, 0, Q(10), Q(10), Q(3)))
        ;
    assert_true(p.vel == 0);
    /* unlimited (velocity tracking): to ssf, then the speed; down via ssf */
    prof_t v = {0, 0};
    int64_t big = (int64_t)1 << 48;
    stp_ramp(&v, Q(50), big, big, Q(3));
    assert_true(v.vel == Q(3));
    stp_ramp(&v, Q(50), big, big, Q(3));
    assert_true(v.vel == Q(50));
    stp_ramp(&v, 0, big, big, Q(3));
    assert_true(v.vel == Q(3));
    stp_ramp(&v, 0, big, big, Q(3));
    assert_true(v.vel == 0);
}

/* ---- units ---------------------------------------------------------- */
static void ratio_examples_of_4_4_2_3_are_exact(void **st)
{
    (void)st;
    int exact;
    assert_true(stp_ratio_q16(25000, 1000, &exact) == 409600u && exact);      /* 6.25 */
    assert_true(stp_ratio_q16(125000, 625, &exact) == 3276800u && exact);     /* 50 */
    assert_true(stp_ratio_q16(500, 1000, &exact) == 8192u && exact);          /* 0.125 */
    assert_true(stp_ratio_q16(500, 500, &exact) == 16384u && exact);
    uint32_t r = stp_ratio_q16(1000, 3, &exact);                              /* 83.33.. */
    assert_true(!exact && r == 5461333u);
    assert_true(stp_ratio_q16(16777215, 1, &exact) == 0xFFFFFFFFu && !exact); /* beyond 65535 */
    /* both examples: whole revolutions convert exactly */
    assert_true(stp_scale(4000, 409600u) == 25000 && stp_scale(-4000, 409600u) == -25000);
    assert_true(stp_scale(2500, 3276800u) == 125000);
    assert_true(stp_scale(1, 409600u) == 6 && stp_scale(2, 409600u) == 13 && stp_scale(-1, 409600u) == -6);
    for (int i = 0; i < 100000; i++) {
        int32_t c = (int32_t)rnd32() >> (rnd32() % 24 + 8);
        uint32_t ratio = rnd32() >> (rnd32() % 24 + 8);
        double want = (double)c * ratio / 65536.0;
        if (want > 2e9 || want < -2e9)
            continue;
        int64_t w = (int64_t)(want < 0 ? want - 0.5 : want + 0.5);
        assert_true(llabs((int64_t)stp_scale(c, ratio) - w) <= 1);
    }
}

/* The firmware's rate stage (stepper.h, stp_rate.c), as stp_motion_start and
 * stp_init leave it: <clocks> generator clocks per tick, lim = clocks << 16. */
static stp_t rate_stage(uint16_t clocks)
{
    stp_t s = {0};
    s.clocks = clocks;
    s.lim = (uint32_t)clocks << 16;
    return s;
}

/* One tick's distance mag (Q16 steps) into the register, as stp_rate.c
 * does: the carry of the tick before added, a wrapped sum saturated. */
static void load(stp_t *s, uint32_t mag)
{
    uint32_t t = mag + s->carry;
    stp_load_rate(s, t < mag ? 0xFFFFFFFFu : t);
}

static void rates_sum_up_to_the_distance(void **st)
{
    (void)st;
    for (int i = 0; i < 2000; i++) {
        uint16_t clocks = (rnd32() & 1) ? STP_TICK_CLOCKS : STP_TICK_CLOCKS_TURBO;
        stp_t s = rate_stage(clocks);
        uint64_t sent = 0, want = 0;
        for (int k = 0; k < 200; k++) {
            uint32_t mag = rnd32() % ((uint32_t)clocks * 65535u);
            load(&s, mag);
            want += mag;
            sent += (uint64_t)s.rate * clocks;
            assert_true(s.carry < clocks);
            assert_true(want - sent == s.carry);   /* nothing lost, nothing made up */
        }
    }
    /* the register's end: clocks * 65536 Q16 steps a tick and more saturate,
     * the carry dropped; one less is the last exact one */
    for (int turbo = 0; turbo < 2; turbo++) {
        uint16_t clocks = turbo ? STP_TICK_CLOCKS_TURBO : STP_TICK_CLOCKS;
        stp_t s = rate_stage(clocks);
        stp_load_rate(&s, ((uint32_t)clocks << 16) - 1u);
        assert_true(s.rate == 0xFFFFu && s.carry == clocks - 1u);
        stp_load_rate(&s, (uint32_t)clocks << 16);
        assert_true(s.rate == 0xFFFFu && s.carry == 0);
        s.carry = clocks - 1u;
        load(&s, 0xFFFFFFFFu);                   /* the sum wraps: saturated */
        assert_true(s.rate == 0xFFFFu && s.carry == 0);
        load(&s, 3u * clocks + 1u);
        assert_true(s.rate == 3 && s.carry == 1);
        load(&s, 0);
        assert_true(s.rate == 0 && s.carry == 1);
    }
}

/* The frequency the firmware publishes (DPRAM ROUT in Hz) and ROUT in
 * Steps/SP (table 6.2), from the rate register of axis n. */
static int32_t hz_of(unsigned n, uint16_t rate, int turbo, int8_t dir)
{
    stp_ax[n] = rate_stage(turbo ? STP_TICK_CLOCKS_TURBO : STP_TICK_CLOCKS);
    stp_ax[n].rate = rate;
    stp_ax[n].dir = dir;
    return stp_hz_now(n);
}

static void hz_and_the_rate_grid(void **st)
{
    (void)st;
    assert_true(stp_rate_hz(30) == 39);           /* 29.75 Hz: never above the 30 Hz asked */
    assert_true(stp_rate_hz(8) == 10);
    assert_true(hz_of(0, 39, 0, 1) == 30 && hz_of(1, 131, 1, 1) == 1000);
    assert_true(hz_of(2, 39, 0, -1) == -30 && hz_of(3, 0, 1, -1) == 0);
    assert_true(hz_of(0, 0xFFFF, 0, 1) == 49999 && hz_of(0, 0xFFFF, 1, -1) == -499990);
    assert_true(stp_rate_hz(50000) == 65536u - 1u || stp_rate_hz(50000) == 65535u);
    for (uint32_t f = 1; f <= 50000; f += 7) {
        uint16_t r = stp_rate_hz(f);
        assert_true((double)r * 50000.0 / 65536.0 <= f + 1e-9);
        assert_true((double)(r + 1) * 50000.0 / 65536.0 > f - 0.001);
    }
    /* every register value: Hz = rate x 50 000 / 65 536 rounded (TURBO
     * ten times that), signed by the direction; Steps/SP = Hz x 32 ms */
    for (uint32_t r = 0; r <= 0xFFFFu; r++) {
        unsigned n = r & 3u;
        int turbo = (r >> 2) & 1u;
        int8_t dir = (r >> 3) & 1u ? -1 : 1;
        int32_t hz = hz_of(n, (uint16_t)r, turbo, dir);
        double exact = (double)r * 50000.0 / 65536.0;
        int32_t want = (int32_t)(exact + 0.5) * (turbo ? 10 : 1);
        assert_true(hz == (dir < 0 ? -want : want));
        int32_t sp = stp_out_steps_sp(n), a = hz < 0 ? -hz : hz, q = hz < 0 ? -sp : sp;
        assert_true(q >= 0 && llabs(1000ll * q - 32ll * a) <= 504);   /* rounded: (4 Hz + 62) / 125 */
    }
    /* <ssf> on the grid: a multiple of one rate LSB over the four ticks */
    assert_true(stp_ssf_grid(62915, 0) == 62400);
    assert_true(stp_ssf_grid(100, 0) == 1600);
    assert_true(stp_ssf_grid(629146, 1) % 16000 == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(position_lands_exactly_with_the_ssf_rule),
        cmocka_unit_test(position_starts_with_ssf_and_brakes_to_it),
        cmocka_unit_test(position_new_targets_on_the_fly),
        cmocka_unit_test(ramps_obey_ssf),
        cmocka_unit_test(ratio_examples_of_4_4_2_3_are_exact),
        cmocka_unit_test(rates_sum_up_to_the_distance),
        cmocka_unit_test(hz_and_the_rate_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
