/*
 * card.c - the card as a whole: its state, reset and start, the profile
 * generator's scheduling, the main loop, the display and the fault record.
 * The stages it runs are each a file: the timer interrupt (tick_servo.c,
 * or tick_stp.c on the STP), the supervision after each tick
 * (supervise.c), the axis state (axis.c), the VMEbus interrupter
 * (vme_irq.c), the commands (cmd.c) and the profile generator (motion.c).
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "axis.h"
#include "tick.h"
#include "cmd.h"
#include "params.h"
#include "serial.h"
#include "motion.h"
#include "ext.h"
#include "card_variant.h"

axis_t axes[MAC4_NAXES];
axis_t *const axis_at[MAC4_NAXES] = {&axes[0], &axes[1], &axes[2], &axes[3]};
_Static_assert(MAC4_NAXES == 4, "axis_at[] lists four axes");
uint32_t card_ostat;
uint16_t card_err_report;
uint32_t card_ticks;
uint8_t card_servo_general;

/* the controller period (7.4): CARD_TICK_US of card_variant.h */
#define TICK_US CARD_TICK_US

static void axis_outputs_reset(unsigned n)
{
    axis_output_off(&axes[n], n);                 /* tick.h: /EN open, 0 V or no pulses */
}

void card_reset(void)
{
    hal_wr16(TMR_CTRL, 0);
    hal_wr16(UART_CTRL, 0);
    params_reset();
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axis_outputs_reset(n);
        axis_t *x = &axes[n];
        *x = (axis_t){0};
        axis_select_mode(x, NO_MODE);
        axis_measure_off(x);
        x->ustat = UB(ON_FLY);                    /* on-fly after switch-on (5.15) */
        axis_set_mode(n, M_DISABLE);
        motion_hold(n);
        axis_reset_enc(x, n);                     /* SSI: J1's Gray code status from basic init on */
    }
    hal_wr16(SYS_LEDS, 0x1111);                   /* LED D on for every axis */
    card_ostat = 0;
    card_err_report = 0;
    card_ticks = 0;
    card_servo_general = 0;
    tick_select();                                /* the K-only tick in the timer's vector */
    card_profile_due = 0;
    card_profile_late = 0;
    supervise_reset();
    vme_irq_reset();
    cmd_reset();
    serial_reset();
    ext_reset();                                  /* the extensions off (docs/extensions.md) */
}

void card_start(void)
{
    hal_wr16(TMR_PERIOD, TICK_US);
    hal_wr16(TMR_CTRL, TMR_CTRL_RUN | TMR_CTRL_IE | ENC_TMR_CTRL);   /* SSI: the tick waits for the receiver */
    hal_wr16(UART_CTRL, UART_CTRL_RXIE);
    /* 7.1.2 m_rdy "command operational": the card takes commands for every
     * axis from here (display $5) until a reset; MR clears it (cmd.c) */
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        axes[n].sstat |= SB(M_RDY);
    hal_irq_enable_all();
}

volatile uint8_t card_profile_due;
uint16_t card_profile_late;

/* The profile generator runs in the main loop, one SP ahead of the servo
 * ticks that interpolate its segments: the tick stays short, and the
 * profile has a whole SP to finish (7.4).  One axis per main-loop pass
 * (card_profile_due: how many axes are still to do), so a command waits for
 * one axis' step at most, not four; each with interrupts masked, so a tick
 * never sees half a segment or half a mode change. */
void card_profile_tick(void)
{
    unsigned prev = hal_irq_save();
    uint8_t due = card_profile_due;
    /* a tick since the last supervision is supervised first (the next pass
     * does it): the profile generator never acts on a tick's result before
     * the reactions to it have */
    if (due && !card_supervise_due()) {
        /* axes in turn: due counts down 4, 3, 2, 1 */
        card_profile_due = (uint8_t)(due - 1u);
        motion_profile_tick(MAC4_NAXES - due);
    }
    hal_irq_restore(prev);
}

/* ---- main loop ----------------------------------------------------------- */
static uint16_t shown = 0xFFFF;

static void display_update(void)
{
    /* Table 2.16: the most serious condition wins. */
    uint16_t d = 5;
    uint32_t all = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        all |= axes[n].ustat;
    if (all & UB(INIT))                           /* any axis initialised */
        d = 0;
    if (all & UB(SYN_F))
        d = 9;
    if (all & UB(LIMIT_F))
        d = 7;
    if (all & UB(LOGO_F))
        d = 8;
    if (all & UB(ENCODER_F))
        d = 0xC;
    if (card_ostat & OB(WATCH_F))
        d = 0xD;
    if (card_ostat & OB(H_STOP))
        d = 0xE;
    if (d != shown) {
        shown = d;
        hal_wr16(SYS_DISPLAY, d);
        hal_wr32(DPC_BOOT_STATE, d);
    }
}

void fw_main_step(void)
{
    card_supervise();
    if (!cmd_mr_pending())
        hal_wr16(WDG_KICK, 0);
    if (card_profile_due) {
        card_supervise();   /* the SP boundary's tick first, wherever the tick hit the pass */
        card_profile_tick();
    }
    ext_work();              /* one slice of the extensions' work, if due (ext.h) */
    cmd_poll();
    vme_irq_service();
    display_update();
}

void fw_fault(uint16_t vector, uint32_t pc, uint16_t sr, uint32_t addr)
{
    hal_wr32(DPC_FAULT_VECTOR, vector);
    hal_wr32(DPC_FAULT_PC, pc);
    hal_wr32(DPC_FAULT_SR, sr);
    hal_wr32(DPC_FAULT_ADDR, addr);
    hal_wr32(DPC_FAULT_COUNT, hal_rd32(DPC_FAULT_COUNT) + 1);   /* in the DPRAM: the reset tests the RAM */
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        hal_wr16(AX_REG(n, AX_CTRL), 0);   /* a crashed card drives nothing */
    fw_halt_for_watchdog(0xF, DPC_ERR_EXCEPTION);   /* J11 in: restart (2.1.3) */
}
