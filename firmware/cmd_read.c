/*
 * cmd_read.c - the reads (1.2 groups 4-6): R../UR.. give the value as
 * written, the diagnosis (6.1, table 6.2) a field of the axis or a value
 * worked out here.  Reads change nothing and are executed even with an
 * error waiting (6.3); the dispatcher (cmd.c) reads the CK_FIELD ones
 * itself.
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "cmd_table.h"
#include "params.h"
#include "ext.h"

uint32_t cmd_read_value(cmd_t c, unsigned a)
{
    const axis_t *x = axis_at[a];
    if (c.kind == CK_FIELD)
        return *(const uint32_t *)(const void *)((const uint8_t *)x + c.arg);
    if (c.kind == CK_RPAR) {
        if (c.arg == P_ZP)
            return (uint32_t)x->zp_value;
        return (uint32_t)par_written(a, c.arg);
    }
    switch (c.arg) {
    case CI_VER: return FW_VER_WORD;
    case CI_RCPI:
    case CI_ROUT: return cmd_read_card(c.arg, a);
    case CI_RPS: return (uint32_t)(int32_t)(x->prof.vel >> 16);
    case CI_RAS: return card_ostat;
    default: return ext_read(c.arg, a);
    }
}
