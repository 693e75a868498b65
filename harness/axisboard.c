/*
 * axisboard.c - the axis interface board of the MAC4-INC/SSI/STP (registers
 * in hal/mac4_map.h, "Axis board"): position counters with index latch, SSI
 * receivers, DAC or step-rate outputs, switch inputs; and the VME master
 * window towards external boards.  Plant models attach here.
 */
#include "sim.h"
#include "periph.h"

/* ---- axis interface board ------------------------------------------------ */
uint32_t axis_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    axis_hw_t *a = &s->ax[off / AXIS_STRIDE];
    switch (off % AXIS_STRIDE) {
    case AX_CNT_HI: a->cnt_lo_latch = (uint16_t)a->counter; return (a->counter >> 16) & 0xFF;
    case AX_CNT_LO: return a->cnt_lo_latch;
    case AX_IDX_HI: a->idx_lo_latch = (uint16_t)a->idx_latch; return (a->idx_latch >> 16) & 0xFF;
    case AX_IDX_LO: return a->idx_lo_latch;
    case AX_IN:
        return (uint32_t)(a->in | (a->idx_latched ? AX_IN_IDX : 0) | (a->gray ? AX_IN_GRAY : 0));
    case AX_CTRL: return a->ctrl;
    case AX_SSI_HI: return (a->ssi >> 16) & 0x3FF;
    case AX_SSI_LO: return a->ssi & 0xFFFF;
    }
    sim_fault(s, "read of undefined axis register +$%X", (unsigned)(off % AXIS_STRIDE));
    return 0xFFFF;
}

void axis_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    axis_hw_t *a = &s->ax[off / AXIS_STRIDE];
    switch (off % AXIS_STRIDE) {
    case AX_CTRL:
        if (v & AX_CTRL_IDX_ARM)
            a->idx_latched = 0;
        if (v & AX_CTRL_CNT_CLR)
            a->counter = 0;
        a->ctrl = (uint16_t)(v & ~(uint32_t)(AX_CTRL_IDX_ARM | AX_CTRL_CNT_CLR));
        return;
    case AX_DAC:   /* AX_RATE on the STP board */
        if (s->card == MAC4_CARD_STP)
            a->rate = (uint16_t)v;
        else   /* 12-bit two's complement converter: the upper bits are not wired */
            a->dac = (int16_t)((int16_t)(uint16_t)(v << 4) >> 4);
        return;
    case AX_SSI_START: return;
    }
    sim_fault(s, "write to undefined axis register +$%X", (unsigned)(off % AXIS_STRIDE));
}

uint32_t axis_irq_rd(sim_t *s, uint32_t off, int size)
{
    (void)off;
    (void)size;
    uint32_t p = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++)
        if (s->ax[n].idx_latched && (s->ax[n].ctrl & AX_CTRL_IDX_IE))
            p |= 1u << n;
    return p;
}

void axis_irq_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)off;
    (void)v;
    (void)size;
    sim_fault(s, "write to the read-only axis interrupt register");
}

void axisboard_reset(sim_t *s)
{
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        axis_hw_t *a = &s->ax[n];
        a->ctrl = 0;        /* /EN open, DIR/BOOST open collector (tables 2.2, 2.6, 2.12) */
        a->dac = 0;         /* 0 V */
        a->rate = 0;
        a->idx_latched = 0;
    }
}

cyc_t axisboard_next_event(sim_t *s)
{
    (void)s;
    return CYC_NEVER;
}

void axisboard_events(sim_t *s, cyc_t now)
{
    (void)s;
    (void)now;
}

/* ---- VMEbus master window ------------------------------------------------ */
/* No VME slave boards are modelled yet: every access times out, which the
 * bus timer of the IPC turns into $FFFF and the BERR flag. */
uint32_t vme_win_rd(sim_t *s, uint32_t off, int size)
{
    (void)off;
    s->vme.berr = 1;
    return size == 1 ? 0xFF : 0xFFFF;
}

void vme_win_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)off;
    (void)v;
    (void)size;
    s->vme.berr = 1;
}

