/* cmd.h - command processing: queue -> decoder -> command table -> response. */
#ifndef CMD_H
#define CMD_H
#include "queue.h"

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

#endif
