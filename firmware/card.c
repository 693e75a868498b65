/*
 * card.c - reset state, the periodic tick and the main loop.
 * Data flows one way through a tick: position measurement -> (axis state
 * machine, profile, servo filter: later issues) -> outputs.
 */
#include "fw.h"
#include "hal.h"
#include "card.h"
#include "cmd.h"

axis_t axes[4];
uint32_t card_ostat;
uint32_t card_ticks;

#if MAC4_CARD == MAC4_CARD_STP
#define TICK_US SERVO_PERIOD_US_STP
#else
#define TICK_US SERVO_PERIOD_US_SERVO
#endif

static void axis_outputs_reset(unsigned n)
{
    /* Tables 2.2, 2.6, 2.12: enable off (/EN open), DAC 0 V or no pulses,
     * DIR and BOOST open collector. */
    axes[n].ctrl = 0;
    axes[n].out = 0;
    hal_wr16(AX_REG(n, AX_CTRL), 0);
    hal_wr16(AX_REG(n, AX_DAC), 0);
}

void card_reset(void)
{
    hal_wr16(TMR_CTRL, 0);
    hal_wr16(UART_CTRL, 0);
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axis_outputs_reset(n);
        axes[n].ustat = 0;
        axes[n].sstat = 0;
        axes[n].pos = 0;
        axes[n].counter = 0;
    }
    hal_wr16(SYS_LEDS, 0x1111);   /* LED D on for every axis: all disabled */
    card_ostat = 0;
    card_ticks = 0;
    cmd_reset();
}

void card_start(void)
{
    hal_wr16(TMR_PERIOD, TICK_US);
    hal_wr16(TMR_CTRL, TMR_CTRL_RUN | TMR_CTRL_IE);
    hal_wr16(UART_CTRL, UART_CTRL_RXIE);
    hal_irq_enable_all();
}

static uint32_t read_counter(unsigned n)
{
    /* Reading the high word latches the low word (24-bit counter). */
    uint32_t hi = hal_rd16(AX_REG(n, AX_CNT_HI));
    uint32_t lo = hal_rd16(AX_REG(n, AX_CNT_LO));
    return (hi << 16) | lo;
}

void card_profile_tick(void)
{
    /* Profile generator: comes with the servo and stepper issues. */
}

void fw_isr_tick(void)
{
    hal_wr16(TMR_STATUS, TMR_ST_EXPIRED);
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        axes[n].counter = read_counter(n);
    card_ticks++;
    if ((card_ticks & (PROFILE_DIVIDER - 1u)) == 0)
        card_profile_tick();
    hal_wr32(DPC_TICKS, card_ticks);
}

void fw_isr_axis(void)
{
    /* Index and step-pulse interrupts: acknowledge by re-arming; used by the
     * justification modes and the STP creep phase (later issues). */
    uint16_t pending = hal_rd16(AXIS_IRQ_PENDING);
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (pending & (1u << n))
            hal_wr16(AX_REG(n, AX_CTRL), (uint16_t)(axes[n].ctrl | AX_CTRL_IDX_ARM));
}

void fw_isr_estop(void)
{
    /* Hardware has already opened every /EN (2.2.3); the firmware follows
     * with mode "disable" on all axes (6.3.5) in the command issue. */
    card_ostat |= 1u;
}

void fw_main_step(void)
{
    hal_wr16(WDG_KICK, 0);
    cmd_poll();
}

void fw_fault(uint16_t vector, uint32_t pc, uint16_t sr, uint32_t addr)
{
    hal_wr32(DPC_FAULT_VECTOR, vector);
    hal_wr32(DPC_FAULT_PC, pc);
    hal_wr32(DPC_FAULT_SR, sr);
    hal_wr32(DPC_FAULT_ADDR, addr);
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        hal_wr16(AX_REG(n, AX_CTRL), 0);   /* a crashed card drives nothing */
    fw_halt(0xF, DPC_ERR_EXCEPTION);
}
