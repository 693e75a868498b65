/*
 * axis.c - the state of an axis as commands and protective reactions change
 * it: mode, gains, error, disable, and the tick's copies of the parameters
 * (axis_prepare), which the main loop refreshes at INIT and E so that the
 * tick never looks a parameter up.  It calls only down (parameters, the
 * output stage): INIT's measurement and the standstill test, which ask the
 * measurement, the extensions and the modes, are motion.c's
 * (tools/callgraph.py).
 */
#include "hal.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "stepper.h"
#include "tick.h"
#include "card_variant.h"
#include "axis.h"

/* The only writer of an axis' gains, so that card_servo_general always
 * says which axes need the general filter (interrupts masked: motion_start).
 * Compiled for speed: the copy inline as long moves, not a memcpy call and
 * its loop, in E's masked commit. */
__attribute__((optimize("O2"))) void axis_set_gains(unsigned n, const servo_gains_t *g)
{
    axis_at[n]->gains = *g;
    if (g->full)
        card_servo_general |= (uint8_t)(1u << n);
    else
        card_servo_general &= (uint8_t)~(1u << n);
    tick_select();                                /* the timer's vector follows */
}

/* the bodies: axis.h (the tick's encoder error instantiates them too) */
void axis_set_mode(unsigned n, uint8_t mode)
{
    axis_t *x = axis_at[n];                       /* the table, not a multiply by sizeof(axis_t) */
    PIN_PTR(x);
    axis_set_mode_at(x, n, mode);
}

void axis_disable(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    axis_disable_at(x, n);
}

void axis_error(unsigned n, uint32_t ubit, uint16_t code)
{
    axes[n].ustat |= ubit;
    axes[n].err_report = code;
}

/* The part of axis_prepare that follows mode parameters (<mf>): all that
 * changes at an E on an initialised axis, since system parameters change
 * only at INIT, which prepares the rest. */
void axis_prepare_mode(unsigned n)
{
    axis_t *x = &axes[n];
    x->mf = PAR(n, MF);
    x->mf += axis_mf_tol(n);                     /* STP 4.8.1: the tolerance of <ms>/(4 <es>) */
    x->in_eval = 1;                              /* the switches again at the next tick */
}

void axis_prepare(unsigned n)
{
    axis_t *x = &axes[n];
    int32_t et = PAR(n, ET);
    x->linear = PAR(n, SH) == 1;
    x->mk = et > 2 ? MK_OTHER : measure_kind_enc(et, x->linear);     /* the card's own encoder */
    x->cr = PAR(n, CR);
    x->lp = PAR(n, LP);
    x->ln = PAR(n, LN);
    axis_prepare_mode(n);
    /* switch configuration (4.5): 0 off, 1 low active, 2 high active */
    static const uint16_t bits[4] = {AX_IN_IESP, AX_IN_IESN, AX_IN_RS, AX_IN_DF};
    int32_t cfg[4] = {PAR(n, PS), PAR(n, NS), PAR(n, RS), PAR(n, DF)};
    axis_prepare_enc(x, n, et);                  /* SSI: the receiver reads at the timer's expiry */
    x->sw_en = x->sw_inv = 0;
    for (unsigned i = 0; i < 4; i++) {
        if (cfg[i])
            x->sw_en |= bits[i];
        if (cfg[i] == 2)
            x->sw_inv |= bits[i];
    }
}
