/*
 * motion.c - the modes of manual chapter 5 and the protective reactions of
 * 4.8 and 6.3, between position measurement and the output stage.
 *
 *   motion_start()        at E (main loop, interrupts masked): set a mode up
 *   motion_after_command() after a command, unmasked: the profile generator's
 *                         velocities of what it changed (vq_compute)
 *   motion_profile_tick() once per SP, in the main loop: the profile generator
 *                         prepares the NEXT SP's segment (nx_*); the tick
 *                         takes it over at the SP boundary (card.c: take_row,
 *                         STP stp_take_segment)
 *   motion_supervise()    after every tick, in the main loop: the protective
 *                         reactions (the tick itself - setpoint, filter or
 *                         step rate, output - is card.c's, four axes inlined)
 *
 * Everything runs in the measurement frame (position without <ao>), in Q16.
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "motion.h"

#define Q16(x) ((int64_t)(x) * 65536)

/* A velocity or acceleration parameter in Q16 per SP, scaled by <sf> (4.8.4). */
static int64_t vq(unsigned n, int32_t v)
{
    int32_t sf = PAR(n, SF);
#if MAC4_CARD == MAC4_CARD_STP
    /* Hz -> steps per SP of 32 ms: x 0.032 = 134218 / 2^22 (2 ppm) */
    int64_t q = (int64_t)prof_umul32((uint32_t)(v < 0 ? -v : v), 134218u) >> 6;
    if (axes[n].sstat & SB(TURBO))
        q *= 10;                                 /* 4.1.3 */
    q >>= sf;
    return v < 0 ? -q : q;
#else
    return ((int64_t)v * 65536) >> sf;
#endif
}

/* The cached vq() values (axis_t q_*): recomputed when a parameter of the
 * axis changed (par_gen), TURBO changed (STP, 4.1.3: x10), and at E (the
 * cruise limits follow the target). */
static inline __attribute__((always_inline)) uint8_t vq_turbo(const axis_t *x)
{
#if MAC4_CARD == MAC4_CARD_STP
    return (x->sstat & SB(TURBO)) != 0;
#else
    (void)x;
    return 0;
#endif
}

static void vq_compute(unsigned n);
static inline __attribute__((always_inline)) void vq_refresh_x(axis_t *x, unsigned n)
{
    if (x->q_gen != par_gen[n] || x->q_turbo != vq_turbo(x))
        vq_compute(n);
}
#define vq_refresh(n) vq_refresh_x(axis_at[n], (n))

static void vq_compute(unsigned n)
{
    axis_t *x = axis_at[n];
    x->q_pv = vq(n, PAR(n, PV));
    x->q_pa = vq(n, PAR(n, PA));
    x->q_pd = vq(n, PAR(n, PD));
    x->q_ed = vq(n, PAR(n, ED));
    x->q_free = prof_free_distance(x->q_pv, x->q_pd);
    x->q_fit = x->q_pv < (1l << 30) && x->q_pa < (1l << 30) && x->q_pd < (1l << 30);
    if (x->q_fit)
        prof_lim32(&x->q_l32, (int32_t)x->q_pv, (int32_t)x->q_pa, (int32_t)x->q_pd, x->q_free);
    x->q_fast = x->q_pv < (1l << 30) && x->q_pa < (1l << 30) && x->q_free > 0 &&
                x->q_free < ((int64_t)1 << 60);
    if (x->q_fast) {                             /* the positioning target's cruise limits */
        int64_t f = x->q_free > x->q_pv ? x->q_free : x->q_pv;
        x->q_hi = x->target - f;
        x->q_lo = x->target + f;
    }
    x->q_gen = par_gen[n];
    x->q_turbo = vq_turbo(x);
}

static int64_t meas_q(unsigned n) { return Q16(axes[n].meas); }

#if MAC4_CARD == MAC4_CARD_STP
#include "stepper.h"
/* 5.14: on the STP every ramp of every mode starts from stand-still with
 * <ssf> and stops from at most <ssf> (stepper.c); set per axis at the top
 * of motion_profile_tick. */
static int64_t stp_ssf_now;
#define prof_ramp(p, vt, acc, dec) stp_ramp(p, vt, acc, dec, stp_ssf_now)
#define STP_UNLIMITED ((int64_t)1 << 48)
#endif

/* A user position (with <ao>) as a measurement-frame target. */
static int64_t target_of(unsigned n, int32_t user)
{
    axis_t *x = axis_at[n];
    int32_t sh = PAR(n, SH);
    if (sh == 1)
        return Q16((int64_t)user - PAR(n, AO));
    /* circular axes (4.3.1.2): from the displayed position; optimised ones
     * take the shorter way round */
    int32_t cr = PAR(n, CR);
    int64_t delta = (int64_t)user - x->pos;
    if (sh == 3) {
        if (delta > cr / 2)
            delta -= cr;
        else if (delta < -(int64_t)(cr / 2))
            delta += cr;
    }
    return Q16(x->meas + delta);
}

static int at_rest(const axis_t *x) { return x->prof.vel == 0 && !x->braking; }

static void arm_index(unsigned n)
{
    axes[n].idx_seen = 0;
    hal_wr16(AX_REG(n, AX_CTRL), (uint16_t)(axes[n].ctrl | AX_CTRL_IDX_ARM));
}

void motion_hold(unsigned n)
{
    axis_t *x = axis_at[n];
    x->prof.pos = meas_q(n);
    x->prof.vel = 0;
    /* both sides of the segment hand-over start again from here */
    x->nx_ready = 0;
    x->sp_i = x->start_i = x->end_i = (int32_t)(x->prof.pos >> 16);
    x->sp_f = x->start_f = x->end_f = (uint16_t)x->prof.pos;
    x->st_i = 0;
    x->st_f = 0;
#if MAC4_CARD != MAC4_CARD_STP
    int32_t sp = x->sp_i + (x->sp_f >= 0x8000u);
    x->sp_now = x->sp_rows[0];
    x->sp_next = x->sp_rows[1];
    for (unsigned k = 0; k < PROFILE_DIVIDER; k++)
        x->sp_rows[0][k] = x->sp_rows[1][k] = sp;
    x->sp_vel = x->sp_vel_next = 0;
#endif
    x->braking = 0;
}

/* Start the tick's own braking ramp now (interrupts masked): from the last
 * tick's setpoint at the speed of the SP under way, dec_sp per SP^2 (=
 * dec_sp / 16 per tick^2).  The prepared next SP is dropped; the profile
 * generator takes over again once the tick stands (motion_profile_tick). */
static void brake_now(axis_t *x, int64_t dec_sp)
{
    int64_t dec = dec_sp >> 4;
    int32_t d = dec < 1 ? 1 : dec > INT32_MAX ? INT32_MAX : (int32_t)dec;
    if (x->braking) {
        /* a stop during a brake (a limit switch or a following error while
         * a stop bit brakes with <pd>): the stronger ramp from here */
        if (d > x->br_dec)
            x->br_dec = d;
        return;
    }
    x->br_dec = d;
#if MAC4_CARD != MAC4_CARD_STP
    int64_t pos = (int64_t)x->setpoint * 65536;
    int32_t v = x->sp_vel / 4;
#else
    /* the Q16 setpoint and the segment's step per tick; a stepper stops at
     * once from <ssf> or less (5.14): br_ssf per tick */
    int64_t pos = (int64_t)x->sp_i * 65536 + x->sp_f;
    int32_t v = (int32_t)((uint32_t)x->st_i << 16) + (int32_t)x->st_f;
    x->br_ssf = (int32_t)(stp_ax[x - axes].ssf >> 2);
#endif
    brake_set_pos(x, pos);
    x->br_v = v;
    x->nx_ready = 0;
    x->braking = 1;
}

/* The tick stands after brake_now(): the profile continues from there, at
 * rest, with the rows (STP: the segment) holding the setpoint. */
static void brake_done(axis_t *x)
{
    x->prof.pos = brake_pos(x);
    x->prof.vel = 0;
#if MAC4_CARD != MAC4_CARD_STP
    int32_t sp = brake_setpoint(x);
    for (unsigned k = 0; k < PROFILE_DIVIDER; k++)
        x->sp_rows[0][k] = x->sp_rows[1][k] = sp;
    x->sp_vel = x->sp_vel_next = 0;
#else
    brake_split(x, &x->sp_i, &x->sp_f);
    x->start_i = x->end_i = x->sp_i;
    x->start_f = x->end_f = x->sp_f;
    x->st_i = 0;
    x->st_f = 0;
#endif
    x->nx_ready = 0;
    x->braking = 0;
}

void motion_brake(unsigned n)
{
    vq_refresh(n);
    brake_now(axis_at[n], axis_at[n]->q_pd);
}


uint8_t motion_vq_due;      /* axes whose velocities motion_after_command computes */

void motion_plan_target(unsigned n, uint8_t mode, motion_plan_t *p)
{
    p->target = mode == M_POSITIONING ? target_of(n, PAR_W(n, AP)) : 0;
}

void motion_plan(unsigned n, motion_plan_t *p)
{
#if MAC4_CARD != MAC4_CARD_STP                  /* the STP has no servo filter */
    servo_set_gains(&p->gains, PAR(n, GA), PAR(n, ZE), PAR(n, PO), PAR(n, KI), PAR(n, KISC));
    servo_set_limit(&p->gains, PAR(n, SW));      /* <sw>, torque (force) limitation */
#endif
    /* <trt> in whole sampling periods, rounded up (5.6) */
    uint32_t sp_ms = MAC4_CARD == MAC4_CARD_STP ? 32u : 10u;
    p->trt_periods = (uint16_t)divu16((uint32_t)PAR(n, TRT) + sp_ms - 1u, (uint16_t)sp_ms);   /* <trt> < 2^16 */
#if MAC4_CARD == MAC4_CARD_STP
    stp_motion_plan(n, vq(n, PAR(n, SSF)), &p->stp);   /* <ssf>, <lv>, TURBO (stepper.c) */
#endif
}

void motion_start(unsigned n, uint8_t mode, uint8_t from, const motion_plan_t *p)
{
    axis_t *x = axis_at[n];
    if (from == M_DISABLE || from == M_TEST) {
        motion_hold(n);                          /* no jump when the drive comes on */
        servo_reset(&x->servo);
    }
#if MAC4_CARD != MAC4_CARD_STP
    axis_set_gains(n, &p->gains);
#endif
    x->done = 0;
    x->phase = 0;
    if (!(mode == M_RESET && x->stop_then >= STOP_DISABLE)) {
        /* (an MRE during a stop that disables: that stop goes on, guards and all) */
        x->stop_then = STOP_NONE;
        x->stop_settle = 0;
    }
    x->trt_count = 0;
    x->trt_periods = p->trt_periods;
    switch (mode) {
    case M_POSITIONING:
        x->target = p->target;
        break;
    case M_SEARCH_IDX_C:
    case M_SEARCH_IDX:
        arm_index(n);
        break;
    default:
        break;
    }
#if MAC4_CARD == MAC4_CARD_STP
    stp_motion_start(n, mode, &p->stp);             /* creep phase, <lv>, TURBO (stepper.c) */
#endif
    /* the velocities and the cruise limits of the new mode and target: in
     * the command, not in the profile generator's next step, but after the
     * mask (motion_after_command); until then they read as stale */
    x->q_gen = (uint16_t)~par_gen[n];
    motion_vq_due |= (uint8_t)(1u << n);
    if (mode == M_RESET)
        motion_emergency(n, STOP_DISABLE);       /* 4.8.2: the <ed> ramp from the next tick on */
}

void motion_after_command_do(void)
{
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (motion_vq_due & (1u << n))
            vq_refresh(n);
    motion_vq_due = 0;
}

void motion_emergency(unsigned n, uint8_t then)
{
    axis_t *x = axis_at[n];
    if (x->mode == M_DISABLE)
        return;
    if (x->mode == M_TEST) {                     /* 4.8.2: no ramp in test mode */
        axis_disable(n);
        return;
    }
    if (x->stop_then == STOP_NONE) {
        /* the runaway guard from the following error of the moment (stop_watch) */
        int32_t e = x->ferr < 0 ? -x->ferr : x->ferr, m = x->mf / 2;
        x->stop_fmax = e > INT32_MAX - m ? INT32_MAX : e + m;
        x->stop_f0 = x->stop_flast = e;
        x->stop_vlast = 0;
        x->stop_grow = 0;
        x->stop_ferr = 0;
        x->stop_ticks = 0;
        x->stop_rest = 0;
        x->stop_limit = 0;
    }
    if (x->stop_then < then)                     /* deinit > disable > hold */
        x->stop_then = then;
    /* INC/SSI: a stop that disables waits for the mechanics at rest; the
     * STP is open loop: stopped is the step rate ramped to <ssf> and off */
    x->stop_settle = MAC4_CARD != MAC4_CARD_STP && x->stop_then != STOP_HOLD;
    vq_refresh(n);
    brake_now(x, x->q_ed);                       /* from the next tick on, not the next SP */
}

/* 6.3.4: the drive's power stage is off, the loop cannot brake the motor:
 * the setpoint ramps with <ed> and the axis is disabled as soon as it stands. */
void motion_drive_fault(unsigned n)
{
    motion_emergency(n, STOP_DISABLE);
    axis_at[n]->stop_settle = 0;
}

/* ---- justification helpers --------------------------------------------- */
static int sw_active(unsigned n, uint32_t ubit) { return (axes[n].ustat & ubit) != 0; }

static void justified(unsigned n, int set_zero)
{
    axis_t *x = axis_at[n];
#if MAC4_CARD != MAC4_CARD_STP
    x->prof.pos = Q16(x->edge);
#endif
    /* (STP: the steps stop where they are, from <lv> <= <ssf>; no jump back
     * to the edge, which would be a reversal above <ssf>) */
    x->prof.vel = 0;
    x->done = 1;
    if (set_zero) {
        /* the index pulse is the axis' reference: position 0 there (4.9) */
        params_force(n, P_AO, -x->edge, PS_WRITTEN);
        axis_set_pos(n);
    }
    x->ustat |= UB(JUS_END);
    vme_irq((uint8_t)PAR(n, IRQ4));
}

static int64_t sgn(int32_t v, int64_t mag) { return v < 0 ? -mag : mag; }

/* 4.3.1.1, 6.3.3: a linear axis in speed or velocity tracking never leaves
 * its software limits: where the step just taken (from `was`) would no longer
 * let it stop with dec before the limit ahead, the SP is instead the step of
 * a positioning move onto the limit, which brakes with dec and lands on it;
 * the axis holds there until the velocity turns away from it. */
static void limit_guard(axis_t *x, unsigned n, const prof_t *was, int64_t dec)
{
    prof_t *p = &x->prof;
    int64_t v = p->vel;
    if (!x->linear || v == 0)
        return;
    int64_t lim = Q16((int64_t)(v > 0 ? x->lp : x->ln) - PAR(n, AO));
    int64_t rem = v > 0 ? lim - p->pos : p->pos - lim;
    int64_t av = v > 0 ? v : -v;
    if (rem > 0 && !prof_must_brake(av, dec, rem))
        return;                                  /* the common case: far from the limit */
    prof_t q = *was;
    int64_t vw = was->vel < 0 ? -was->vel : was->vel;
    prof_position(&q, lim, av > vw ? av : vw, av > vw ? av - vw : 1, dec);
    if (v > 0 ? q.pos < p->pos : q.pos > p->pos)
        *p = q;
}

/* ---- the profile generator, once per SP -------------------------------- */
/* The SP from `before` to prof.pos as the tick takes it: start, step per
 * tick and end split into 32-bit parts (STP), the four setpoints (INC/SSI). */
/* The four setpoints of an SP that moves d (Q16, |d| < 2^30) from before:
 * row k = round(before + (k+1) floor(d / 4)), the last round(before + d) -
 * what the split arithmetic of next_segment gives. */
static inline __attribute__((always_inline)) void rows_of(axis_t *x, int64_t before, int32_t d)
{
    x->sp_vel_next = d;
    int32_t *r = x->sp_next;
    /* >> of a negative value: GCC shifts arithmetically (floor), as the
     * firmware relies on throughout, e.g. the 24-bit sign extension */
    // cppcheck-suppress shiftNegativeLHS ; see above
    int32_t st = d >> 2, bi = (int32_t)(before >> 16);
    int32_t q0 = (int32_t)(uint16_t)before + 0x8000, q = q0;
    q += st;
    r[0] = pos_add(bi, q >> 16);                 /* positions modulo 2^32 (card.h) */
    q += st;
    r[1] = pos_add(bi, q >> 16);
    q += st;
    r[2] = pos_add(bi, q >> 16);
    r[3] = pos_add(bi, (q0 + d) >> 16);
    x->nx_ready = 1;
}

static void next_segment_wide(axis_t *x, int64_t before);

static inline __attribute__((always_inline)) void next_segment(axis_t *x, int64_t before)
{
#if MAC4_CARD != MAC4_CARD_STP
    int64_t dd = x->prof.pos - before;
    if (dd < (1l << 30) && dd > -(1l << 30)) {
        rows_of(x, before, (int32_t)dd);         /* the usual SP, in 32 bits */
        return;
    }
#endif
    next_segment_wide(x, before);
}

/* The rest: the STP's split segment, and an INC/SSI SP of 2^30 or more. */
static void next_segment_wide(axis_t *x, int64_t before)
{
    PIN_PTR(x);
    const prof_t *p = &x->prof;
    int64_t d64 = p->pos - before;
#if MAC4_CARD != MAC4_CARD_STP
    x->sp_vel_next = d64 > INT32_MAX ? INT32_MAX : d64 < -INT32_MAX ? -INT32_MAX : (int32_t)d64;
#endif
    split_q16(before, &x->nx_start_i, &x->nx_start_f);
    split_q16(p->pos, &x->nx_end_i, &x->nx_end_f);
    if (d64 >= INT32_MIN && d64 <= INT32_MAX) {  /* no 64-bit shift */
        int32_t d32 = (int32_t)d64;
        // cppcheck-suppress shiftNegativeLHS ; arithmetic (floor) on GCC, as in rows_of
        int32_t st = d32 >> 2;
        x->nx_st_i = st >> 16;
        x->nx_st_f = (uint16_t)st;
    } else {
        // cppcheck-suppress shiftNegativeLHS ; arithmetic (floor) on GCC, as in rows_of
        split_q16(d64 >> 2, &x->nx_st_i, &x->nx_st_f);
    }
#if MAC4_CARD != MAC4_CARD_STP
    /* the four ticks' setpoints: start + k step, the last exactly the end */
    int32_t *row = x->sp_next;
    int32_t i = x->nx_start_i;
    uint16_t f = x->nx_start_f;
    for (unsigned k = 0; k < PROFILE_DIVIDER - 1u; k++) {
        uint32_t f32 = (uint32_t)f + x->nx_st_f;
        i = pos_add(pos_add(i, x->nx_st_i), (int32_t)(f32 >> 16));
        f = (uint16_t)f32;
        row[k] = pos_add(i, f >= 0x8000u);
    }
    row[PROFILE_DIVIDER - 1u] = pos_add(x->nx_end_i, x->nx_end_f >= 0x8000u);
#endif
    x->nx_ready = 1;
}

static void profile_modes(unsigned n) __attribute__((noinline));

/* 5.6: pos_end once the axis has been in the target radius <tr> for <trt>
 * sampling periods after the setpoint arrived. */
static void pos_end_check(unsigned n)
{
    axis_t *x = axis_at[n];
    int64_t d = (x->target >> 16) - x->meas;
    if (d < 0)
        d = -d;
#if MAC4_CARD == MAC4_CARD_STP
    d -= stp_tol(n);                             /* 5.6: the tolerance of <ms>/(4 <es>) */
#endif
    if (d <= PAR(n, TR)) {
        if (x->trt_count >= x->trt_periods) {
            x->ustat |= UB(POS_END);
#if MAC4_CARD == MAC4_CARD_STP
            x->sstat |= SB(IN_POS);              /* 7.1.2: MAC4-STP only (LED P) */
#endif
            vme_irq((uint8_t)PAR(n, IRQ4));
        } else {
            x->trt_count++;
        }
    } else {
        x->trt_count = 0;
    }
}

/* A protective stop has ramped down (and, if it waits for it, the mechanics
 * stand): what follows it (4.8). */
static void stop_done(unsigned n)
{
    axis_t *x = axis_at[n];
    if (x->stop_then == STOP_HOLD) {
        axis_set_mode(n, M_BRAKE);
    } else {
        uint8_t then = x->stop_then;
        axis_disable(n);
        if (then == STOP_DEINIT)
            x->ustat &= ~UB(INIT);
    }
    x->stop_then = STOP_NONE;
    x->stop_settle = 0;
    x->done = 1;
}

/* After every tick of a stop that waits for the mechanics (stop_settle):
 * the loop brakes them to rest and holds the braked setpoint; the axis is
 * disabled once the measured speed has stayed near 0 for STOP_REST_TICKS.
 * The guards against a loop that cannot stop them (6.3.9: a reversed or
 * frozen encoder, a motor that cannot follow <ed>): /EN opens at once, with
 * ferr_f and 163, when the following error grows beyond its value at the
 * start of the stop plus <mf>/2, or beyond that value in STOP_GROW_TICKS
 * ticks in a row without the mechanics slowing down, when the axis measures no motion with more than <mf>
 * still to go, or when twice the ticks of the setpoint's ramp plus
 * STOP_SETTLE_TICKS have passed.  1: the stop has ended. */
static int stop_watch(axis_t *x, unsigned n)
{
    if (x->stop_ticks < UINT16_MAX)
        x->stop_ticks++;
    int32_t e = x->ferr < 0 ? -x->ferr : x->ferr, av = x->vel < 0 ? -x->vel : x->vel;
    /* growing instead of shrinking: beyond its start, tick after tick, and
     * the mechanics not slowing down (an overshoot slows down; a loop with
     * its sign reversed speeds up or runs at its limit) */
    if (e > x->stop_f0 && e > x->stop_flast + STOP_REST_VEL && av + STOP_REST_VEL >= x->stop_vlast)
        x->stop_grow++;
    else
        x->stop_grow = 0;
    x->stop_flast = e;
    x->stop_vlast = av;
    int over = e > x->stop_fmax || x->stop_grow >= STOP_GROW_TICKS;
    if (!over && x->braking)
        return 0;                                /* the setpoint's ramp runs */
    if (!over) {
        int32_t v = x->vel;
        if (v <= STOP_REST_VEL && v >= -STOP_REST_VEL) {
            /* standing with more than <mf> to go: the feedback does not follow
             * the output (frozen or stuck encoder, a jammed motor) */
            over = e > x->mf;
            if (!over && ++x->stop_rest >= STOP_REST_TICKS) {
                stop_done(n);                    /* at rest: now disable */
                return 1;
            }
        } else {
            x->stop_rest = 0;
        }
        if (!over && x->stop_ticks <= x->stop_limit)
            return 0;
    }
    /* runaway or too slow: open /EN now, a following error - but not a
     * second one when the stop is the following error's own reaction: that
     * was raised once, and a C during the braking has acknowledged it */
    if (!x->stop_ferr)
        axis_error(n, UB(FERR_F), ERR_LOGICAL);
    stop_done(n);
    return 1;
}

#if MAC4_CARD != MAC4_CARD_STP
/* A positioning SP with limits below 2^30 (braking, landing) where the cruise
 * step does not apply; apart from motion_profile_tick, which keeps its
 * registers for the cruise step. */
static void __attribute__((noinline)) position_fit_step(axis_t *x, unsigned n)
{
    PIN_PTR(x);
    int64_t before = x->prof.pos, rem = x->target - before;
    int landed;
    int32_t d;
    if (prof_fits32(&x->prof, rem)) {
        landed = prof_step32(&x->prof, rem, &x->q_l32, &d);
        rows_of(x, before, d);
    } else {
        landed = prof_position_ref(&x->prof, x->target, x->q_pv, x->q_pa, x->q_pd, x->q_free);
        next_segment(x, before);
    }
    if (landed) {
        x->done = 1;
        pos_end_check(n);
    }
}
#endif

/* The common case first, in a small function: a positioning move far from
 * its target (prof_cruise); everything else in profile_modes(). */
void motion_profile_tick(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    if (x->nx_ready)
        return;                                  /* the tick has not taken the last one */
    if (x->braking) {
        if (x->br_v != 0)
            return;                              /* the tick brakes (brake_now) */
        brake_done(x);
    }
#if MAC4_CARD != MAC4_CARD_STP
    if (x->mode == M_POSITIONING && !x->stop_then && x->done) {
        /* on target: the setpoint stands (the step would be 0) until pos_end */
        if (!(x->ustat & UB(POS_END)))
            pos_end_check(n);
        rows_of(x, x->prof.pos, 0);
        return;
    }
    if (x->mode == M_POSITIONING && !x->stop_then && !x->done) {
        vq_refresh_x(x, n);
        int64_t before = x->prof.pos;
        int32_t d;
        if (x->q_fast &&
            (d = prof_cruise32(&x->prof, x->q_hi, x->q_lo, (int32_t)x->q_pv, (int32_t)x->q_pa)) != 0) {
            rows_of(x, before, d);
            return;
        }
        if (x->q_fit) {                          /* braking, landing: what profile_modes does */
            position_fit_step(x, n);
            return;
        }
    }
#endif
    profile_modes(n);
}

static void profile_modes(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    prof_t *p = &x->prof;
    if (x->nx_ready)
        return;                                  /* the tick has not taken the last one */
    int64_t before = p->pos;
#if MAC4_CARD == MAC4_CARD_STP
    int64_t before_vel = p->vel;
    if (x->mode == M_DISABLE || x->mode == M_TEST)
        stp_status(n);                           /* system status bits (else stp_profile_end) */
    stp_ssf_now = stp_ax[n].ssf;                 /* <ssf> on the rate grid, from E */
#endif

    if (x->mode == M_DISABLE || x->mode == M_TEST) {
        motion_hold(n);
        return;
    }
    vq_refresh(n);
    if (x->stop_then) {                          /* protective stop: ramp <ed> */
        int64_t ed = x->q_ed;
        if (prof_ramp(p, 0, ed, ed) && !x->stop_settle)
            stop_done(n);                        /* (else when the mechanics stand: stop_watch) */
    } else {
        switch (x->mode) {
        case M_ENABLE:                           /* hold; UE from a move: stop with <pd> */
        case M_BRAKE:
            x->done = (uint8_t)prof_ramp(p, 0, x->q_pd, x->q_pd);
            break;
        case M_RESET:                            /* 4.8.2: emergency ramp, at rest, then disable */
            motion_emergency(n, STOP_DISABLE);   /* the tick brakes (brake_now) */
            return;
        case M_SPEED: {                          /* <vt> with the ramps <pa>/<pd> */
            prof_t was = *p;
            prof_ramp(p, vq(n, PAR(n, VT)), x->q_pa, x->q_pd);
            limit_guard(x, n, &was, x->q_pd);    /* before a software limit: <pd> */
            break;
        }
        case M_VEL_TRACK: {                      /* 5.11: acceleration not limited */
            prof_t was = *p;
#if MAC4_CARD == MAC4_CARD_STP
            /* ... but from and to stand-still through <ssf> (5.14) */
            prof_ramp(p, vq(n, PAR(n, VT)), STP_UNLIMITED, STP_UNLIMITED);
#else
            p->vel = vq(n, PAR(n, VT));
            p->pos += p->vel;
#endif
            limit_guard(x, n, &was, x->q_ed);    /* before a software limit: <ed> */
            break;
        }
        case M_POS_TRACK: {                      /* 5.12: <at> within the next SP */
            int64_t t = target_of(n, PAR(n, AT));
            p->vel = t - p->pos;
            p->pos = t;
            break;
        }
        case M_POSITIONING:
#if MAC4_CARD == MAC4_CARD_STP
            /* ramps to <stc> steps before the target, then the creep phase (diagram 5.2) */
            if (!x->done && stp_positioning(n, x->q_pv, x->q_pa, x->q_pd, stp_ssf_now))
                x->done = 1;
#else
            if (!x->done &&
                (x->q_fit ? prof_position_fit(p, x->target, &x->q_l32)
                          : prof_position_free(p, x->target, x->q_pv, x->q_pa, x->q_pd, x->q_free))) {
                x->done = 1;
            }
#endif
            if (x->done && !(x->ustat & UB(POS_END)))
                pos_end_check(n);
            break;
        case M_SEARCH_IDX_C:                     /* 5.7 */
            if (x->phase == 0) {
                prof_ramp(p, vq(n, PAR(n, CV)), vq(n, PAR(n, CA)), vq(n, PAR(n, CA)));
                if (x->idx_seen)
                    x->phase = 1;
            } else if (!x->done && prof_ramp(p, 0, vq(n, PAR(n, CD)), vq(n, PAR(n, CD)))) {
                x->done = 1;
                x->ustat |= UB(JUS_END);
                vme_irq((uint8_t)PAR(n, IRQ4));
            }
            break;
        case M_SEARCH_IDX:                       /* 5.8: at <lv> to the index */
            if (!x->done) {
                if (x->idx_seen)
                    justified(n, 1);
                else
                    p->pos += (p->vel = sgn(PAR(n, CV), vq(n, PAR(n, LV))));
            }
            break;
        case M_HOME: {                           /* 5.9 */
            int32_t hv = PAR(n, HV);
            switch (x->phase) {
            case 0:                              /* 1: find the reference switch */
                if (sw_active(n, UB(REF))) {
                    x->phase = 1;
#if MAC4_CARD == MAC4_CARD_STP
                    /* the braking ramp begins in this SP: a stepper must not pause at speed */
                    if (prof_ramp(p, 0, vq(n, PAR(n, HD)), vq(n, PAR(n, HD))))
                        x->phase = 2;
#endif
                } else
                    prof_ramp(p, vq(n, hv), vq(n, PAR(n, HA)), vq(n, PAR(n, HA)));
                break;
            case 1:                              /* brake with <hd> */
                if (prof_ramp(p, 0, vq(n, PAR(n, HD)), vq(n, PAR(n, HD))))
                    x->phase = sw_active(n, UB(REF)) ? 2 : 0;
                break;
            case 2:                              /* 2: left edge of the switch at <lv> */
                if (!sw_active(n, UB(REF))) {
                    p->vel = 0;
#if MAC4_CARD != MAC4_CARD_STP
                    p->pos = meas_q(n);          /* (STP: the steps stop where they are) */
#endif
                    arm_index(n);
                    x->phase = 3;
                } else {
                    p->pos += (p->vel = -vq(n, PAR(n, LV)));
                }
                break;
            case 3:                              /* 3: next index pulse, positive */
                if (x->done)
                    break;                       /* once: jus_end and interrupt 4 (5.9) */
                if (x->idx_seen)
                    justified(n, 1);
                else
                    p->pos += (p->vel = vq(n, PAR(n, LV)));
                break;
            }
            break;
        }
        case M_FIND_EDGE: {                      /* 5.10 */
            int32_t dl = PAR(n, DL);
            uint32_t bit = dl == 0 ? UB(REF) : dl == 1 ? UB(HWL_N) : UB(HWL_P);
            int32_t dir = dl == 0 ? PAR(n, FV) : dl == 1 ? -1 : 1;
            int64_t fv = vq(n, PAR(n, FV) < 0 ? -PAR(n, FV) : PAR(n, FV));
            switch (x->phase) {
            case 0:
                if (sw_active(n, bit)) {
                    x->phase = 1;
#if MAC4_CARD == MAC4_CARD_STP
                    /* the braking ramp begins in this SP: a stepper must not pause at speed */
                    if (prof_ramp(p, 0, vq(n, PAR(n, FD)), vq(n, PAR(n, FD))))
                        x->phase = 2;
#endif
                } else
                    prof_ramp(p, sgn(dir, fv), vq(n, PAR(n, FA)), vq(n, PAR(n, FA)));
                break;
            case 1:
                if (prof_ramp(p, 0, vq(n, PAR(n, FD)), vq(n, PAR(n, FD))))
                    x->phase = 2;
                break;
            case 2:                              /* back at <lv> to the transition */
                if (!sw_active(n, bit)) {
                    x->edge = x->meas;
                    justified(n, 0);
                    x->phase = 3;
                } else {
                    p->pos += (p->vel = sgn(-dir, vq(n, PAR(n, LV))));
                }
                break;
            default:
                break;
            }
            break;
        }
        default:
            break;
        }
    }
#if MAC4_CARD == MAC4_CARD_STP
    stp_profile_end(n, before, before_vel);     /* BOOST <bt> ahead of a move (4.1.4) */
#endif
    /* the next SP's segment, for the tick to take at the boundary */
    if (x->mode != M_DISABLE && x->mode != M_TEST)
        next_segment(x, before);
}


/* ---- after every tick, in the main loop --------------------------------
 * What the tick measured, checked before the main loop does anything else
 * (card_supervise): the index latch of the searches and the protective
 * reactions.  They act through the profile generator's ramps, whose next SP
 * is still ahead, and through axis_disable(), which opens /EN at once: the
 * reaction is within the servo period of the event, as in the tick. */
void motion_supervise(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    if (x->mode == M_DISABLE || x->mode == M_TEST)
        return;
    if (x->braking && x->br_v == 0) {            /* the tick's ramp has ended: act now */
        brake_done(x);
        if (x->stop_settle) {                    /* the time bound from the ramp's ticks */
            uint32_t lim = 2u * x->stop_ticks + STOP_SETTLE_TICKS;
            x->stop_limit = (uint16_t)(lim > UINT16_MAX ? UINT16_MAX : lim);
        } else if (x->stop_then) {
            stop_done(n);
        }
        if (x->mode == M_DISABLE)
            return;
    }
    if (x->stop_settle && stop_watch(x, n))
        return;                                  /* disabled */
    /* the index latch, for the searches (the rare bit first) */
    if ((x->in & AX_IN_IDX) && !x->idx_seen &&
        (x->mode == M_SEARCH_IDX_C || x->mode == M_SEARCH_IDX || (x->mode == M_HOME && x->phase == 3))) {
        uint32_t hi = hal_rd16(AX_REG(n, AX_IDX_HI));
        uint32_t raw = (hi << 16) | hal_rd16(AX_REG(n, AX_IDX_LO));
        int32_t d = (int32_t)((raw - x->counter) << 8) >> 8;   /* 24-bit counter */
        x->edge = x->meas + d;
#if MAC4_CARD == MAC4_CARD_STP
        x->edge = stp_edge(n, d);                /* increments -> steps */
#endif
        x->idx_seen = 1;
    }

    /* protective reactions (4.8, 6.3) */
    if (!x->stop_then) {
        int32_t mf = x->mf;
        if (x->ferr > mf || x->ferr < -mf) {     /* 4.8.1, 6.3.9 */
            axis_error(n, UB(FERR_F), ERR_LOGICAL);
            motion_emergency(n, STOP_DISABLE);
            x->stop_ferr = 1;                    /* raised once: its guard raises nothing more */
        } else if (x->linear && (x->pos > x->lp || x->pos < x->ln)) {
            x->ustat |= x->pos > x->lp ? UB(SWL_P) : UB(SWL_N);
            axis_error(n, UB(LOGO_F), ERR_LOGICAL);   /* 4.3.1.1: braked and disabled; C first (6.3) */
            motion_emergency(n, STOP_DISABLE);
        } else if (x->ustat & (UB(HWL_P) | UB(HWL_N))) {
            /* hardware limits stop motion into the switch, not out of it, in
             * every mode (test mode: card.c); find edge may run into the one
             * limit switch it looks for (<dl> 1, 2), to its edge */
            int64_t v = x->prof.vel;
            int dir = v > 0 ? 1 : v < 0 ? -1 : 0;
#if MAC4_CARD == MAC4_CARD_STP
            if (!dir)
                dir = stp_creep_dir(n);          /* the creep phase's pulses (5.6): the profile stands */
#endif
            uint32_t into = x->ustat & (dir > 0 ? UB(HWL_P) : dir < 0 ? UB(HWL_N) : 0);
            if (x->mode == M_FIND_EDGE) {
                int32_t dl = PAR(n, DL);
                into &= ~(dl == 1 ? UB(HWL_N) : dl == 2 ? UB(HWL_P) : 0);
            }
            if (into) {
                axis_error(n, UB(LOGO_F), ERR_LOGICAL);   /* C first (6.3), then out of the switch */
                motion_emergency(n, STOP_HOLD);
            }
        }
    }
    if ((x->ustat & (UB(SWL_P) | UB(SWL_N))) && x->pos >= x->ln && x->pos <= x->lp)
        x->ustat &= ~(UB(SWL_P) | UB(SWL_N));
}

int motion_busy(unsigned n)
{
    const axis_t *x = axis_at[n];
    switch (x->mode) {
    case M_POSITIONING:
        return !(x->ustat & UB(POS_END));
    case M_SEARCH_IDX_C:
    case M_SEARCH_IDX:
    case M_HOME:
    case M_FIND_EDGE:
        return !x->done;
    default:
        return 0;
    }
}

int motion_at_rest(unsigned n) { return at_rest(&axes[n]); }
