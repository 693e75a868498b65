/* The extensions' arithmetic (firmware/ext_comp.c, ext_compare.c) against
 * double-precision models: the compensation table's interpolation in one
 * and two dimensions with wrap and edges (PMAC DEFINE COMP semantics), the
 * cell tracking from tick to tick, and the position compare's crossings. */
#include <math.h>
#include <stdlib.h>
#include "unit_support.h"
#include "ext.h"
#include "card.h"

/* ---- the model: PMAC's table as a function of the source positions ------- */
typedef struct {
    int rows, cols, wrap;
    double sp_c, sp_r;          /* column spacing (row source), row spacing (column source) */
    double e[EXT_COMP_MAX];     /* grid, e[0] the origin */
} model_t;

static double grid(const model_t *m, int i, int j) { return m->e[i * (m->cols + 1) + j]; }

/* where a source is on its axis of the grid: index and fraction */
static void locate(double p, double sp, int cells, int wrap, int *j, double *f)
{
    double span = sp * cells;
    if (wrap) {
        p = fmod(p, span);
        if (p < 0)
            p += span;
    } else if (p <= 0) {
        *j = 0, *f = 0;
        return;
    } else if (p >= span) {
        *j = cells, *f = 0;
        return;
    }
    *j = (int)floor(p / sp);
    *f = (p - *j * sp) / sp;
    if (*j >= cells)            /* rounding at the top edge */
        *j = cells - 1, *f = 1;
}

static double model_value(const model_t *m, double pr, double pc)
{
    int j, i = 0;
    double f, g = 0;
    locate(pr, m->sp_c, m->cols, m->wrap, &j, &f);
    if (m->rows)
        locate(pc, m->sp_r, m->rows, m->wrap, &i, &g);
    int j1 = f > 0 ? j + 1 : j, i1 = g > 0 ? i + 1 : i;
    double a = grid(m, i, j) + (grid(m, i, j1) - grid(m, i, j)) * f;
    double b = grid(m, i1, j) + (grid(m, i1, j1) - grid(m, i1, j)) * f;
    return a + (b - a) * g;
}

/* the same table in the firmware's form, entries as a host loads them */
static void make_table(ext_comp_t *t, model_t *m, int rows, int cols, int sp_c, int sp_r, int wrap)
{
    memset(t, 0, sizeof *t);
    memset(m, 0, sizeof *m);
    t->rows = (uint8_t)rows, t->cols = (uint8_t)cols, t->wrap = (uint8_t)wrap;
    t->n = (uint16_t)((rows + 1) * (cols + 1) - 1);
    t->cr = (ext_cell_t){.sp = (uint16_t)sp_c, .cells = (uint16_t)cols, .wrap = (uint8_t)wrap};
    t->cc = (ext_cell_t){.sp = (uint16_t)(rows ? sp_r : 1), .cells = (uint16_t)(rows ? rows : 1), .wrap = (uint8_t)wrap};
    m->rows = rows, m->cols = cols, m->wrap = wrap, m->sp_c = sp_c, m->sp_r = sp_r;
    for (unsigned k = 1; k <= t->n; k++) {
        int v = (int)(rnd32() % 32767u) - 16384;
        t->e[k] = (int16_t)v;
        m->e[k] = v;
    }
    if (wrap) {                 /* I30: the last entry is the correction at the origin too */
        t->e[0] = t->e[t->n];
        m->e[0] = m->e[t->n];
    }
}

static int32_t rnd_pos(int32_t span) { return (int32_t)(rnd32() % (uint32_t)(2 * span + 1)) - span; }

static void check_tables(int rows, int cols, int sp_c, int sp_r, int wrap, double tol)
{
    ext_comp_t t;
    model_t m;
    for (int rep = 0; rep < 20; rep++) {
        make_table(&t, &m, rows, cols, sp_c, sp_r, wrap);
        int32_t span_r = sp_c * cols, span_c = sp_r * (rows ? rows : 1);
        /* jumps (ext_cell_set), then small moves (ext_cell_move) as from tick to tick */
        int32_t pr = rnd_pos(3 * span_r), pc = rnd_pos(3 * span_c);
        ext_cell_set(&t.cr, pr);
        ext_cell_set(&t.cc, pc);
        for (int k = 0; k < 2000; k++) {
            if (k % 500 == 0) {
                pr = rnd_pos(3 * span_r);
                pc = rnd_pos(3 * span_c);
                ext_cell_set(&t.cr, pr);
                ext_cell_set(&t.cc, pc);
            } else {
                pr += rnd_pos(sp_c / 2 + 1);
                pc += rnd_pos(sp_r / 2 + 1);
                ext_cell_move(&t.cr, pr);
                ext_cell_move(&t.cc, pc);
            }
            double want = model_value(&m, pr, pc);
            double got = ext_comp_value(&t);
            if (fabs(got - want) > tol + 1e-6) {
                fail_msg("r %d c %d sp %d/%d wrap %d at %d,%d: %g, model %g", rows, cols, sp_c, sp_r, wrap,
                         (int)pr, (int)pc, got, want);
            }
        }
    }
}

/* one rounding per interpolation: half an entry LSB each */
static void test_one_dimensional(void **state)
{
    (void)state;
    check_tables(0, 16, 250, 1, 0, 0.5);
    check_tables(0, 16, 250, 1, 1, 0.5);
    check_tables(0, 255, 65535, 1, 1, 0.5);
    check_tables(0, 1, 7, 1, 0, 0.5);
}

static void test_two_dimensional(void **state)
{
    (void)state;
    check_tables(3, 4, 1000, 500, 0, 1.5);
    check_tables(3, 4, 1000, 500, 1, 1.5);
    check_tables(15, 15, 4096, 65535, 1, 1.5);
    check_tables(1, 1, 3, 5, 0, 1.5);
}

/* the interpolation's rounding: to nearest, symmetric in the sign */
static void test_lerp(void **state)
{
    (void)state;
    for (int k = 0; k < 100000; k++) {
        int32_t a = (int32_t)(rnd32() % 32767u) - 16384, b = (int32_t)(rnd32() % 32767u) - 16384;
        uint16_t sp = (uint16_t)(rnd32() % 65535u + 1u), f = (uint16_t)(rnd32() % sp);
        double want = a + (double)(b - a) * f / sp;
        int32_t got = ext_lerp(a, b, f, sp);
        assert_true(fabs(got - want) <= 0.5);
    }
}

/* ---- position compare: crossings of P, P+N, ..., up to E ------------------- */
static long model_points_at_or_below(long p, long p0, long n, long e)
{
    if (p < p0)
        return 0;
    long k = n ? (e > p0 ? (e - p0) / n + 1 : 1) : 1;
    long q = n ? (p - p0) / n + 1 : 1;
    return q < k ? q : k;
}

static void compare_case(long p0, long n, long e, int32_t step)
{
    ext_pc_t c = {0};
    c.p0 = p0;
    c.n = n;
    c.k = n && e > p0 ? (int32_t)((e - p0) / n + 1) : 1;
    c.last_pt = p0 + (c.k - 1) * n;
    long p = p0 - 5000 - (long)(rnd32() % 1000u);
    ext_pc_locate(&c, p);
    long total = 0, model_total = 0;
    for (int k = 0; k < 4000; k++) {
        long q = p + rnd_pos(step) + (k < 2000 ? step / 2 : -step / 2);
        long crossed = labs(model_points_at_or_below(q, p0, n, e) - model_points_at_or_below(p, p0, n, e));
        uint32_t got = (q >= c.lo && q < c.hi) ? 0 : ext_pc_cross(&c, q);
        assert_int_equal(got, crossed);
        total += got;
        model_total += crossed;
        p = q;
    }
    assert_true(model_total > 0);
    assert_int_equal(total, model_total);
}

static void test_compare_crossings(void **state)
{
    (void)state;
    compare_case(1000, 0, 0, 200);          /* once */
    compare_case(1000, 100, 9000, 300);     /* every 100 in a window, several per step */
    compare_case(-7000, 1, -6000, 50);      /* every count */
    compare_case(0, 333, 0x7FFFFFFFL, 1000);/* an open window */
}

/* ---- feedback processing against double models ------------------------------ */
static void fb_start(unsigned k, uint32_t setup, uint32_t w1, uint32_t w2)
{
    ext_fb[k].setup = 0;
    ext_fb[k].w1 = w1;
    ext_fb[k].w2 = w2;
    assert_int_equal(ext_fb_setup(k, setup), 0);
}

/* the exponential filter: out += clamp(g (in - out), max), in Q8 */
static void test_exponential_filter(void **state)
{
    (void)state;
    memset(axes, 0, sizeof axes);
    memset(ext_comp, 0, sizeof ext_comp);
    const uint32_t gain = (1u << 23) / 10, max = 40;
    fb_start(0, 0xD00000u | FB_SRC_MEAS, max, gain);
    double out = 0, g = gain / 8388608.0;
    for (int k = 0; k < 3000; k++) {
        axes[0].meas = k < 1000 ? 5000 : k < 2000 ? -300 + (int32_t)(rnd32() % 61u) - 30 : 7 * k;
        if (k == 0)
            out = axes[0].meas;
        double step = g * (axes[0].meas - out);
        step = step > max ? max : step < -(double)max ? -(double)max : step;
        out += step;
        ext_fb_step(&ext_fb[0]);
        if (fabs(ext_fb[0].result - out) > 1.0)
            fail_msg("tick %d: %d, model %.3f", k, ext_fb[0].result, out);
    }
}

/* the tracking filter (001): out += I, then with err = in - out,
 * I += Ki err and out += Kp err: follows a ramp without a lag once
 * settled (the integrator is the speed) */
static void test_tracking_filter(void **state)
{
    (void)state;
    memset(axes, 0, sizeof axes);
    memset(ext_comp, 0, sizeof ext_comp);
    const uint32_t kp = (1u << 23) / 4, ki = (1u << 23) / 64;
    fb_start(1, 0xB00000u | (FB_SRC_MEAS + 2), kp, ki);
    double out = 0, integ = 0, p = kp / 8388608.0, i = ki / 8388608.0;
    for (int k = 0; k < 4000; k++) {
        axes[2].meas = k < 500 ? 0 : 25 * (k - 500);
        out += integ;
        double err = axes[2].meas - out;
        integ += i * err;
        out += p * err;
        ext_fb_step(&ext_fb[1]);
        if (fabs(ext_fb[1].result - out) > 1.5)
            fail_msg("tick %d: %d, model %.3f", k, ext_fb[1].result, out);
    }
    assert_true(abs(ext_fb[1].result - axes[2].meas) <= 1);
}

/* $E and $3: the control bits; a field of the counter across its wrap with
 * the maximum change per cycle */
static void test_sum_and_parallel(void **state)
{
    (void)state;
    memset(axes, 0, sizeof axes);
    memset(ext_comp, 0, sizeof ext_comp);
    axes[0].meas = 1000;
    axes[1].meas = 234;
    ext_comp[1].cin = 4;                          /* the source is the axis' own measurement */
    fb_start(0, 0xE00000u | (FB_SRC_MEAS + 1) << 8 | FB_SRC_MEAS, 0, 0);
    ext_fb_step(&ext_fb[0]);
    assert_int_equal(ext_fb[0].result, 1230);
    fb_start(0, 0xE20000u | (FB_SRC_MEAS + 1) << 8 | FB_SRC_MEAS, 0, 0);   /* minus the second */
    ext_fb_step(&ext_fb[0]);
    assert_int_equal(ext_fb[0].result, 770);
    fb_start(0, 0xE50000u | FB_SRC_MEAS, 0, 0);    /* the first negated, no second */
    ext_fb_step(&ext_fb[0]);
    assert_int_equal(ext_fb[0].result, -1000);
    fb_start(0, 0xE80000u | (FB_SRC_MEAS + 1) << 8 | FB_SRC_MEAS, 0, 0);   /* integrated */
    ext_fb_step(&ext_fb[0]);
    ext_fb_step(&ext_fb[0]);
    assert_int_equal(ext_fb[0].result, 2460);
    assert_int_equal(ext_fb_setup(0, 0x700000u), ERR_LIMIT);               /* no such method */
    assert_int_equal(ext_fb_setup(0, 0xE00000u | 0x33), ERR_LIMIT);        /* no such source */
    /* bits 4..11 of the 24-bit counter, the change limited to 5 per cycle:
     * against the unwrapped counter's position / 16, across the counter's
     * wrap and one jump of 1600 counts (100 fields, less than half the
     * field: more would be the other way round), which it follows at 5
     * per cycle until it has caught up */
    fb_start(2, 0x300000u | (FB_SRC_COUNTER + 3), 8 | 4 << 8, 5);
    const int64_t start = 0xFFFF00;
    int64_t unw = start;
    int32_t prev = 0;
    for (int k = 0; k < 2000; k++) {
        int32_t d = k == 1000 ? 1600 : (int32_t)(rnd32() % 97u) - 40;
        if (k)
            unw += d;
        axes[3].counter = (uint32_t)(unw & 0xFFFFFF);
        ext_fb_step(&ext_fb[2]);
        int64_t model = (unw >> 4) - (start >> 4) + ((start >> 4) & 0xFF);
        if (k < 1000 || k >= 1100)
            assert_int_equal(ext_fb[2].result, model);
        else
            assert_true(ext_fb[2].result - prev <= 5 && ext_fb[2].result - prev >= -5);
        prev = ext_fb[2].result;
    }
}

/* ---- the plant's leadscrew (harness/plant.c) against libm ------------------ */
static void test_plant_leadscrew(void **state)
{
    (void)state;
    plant_axis_t p = {.lead_amp = 20.0, .lead_pitch = 4000.0, .lead_ppm = 50.0};
    for (int k = -20000; k <= 20000; k++) {
        double u = k * 13.7;
        double want = 20.0 * sin(2 * M_PI * u / 4000.0) + 50e-6 * u;
        assert_true(fabs(plant_lead_error(&p, u) - want) < 1e-6);
    }
    plant_axis_t none = {0};
    assert_true(plant_lead_error(&none, 12345.0) == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plant_leadscrew),
        cmocka_unit_test(test_exponential_filter),
        cmocka_unit_test(test_tracking_filter),
        cmocka_unit_test(test_sum_and_parallel),
        cmocka_unit_test(test_lerp),
        cmocka_unit_test(test_one_dimensional),
        cmocka_unit_test(test_two_dimensional),
        cmocka_unit_test(test_compare_crossings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
