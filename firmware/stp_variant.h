/*
 * stp_variant.h - the MAC4-STP's hooks of card_variant.h: the tick writes
 * AX_CTRL itself, keeps setpoint and following error, and counts the creep
 * phase's pulses by interrupt.
 */
#ifndef STP_VARIANT_H
#define STP_VARIANT_H
#include "inline.h"
#include "hal.h"
#include "card.h"
#include "params.h"
#include "stepper.h"
#include "stp_rate.h"
#include "cmd.h"

/* the controller period (7.4), the board's (hal/mac4_map.h) */
#define CARD_TICK_US SERVO_PERIOD_US_STP

/* One tick body: the timer's vector stays fw_isr_tick. */
FW_INLINE void tick_select(void) {}

/* axis_set_mode: the tick's body for the axis (the tick writes AX_CTRL,
 * /EN too, every tick). */
FW_INLINE void axis_mode_card(axis_t *x, unsigned n, uint8_t mode)
{
    (void)n;
    stp_path_set_for(x, mode);
}
/* 4.8.1: <mf> plus the tolerance of <ms>/(4 <es>). */
FW_INLINE int32_t axis_mf_tol(unsigned n) { return stp_tol(n); }

/* ROUT: the step frequency in Hz. */
FW_INLINE uint32_t card_rout(const axis_t *x, unsigned n) { (void)x; return (uint32_t)stp_hz_now(n); }
/* The diagnosis' card stages (cmd.c read_value, CK_CARD), inline: a
 * quarter of the reads is ROUT, Steps/SP (table 6.2); RCPI the increments
 * since INIT. */
#define CARD_READ_INLINE 1
FW_INLINE uint32_t card_read(unsigned ci, unsigned a)
{
    if (ci == CI_RCPI)
        return (uint32_t)stp_counts(a);
    return (uint32_t)stp_out_steps_sp(a);
}
/* LED F also shows an unacknowledged error (7.1.2 led_fault). */
FW_INLINE int card_led_fault(const axis_t *x) { return (x->ustat & US_ERRORS) != 0; }

/* The STP's tick keeps setpoint and following error itself. */
FW_INLINE void tick_result(axis_t *x, unsigned ph) { (void)x; (void)ph; }
/* Level 5: the creep phase's step pulses and count done (stp_rate.h). */
FW_INLINE void card_isr_axis(uint16_t pending)
{
    if (pending & 0x0FF0u)
        stp_isr(pending);
}

/* INIT (cmd_general.c): the tick works on a disabled axis' step output and
 * count too (stp_t, which the set-up rewrites): the measurement masked. */
#define CARD_INIT_MASKED 1

/* The encoder interface, the internal counter (counter_meas.c): no J1, no
 * timer wait (card_variant.h). */
#define ENC_TMR_CTRL 0
FW_INLINE void axis_inputs_enc(axis_t *x, uint16_t in) { (void)x; (void)in; }
FW_INLINE void axis_reset_enc(axis_t *x, unsigned n) { (void)x; (void)n; }

/* 4.8.3: <lv> not above the start/stop frequency. */
FW_INLINE int card_lv_ok(unsigned a, int32_t v) { return v <= PAR_W(a, SSF); }

#endif
