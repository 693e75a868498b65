/*
 * stp_card.h - what the MAC4-STP card's stages share (stepper.c: the axis,
 * its measurement, motion and status; stp_rate.c: the step rate, the creep
 * phase and the output): the creep phase's abort (its states are
 * stepper.h's, which the tick's rate stage tests).
 */
#ifndef STP_CARD_H
#define STP_CARD_H
#include "stepper.h"

/* A creep broken off (a new mode, a protective stop): stp_rate.c */
void stp_creep_abort(unsigned n);

#endif
