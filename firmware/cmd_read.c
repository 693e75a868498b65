/*
 * cmd_read.c - the reads (1.2 groups 4-6): R../UR.. give the value as
 * written, the diagnosis (6.1, table 6.2) a field of the axis or a value
 * worked out here.  Reads change nothing and are executed even with an
 * error waiting (6.3); the dispatcher (cmd.c) reads the fields and the
 * card's stages' values (CK_FIELD, CK_FIELD16, CK_CARD) itself.
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"
#include "cmd_table.h"
#include "params.h"
#include "ext.h"

uint32_t cmd_read_value(unsigned kind, unsigned arg, unsigned a)
{
    const axis_t *x = axis_at[a];
    if (kind == CK_RPAR) {
        if (arg == P_ZP)
            return (uint32_t)x->zp_value;
        return (uint32_t)par_written(a, arg);
    }
    switch (arg) {
    case CI_VER: return FW_VER_WORD;
    case CI_RPS: return (uint32_t)(int32_t)(x->prof.vel >> 16);
    case CI_RAS: return card_ostat;
    default: return ext_read(arg, a);
    }
}
