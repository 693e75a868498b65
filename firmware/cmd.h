/* cmd.h - command processing: queue -> decoder -> command table -> response. */
#ifndef CMD_H
#define CMD_H
#include "queue.h"

void cmd_reset(void);
void cmd_poll(void);                    /* main loop: handle at most one command */
void cmd_execute(const mac4_msg_t *in, mac4_msg_t *out);
int cmd_mr_pending(void);               /* MR accepted: let the watchdog reset the card */

#endif
