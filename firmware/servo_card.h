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

/* The tick's path of an axis (axis_t.servo_path): which instantiation of
 * the one axis body (tick_servo.c tick_axis) runs it.  What decides it
 * changes only in the main loop, masked - the mode (axis_set_mode), the
 * tick's own brake (motion.c brake_now, brake_done, motion_hold) and the
 * gains (motion_start_card, axis_set_gains' one caller) - and each of those
 * calls servo_path_set, so the tick tests one byte instead of the mode
 * twice, the brake and the gains.  0 is IDLE: a zeroed axis is disabled. */
enum {
    SERVO_PATH_IDLE,        /* disabled (0 V) or test mode (<da>): no setpoint, no filter */
    SERVO_PATH_RUN,         /* a mode with a profile, the setpoint from the SP's row, K only */
    SERVO_PATH_RUN_FULL,    /* the same with the general filter (servo_gains_t.full) */
    SERVO_PATH_BRAKE,       /* braked by the tick itself (x->braking), K only */
    SERVO_PATH_BRAKE_FULL   /* the same with the general filter */
};
FW_INLINE uint8_t servo_path_of(const axis_t *x)
{
    if (x->mode == M_DISABLE || x->mode == M_TEST)
        return SERVO_PATH_IDLE;
    if (x->braking)
        return x->gains.full ? SERVO_PATH_BRAKE_FULL : SERVO_PATH_BRAKE;
    return x->gains.full ? SERVO_PATH_RUN_FULL : SERVO_PATH_RUN;
}
FW_INLINE void servo_path_set(axis_t *x) { x->servo_path = servo_path_of(x); }

/* The tick body the timer's vector enters (tick_servo.c): the general one
 * while an axis needs the general filter, else the K-only one.  Where
 * card_servo_general changes (axis_set_gains, card_reset), masked. */
FW_INLINE void tick_select(void)
{
    hal_set_tick_vector(card_servo_general != 0);
}

/* axis_set_mode: /EN follows the mode at once (the servo tick writes only
 * the DAC), and the tick's body for the axis. */
FW_INLINE void axis_mode_card(axis_t *x, unsigned n, uint8_t mode)
{
    axis_ctrl_set(x, (uint16_t)((x->ctrl & ~AX_CTRL_EN) | (mode != M_DISABLE ? AX_CTRL_EN : 0)));
    hal_wr16(AX_REG(n, AX_CTRL), x->ctrl);
    servo_path_set(x);
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
        axis_result_idle(x);
    } else if (x->mode != M_TEST) {
        axis_result_set(x, x->braking ? brake_setpoint(x) : x->sp_now[ph]);
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
