/* axis.h - the inline part of axis.c (tools/onewriter.py: axis.c and
 * axis.h are one module; tools/callgraph.py: axis.h is axis.c):
 *
 * - the writes of axis.c's parts that the commands (masked), the
 *   supervision after every tick (four axes inlined) and the extensions
 *   make, inline so that axis.c stays their one writer at no cost there;
 * - axis_set_mode's and axis_disable's one body each (axis.c instantiates
 *   them for any axis) and the encoder error (6.3.8), which the tick's
 *   external measurement instantiates with a constant axis and M_DISABLE
 *   (servo_meas.c), so that the disable is straight-line there: no call, no
 *   mode dispatch.
 *
 * The rest of axis.c is declared in card.h. */
#ifndef AXIS_H
#define AXIS_H
#include "inline.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "measure.h"
#include "tick.h"
#include "card_variant.h"

/* The error code is given as the answer to a command (cmd.c): no report
 * left (axis_error sets it). */
FW_INLINE void axis_error_reported(axis_t *x)
{
    x->err_report = 0;
}

/* The mode the next E selects (a mode command, cmd_general.c), or NO_MODE:
 * what E, INIT, DEINIT, a stop bit, a disable and a reset leave behind. */
FW_INLINE void axis_select_mode(axis_t *x, uint8_t mode)
{
    x->next_mode = mode;
}

/* What follows the protective stop in progress (STOP_*, STOP_NONE: none)
 * and whether it waits for the mechanics at rest (4.8): motion.c begins,
 * raises and ends the stop through these, and every disable ends it
 * (axis_disable_at), as a disable ends the mode selected. */
FW_INLINE void axis_stop_set(axis_t *x, uint8_t then, uint8_t settle)
{
    x->stop_then = then;
    x->stop_settle = settle;
}

FW_INLINE void axis_stop_settle_set(axis_t *x, uint8_t settle)
{
    x->stop_settle = settle;
}

/* At a reset and while INIT sets up the measurement (cmd_general.c
 * do_init): the tick leaves the axis alone until the supervision after. */
FW_INLINE void axis_measure_off(axis_t *x)
{
    x->mk_tick = MK_NONE;
}

/* A compensation table (ext_comp.c) takes the SSI's absolute reading as a
 * relative one while it is on, and gives the kind back when it is off; the
 * tick follows at once where it measures the axis. */
FW_INLINE void axis_kind_relative(axis_t *x)
{
    if (x->mk == MK_SSI_ABS)
        x->mk = MK_SSI;
    if (x->mk_tick == MK_SSI_ABS)
        x->mk_tick = MK_SSI;
}

FW_INLINE void axis_kind_restore(axis_t *x, uint8_t mk)
{
    x->mk = mk;
    if (x->mk_tick != MK_NONE)
        x->mk_tick = mk;
}

/* The supervision has looked at the switch inputs (supervise.c): again at
 * the next tick only if again (an active drive fault, which acts as soon
 * as the axis runs); axis_prepare_mode asks for it at INIT and E. */
FW_INLINE void axis_inputs_evaluated(axis_t *x, int again)
{
    x->in_eval = (uint8_t)again;
}

/* What the tick measures from now: mk once initialised, else MK_NONE (4.9). */
FW_INLINE void axis_follow_init(axis_t *x)
{
    x->mk_tick = (x->ustat & UB(INIT)) ? x->mk : MK_NONE;
}

/* The measurement at this supervision (and at INIT, motion.c), from which
 * the next one's RAV counts. */
FW_INLINE void axis_supervised_at(axis_t *x, int32_t meas)
{
    x->meas_sup = meas;
}

/* A compensation table moved the measurement by d (ext_comp.c): the RAV
 * counts the motion, not the correction's step, and the position moves
 * with it, wrapped on a circular axis. */
FW_INLINE void axis_moved_by(axis_t *x, int32_t d)
{
    x->meas_sup = pos_add(x->meas_sup, d);
    int32_t pos = pos_add(x->pos, d);
    if (!x->linear) {
        while (pos >= x->cr)
            pos -= x->cr;
        while (pos < 0)
            pos += x->cr;
    }
    measure_pos_set(x, pos);
}

/* ---- the mode ---------------------------------------------------------- */
/* The mode in force, in mode and ustat (DR_EN with it), and the card's
 * part (servo: /EN at once and the tick's path; STP: the tick's path). */
FW_INLINE void axis_set_mode_at(axis_t *x, unsigned n, uint8_t mode)
{
    x->mode = mode;
    x->ustat = (x->ustat & ~US_MODE_MASK) | mode;
    if (mode == M_DISABLE) {
        x->ustat &= ~UB(DR_EN);
    } else {
        x->ustat |= UB(DR_EN);
        meas_cfg[n].failed = 0;                   /* the axis runs: a failure counts again (6.3.8) */
    }
    axis_mode_card(x, n, mode);                   /* servo: /EN at once; STP: the tick's body */
}

/* Disabled at once, no ramp: /EN open, 0 V or no pulses now, not at the
 * next tick; no stop and no next mode left. */
FW_INLINE void axis_disable_at(axis_t *x, unsigned n)
{
    axis_set_mode_at(x, n, M_DISABLE);
    axis_output_x(x, n, 0);
    axis_stop_set(x, STOP_NONE, 0);
    axis_select_mode(x, NO_MODE);
}

/* 6.3.8: encoder_f and logo_f, 163 for the next command, disabled without a
 * ramp.  Once: while the axis stays disabled after it, a measurement that
 * keeps failing raises nothing more, so C, DEINIT and new parameters get
 * through; enabled again (axis_set_mode clears `failed`), the next failure
 * raises it again.  measure.c's measure_encoder_error, and the servo tick's
 * external measurement with a constant n. */
FW_INLINE void axis_encoder_error_at(axis_t *x, meas_cfg_t *c, unsigned n)
{
    if (c->failed)
        return;
    c->failed = 1;
    x->ustat |= UB(ENCODER_F) | UB(LOGO_F);       /* axis_error's, in place */
    x->err_report = ERR_LOGICAL;
    axis_disable_at(x, n);
}

#endif
