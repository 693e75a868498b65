/*
 * ssi_card.h - the MAC4-SSI's inline hooks of card_variant.h: the servo
 * cards' (servo_card.h) and those of its encoder interface, J1's Gray code
 * status and the timer's SSI wait.  INIT's part of the interface is
 * ssi_meas.c.
 */
#ifndef SSI_CARD_H
#define SSI_CARD_H
#include "inline.h"
#include "hal.h"
#include "card.h"
#include "servo_card.h"

/* card_start: the tick comes when the SSI reads the expiry started are done */
#define ENC_TMR_CTRL TMR_CTRL_SSI_WAIT

/* J1 (Gray or binary) is readable from basic init on: the GRAY status bit
 * follows it at every input change (supervise.c axis_inputs) and at INIT
 * (ssi_meas.c). */
FW_INLINE void axis_inputs_enc(axis_t *x, uint16_t in)
{
    if (in & AX_IN_GRAY)
        x->ustat |= UB(GRAY);
    else
        x->ustat &= ~UB(GRAY);
}
/* card_reset: J1 known before an INIT that comes ahead of the first tick
 * reads the encoder. */
FW_INLINE void axis_reset_enc(axis_t *x, unsigned n)
{
    axis_inputs_enc(x, hal_rd16(AX_REG(n, AX_IN)));
}

#endif
