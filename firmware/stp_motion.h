/*
 * stp_motion.h - the MAC4-STP's inline motion hooks (motion_card.h): the
 * tick takes a split segment per SP (tick_stp.c stp_take_segment), the
 * step rate is open loop, every ramp goes through <ssf> (5.14).
 */
#ifndef STP_MOTION_H
#define STP_MOTION_H
#include "inline.h"
#include "card.h"
#include "params.h"
#include "profile.h"
#include "stepper.h"
#include "handover.h"

#define CARD_SP_ROWS 0          /* the profile hands the tick a segment */
#define CARD_SP_MS 32u          /* the sampling period, ms (<trt>, 5.6) */
#define CARD_STOP_SETTLES 0     /* open loop: stopped is the rate ramped to <ssf> and off */

/* 5.14: on the STP every ramp of every mode starts from stand-still with
 * <ssf> and stops from at most <ssf> (stepper.c); set per axis by
 * profile_begin_card before the mode's step. */
extern int64_t stp_ssf_now;
#define STP_UNLIMITED ((int64_t)1 << 48)

FW_INLINE uint8_t vq_turbo(const axis_t *x)
{
    return (x->sstat & SB(TURBO)) != 0;          /* 4.1.3 */
}

/* The ramp of every mode, through <ssf>. */
FW_INLINE int ramp(prof_t *p, int64_t vt, int64_t acc, int64_t dec)
{
    return stp_ramp(p, vt, acc, dec, stp_ssf_now);
}

/* The tick's body for the axis (stepper.h stp_path_of): after every change
 * of the mode or the tick's brake. */
FW_INLINE void motion_path_set(axis_t *x) { stp_path_set(x); }

/* motion_hold: the segment (already at rest) is all the tick reads. */
FW_INLINE void motion_hold_card(axis_t *x) { (void)x; }

/* brake_now: from the Q16 setpoint and the segment's step per tick; a
 * stepper stops at once from <ssf> or less (5.14): br_ssf per tick. */
FW_INLINE void brake_from_card(axis_t *x, int64_t *pos, int32_t *v)
{
    *pos = (int64_t)x->sp_i * 65536 + x->sp_f;
    *v = (int32_t)((uint32_t)x->st_i << 16) + (int32_t)x->st_f;
    x->br_ssf = (int32_t)(stp_ax[x - axes].ssf >> 2);
}

/* brake_done: the segment holds the braked setpoint. */
FW_INLINE void brake_done_card(axis_t *x)
{
    handover_segment_at_brake(x);
}

/* motion_start, masked: creep phase, <lv>, TURBO (stepper.c). */
FW_INLINE void motion_start_card(unsigned n, uint8_t mode, const motion_plan_t *p)
{
    stp_motion_start(n, mode, &p->stp);
}

/* ---- the profile generator, per SP (motion_profile.c) ---- */
FW_INLINE void profile_begin_card(axis_t *x, unsigned n)
{
    if (x->mode == M_DISABLE || x->mode == M_TEST)
        stp_status(n);                           /* system status bits (else stp_profile_end) */
    stp_ssf_now = stp_ax[n].ssf;                 /* <ssf> on the rate grid, from E */
}
FW_INLINE void profile_end_card(unsigned n, int64_t before, int64_t before_vel)
{
    stp_profile_end(n, before, before_vel);      /* BOOST <bt> ahead of a move (4.1.4) */
}
/* 5.11: the acceleration not limited, but from and to stand-still through <ssf> (5.14). */
FW_INLINE void vel_track_card(prof_t *p, int64_t vt)
{
    ramp(p, vt, STP_UNLIMITED, STP_UNLIMITED);
}
/* 5.6: ramps to <stc> steps before the target, then the creep phase
 * (diagram 5.2); 1 once on target. */
FW_INLINE int position_card(axis_t *x, unsigned n)
{
    return stp_positioning(n, x->q_pv, x->q_pa, x->q_pd, stp_ssf_now);
}
/* 5.6: <tr> less the tolerance of <ms>/(4 <es>). */
FW_INLINE int32_t pos_end_tol(unsigned n) { return stp_tol(n); }
FW_INLINE void pos_end_card(axis_t *x) { x->sstat |= SB(IN_POS); }   /* 7.1.2: STP only (LED P) */

/* ---- the supervision after every tick (motion_supervise.c) ---- */
/* The index latched d increments from here, in steps. */
FW_INLINE int32_t index_edge_card(const axis_t *x, unsigned n, int32_t d) { (void)x; return stp_edge(n, d); }
/* A creep phase's direction while it runs, else 0. */
FW_INLINE int creep_dir_card(unsigned n) { return stp_creep_dir(n); }

/* ---- the justification modes (motion_justify.c) ---- */
/* At the edge: the steps stop where they are, from <lv> <= <ssf>; no jump
 * back to the edge, which would be a reversal above <ssf>. */
FW_INLINE void justified_card(axis_t *x) { (void)x; }
/* Left the switch: the steps stop where they are. */
FW_INLINE void left_switch_card(prof_t *p, unsigned n) { (void)p; (void)n; }
/* The switch found: the braking ramp begins in this SP, a stepper must not
 * pause at speed; 1 once it stands. */
FW_INLINE int brake_at_switch(prof_t *p, unsigned n, int32_t dec)
{
    int64_t d = vq(n, dec);
    return ramp(p, 0, d, d);
}

#endif
