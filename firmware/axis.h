/*
 * axis.h - axis.c's changes of the mode, inline: axis_set_mode's and
 * axis_disable's one body each (axis.c instantiates them for any axis), and
 * the encoder error (6.3.8), which the tick's external measurement
 * instantiates with a constant axis and M_DISABLE (servo_meas.c), so that
 * the disable is straight-line there: no call, no mode dispatch.
 */
#ifndef AXIS_H
#define AXIS_H
#include "inline.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "measure.h"
#include "tick.h"
#include "card_variant.h"

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
    x->stop_then = STOP_NONE;
    x->stop_settle = 0;
    x->next_mode = NO_MODE;
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
