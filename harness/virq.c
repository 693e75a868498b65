/*
 * virq.c - the IPC's VMEbus interrupter and the master window's page
 * register with its bus cycles: a device of periph.c's table (the window's
 * slave boards are in plant_vme.c).
 */
#include "sim.h"
#include "periph.h"

/* ---- VMEbus interrupter and master window -------------------------------- */
static uint32_t virq_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    switch (off) {
    case 0x2: return (uint32_t)(s->vme.pending ? VIRQ_ST_PENDING : 0) | ((uint32_t)s->vme.level << 8);
    case 0x4: return s->vme.page;
    case 0x6: {
        uint32_t st = s->vme.berr ? VME_ST_BERR : 0;
        s->vme.berr = 0;
        return st;
    }
    }
    sim_fault(s, "read of undefined VME register +$%X", (unsigned)off);
    return 0xFFFF;
}

static void virq_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    switch (off) {
    case 0x0:
        if (s->vme.pending) {
            sim_fault(s, "VME interrupt vector $%02X written while one is pending", (unsigned)(v & 0xFF));
            return;
        }
        s->vme.pending = 1;
        s->vme.vector = (uint8_t)v;
        s->vme.iack_at = sim_now(s) + US_TO_CYC(2);   /* the host's IACK cycle */
        return;
    case 0x4: s->vme.page = (uint16_t)(v & 0xF); return;
    }
    sim_fault(s, "write to undefined VME register +$%X", (unsigned)off);
}

/* The master window, local $E00000-$EFFFFF: VME_PAGE supplies A23-A20.
 * Where no slave board answers (plant_vme.c), the bus timer ends the cycle:
 * reads return $FFFF and VME_STATUS.BERR is set. */
static uint32_t vme_win_rd(sim_t *s, uint32_t off, int size)
{
    uint32_t addr = ((uint32_t)(s->vme.page & 0xF) << 20) | (off & 0xFFFFF), w;
    if (!plant_vme_rd16(s, addr, &w)) {
        s->vme.berr = 1;
        return size == 1 ? 0xFF : 0xFFFF;
    }
    if (size == 1)
        return (addr & 1) ? (w & 0xFF) : (w >> 8);
    return w;
}

static void vme_win_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)v;
    (void)size;
    uint32_t addr = ((uint32_t)(s->vme.page & 0xF) << 20) | (off & 0xFFFFF);
    if (!plant_vme_wr16(s, addr))
        s->vme.berr = 1;
}

static void vme_reset(sim_t *s)
{
    s->vme.pending = 0;
    s->vme.page = 0;
    s->vme.berr = 0;
}

static cyc_t vme_next_event(sim_t *s) { return s->vme.pending ? s->vme.iack_at : CYC_NEVER; }

static void vme_event(sim_t *s, cyc_t now)
{
    if (s->vme.pending && s->vme.iack_at <= now) {
        s->vme.pending = 0;
        s->vme_irqs++;
        sim_printf(s, "vme-irq %u %u\n", s->vme.level, s->vme.vector);
    }
}

/* window 0: the interrupter's registers, window 1: the master window */
const device_t vme_device = {.name = "virq", .win = {{virq_rd, virq_wr}, {vme_win_rd, vme_win_wr}},
                             .reset = vme_reset, .next_event = vme_next_event, .events = vme_event};
