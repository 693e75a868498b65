/*
 * cmd_table.h - what the stages of the command path share: the command
 * table's entries, the interrupt mask around a command, and the handlers
 * of each group of commands (1.2):
 *   cmd.c          the dispatcher: poll loop, checks, respond, off-fly, <wd>
 *   cmd_general.c  general instructions, mode change (E) and system set-up
 *                  (groups 1-3)
 *   cmd_param.c    the parameter writes W../UW.. (groups 4-5)
 *   cmd_read.c     the reads: R../UR.. and the diagnosis (groups 4-6)
 */
#ifndef CMD_TABLE_H
#define CMD_TABLE_H
#include "inline.h"
#include <stdint.h>
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "cmd_mask.h"

/* ---- the command table -------------------------------------------------- */
/* The kinds of command; reads last: kind >= CK_READ_ is a read.  The
 * diagnosis (cmd.c's table): worked out (CK_DIAG, cmd_read.c), a 32-bit
 * field of axis_t (CK_FIELD) or a signed 16-bit one (CK_FIELD16): arg is
 * the field's offset; or the card's own stages' (CK_CARD, cmd_read_card).
 * The values up to CK_FIELD are the floor's too (bench/floor/floor.h). */
enum { CK_NONE, CK_GEN_, CK_MODE, CK_WPAR, CK_READ_, CK_RPAR, CK_DIAG, CK_FIELD, CK_FIELD16, CK_CARD };
#define CK_GEN CK_GEN_
#define CK_READ CK_READ_

/* Code -> what it is (cmd.c's table): the kind and its argument. */
typedef struct {
    uint8_t kind;
    uint8_t arg;
} cmd_t;

/* Reads answer a value and change nothing (6.3: "read commands always run"). */
static inline int kind_is_read(uint8_t kind) { return kind >= CK_READ; }

/* The time of the last command, for <wd> (kept while <wd> > 0): cmd.c's,
 * set by a <wd> write too (cmd_param.c). */
extern uint32_t cmd_wd_last_us;
void cmd_irq12_update(void);       /* after a write of <irq1>/<irq2> (cmd.c) */

FW_INLINE uint32_t now_us(void)
{
    uint32_t hi = hal_rd16(TMR_FREE_HI);   /* latches the low word */
    return (hi << 16) | hal_rd16(TMR_FREE_LO);
}

/* Which encoder types each card has (table 4.2/4.3). */
static inline int et_ok(int32_t et)
{
    switch (MAC4_CARD) {
    case MAC4_CARD_INC: return et == 1 || et == 3 || et == 4;
    case MAC4_CARD_SSI: return et >= 1 && et <= 4;
    default: return et == 0 || et == 1 || et == 3 || et == 4;
    }
}

static inline int system_change_allowed(unsigned a)
{
    return !axis_initialised(a) || axes[a].mode == M_DISABLE;
}

/* Commands run in the main loop only, at level 0: execute_and_respond masks
 * them and restores level 0 after; cmd_mask.h's cmd_unmask/cmd_remask for a
 * part of a command that the tick does not read. */

/* ---- the groups' handlers ---------------------------------------------- */
/* cmd_param.c */
int cmd_write_param_checked(unsigned a, unsigned p, int32_t v);

/* A parameter write touches what the main loop reads (par_w, par_a, the
 * watchdog's start, the vector flags): the tick reads no parameter but
 * <da>'s word in test mode, and an interrupt reads a parameter with one
 * move, so the checks and the write run with interrupts enabled - but
 * <zp>'s, which sets <ao> against the measured position and the position. */
static inline int write_param(unsigned a, unsigned p, int32_t v)
{
    cmd_unmask();
    int r = cmd_write_param_checked(a, p, v);
    cmd_remask();
    return r;
}

/* cmd_general.c: a target reachable on the axis (6.3.3) */
int cmd_target_ok(unsigned a, int32_t t);
/* cmd_general.c: everything but the reads - C, and the commands that need
 * every error acknowledged first (6.3.7) */
uint16_t cmd_execute_other(cmd_t c, unsigned a, uint32_t param);
/* cmd_read.c: the value of a read (kind_is_read) that is not a field or
 * the card's (cmd.c): the entry's kind and arg as two arguments, which the
 * caller need not pack into a cmd_t */
uint32_t cmd_read_value(unsigned kind, unsigned arg, unsigned a);
/* per card, servo_meas.c (INC, SSI) or stp_meas.c (STP): the diagnosis
 * values read from the card's own stages, ROUT and the STP's RCPI (ci) */
uint32_t cmd_read_card(unsigned ci, unsigned a);

#endif
