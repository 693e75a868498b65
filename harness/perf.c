/*
 * perf.c - measurement without instrumenting the firmware (docs/performance.md):
 * host-script commands `perf ...` and `run-ticks N`.
 *
 *   perf reset             start a measurement window now: interrupt table,
 *                          load, latency and probe statistics from zero
 *   perf irq               the interrupt table, one `perf-irq` line per source
 *   perf net               per source and occurrence: exclusive cycles less the
 *                          probed functions that ran inside it
 *   perf track on|off      main-loop passes (calls of fw_main_step) classified as
 *                          command passes (cmd_done ran) or idle polling
 *   perf probe FUNC        inclusive cycles per call of FUNC, nested ISRs excluded,
 *                          and per profile period (the calls that ended in it)
 *   perf load              CPU load over the window (needs `perf track on`)
 *   perf latency           host enqueue -> response in the response queue
 *   perf latency-log on|off  print every latency as it is measured (perf-lat)
 *   perf probe-log on|off  print every probed call as it ends (perf-call)
 *   perf host-load on|off  the host keeps one command in flight, sending the
 *                          next at its first poll after the previous answer
 *   perf quiet on|off      do not print card events (resp, rx, display ...)
 *   perf ticks FILE|-|off  one line per timer tick: outputs, counters, axis data
 *   perf sample FILE AXIS|off  CSV per tick: setpoint, position, following
 *                          error, output (DPRAM axis data) and the DAC/rate register
 *   perf axis-sync on      the axis board on logical time, the timer held while
 *                          the card has host input (sim.h axis_sync; the
 *                          differential test)
 *   perf mask              the main loop's masked sections: from an instruction
 *                          that runs with the interrupt mask at 5 or more (the
 *                          axis board's level; the firmware masks to 7) to the
 *                          first one below, the longest a level-5 or level-6
 *                          request can wait (needs `perf track on` or a probe)
 *   perf report            irq, net, probes, load, masked sections and latency together
 *   perf table             the cycle table for people, with the budgets used
 *   run-ticks N [off-sp]   run until N more timer ticks have expired (stops at
 *                          the expiry, before the CPU sees it); off-sp: and on,
 *                          one tick at a time, until the next tick does not begin
 *                          a profile period
 *
 * Probes and passes watch the 68000's program counter through the Musashi
 * instruction hook (profile.c) and the symbols of build/eprom/mac4-CARD.sym:
 * a call starts when the PC reaches the function's first instruction and
 * ends when it reaches the return address with the stack pointer back above
 * it.  The interrupt table and latency work with any CPU backend.
 */
#include <stdlib.h>
#include <string.h>
#include "m68k.h"
#include "cpu.h"
#include "script.h"
#include "profile.h"
#include "periph.h"
#include "plant.h"

unsigned int m68k_read_disassembler_32(unsigned int a);   /* cpu_m68k.c: no side effects */

/* ---- statistics ---------------------------------------------------------- */
typedef struct {
    uint64_t count;
    cyc_t min, max, sum, worst_at;
} stat_t;

static void stat_clear(stat_t *st)
{
    memset(st, 0, sizeof *st);
    st->min = CYC_NEVER;
}

static void stat_add(stat_t *st, cyc_t v, cyc_t at)
{
    st->count++;
    st->sum += v;
    if (v < st->min)
        st->min = v;
    if (v > st->max || st->count == 1) {
        st->max = v;
        st->worst_at = at;
    }
}

static FILE *out;            /* where perf prints (stdout even when quiet) */
static FILE *devnull;
static FILE *saved_out;

static double ms_of(cyc_t c) { return (double)c / 16000.0; }

static void stat_print(const char *tag, const char *name, const stat_t *st)
{
    if (!st->count) {
        fprintf(out, "%s %s count=0\n", tag, name);
        return;
    }
    fprintf(out, "%s %s count=%llu min=%llu mean=%llu max=%llu sum=%llu worst_at_ms=%.3f\n", tag, name,
            (unsigned long long)st->count, (unsigned long long)st->min,
            (unsigned long long)(st->sum / st->count), (unsigned long long)st->max,
            (unsigned long long)st->sum, ms_of(st->worst_at));
}

/* ---- probes -------------------------------------------------------------- */
#define NPROBE 8
typedef struct {
    char name[64];
    uint32_t entry;
    int active;
    uint32_t ret, sp;        /* return address and stack pointer at entry */
    cyc_t start, nested;
    int depth;               /* interrupt nesting depth at entry (0: main loop) */
    stat_t st;
    /* per profile period (PROFILE_DIVIDER ticks from a tick the firmware
     * counts as phase 0): the cycles of the calls that ended in it */
    long long win;
    cyc_t win_sum, win_start;
    stat_t wst;
} probe_t;

static probe_t probes[NPROBE];
static int nprobes;
static cyc_t isr_probe_cycles[9];   /* probe cycles inside the ISR at each depth */

/* main-loop passes */
static int track;
static probe_t pass;
static uint32_t cmd_entry;
static int pass_cmd;
static cyc_t pass_probe, cmd_probe;  /* probe cycles in this pass, in all command passes */
static stat_t pass_cmd_st, pass_idle_st;

/* masked sections at main-loop level (perf mask) */
static int mask_on;
static cyc_t mask_start;
static uint32_t mask_pc, mask_worst_pc;     /* where a section began, the longest one */
static stat_t mask_st;

/* interrupt occurrences minus the probes that ran inside them */
static stat_t net[SRC_COUNT];

/* latency: enqueue times of the VME commands not answered yet */
#define LAT_FIFO 64
static cyc_t lat_fifo[LAT_FIFO];
static unsigned lat_n, lat_head;
static uint32_t cmdq_seen = 0xFFFFFFFFu, rspq_seen = 0xFFFFFFFFu;
static stat_t lat_st;
static uint64_t lat_unmatched;
static int lat_log;
static int probe_log;               /* perf-call per probed call */
static cyc_t lat_window;             /* commands enqueued from here on count */
static uint64_t resets_seen;

/* host load */
static int host_load;
static unsigned host_load_i;
static uint64_t host_load_sent;

/* per-tick logs */
static FILE *ticks_f, *sample_f;
static int sample_axis;
static cyc_t tmr_last_seen;

static const char *const src_key[SRC_COUNT] = {"uart", "axis", "timer", "estop", "other"};

static sim_t *S;
static int installed;

static uint32_t cpu_sp(void) { return m68k_get_reg(NULL, M68K_REG_SP); }

static void probe_start(sim_t *s, probe_t *p, cyc_t now)
{
    p->active = 1;
    p->sp = cpu_sp();
    p->ret = m68k_read_disassembler_32(p->sp);
    p->start = now;
    p->nested = 0;
    p->depth = s->nactive;
}

static uint64_t tick_no;

/* Profile periods: a new one starts at each timer expiry after which the
 * firmware runs its phase-0 tick, i.e. when the tick count it publishes at
 * DPC_TICKS (ticks done so far) is a multiple of PROFILE_DIVIDER. */
static long long win_no;
static long long window_of_now(void) { return win_no; }

static void window_flush(probe_t *p)
{
    if (p->win_sum)
        stat_add(&p->wst, p->win_sum, p->win_start);
    p->win_sum = 0;
}

static cyc_t probe_end(probe_t *p, cyc_t now)
{
    p->active = 0;
    cyc_t d = now - p->start - p->nested;
    stat_add(&p->st, d, p->start);
    if (probe_log && p != &pass)
        fprintf(out, "perf-call %s at_ms=%.3f cycles=%llu\n", p->name, ms_of(p->start), (unsigned long long)d);
    /* the period the call ended in: a call that begins just before a tick
     * sets the flag it acts on may well do its work for the new period */
    long long w = window_of_now();
    if (w != p->win) {
        window_flush(p);
        p->win = w;
    }
    if (!p->win_sum)
        p->win_start = p->start;
    p->win_sum += d;
    return d;
}

static uint32_t sp_low = SRAM_BASE + SRAM_SIZE;   /* the deepest stack seen (SRAM stack) */

static void instr_hook(unsigned pc)
{
    sim_t *s = S;
    cyc_t now = sim_now(s);
    uint32_t sp = cpu_sp();
    if (sp < sp_low && sp >= SRAM_BASE)
        sp_low = sp;
    for (int i = 0; i < nprobes; i++) {
        probe_t *p = &probes[i];
        if (p->active) {
            if (pc == p->ret && cpu_sp() == p->sp + 4) {
                cyc_t d = probe_end(p, now);
                if (p->depth > 0 && p->depth <= 8)
                    isr_probe_cycles[p->depth - 1] += d;
                else if (pass.active)
                    pass_probe += d;
            }
        } else if (pc == p->entry) {
            probe_start(s, p, now);
        }
    }
    /* a masked section: main level, mask >= the axis board's level */
    int masked = s->nactive == 0 && ((m68k_get_reg(NULL, M68K_REG_SR) >> 8) & 7u) >= IRQ_LEVEL_AXIS;
    if (masked != mask_on) {
        if (masked) {
            mask_start = now;
            mask_pc = pc;
        } else {
            if (now - mask_start > mask_st.max || !mask_st.count)
                mask_worst_pc = mask_pc;
            stat_add(&mask_st, now - mask_start, mask_start);
        }
        mask_on = masked;
    }
    if (track) {
        if (pass.active) {
            if (pc == cmd_entry)
                pass_cmd = 1;
            else if (pc == pass.ret && cpu_sp() == pass.sp + 4) {
                cyc_t d = probe_end(&pass, now);
                stat_add(pass_cmd ? &pass_cmd_st : &pass_idle_st, d, pass.start);
                if (pass_cmd)
                    cmd_probe += pass_probe;
            }
        } else if (pc == pass.entry && s->nactive == 0) {
            probe_start(s, &pass, now);
            pass_cmd = 0;
            pass_probe = 0;
        }
    }
}

static void update_hook(void) { profile_set_hook(nprobes || track ? instr_hook : NULL); }

/* The axis board's interrupts by how many step pulses each served (the
 * AX_CTRL writes with AX_CTRL_PULSE_ACK while it ran, on_bus_write): the
 * creep's and the UART's bounds charge a pulse the worst cost per pulse
 * (perfscen.creep_wait), not the worst interrupt, which may serve four. */
#define PULSE_MAX 4
static stat_t pulse_st[PULSE_MAX + 1];
static unsigned axis_isr_acks;

static void on_irq_leave(sim_t *s, int src, cyc_t start, cyc_t dur, cyc_t excl, int depth)
{
    (void)s;
    for (int i = 0; i < nprobes; i++)
        if (probes[i].active && probes[i].depth == depth)
            probes[i].nested += dur;
    if (pass.active && pass.depth == depth)
        pass.nested += dur;
    cyc_t in = depth < 9 ? isr_probe_cycles[depth] : 0;
    if (depth < 9)
        isr_probe_cycles[depth] = 0;
    stat_add(&net[src], excl > in ? excl - in : 0, start);
    if (src == SRC_AXIS) {
        stat_add(&pulse_st[axis_isr_acks < PULSE_MAX ? axis_isr_acks : PULSE_MAX], excl > in ? excl - in : 0, start);
        axis_isr_acks = 0;
    }
}

/* ---- latency ----------------------------------------------------------------- */
static int queue_ok(sim_t *s, uint32_t q, uint32_t *front)
{
    uint32_t base = dp_rd32(s, q + QH_BASE), width = dp_rd32(s, q + QH_WIDTH);
    uint32_t nel = dp_rd32(s, q + QH_NEL), f = dp_rd32(s, q + QH_FRONT);
    if (base != Q_HEADER_SIZE || width != Q_WIDTH || nel != Q_NEL || f >= nel)
        return 0;
    *front = f;
    return 1;
}

static void check_reset(sim_t *s)
{
    if (s->resets != resets_seen) {     /* a reset loses what was in flight */
        resets_seen = s->resets;
        lat_n = lat_head = 0;
        cmdq_seen = rspq_seen = 0xFFFFFFFFu;
        pass.active = 0;
        for (int i = 0; i < nprobes; i++)
            probes[i].active = 0;
    }
}

static void on_bus_write(sim_t *s, uint32_t addr, uint32_t v, int size)
{
    if (addr - AXIS_BASE < MAC4_NAXES * AXIS_STRIDE && (addr & 0xFF) == AX_CTRL && (v & AX_CTRL_PULSE_ACK)
        && s->nactive && s->active[s->nactive - 1].src == SRC_AXIS)
        axis_isr_acks++;               /* a pulse served by the axis interrupt that runs */
    uint32_t lo = addr & 0xFFFF;
    if (addr >= DPRAM_SIZE)
        return;
    check_reset(s);
    uint32_t f;
    if (lo + (uint32_t)size > DP_CMD_QUEUE + QH_FRONT && lo < DP_CMD_QUEUE + QH_FRONT + 4) {
        cmdq_seen = dp_rd32(s, DP_CMD_QUEUE + QH_FRONT);   /* the card creates the queue */
        return;
    }
    if (!(lo + (uint32_t)size > DP_RSP_QUEUE + QH_FRONT && lo < DP_RSP_QUEUE + QH_FRONT + 4))
        return;
    if (!queue_ok(s, DP_RSP_QUEUE, &f)) {                 /* being created */
        rspq_seen = dp_rd32(s, DP_RSP_QUEUE + QH_FRONT);
        return;
    }
    if (rspq_seen < Q_NEL && f != rspq_seen) {
        unsigned k = (f + Q_NEL - rspq_seen) % Q_NEL;
        cyc_t now = sim_now(s);
        while (k--) {
            if (!lat_n) {
                lat_unmatched++;
                if (lat_log)
                    fprintf(out, "perf-lat unmatched response at %.3f ms\n", ms_of(now));
                continue;
            }
            if (lat_fifo[lat_head] >= lat_window && lat_fifo[lat_head])   /* sent before `perf reset`: not counted */
                stat_add(&lat_st, now - lat_fifo[lat_head], lat_fifo[lat_head]);
            if (lat_log)
                fprintf(out, "perf-lat enq_ms=%.3f rsp_ms=%.3f us=%.1f\n", ms_of(lat_fifo[lat_head]), ms_of(now),
                        (double)(now - lat_fifo[lat_head]) / 16.0);
            lat_head = (lat_head + 1) % LAT_FIFO;
            lat_n--;
        }
    }
    rspq_seen = f;
}

/* A timer tick: count it, and log what the card put out during the last one. */
static void tick_poll(sim_t *s)
{
    if (s->tmr.last == tmr_last_seen)
        return;
    tmr_last_seen = s->tmr.last;
    if (!(s->tmr.status & TMR_ST_EXPIRED)) {
        tick_no = 0;                /* the timer was (re)started */
        return;
    }
    tick_no++;
    if (dp_rd32(s, DPC_TICKS) % PROFILE_DIVIDER == 0)
        win_no++;
    cyc_t now = sim_now(s);
    if (ticks_f) {
        cyc_t t = sim_axis_peek(s);
        fprintf(ticks_f, "tick %llu", (unsigned long long)tick_no);
        for (int n = 0; n < MAC4_NAXES; n++) {
            axis_hw_t *a = &s->ax[n];
            fprintf(ticks_f, " | %d %04X", s->card == MAC4_CARD_STP ? (int)a->rate : (int)a->dac, a->ctrl);
            if (s->card == MAC4_CARD_STP)   /* the plant is up to date: periph_events */
                fprintf(ticks_f, " g%lld", (long long)s->plant.ax[n].gen);
            if (s->card == MAC4_CARD_SSI)
                fprintf(ticks_f, " s%06X", plant_ssi_value(s, n, t));
            else
                fprintf(ticks_f, " c%06X", axb_counter(s, n, t));
            for (uint32_t w = 0; w < 0x20; w += 4)
                fprintf(ticks_f, " %X", dp_rd32(s, DP_AXIS_DATA(n) + w));
        }
        fputc('\n', ticks_f);
    }
    if (sample_f) {
        uint32_t d = DP_AXIS_DATA(sample_axis);
        axis_hw_t *a = &s->ax[sample_axis];
        fprintf(sample_f, "%.3f,%d,%d,%d,%d,%d\n", ms_of(now), (int32_t)dp_rd32(s, d + DPA_SETPOINT),
                (int32_t)dp_rd32(s, d + DPA_POS), (int32_t)dp_rd32(s, d + DPA_FERR),
                (int32_t)dp_rd32(s, d + DPA_OUT), s->card == MAC4_CARD_STP ? (int)a->rate : (int)a->dac);
    }
}

/* axis_sync: while the card has host input to work on (commands in the
 * queue, serial bytes on the line) and HOLD_CYC after, the next tick waits.
 * Both CPUs then finish a command between the same two ticks, however long
 * it takes them; on logical time the plant does not notice. */
#define HOLD_CYC MS_TO_CYC(20)
static cyc_t hold_until;

static void hold_timer(sim_t *s, cyc_t now)
{
    if (s->tmr.next == CYC_NEVER)
        return;
    uint32_t front = dp_rd32(s, DP_CMD_QUEUE + QH_FRONT), rear = dp_rd32(s, DP_CMD_QUEUE + QH_REAR);
    int busy = front != rear || s->uart.wire_head != s->uart.wire_tail || s->uart.rx_full;
    if (busy)
        hold_until = now + HOLD_CYC;
    if (hold_until > now && s->tmr.next < hold_until)
        s->tmr.next = hold_until;
}

static const char *const load_cmds[] = {"RBS", "RCP", "RFE", "ROUT"};

static void on_slice(sim_t *s, cyc_t now, int host_polled)
{
    check_reset(s);
    /* the host's enqueues happen between slices: see them at the next one */
    if (host_load && host_polled && lat_n == 0) {
        static long codes[4] = {-2, -2, -2, -2};
        unsigned i = host_load_i++, c = (i / MAC4_NAXES) % 4;
        if (codes[c] == -2)
            codes[c] = script_code(load_cmds[c]);
        long code = codes[c];
        if (code >= 0 && host_send(s, (uint8_t)(i % MAC4_NAXES), (uint16_t)code, 0, MSG_SRC_VME) == 1)
            host_load_sent++;
    }
    uint32_t f;
    if (queue_ok(s, DP_CMD_QUEUE, &f)) {
        if (cmdq_seen < Q_NEL && f != cmdq_seen) {
            unsigned k = (f + Q_NEL - cmdq_seen) % Q_NEL;
            while (k-- && lat_n < LAT_FIFO) {
                lat_fifo[(lat_head + lat_n) % LAT_FIFO] = now;
                lat_n++;
            }
        }
        cmdq_seen = f;
    }
    tick_poll(s);
    if (s->axis_sync)
        hold_timer(s, now);
}

/* ---- the window -------------------------------------------------------------- */
static void window_reset(sim_t *s)
{
    for (int i = 0; i < SRC_COUNT; i++) {
        memset(&s->irq[i], 0, sizeof s->irq[i]);
        s->irq[i].min = s->irq[i].xmin = CYC_NEVER;
        stat_clear(&net[i]);
    }
    for (int j = 0; j <= PULSE_MAX; j++)
        stat_clear(&pulse_st[j]);
    axis_isr_acks = 0;
    s->irq_window_start = sim_now(s);
    for (int i = 0; i < nprobes; i++) {
        stat_clear(&probes[i].st);
        stat_clear(&probes[i].wst);
        probes[i].win_sum = 0;
        probes[i].win = window_of_now();
    }
    stat_clear(&pass.st);
    stat_clear(&mask_st);
    mask_on = 0;
    stat_clear(&pass_cmd_st);
    stat_clear(&pass_idle_st);
    cmd_probe = 0;
    stat_clear(&lat_st);
    lat_unmatched = 0;
    lat_window = sim_now(s);
    host_load_sent = 0;
}

static void install(sim_t *s)
{
    if (installed)
        return;
    installed = 1;
    S = s;
    out = s->out;
    s->on_irq_leave = on_irq_leave;
    s->on_bus_write = on_bus_write;
    s->on_slice = on_slice;
    resets_seen = s->resets;
    tmr_last_seen = s->tmr.last;
    uint32_t f;
    if (queue_ok(s, DP_CMD_QUEUE, &f)) {
        /* commands already waiting: answered later, their time unknown */
        uint32_t rear = dp_rd32(s, DP_CMD_QUEUE + QH_REAR);
        for (unsigned k = rear < Q_NEL ? (f + Q_NEL - rear) % Q_NEL : 0; k; k--)
            lat_fifo[(lat_head + lat_n++) % LAT_FIFO] = 0;
        cmdq_seen = f;
    }
    if (queue_ok(s, DP_RSP_QUEUE, &f))
        rspq_seen = f;
    stat_clear(&pass.st);
    for (int i = 0; i < SRC_COUNT; i++)
        stat_clear(&net[i]);
    stat_clear(&pass_cmd_st);
    stat_clear(&pass_idle_st);
    stat_clear(&lat_st);
}

static void print_irq(sim_t *s)
{
    for (int i = 0; i < SRC_COUNT; i++) {
        irqstat_t *st = &s->irq[i];
        if (!st->count) {
            fprintf(out, "perf-irq %s count=0\n", src_key[i]);
            continue;
        }
        fprintf(out, "perf-irq %s count=%llu min=%llu mean=%llu max=%llu xmin=%llu xmax=%llu xsum=%llu "
                "worst_at_ms=%.3f", src_key[i], (unsigned long long)st->count, (unsigned long long)st->min,
                (unsigned long long)(st->sum / st->count), (unsigned long long)st->max,
                (unsigned long long)st->xmin, (unsigned long long)st->xmax, (unsigned long long)st->xsum,
                ms_of(st->worst_at));
        if (st->lat_count)
            fprintf(out, " lat_max=%llu lat_mean=%llu lat_worst_at_ms=%.3f", (unsigned long long)st->lat_max,
                    (unsigned long long)(st->lat_sum / st->lat_count), ms_of(st->lat_worst_at));
        fputc('\n', out);
    }
}

/* CPU load over the window: the interrupts (exclusive cycles) and the main
 * loop's work, i.e. every pass's cycles beyond the cheapest idle pass (the
 * bare poll the loop spins in when there is nothing to do).  Of that work,
 * "cmd" is what the passes that executed a command needed beyond the bare
 * poll (queue read, decode, execution, response) less the probes' cycles in
 * them, "profile" the probes' cycles at main-loop level (card_profile_tick
 * when probed). */
static void print_load(sim_t *s)
{
    cyc_t w = sim_now(s) - s->irq_window_start;
    if (!w)
        w = 1;
    cyc_t isr = 0;
    fprintf(out, "perf-load window_ms=%.3f", ms_of(w));
    for (int i = 0; i < SRC_COUNT; i++) {
        isr += s->irq[i].xsum;
        fprintf(out, " %s=%.3f", src_key[i], 100.0 * (double)s->irq[i].xsum / (double)w);
    }
    cyc_t idle_min = pass_idle_st.count ? pass_idle_st.min : (pass_cmd_st.count ? pass_cmd_st.min : 0);
    uint64_t npass = pass_cmd_st.count + pass_idle_st.count;
    cyc_t all = pass_cmd_st.sum + pass_idle_st.sum;
    cyc_t main_work = all > npass * idle_min ? all - npass * idle_min : 0;
    cyc_t cmd = pass_cmd_st.sum > pass_cmd_st.count * idle_min + cmd_probe
              ? pass_cmd_st.sum - pass_cmd_st.count * idle_min - cmd_probe : 0;
    cyc_t prof = 0;
    for (int i = 0; i < nprobes; i++)
        if (probes[i].depth == 0)
            prof += probes[i].st.sum;
    double pc = 100.0 / (double)w;
    fprintf(out, " isr=%.3f main=%.3f cmd=%.3f profile=%.3f total=%.3f idle_pass_min=%llu tracked=%d "
            "cmd_passes=%llu idle_passes=%llu host_load_sent=%llu\n", pc * (double)isr, pc * (double)main_work,
            pc * (double)cmd, pc * (double)prof, pc * (double)(isr + main_work), (unsigned long long)idle_min, track,
            (unsigned long long)pass_cmd_st.count, (unsigned long long)pass_idle_st.count,
            (unsigned long long)host_load_sent);
    stat_print("perf-pass", "cmd", &pass_cmd_st);
    stat_print("perf-pass", "idle", &pass_idle_st);
    if (track || nprobes)
        fprintf(out, "perf-stack deepest_bytes=%u\n", (unsigned)(SRAM_BASE + SRAM_SIZE - sp_low));
}

static void print_latency(void)
{
    if (!lat_st.count) {
        fprintf(out, "perf-latency count=0 unmatched=%llu pending=%u\n", (unsigned long long)lat_unmatched, lat_n);
        return;
    }
    fprintf(out, "perf-latency count=%llu min_us=%.1f mean_us=%.1f max_us=%.1f worst_at_ms=%.3f unmatched=%llu "
            "pending=%u\n", (unsigned long long)lat_st.count, (double)lat_st.min / 16.0,
            (double)lat_st.sum / (double)lat_st.count / 16.0, (double)lat_st.max / 16.0, ms_of(lat_st.worst_at),
            (unsigned long long)lat_unmatched, lat_n);
}

static void print_probes(void)
{
    for (int i = 0; i < nprobes; i++) {
        probe_t *p = &probes[i];
        stat_print("perf-probe", p->name, &p->st);
        /* the period under way counts as it stands */
        stat_t w = p->wst;
        if (p->win_sum)
            stat_add(&w, p->win_sum, p->win_start);
        stat_print("perf-probe-period", p->name, &w);
    }
}

static void print_mask(void)
{
    stat_print("perf-mask", "main", &mask_st);
    if (mask_st.count)
        fprintf(out, "perf-mask-worst pc=0x%06X (the first instruction with the mask raised)\n", (unsigned)mask_worst_pc);
}

static void print_net(void)
{
    for (int i = 0; i < SRC_COUNT; i++)
        stat_print("perf-net", src_key[i], &net[i]);
    for (int j = 0; j <= PULSE_MAX; j++) {
        char name[16];
        snprintf(name, sizeof name, "pulses=%d", j);
        stat_print("perf-axis", name, &pulse_st[j]);
    }
}

/* The cycle table for people, with the budgets (docs/performance.md):
 * the servo tick 10% of its period, the profile generator 6000 cycles per
 * 10 ms (INC/SSI) or 10% of 32 ms (STP), the whole card 25%, a command 2 ms. */
static void print_table(sim_t *s)
{
    int stp = s->card == MAC4_CARD_STP;
    cyc_t period = US_TO_CYC(stp ? SERVO_PERIOD_US_STP : SERVO_PERIOD_US_SERVO);
    cyc_t w = sim_now(s) - s->irq_window_start;
    static const char *const names[SRC_COUNT] = {"serial (L4)", "axis board (L5)", "timer tick (L6)",
                                                 "emergency stop (L7)", "other"};
    fprintf(out, "cycles at 16 MHz over %.1f ms            count     min    mean     max  load%%   budget  used\n",
            ms_of(w));
    for (int i = 0; i < SRC_COUNT; i++) {
        const stat_t *n = &net[i];
        if (!n->count)
            continue;
        fprintf(out, "  %-36s %7llu %7llu %7llu %7llu %6.2f", names[i], (unsigned long long)n->count,
                (unsigned long long)n->min, (unsigned long long)(n->sum / n->count), (unsigned long long)n->max,
                w ? 100.0 * (double)s->irq[i].xsum / (double)w : 0.0);
        if (i == SRC_TIMER)
            fprintf(out, " %8llu %4.0f%%", (unsigned long long)(period / 10),
                    100.0 * (double)n->max / (double)(period / 10));
        fputc('\n', out);
    }
    for (int i = 0; i < nprobes; i++) {
        probe_t *p = &probes[i];
        stat_t wst = p->wst;
        if (p->win_sum)
            stat_add(&wst, p->win_sum, p->win_start);
        if (!wst.count)
            continue;
        cyc_t budget = stp ? period * PROFILE_DIVIDER / 10 : 6000;
        char label[96];
        snprintf(label, sizeof label, "%.63s per %u ms", p->name, (unsigned)(period * PROFILE_DIVIDER / 16000));
        fprintf(out, "  %-36s %7llu %7llu %7llu %7llu %6.2f %8llu %4.0f%%\n", label, (unsigned long long)wst.count,
                (unsigned long long)wst.min, (unsigned long long)(wst.sum / wst.count), (unsigned long long)wst.max,
                w ? 100.0 * (double)wst.sum / (double)w : 0.0, (unsigned long long)budget,
                100.0 * (double)wst.max / (double)budget);
    }
    const irqstat_t *tq = &s->irq[SRC_TIMER];
    if (tq->lat_count)
        fprintf(out, "  %-36s %7llu %7s %7llu %7llu %6s %8llu %4.0f%%\n", "timer latency, request to acknowledge",
                (unsigned long long)tq->lat_count, "", (unsigned long long)(tq->lat_sum / tq->lat_count),
                (unsigned long long)tq->lat_max, "", (unsigned long long)(period / 10),
                100.0 * (double)tq->lat_max / (double)(period / 10));
    if (mask_st.count)
        fprintf(out, "  %-36s %7llu %7llu %7llu %7llu %6s %8llu %4.0f%%\n", "masked section (main loop), bound",
                (unsigned long long)mask_st.count, (unsigned long long)mask_st.min,
                (unsigned long long)(mask_st.sum / mask_st.count), (unsigned long long)mask_st.max, "",
                (unsigned long long)(period / 10), 100.0 * (double)mask_st.max / (double)(period / 10));
    if (track && w) {
        cyc_t idle_min = pass_idle_st.count ? pass_idle_st.min : 0;
        uint64_t npass = pass_cmd_st.count + pass_idle_st.count;
        cyc_t all = pass_cmd_st.sum + pass_idle_st.sum, isr = 0;
        for (int i = 0; i < SRC_COUNT; i++)
            isr += s->irq[i].xsum;
        cyc_t main_work = all > npass * idle_min ? all - npass * idle_min : 0;
        double load = 100.0 * (double)(isr + main_work) / (double)w;
        fprintf(out, "  %-36s %7s %7s %7s %7s %6.2f %7s%% %4.0f%%\n", "CPU load (interrupts + main loop)", "", "",
                "", "", load, "25", load / 25.0 * 100.0);
    }
    if (lat_st.count)
        fprintf(out, "  %-36s %7llu %7.2f %7.2f %7.2f %6s %5s ms %4.0f%%\n", "command latency (ms)",
                (unsigned long long)lat_st.count, (double)lat_st.min / 16000.0,
                (double)lat_st.sum / (double)lat_st.count / 16000.0, (double)lat_st.max / 16000.0, "", "2",
                (double)lat_st.max / 16000.0 / 2.0 * 100.0);
}

static int needs_symbols(script_t *sc, const char *name, uint32_t *addr)
{
    if (profile_symbol(name, addr))
        return script_err(sc, "perf: no symbol '%s' (the 68000 image's .sym beside it is needed)", name);
    return 0;
}

static int open_log(script_t *sc, const char *path, FILE **f)
{
    if (*f && *f != stdout)
        fclose(*f);
    *f = NULL;
    if (!strcmp(path, "off"))
        return 0;
    *f = !strcmp(path, "-") ? stdout : fopen(path, "w");
    if (!*f)
        return script_err(sc, "perf: cannot open '%s'", path);
    return 0;
}

static int cmd_perf(script_t *sc, sim_t *s, char **tok, int n)
{
    install(s);
    const char *c = n >= 2 ? tok[1] : "";
    if (!strcmp(c, "reset") && n == 2) {
        window_reset(s);
        return 0;
    }
    if (!strcmp(c, "irq") && n == 2) {
        print_irq(s);
        return 0;
    }
    if (!strcmp(c, "net") && n == 2) {
        print_net();
        return 0;
    }
    if (!strcmp(c, "load") && n == 2) {
        print_load(s);
        return 0;
    }
    if (!strcmp(c, "latency") && n == 2) {
        print_latency();
        return 0;
    }
    if (!strcmp(c, "table") && n == 2) {
        print_table(s);
        return 0;
    }
    if (!strcmp(c, "report") && n == 2) {
        print_irq(s);
        print_net();
        print_probes();
        print_load(s);
        print_mask();
        print_latency();
        return 0;
    }
    if (!strcmp(c, "mask") && n == 2) {
        print_mask();
        return 0;
    }
    if (!strcmp(c, "track") && (n == 3 || n == 5)) {
        if (!strcmp(tok[2], "off")) {
            track = 0;
        } else {
            const char *m = n == 5 ? tok[3] : "fw_main_step", *x = n == 5 ? tok[4] : "cmd_done";
            if (needs_symbols(sc, m, &pass.entry) || needs_symbols(sc, x, &cmd_entry))
                return -1;
            snprintf(pass.name, sizeof pass.name, "%s", m);
            pass.active = 0;
            track = 1;
        }
        update_hook();
        return 0;
    }
    if (!strcmp(c, "probe") && n == 3) {
        if (nprobes == NPROBE)
            return script_err(sc, "perf: at most %s probes", "8");
        probe_t *p = &probes[nprobes];
        memset(p, 0, sizeof *p);
        if (needs_symbols(sc, tok[2], &p->entry))
            return -1;
        snprintf(p->name, sizeof p->name, "%s", tok[2]);
        stat_clear(&p->st);
        stat_clear(&p->wst);
        p->win = window_of_now();
        nprobes++;
        update_hook();
        return 0;
    }
    if (!strcmp(c, "latency-log") && n == 3) {
        lat_log = !strcmp(tok[2], "on");
        return 0;
    }
    if (!strcmp(c, "probe-log") && n == 3) {
        probe_log = !strcmp(tok[2], "on");
        return 0;
    }
    if (!strcmp(c, "host-load") && n == 3) {
        host_load = !strcmp(tok[2], "on");
        return 0;
    }
    if (!strcmp(c, "quiet") && n == 3) {
        if (!strcmp(tok[2], "on")) {
            if (!devnull)
                devnull = fopen("/dev/null", "w");
            if (!saved_out)
                saved_out = s->out;
            if (devnull) {
                s->out = devnull;
                s->quiet = 1;      /* sim_printf formats nothing for it */
            }
        } else if (saved_out) {
            s->out = saved_out;
            s->quiet = 0;
        }
        return 0;
    }
    if (!strcmp(c, "ticks") && n == 3)
        return open_log(sc, tok[2], &ticks_f);
    if (!strcmp(c, "sample") && (n == 3 || n == 4)) {
        long long a = 0;
        if (n == 4 && (script_parse_num(tok[3], &a) || a < 0 || a >= MAC4_NAXES))
            return script_err(sc, "perf sample: bad axis '%s'", tok[3]);
        sample_axis = (int)a;
        if (open_log(sc, tok[2], &sample_f))
            return -1;
        if (sample_f)
            fprintf(sample_f, "t_ms,setpoint,pos,ferr,out,%s\n", s->card == MAC4_CARD_STP ? "rate" : "dac");
        return 0;
    }
    if (!strcmp(c, "axis-sync") && n == 3) {
        if (sim_now(s) != 0)
            return script_err(sc, "perf axis-sync: only as the first command, before time %s", "0");
        s->axis_sync = !strcmp(tok[2], "on");
        return 0;
    }
    return script_err(sc, "usage: perf reset|irq|net|load|latency|report|table|track on|off|probe FUNC|"
                          "host-load on|off|quiet on|off|ticks FILE|sample FILE AXIS|axis-sync on%s", "");
}

static int cmd_run_ticks(script_t *sc, sim_t *s, char **tok, int n)
{
    long long k;
    int off_sp = n == 3 && !strcmp(tok[2], "off-sp");
    if ((n != 2 && !off_sp) || script_parse_num(tok[1], &k) || k < 1 || k > 100000000)
        return script_err(sc, "usage: %s N [off-sp] (N ticks, 1..100000000)", "run-ticks");
    install(s);
    tick_poll(s);
    uint64_t want = tick_no + (uint64_t)k;
    /* off-sp: not where the next tick starts a profile period (the firmware's
     * tick count at DPC_TICKS a multiple of PROFILE_DIVIDER): commands
     * injected there would meet a main loop that may or may not have begun
     * the profile generator's pass, depending on the CPU's speed. */
    while (tick_no < want || (off_sp && dp_rd32(s, DPC_TICKS) % PROFILE_DIVIDER == 0)) {
        if (s->tmr.next == CYC_NEVER)
            return script_err(sc, "run-ticks: the timer is %s", "not running");
        sim_run(s, s->tmr.next > s->slice_base ? s->tmr.next - s->slice_base : 1);
        tick_poll(s);
    }
    return 0;
}

int script_perf(script_t *sc, sim_t *s, char **tok, int n)
{
    if (!strcmp(tok[0], "perf"))
        return cmd_perf(sc, s, tok, n);
    if (!strcmp(tok[0], "run-ticks"))
        return cmd_run_ticks(sc, s, tok, n);
    return SCRIPT_NOT_MINE;
}
