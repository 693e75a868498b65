/*
 * axisboard.c - the axis interface board of the MAC4-INC/SSI/STP (registers
 * in hal/mac4_map.h, "Axis board"): position counters with index latch, SSI
 * receivers, DAC or step-rate outputs with the step generator and its pulse
 * down-counter, switch inputs.  The motors, encoders and switches behind the
 * board are in plant.c; the VME master window's slave boards in plant_vme.c.
 * Every access brings the plant up to the cycle it happens (sim_now).  A
 * device of periph.c's table; the timer's expiry reaches it as a signal.
 */
#include "sim.h"
#include "periph.h"
#include "plant.h"

/* ---- axis interface board ------------------------------------------------ */
static uint32_t axis_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    int n = (int)(off / AXIS_STRIDE);
    axis_hw_t *a = &s->ax[n];
    cyc_t now = sim_axis_now(s);   /* sim_now(s) unless axis_sync (sim.h) */
    switch (off % AXIS_STRIDE) {
    case AX_CNT_HI: {
        uint32_t c = plant_counter(s, n, now);
        a->cnt_lo_latch = (uint16_t)c;
        return (c >> 16) & 0xFF;
    }
    case AX_CNT_LO: return a->cnt_lo_latch;
    case AX_CNT_LIVE: return plant_counter(s, n, now) & 0xFFFF;
    case AX_IDX_HI:
        plant_sync(s, n, now);
        a->idx_lo_latch = (uint16_t)a->idx_latch;
        return (a->idx_latch >> 16) & 0xFF;
    case AX_IDX_LO: return a->idx_lo_latch;
    case AX_IN:
        return (uint32_t)(plant_inputs_word(s, n, now) | a->in | (a->idx_latched ? AX_IN_IDX : 0) |
                          (a->gray ? AX_IN_GRAY : 0) | (plant_ssi_busy(s, n, now) ? AX_IN_SSI_BUSY : 0) |
                          a->pstat);
    case AX_CTRL: return a->ctrl;
    case AX_SSI_HI: return (plant_ssi_reg(s, n, now) >> 16) & 0x3FF;
    case AX_SSI_LO: return plant_ssi_reg(s, n, now) & 0xFFFF;
    case AX_PULSES:
        plant_sync(s, n, now);
        return s->plant.ax[n].remaining & 0xFFFF;
    }
    sim_fault(s, "read of undefined axis register +$%X", (unsigned)(off % AXIS_STRIDE));
    return 0xFFFF;
}

#define AX_CTRL_W_ONLY (AX_CTRL_IDX_ARM | AX_CTRL_CNT_CLR | AX_CTRL_PULSE_ACK | AX_CTRL_DONE_ACK)

static void axis_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    int n = (int)(off / AXIS_STRIDE);
    axis_hw_t *a = &s->ax[n];
    cyc_t now = sim_axis_now(s);   /* sim_now(s) unless axis_sync (sim.h) */
    switch (off % AXIS_STRIDE) {
    case AX_CTRL:
        plant_sync(s, n, now);
        if (v & AX_CTRL_CNT_CLR)
            plant_counter_set(s, n, now, 0);
        if (v & AX_CTRL_PULSE_ACK)
            a->pstat &= (uint16_t)~(AX_IN_PULSE | AX_IN_PULSE_OVR);
        if (v & AX_CTRL_DONE_ACK)
            a->pstat &= (uint16_t)~AX_IN_PDONE;
        a->ctrl = (uint16_t)(v & ~(uint32_t)AX_CTRL_W_ONLY);
        if (v & AX_CTRL_IDX_ARM)
            plant_idx_arm(s, n, now);
        plant_inputs(s, n, now);
        return;
    case AX_DAC:   /* AX_RATE on the STP board */
        plant_sync(s, n, now);
        if (s->card == MAC4_CARD_STP)
            a->rate = (uint16_t)v;
        else   /* 12-bit two's complement converter: the upper bits are not wired */
            a->dac = (int16_t)((int16_t)(uint16_t)(v << 4) >> 4);
        plant_inputs(s, n, now);
        return;
    case AX_SSI_START:
        plant_ssi_start(s, n, now);
        return;
    case AX_PULSES:
        plant_pulses_write(s, n, now, (uint16_t)v);
        return;
    }
    sim_fault(s, "write to undefined axis register +$%X", (unsigned)(off % AXIS_STRIDE));
}

static uint32_t axis_irq_rd(sim_t *s, uint32_t off, int size)
{
    (void)off;
    (void)size;
    uint32_t p = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        const axis_hw_t *a = &s->ax[n];
        if (a->idx_latched && (a->ctrl & AX_CTRL_IDX_IE))
            p |= AXIS_IRQ_IDX(n);
        if ((a->pstat & AX_IN_PULSE) && (a->ctrl & AX_CTRL_PULSE_IE))
            p |= AXIS_IRQ_PULSE(n);
        if ((a->pstat & AX_IN_PDONE) && (a->ctrl & AX_CTRL_DONE_IE))
            p |= AXIS_IRQ_DONE(n);
    }
    return p;
}

static void axis_irq_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)off;
    (void)v;
    (void)size;
    sim_fault(s, "write to the read-only axis interrupt register");
}

const axis_led_t axis_leds[AXIS_NLEDS] = {
    {"D", SYS_LED_D, 0}, {"P", SYS_LED_P, 0}, {"F", SYS_LED_F, 0},
    {"LP", 0, AX_IN_IESP}, {"LN", 0, AX_IN_IESN}, {"REF", 0, AX_IN_RS},
};

unsigned axisboard_leds(sim_t *s, int n)
{
    uint16_t reg = (uint16_t)(s->sys.leds >> SYS_LED_SHIFT(n));
    uint16_t in = plant_inputs_word(s, n, sim_now(s));
    unsigned lit = 0;
    for (unsigned i = 0; i < AXIS_NLEDS; i++)
        if ((reg & axis_leds[i].reg) || (in & axis_leds[i].in))
            lit |= 1u << i;
    return lit;
}

/* Reset (tables 2.2, 2.6, 2.12): /EN open, DAC 0 V, rate 0, DIR and BOOST
 * open collector, counters, latches, SSI receivers and pulse logic cleared.
 * The plant itself is not reset: the motors coast. */
static void axisboard_reset(sim_t *s) { plant_reset(s); }

/* With axis_sync the plant lives on the axis clock: it is brought up to date
 * at every access and every scheduler event, never scheduled in real time. */
static cyc_t axisboard_next_event(sim_t *s) { return s->axis_sync ? CYC_NEVER : plant_next_event(s); }

static void axisboard_events(sim_t *s, cyc_t now) { plant_events(s, s->axis_sync ? sim_axis_peek(s) : now); }

static unsigned axisboard_irq_lines(sim_t *s) { return axis_irq_rd(s, 0, 2) ? 1u << IRQ_LEVEL_AXIS : 0; }

/* The timer expired at `at`: the SSI receivers set to AX_CTRL_SSI_SYNC
 * freeze their encoders and start reading (on the axis clock of the
 * differential test, at the axis clock's time); each tells the timer how
 * long it reads. */
static void axisboard_tmr_expired(sim_t *s, uint64_t at)
{
    for (int n = 0; n < MAC4_NAXES; n++)
        if (s->card == MAC4_CARD_SSI && (s->ax[n].ctrl & AX_CTRL_SSI_SYNC)) {
            plant_ssi_start(s, n, s->axis_sync ? sim_axis_peek(s) : at);
            sig_raise(s, SIG_SSI_BUSY, s->plant.ax[n].ssi_end);
        }
}

void axisboard_connect(sim_t *s) { sig_connect(s, SIG_TMR_EXPIRED, axisboard_tmr_expired); }

/* window 0: the four boards' registers (AX_REG), window 1: AXIS_IRQ_PENDING */
const device_t axisboard_device = {.name = "axis", .win = {{axis_rd, axis_wr}, {axis_irq_rd, axis_irq_wr}},
                                   .reset = axisboard_reset, .next_event = axisboard_next_event,
                                   .events = axisboard_events, .irq_lines = axisboard_irq_lines};
