/* axis.h - the inline part of axis.c: the writes of axis.c's parts that
 * the commands (masked), the supervision after every tick (four axes
 * inlined) and the extensions make, inline so that axis.c stays their one
 * writer at no cost on those paths (tools/onewriter.py: axis.c and axis.h
 * are one module; tools/callgraph.py: axis.h is axis.c).  The rest of
 * axis.c is declared in card.h. */
#ifndef AXIS_H
#define AXIS_H
#include "inline.h"
#include "card.h"

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
    x->pos = pos;
}

#endif
