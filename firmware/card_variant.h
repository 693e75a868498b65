/*
 * card_variant.h - the card variant's part of the card's common files
 * (axis.c, card.c, supervise.c, measure.c, cmd.c, cmd_general.c,
 * cmd_param.c): one
 * name per hook, inline, defined once for the servo cards (INC, SSI:
 * servo_card.h) and once for the stepper (STP: stp_variant.h); and the
 * card's own encoder, defined once per encoder interface.  The motion
 * files' hooks are motion_card.h's.  docs/firmware.md, "The card variant by
 * file".
 */
#ifndef CARD_VARIANT_H
#define CARD_VARIANT_H
#include "card.h"
#include "measure.h"

/* ---- the card's own encoder (<et> 0-2, table 4.3) -------------------------
 * The internal 24-bit counter (INC, STP: counter_meas.c) or the SSI receiver
 * (SSI: ssi_meas.c), out of line (INIT, E):
 *   measure_init_enc: INIT's <ea> in force and <eb>/<ec> limited (table 4.3
 *     "def."), c's path for <et> 0-2; on the SSI J1's Gray code status too;
 *   measure_read_enc: INIT's first reading, 0 and the raw value;
 *   measure_kind_enc: axis_prepare's MK_* for <et> 0-2;
 *   axis_prepare_enc: axis_prepare's set-up of the interface (SSI: the
 *     receiver reads at the timer's expiry).
 * Inline, in the card's header below: axis_inputs_enc (the supervision,
 * at an input change), axis_reset_enc (card_reset), ENC_TMR_CTRL (the
 * timer's control bits of card_start). */
void measure_init_enc(unsigned n, meas_cfg_t *c, int32_t et, int32_t *eb, int32_t *ec);
int measure_read_enc(unsigned n, const meas_cfg_t *c, uint32_t *raw);
uint8_t measure_kind_enc(int32_t et, int linear);
void axis_prepare_enc(axis_t *x, unsigned n, int32_t et);

/* This header's one card test: a header cannot be chosen by the link, and
 * the tick's and the supervision's hooks want to be inline.  The servo
 * cards' headers include servo_card.h. */
#if MAC4_CARD == MAC4_CARD_STP
#include "stp_variant.h"
#elif MAC4_CARD == MAC4_CARD_SSI
#include "ssi_card.h"
#else
#include "inc_card.h"
#endif

/* The diagnosis' card stages (cmd.c, CK_CARD): inline where the card's
 * header gives card_read (STP), else cmd_read_card out of line
 * (servo_meas.c). */
#ifndef CARD_READ_INLINE
#include "cmd_table.h"
FW_INLINE uint32_t card_read(unsigned ci, unsigned a) { return cmd_read_card(ci, a); }
#endif

#endif
