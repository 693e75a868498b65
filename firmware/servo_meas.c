/*
 * servo_meas.c - the MAC4-INC/SSI's part of the measurement (measure.h,
 * "per card") and of the diagnosis (cmd_read.c); the STP's is stp_meas.c.
 * The INC and SSI images link it (Makefile, FW_SERVO).
 */
#include "fw.h"
#include "card.h"
#include "measure.h"
#include "cmd.h"
#include "cmd_table.h"
#include "axis.h"


FW_INLINE void measure_ext_body(axis_t *x, meas_cfg_t *c, unsigned n)
{
    uint32_t raw;
    if (measure_ext_valid(x, c, n, &raw)) {
        axis_encoder_error_at(x, c, n);           /* inline: n a constant in the tick */
        return;
    }
    int32_t d = measure_delta(x, c, raw);
    x->raw = raw;
    x->counter = raw;
    measure_apply(x, d);
}

void measure_ext(axis_t *x, meas_cfg_t *c, unsigned n) { measure_ext_body(x, c, n); }

/* The tick's (tick_servo.c measure_ext_axis): the same body once per axis
 * with a constant n, so that the call passes nothing; the axis and its
 * configuration each in an address register (shorter than absolute
 * addresses), the registers absolute. */
FW_INLINE void measure_ext_at(unsigned n)
{
    axis_t *x = &axes[n];
    meas_cfg_t *c = &meas_cfg[n];
    PIN_PTR(x);
    PIN_PTR(c);
    measure_ext_body(x, c, n);
}
void measure_ext_0(void) { measure_ext_at(0); }
void measure_ext_1(void) { measure_ext_at(1); }
void measure_ext_2(void) { measure_ext_at(2); }
void measure_ext_3(void) { measure_ext_at(3); }

void measure_init_card(unsigned n)
{
    (void)n;                        /* a servo axis' measurement is measure_init's alone */
}

uint32_t cmd_read_card(unsigned ci, unsigned a)
{
    (void)ci;                       /* ROUT: RCPI is not on the INC/SSI (commands.def) */
    return (uint32_t)(int32_t)axis_at[a]->out;      /* the DAC word, sign-extended */
}
