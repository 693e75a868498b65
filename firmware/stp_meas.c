/*
 * stp_meas.c - the MAC4-STP's part of the measurement (measure.h, "per
 * card"); its diagnosis is stp_variant.h's card_read.  The INC/SSI's is
 * servo_meas.c; the STP image links this one (Makefile, FW_STP).
 */
#include "fw.h"
#include "card.h"
#include "measure.h"
#include "cmd.h"
#include "cmd_table.h"
#include "stepper.h"


/* measure_ext (measure.h) on the STP: the body is stepper.h's
 * stp_measure_ext, which the tick inlines per axis. */
void measure_ext(axis_t *x, meas_cfg_t *c, unsigned n) { stp_measure_ext(x, c, n); }

void measure_init_card(unsigned n)
{
    stp_init(n);                    /* ratio, tolerance, BR; meas in steps */
}
