/*
 * periph.c - the IPC's peripherals, each a small model with the register
 * interface of mac4_map.h and its timing driven by the CPU cycle count, and
 * the table of devices (below) through which the scheduler resets them,
 * asks for their next event, runs their events and reads their interrupt
 * request lines.  The axis interface board is a device of its own
 * (axisboard.c); what a wire carries from one device to another is a named
 * signal (sim.h, SIG_*), wired in periph_connect().
 */
#include <string.h>
#include "sim.h"
#include "periph.h"
#include "buswait.h"

static int estop_edge;   /* /STOP is wired to the edge-triggered level 7 (NMI) */

/* ---- system control ------------------------------------------------------ */
static void display_show(sim_t *s, uint16_t v)
{
    v &= 0x1F;
    if (v == s->display)
        return;
    s->display = v;
    buswait_mark(sim_now(s));      /* `bus-stats display`: the counts at this write */
    sim_printf(s, "display %X%s\n", v & 0xF, (v & SYS_DISPLAY_DP) ? "." : "");
    if (s->on_display)
        s->on_display(s);
}

uint32_t sys_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    switch (off) {
    case 0x0: return s->display;
    case 0x2: return s->leds;
    case 0x4: return s->sysctl;
    case 0x6:
        return (uint32_t)((s->estop ? SYS_ST_STOP : 0) | ((s->fc & 7u) << SYS_ST_FC_SHIFT) |
                          (s->wdg.j11 ? SYS_ST_J11 : 0) | (s->in_reset_by_wdg ? SYS_ST_WDG_RESET : 0) |
                          ((unsigned)(s->vme.level & 7u) << SYS_ST_LEVEL_SHIFT));
    case 0x8: return (uint32_t)s->card;
    }
    sim_fault(s, "read of undefined system register +$%X", (unsigned)off);
    return 0xFFFF;
}

void sys_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    switch (off) {
    case 0x0: display_show(s, (uint16_t)v); return;
    case 0x2: s->leds = (uint16_t)v; return;
    case 0x4: s->sysctl = (uint16_t)(v & SYS_CTRL_OVERLAY); return;
    }
    sim_fault(s, "write to read-only or undefined system register +$%X", (unsigned)off);
}

/* ---- periodic timer ------------------------------------------------------ */
uint32_t tmr_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    cyc_t now = sim_now(s);
    switch (off) {
    case 0x0: return s->tmr.period_us;
    case 0x2: return s->tmr.ctrl;
    case 0x4: return s->tmr.status;
    case 0x6: return (uint32_t)((now - s->tmr.last) / MAC4_CYCLES_PER_US) & 0xFFFF;
    case 0x8: {
        uint32_t us = (uint32_t)(now / MAC4_CYCLES_PER_US);
        s->free_lo_latch = (uint16_t)us;
        return us >> 16;
    }
    case 0xA: return s->free_lo_latch;
    }
    sim_fault(s, "read of undefined timer register +$%X", (unsigned)off);
    return 0xFFFF;
}

void tmr_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    cyc_t now = sim_now(s);
    switch (off) {
    case 0x0: s->tmr.period_us = (uint16_t)v; return;
    case 0x2: {
        int was = s->tmr.ctrl & TMR_CTRL_RUN;
        s->tmr.ctrl = (uint16_t)v;
        if (!(v & TMR_CTRL_RUN))
            s->tmr.next = CYC_NEVER;
        else if (!was && s->tmr.period_us) {
            s->tmr.last = now;
            s->tmr.next = now + US_TO_CYC(s->tmr.period_us);
        }
        return;
    }
    case 0x4: s->tmr.status &= (uint16_t)~v; return;   /* write 1 to acknowledge */
    }
    sim_fault(s, "write to undefined timer register +$%X", (unsigned)off);
}

static void tmr_event(sim_t *s, cyc_t now)
{
    while (s->tmr.next <= now) {
        if (s->tmr.status & TMR_ST_EXPIRED)
            sim_printf(s, "timer-overrun: tick %llu not acknowledged in time\n",
                       (unsigned long long)(s->tmr.next / MAC4_CYCLES_PER_US));
        s->tmr.status |= TMR_ST_EXPIRED;
        s->tmr.last = s->tmr.next;
        /* the expiry line to the axis board: the SSI receivers set to
         * AX_CTRL_SSI_SYNC freeze their encoders now, and each says how long
         * it reads (SIG_SSI_BUSY, tmr_ssi_busy) */
        s->tmr.irq_at = s->tmr.last;
        sig_raise(s, SIG_TMR_EXPIRED, s->tmr.last);
        s->tmr.next += US_TO_CYC(s->tmr.period_us ? s->tmr.period_us : 1);
    }
}

/* An SSI receiver reads until `end`: with TMR_CTRL_SSI_WAIT the interrupt
 * waits for the last of them (on the axis clock of the differential test it
 * does not wait). */
static void tmr_ssi_busy(sim_t *s, uint64_t end)
{
    if ((s->tmr.ctrl & TMR_CTRL_SSI_WAIT) && !s->axis_sync && end > s->tmr.irq_at)
        s->tmr.irq_at = end;
}

/* ---- UART, 4800 baud 8N1 ------------------------------------------------- */
void uart_feed(sim_t *s, const uint8_t *bytes, unsigned n)
{
    uart_t *u = &s->uart;
    for (unsigned i = 0; i < n; i++) {
        unsigned next = (u->wire_head + 1) % UART_WIRE_SIZE;
        if (next == u->wire_tail) {
            sim_printf(s, "error serial input buffer of the emulator full\n");
            return;
        }
        u->wire[u->wire_head] = bytes[i];
        u->wire_head = next;
    }
    if (u->rx_done == CYC_NEVER && u->wire_head != u->wire_tail)
        u->rx_done = sim_now(s) + UART_CHAR_CYC;
}

uint32_t uart_rd(sim_t *s, uint32_t off, int size)
{
    (void)size;
    uart_t *u = &s->uart;
    switch (off) {
    case 0x0: u->rx_full = 0; return u->rx_hold;
    case 0x2: {
        uint32_t st = (u->rx_full ? UART_ST_RXRDY : 0) | (u->tx_busy ? 0 : UART_ST_TXEMPTY) |
                      (u->overrun ? UART_ST_OVERRUN : 0) | (u->framing ? UART_ST_FRAMING : 0);
        u->overrun = u->framing = 0;
        return st;
    }
    case 0x4: return u->ctrl;
    }
    sim_fault(s, "read of undefined UART register +$%X", (unsigned)off);
    return 0xFFFF;
}

void uart_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)size;
    uart_t *u = &s->uart;
    switch (off) {
    case 0x0:
        if (u->tx_busy) {
            sim_fault(s, "UART transmit while busy: byte $%02X lost", (unsigned)(v & 0xFF));
            return;
        }
        u->tx_busy = 1;
        u->tx_shift = (uint8_t)v;
        u->tx_done = sim_now(s) + UART_CHAR_CYC;
        return;
    case 0x4: u->ctrl = (uint16_t)v; return;
    }
    sim_fault(s, "write to undefined UART register +$%X", (unsigned)off);
}

static void uart_event(sim_t *s, cyc_t now)
{
    uart_t *u = &s->uart;
    while (u->rx_done <= now) {
        uint8_t b = u->wire[u->wire_tail];
        u->wire_tail = (u->wire_tail + 1) % UART_WIRE_SIZE;
        if (u->rx_full)
            u->overrun = 1;          /* the new character is lost, as on a real UART */
        else {
            u->rx_hold = b;
            u->rx_full = 1;
        }
        u->rx_done = (u->wire_head != u->wire_tail) ? u->rx_done + UART_CHAR_CYC : CYC_NEVER;
    }
    if (u->tx_busy && u->tx_done <= now) {
        u->tx_busy = 0;
        u->tx_done = CYC_NEVER;
        if (u->on_tx)
            u->on_tx(u->tx_ctx, u->tx_shift);
    }
}

/* ---- VMEbus interrupter and master window -------------------------------- */
uint32_t virq_rd(sim_t *s, uint32_t off, int size)
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

void virq_wr(sim_t *s, uint32_t off, uint32_t v, int size)
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

/* ---- hardware watchdog --------------------------------------------------- */
uint32_t wdg_rd(sim_t *s, uint32_t off, int size)
{
    (void)off;
    (void)size;
    sim_fault(s, "read of the write-only watchdog register");
    return 0xFFFF;
}

void wdg_wr(sim_t *s, uint32_t off, uint32_t v, int size)
{
    (void)off;
    (void)v;
    (void)size;
    s->wdg.deadline = sim_now(s) + US_TO_CYC(WDG_TIMEOUT_US);
}

/* ---- emergency stop ------------------------------------------------------ */
void estop_set(sim_t *s, int active)
{
    if (active && !s->estop)
        estop_edge = 1;
    s->estop = active;
}
int estop_irq_pending(sim_t *s) { (void)s; return estop_edge; }
void estop_irq_ack(sim_t *s) { (void)s; estop_edge = 0; }

/* ---- the devices ---------------------------------------------------------- */
static void sys_reset(sim_t *s)
{
    s->display = 0xFF;     /* blank until the firmware writes */
    s->leds = 0;
    s->sysctl = SYS_CTRL_OVERLAY;
}

static void tmr_reset(sim_t *s)
{
    memset(&s->tmr, 0, sizeof s->tmr);
    s->tmr.next = CYC_NEVER;
}

static cyc_t tmr_next_event(sim_t *s)
{
    cyc_t t = s->tmr.next;
    if ((s->tmr.status & TMR_ST_EXPIRED) && s->tmr.irq_at > s->tmr.last && s->tmr.irq_at > sim_now(s) &&
        s->tmr.irq_at < t)
        t = s->tmr.irq_at;                      /* the delayed request (TMR_CTRL_SSI_WAIT) */
    return t;
}

static unsigned tmr_irq_lines(sim_t *s)
{
    return (s->tmr.status & TMR_ST_EXPIRED) && (s->tmr.ctrl & TMR_CTRL_IE) &&
           (s->tmr.irq_at <= s->tmr.last || sim_now(s) >= s->tmr.irq_at)   /* TMR_CTRL_SSI_WAIT */
           ? 1u << IRQ_LEVEL_TIMER : 0;
}

static void uart_reset(sim_t *s)
{
    uart_t *u = &s->uart;
    u->ctrl = 0;
    u->rx_full = u->overrun = u->framing = 0;
    u->tx_busy = 0;
    u->tx_done = CYC_NEVER;
    u->rx_done = (u->wire_head != u->wire_tail) ? sim_now(s) + UART_CHAR_CYC : CYC_NEVER;
}

static cyc_t uart_next_event(sim_t *s) { return s->uart.rx_done < s->uart.tx_done ? s->uart.rx_done : s->uart.tx_done; }

static unsigned uart_irq_lines(sim_t *s)
{
    if ((s->uart.ctrl & UART_CTRL_RXIE) && (s->uart.rx_full || s->uart.overrun))
        return 1u << IRQ_LEVEL_UART;
    if ((s->uart.ctrl & UART_CTRL_TXIE) && !s->uart.tx_busy)
        return 1u << IRQ_LEVEL_UART;
    return 0;
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

static void estop_reset(sim_t *s) { estop_edge = s->estop; }   /* an active /STOP at reset is seen at once */

static unsigned estop_irq_lines(sim_t *s) { (void)s; return estop_edge ? 1u << IRQ_LEVEL_ESTOP : 0; }

static const device_t sys_device = {"sys", sys_reset, NULL, NULL, NULL};
static const device_t tmr_device = {"timer", tmr_reset, tmr_next_event, tmr_event, tmr_irq_lines};
static const device_t uart_device = {"uart", uart_reset, uart_next_event, uart_event, uart_irq_lines};
static const device_t vme_device = {"virq", vme_reset, vme_next_event, vme_event, NULL};
static const device_t wdg_device = {"watchdog", wdg_reset, wdg_next_event, wdg_event, NULL};
static const device_t estop_device = {"estop", estop_reset, NULL, NULL, estop_irq_lines};

/* The card's devices, in the order of their reset and of their events. */
static const device_t *const devices[] = {
    &sys_device, &tmr_device, &uart_device, &vme_device, &wdg_device, &estop_device, &axisboard_device,
};
#define NDEVICES (sizeof devices / sizeof devices[0])

/* ---- the signals between them ---------------------------------------------- */
void sig_connect(sim_t *s, int sig, sim_sig_hook_t hook)
{
    sim_sig_t *g = &s->sig[sig];
    if (g->n < SIM_SIG_HOOKS)
        g->hook[g->n++] = hook;
}

void sig_raise(sim_t *s, int sig, uint64_t value)
{
    const sim_sig_t *g = &s->sig[sig];
    for (unsigned i = 0; i < g->n; i++)
        g->hook[i](s, value);
}

void periph_connect(sim_t *s)
{
    static const char *const names[SIG_COUNT] = {"timer.expired", "axis.ssi_busy"};
    for (int i = 0; i < SIG_COUNT; i++) {
        s->sig[i].name = names[i];
        s->sig[i].n = 0;
    }
    axisboard_connect(s);                       /* timer.expired -> the SSI receivers */
    sig_connect(s, SIG_SSI_BUSY, tmr_ssi_busy);
}

/* ---- all devices ------------------------------------------------------------ */
void periph_reset(sim_t *s)
{
    for (unsigned i = 0; i < NDEVICES; i++)
        devices[i]->reset(s);
}

/* Every request line (the waveform shows them one by one, vcd.c). */
unsigned sim_irq_lines(sim_t *s)
{
    unsigned l = 0;
    for (unsigned i = 0; i < NDEVICES; i++)
        if (devices[i]->irq_lines)
            l |= devices[i]->irq_lines(s);
    return l;
}

int sim_irq_level(sim_t *s)
{
    unsigned l = sim_irq_lines(s);
    int lvl = 0;
    while (l >>= 1)
        lvl++;
    return lvl;                    /* the highest request */
}

int sim_irq_source(int level)
{
    switch (level) {
    case IRQ_LEVEL_ESTOP: return SRC_ESTOP;
    case IRQ_LEVEL_TIMER: return SRC_TIMER;
    case IRQ_LEVEL_AXIS: return SRC_AXIS;
    case IRQ_LEVEL_UART: return SRC_UART;
    }
    return SRC_OTHER;
}

cyc_t periph_next_event(sim_t *s)
{
    cyc_t t = CYC_NEVER;
    for (unsigned i = 0; i < NDEVICES; i++)
        if (devices[i]->next_event) {
            cyc_t e = devices[i]->next_event(s);
            if (e < t)
                t = e;
        }
    return t;
}

void periph_events(sim_t *s, cyc_t now)
{
    for (unsigned i = 0; i < NDEVICES; i++)
        if (devices[i]->events)
            devices[i]->events(s, now);
}
