/*
 * stp_meas.c - the MAC4-STP's part of the measurement (measure.h, "per
 * card") and of the diagnosis (cmd_read.c); the INC/SSI's is servo_meas.c.
 * The STP image links it (Makefile, FW_STP).
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

uint32_t cmd_read_card(unsigned ci, unsigned a)
{
    if (ci == CI_RCPI)
        return (uint32_t)stp_counts(a);             /* increments since INIT */
    return (uint32_t)stp_out_steps_sp(a);           /* ROUT: Steps/SP (table 6.2) */
}
