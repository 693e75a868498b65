/*
 * motion_justify.c - the justification modes of the profile generator, one
 * SP each (profile_modes): search index with C (5.7), search index (5.8),
 * home (5.9), find edge (5.10).  The index latch they wait for is polled
 * after every tick (motion_supervise.c).
 */
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "motion.h"
#include "motion_priv.h"

static int sw_active(unsigned n, uint32_t ubit) { return (axes[n].ustat & ubit) != 0; }

static void justified(unsigned n, int set_zero)
{
    axis_t *x = axis_at[n];
    justified_card(x);                           /* the profile onto the edge (STP: not) */
    x->prof.vel = 0;
    mode_done(x, 1);
    if (set_zero) {
        /* the index pulse is the axis' reference: position 0 there (4.9) */
        params_force(n, P_AO, -x->edge, PS_WRITTEN);
        measure_set_pos(n);
    }
    x->ustat |= UB(JUS_END);
    vme_irq((uint8_t)PAR(n, IRQ4));
}

static int64_t sgn(int32_t v, int64_t mag) { return v < 0 ? -mag : mag; }

void justify_modes(unsigned n)
{
    axis_t *x = axis_at[n];
    PIN_PTR(x);
    prof_t *p = &x->prof;
    switch (x->mode) {
    case M_SEARCH_IDX_C:                     /* 5.7 */
        if (x->phase == 0) {
            ramp(p, vq(n, PAR(n, CV)), vq(n, PAR(n, CA)), vq(n, PAR(n, CA)));
            if (x->idx_seen)
                justify_phase(x, 1);
        } else if (!x->done && ramp(p, 0, vq(n, PAR(n, CD)), vq(n, PAR(n, CD)))) {
            mode_done(x, 1);
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
                justify_phase(x, 1);
                if (brake_at_switch(p, n, PAR(n, HD)))   /* STP: braking in this SP */
                    justify_phase(x, 2);
            } else
                ramp(p, vq(n, hv), vq(n, PAR(n, HA)), vq(n, PAR(n, HA)));
            break;
        case 1:                              /* brake with <hd> */
            if (ramp(p, 0, vq(n, PAR(n, HD)), vq(n, PAR(n, HD))))
                justify_phase(x, sw_active(n, UB(REF)) ? 2 : 0);
            break;
        case 2:                              /* 2: left edge of the switch at <lv> */
            if (!sw_active(n, UB(REF))) {
                p->vel = 0;
                left_switch_card(p, n);      /* onto the measurement (STP: not) */
                arm_index(n);
                justify_phase(x, 3);
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
                justify_phase(x, 1);
                if (brake_at_switch(p, n, PAR(n, FD)))   /* STP: braking in this SP */
                    justify_phase(x, 2);
            } else
                ramp(p, sgn(dir, fv), vq(n, PAR(n, FA)), vq(n, PAR(n, FA)));
            break;
        case 1:
            if (ramp(p, 0, vq(n, PAR(n, FD)), vq(n, PAR(n, FD))))
                justify_phase(x, 2);
            break;
        case 2:                              /* back at <lv> to the transition */
            if (!sw_active(n, bit)) {
                edge_found(x, x->meas);
                justified(n, 0);
                justify_phase(x, 3);
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
