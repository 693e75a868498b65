/*
 * handover.h - the hand-over of the next SP from the profile generator
 * (main loop, motion_profile.c) to the tick (tick_servo.c take_row,
 * tick_stp.c stp_take_segment), both sides of it: the one writer of
 * nx_ready, the INC/SSI's setpoint rows and the STP's taken segment and
 * interpolated setpoint (card.h).  The profile generator fills the next
 * row (INC/SSI) or the segment nx_* (motion_profile.c's) and publishes it,
 * masked; the tick takes it at the SP boundary, or holds where it stands
 * when none is ready; motion.c drops a prepared SP (brake_now, brake_done)
 * and starts both sides again at a hold and at the end of the tick's brake
 * (motion_hold, brake_done_card), masked.  All inline, calling nothing: a
 * leaf both sides include.
 */
#ifndef HANDOVER_H
#define HANDOVER_H
#include "inline.h"
#include "card.h"

/* ---- the profile generator: publish the next SP (main loop, masked) ---- */
/* The next SP is ready: the tick takes it at the boundary. */
FW_INLINE void handover_publish(axis_t *x) { x->nx_ready = 1; }

/* INC/SSI: the four setpoints of an SP that moves d (Q16, |d| < 2^30) from
 * before, published: row k = round(before + (k+1) floor(d / 4)), the last
 * round(before + d) - what the split arithmetic of next_segment gives. */
FW_INLINE void handover_rows(axis_t *x, int64_t before, int32_t d)
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
    handover_publish(x);
}

/* INC/SSI, an SP of 2^30 or more: the rows' velocity (saturated), then the
 * next row from the split segment nx_* (start + k step, the last exactly
 * the end); handover_publish() after it. */
FW_INLINE void handover_vel_next(axis_t *x, int32_t vel) { x->sp_vel_next = vel; }
FW_INLINE void handover_row_of_segment(axis_t *x)
{
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
}

/* ---- the tick: take it at the SP boundary ------------------------------ */
/* INC/SSI: the ready row (sp_next) in force from now, row (sp_now) the
 * next to fill. */
FW_INLINE int32_t *handover_take_row(axis_t *x, int32_t *row)
{
    int32_t *next = x->sp_next;
    x->sp_now = next;
    x->sp_next = row;
    x->sp_vel = x->sp_vel_next;
    x->nx_ready = 0;
    return next;
}
/* ... none ready (late): the row in force holds its last setpoint. */
FW_INLINE void handover_row_late(axis_t *x, int32_t *row)
{
    row[0] = row[1] = row[2] = row[PROFILE_DIVIDER - 1u];
    x->sp_vel = 0;
}
/* STP: the ready segment in force from now. */
FW_INLINE void handover_take_segment(axis_t *x)
{
    x->start_i = x->nx_start_i;
    x->start_f = x->nx_start_f;
    x->st_i = x->nx_st_i;
    x->st_f = x->nx_st_f;
    x->end_i = x->nx_end_i;
    x->end_f = x->nx_end_f;
    x->nx_ready = 0;
}
/* ... none ready (late): hold at the end of the last one. */
FW_INLINE void handover_segment_late(axis_t *x)
{
    x->start_i = x->end_i;
    x->start_f = x->end_f;
    x->st_i = 0;
    x->st_f = 0;
}
/* STP, every tick: the setpoint interpolated in the segment (tick_stp.c). */
FW_INLINE void handover_sp_set(axis_t *x, int32_t i, uint16_t f)
{
    x->sp_i = i;
    x->sp_f = f;
}
/* STP, a creep phase's start (stp_rate.h creep_begin): the profile's creep
 * segment is the down-counter's, the setpoint at its end. */
FW_INLINE void handover_segment_at_end(axis_t *x)
{
    x->start_i = x->sp_i = x->end_i;
    x->start_f = x->sp_f = x->end_f;
    x->st_i = 0;
    x->st_f = 0;
}

/* ---- the main loop: drop it, start again (masked) ---------------------- */
/* A prepared SP is dropped: the tick brakes by itself (brake_now,
 * brake_done). */
FW_INLINE void handover_drop(axis_t *x) { x->nx_ready = 0; }
/* motion_hold: both sides start again from the profile's position pos
 * (Q16): none ready, the segment at rest there. */
FW_INLINE void handover_hold(axis_t *x, int64_t pos)
{
    x->nx_ready = 0;
    x->sp_i = x->start_i = x->end_i = (int32_t)(pos >> 16);
    x->sp_f = x->start_f = x->end_f = (uint16_t)pos;
    x->st_i = 0;
    x->st_f = 0;
}
/* INC/SSI, motion_hold: the rows anew, both holding the setpoint
 * handover_hold() left. */
FW_INLINE void handover_rows_hold(axis_t *x)
{
    int32_t sp = x->sp_i + (x->sp_f >= 0x8000u);
    x->sp_now = x->sp_rows[0];
    x->sp_next = x->sp_rows[1];
    for (unsigned k = 0; k < PROFILE_DIVIDER; k++)
        x->sp_rows[0][k] = x->sp_rows[1][k] = sp;
    x->sp_vel = x->sp_vel_next = 0;
}
/* INC/SSI, brake_done: both rows hold the setpoint sp, at rest. */
FW_INLINE void handover_rows_at(axis_t *x, int32_t sp)
{
    for (unsigned k = 0; k < PROFILE_DIVIDER; k++)
        x->sp_rows[0][k] = x->sp_rows[1][k] = sp;
    x->sp_vel = x->sp_vel_next = 0;
}
/* STP, brake_done: the segment holds the braked setpoint. */
FW_INLINE void handover_segment_at_brake(axis_t *x)
{
    brake_split(x, &x->sp_i, &x->sp_f);
    x->start_i = x->end_i = x->sp_i;
    x->start_f = x->end_f = x->sp_f;
    x->st_i = 0;
    x->st_f = 0;
}

#endif
