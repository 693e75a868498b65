/*
 * sim.c - card state, event printing and the interrupt cycle accounting.
 */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include "sim.h"
#include "periph.h"
#include "vcd.h"

sim_t *g_sim;

static cyc_t no_cpu_elapsed(void) { return 0; }

void sim_init(sim_t *s, int card)
{
    memset(s, 0, sizeof *s);
    s->card = card;
    s->out = stdout;
    s->cpu_elapsed = no_cpu_elapsed;
    s->vme.level = 3;            /* LB1/LB2 as delivered: level 3 (table 2.1) */
    s->wdg.j11 = 1;              /* J11 in: MR and the watchdog can reset the card */
    s->host_reads = 1;
    s->uart.rx_done = CYC_NEVER;
    for (int i = 0; i < SRC_COUNT; i++)
        s->irq[i].min = s->irq[i].xmin = CYC_NEVER;
    memset(s->eprom, 0xFF, sizeof s->eprom);
    periph_connect(s);
    /* Power-on DPRAM and SRAM contents are not zero on real parts. */
    for (unsigned i = 0; i < sizeof s->dpram; i++)
        s->dpram[i] = (uint8_t)(i * 131u + 7u);
    for (unsigned i = 0; i < sizeof s->sram; i++)
        s->sram[i] = (uint8_t)(i * 97u + 3u);
    periph_reset(s);
    g_sim = s;
}

int sim_load_image(sim_t *s, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    size_t n = fread(s->eprom, 1, sizeof s->eprom, f);
    int extra = fgetc(f);
    fclose(f);
    if (n == 0 || extra != EOF)
        return -2;     /* empty, or larger than the 64 KiB socket */
    return (int)n;
}

cyc_t sim_now(sim_t *s) { return s->slice_base + s->cpu_elapsed(); }

void sim_printf(sim_t *s, const char *fmt, ...)
{
    if (s->quiet)
        return;
    if (s->timestamps) {
        cyc_t now = sim_now(s);
        fprintf(s->out, "@%llu.%03llums ", (unsigned long long)(now / 16000u),
                (unsigned long long)(now % 16000u / 16u));
    }
    va_list ap;
    va_start(ap, fmt);
    vfprintf(s->out, fmt, ap);
    va_end(ap);
    fflush(s->out);
}

/* ---- interrupt accounting -------------------------------------------------
 * From the interrupt acknowledge cycle to the end of the RTE, measured on the
 * emulator's cycle counter: nothing in the firmware is instrumented.  Nested
 * interrupts are counted in full for the interrupted ISR ("inclusive") and
 * subtracted for its own cost ("exclusive"). */
void irq_enter(sim_t *s, int level)
{
    if (s->nactive >= (int)(sizeof s->active / sizeof s->active[0])) {
        sim_fault(s, "interrupt nesting deeper than 7 levels");
        return;
    }
    s->active[s->nactive].src = sim_irq_source(level);
    s->active[s->nactive].start = sim_now(s);
    if (s->active[s->nactive].src == SRC_TIMER && s->tmr.irq_at <= sim_now(s)) {
        irqstat_t *st = &s->irq[SRC_TIMER];
        cyc_t lat = sim_now(s) - s->tmr.irq_at;
        st->lat_count++;
        st->lat_sum += lat;
        if (lat > st->lat_max || st->lat_count == 1) {
            st->lat_max = lat;
            st->lat_worst_at = s->tmr.irq_at;
        }
    }
    s->active[s->nactive].nested = 0;
    s->nactive++;
    if (s->vcd)
        vcd_handler(s, sim_now(s));
}

void irq_leave(sim_t *s, cyc_t extra)
{
    if (s->nactive == 0)
        return;                 /* RTE of a non-interrupt exception */
    s->nactive--;
    cyc_t start = s->active[s->nactive].start;
    cyc_t dur = sim_now(s) + extra - start;
    cyc_t excl = dur - s->active[s->nactive].nested;
    irqstat_t *st = &s->irq[s->active[s->nactive].src];
    st->count++;
    st->sum += dur;
    st->xsum += excl;
    if (dur < st->min)
        st->min = dur;
    if (dur > st->max) {
        st->max = dur;
        st->worst_at = start;
    }
    if (excl < st->xmin)
        st->xmin = excl;
    if (excl > st->xmax)
        st->xmax = excl;
    if (s->nactive > 0)
        s->active[s->nactive - 1].nested += dur;
    if (s->vcd)
        vcd_handler(s, sim_now(s) + extra);
    if (s->on_irq_leave)
        s->on_irq_leave(s, s->active[s->nactive].src, start, dur, excl, s->nactive);
}

static const char *const src_names[SRC_COUNT] = {"uart (L4)", "axis (L5)", "timer (L6)",
                                                 "estop (L7)", "other"};

void irq_print_table(sim_t *s, FILE *f)
{
    cyc_t total = sim_now(s) - s->irq_window_start;   /* since boot unless `perf reset` */
    fprintf(f, "irq source    count      min     mean      max  excl.max  load%%  worst at (ms)\n");
    for (int i = 0; i < SRC_COUNT; i++) {
        irqstat_t *st = &s->irq[i];
        if (!st->count) {
            fprintf(f, "%-12s %6u        -        -        -         -      -  -\n", src_names[i], 0u);
            continue;
        }
        fprintf(f, "%-12s %6llu %8llu %8llu %8llu  %8llu  %5.2f  %.3f\n", src_names[i],
                (unsigned long long)st->count, (unsigned long long)st->min,
                (unsigned long long)(st->sum / st->count), (unsigned long long)st->max,
                (unsigned long long)st->xmax, total ? 100.0 * (double)st->xsum / (double)total : 0.0,
                (double)st->worst_at / 16000.0);
    }
}

/* ---- the axis clock (differential test, sim.h "axis_sync") ------------------
 * Logical time: the axis board and the plant advance one timer period at
 * every tick (an expiry, not a restart of the timer) and AXIS_SYNC_STEP
 * cycles at every access in between, whatever the CPU's real timing. */
static cyc_t axis_period(sim_t *s)
{
    cyc_t p = US_TO_CYC(s->tmr.period_us);
    p -= p % PLANT_STEP_CYC;
    return p ? p : PLANT_STEP_CYC;
}

cyc_t sim_axis_peek(sim_t *s)
{
    if (!s->axis_sync)
        return sim_now(s);
    if (s->tmr.last != s->axis_tick_seen) {
        s->axis_tick_seen = s->tmr.last;
        if (s->tmr.status & TMR_ST_EXPIRED) {      /* an expiry, not a (re)start */
            s->axis_base += axis_period(s);
            s->axis_n = 0;
        }
    }
    cyc_t t = s->axis_base + (cyc_t)s->axis_n * AXIS_SYNC_STEP;
    if (s->tmr.period_us && t >= s->axis_base + axis_period(s))
        t = s->axis_base + axis_period(s) - 1;   /* stay before the next tick */
    return t;
}

cyc_t sim_axis_now(sim_t *s)
{
    cyc_t t = sim_axis_peek(s);
    if (s->axis_sync)
        s->axis_n++;
    return t;
}
