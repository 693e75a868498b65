/*
 * motion_profile.c - the profile generator, once per SP in the main loop,
 * one axis per pass (card_profile_tick): the modes' next step, and the
 * next SP's segment prepared for the tick, which takes it over at the SP
 * boundary (tick_servo.c take_row, tick_stp.c stp_take_segment).
 * Everything runs in the measurement frame (position without <ao>), in Q16.
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "motion.h"
#include "motion_priv.h"
#include "handover.h"

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
static void next_segment_wide(axis_t *x, int64_t before);

FW_INLINE void next_segment(axis_t *x, int64_t before)
{
    int64_t dd = x->prof.pos - before;
    if (CARD_SP_ROWS && dd < (1l << 30) && dd > -(1l << 30)) {
        handover_rows(x, before, (int32_t)dd);   /* the usual SP, in 32 bits */
        return;
    }
    next_segment_wide(x, before);
}

/* The rest: the STP's split segment, and an INC/SSI SP of 2^30 or more. */
static void next_segment_wide(axis_t *x, int64_t before)
{
    PIN_PTR(x);
    const prof_t *p = &x->prof;
    int64_t d64 = p->pos - before;
    if (CARD_SP_ROWS)
        handover_vel_next(x, d64 > INT32_MAX ? INT32_MAX : d64 < -INT32_MAX ? -INT32_MAX : (int32_t)d64);
    split_q16(before, &x->nx_start_i, &x->nx_start_f);
    split_q16(p->pos, &x->nx_end_i, &x->nx_end_f);
    if (d64 >= INT32_MIN && d64 <= INT32_MAX) {  /* no 64-bit shift */
        int32_t d32 = (int32_t)d64;
        // cppcheck-suppress shiftNegativeLHS ; arithmetic (floor) on GCC, as in handover_rows
        int32_t st = d32 >> 2;
        x->nx_st_i = st >> 16;
        x->nx_st_f = (uint16_t)st;
    } else {
        // cppcheck-suppress shiftNegativeLHS ; arithmetic (floor) on GCC, as in handover_rows
        split_q16(d64 >> 2, &x->nx_st_i, &x->nx_st_f);
    }
    if (CARD_SP_ROWS)
        handover_row_of_segment(x);              /* the four ticks' setpoints */
    handover_publish(x);
}

static void profile_modes(unsigned n) __attribute__((noinline));

/* 5.6: pos_end once the axis has been in the target radius <tr> for <trt>
 * sampling periods after the setpoint arrived. */
void pos_end_check(unsigned n)
{
    axis_t *x = axis_at[n];
    int64_t d = (x->target >> 16) - x->meas;
    if (d < 0)
        d = -d;
    d -= pos_end_tol(n);                         /* STP 5.6: the tolerance of <ms>/(4 <es>) */
    if (d <= PAR(n, TR)) {
        if (x->trt_count >= x->trt_periods) {
            x->ustat |= UB(POS_END);
            pos_end_card(x);                     /* STP: IN_POS, 7.1.2 (LED P) */
            vme_irq((uint8_t)PAR(n, IRQ4));
        } else {
            trt_count_step(x);
        }
    } else {
        trt_count_reset(x);
    }
}

/* INC/SSI: a positioning SP with limits below 2^30 (braking, landing) where the cruise
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
        handover_rows(x, before, d);
    } else {
        landed = prof_position_ref(&x->prof, x->target, x->q_pv, x->q_pa, x->q_pd, x->q_free);
        next_segment(x, before);
    }
    if (landed) {
        mode_done(x, 1);
        pos_end_check(n);
    }
}


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
    /* INC/SSI: the positioning fast paths (the STP's positioning has its creep phase) */
    if (CARD_SP_ROWS && x->mode == M_POSITIONING && !x->stop_then && x->done) {
        /* on target: the setpoint stands (the step would be 0) until pos_end */
        if (!(x->ustat & UB(POS_END)))
            pos_end_check(n);
        handover_rows(x, x->prof.pos, 0);
        return;
    }
    if (CARD_SP_ROWS && x->mode == M_POSITIONING && !x->stop_then && !x->done) {
        vq_refresh_x(x, n);
        int64_t before = x->prof.pos;
        int32_t d;
        if (x->q_fast &&
            (d = prof_cruise32(&x->prof, x->q_hi, x->q_lo, (int32_t)x->q_pv, (int32_t)x->q_pa)) != 0) {
            handover_rows(x, before, d);
            return;
        }
        if (x->q_fit) {                          /* braking, landing: what profile_modes does */
            position_fit_step(x, n);
            return;
        }
    }
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
    int64_t before_vel = p->vel;
    profile_begin_card(x, n);                    /* STP: status bits, <ssf> of the axis */

    if (x->mode == M_DISABLE || x->mode == M_TEST) {
        motion_hold(n);
        return;
    }
    vq_refresh(n);
    if (x->stop_then) {                          /* protective stop: ramp <ed> */
        int64_t ed = x->q_ed;
        if (ramp(p, 0, ed, ed) && !x->stop_settle)
            stop_done(n);                        /* (else when the mechanics stand: stop_watch) */
    } else {
        switch (x->mode) {
        case M_ENABLE:                           /* hold; UE from a move: stop with <pd> */
        case M_BRAKE:
            mode_done(x, ramp(p, 0, x->q_pd, x->q_pd));
            break;
        case M_RESET:                            /* 4.8.2: emergency ramp, at rest, then disable */
            motion_emergency(n, STOP_DISABLE);   /* the tick brakes (brake_now) */
            return;
        case M_SPEED: {                          /* <vt> with the ramps <pa>/<pd> */
            prof_t was = *p;
            ramp(p, vq(n, PAR(n, VT)), x->q_pa, x->q_pd);
            limit_guard(x, n, &was, x->q_pd);    /* before a software limit: <pd> */
            break;
        }
        case M_VEL_TRACK: {                      /* 5.11: acceleration not limited */
            prof_t was = *p;
            vel_track_card(p, vq(n, PAR(n, VT)));   /* STP: through <ssf> (5.14) */
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
            if (!x->done && position_card(x, n))  /* STP: then the creep phase (diagram 5.2) */
                mode_done(x, 1);
            if (x->done && !(x->ustat & UB(POS_END)))
                pos_end_check(n);
            break;
        case M_SEARCH_IDX_C:                     /* the justification modes (motion_justify.c) */
        case M_SEARCH_IDX:
        case M_HOME:
        case M_FIND_EDGE:
            justify_modes(n);
            break;
        default:
            break;
        }
    }
    profile_end_card(n, before, before_vel);     /* STP: BOOST <bt> ahead of a move (4.1.4) */
    /* the next SP's segment, for the tick to take at the boundary */
    if (x->mode != M_DISABLE && x->mode != M_TEST)
        next_segment(x, before);
}
