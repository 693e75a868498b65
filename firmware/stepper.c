/*
 * stepper.c - the MAC4-STP (docs/stepper.md).
 *
 * Open loop: the profile generator (motion.c, one SP of 32 ms ahead) gives
 * a position per tick; each 8 ms tick the step generator gets the rate that
 * emits exactly that tick's distance (400 generator clocks per tick, the
 * remainder carried), so the steps follow the profile's velocity.  The
 * profile obeys the start/stop frequency (5.14): from stand-still it jumps
 * to <ssf>, and it stops from at most <ssf>.  Positioning ends in the creep
 * phase (5.6, diagram 5.2): <stc> steps at <lv>, programmed into the pulse
 * down-counter AX_PULSES with the exact number of steps still missing and
 * counted by the step-pulse interrupt, so the axis stops on the target step.
 * BOOST (4.1.4) is raised <bt> ms before the first step of every move and
 * dropped at stand-still.
 *
 * Position units are steps.  The position counter counts either the
 * generated steps (<et> 0, solder bridge BR closed) or an encoder's
 * increments (BR open, or an external encoder), which ms/(4 es) converts
 * to steps (4.4.2.3).
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "stepper.h"

/* ======================================================================== */
/* arithmetic (every card; unit-tested natively)                             */
/* ======================================================================== */
static int64_t mag64(int64_t v) { return v < 0 ? -v : v; }

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

/* ---- the same in 32 bits ---------------------------------------------------
 * A move with less than 2^32 to go (Q16: 65536 steps) and speeds and ramps
 * below 2^30 (16384 steps per SP) needs no 64-bit arithmetic: stp_position()
 * and stp_positioning() take this path then, with exactly the results of the
 * 64-bit one (a 64-bit add or compare is a few instructions on the 68000; a
 * 64-bit product prof_umul32(), a shift by a variable amount a helper call). */
#define STP_R30 0x40000000u

/* stp_must_brake() for 0 <= u, dec < 2^30, rem < 2^32, ssf >= 1. */
static inline __attribute__((always_inline)) int stp_must_brake32(int32_t u, int32_t dec, uint32_t rem, int32_t ssf)
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
static inline __attribute__((always_inline)) int stp_position32(prof_t *p, uint32_t rem, int neg, int32_t vel,
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
static inline __attribute__((always_inline)) int stp_args32(const prof_t *p, int64_t target, int64_t vmax,
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


int32_t stp_scale_call(int32_t c, uint32_t ratio_q16) { return stp_scale(c, ratio_q16); }

uint16_t stp_rate_of(uint32_t mag, uint32_t *carry, uint16_t clocks_per_tick)
{
    uint32_t t = mag + *carry;
    if (t < mag || t >= ((uint32_t)clocks_per_tick << 16)) {
        *carry = 0;
        return 0xFFFFu;                          /* beyond 50 kHz (500 kHz): saturated */
    }
    uint32_t qr = stp_divu16(t, clocks_per_tick);
    *carry = qr >> 16;
    return (uint16_t)qr;
}

int32_t stp_hz_of(uint16_t rate, int turbo)
{
    int32_t hz = (int32_t)((mulu16(rate, 25000u) + 0x4000u) >> 15);   /* x 50000 / 65536 */
    return turbo ? hz * 10 : hz;
}

uint16_t stp_rate_hz(uint32_t hz)
{
    if (hz >= STP_CLK_HZ)
        return 0xFFFFu;
    return (uint16_t)stp_divu16(hz << 15, 25000u);   /* hz x 65536 / 50000, rounded down */
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

/* ======================================================================== */
/* the MAC4-STP card                                                         */
/* ======================================================================== */
#if MAC4_CARD == MAC4_CARD_STP
#include "card.h"
#include "params.h"
#include "motion.h"

/* CREEP_TRIM: at stand-still, the step counter a step or two off the
 * setpoint (the generator's phase): those steps at <lv>, any mode. */
enum { CREEP_IDLE = STP_CREEP_IDLE, CREEP_REQ, CREEP_WAIT, CREEP_RUN, CREEP_DONE, CREEP_TRIM };
#define TRIM_MAX 3

/* The creep's pulses are counted by interrupt up to 1000 Hz (rate register
 * 1311, TURBO 131); faster, the tick reads the down-counter instead. */
#define PULSE_IRQ_MAX_RATE 1311u
#define PULSE_IRQ_MAX_RATE_TURBO 131u

stp_t stp_ax[MAC4_NAXES];
uint8_t stp_conv;           /* bit n: axis n's counter counts increments */

/* ---- measurement ---------------------------------------------------------- */
void stp_init(unsigned n)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    int32_t et = PAR(n, ET);
    int exact;
    int8_t dir = s->dir;
    *s = (stp_t){0};
    s->dir = dir;
    s->clocks = STP_TICK_CLOCKS;
    s->lim = (uint32_t)STP_TICK_CLOCKS << 16;
    s->obits = stp_dir_bit(x, dir);
    if (et == 0) {                               /* the step counter (4.4.1.1) */
        stp_conv = (uint8_t)(stp_conv & ~(1u << n));
        s->ratio = 0x10000u;
    } else {                                     /* increments: ms / (4 es) (4.4.2.3) */
        stp_conv = (uint8_t)(stp_conv | (1u << n));
        s->ratio = stp_ratio_q16((uint32_t)PAR(n, MS), (uint32_t)PAR(n, ES), &exact);
        /* one increment is ratio steps: the tolerance of RFE and <tr> (4.8.1, 5.6) */
        s->tol = (int32_t)((s->ratio >> 16) + ((s->ratio & 0xFFFFu) != 0));
        s->inc = x->meas;                        /* 0, or the absolute encoder's value */
        s->conv = stp_scale_call(s->inc, s->ratio);
        x->meas = s->conv;
    }
    /* BR (2.4.2): closed to count the steps (<et> 0), open for the encoder (<et> 1) */
    if (et <= 1) {
        int br = (hal_rd16(AX_REG(n, AX_IN)) & AX_IN_BR_STEPS) != 0;
        if (br != (et == 0))
            axis_error(n, UB(ENCODER_F) | UB(LOGO_F), ERR_LOGICAL);
    }
}

int32_t stp_counts(unsigned n)
{
    if (stp_conv & (1u << n))
        return stp_ax[n].inc;
    return (axes[n].ustat & UB(REV_O)) ? -axes[n].meas : axes[n].meas;
}

int32_t stp_tol(unsigned n) { return stp_ax[n].tol; }

/* stp_edge() with the axis' pointers at hand (the tick's creep path). */
static inline __attribute__((always_inline)) int32_t edge_of(const axis_t *x, const stp_t *s, unsigned n, int32_t d)
{
    if (stp_conv & (1u << n))
        return stp_scale_call(s->inc + d, s->ratio);   /* a creep's start, an index: a call */
    return x->meas + ((x->ustat & UB(REV_O)) ? -d : d);
}

int32_t stp_edge(unsigned n, int32_t d) { return edge_of(&axes[n], &stp_ax[n], n, d); }

/* The position now, re-reading the counter (the tick's reading is from its
 * start); external encoders keep the tick's value. */
static inline __attribute__((always_inline)) int32_t meas_now(const axis_t *x, const stp_t *s, unsigned n)
{
    if (x->mk != MK_COUNTER)
        return x->meas;
    uint32_t hi = hal_rd16(AX_REG(n, AX_CNT_HI));           /* latches LO */
    uint32_t raw = (hi << 16) | hal_rd16(AX_REG(n, AX_CNT_LO));
    int32_t d = (int32_t)((raw - x->counter) << 8) >> 8;
    return edge_of(x, s, n, d);
}

/* ---- the creep phase ------------------------------------------------------ */
static void creep_stop(axis_t *x, stp_t *s, uint32_t reg)   /* reg: AX_REG(n, 0) */
{
    if (s->creep == CREEP_RUN || s->creep == CREEP_TRIM) {
        hal_wr16(reg + AX_RATE, 0);
        hal_wr16(reg + AX_PULSES, 0);                       /* free running again */
        s->rate = 0;
        s->carry = 0;
    }
    x->ctrl = (uint16_t)(x->ctrl & ~(AX_CTRL_PULSE_IE | AX_CTRL_DONE_IE));
    hal_wr16(reg + AX_CTRL, (uint16_t)(x->ctrl | AX_CTRL_PULSE_ACK | AX_CTRL_DONE_ACK));
    s->creep = CREEP_IDLE;
    s->hw_done = 0;
}

/* A creep broken off (a new mode, a protective stop): the profile goes on
 * from where the steps are. */
static void creep_abort(unsigned n)
{
    uint8_t c = stp_ax[n].creep;
    creep_stop(&axes[n], &stp_ax[n], AX_REG(n, 0));
    if (c != CREEP_DONE)
        motion_hold(n);
}

/* Tick: the ramp has ended on creep_from, the generator still runs at the
 * ramp's last rate (at most <ssf>). */
static inline __attribute__((always_inline)) void creep_begin(axis_t *x, stp_t *s, unsigned n, uint32_t reg)
{
    hal_wr16(reg + AX_RATE, 0);                  /* no pulse while we count */
    s->rate = 0;
    int32_t cur = meas_now(x, s, n);
    int32_t miss = (int32_t)(x->target >> 16) - cur;
    if (s->creep == CREEP_REQ) {
        /* the profile's creep segment is the down-counter's: the setpoint is at its end */
        x->start_i = x->sp_i = x->end_i;
        x->start_f = x->sp_f = x->end_f;
        x->st_i = 0;
        x->st_f = 0;
    }
    int8_t dir = miss < 0 ? -1 : 1;
    if (miss == 0) {
        s->creep = CREEP_DONE;
        return;
    }
    if (dir != s->dir && s->creep == CREEP_REQ) {
        s->creep = CREEP_WAIT;                   /* a reversal: stand still for one tick first */
        return;
    }
    uint32_t m = (uint32_t)(miss < 0 ? -miss : miss);
    s->creep_n = (uint16_t)(m > 0xFFFFu ? 0xFFFFu : m);
    s->counted = 0;
    s->hw_done = 0;
    s->creep_dir = dir;
    s->creep_base = cur;
    s->dir = dir;
    s->obits = (uint16_t)((s->obits & ~AX_CTRL_DIR) | stp_dir_bit(x, dir));
    s->carry = 0;
    hal_wr16(reg + AX_PULSES, s->creep_n);       /* exactly this many, then the output stops */
    x->ctrl = (uint16_t)(x->ctrl | AX_CTRL_DONE_IE);
    s->creep_irq = s->lv_rate <= (s->clocks == STP_TICK_CLOCKS ? PULSE_IRQ_MAX_RATE : PULSE_IRQ_MAX_RATE_TURBO);
    if (s->creep_irq)
        x->ctrl = (uint16_t)(x->ctrl | AX_CTRL_PULSE_IE);
    s->rate = s->lv_rate;                        /* DIR and rate go out in axis_output */
    s->creep = CREEP_RUN;
}

/* Tick, while a creep or a trim is requested or running: 1 if the
 * down-counter has the axis this tick, 2 if the setpoint moved under the
 * caller, 0 if nothing. */
static inline __attribute__((always_inline)) int creep_tick(axis_t *x, stp_t *s, unsigned n, unsigned phase,
                                                            int32_t old_i, uint16_t old_f)
{
    uint32_t reg = AX_REG(n, 0);
    if (s->creep == CREEP_TRIM) {
        if (x->sp_i == old_i && x->sp_f == old_f && !(x->in & AX_IN_PDONE)) {
            x->setpoint = pos_add(old_i, old_f >= 0x8000u);
            x->ferr = pos_sub(x->setpoint, x->meas);
            return 1;                            /* the trim's pulses still to come */
        }
        creep_stop(x, s, reg);                   /* done, or the profile moves on */
        return 0;
    }
    if (x->mode != M_POSITIONING || x->stop_then) {
        creep_abort(n);                          /* a new mode, or a protective stop */
        return 2;
    }
    if (s->creep == CREEP_REQ && phase != 0)
        return 0;                                /* the ramp's last segment still runs */
    if (s->creep == CREEP_REQ || s->creep == CREEP_WAIT)
        creep_begin(x, s, n, reg);
    if (s->creep != CREEP_RUN)
        return 2;
    uint16_t left;
    if (s->hw_done || (x->in & AX_IN_PDONE)) {
        creep_stop(x, s, reg);
        s->creep = CREEP_DONE;
        left = 0;
    } else if (x->ctrl & AX_CTRL_PULSE_IE) {
        left = (uint16_t)(s->creep_n - s->counted);
    } else {
        left = hal_rd16(reg + AX_PULSES);
    }
    int32_t done = (int32_t)(s->creep_n - left);
    x->setpoint = pos_add(s->creep_base, s->creep_dir < 0 ? -done : done);
    x->ferr = pos_sub(x->setpoint, x->meas);
    return 1;
}

/* The direction of the creep phase's pulses while they run (the profile
 * stands meanwhile): for the limit switches (motion_supervise). */
int stp_creep_dir(unsigned n)
{
    const stp_t *s = &stp_ax[n];
    return s->creep == CREEP_RUN ? s->creep_dir : 0;
}

/* ---- motion (motion.c, main loop) ----------------------------------------- */
void stp_motion_plan(unsigned n, int64_t ssf, stp_plan_t *pl)
{
    /* TURBO and USR change only at stand-still, before the next E */
    pl->turbo = (axis_at[n]->sstat & SB(TURBO)) ? AX_CTRL_TURBO : 0;
    pl->ssf = (int32_t)stp_ssf_grid(ssf, pl->turbo != 0);   /* at most 0x7FFFFFFF */
    uint16_t lv = (uint16_t)(stp_rate_hz((uint32_t)PAR(n, LV)) >> PAR(n, SF));
    pl->lv_rate = lv ? lv : 1u;
}

void stp_motion_start(unsigned n, uint8_t mode, const stp_plan_t *pl)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    if (s->creep != CREEP_IDLE)
        creep_abort(n);
    uint16_t turbo = pl->turbo;
    s->clocks = turbo ? STP_TICK_CLOCKS_TURBO : STP_TICK_CLOCKS;
    s->lim = (uint32_t)s->clocks << 16;
    s->obits = (uint16_t)((s->obits & AX_CTRL_BOOST) | turbo | stp_dir_bit(x, s->dir));
    s->ssf = pl->ssf;
    s->lv_rate = pl->lv_rate;
    if (mode == M_POSITIONING) {
        /* the ramps end <stc> steps before the target, on the near side */
        int64_t rem = x->target - x->prof.pos, stc = (int64_t)PAR(n, STC) << 16;
        if (rem > stc)
            s->creep_from = x->target - stc;
        else if (rem < -stc)
            s->creep_from = x->target + stc;
        else
            s->creep_from = x->prof.pos;
    }
}

int stp_positioning(unsigned n, int64_t vmax, int64_t acc, int64_t dec, int64_t ssf)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    PIN_PTR(x);
    PIN_PTR(s);
    prof_t *p = &x->prof;
    switch (x->phase) {
    case 0: {                                    /* the ramps, to creep_from */
        uint32_t r;
        int neg;
        int32_t a[5];
        if (stp_args32(p, s->creep_from, vmax, acc, dec, ssf, &r, &neg, a)) {
            if (r != 0 || a[0] > a[4] || a[0] < -a[4]) {
                stp_position32(p, r, neg, a[0], a[1], a[2], a[3], a[4]);
                return 0;
            }
        } else if (p->pos != s->creep_from || mag64(p->vel) > ssf) {
            stp_position(p, s->creep_from, vmax, acc, dec, ssf);
            return 0;
        }
        x->phase = 1;                            /* landed, from at most <ssf> */
    }
        /* fall through */
    case 1:                                      /* the creep: <stc> steps at <lv> */
        s->creep = CREEP_REQ;
        p->pos = x->target;
        p->vel = 0;
        x->phase = 2;
        return 0;
    default:                                     /* until the last pulse is out */
        if (s->creep != CREEP_DONE)
            return 0;
        s->creep = CREEP_IDLE;
        return 1;
    }
}

/* Once per SP for every axis: the system status bits (7.1.2,
 * docs/interpretations.md). */
static inline __attribute__((always_inline)) void status_of(axis_t *x, const stp_t *s)
{
    uint32_t ss = x->sstat & ~(SB(DR_DISABLE) | SB(SERVO_ON) | SB(BOOST) | SB(BOOST_EN) | SB(IRQ_LINE) |
                               SB(LED_FAULT) | SB(PHASE5) | SB(BOOST_LOCK));
    if (s->dir < 0)
        ss |= SB(DR_DISABLE);                    /* "direction": motion in negative direction */
    if (x->mode != M_DISABLE && x->mode != M_TEST)
        ss |= SB(SERVO_ON);                      /* profile and step output in charge */
    if (s->boost)
        ss |= SB(BOOST);                         /* the BOOST output */
    if (s->boost_en)
        ss |= SB(BOOST_EN);                      /* BOOST on for <bt>: the move may go */
    else if (s->boost)
        ss |= SB(BOOST_LOCK);                    /* a move waits for the BOOST lead time */
    if (x->ctrl & AX_CTRL_PULSE_IE)
        ss |= SB(IRQ_LINE);                      /* creep pulses counted by interrupt */
    if (s->creep == CREEP_RUN) {
        ss |= SB(PHASE5);                        /* the creep phase */
        /* ... to its end: the last pulse's interrupt has already cleared
         * PULSE_IE when it comes between a tick and this (the next tick ends
         * the creep) */
        if (s->hw_done && s->creep_irq)
            ss |= SB(IRQ_LINE);
    }
    if (x->ustat & US_ERRORS)
        ss |= SB(LED_FAULT);                     /* LED F */
    x->sstat = ss;
}

void stp_status(unsigned n)
{
    axis_t *x = axis_at[n];
    const stp_t *s = &stp_ax[n];
    PIN_PTR(x);
    PIN_PTR(s);
    status_of(x, s);
}

/* stp_profile_end() but for a move under way (below). */
static __attribute__((noinline)) void profile_end(axis_t *x, stp_t *s, unsigned n, int64_t before, int64_t before_vel)
{
    prof_t *p = &x->prof;
    int wants = s->creep != CREEP_IDLE || p->pos != before;
    if (wants && !s->active) {
        if (!s->boost) {                         /* BOOST on, <bt> before the first step */
            s->boost = 1;
            s->obits |= AX_CTRL_BOOST;
            s->boost_tick = card_ticks;          /* the next tick puts it out */
        }
        /* this segment starts at the next SP boundary, tick `start` */
        uint32_t start = (card_ticks + (PROFILE_DIVIDER - 1u)) & ~(PROFILE_DIVIDER - 1u);
        if (((start - s->boost_tick) << 3) >= (uint32_t)PAR(n, BT)) {
            s->active = 1;
            s->boost_en = 1;
        } else {                                 /* not yet: stand still this SP */
            p->pos = before;
            p->vel = 0;
            if (s->creep == CREEP_REQ) {
                s->creep = CREEP_IDLE;
                x->phase = 1;
            }
        }
    } else if (!wants && s->boost && p->vel == 0 && before_vel == 0) {
        s->active = s->boost = s->boost_en = 0;  /* stand-still: BOOST off */
        s->obits &= (uint16_t)~AX_CTRL_BOOST;
    }
    status_of(x, s);
}

void stp_profile_end(unsigned n, int64_t before, int64_t before_vel)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    PIN_PTR(x);
    PIN_PTR(s);
    /* a move under way that goes on: BOOST stays as it is */
    if (s->active && (s->creep != CREEP_IDLE || x->prof.pos != before))
        status_of(x, s);
    else
        profile_end(x, s, n, before, before_vel);
}

/* ---- the tick (the common path is stp_servo in stepper.h) ------------------ */
/* The setpoint stands still but the step counter is a step or two off it:
 * the generator's phase (docs/stepper.md).  Those steps at <lv>. */
void stp_trim(unsigned n)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    int32_t e = x->ferr;
    if (e < -TRIM_MAX || e > TRIM_MAX || s->creep != CREEP_IDLE) {
        s->rate = 0;
        return;
    }
    int8_t dir = e < 0 ? -1 : 1;
    s->dir = dir;
    s->obits = (uint16_t)((s->obits & ~AX_CTRL_DIR) | stp_dir_bit(x, dir));
    s->carry = 0;
    hal_wr16(AX_REG(n, AX_PULSES), (uint16_t)(e < 0 ? -e : e));
    s->creep = CREEP_TRIM;
    s->rate = s->lv_rate;
}

/* stp_servo (stepper.h) in every case: creep and trim, a new direction,
 * stand-still, a jump.  One copy per axis (stp_servo_full_0..3), so that
 * the axis, its stp_t and its registers are constants: the tick in which
 * four creep phases begin runs four of them. */
static inline __attribute__((always_inline)) void servo_full(unsigned n, unsigned phase, int32_t old_i,
                                                             uint16_t old_f)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    stp_t *s = &stp_ax[n];
    PIN_PTR(s);
    if (s->creep != CREEP_IDLE) {
        int c = creep_tick(x, s, n, phase, old_i, old_f);
        if (c == 1)
            return;
        if (c == 2) {
            old_i = x->sp_i;
            old_f = x->sp_f;
        }
    }
    /* the setpoint of the last tick is where its steps have brought the
     * axis by now (the steps of this tick are still to come, 4.8.1) */
    int32_t di = x->sp_i - old_i;
    int32_t d;
    if (di > 30000 || di < -30000)
        d = di > 0 ? 0x7FFFFFFF : -0x7FFFFFFF;
    else
        d = (int32_t)((uint32_t)di << 16) + (int32_t)x->sp_f - (int32_t)old_f;
    int32_t sp = old_i + (old_f >= 0x8000u);
    x->setpoint = sp;
    x->ferr = pos_sub(sp, x->meas);
    if (d == 0) {
        /* stand-still: the step counter must read the setpoint (stp_trim) */
        if (x->ferr && !s->rate && !x->prof.vel && !(stp_conv & (1u << n)))
            stp_trim(n);
        else
            s->rate = 0;
        return;
    }
    int8_t dir = 1;
    uint32_t mag = (uint32_t)d;
    if (d < 0) {
        dir = -1;
        mag = (uint32_t)-d;
    }
    if (dir != s->dir) {                         /* a new direction: DIR, and no remainder */
        s->dir = dir;
        s->carry = 0;
        s->obits = (uint16_t)((s->obits & ~AX_CTRL_DIR) | stp_dir_bit(x, dir));
    }
    uint32_t t = mag + s->carry;
    stp_load_rate(s, t < mag ? 0xFFFFFFFFu : t);  /* a wrapped sum saturates */
}

void stp_servo_full_0(unsigned phase, int32_t old_i, uint16_t old_f) { servo_full(0, phase, old_i, old_f); }
void stp_servo_full_1(unsigned phase, int32_t old_i, uint16_t old_f) { servo_full(1, phase, old_i, old_f); }
void stp_servo_full_2(unsigned phase, int32_t old_i, uint16_t old_f) { servo_full(2, phase, old_i, old_f); }
void stp_servo_full_3(unsigned phase, int32_t old_i, uint16_t old_f) { servo_full(3, phase, old_i, old_f); }

/* axis_output, disabled (with something to switch off) or in test mode. */
void stp_idle_output(unsigned n)
{
    axis_t *x = axis_at[n];
    stp_t *s = &stp_ax[n];
    if (x->mode == M_TEST) {
        /* 5.13: <da> in Hz straight to the generator, no profile, no USR */
        int32_t da = PAR(n, DA);
        s->rate = stp_rate_hz((uint32_t)(da < 0 ? -da : da));
        if (da)
            s->dir = da < 0 ? -1 : 1;
        s->obits = (uint16_t)((s->obits & AX_CTRL_TURBO) | (s->dir >= 0 ? AX_CTRL_DIR : 0));
        s->active = s->boost = s->boost_en = 0;
        return;
    }
    if (s->creep != CREEP_IDLE)
        creep_stop(x, s, AX_REG(n, 0));
    s->rate = 0;
    s->carry = 0;
    s->active = s->boost = s->boost_en = 0;
    s->obits &= (uint16_t)~AX_CTRL_BOOST;
}

/* ROUT in Steps/SP (table 6.2): the frequency of the moment x 32 ms,
 * rounded, 4 hz / 125 (|hz| <= 500 kHz: the quotient fits DIVU's 16 bits) */
int32_t stp_out_steps_sp(unsigned n)
{
    int32_t hz = stp_hz_now(n);
    uint32_t a = (uint32_t)(hz < 0 ? -hz : hz);
    int32_t q = (int32_t)(uint16_t)divu16(4u * a + 62u, 125u);
    return hz < 0 ? -q : q;
}

#endif
