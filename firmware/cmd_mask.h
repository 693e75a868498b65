/* cmd_mask.h - a command's masked section (cmd.c execute_and_respond and
 * vme_read run every command with interrupts masked, so that the tick sees
 * it whole or not at all) and the way out of it for a part of a command
 * that no interrupt reads: the main loop's own state (parameters being
 * activated, the extensions' tables and budget). */
#ifndef CMD_MASK_H
#define CMD_MASK_H
#include "hal.h"

/* Only inside a command, at level 0 before it: interrupts enabled for the
 * part between these two, masked again after. */
static inline void cmd_unmask(void) { hal_irq_enable_all(); }
static inline void cmd_remask(void) { (void)hal_irq_save(); }

#endif
