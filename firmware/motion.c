/*
 * motion.c - the modes of manual chapter 5 and the protective reactions of
 * 4.8 and 6.3, between position measurement and the output stage; this
 * file sets a mode up and owns the protective stops (begun, watched after
 * every tick, ended), the stages are beside it (motion_priv.h lists them).
 *
 *   motion_start()        at E (main loop, interrupts masked): set a mode up
 *   motion_after_command() after a command, unmasked: the profile generator's
 *                         velocities of what it changed (vq_compute)
 *   motion_profile_tick() once per SP, in the main loop: the profile generator
 *                         prepares the NEXT SP's segment (nx_*); the tick
 *                         takes it over at the SP boundary (tick_servo.c: take_row,
 *                         STP stp_take_segment)
 *   motion_supervise()    after every tick, in the main loop: the protective
 *                         reactions (the tick itself - setpoint, filter or
 *                         step rate, output - is tick_servo.c's or tick_stp.c's, four axes inlined)
 *
 * Everything runs in the measurement frame (position without <ao>), in Q16.
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "axis.h"
#include "params.h"
#include "motion.h"
#include "motion_priv.h"
#include "measure.h"
#include "ext.h"
#include "tick.h"
#include "tick_servo.h"
#include "handover.h"

/* vq(): the card variant's (servo_motion.c, stp_motion.c). */

/* A deceleration per SP^2 as the tick's brake takes it: per tick^2 (/16),
 * at least 1. */
static int32_t dec_per_tick(int64_t dec_sp)
{
    int64_t dec = dec_sp >> 4;
    return dec < 1 ? 1 : dec > INT32_MAX ? INT32_MAX : (int32_t)dec;
}

void vq_compute(unsigned n)
{
    axis_t *x = axis_at[n];
    x->q_pv = vq(n, PAR(n, PV));
    x->q_pa = vq(n, PAR(n, PA));
    x->q_pd = vq(n, PAR(n, PD));
    x->q_ed = vq(n, PAR(n, ED));
    x->q_pd_t = dec_per_tick(x->q_pd);
    x->q_ed_t = dec_per_tick(x->q_ed);
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

/* A user position (with <ao>) as a measurement-frame target. */
int64_t target_of(unsigned n, int32_t user)
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

void arm_index(unsigned n)
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
    handover_hold(x, x->prof.pos);
    motion_hold_card(x);                         /* the servo tick's setpoint rows */
    x->braking = 0;
    motion_path_set(x);                          /* the tick's body for the axis */
}

/* Start the tick's own braking ramp now (interrupts masked): from the last
 * tick's setpoint at the speed of the SP under way, d per tick^2
 * (dec_per_tick).  The prepared next SP is dropped; the profile generator
 * takes over again once the tick stands (motion_profile_tick). */
static void brake_now(axis_t *x, int32_t d)
{
    if (x->braking) {
        /* a stop during a brake (a limit switch or a following error while
         * a stop bit brakes with <pd>): the stronger ramp from here */
        if (d > x->br_dec)
            x->br_dec = d;
        return;
    }
    x->br_dec = d;
    int64_t pos;
    int32_t v;
    brake_from_card(x, &pos, &v);                /* the setpoint and its speed per tick */
    brake_start(x, pos, v);                      /* tick.h: the ramp is the tick's */
    handover_drop(x);
    x->braking = 1;
    motion_path_set(x);
}

/* The tick stands after brake_now(): the profile continues from there, at
 * rest, with the rows (STP: the segment) holding the setpoint.  A stop that
 * waits for the mechanics at rest gets its time bound here, from the ramp's
 * ticks (stop_watch): whichever of the supervision and the profile generator
 * sees the ramp's end first. */
void brake_done(axis_t *x)
{
    if (x->stop_settle) {
        uint32_t lim = 2u * x->stop_ticks + STOP_SETTLE_TICKS;
        x->stop_limit = (uint16_t)(lim > UINT16_MAX ? UINT16_MAX : lim);
    }
    x->prof.pos = brake_pos(x);
    x->prof.vel = 0;
    brake_done_card(x);                          /* the rows (STP: the segment) hold it */
    handover_drop(x);
    x->braking = 0;
    motion_path_set(x);                          /* the tick's body for the axis */
}

void motion_brake(unsigned n)
{
    vq_refresh(n);
    brake_now(axis_at[n], axis_at[n]->q_pd_t);
}


uint8_t motion_vq_due;      /* axes whose velocities motion_after_command computes */

void motion_plan_target(unsigned n, uint8_t mode, motion_plan_t *p)
{
    p->target = mode == M_POSITIONING ? target_of(n, PAR_W(n, AP)) : 0;
}

void motion_plan(unsigned n, motion_plan_t *p)
{
    motion_plan_card(n, p);                      /* servo gains, or <ssf>, <lv>, TURBO */
    /* <trt> in whole sampling periods, rounded up (5.6) */
    p->trt_periods = (uint16_t)divu16((uint32_t)PAR(n, TRT) + CARD_SP_MS - 1u, (uint16_t)CARD_SP_MS);   /* <trt> < 2^16 */
    /* MRE's ramp (4.8.2) from the <ed> this E activates: the velocities of
     * the new parameters are worked out after the command (vq_compute), not
     * in its masked commit */
    p->ed_t = dec_per_tick(vq(n, PAR(n, ED)));
}

/* A protective stop of a running axis: its guards, what follows it, and
 * the tick's ramp with ed_t per tick^2 from the next tick on. */
FW_INLINE void emergency_at(axis_t *x, uint8_t then, int32_t ed_t)
{
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
    if (x->stop_then > then)                     /* deinit > disable > hold */
        then = x->stop_then;
    /* INC/SSI: a stop that disables waits for the mechanics at rest; the
     * STP is open loop: stopped is the step rate ramped to <ssf> and off */
    axis_stop_set(x, then, CARD_STOP_SETTLES && then != STOP_HOLD);
    brake_now(x, ed_t);                          /* from the next tick on, not the next SP */
}

void motion_start(unsigned n, uint8_t mode, uint8_t from, const motion_plan_t *p)
{
    axis_t *x = axis_at[n];
    if (from == M_DISABLE || from == M_TEST) {
        motion_hold(n);                          /* no jump when the drive comes on */
        tick_servo_reset(x);
    }
    x->done = 0;
    axis_phase_set(x, 0);
    if (!(mode == M_RESET && x->stop_then >= STOP_DISABLE)) {
        /* (an MRE during a stop that disables: that stop goes on, guards and all) */
        axis_stop_set(x, STOP_NONE, 0);
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
    motion_start_card(n, mode, p);               /* the gains, or creep phase, <lv>, TURBO */
    /* the velocities and the cruise limits of the new mode and target: in
     * the command, not in the profile generator's next step, but after the
     * mask (motion_after_command); until then they read as stale */
    x->q_gen = (uint16_t)~par_gen[n];
    motion_vq_due |= (uint8_t)(1u << n);
    if (mode == M_RESET)                         /* 4.8.2: the <ed> ramp from the next tick on */
        emergency_at(x, STOP_DISABLE, p->ed_t);  /* (the velocities are stale until after the command) */
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
    vq_refresh_x(x, n);
    emergency_at(x, then, x->q_ed_t);
}

/* 6.3.4: the drive's power stage is off, the loop cannot brake the motor:
 * the setpoint ramps with <ed> and the axis is disabled as soon as it stands. */
void motion_drive_fault(unsigned n)
{
    motion_emergency(n, STOP_DISABLE);
    axis_stop_settle_set(axis_at[n], 0);
}

/* A protective stop has ramped down (and, if it waits for it, the mechanics
 * stand): what follows it (4.8). */
void stop_done(unsigned n)
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
    axis_stop_set(x, STOP_NONE, 0);
    x->done = 1;
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

/* Whether the axis stands for a command that needs it to (WZP, DEINIT, ...):
 * declared with the axis' state (card.h), here since it asks the modes. */
int axis_standstill(unsigned n)
{
    uint8_t m = axes[n].mode;
    if (m == M_DISABLE || m == M_TEST)
        return 1;
    return motion_at_rest(n) && !motion_busy(n) && m != M_SPEED && m != M_VEL_TRACK &&
           m != M_POS_TRACK && !axes[n].stop_then;
}

/* INIT's measurement (4.9), declared with the axis' state (card.h): here,
 * above the measurement and the extensions it sets up. */
void axis_init_measurement(unsigned n)
{
    measure_init(n);
    axis_supervised_at(&axes[n], axes[n].meas);    /* axis.h */
    ext_axis_init(n);                            /* the extensions follow the new measurement */
}
