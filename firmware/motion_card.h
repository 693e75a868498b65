/*
 * motion_card.h - the card variant's part of the motion files (motion*.c):
 * one name per hook, defined once for the servo cards (INC, SSI) and once
 * for the stepper (STP).  docs/firmware.md, "The card variant by file".
 *
 *   out of line (main loop, at E or per parameter change): servo_motion.c,
 *   stp_motion.c, linked per card by the Makefile (FW_SERVO, FW_STP);
 *   inline (per SP or per tick, where a call would cost cycles):
 *   servo_motion.h, stp_motion.h, one of them included below.
 */
#ifndef MOTION_CARD_H
#define MOTION_CARD_H
#include "card.h"
#include "motion.h"
#include "profile.h"

/* A velocity or acceleration parameter in Q16 per SP, scaled by <sf> (4.8.4). */
int64_t vq(unsigned n, int32_t v);
/* E, unmasked: the card's part of the plan (servo gains, or <ssf>, <lv>, TURBO). */
void motion_plan_card(unsigned n, motion_plan_t *p);

/* The inline hooks.  This header's one card test: a header cannot be
 * chosen by the link, and the hot paths want them inline. */
#if MAC4_CARD == MAC4_CARD_STP
#include "stp_motion.h"
#else
#include "servo_motion.h"
#endif

#endif
