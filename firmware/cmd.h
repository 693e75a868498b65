/* cmd.h - command processing: queue -> decoder -> command table -> response. */
#ifndef CMD_H
#define CMD_H
#include "queue.h"
#include "status.h"

/* The index of every command of commands.def (cmd.c's table, the
 * extensions' dispatch in ext.c). */
enum {
#define GEN(mn, code, cards, kind, desc) CI_##mn,
#define MODESEL(mn, code, cards, mode, desc) CI_##mn,
#define DIAG(mn, code, cards, units, desc) CI_##mn,
#define PARAM(id, mn, kind, wcode, cards, flags, min, max, def, units, desc) CI_W_##id, CI_R_##id,
#include "commands.def"
    NCMDS
};

void cmd_reset(void);
void cmd_poll(void);                    /* main loop: handle at most one command */
void cmd_execute(const mac4_msg_t *in, mac4_msg_t *out);
void cmd_publish(void);                 /* the command counters to the card data block */
extern uint8_t cmd_mr;                 /* MR accepted: let the watchdog reset the card */
static inline int cmd_mr_pending(void) { return cmd_mr; }
/* Off-fly (5.15): commands waiting for their axis' move, oldest first
 * (for tests and the fuzz model).  At most CMD_HOLD_MAX; while that many
 * wait, no interface is read. */
#define CMD_HOLD_MAX 16
unsigned cmd_held(const mac4_msg_t **list);
/* cmd_offfly.c, for cmd.c's poll: */
extern uint8_t cmd_n_held;              /* commands waiting (written by cmd_offfly.c only) */
void cmd_offfly_reset(void);
int cmd_offfly_busy(unsigned axis);     /* a valid axis whose commands wait now */
void cmd_offfly_hold(const mac4_msg_t *m);  /* m waits, behind the others (room checked) */
int cmd_offfly_next(mac4_msg_t *m);     /* the oldest whose axis is free, taken out: 1; or 0 */

#endif
