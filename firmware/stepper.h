/*
 * stepper.h - the MAC4-STP: open-loop step generation, the <ssf> rule of the
 * profile (5.14), BOOST (4.1.4), the creep phase of positioning (5.6,
 * diagram 5.2) and the increment/step conversion (4.4.2.3).  docs/stepper.md.
 *
 * The first part is plain arithmetic, compiled for every card (the linker
 * drops it where nothing calls it) and unit-tested natively
 * (tests/unit/test_stepper.c).  The second part is the STP card's axis logic.
 */
#ifndef STEPPER_H
#define STEPPER_H
#include "inline.h"
#include <stdint.h>
#include "profile.h"
#include "mul16.h"

/* The STP's part of an E's plan (motion.h motion_plan_t), computed before
 * the masked commit: stp_motion_plan, stp_motion_start. */
typedef struct {
    int32_t ssf;                /* <ssf> on the rate register's grid, Q16 steps per SP */
    uint16_t lv_rate;           /* the creep's rate register value for <lv> */
    uint16_t turbo;             /* AX_CTRL_TURBO or 0 */
} stp_plan_t;

/* ---- arithmetic -------------------------------------------------------- */
/* DIVU.W: 32 / 16 bits, the quotient (it must fit 16 bits) in the low word,
 * the remainder in the high word. */
static inline uint32_t stp_divu16(uint32_t num, uint16_t den)
{
#if defined(HAL_TARGET)
    __asm__("divu.w %1, %0" : "+d"(num) : "dmi"(den) : "cc");
    return num;
#else
    return ((num % den) << 16) | (num / den);
#endif
}

/* One SP of a velocity ramp towards vt obeying the start/stop frequency ssf
 * (Q16 per SP, > 0): from stand-still the first speed is min(|vt|, ssf); a
 * speed above ssf falls with dec to ssf and stops from there (a reversal
 * stops first).  Between two speeds of the same sign it is prof_ramp().
 * Returns 1 when vel == vt. */
int stp_ramp(prof_t *p, int64_t vt, int64_t acc, int64_t dec, int64_t ssf);
/* One SP of a move to target (Q16) starting with min(ssf, vmax), braking
 * with dec down to ssf and landing from at most ssf: never a jump larger
 * than ssf from or to stand-still.  Returns 1 once on target; vel is then
 * the landing SP's speed (at most ssf), 0 from the next call on. */
int stp_position(prof_t *p, int64_t target, int64_t vmax, int64_t acc, int64_t dec, int64_t ssf);
/* ms / (4 es) in Q16, rounded, saturated at 0xFFFFFFFF; *exact = 1 when
 * the Q16 value is exact.  Main loop (it divides). */
uint32_t stp_ratio_q16(uint32_t ms, uint32_t es, int *exact);
/* round(c * ratio) for a counter value c and a Q16 ratio: four MULU.W.
 * Inline: the tick converts every axis' increments with it. */
FW_INLINE int32_t stp_scale(int32_t c, uint32_t ratio_q16)
{
    uint32_t a = c < 0 ? 0u - (uint32_t)c : (uint32_t)c;
    uint32_t r = ratio_q16;
    IN_REG(a);
    IN_REG(r);
    uint16_t ah = (uint16_t)(a >> 16), al = (uint16_t)a, rh = (uint16_t)(r >> 16), rl = (uint16_t)r;
    uint32_t v = (mulu16(ah, rh) << 16) + mulu16(al, rh) + mulu16(ah, rl) + ((mulu16(al, rl) + 0x8000u) >> 16);
    return c < 0 ? -(int32_t)v : (int32_t)v;
}
int32_t stp_scale_call(int32_t c, uint32_t ratio_q16);   /* the same as a call: for the paths of an event */
/* The rate register for f Hz (test mode, the creep): f / 0.7629, rounded
 * down, so <lv> never comes out above <ssf>. */
uint16_t stp_rate_hz(uint32_t hz);
/* <ssf> (Q16 steps per SP) down to the rate register's grid (at least one
 * LSB): a start to <ssf> or a stop from it then never comes out above <ssf>
 * however the remainders of the rate division fall.  Main loop. */
int64_t stp_ssf_grid(int64_t ssf, int turbo);

#define STP_TICK_CLOCKS 400u          /* generator clocks per 8 ms tick (50 kHz) */
#define STP_TICK_CLOCKS_TURBO 4000u   /* TURBO: 500 kHz */

/* ---- the STP card --------------------------------------------------------
 * Declared on every card, so that the common code can say
 * `if (MAC4_CARD == MAC4_CARD_STP) ...` in plain C; defined in the STP's
 * own files (stepper.c, stp_rate.c), which only its image links. */
#include "hal.h"
#include "card.h"
#include "measure.h"
/* Per axis; public so that the tick's output stage (stp_rate.h) is a copy.
 * 64 bytes on the 68000: &stp_ax[n] is then n << 6, not a multiply by the
 * struct's size, in every function that takes an axis number (a field
 * more needs another one out, or the padding to 128). */
typedef struct {
    /* measurement */
    uint32_t ratio;         /* Q16 steps per increment */
    int32_t inc;            /* the encoder since INIT, increments (RCPI) */
    int32_t conv;           /* inc in steps */
    int32_t tol;            /* steps one increment leaves open (<mf>, <tr>) */
    /* output, prepared so that the tick only copies */
    uint16_t rate;          /* the rate register */
    uint16_t obits;         /* DIR, BOOST, TURBO for AX_CTRL */
    uint16_t clocks;        /* generator clocks per tick: 400, TURBO 4000 */
    int8_t dir;             /* direction of the last motion, 1 or -1 (0: none yet) */
    /* BOOST (4.1.4) */
    uint8_t boost;          /* BOOST output on */
    uint32_t lim;           /* clocks << 16: the rate register's end */
    uint32_t carry;         /* Q16 steps the rates still owe */
    uint8_t boost_en;       /* BOOST on long enough: the move may go */
    uint8_t active;         /* a move is under way: BOOST stays on */
    uint32_t boost_tick;    /* card_ticks when it went on */
    /* creep phase (5.6) */
    uint8_t creep;          /* CREEP_* */
    volatile uint8_t hw_done;       /* the down-counter ended (interrupt) */
    volatile uint16_t counted;      /* creep pulses counted by interrupt */
    int8_t creep_dir;
    uint8_t creep_irq;      /* this creep's pulses are counted by interrupt */
    uint16_t creep_n;       /* pulses programmed */
    uint16_t lv_rate;       /* rate register of <lv> */
    int32_t creep_base;     /* position where the creep began */
    int64_t creep_from;     /* where the ramps end and the creep begins (Q16) */
    int32_t ssf;            /* <ssf>, Q16 steps per SP on the rate grid (at E; < 2^31) */
} stp_t;
#if defined(HAL_TARGET)
_Static_assert(sizeof(stp_t) == 64, "stp_t: 64 bytes, so that &stp_ax[n] is a shift");
#endif
extern stp_t stp_ax[MAC4_NAXES];
#define STP_OBITS (AX_CTRL_DIR | AX_CTRL_BOOST | AX_CTRL_TURBO)
/* stp_t.creep.  CREEP_TRIM: at stand-still, the step counter a step or two
 * off the setpoint (the generator's phase): those steps at <lv>, any mode. */
enum { CREEP_IDLE, CREEP_REQ, CREEP_WAIT, CREEP_RUN, CREEP_DONE, CREEP_TRIM };
#define STP_CREEP_IDLE CREEP_IDLE

/* The tick's path of an axis (axis_t.stp_path): which instantiation of the
 * one axis body (tick_stp.c stp_axis) runs it.  What decides it changes only
 * in the main loop, masked - the mode (axis_set_mode) and the tick's own
 * brake (motion.c brake_now, brake_done, motion_hold) - and each of those
 * calls stp_path_set, so the tick tests one byte instead of the mode twice
 * and the brake. */
enum {
    STP_PATH_RUN,           /* a mode with a profile, the setpoint from the SP's segment */
    STP_PATH_BRAKE,         /* the same, braked by the tick itself (x->braking) */
    STP_PATH_IDLE           /* disabled or test mode: no setpoint, stp_idle_output */
};
FW_INLINE uint8_t stp_path_of(uint8_t mode, uint8_t braking)
{
    return mode == M_DISABLE || mode == M_TEST ? STP_PATH_IDLE : braking ? STP_PATH_BRAKE : STP_PATH_RUN;
}
/* stp_path's writes: for the axis' mode and, at a mode change, for the
 * mode coming into force (stp_variant.h axis_mode_card: the mode already in
 * a register; stp_path_set on top of it costs the brake's callers an
 * instruction, as the compiler orders the volatile braking's read) */
FW_INLINE void stp_path_set(axis_t *x) { x->stp_path = stp_path_of(x->mode, x->braking); }
FW_INLINE void stp_path_set_for(axis_t *x, uint8_t mode) { x->stp_path = stp_path_of(mode, x->braking); }

/* AX_CTRL's DIR for a motion in direction dir: 0 V (bit set) = positive,
 * open collector = negative (table 2.12); USR turns it round (4.2). */
FW_INLINE uint16_t stp_dir_bit(const axis_t *x, int8_t dir)
{
    return ((dir >= 0) != ((x->ustat & UB(REV_O)) != 0)) ? AX_CTRL_DIR : 0;
}

/* measurement (measure.c) */
void stp_init(unsigned n);                    /* INIT: ratio, tolerance, counts */
extern uint8_t stp_conv;                      /* bit n: axis n counts increments */
/* tick: increments -> steps (the step count of the increments so far, less
 * that of the tick before), from the encoder's count now (stp_steps_at) or
 * its motion since the last tick (stp_measured) */
FW_INLINE int32_t stp_steps_at(stp_t *s, int32_t inc)
{
    s->inc = inc;
    int32_t m = stp_scale(inc, s->ratio);
    int32_t d = pos_sub(m, s->conv);
    s->conv = m;
    return d;
}
FW_INLINE int32_t stp_measured(unsigned n, int32_t d)
{
    stp_t *s = &stp_ax[n];
    PIN_PTR(s);
    return stp_steps_at(s, pos_add(s->inc, d));   /* modulo 2^32, as the positions */
}
/* The STP measures in steps: encoder increments through <ms>/(4 <es>); the
 * step counter itself follows DIR, which USR turns round (4.4.2.3, 4.2). */
FW_INLINE int32_t measure_steps(const axis_t *x, unsigned n, int32_t d)
{
    if (!(stp_conv & (1u << n)))                 /* the step counter, the common case first: it falls through */
        return (x->ustat & UB(REV_O)) ? -d : d;
    return stp_measured(n, d);
}
/* The position counter in its units (RCPI): increments, or steps the way
 * the counter counts them (USR turns them round). */
FW_INLINE int32_t stp_counts_at(const axis_t *x, const stp_t *s, unsigned n)
{
    if (stp_conv & (1u << n))
        return s->inc;
    return (x->ustat & UB(REV_O)) ? -x->meas : x->meas;
}
int32_t stp_counts(unsigned n);               /* the same, out of line */
/* The tick's external measurement (<et> 3/4, measure.h's measure_ext on the
 * STP, stp_meas.c): the reading in increments, converted to steps.  Inline:
 * the tick takes it per axis with its pointers and registers constants. */
FW_INLINE void stp_measure_ext(axis_t *x, meas_cfg_t *c, unsigned n)
{
    PIN_PTR(c);                                   /* its fields at d16(An), not absolute addresses */
    uint32_t raw;
    if (measure_ext_checked(x, c, n, &raw))
        return;
    if (c->abs && (stp_conv & (1u << n))) {       /* absolute, in increments: the reading is the count */
        stp_t *s = &stp_ax[n];
        PIN_PTR(s);
        measure_raw_take(x, raw);
        measure_apply(x, stp_steps_at(s, (int32_t)raw));
        return;
    }
    /* absolute: the reading against the counter in its increments */
    int32_t d = c->abs ? (int32_t)(raw - (uint32_t)stp_counts_at(x, &stp_ax[n], n)) : measure_delta(x, c, raw);
    measure_raw_take(x, raw);
    measure_apply(x, measure_steps(x, n, d));
}
int32_t stp_edge(unsigned n, int32_t d);      /* index latched d counts from here: steps */
int32_t stp_tol(unsigned n);                  /* steps the encoder ratio leaves open */
int stp_creep_dir(unsigned n);                /* a creep phase's direction while it runs, else 0 */
/* motion (motion.c) */
/* E: the parameters' part, unmasked (motion_plan: from the activated
 * parameters and TURBO, which only commands change), then the commit,
 * masked (motion_start).  stp_plan_t is motion.h's. */
void stp_motion_plan(unsigned n, int64_t ssf, stp_plan_t *pl);
void stp_motion_start(unsigned n, uint8_t mode, const stp_plan_t *pl);
void stp_status(unsigned n);                  /* once per SP: TURBO, status bits */
int stp_positioning(unsigned n, int64_t vmax, int64_t acc, int64_t dec, int64_t ssf);
void stp_profile_end(unsigned n, int64_t before, int64_t before_vel);  /* BOOST gate */
/* The step frequency now, Hz, signed: x 0.7629 (TURBO x 7.629). */
static inline int32_t stp_hz_now(unsigned n)
{
    const stp_t *s = &stp_ax[n];
    if (!s->rate)
        return 0;
    int32_t hz = (int32_t)((mulu16(s->rate, 25000u) + 0x4000u) >> 15);
    if (s->clocks == STP_TICK_CLOCKS_TURBO)
        hz *= 10;
    return s->dir < 0 ? -hz : hz;
}

/* ROUT in Steps/SP (table 6.2): the frequency of the moment x 32 ms,
 * rounded, 4 hz / 125 (|hz| <= 500 kHz: the quotient fits DIVU's 16 bits).
 * Inline: the diagnosis (stp_variant.h card_read) takes it without a
 * second call with stack arguments. */
FW_INLINE int32_t stp_out_steps_sp(unsigned n)
{
    int32_t hz = stp_hz_now(n);
    uint32_t a = (uint32_t)(hz < 0 ? -hz : hz);
    int32_t q = (int32_t)(uint16_t)divu16(4u * a + 62u, 125u);
    return hz < 0 ? -q : q;
}

#endif
