/*
 * card_variant.h - the card variant's part of the card's common files
 * (axis.c, card.c, supervise.c, cmd_general.c, cmd_param.c): one name per
 * hook, inline, defined once for the servo cards (INC, SSI: servo_card.h)
 * and once for the stepper (STP: stp_variant.h).  The motion files' hooks
 * are motion_card.h's.  docs/firmware.md, "The card variant by file".
 */
#ifndef CARD_VARIANT_H
#define CARD_VARIANT_H
#include "card.h"

/* This header's one card test: a header cannot be chosen by the link, and
 * the tick's and the supervision's hooks want to be inline. */
#if MAC4_CARD == MAC4_CARD_STP
#include "stp_variant.h"
#else
#include "servo_card.h"
#endif

#endif
