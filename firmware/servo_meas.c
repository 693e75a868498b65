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


/* ... for every kind of axis: out of line, so that the tick's copies keep
 * only the absolute linear case and few registers, the others a tail call */
static void __attribute__((noinline)) measure_ext_take_any(axis_t *x, const meas_cfg_t *c, uint32_t raw)
{
    measure_ext_take(x, c, raw, 0);
}

FW_INLINE void measure_ext_body(axis_t *x, meas_cfg_t *c, unsigned n)
{
    uint32_t raw;
    if (measure_ext_valid(x, c, n, &raw)) {
        axis_encoder_error_at(x, c, n);           /* inline: n a constant in the tick */
        return;
    }
    if (c->abs && x->linear)
        measure_ext_take(x, c, raw, 1);
    else
        measure_ext_take_any(x, c, raw);
}

void measure_ext(axis_t *x, meas_cfg_t *c, unsigned n) { measure_ext_body(x, c, n); }

/* The tick's (tick_servo.c measure_ext_axis): the same body once per axis
 * with a constant n, so that the call passes nothing and the axis, its
 * configuration and its registers are absolute addresses (no register to
 * save: fewer cycles than the two pointers in address registers). */
FW_INLINE void measure_ext_at(unsigned n)
{
    measure_ext_body(&axes[n], &meas_cfg[n], n);
}
void measure_ext_0(void) { measure_ext_at(0); }
void measure_ext_1(void) { measure_ext_at(1); }
void measure_ext_2(void) { measure_ext_at(2); }
void measure_ext_3(void) { measure_ext_at(3); }

/* The encoder error of the tick's inline path (tick_servo.c
 * tick_measure_ext), the same way with a constant n */
FW_INLINE void measure_ext_error_at(unsigned n)
{
    axis_encoder_error_at(&axes[n], &meas_cfg[n], n);
}
void measure_ext_error_0(void) { measure_ext_error_at(0); }
void measure_ext_error_1(void) { measure_ext_error_at(1); }
void measure_ext_error_2(void) { measure_ext_error_at(2); }
void measure_ext_error_3(void) { measure_ext_error_at(3); }

void measure_init_card(unsigned n)
{
    (void)n;                        /* a servo axis' measurement is measure_init's alone */
}

uint32_t cmd_read_card(unsigned ci, unsigned a)
{
    (void)ci;                       /* ROUT: RCPI is not on the INC/SSI (commands.def) */
    return (uint32_t)(int32_t)axis_at[a]->out;      /* the DAC word, sign-extended */
}
