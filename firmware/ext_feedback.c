/*
 * ext_feedback.c - feedback processing after the Turbo PMAC's encoder
 * conversion table (000; 001 for the tracking filter and the sum or
 * difference of entries): eight entries for the card, processed in order
 * after each tick from that tick's measurements; an axis takes an entry's
 * result as a correction of its measured position (<fbe>), as the
 * compensation table's (ext_comp.c).  docs/extensions.md.
 *
 *   $3 parallel data with filter: a field of <width> bits from bit <offset>
 *      of an axis' counter content (RCT), followed across its wrap, each
 *      cycle's change limited to the maximum change (0: none)
 *   $D exponential filter: out += clamp(gain/2^23 x (in - out), +-max)
 *   $B tracking filter: out += I; err = in - out; I += Ki/2^23 err;
 *      out += Kp/2^23 err (a second-order loop: no lag on a ramp)
 *   $E sum or difference: +-first +-second (bit 18: no second), bit 19
 *      integrated; bits 16/17 negate the first/second
 * The filters keep their output in Q16 (1/65536 count) and take the
 * difference in - out at most ERR_MAX counts per cycle; the result is rounded.
 */
/* The extensions run after every tick: their hot paths compiled for speed
 * (the rest of the firmware for size, Makefile OPT68). */
#pragma GCC optimize("O2")
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "ext.h"

ext_fb_t ext_fb[EXT_FB_N];
uint8_t ext_fb_sel;

#define FB_METHOD(s) (((s) >> 20) & 0xFu)
#define FB_SRC1(s) ((s) & 0xFFu)
#define FB_SRC2(s) (((s) >> 8) & 0xFFu)
#define FB_NEG1 (1u << 16)
#define FB_NEG2 (1u << 17)
#define FB_NO2 (1u << 18)
#define FB_INTEG (1u << 19)
#define FB_GAIN_MAX (1u << 23)
#define ERR_MAX 16383                            /* |in - out| taken at most this, counts */

/* e x g / 2^23 for |e| < 2^30 (Q16) and g <= 2^23: MULU.W, no 64-bit arithmetic */
FW_INLINE int32_t mul_gain(int32_t e, uint32_t g)
{
    uint32_t a = (uint32_t)(e < 0 ? -e : e), hi, lo;
    mulu31(a, g, &hi, &lo);
    int32_t p = (int32_t)(hi << 9 | lo >> 23);
    return e < 0 ? -p : p;
}

/* The filter's output plus a Q16 step */
FW_INLINE void add_q16(ext_fb_t *e, int32_t step)
{
    uint32_t f = (uint32_t)e->qf + (uint16_t)step;
    e->qi = pos_add(pos_add(e->qi, step >> 16), (int32_t)(f >> 16));
    e->qf = (uint16_t)f;
}

FW_INLINE int32_t out_rounded(const ext_fb_t *e)
{
    return pos_add(e->qi, e->qf >= 0x8000u);
}

/* in - out in Q16, |in - out| limited to ERR_MAX counts */
FW_INLINE int32_t err_q16(const ext_fb_t *e, int32_t in)
{
    int32_t d = pos_sub(in, e->qi);
    if (d > ERR_MAX)
        d = ERR_MAX;
    else if (d < -ERR_MAX)
        d = -ERR_MAX;
    return (int32_t)((uint32_t)d << 16) - e->qf;
}

static void start(ext_fb_t *e, int32_t in)
{
    e->started = 1;
    e->qi = in;
    e->qf = 0;
    e->iq = 0;
}

static int src_ok(unsigned code)
{
    return code < EXT_FB_N || (code >= FB_SRC_MEAS && code < FB_SRC_MEAS + MAC4_NAXES) ||
           (code >= FB_SRC_COUNTER && code < FB_SRC_COUNTER + MAC4_NAXES);
}

int32_t ext_fb_source(unsigned code)
{
    if (code < EXT_FB_N)
        return ext_fb[code].result;
    unsigned n = code & (MAC4_NAXES - 1u);        /* (FBS checked the code: src_ok) */
    if (code >= FB_SRC_COUNTER)
        return (int32_t)axes[n].counter;
    return pos_sub(axes[n].meas, ext_comp[n].cin);   /* the axis' own measurement */
}

static void parallel(ext_fb_t *e)
{
    unsigned width = e->w1 & 0xFFu, off = (e->w1 >> 8) & 0xFFu;
    uint32_t mask = width >= 32 ? 0xFFFFFFFFu : ((uint32_t)1 << width) - 1u;
    uint32_t field = ((uint32_t)ext_fb_source(FB_SRC1(e->setup)) >> off) & mask;
    if (!e->started) {
        e->started = 1;
        e->last = field;
        e->result = (int32_t)field;
        return;
    }
    uint32_t u = (field - e->last) & mask;
    if (width < 32 && (u & ((mask >> 1) + 1u)))
        u |= ~mask;                               /* the shorter way round the field's wrap */
    int32_t d = (int32_t)u, max = (int32_t)e->w2;
    if (max > 0 && (d > max || d < -max))
        d = d > 0 ? max : -max;                   /* the maximum change per cycle */
    e->last = (e->last + (uint32_t)d) & mask;
    e->result = pos_add(e->result, d);
}

void ext_fb_step(ext_fb_t *e)
{
    uint32_t s = e->setup;
    switch (FB_METHOD(s)) {
    case FB_PARALLEL:
        parallel(e);
        return;
    case FB_EXP: {
        int32_t in = ext_fb_source(FB_SRC1(s));
        if (!e->started)
            start(e, in);
        int32_t step = mul_gain(err_q16(e, in), e->w2);
        if (e->w1 && e->w1 <= ERR_MAX) {          /* the maximum change per cycle */
            int32_t max = (int32_t)(e->w1 << 16);
            step = step > max ? max : step < -max ? -max : step;
        }
        add_q16(e, step);
        e->result = out_rounded(e);
        return;
    }
    case FB_TRACK: {
        int32_t in = ext_fb_source(FB_SRC1(s));
        if (!e->started)
            start(e, in);
        add_q16(e, e->iq);                        /* the prediction: the integrator is the speed */
        int32_t err = err_q16(e, in);
        int32_t iq = e->iq + mul_gain(err, e->w2);    /* 001: Ki/2^23 Err(n) into the integrator ... */
        e->iq = iq > 0x3FFFFFFF ? 0x3FFFFFFF : iq < -0x3FFFFFFF ? -0x3FFFFFFF : iq;
        add_q16(e, mul_gain(err, e->w1));         /* ... and Kp/2^23 Err(n) into the output */
        e->result = out_rounded(e);
        return;
    }
    case FB_SUM: {
        int32_t a = ext_fb_source(FB_SRC1(s)), b = (s & FB_NO2) ? 0 : ext_fb_source(FB_SRC2(s));
        if (s & FB_NEG1)
            a = pos_sub(0, a);
        if (s & FB_NEG2)
            b = pos_sub(0, b);
        int32_t sum = pos_add(a, b);
        e->result = (s & FB_INTEG) ? pos_add(e->result, sum) : sum;
        return;
    }
    default:
        return;
    }
}

int ext_fb_setup(unsigned k, uint32_t setup)
{
    ext_fb_t *e = &ext_fb[k];
    unsigned m = FB_METHOD(setup);
    if (setup >> 24)
        return ERR_LIMIT;
    switch (m) {
    case FB_OFF:
        if (setup)
            return ERR_LIMIT;
        break;
    case FB_PARALLEL: {
        unsigned width = e->w1 & 0xFFu, off = (e->w1 >> 8) & 0xFFu;
        if ((setup & 0xFFF00u) || !src_ok(FB_SRC1(setup)) || FB_SRC1(setup) < EXT_FB_N || width < 1 ||
            width > 32 || off > 31 || (e->w1 >> 16) || e->w2 > 0x7FFFFFFFu)
            return ERR_LIMIT;
        break;
    }
    case FB_EXP:
    case FB_TRACK:
        if ((setup & 0xFFF00u) || !src_ok(FB_SRC1(setup)) || e->w2 > FB_GAIN_MAX ||
            (m == FB_TRACK ? e->w1 > FB_GAIN_MAX : e->w1 > 0x7FFFFFu))
            return ERR_LIMIT;
        break;
    case FB_SUM:
        if (!src_ok(FB_SRC1(setup)) || (!(setup & FB_NO2) && !src_ok(FB_SRC2(setup))))
            return ERR_LIMIT;
        break;
    default:
        return ERR_LIMIT;
    }
    uint32_t was = e->setup;
    e->setup = 0;
    int others = 0;
    for (unsigned i = 0; i < EXT_FB_N; i++)
        others |= ext_fb[i].setup != 0;
    if (setup && !ext_fits(((m == FB_EXP || m == FB_TRACK) ? EXT_W_FB_FILTER : EXT_W_FB_SIMPLE) +
                           (others ? 0 : EXT_W_FB_AXES))) {
        e->setup = was;
        return ERR_LOGICAL;                       /* beyond the extensions' budget (ext.h) */
    }
    e->setup = setup;
    e->started = 0;
    e->result = 0;
    e->qi = e->iq = 0;
    e->qf = 0;
    ext_on &= (uint16_t)~EXT_FB_ON;
    for (unsigned i = 0; i < EXT_FB_N; i++)
        if (ext_fb[i].setup)
            ext_on |= EXT_FB_ON;
    return 0;
}
