/* The profile generator's arithmetic (firmware/profile.c). */
#include "unit_support.h"
#include <stdlib.h>
#include "profile.h"


/* One move; checks landing, no overshoot, limits; returns the SP count. */
static long move(int64_t from, int64_t to, int64_t v0, int64_t vmax, int64_t acc, int64_t dec)
{
    prof_t p = {from, v0};
    int dir = to >= from ? 1 : -1;
    long n = 0;
    int64_t lastv = v0;
    while (!prof_position(&p, to, vmax, acc, dec)) {
        n++;
        assert_true(n < 10000000);
        int64_t v = p.vel * dir;
        if (v0 * dir >= 0) {
            /* never beyond the target, never faster than vmax (from rest) */
            assert_true((to - p.pos) * dir >= 0);
            assert_true(v <= vmax || v <= lastv);
        }
        int64_t dv = p.vel - lastv;
        if (dv < 0)
            dv = -dv;
        assert_true(dv <= (acc > dec ? acc : dec));
        lastv = p.vel;
    }
    assert_true(p.pos == to);
    assert_true(p.vel == 0);
    return n;
}

static void lands_exactly_random(void **st)
{
    (void)st;
    for (int i = 0; i < 3000; i++) {
        int64_t from = (int32_t)rnd32() >> 4, to = (int32_t)rnd32() >> 4;
        int64_t vmax = Q(1 + rnd32() % 5000) + (rnd32() & 0xFFFF);
        int64_t acc = Q(1 + rnd32() % 200) + (rnd32() & 0xFFFF);
        int64_t dec = Q(1 + rnd32() % 200) + (rnd32() & 0xFFFF);
        if (llabs(to - from) > 4000000)
            to = from + (to > from ? 4000000 : -4000000);
        move(Q(from), Q(to), 0, vmax, acc, dec);
    }
}

static void triangle_and_trapezoid_timing(void **st)
{
    (void)st;
    /* 100000 Inc with v 1000/SP, a = d = 100/SP^2: 10 SP up, 90 SP cruise, 10 down */
    long n = move(0, Q(100000), 0, Q(1000), Q(100), Q(100));
    print_message("trapezoid: %ld SP\n", n);
    assert_true(n >= 108 && n <= 114);
    /* short: a triangle, peak below vmax */
    n = move(0, Q(1000), 0, Q(1000), Q(100), Q(100));
    print_message("triangle: %ld SP\n", n);
    assert_true(n >= 5 && n <= 9);
}

static void fractional_velocities(void **st)
{
    (void)st;   /* <sf> scaling: 1/256 increment per SP and less still arrive */
    move(0, Q(3), 0, 256, 16, 16);
    move(Q(10), Q(7), 0, 1000, 3, 5);
}

static void new_target_on_the_fly(void **st)
{
    (void)st;   /* 5.15 example 2: moving to 20000, new target 10000 */
    prof_t p = {0, 0};
    for (int i = 0; i < 20; i++)
        prof_position(&p, Q(20000), Q(500), Q(50), Q(50));
    assert_true(p.vel > 0);
    long n = 0;
    int64_t maxpos = 0;
    while (!prof_position(&p, Q(10000), Q(500), Q(50), Q(50))) {
        if (p.pos > maxpos)
            maxpos = p.pos;
        assert_true(++n < 100000);
    }
    assert_true(p.pos == Q(10000));
    assert_true(maxpos <= Q(10000));   /* stops at the new target without passing it */
}

static void reversing_target(void **st)
{
    (void)st;   /* moving away from a new target: brake, turn, arrive */
    move(Q(5000), Q(0), Q(300), Q(500), Q(40), Q(40));
}

static void ramps(void **st)
{
    (void)st;
    prof_t p = {0, 0};
    int n = 0;
    while (!prof_ramp(&p, Q(1000), Q(100), Q(50)))
        n++;
    assert_int_equal(n, 9);
    assert_true(p.vel == Q(1000));
    n = 0;
    while (!prof_ramp(&p, -Q(500), Q(100), Q(50)))   /* brake with dec, then accelerate */
        n++;
    assert_true(p.vel == -Q(500));
    assert_int_equal(n, 20 + 5 - 1);
}

static void umul32_exact(void **st)
{
    (void)st;
    for (int i = 0; i < 100000; i++) {
        uint32_t a = rnd32(), b = rnd32();
        assert_true(prof_umul32(a, b) == (uint64_t)a * b);
    }
}

/* The 32-bit braking test (three MULU.W in its usual range, mulu31 beyond)
 * decides as the 64-bit one, over its whole domain and at the edges of the
 * usual range; and it grows with the speed, which prof_step32 relies on. */
static void brake32_is_the_general_test(void **st)
{
    (void)st;
    int yes = 0, no = 0;
    for (int i = 0; i < 300000; i++) {
        unsigned sh = rnd32() % 3;
        uint32_t v = rnd32() >> (2 + 6 * sh), dec = (rnd32() >> (2 + 6 * (rnd32() % 3))) + 1;
        uint32_t rem = rnd32() >> (rnd32() % 12);
        if (i % 7 == 0) {                          /* around v8 + d8 = 2^16 and r8 = 2^23 */
            v = (0xFFFFu - (dec >> 8 & 0xFFFFu) + (rnd32() % 5) - 2) << 8 | (rnd32() & 0xFF);
            rem = (0x800000u + (rnd32() % 5) - 2) << 8 | (rnd32() & 0xFF);
            v &= 0x3FFFFFFFu;
        }
        int b = prof_must_brake32(v, dec, rem);
        assert_int_equal(b, prof_must_brake(v, dec, rem));
        if (b && v < 0x3FFFFF00u)
            assert_int_equal(prof_must_brake32(v + 256, dec, rem), 1);
        b ? yes++ : no++;
    }
    assert_true(yes > 10000 && no > 10000);
}

/* Beyond prof_free_distance(vmax, dec) no speed up to vmax must brake,
 * and it is at most about twice the braking distance; prof_position_free
 * with it moves exactly as prof_position. */
static void free_distance_needs_no_braking(void **state)
{
    (void)state;
    for (int i = 0; i < 3000; i++) {
        int64_t vmax = Q(1 + rnd32() % 20000) + (rnd32() & 0xFFFF);
        int64_t dec = Q(rnd32() % 300) + (rnd32() & 0xFFFF) + 1;
        int64_t free = prof_free_distance(vmax, dec);
        assert_true(free > 0);
        if (free == INT64_MAX)
            continue;                                  /* beyond what the Q8 test can tell */
        for (int k = 0; k < 8; k++) {
            int64_t v = k == 0 ? vmax : (int64_t)(((uint64_t)vmax * (rnd32() & 0xFFFF)) >> 16);
            assert_int_equal(prof_must_brake(v, dec, free + 1 + (rnd32() & 0xFFFFF)), 0);
        }
        assert_true(prof_must_brake(vmax, dec, free / 4));   /* not far beyond the truth */
    }
    for (int i = 0; i < 200; i++) {
        prof_t a = {0, 0}, b = {0, 0};
        int64_t to = (int64_t)((int32_t)rnd32() >> 8) * 65536;
        int64_t vmax = Q(1 + rnd32() % 2000), acc = Q(1 + rnd32() % 50), dec = Q(1 + rnd32() % 50);
        int64_t free = prof_free_distance(vmax, dec);
        for (int k = 0; k < 100000; k++) {
            int da = prof_position(&a, to, vmax, acc, dec);
            int db = prof_position_free(&b, to, vmax, acc, dec, free);
            assert_true(a.pos == b.pos && a.vel == b.vel && da == db);
            if (da)
                break;
        }
    }
}

/* prof_cruise32 (the profile generator's common step) does what
 * prof_position_free does where it applies, and nothing where it does not. */
static void cruise32_is_the_general_step(void **state)
{
    (void)state;
    int applied = 0, declined = 0;
    for (int i = 0; i < 200000; i++) {
        int64_t vmax = Q(1 + rnd32() % 3000) + (rnd32() & 0xFFFF);
        int64_t acc = Q(1 + rnd32() % 100) + (rnd32() & 0xFFFF);
        int64_t dec = Q(1 + rnd32() % 100) + (rnd32() & 0xFFFF);
        int64_t target = (int64_t)((int32_t)rnd32() >> 6) * 65536 + (rnd32() & 0xFFFF);
        int64_t free = prof_free_distance(vmax, dec);
        if (free == INT64_MAX)
            continue;
        int64_t f = free > vmax ? free : vmax;
        prof_t a, b;
        a.pos = target + ((int64_t)((int32_t)rnd32() >> 4) * 4);   /* near and far from the target */
        a.vel = (int64_t)(((uint64_t)vmax * (rnd32() & 0x1FFFF)) >> 16) * (rnd32() & 1 ? 1 : -1);
        b = a;
        prof_t before = a;
        int32_t d = prof_cruise32(&a, target - f, target + f, (int32_t)vmax, (int32_t)acc);
        if (d) {
            applied++;
            assert_int_equal(prof_position_free(&b, target, vmax, acc, dec, free), 0);
            assert_true(a.pos == b.pos && a.vel == b.vel && a.pos - before.pos == d);
        } else {
            declined++;
            assert_true(a.pos == before.pos && a.vel == before.vel);
        }
    }
    assert_true(applied > 1000 && declined > 1000);
}

/* prof_position_free's 32-bit path gives what the 64-bit reference gives,
 * step for step, over whole moves that start in and out of its range. */
static void position32_is_the_reference(void **state)
{
    (void)state;
    long steps = 0;
    for (int i = 0; i < 3000; i++) {
        int64_t vmax = Q(1 + rnd32() % 400) + (rnd32() & 0xFFFF);
        int64_t acc = Q(rnd32() % 40) + (rnd32() & 0xFFFF) + 1;
        int64_t dec = Q(rnd32() % 40) + (rnd32() & 0xFFFF) + 1;
        int64_t free = i % 3 ? prof_free_distance(vmax, dec) : 0;
        prof_t a, b;
        a.pos = (int64_t)((int32_t)rnd32() >> (i % 2 ? 8 : 14)) * 65536;
        a.vel = (int64_t)((int32_t)rnd32() >> 12);                 /* moving either way */
        b = a;
        int64_t to = i % 5 ? (int64_t)((int32_t)rnd32() >> 12) * 65536 + (rnd32() & 0xFFFF) : a.pos + Q(1);
        for (int k = 0; k < 20000; k++) {
            int da = prof_position_free(&a, to, vmax, acc, dec, free);
            int db = prof_position_ref(&b, to, vmax, acc, dec, free);
            steps++;
            assert_true(a.pos == b.pos && a.vel == b.vel && da == db);
            if (da)
                break;
        }
    }
    assert_true(steps > 100000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(brake32_is_the_general_test),
        cmocka_unit_test(free_distance_needs_no_braking),
        cmocka_unit_test(cruise32_is_the_general_step),
        cmocka_unit_test(position32_is_the_reference),
        cmocka_unit_test(lands_exactly_random),
        cmocka_unit_test(triangle_and_trapezoid_timing),
        cmocka_unit_test(fractional_velocities),
        cmocka_unit_test(new_target_on_the_fly),
        cmocka_unit_test(reversing_target),
        cmocka_unit_test(ramps),
        cmocka_unit_test(umul32_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
