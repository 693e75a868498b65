/*
 * supervise.c - the main loop's look at each tick's result, once after
 * every tick and before anything else there (fw_main_step): switches, stop
 * bits and protective reactions -> status and the published axis data, the
 * LEDs; and the interrupts that feed it (the axis boards' level 5, /STOP at
 * level 7).  A reaction taken here acts within the servo period of the
 * event: axis_disable() opens /EN at once, and a ramp is braked by the tick
 * itself from the next tick on (motion.c, brake_now).
 */
#include "inline.h"
#include "fw.h"
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "measure.h"
#include "axis.h"
#include "cmd.h"
#include "params.h"
#include "serial.h"
#include "motion.h"
#include "ext.h"
#include "card_variant.h"
#include "leds.h"

static volatile uint8_t estop_seen;   /* set by the level 7 handler */
uint32_t card_supervised;             /* card_ticks at the last card_supervise() */
uint16_t card_supervise_late;         /* ticks the main loop did not supervise in time */

static void stop_bits(void)
{
    /* 3.5.1: bits 1, 3, 5, 7 at $4600; accepted in either byte of the word */
    uint16_t w = hal_rd16(DP_STOP_BITS);
    uint16_t bits = (uint16_t)((w | (w >> 8)) & 0xAAu);
    if (!bits)
        return;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        if (!(bits & (2u << (2 * n))))
            continue;
        axis_t *x = &axes[n];
        if (x->mode == M_TEST)
            axis_disable(n);                      /* test mode: disable */
        else if (x->mode != M_DISABLE) {
            axis_set_mode(n, M_BRAKE);
            axis_select_mode(x, NO_MODE);
            motion_brake(n);                      /* from the next tick on */
        }
    }
    /* the card clears the bits it acted on, nothing else */
    uint16_t now = hal_rd16(DP_STOP_BITS);
    hal_wr16(DP_STOP_BITS, (uint16_t)(now & ~(bits | (uint16_t)(bits << 8))));
}

/* AX_IN switch bits (IESP, IESN, RS) -> user status bits */
static const uint32_t sw_ustat[8] = {
    0, UB(HWL_P), UB(HWL_N), UB(HWL_P) | UB(HWL_N), UB(REF), UB(REF) | UB(HWL_P),
    UB(REF) | UB(HWL_N), UB(REF) | UB(HWL_P) | UB(HWL_N),
};

FW_INLINE void axis_inputs(unsigned n)
{
    axis_t *x = &axes[n];
    PIN_PTR(x);
    uint16_t in = hal_rd16(AX_REG(n, AX_IN));
    /* nothing to do when no input changed, unless a drive fault is active
     * (it acts as soon as the axis runs) or INIT/E reconfigured the switches */
    if (in == x->in && !x->in_eval)
        return;
    x->in = in;
    axis_inputs_enc(x, in);                       /* SSI: J1's Gray code status, from basic init on */
    if (!(x->ustat & UB(INIT))) {                 /* axis_initialised, through x: one BTST */
        axis_inputs_evaluated(x, 0);              /* axis.h */
        return;                                   /* switches count after INIT (4.9) */
    }
    uint16_t active = (uint16_t)((in ^ x->sw_inv) & x->sw_en);
    axis_inputs_evaluated(x, (active & AX_IN_DF) != 0);   /* a drive fault: again next time */
    uint32_t sw = sw_ustat[active & 7u];
    uint32_t prev = x->ustat;
    x->ustat = (x->ustat & ~(UB(HWL_P) | UB(HWL_N) | UB(REF))) | sw;

    if ((active & AX_IN_DF) && x->mode != M_DISABLE && !(x->ustat & UB(DR_F))) {
        axis_error(n, UB(DR_F), ERR_LOGICAL);     /* 6.3.4 drive fault: ramp <ed>, disable */
        motion_drive_fault(n);
        vme_irq((uint8_t)PAR(n, IRQ3));
    }
    /* 5.13: a limit switch reached in test mode turns the axis off; it can
     * then be driven out of the switch in test mode again (edge, not level) */
    if (x->mode == M_TEST && (sw & ~prev & (UB(HWL_P) | UB(HWL_N))))
        axis_disable(n);
}

/* One axis' DPRAM data: inlined per axis with a constant n (absolute
 * addresses; from an address in a register GCC would add each word's
 * offset to it in a LEA of its own). */
FW_INLINE void publish_axis(unsigned n)
{
    const axis_t *x = &axes[n];
    uint32_t d = DP_AXIS_DATA(n);
    hal_wr32(d + DPA_USTAT, x->ustat);
    hal_wr32(d + DPA_SSTAT, x->sstat);
    hal_wr32(d + DPA_POS, (uint32_t)x->pos);
    /* in the frame of the position (with <ao>, 4.3.2), so that setpoint -
     * position is the following error for the host too */
    hal_wr32(d + DPA_SETPOINT, (uint32_t)pos_add(x->pos, x->ferr));
    hal_wr32(d + DPA_FERR, (uint32_t)x->ferr);
    /* ROUT: the DAC word, on the STP the step frequency in Hz */
    hal_wr32(d + DPA_OUT, card_rout(x, n));
    hal_wr32(d + DPA_VEL, (uint32_t)x->vel);
    hal_wr32(d + DPA_RAW, x->raw);
}

static void publish(unsigned n)
{
    switch (n) {
    case 0: publish_axis(0); break;
    case 1: publish_axis(1); break;
    case 2: publish_axis(2); break;
    default: publish_axis(3); break;
    }
}

static void leds(void)
{
    uint16_t l = 0;
    l = axis_leds(l, 0);
    l = axis_leds(l, 1);
    l = axis_leds(l, 2);
    l = axis_leds(l, 3);
    hal_wr16(SYS_LEDS, l);
}

/* tick_result: the card variant's (servo_card.h, stp_variant.h). */

/* One axis of card_supervise_tick(), inlined four times with a constant n
 * (absolute register addresses): what the tick did, the inputs, the
 * protective reactions; with interrupts masked, so that it sees one tick's
 * results, never half of the next. */
FW_INLINE void supervise_axis(unsigned n, unsigned ph)
{
    unsigned prev = hal_irq_save();
    axis_t *x = &axes[n];
    PIN_PTR(x);
    tick_result(x, ph);                           /* INC/SSI (the STP's tick keeps them itself) */
    if (x->mk_tick != MK_NONE)                    /* RAV: the tick keeps only meas */
        measure_vel_set(x, pos_sub(x->meas, x->meas_sup));
    if (x->mk_tick == MK_COUNTER)                 /* RED: the counter path keeps only the counter */
        measure_red_counter(x);
    axis_supervised_at(x, x->meas);               /* axis.h: the parts axis.c writes */
    axis_follow_init(x);
    axis_inputs(n);
    if (!motion_quiet(x))
        motion_supervise(n);
    hal_irq_restore(prev);
}

void card_supervise_tick(void)
{
    uint32_t t = *(volatile uint32_t *)&card_ticks;
    if (t == card_supervised)
        return;
    if (t - card_supervised > 1u)
        card_supervise_late++;
    card_supervised = t;
    uint16_t sys = hal_rd16(SYS_STATUS);
    card_ostat = (card_ostat & ~(uint32_t)(OB(FCODE0) | OB(FCODE1) | OB(FCODE2))) |
                 ((uint32_t)((sys >> SYS_ST_FC_SHIFT) & 7u) << OS_FCODE0);
    if (estop_seen) {                             /* 6.3.5: all axes, no ramp */
        estop_seen = 0;
        for (unsigned n = 0; n < MAC4_NAXES; n++)
            axis_disable(n);
    }
    unsigned phase = (t - 1u) & (PROFILE_DIVIDER - 1u);
    supervise_axis(0, phase);
    supervise_axis(1, phase);
    supervise_axis(2, phase);
    supervise_axis(3, phase);
    stop_bits();             /* after the reactions: a stop they began keeps its <ed> */
    ext_supervise();         /* the extensions' slices due (ext.h): one test while all are off */
    /* One axis' DPRAM data per tick: each is fresh every profile period
     * (10 ms / 32 ms), at a quarter of the cost. */
    unsigned prev = hal_irq_save();
    publish(phase);
    hal_irq_restore(prev);
    if (phase == 0)
        leds();
    hal_wr32(DPC_TICKS, t);
    hal_wr32(DPC_OSTAT, card_ostat);
    hal_wr32(DPC_PROFILE_LATE, card_profile_late);
    hal_wr32(DPC_SUPERVISE_LATE, card_supervise_late);
    /* the counters live in RAM: a host write to them lasts a tick at most */
    hal_wr32(DPC_VME_IRQ_LOST, virq_lost);
    cmd_publish();
    serial_publish(phase);
    vme_irq_service();
}

HAL_ISR void fw_isr_axis(void)
{
    /* The STP's creep phase counts its pulses here (stepper.c).  The index
     * latch is polled by the supervision (the searches); its interrupt is
     * never enabled, so an index request can only be a fault: it is
     * switched off, and the latch the search waits for is left alone. */
    uint16_t pending = hal_rd16(AXIS_IRQ_PENDING);
    card_isr_axis(pending);                      /* STP creep phase: step pulses, count done */
    if (!(pending & 0x000Fu))
        return;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (pending & (1u << n)) {
            axis_ctrl_set(&axes[n], (uint16_t)(axes[n].ctrl & ~AX_CTRL_IDX_IE));
            hal_wr16(AX_REG(n, AX_CTRL), axes[n].ctrl);
        }
}

void fw_isr_estop(void)
{
    /* The hardware has already opened every /EN (2.2.3).  Here only what
     * cannot wait: the report and the interrupt; the tick disables the
     * axes in firmware state. */
    estop_seen = 1;
    card_ostat |= OB(H_STOP);
    card_err_report = ERR_HSTOP;
    vme_irq((uint8_t)PAR(0, IRQ5));
}

void supervise_reset(void)
{
    estop_seen = 0;
    card_supervise_late = 0;
    card_supervised = 0;
}

