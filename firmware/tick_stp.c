/*
 * tick_stp.c - the timer interrupt of the MAC4-STP (the Makefile links it
 * for that card; tick_servo.c is the INC/SSI's): position measurement ->
 * the setpoint interpolated in the profile generator's SP segment -> the
 * step rate (stepper.h) -> outputs.  What looks at the result is the
 * supervision (supervise.c) in the main loop.
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "measure.h"
#include "stepper.h"
#include "tick.h"
#include "handover.h"

/* The STP's position counter (steps, or encoder increments with BR closed)
 * as the INC's, converted to steps. */
FW_INLINE void stp_tick_measure(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    uint8_t mk = x->mk_tick;
    if (mk == MK_COUNTER)
        measure_apply(x, measure_steps(x, n, measure_counter(x, n)));
    else if (mk != MK_NONE)                       /* MK_NONE: position reads 0 before INIT (4.9) */
        stp_measure_ext(x, &meas_cfg[n], n);      /* <et> 3/4 (stepper.h) */
}

/* At each SP boundary: take the segment the main loop prepared (motion_profile.c,
 * next_segment), split into 32-bit parts, which the tick interpolates in
 * Q16 for the step rate, or hold at the end of the last one; a late
 * segment counts in card_profile_late (only then: the common case adds
 * nothing).  No 64-bit arithmetic here. */
FW_INLINE void stp_take_segment(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    if (x->braking)
        return;                                  /* the tick brakes by itself */
    if (x->nx_ready) {
        handover_take_segment(x);
        return;
    }
    handover_segment_late(x);
    if (x->mode != M_DISABLE && x->mode != M_TEST)
        card_profile_late++;
}

/* The setpoint a step per tick on from b + bf (the segment's start, or the
 * last tick's setpoint). */
FW_INLINE void stp_step(const axis_t *x, int32_t b, uint16_t bf, int32_t *i, uint16_t *f)
{
    uint16_t nf = (uint16_t)(bf + x->st_f);
    int32_t ni = pos_add(b, x->st_i);
    if (nf < bf)                                 /* the fraction's carry */
        ni = pos_add(ni, 1);
    *i = ni;
    *f = nf;
}

/* One axis of the STP tick after its measurement: the setpoint, the step
 * rate (stepper.h stp_rate), the outputs.  One body, instantiated with a
 * constant path (STP_PATH_*, the axis' stp_path) so that neither the mode
 * nor the brake is tested in it. */
FW_INLINE void stp_axis(unsigned n, unsigned phase, unsigned path)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    stp_t *s = &stp_ax[n];
    PIN_PTR(s);
    if (path == STP_PATH_IDLE) {
        if (x->mode == M_DISABLE) {
            axis_result_idle(x);
        }
        axis_output_at(n, 0);   /* the step rate and DIR, BOOST, TURBO (stp_output); test mode: <da> in Hz */
        return;
    }
    /* Setpoint: the SP segment in four steps, integer + Q16 fraction in 32
     * bits; the segment's start and end are taken exactly from the profile. */
    int32_t old_i = x->sp_i;
    uint16_t old_f = x->sp_f;
    int32_t i;
    uint16_t f;
    if (path == STP_PATH_BRAKE) {                /* a stop that cannot wait for the next SP */
        int32_t v = brake_slower(x), ssf = x->br_ssf;
        if (v <= ssf && v >= -ssf) {
            /* from <ssf> or less a stepper stops at once (5.14); a ramp step
             * that would jump from above it to below it ends at <ssf> first */
            int32_t w = x->br_v;
            v = w > ssf ? ssf : w < -ssf ? -ssf : 0;
        }
        brake_step(x, v);
        brake_split(x, &i, &f);                  /* into locals: they alias nothing */
    } else if (phase == 0) {                     /* the SP boundary's, the longest tick, first */
        stp_step(x, x->start_i, x->start_f, &i, &f);
    } else if (phase != 3) {
        stp_step(x, old_i, old_f, &i, &f);
    } else {
        i = x->end_i;
        f = x->end_f;
    }
    handover_sp_set(x, i, f);
    stp_rate(x, s, n, phase, old_i, old_f, i, f);    /* step rate, creep phase, RFE */
    /* the outputs of a running axis (tick.h axis_output_at, stp_output):
     * /EN, DIR, BOOST, TURBO and the rate the rate stage prepared */
    uint16_t ctrl = (uint16_t)((x->ctrl & ~(AX_CTRL_EN | STP_OBITS)) | AX_CTRL_EN | s->obits);
    axis_output_write(x, n, ctrl, s->rate);
}

/* One axis: its measurement, then the body its path byte names, read after
 * the measurement (an encoder error disables the axis there). */
FW_INLINE void stp_tick_axis(unsigned n, unsigned phase)
{
    stp_tick_measure(n);
    uint8_t path = axes[n].stp_path;
    if (path == STP_PATH_RUN)
        stp_axis(n, phase, STP_PATH_RUN);
    else if (path == STP_PATH_BRAKE)
        stp_axis(n, phase, STP_PATH_BRAKE);
    else
        stp_axis(n, phase, STP_PATH_IDLE);
}

/* The timer's vector enters it directly (HAL_ISR: no entry stub). */
HAL_ISR void fw_isr_tick(void)
{
    hal_wr16(TMR_STATUS, TMR_ST_EXPIRED);
    unsigned phase = card_ticks & (PROFILE_DIVIDER - 1u);
    if (phase == 0) {                             /* SP boundary: take the prepared segments */
        stp_take_segment(0);
        stp_take_segment(1);
        stp_take_segment(2);
        stp_take_segment(3);
        card_profile_due = MAC4_NAXES;
    }
    /* four times with a constant n: absolute register addresses, the axis
     * in an address register */
    stp_tick_axis(0, phase);
    stp_tick_axis(1, phase);
    stp_tick_axis(2, phase);
    stp_tick_axis(3, phase);
    card_ticks++;
}
