/*
 * servo_motion.h - the INC/SSI cards' inline motion hooks (motion_card.h):
 * the tick takes four setpoint rows per SP (tick_servo.c take_row), and the
 * closed loop waits for the mechanics at rest.
 */
#ifndef SERVO_MOTION_H
#define SERVO_MOTION_H
#include "inline.h"
#include "card.h"
#include "params.h"
#include "profile.h"
#include "servo_card.h"
#include "handover.h"

#define CARD_SP_ROWS 1          /* the profile hands the tick setpoint rows */
#define CARD_SP_MS 10u          /* the sampling period, ms (<trt>, 5.6) */
#define CARD_STOP_SETTLES 1     /* a stop that disables waits for rest (4.8.2) */

/* TURBO (4.1.3) is the STP's only. */
FW_INLINE uint8_t vq_turbo(const axis_t *x) { (void)x; return 0; }

/* The ramp of every mode: the profile's. */
FW_INLINE int ramp(prof_t *p, int64_t vt, int64_t acc, int64_t dec)
{
    return prof_ramp(p, vt, acc, dec);
}

/* The tick's body for the axis (servo_card.h SERVO_PATH_*). */
FW_INLINE void motion_path_set(axis_t *x) { servo_path_set(x); }

/* motion_hold: the tick's setpoint rows hold the position. */
FW_INLINE void motion_hold_card(axis_t *x)
{
    handover_rows_hold(x);
}

/* brake_now: the ramp from the last tick's setpoint at the SP's speed. */
FW_INLINE void brake_from_card(axis_t *x, int64_t *pos, int32_t *v)
{
    *pos = (int64_t)x->setpoint * 65536;
    *v = x->sp_vel / 4;
}

/* brake_done: the rows hold the braked setpoint. */
FW_INLINE void brake_done_card(axis_t *x)
{
    handover_rows_at(x, brake_setpoint(x));
}

/* motion_start, masked: the gains of the plan. */
FW_INLINE void motion_start_card(unsigned n, uint8_t mode, const motion_plan_t *p)
{
    (void)mode;
    axis_set_gains(n, &p->gains);
    servo_path_set(axis_at[n]);                  /* K only or the general filter */
}

/* ---- the profile generator, per SP (motion_profile.c) ---- */
FW_INLINE void profile_begin_card(axis_t *x, unsigned n) { (void)x; (void)n; }
FW_INLINE void profile_end_card(unsigned n, int64_t before, int64_t before_vel)
{
    (void)n; (void)before; (void)before_vel;
}
/* 5.11: velocity tracking, the acceleration not limited. */
FW_INLINE void vel_track_card(prof_t *p, int64_t vt)
{
    p->vel = vt;
    p->pos += p->vel;
}
/* 5.6: one SP of positioning; 1 once on target. */
FW_INLINE int position_card(axis_t *x, unsigned n)
{
    (void)n;
    return x->q_fit ? prof_position_fit(&x->prof, x->target, &x->q_l32)
                    : prof_position_free(&x->prof, x->target, x->q_pv, x->q_pa, x->q_pd, x->q_free);
}
FW_INLINE int32_t pos_end_tol(unsigned n) { (void)n; return 0; }
FW_INLINE void pos_end_card(axis_t *x) { (void)x; }

/* ---- the supervision after every tick (motion_supervise.c) ---- */
/* The index latched d counts from the measurement. */
FW_INLINE int32_t index_edge_card(const axis_t *x, unsigned n, int32_t d) { (void)n; return x->meas + d; }
/* The direction of a motion the profile does not show: none. */
FW_INLINE int creep_dir_card(unsigned n) { (void)n; return 0; }

/* ---- the justification modes (motion_justify.c) ---- */
/* At the edge: the profile back onto it (a servo may reverse). */
FW_INLINE void justified_card(axis_t *x) { x->prof.pos = Q16(x->edge); }
/* Left the switch: the profile stands on the measurement. */
FW_INLINE void left_switch_card(prof_t *p, unsigned n) { p->pos = meas_q(n); }
/* The switch found: the servo brakes from the next SP on (0: not braked). */
FW_INLINE int brake_at_switch(prof_t *p, unsigned n, int32_t dec)
{
    (void)p; (void)n; (void)dec;
    return 0;
}

#endif
