/*
 * cmd_offfly.c - off-fly (5.15, docs/interpretations.md): the commands for
 * an axis whose move runs off-fly wait here, in the order they came, until
 * the move ends; reads and C are answered at once (cmd.c decides which may
 * wait), other axes are not held up.  cmd.c's poll asks this stage whether
 * a command waits, hands it over, and takes back the oldest one whose axis
 * is free; this file calls nothing of cmd.c.
 */
#include "fw.h"
#include "card.h"
#include "cmd.h"
#include "motion.h"
#include "params.h"
#include "cmd_table.h"            /* now_us, cmd_wd_last_us: <wd> (4.7) */

static mac4_msg_t held[CMD_HOLD_MAX];
uint8_t cmd_n_held;
static uint8_t held_axes;       /* bit n: a command for axis n waits in held[] */

void cmd_offfly_reset(void)
{
    cmd_n_held = 0;
    held_axes = 0;
}

unsigned cmd_held(const mac4_msg_t **list)
{
    *list = held;
    return cmd_n_held;
}

/* The axis' move runs off-fly: its commands wait for the end of it. */
FW_INLINE int axis_in_series(unsigned a)
{
    return !(axis_at[a]->ustat & UB(ON_FLY)) && motion_busy(a);
}

int cmd_offfly_busy(unsigned a)
{
    return a < MAC4_NAXES && ((held_axes & (1u << a)) || axis_in_series(a));
}

void cmd_offfly_hold(const mac4_msg_t *m)
{
    held[cmd_n_held++] = *m;
    held_axes |= (uint8_t)(1u << m->axis);
    if (PAR(0, WD) > 0)
        cmd_wd_last_us = now_us();      /* a held command counts for the watchdog when it comes */
}

int cmd_offfly_next(mac4_msg_t *m)
{
    unsigned blocked = 0;
    for (unsigned i = 0; i < cmd_n_held; i++) {
        unsigned a = held[i].axis, bit = 1u << a;
        if (blocked & bit)
            continue;               /* an older command of this axis waits */
        if (axis_in_series(a)) {
            blocked |= bit;
            continue;
        }
        *m = held[i];
        unsigned mask = 0;
        for (unsigned k = 0; k + 1u < cmd_n_held; k++) {
            if (k >= i)
                held[k] = held[k + 1u];
            mask |= 1u << held[k].axis;
        }
        cmd_n_held--;
        held_axes = (uint8_t)mask;
        return 1;
    }
    return 0;
}
