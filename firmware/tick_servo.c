/*
 * tick_servo.c - the timer interrupt of the MAC4-INC and MAC4-SSI (the
 * Makefile links it for those cards; tick_stp.c is the STP's).  Data flows
 * one way: position measurement -> the setpoint the profile generator
 * prepared for this tick -> servo filter -> DAC.  What looks at the result
 * is the supervision (supervise.c) in the main loop.
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "measure.h"
#include "tick.h"
#include "servo_card.h"
#include "tick_servo.h"
#include "handover.h"


/* The tick does only what must happen at the sampling instant (7.4):
 * measure, interpolate the setpoint, filter, drive the outputs.  Everything
 * that looks at the result - switches, protective reactions, stop bits,
 * status, the DPRAM data - is card_supervise() in the main loop, which
 * runs before anything else there once per tick. */
/* The external measurement of axis n, a constant (servo_meas.c) */
FW_INLINE void measure_ext_axis(unsigned n)
{
    if (n == 0)
        measure_ext_0();
    else if (n == 1)
        measure_ext_1();
    else if (n == 2)
        measure_ext_2();
    else
        measure_ext_3();
}

/* ... and its encoder error (6.3.8), out of line */
FW_INLINE void measure_ext_error_axis(unsigned n)
{
    if (n == 0)
        measure_ext_error_0();
    else if (n == 1)
        measure_ext_error_1();
    else if (n == 2)
        measure_ext_error_2();
    else
        measure_ext_error_3();
}

/* The tick's external measurement (MK_OTHER), <et> 3/4, n a constant: the
 * common case - 32-bit VMEbus reads of an absolute encoder on a linear
 * axis - inline (the INC's counter path still falls through to the rest of
 * the axis), the rest out of line (servo_meas.c).  The measured position
 * afterwards. */
FW_INLINE int32_t tick_measure_ext(axis_t *x, unsigned n)
{
    meas_cfg_t *c = &meas_cfg[n];
    PIN_PTR(c);                                   /* its six fields: displacements, not absolute addresses */
    uint32_t raw;
    if (c->path == EXT_VME32 && c->abs && x->linear) {
        if (measure_ext_valid_k(x, c, n, &raw, 1) == 0)
            return measure_abs_take(x, raw);
        measure_ext_error_axis(n);
    } else {
        measure_ext_axis(n);
    }
    return x->meas;
}

/* The measurement of one axis of the INC/SSI tick, the card's own common
 * kind first (one test on the common path), the external one second.  Inlined four times with a constant
 * n, so the registers are absolute addresses and the axis one address
 * register.  The measured position afterwards: an absolute reading gives it
 * in a register. */
FW_INLINE int32_t tick_measure(axis_t *x, unsigned n)
{
    uint8_t mk = x->mk_tick;                      /* MK_NONE before INIT (4.9) */
    uint32_t raw;
    if (MAC4_CARD == MAC4_CARD_INC && mk == MK_COUNTER) {
        measure_apply(x, measure_counter(x, n));
    } else if (MAC4_CARD == MAC4_CARD_SSI && mk == MK_SSI_ABS) {   /* the encoder at the connector, absolute, linear */
        if (measure_ssi_read(x, n, &raw) == 0)
            return measure_abs_take(x, raw);
    } else if (mk == MK_OTHER) {                  /* <et> 3/4, second: one test more for the SSI's others */
        return tick_measure_ext(x, n);
    } else if (MAC4_CARD == MAC4_CARD_SSI && mk == MK_SSI_CIRC) {  /* absolute, circular */
        if (measure_ssi_read(x, n, &raw) == 0)
            return measure_circ_take(x, raw);
    } else if (MAC4_CARD == MAC4_CARD_SSI && mk == MK_SSI) {       /* relative, or followed as relative */
        if (measure_ssi_read(x, n, &raw) == 0)
            return measure_rel_take(x, &meas_cfg[n], raw);
    }
    return x->meas;                               /* MK_NONE: nothing measured before INIT */
}

/* The SSI's measurements hand the measured position on in a register (an
 * absolute reading is it); the INC's counter adds its motion to it in
 * memory, where the setpoint difference reads it back (in a register it
 * would cost a load and a store more than that saves). */
#define TICK_MEAS_HELD (MAC4_CARD == MAC4_CARD_SSI)

/* One axis of the INC/SSI tick after its measurement: the setpoint, the
 * filter, the DAC.  One body, instantiated with a constant path
 * (SERVO_PATH_*, the axis' servo_path, servo_card.h) so that neither the
 * mode, the brake nor the gains are tested in it.  The setpoint
 * is entry ph4 / 4 of the row in force: at the SP boundary (boundary, a
 * constant) the row take_row gave, still in a register, and entry 0;
 * else x->sp_now's.  /EN follows the mode in axis_set_mode(); here only the
 * DAC. */
FW_INLINE void tick_axis(axis_t *x, unsigned n, int32_t meas, const int32_t *row, unsigned ph4,
                                                                     unsigned path, int boundary)
{
    int16_t u = 0;
    if (path == SERVO_PATH_IDLE) {
        /* disabled: 0 V; the setpoint and following error: card_supervise (tick_result) */
        if (x->mode == M_TEST)
            u = (int16_t)PAR(n, DA);              /* 5.13: straight to the DAC */
    } else {
        int32_t sp;
        if (path == SERVO_PATH_BRAKE || path == SERVO_PATH_BRAKE_FULL) {    /* a stop that cannot wait for the next SP */
            brake_step(x, brake_slower(x));
            sp = brake_setpoint(x);
        } else if (boundary) {
            sp = row[0];
        } else {
            sp = *(const int32_t *)(const void *)((const uint8_t *)x->sp_now + ph4);
        }
        int32_t e = pos_sub(sp, TICK_MEAS_HELD ? meas : x->meas);
        if (path == SERVO_PATH_RUN_FULL || path == SERVO_PATH_BRAKE_FULL)
            u = servo_filter(&x->servo, &x->gains, e);
        else
            u = servo_step_k(&x->servo, &x->gains, e);
        if (x->ustat & UB(REV_O))                 /* USR (4.2) */
            u = (int16_t)(u == SERVO_OUT_MIN ? SERVO_OUT_MAX : -u);
    }
    axis_dac_write(x, n, u);
}

/* The SP boundary for INC/SSI (the STP's is stp_take_segment), inlined
 * with the axis a constant: the row in force from now.  A late row counts
 * in card_profile_late (only then: the common case adds nothing). */
FW_INLINE const int32_t *take_row(axis_t *x)
{
    int32_t *row = x->sp_now;
    if (x->nx_ready)
        return handover_take_row(x, row);
    if (x->braking)
        return row;                               /* the tick brakes by itself */
    handover_row_late(x, row);
    if (x->mode != M_DISABLE && x->mode != M_TEST)
        card_profile_late++;
    return row;
}

FW_INLINE void take_row_at(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    (void)take_row(x);
}

/* One axis: at the SP boundary of the K-only tick (boundary) its row
 * first, then its measurement, then the body its path byte names, read
 * after the measurement (an encoder error disables the axis there).  The
 * K-only tick (general 0) has no RUN_FULL and no BRAKE_FULL: they mean
 * gains.full, and axis.c's axis_set_gains, their one writer (card.h's
 * writers: line, checked by tools/onewriter.py), sets the axis' bit of
 * card_servo_general with them, so the general tick runs whenever an
 * axis' path is one of them. */
FW_INLINE void tick_axis_at(unsigned n, unsigned ph4, int general, int boundary)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    const int32_t *row = 0;
    if (boundary)
        row = take_row(x);
    int32_t meas = tick_measure(x, n);
    uint8_t path = x->servo_path;
    if (general && path == SERVO_PATH_RUN_FULL)   /* first in the general tick: its worst */
        tick_axis(x, n, meas, row, ph4, SERVO_PATH_RUN_FULL, boundary);
    else if (path == SERVO_PATH_RUN)
        tick_axis(x, n, meas, row, ph4, SERVO_PATH_RUN, boundary);
    else if (path == SERVO_PATH_BRAKE)
        tick_axis(x, n, meas, row, ph4, SERVO_PATH_BRAKE, boundary);
    else if (general && path == SERVO_PATH_BRAKE_FULL)
        tick_axis(x, n, meas, row, ph4, SERVO_PATH_BRAKE_FULL, boundary);
    else
        tick_axis(x, n, meas, row, ph4, SERVO_PATH_IDLE, boundary);
}

FW_INLINE void tick_axes(unsigned ph4, int general, int boundary)
{
    tick_axis_at(0, ph4, general, boundary);
    tick_axis_at(1, ph4, general, boundary);
    tick_axis_at(2, ph4, general, boundary);
    tick_axis_at(3, ph4, general, boundary);
}

/* The general tick's four axes, the general filter inline (it runs K-only
 * gains the K-only way), the rows first at the SP boundary ... */
FW_INLINE void tick_general_body(void)
{
    unsigned phase = card_ticks & (PROFILE_DIVIDER - 1u);
    if (phase == 0) {                             /* SP boundary: take the prepared rows */
        take_row_at(0);
        take_row_at(1);
        take_row_at(2);
        take_row_at(3);
        card_profile_due = MAC4_NAXES;
    }
    tick_axes(phase * 4u, 1, 0);
    card_ticks++;
}

/* ... out of line: the K-only tick's between SP boundaries, so that the
 * K-only tick's own body is only its worst tick's, the SP boundary's; on
 * the SSI also the general tick's (its image has no room for the body
 * twice: 6 KiB), on the INC the general tick has it inline (no call). */
static void __attribute__((noinline)) tick_general(void)
{
    tick_general_body();
}
#define TICK_GENERAL_INLINE (MAC4_CARD == MAC4_CARD_INC)

/* The tick: the K-only one (general 0: K-only gains on every axis, the
 * defaults) has a body of its own for the SP boundary, which takes each
 * axis' row where it runs the axis and reads the setpoint from it. */
FW_INLINE void tick(int general)
{
    hal_wr16(TMR_STATUS, TMR_ST_EXPIRED);
    if (!general && (card_ticks & (PROFILE_DIVIDER - 1u)) == 0) {
        tick_axes(0, 0, 1);
        card_profile_due = MAC4_NAXES;
        card_ticks++;
    } else if (general && TICK_GENERAL_INLINE) {
        tick_general_body();
    } else {
        tick_general();
    }
}

/* The timer's vector enters a tick directly (HAL_ISR: it saves only the
 * registers it uses and ends in RTE, no entry stub): the K-only tick from
 * reset on, the general one while an axis needs the general filter, which
 * tick_select (servo_card.h) puts in the vector wherever
 * card_servo_general changes.  Natively there is no vector: the emulator
 * calls fw_isr_tick, which chooses (HAL_VECTORED 0). */
HAL_ISR void fw_isr_tick(void)
{
    if (!HAL_VECTORED && card_servo_general)
        tick(1);
    else
        tick(0);
}

HAL_ISR void fw_isr_tick_general(void) { tick(1); }
