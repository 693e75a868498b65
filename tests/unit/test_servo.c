/* The position controller (firmware/servo.c) against a double-precision
 * reference of the manual's difference equations (5.16). */
#include <math.h>
#include <stdlib.h>
#include "unit_support.h"
#include "servo.h"

typedef struct { double u1, u2, e_prev; } ref_t;

/* u1(k) = K e(k) - K A e(k-1) - B u1(k-1); u2(k) = C e(k-1) + u2(k-1),
 * u2 limited to the DAC range (anti wind-up); u saturated to 12 bits. */
static double ref_step_sw(ref_t *r, int ga, int ze, int po, int ki, int kisc, double e, int sw)
{
    double K = ga / 4.0, A = ze / 256.0, B = po / 256.0, C = ki / (256.0 * (double)(1 << kisc));
    /* the output range: the DAC's, or -<sw>..<sw> (torque limitation) */
    double hi = sw >= 2048 ? 2047 : sw, lo = sw >= 2048 ? -2048 : -sw;
    double u1 = K * e - K * A * r->e_prev - B * r->u1;
    double u2 = C * r->e_prev + r->u2;
    if (u2 > hi)
        u2 = hi;
    if (u2 < lo)
        u2 = lo;
    r->u1 = u1;
    r->u2 = u2;
    r->e_prev = e;
    double u = u1 + u2;
    return u > hi ? hi : u < lo ? lo : u;
}


static uint32_t rng = 12345;
static int32_t rnd(int32_t span)
{
    rng = rng * 1103515245u + 12345u;
    return (int32_t)((rng >> 8) % (uint32_t)(2 * span + 1)) - span;
}

/* Runs n ticks of a following-error sequence; returns the largest
 * |fixed - reference| in DAC LSB.  sw: the torque limit (2048: none). */
static double run_sw(int ga, int ze, int po, int ki, int kisc, int kind, long n, int sw)
{
    servo_gains_t g;
    servo_state_t s;
    ref_t r = {0, 0, 0};
    servo_set_gains(&g, ga, ze, po, ki, kisc);
    servo_set_limit(&g, sw);
    servo_reset(&s);
    double worst = 0;
    int32_t e = 0;
    for (long k = 0; k < n; k++) {
        switch (kind) {
        case 0: e += rnd(3); if (e > 150) e = 150; if (e < -150) e = -150; break;  /* random walk */
        case 1: e = (int32_t)lround(60.0 * sin((double)k * 2 * M_PI / (200.0 + (double)(k % 7000) / 10.0))); break;
        case 2: e = (k / 500) % 2 ? 40 : -25; break;                                  /* steps */
        default: e = rnd(20); break;                                                  /* noise */
        }
        double want = ref_step_sw(&r, ga, ze, po, ki, kisc, e, sw);
        int16_t got = servo_step(&s, &g, e);
        if (sw < 2048)
            assert_true(got >= -sw && got <= sw);
        double d = fabs((double)got - want);
        if (d > worst)
            worst = d;
    }
    return worst;
}

static double run(int ga, int ze, int po, int ki, int kisc, int kind, long n)
{
    return run_sw(ga, ze, po, ki, kisc, kind, n, 2048);
}

static void manual_inc_example(void **st)
{
    (void)st;   /* 7.2 MAC4-INC: WGA 80, WZE 128, WPO 0, UWKISC 3, WKI 41 */
    for (int kind = 0; kind < 4; kind++) {
        double w = run(80, 128, 0, 41, 3, kind, 400000);
        print_message("INC example, signal %d: max |fixed - double| = %.4f LSB\n", kind, w);
        assert_true(w <= 1.0);
    }
}

static void manual_ssi_example(void **st)
{
    (void)st;   /* 7.2 MAC4-SSI: WGA 200, WZE 253, WPO 0, UWKISC 0, WKI 13 */
    for (int kind = 0; kind < 4; kind++) {
        double w = run(200, 253, 0, 13, 0, kind, 400000);
        print_message("SSI example, signal %d: max |fixed - double| = %.4f LSB\n", kind, w);
        assert_true(w <= 1.0);
    }
}

static void with_a_pole_and_default_shift(void **st)
{
    (void)st;
    for (int kind = 0; kind < 4; kind++)
        assert_true(run(120, 200, 64, 300, 8, kind, 200000) <= 1.0);
    assert_true(run(40, 0, -100, 0, 8, 0, 200000) <= 1.0);
}

static void integrator_does_not_drift(void **st)
{
    (void)st;
    /* a constant small error: u2 must grow by exactly C e per tick */
    servo_gains_t g;
    servo_state_t s;
    servo_set_gains(&g, 0, 0, 0, 1, 8);   /* C = 1/65536 */
    servo_reset(&s);
    int16_t u = 0;
    for (long k = 0; k < 65536L * 3 + 1; k++)
        u = servo_step(&s, &g, 1);
    assert_int_equal(u, 3);               /* 3 * 65536 ticks * 1/65536 */
}

static void saturates_and_winds_up_no_further(void **st)
{
    (void)st;
    servo_gains_t g;
    servo_state_t s;
    servo_set_gains(&g, 80, 0, 0, 32767, 0);
    servo_reset(&s);
    for (int k = 0; k < 10000; k++)
        assert_int_equal(servo_step(&s, &g, 5000), 2047);
    /* after the error reverses, the output leaves saturation within a few
     * ticks: the integral part was held at the DAC range */
    int k = 0;
    while (servo_step(&s, &g, -20) > -2048 && k < 100)
        k++;
    assert_true(k < 100);
}

/* servo_step's inline path for K-only gains (the tick's) gives what the
 * general filter gives, word for word and state for state, also at the
 * limits of e, u1 and the DAC, and with an integrator left from earlier gains. */
static void fast_path_is_the_full_filter(void **state)
{
    (void)state;
    static const int gas[] = {1, 3, 40, 400, 4000, 32767};
    for (unsigned i = 0; i < sizeof gas / sizeof gas[0]; i++) {
        servo_gains_t g, gf;
        servo_state_t a, b;
        servo_set_gains(&g, gas[i], 0, 0, 0, 8);
        assert_int_equal(g.full, 0);
        gf = g;
        gf.full = 1;
        servo_reset(&a);
        a.u2 = (int32_t)(i * 97u) * 256 - 1000 * 256;   /* a frozen integrator */
        b = a;
        for (long k = 0; k < 20000; k++) {
            int32_t e = k % 1000 == 0 ? rnd(5000000) : rnd(k % 3 ? 300 : 70000);
            int16_t ua = servo_step(&a, &g, e);
            int16_t ub = servo_step(&b, &gf, e);
            assert_int_equal(ua, ub);
            assert_int_equal(a.u1, b.u1);
            assert_int_equal(a.u2, b.u2);
            assert_int_equal(a.e_prev, b.e_prev);
        }
    }
    servo_gains_t g;
    servo_set_gains(&g, 40, 1, 0, 0, 8);
    assert_int_equal(g.full, 1);
}

/* <sw> (5.16, diagram 5.12): the output magnitude at most <sw>, the
 * integrator limited with it, within 1 LSB of the reference, for the
 * manual's gains and for K-only gains (which then take the full filter). */
static void torque_limit_against_the_reference(void **st)
{
    (void)st;
    static const int sws[] = {0, 1, 100, 700, 2047};
    for (unsigned i = 0; i < sizeof sws / sizeof sws[0]; i++)
        for (int kind = 0; kind < 4; kind++) {
            assert_true(run_sw(80, 128, 0, 41, 3, kind, 50000, sws[i]) <= 1.0);
            assert_true(run_sw(200, 253, 0, 13, 0, kind, 50000, sws[i]) <= 1.0);
            assert_true(run_sw(120, 200, 64, 300, 8, kind, 50000, sws[i]) <= 1.0);
            assert_true(run_sw(400, 0, 0, 0, 8, kind, 50000, sws[i]) <= 1.0);
        }
}

/* The limit holds in servo_step (the tick's entry) as in servo_step_full,
 * word for word; with the K-only gains it is what moves the tick off its
 * inline path, and <sw> = 2048 (the default) or more leaves that path and
 * every result exactly as without a limit. */
static void torque_limit_in_both_paths(void **st)
{
    (void)st;
    servo_gains_t g, plain;
    servo_state_t a, b, c;
    servo_set_gains(&g, 400, 0, 0, 0, 8);
    plain = g;
    assert_int_equal(g.full, 0);
    servo_set_limit(&g, 300);
    assert_int_equal(g.full, 1);
    servo_reset(&a);
    b = a;
    for (long k = 0; k < 20000; k++) {
        int32_t e = rnd(k % 3 ? 400 : 70000);
        int16_t ua = servo_step(&a, &g, e), ub = servo_step_full(&b, &g, e);
        assert_int_equal(ua, ub);
        assert_true(ua >= -300 && ua <= 300);
        assert_int_equal(a.u2, b.u2);
    }
    static const int32_t full_range[] = {2048, 2049, 1000000};
    for (unsigned i = 0; i < sizeof full_range / sizeof full_range[0]; i++) {
        servo_gains_t h = plain;
        servo_set_limit(&h, full_range[i]);
        assert_int_equal(h.full, 0);
        assert_int_equal(h.sw_lim, 0);
        servo_reset(&a);
        servo_reset(&c);
        for (long k = 0; k < 5000; k++) {
            int32_t e = rnd(k % 3 ? 400 : 70000);
            assert_int_equal(servo_step(&a, &h, e), servo_step(&c, &plain, e));
        }
    }
    /* a negative <sw> cannot be written (0..2048); the setter takes it as 0 */
    servo_set_limit(&g, -5);
    servo_reset(&a);
    assert_int_equal(servo_step(&a, &g, 1000), 0);
    /* the full filter's own gains keep their limit too, and gains set anew
     * clear it until servo_set_limit comes again (motion.c: at E, both) */
    servo_set_gains(&g, 80, 128, 0, 41, 3);
    servo_set_limit(&g, 50);
    servo_reset(&a);
    for (int k = 0; k < 100; k++)
        assert_true(abs(servo_step(&a, &g, k % 2 ? 3000 : -3000)) <= 50);
    servo_set_gains(&g, 80, 128, 0, 41, 3);
    assert_int_equal(g.sw_lim, 0);
    servo_reset(&a);
    assert_int_equal(servo_step(&a, &g, 3000), 2047);
}

/* Under a limit the integrator winds up no further than the limit: when
 * the error reverses, the output leaves the limit within a few ticks. */
static void torque_limit_winds_up_no_further(void **st)
{
    (void)st;
    servo_gains_t g;
    servo_state_t s;
    servo_set_gains(&g, 80, 0, 0, 32767, 0);
    servo_set_limit(&g, 500);
    servo_reset(&s);
    for (int k = 0; k < 10000; k++)
        assert_int_equal(servo_step(&s, &g, 5000), 500);
    assert_int_equal(s.u2, 500 * 256);
    int k = 0;
    while (servo_step(&s, &g, -20) > -500 && k < 100)
        k++;
    assert_true(k < 100);
}

/* The fixed-point filter's own definition, in 64 bits with exact floors
 * (servo.h): u1 = 64 ga e - floor(ga ze e' / 4) - floor(po u1' / 256),
 * bounded to 2^23; u2 += floor(r / 2^kisc) of r = residual + ki e', the
 * rest kept as the residual, u2 bounded to the output range in Q8; u the
 * rounded sum, saturated.  servo_step must be it bit for bit, whatever way
 * servo.c computes it. */
typedef struct { int64_t u1, u2, res, ep; } exact_t;

static int64_t floor_div(int64_t a, int64_t d) { return a >= 0 ? a / d : -((-a + d - 1) / d); }

static int16_t exact_step(exact_t *x, const servo_gains_t *g, int32_t e32)
{
    int64_t e = e32 > g->e_lim ? g->e_lim : e32 < -g->e_lim ? -g->e_lim : e32;
    int64_t hi = g->sw_lim ? g->sw_lim - 1 : SERVO_OUT_MAX, lo = g->sw_lim ? -(g->sw_lim - 1) : SERVO_OUT_MIN;
    int64_t u1 = 64 * (int64_t)g->ga * e - floor_div((int64_t)g->ga * g->ze * x->ep, 4) -
                 floor_div((int64_t)g->po * x->u1, 256);
    if (u1 > SERVO_U1_MAX)
        u1 = SERVO_U1_MAX;
    if (u1 < -SERVO_U1_MAX)
        u1 = -SERVO_U1_MAX;
    int64_t u2 = x->u2;
    if (g->ki) {
        int64_t r = x->res + (int64_t)g->ki * x->ep, q = floor_div(r, (int64_t)1 << g->kisc);
        x->res = r - q * ((int64_t)1 << g->kisc);
        u2 += q;
    }
    if (u2 > hi * 256)
        u2 = hi * 256;
    if (u2 < lo * 256)
        u2 = lo * 256;
    x->u1 = u1;
    x->u2 = u2;
    x->ep = e;
    int64_t u = floor_div(u1 + u2 + 128, 256);
    return (int16_t)(u > hi ? hi : u < lo ? lo : u);
}

static void full_filter_is_its_exact_definition(void **st)
{
    (void)st;
    static const int16_t set[][6] = {     /* ga ze po ki kisc sw */
        {80, 128, 0, 41, 3, 2048}, {200, 253, 0, 13, 0, 2048}, {80, 128, 10, 41, 8, 2000},
        {32767, 255, 255, 32767, 0, 2048}, {32767, 255, -255, 32767, 15, 1}, {1, 0, -255, 1, 15, 0},
        {9, 255, 255, 32767, 0, 2048}, {8, 255, -255, 32767, 15, 700}, {40, 0, 0, 0, 8, 2048},
    };
    for (unsigned n = 0; n < 400; n++) {
        int32_t ga, ze, po, ki, kisc, sw;
        if (n < sizeof set / sizeof set[0]) {
            ga = set[n][0], ze = set[n][1], po = set[n][2], ki = set[n][3], kisc = set[n][4], sw = set[n][5];
        } else {
            ga = rnd(16383) + 16384;
            ze = rnd(127) + 128;
            po = rnd(255);
            ki = n % 3 ? rnd(16383) + 16384 : 0;
            kisc = rnd(7) + 8;
            sw = n % 2 ? rnd(1024) + 1024 : 2048;
            if (n % 5 == 0)
                ga = rnd(8) + 8;                /* e_lim at 32767 */
        }
        servo_gains_t g;
        servo_state_t s;
        exact_t x = {0, 0, 0, 0};
        servo_set_gains(&g, ga, ze, po, ki, kisc);
        servo_set_limit(&g, sw);
        servo_reset(&s);
        int32_t e = 0;
        for (long k = 0; k < 3000; k++) {
            switch (k % 4) {
            case 0: e = rnd(k % 3 ? 3000 : 5000000); break;
            case 1: e += rnd(50); break;
            case 2: e = rnd(40); break;
            default: break;
            }
            int16_t want = exact_step(&x, &g, e), got = servo_step(&s, &g, e);
            if (got != want || s.u1 != x.u1 || s.u2 != x.u2 || s.u2_res != x.res || s.e_prev != x.ep)
                fail_msg("gains %d %d %d %d %d sw %d, tick %ld, e %d: u %d want %d, u1 %d/%lld u2 %d/%lld res %d/%lld",
                         ga, ze, po, ki, kisc, sw, k, e, got, want, s.u1, (long long)x.u1, s.u2, (long long)x.u2,
                         s.u2_res, (long long)x.res);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fast_path_is_the_full_filter),
        cmocka_unit_test(full_filter_is_its_exact_definition),
        cmocka_unit_test(manual_inc_example),
        cmocka_unit_test(manual_ssi_example),
        cmocka_unit_test(with_a_pole_and_default_shift),
        cmocka_unit_test(integrator_does_not_drift),
        cmocka_unit_test(saturates_and_winds_up_no_further),
        cmocka_unit_test(torque_limit_against_the_reference),
        cmocka_unit_test(torque_limit_in_both_paths),
        cmocka_unit_test(torque_limit_winds_up_no_further),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
