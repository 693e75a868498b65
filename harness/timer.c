/*
 * timer.c - the IPC's periodic timer (level 6) and its free-running
 * microsecond counter: a device of periph.c's table.  Its expiry is the
 * signal timer.expired; with TMR_CTRL_SSI_WAIT its request waits for the SSI
 * receivers that say they read (axis.ssi_busy).
 */
#include <string.h>
#include "sim.h"
#include "periph.h"

/* ---- periodic timer ------------------------------------------------------ */
static uint32_t tmr_rd(sim_t *s, uint32_t off, int size)
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
        s->tmr.free_lo_latch = (uint16_t)us;
        return us >> 16;
    }
    case 0xA: return s->tmr.free_lo_latch;
    }
    sim_fault(s, "read of undefined timer register +$%X", (unsigned)off);
    return 0xFFFF;
}

static void tmr_wr(sim_t *s, uint32_t off, uint32_t v, int size)
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


/* its end of the wire from the SSI receivers (axis.ssi_busy) */
void timer_connect(sim_t *s) { sig_connect(s, SIG_SSI_BUSY, tmr_ssi_busy); }

const device_t tmr_device = {.name = "timer", .win = {{tmr_rd, tmr_wr}}, .reset = tmr_reset,
                             .next_event = tmr_next_event, .events = tmr_event, .irq_lines = tmr_irq_lines};
