/*
 * stp_card.h - what the MAC4-STP card's stages share (stepper.c: the axis,
 * its measurement, motion and status; stp_rate.c: the step rate, the creep
 * phase and the output): the creep phase's states.
 */
#ifndef STP_CARD_H
#define STP_CARD_H
#include "stepper.h"


/* CREEP_TRIM: at stand-still, the step counter a step or two off the
 * setpoint (the generator's phase): those steps at <lv>, any mode. */
enum { CREEP_IDLE = STP_CREEP_IDLE, CREEP_REQ, CREEP_WAIT, CREEP_RUN, CREEP_DONE, CREEP_TRIM };

/* A creep broken off (a new mode, a protective stop): stp_rate.c */
void stp_creep_abort(unsigned n);

#endif
