/*
 * inc_card.h - the MAC4-INC's inline hooks of card_variant.h: the servo
 * cards' (servo_card.h); its encoder interface, the internal counter, has
 * no J1 and no timer wait.  INIT's part of the interface is counter_meas.c.
 */
#ifndef INC_CARD_H
#define INC_CARD_H
#include "inline.h"
#include "card.h"
#include "servo_card.h"

#define ENC_TMR_CTRL 0
FW_INLINE void axis_inputs_enc(axis_t *x, uint16_t in) { (void)x; (void)in; }
FW_INLINE void axis_reset_enc(axis_t *x, unsigned n) { (void)x; (void)n; }

#endif
