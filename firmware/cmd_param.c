/*
 * cmd_param.c - the parameter writes W../UW.. (1.2 groups 4 and 5): the
 * checks of each parameter (range, card, stand-still, 6.3.3, 6.3.7), then
 * the parameter store (params.c).  Called through write_param (cmd_table.h)
 * from cmd_execute_other (cmd_general.c).
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "cmd_table.h"
#include "params.h"
#include "measure.h"
#include "card_variant.h"

/* ---- parameter writes ---------------------------------------------------- */
int cmd_write_param_checked(unsigned a, unsigned p, int32_t v)
{
    if (pdesc[p].kind == PK_SYS && !system_change_allowed(a))
        return ERR_LOGICAL;
    if (v < pdesc[p].min || v > pdesc[p].max)
        return ERR_LIMIT;
    switch (p) {
    case P_ET:
        if (!et_ok(v))
            return ERR_LIMIT;
        break;
    case P_EA:
        if (v != 0 && !measure_ea_ok((uint32_t)v, 0))
            return ERR_LIMIT;     /* odd, or DPRAM outside the host's part (0: not set yet) */
        break;
    case P_EC: {
        int32_t sh = PAR_W(a, SH), et = PAR_W(a, ET);
        if (sh != 1 && (et == 2 || et == 4))
            return ERR_LOGICAL;   /* 6.3.7: not on circular axes with an absolute encoder */
        break;
    }
    case P_AP:
    case P_AT:                    /* 6.3.3: every target, the tracking one too */
        if (!cmd_target_ok(a, v))
            return ERR_LIMIT;
        break;
    case P_LV:
        if (!card_lv_ok(a, v))
            return ERR_LIMIT;     /* 4.8.3: not above the start/stop frequency */
        break;
    case P_WD:
        cmd_wd_last_us = now_us();    /* the watchdog counts from here (only kept while <wd> > 0) */
        break;
    case P_ZP:
        /* against the measured position and the mode: masked (write_param) */
        cmd_remask();
        if (!axis_standstill(a))
            return ERR_LOGICAL;   /* 6.3.7: position set only at stand-still */
        if (axis_initialised(a)) {
            /* <ao> such that the actual position becomes v (4.3.2) */
            int32_t ao = pos_sub(v, axes[a].meas);
            params_force(a, P_AO, ao, PS_WRITTEN);
            measure_set_pos(a);
        }
        axes[a].zp_value = v;
        cmd_unmask();
        break;
    default:
        break;
    }
    params_write(a, p, v);                        /* (in range: checked above) */
    if (p == P_IRQ1 || p == P_IRQ2)
        cmd_irq12_update();
    if (p == P_SSF && PAR_W(a, LV) > v) {   /* 4.8.3: <lv> follows a lower <ssf> */
        params_force(a, P_LV, v, PS_WRITTEN);
    }
    return 0;
}
