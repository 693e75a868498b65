/*
 * sysctl.c - the IPC's system control (display, LEDs, boot overlay, status
 * inputs, board ID), its hardware watchdog and the /STOP input: three devices
 * of periph.c's table.
 */
#include "sim.h"
#include "periph.h"
#include "buswait.h"

/* ---- system control ------------------------------------------------------ */
static void display_show(sim_t *s, uint16_t v)
{
    v &= 0x1F;
    if (v == s->sys.display)
        return;
    s->sys.display = v;
    buswait_mark(sim_now(s));      /* `bus-stats display`: the counts at this write */
    sim_printf(s, "display %X%s\n", v & 0xF, (v & SYS_DISPLAY_DP) ? "." : "");
    if (s->on_display)
        s->on_display(s);
}

static uint32_t sys_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    switch (off) {
    case 0x0: return s->sys.display;
    case 0x2: return s->sys.leds;
    case 0x4: return s->sysctl;
    case 0x6:
        return (uint32_t)((s->sys.estop ? SYS_ST_STOP : 0) | ((s->sys.fc & 7u) << SYS_ST_FC_SHIFT) |
                          (s->wdg.j11 ? SYS_ST_J11 : 0) | (s->in_reset_by_wdg ? SYS_ST_WDG_RESET : 0) |
                          ((unsigned)(s->vme.level & 7u) << SYS_ST_LEVEL_SHIFT));
    case 0x8: return (uint32_t)s->card;
    }
    sim_fault(s, "read of undefined system register +$%X", (unsigned)off);
    return 0xFFFF;
}

static void sys_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    switch (off) {
    case 0x0: display_show(s, (uint16_t)v); return;
    case 0x2: s->sys.leds = (uint16_t)v; return;
    case 0x4: s->sysctl = (uint16_t)(v & SYS_CTRL_OVERLAY); return;
    }
    sim_fault(s, "write to read-only or undefined system register +$%X", (unsigned)off);
}

/* ---- hardware watchdog --------------------------------------------------- */
static uint32_t wdg_rd(sim_t *s, uint32_t off, int size)
{
    (void)off;
    (void)size;
    sim_fault(s, "read of the write-only watchdog register");
    return 0xFFFF;
}

static void wdg_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)off;
    (void)v;
    (void)size;
    s->wdg.deadline = sim_now(s) + US_TO_CYC(WDG_TIMEOUT_US);
}

/* ---- emergency stop ------------------------------------------------------ */
void estop_set(sim_t *s, int active)
{
    if (active && !s->sys.estop)
        s->sys.estop_edge = 1;
    s->sys.estop = active;
    sig_raise(s, SIG_STOP, (uint64_t)(active != 0));   /* the line to the axis boards */
}
int estop_irq_pending(sim_t *s) { return s->sys.estop_edge; }
void estop_irq_ack(sim_t *s) { s->sys.estop_edge = 0; }

/* ---- the devices ---------------------------------------------------------- */
static void sys_reset(sim_t *s)
{
    s->sys.display = 0xFF;     /* blank until the firmware writes */
    s->sys.leds = 0;
    s->sysctl = SYS_CTRL_OVERLAY;
}

static void wdg_reset(sim_t *s)
{
    s->wdg.deadline = sim_now(s) + US_TO_CYC(WDG_TIMEOUT_US);
    s->wdg.reset_pending = 0;
}

static cyc_t wdg_next_event(sim_t *s) { return s->wdg.j11 ? s->wdg.deadline : CYC_NEVER; }

static void wdg_event(sim_t *s, cyc_t now)
{
    if (s->wdg.j11 && s->wdg.deadline <= now)
        s->wdg.reset_pending = 1;
}

static void estop_reset(sim_t *s) { s->sys.estop_edge = s->sys.estop; }   /* an active /STOP at reset is seen at once */

static unsigned estop_irq_lines(sim_t *s) { return s->sys.estop_edge ? 1u << IRQ_LEVEL_ESTOP : 0; }

const device_t sys_device = {.name = "sys", .win = {{sys_rd, sys_wr}}, .reset = sys_reset};
const device_t wdg_device = {.name = "watchdog", .win = {{wdg_rd, wdg_wr}}, .reset = wdg_reset,
                             .next_event = wdg_next_event, .events = wdg_event};
const device_t estop_device = {.name = "estop", .reset = estop_reset, .irq_lines = estop_irq_lines};
