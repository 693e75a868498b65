/*
 * servo_card.h - the INC/SSI cards' hooks of card_variant.h: a DAC output,
 * /EN written with the mode, the tick's setpoint rows read back by the
 * supervision.
 */
#ifndef SERVO_CARD_H
#define SERVO_CARD_H
#include "inline.h"
#include "hal.h"
#include "card.h"
#include "params.h"

/* the controller period (7.4), the board's (hal/mac4_map.h) */
#define CARD_TICK_US SERVO_PERIOD_US_SERVO

/* axis_set_mode: /EN follows the mode at once (the servo tick writes only
 * the DAC). */
FW_INLINE void axis_mode_card(axis_t *x, unsigned n, uint8_t mode)
{
    x->ctrl = (uint16_t)((x->ctrl & ~AX_CTRL_EN) | (mode != M_DISABLE ? AX_CTRL_EN : 0));
    hal_wr16(AX_REG(n, AX_CTRL), x->ctrl);
}
/* The following error's tolerance beyond <mf> (4.8.1): none. */
FW_INLINE int32_t axis_mf_tol(unsigned n) { (void)n; return 0; }

/* ROUT: the DAC word. */
FW_INLINE uint32_t card_rout(const axis_t *x, unsigned n) { (void)n; return (uint32_t)(int32_t)x->out; }
/* LED F beyond the drive fault signal (7.1.2): nothing. */
FW_INLINE int card_led_fault(const axis_t *x) { (void)x; return 0; }

/* The setpoint and following error of the tick in phase ph, as it used
 * them (RCP-side values, the following-error check): the tick itself keeps
 * only what the next tick needs. */
FW_INLINE void tick_result(axis_t *x, unsigned ph)
{
    if (x->mode == M_DISABLE) {
        x->setpoint = x->meas;
        x->ferr = 0;
    } else if (x->mode != M_TEST) {
        x->setpoint = x->braking ? brake_setpoint(x) : x->sp_now[ph];
        x->ferr = pos_sub(x->setpoint, x->meas);
    }
}
/* Level 5: the servo cards have no step pulses. */
FW_INLINE void card_isr_axis(uint16_t pending) { (void)pending; }

/* INIT (cmd_general.c): the measurement is set up unmasked, the tick
 * leaving the axis alone (mk_tick) meanwhile. */
#define CARD_INIT_MASKED 0

/* <lv> (4.8.3) limits only the STP. */
FW_INLINE int card_lv_ok(unsigned a, int32_t v) { (void)a; (void)v; return 1; }

#endif
