/*
 * idle.c - the exact idle skip (docs/performance.md, "The idle skip").
 *
 * The firmware's idle main loop reads memory, writes the same bytes and
 * kicks the watchdog, pass after pass.  From the entry of fw_main_step (the
 * anchor), after a pass that read no device, took no interrupt and was no
 * longer than the last window's passes and a half (a busy pass costs more to
 * record than a skip after it gives back), the CPU is recorded for up to
 * REC_PASSES passes: at every CK_EVERY-th instruction and at the anchor a checkpoint (registers, cycle offset, bus counters),
 * every byte of the SRAM and DPRAM read or written, and the writes to the
 * watchdog, the one I/O register a window may touch.  The window closes
 * when the CPU is back at the anchor with the registers it started with and
 * every byte it read before writing it as it was: then the next pass pair
 * is the same window again, instruction for instruction, unless something
 * from outside changes what it reads.
 *
 * Skip: when the CPU stands before a checkpoint of a closed window with
 * that checkpoint's registers, the bytes the rest of the window reads as
 * they were then, the same interrupt request level, no VME host access
 * holding the DPRAM and the same bus timing, everything up to the last
 * checkpoint the slice would start is applied at once: its registers, the
 * last value of every byte written, the last watchdog write at its cycle
 * (through the bus, as the CPU made it; the watchdog's state is the time of
 * its last write), the bus counts and the cycles.  Musashi runs the rest of
 * the slice, so it ends as it would.  Interrupts are only taken at
 * m68k_execute's start or at an SR change (cpu_m68k.c), so with the request
 * level of the recording none is taken inside the window.
 *
 * Off with --no-fast, the profiler, perf probes, tracks and masks (their
 * instruction hook), gdb, a waveform, an SRAM fault or the boot overlay.
 */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include "m68k.h"
#include "m68kcpu.h"
#include "cpu.h"
#include "idle.h"
#include "buswait.h"
#include "profile.h"
#include "gdbstub.h"

unsigned mac4_idle_pc = 1;      /* the PC watched: odd, never one, until the anchor is known */
int mac4_idle_rec;              /* recording: cpu_m68k.c reports every memory access */
idle_stats_t idle_stats;

#define REC_PASSES 2            /* a window is one or two main-loop passes */
#define MAX_INS 1024            /* checkpoints */
#define CK_EVERY 16
#define MAX_INSTR (MAX_INS * CK_EVERY / 2)
#define MAX_BYTES 1024
#define MAX_WRITES 4096
#define MAX_IO 64
#define NREG 34
/* A window that skipped less than REC_COST times its own cycles counts as
 * a failure for the back-off: recording costs the host more than emulating
 * (idle_rec_read/_write, the checkpoints).  With 1 instead of 3 the bench
 * scenario took 8% more host instructions (cachegrind), the idle card the
 * same (docs/performance.md, "The idle skip"). */
#define REC_COST 3
#define SHORT_PASS_FIRST 4096   /* cycles, until a window gives the idle pass' length */

/* the registers an instruction leaves (PPC and IR are set by the next one) */
typedef struct { uint32_t r[NREG]; } regs_t;
_Static_assert(offsetof(m68ki_cpu_core, int_mask) - offsetof(m68ki_cpu_core, t1_flag) == 9 * sizeof(uint),
               "t1_flag .. int_mask are ten words in a row");

/* The slot of REG_SP_BASE the active stack pointer was last stored in
 * holds a stale copy of A7 (rewritten before it is read, at the next change
 * of S or M): not state. */
static unsigned sp_active(void) { return FLAG_S | ((FLAG_S >> 1) & FLAG_M); }

static void regs_get(regs_t *g)
{
    memcpy(g->r, m68ki_cpu.dar, 16 * sizeof(uint32_t));
    g->r[16] = m68ki_cpu.pc;
    memcpy(g->r + 17, m68ki_cpu.sp, 7 * sizeof(uint32_t));
    memcpy(g->r + 24, &m68ki_cpu.t1_flag, 10 * sizeof(uint32_t));
    g->r[17 + sp_active()] = 0;
}

static void regs_set(const regs_t *g)
{
    uint32_t stale = m68ki_cpu.sp[sp_active()];
    memcpy(m68ki_cpu.dar, g->r, 16 * sizeof(uint32_t));
    m68ki_cpu.pc = g->r[16];
    memcpy(m68ki_cpu.sp, g->r + 17, 7 * sizeof(uint32_t));
    memcpy(&m68ki_cpu.t1_flag, g->r + 24, 10 * sizeof(uint32_t));
    m68ki_cpu.sp[sp_active()] = stale;    /* S and M are those of the window, as before */
}

/* a checkpoint: every CK_EVERY-th instruction of the window and each one at the anchor */
typedef struct {
    uint32_t idx;               /* the instruction's number in the window */
    regs_t g;
    uint64_t t;                 /* cycles from the window's start to the instruction's */
    uint32_t nw, nio;           /* writes and watchdog writes before it */
    uint64_t cyc[BW_NREGIONS][2], wait[BW_NREGIONS][2];   /* buswait_stats before it */
} ins_t;
typedef struct { uint8_t *p; uint32_t last_rd; uint8_t start, shadow, rbw; } byte_t;   /* rbw: read before written */
typedef struct { uint32_t ins; uint16_t b; uint8_t v; } wr_t;
typedef struct { uint32_t ins; uint64_t t; uint32_t addr, v; int size; } io_t;

static ins_t *ins;              /* MAX_INS + 1 */
static unsigned n_ins, n_ck, n_bytes, n_w, n_io;   /* n_ins: instructions recorded */
static byte_t bytes[MAX_BYTES];
static wr_t wr[MAX_WRITES];
static io_t io[MAX_IO];
/* byte -> index in bytes[], valid where its stamp is the recording's */
#define KEYS (DPRAM_SIZE + SRAM_SIZE)
static uint32_t stamp[KEYS];
static uint16_t bidx[KEYS];
static uint32_t gen;

static uint32_t anchor = 1;
static int anchor_looked;
static uint64_t t0;             /* the recording's start, in cycles */
static uint64_t slice_at;       /* the cycle m68k_execute started at */
static uint64_t last_reads = ~0ull, last_iacks = ~0ull;   /* at the last anchor */
#define NOW() (slice_at + (uint64_t)m68k_cycles_run())
static unsigned passes, level0, fails, backoff;
/* The main loop's last pass, anchor to anchor, in cycles (0: not seen):
 * only a pass no longer than short_pass starts a recording.  A busy pass
 * (a command, the supervision, the profile generator) is long, and one
 * recorded costs the host more than the skip that may follow it gives back:
 * with the host sending back to back, pass after pass is busy. */
static uint64_t anchor_at, last_pass;
static uint64_t short_pass = SHORT_PASS_FIRST;
static uint64_t contention0, iacks0;
static int rec_dp;                /* the recording wrote the DPRAM */

/* the closed window */
static struct {
    int valid;
    unsigned n;                 /* checkpoints; ins[n] is the anchor again */
    uint32_t instr;             /* instructions */
    uint64_t P;                 /* its cycles */
    unsigned level;             /* interrupt request level it ran under */
    int dp_writes;              /* it writes the DPRAM (bus writes perf.c may watch) */
    uint64_t skipped;           /* cycles skipped with it so far */
    uint8_t ws[BW_NREGIONS][2];
} win;
static unsigned park;           /* the window's instruction the CPU stands before, if it followed it */
static unsigned n_anch, anch[REC_PASSES];   /* the window's instructions at the anchor */
static int16_t expect[MAX_BYTES];
static int exp_at = -1;          /* the checkpoint expect[] is at, -1 none */
typedef struct { const uint8_t *p; uint8_t v; } chk_t;
static chk_t *chk;
static unsigned chk_n[MAX_INS + 1];   /* checkpoint c's checks: chk[c * n_bytes ...], so many */
#define CHK_UNBUILT (~0u)

static int following;           /* the CPU follows the window towards checkpoint park */
static unsigned misses;         /* its PC seen with another state since */

static void watch(unsigned p)
{
    park = p;
    following = 0;
    mac4_idle_pc = win.valid ? ins[p].g.r[16] : anchor;
    mac4_hooks_update();
}

/* Nothing but the CPU itself acts on the window's state until the host, the
 * script or an interrupt diverts it (idle_diverted), so it gets there. */
static void follow(unsigned p)
{
    watch(p);
    following = 1;
    misses = 0;
}

static int allowed(void)
{
    sim_t *s = g_sim;
    return mac4_fast && !(mac4_profiling & ~MAC4_PROFILING_IDLE) && !mac4_gdb_on && !s->vcd && !s->sram_fault_mask &&
           !(s->sysctl & SYS_CTRL_OVERLAY) && !s->nactive && !CPU_STOPPED && !m68ki_cpu.nmi_pending;
}

static void rec_end(void)
{
    mac4_idle_rec = 0;
    mac4_profiling &= ~MAC4_PROFILING_IDLE;
    mac4_hooks_update();
    cpu_m68k_windows();
}

void idle_invalidate(void)
{
    if (mac4_idle_rec)
        rec_end();
    win.valid = 0;
    watch(0);
}

/* After a few failures in a row the anchor is passed over 2, 4 ... 64 times. */
static void note_failure(void)
{
    if (++fails > 2)
        backoff = fails > 8 ? 64 : 1u << (fails - 2);
}

static void rec_fail(void)
{
    rec_end();
    idle_stats.failed++;
    note_failure();
    watch(0);
}

static void rec_begin(void)
{
    if (!ins) {
        ins = malloc((MAX_INS + 1) * sizeof *ins);
        if (!ins) {
            anchor = 1;          /* no memory: no skip */
            mac4_idle_pc = 1;
            mac4_hooks_update();
            return;
        }
    }
    win.valid = 0;
    if (++gen == 0) {
        memset(stamp, 0, sizeof stamp);
        gen = 1;
    }
    n_ins = n_ck = n_bytes = n_w = n_io = 0;
    passes = 0;
    rec_dp = 0;
    t0 = sim_now(g_sim);
    level0 = CPU_INT_LEVEL;
    contention0 = buswait_stats.contention;
    iacks0 = buswait_stats.iacks;
    mac4_idle_rec = 1;
    mac4_profiling |= MAC4_PROFILING_IDLE;
    mac4_hooks_update();
    cpu_m68k_windows();     /* the SRAM's accesses through the callbacks, which report them */
    idle_stats.recordings++;
}

static int closed(void)
{
    regs_t g;
    regs_get(&g);
    if (memcmp(&g, &ins[0].g, sizeof g))
        return 0;
    for (unsigned b = 0; b < n_bytes; b++)
        if (bytes[b].rbw && *bytes[b].p != bytes[b].start)
            return 0;
    return 1;
}

/* The window is closed: its bus counts per instruction as prefix sums over
 * the slots (region, read/write) it uses; they must add up to what the
 * counters counted. */

/* buffers that only grow: a window is built at every tick */
static size_t chk_cap;
static int grow(void **buf, size_t *cap, size_t need)
{
    if (need <= *cap)
        return 1;
    void *n = realloc(*buf, need * 2);
    if (!n)
        return 0;
    *buf = n;
    *cap = need * 2;
    return 1;
}

static void bus_counts(ins_t *e)
{
    if (buswait_sync)
        buswait_sync();     /* the core's windows count for themselves */
    memcpy(e->cyc, buswait_stats.cycles, sizeof e->cyc);
    memcpy(e->wait, buswait_stats.wait, sizeof e->wait);
}

static int finish(void)
{
    unsigned n = n_ck;
    ins[n].idx = n_ins;
    ins[n].t = NOW() - t0;
    ins[n].nw = n_w;
    ins[n].nio = n_io;
    bus_counts(&ins[n]);
    regs_get(&ins[n].g);
    if (buswait_stats.contention != contention0 || buswait_stats.iacks != iacks0 || !ins[n].t)
        return 0;
    if (!grow((void **)&chk, &chk_cap, ((size_t)n * n_bytes + 1) * sizeof *chk))
        return 0;
    for (unsigned c = 0; c < n; c++)
        chk_n[c] = CHK_UNBUILT;
    exp_at = -1;
    win.n = n;
    win.instr = n_ins;
    win.P = ins[n].t;
    win.level = level0;
    memcpy(win.ws, buswait_cfg.ws, sizeof win.ws);
    win.dp_writes = rec_dp;
    n_anch = 0;
    for (unsigned i = 0; i < n; i++)
        if (ins[i].g.r[16] == anchor && n_anch < REC_PASSES)
            anch[n_anch++] = i;
    win.skipped = 0;
    win.valid = 1;
    /* half as long again as this window's passes is still an idle pass */
    short_pass = win.P / n_anch + win.P / n_anch / 2;
    return 1;
}

static int try_skip(unsigned pc);

/* at every anchor the hook sees: the length of the pass that ends here */
static void anchor_seen(void)
{
    uint64_t now = NOW();
    last_pass = anchor_at && now > anchor_at ? now - anchor_at : 0;
    anchor_at = now;
}

static int pass_was_short(void) { return last_pass && last_pass <= short_pass; }

static void rec_instr(unsigned pc)
{
    if (pc == anchor && n_ins > 0) {
        anchor_seen();
        passes++;
        if (closed()) {
            rec_end();
            if (finish()) {
                idle_stats.windows++;
                watch(0);
                try_skip(pc);
            } else {
                rec_fail();
            }
            return;
        }
        if (passes >= REC_PASSES) {      /* begin again here: the pass that started it may have been a busy one */
            rec_end();
            idle_stats.failed++;
            note_failure();
            if (backoff || !pass_was_short()) {
                watch(0);
                return;
            }
            rec_begin();
        }
    }
    if (n_ins >= MAX_INSTR || n_ck >= MAX_INS || CPU_INT_LEVEL != level0) {
        rec_fail();
        return;
    }
    if (n_ins % CK_EVERY == 0 || pc == anchor) {
        ins_t *e = &ins[n_ck++];
        e->idx = n_ins;
        regs_get(&e->g);
        e->t = NOW() - t0;
        e->nw = n_w;
        e->nio = n_io;
        bus_counts(e);
    }
    n_ins++;
}

/* ---- what the recorded instructions touch (cpu_m68k.c) ---------------------- */
/* The memory behind an address the window may touch, and its first key in
 * stamp[]; NULL for anything else (I/O, the vectors, the EPROM's copy). */
static inline uint8_t *mem_of(uint32_t a, unsigned n, unsigned *key)
{
    if (a - SRAM_BASE <= SRAM_SIZE - n) {
        *key = DPRAM_SIZE + (a - SRAM_BASE);
        return g_sim->sram + (a - SRAM_BASE);
    }
    if (a >= 0x400 && a <= DPRAM_SIZE - n && !(g_sim->sysctl & SYS_CTRL_OVERLAY)) {
        *key = a;
        return g_sim->dpram + a;
    }
    return NULL;
}

static inline int byte_of(uint8_t *p, unsigned key, int read)
{
    if (stamp[key] == gen)
        return bidx[key];
    if (n_bytes >= MAX_BYTES)
        return -1;
    stamp[key] = gen;
    bidx[key] = (uint16_t)n_bytes;
    bytes[n_bytes] = (byte_t){p, 0, *p, *p, (uint8_t)read};
    return (int)n_bytes++;
}

void idle_rec_read(uint32_t a, unsigned n)
{
    a &= 0xFFFFFF;
    if (a - EPROM_BASE < EPROM_SIZE)
        return;                 /* read-only */
    unsigned key;
    uint8_t *p = mem_of(a, n, &key);
    if (!p) {                   /* I/O */
        rec_fail();
        return;
    }
    for (unsigned i = 0; i < n; i++) {
        int b = byte_of(p + i, key + i, 1);
        if (b < 0 || p[i] != bytes[b].shadow) {   /* changed behind the CPU's back */
            rec_fail();
            return;
        }
        bytes[b].last_rd = n_ins - 1;
    }
}

void idle_rec_write(uint32_t a, uint32_t v, unsigned n)
{
    a &= 0xFFFFFF;
    if (a - WDG_KICK < 2) {
        if (n_io >= MAX_IO) {
            rec_fail();
            return;
        }
        io[n_io++] = (io_t){n_ins - 1, NOW() - t0, a, v, (int)n};
        return;
    }
    unsigned key;
    uint8_t *p = mem_of(a, n, &key);
    if (!p || n_w + n > MAX_WRITES) {
        rec_fail();
        return;
    }
    if (key < DPRAM_SIZE)
        rec_dp = 1;
    for (unsigned i = 0; i < n; i++) {
        int b = byte_of(p + i, key + i, 0);
        if (b < 0) {
            rec_fail();
            return;
        }
        uint8_t byte = (uint8_t)(v >> (8 * (n - 1 - i)));
        bytes[b].shadow = byte;
        wr[n_w++] = (wr_t){n_ins - 1, (uint16_t)b, byte};
    }
}

void idle_irq(void) { idle_diverted(); }

/* ---- the skip ------------------------------------------------------------------ */
/* The bytes the window from instruction p on depends on, as they are now. */
/* Checkpoint p's checks, built when first needed: the bytes the window
 * from there on reads and their values then (read before written: the value
 * read; written before p: the last value written). */
static void build_checks(unsigned p)
{
    /* expect[]: the bytes at checkpoint exp_at, moved on from there when it can */
    if (exp_at < 0 || (unsigned)exp_at > p) {
        for (unsigned b = 0; b < n_bytes; b++)
            expect[b] = bytes[b].rbw ? bytes[b].start : -1;
        exp_at = 0;
    }
    for (unsigned e = ins[exp_at].nw; e < ins[p].nw; e++)
        expect[wr[e].b] = wr[e].v;
    exp_at = (int)p;
    chk_t *c = chk + (size_t)p * n_bytes;
    unsigned k = 0;
    for (unsigned b = 0; b < n_bytes; b++)
        if (expect[b] >= 0 && bytes[b].last_rd >= ins[p].idx)
            c[k++] = (chk_t){bytes[b].p, (uint8_t)expect[b]};
    chk_n[p] = k;
}

static int bytes_ok(unsigned p)
{
    if (chk_n[p] == CHK_UNBUILT)
        build_checks(p);
    for (const chk_t *c = chk + (size_t)p * n_bytes, *e = c + chk_n[p]; c < e; c++)
        if (*c->p != c->v)
            return 0;
    return 1;
}

static void apply_writes(unsigned from, unsigned to)
{
    for (unsigned e = from; e < to; e++)
        *bytes[wr[e].b].p = wr[e].v;
}

static int state_ok(unsigned p)
{
    regs_t g;
    regs_get(&g);
    return !memcmp(&g, &ins[p].g, sizeof g) && bytes_ok(p);
}

static void start_recording(unsigned pc)
{
    /* not after a pass that read a device or was interrupted: the next one
     * supervises the tick or works on what it read */
    int quiet = bus_reads == last_reads && buswait_stats.iacks == last_iacks;
    last_reads = bus_reads;
    last_iacks = buswait_stats.iacks;
    anchor_seen();
    if (!quiet || !pass_was_short() || !allowed())
        return;
    if (backoff) {
        backoff--;
        return;
    }
    rec_begin();
    if (mac4_idle_rec)
        rec_instr(pc);
}

static int try_skip(unsigned pc)
{
    unsigned p = park;
    if (ins[p].g.r[16] != pc || !state_ok(p)) {
        /* following the window from a checked state, the CPU may pass the
         * checkpoint's PC before it stands at the checkpoint (a loop) */
        if (following && pc != anchor && ++misses < 64)
            return 0;
        watch(0);
        if (pc != anchor)
            return 0;
        unsigned j = 0;
        while (j < n_anch && !state_ok(anch[j]))
            j++;
        if (j == n_anch || memcmp(win.ws, buswait_cfg.ws, sizeof win.ws)) {
            /* a window that skipped less than it took to record counts as a
             * failure: with the host sending back to back a command changes
             * the queue it reads before it pays */
            if (win.skipped < REC_COST * win.P)
                note_failure();
            else
                fails = 0;
            win.valid = 0;       /* not the window's state any more: record anew */
            watch(0);
            start_recording(pc);
            return 0;
        }
        p = anch[j];
    }
    sim_t *s = g_sim;
    if (!allowed() || CPU_INT_LEVEL != win.level || GET_CYCLES() <= 0 || (win.dp_writes && s->on_bus_write)) {
        watch(0);
        return 0;
    }
    if (buswait_host_free() > sim_now(s)) {
        /* a VME host access holds a DPRAM word: the next checkpoint */
        follow(p + 1 < win.n ? p + 1 : 0);
        return 0;
    }
    /* the last instruction the slice starts: at window k, instruction i */
    unsigned n = win.n;
    uint64_t P = win.P, T = ins[p].t + (uint64_t)GET_CYCLES();
    uint64_t k = (T - 1) / P, rem = T - k * P;
    unsigned lo = 0, hi = n;     /* the largest i with ins[i].t < rem */
    while (hi - lo > 1) {
        unsigned mid = (lo + hi) / 2;
        if (ins[mid].t < rem)
            lo = mid;
        else
            hi = mid;
    }
    unsigned i = lo;
    if (k == 0 && i <= p) {
        follow(p + 1 < n ? p + 1 : 0);
        return 0;
    }
    /* memory: the last value of every byte written on the way */
    if (k == 0) {
        apply_writes(ins[p].nw, ins[i].nw);
    } else {
        apply_writes(ins[p].nw, ins[n].nw);
        if (k >= 2)
            apply_writes(0, ins[n].nw);
        apply_writes(0, ins[i].nw);
    }
    /* bus counts */
    for (unsigned r = 0; r < BW_NREGIONS; r++)
        for (unsigned w = 0; w < 2; w++) {
            buswait_stats.cycles[r][w] += k * (ins[n].cyc[r][w] - ins[0].cyc[r][w]) + ins[i].cyc[r][w] - ins[p].cyc[r][w];
            buswait_stats.wait[r][w] += k * (ins[n].wait[r][w] - ins[0].wait[r][w]) + ins[i].wait[r][w] - ins[p].wait[r][w];
        }
    /* The watchdog's state is the time of its last write: that one, at its
     * cycle, through the bus as the CPU made it. */
    uint64_t used = 0, base = ins[p].t;
    int last = -1;
    uint64_t last_j = 0;
    if (ins[i].nio > 0 && (k > 0 || ins[i].nio > ins[p].nio)) {
        last = (int)ins[i].nio - 1;
        last_j = k;
    } else if (k > 0 && ins[n].nio > (k == 1 ? ins[p].nio : 0)) {
        last = (int)ins[n].nio - 1;
        last_j = k - 1;
    }
    if (last >= 0) {
        uint64_t at = last_j * P + io[last].t - base;
        USE_CYCLES((int)at);
        used = at;
        bus_write(s, io[last].addr, io[last].v, io[last].size);
    }
    uint64_t end = k * P + ins[i].t - base;
    USE_CYCLES((int)(end - used));
    regs_set(&ins[i].g);
    idle_stats.skips++;
    win.skipped += end;
    idle_stats.cycles += end;
    idle_stats.instructions += k * win.instr + ins[i].idx - ins[p].idx;
    follow(i + 1 < n ? i + 1 : 0);  /* the slice ends before it: where the next one checks again */
    return 1;
}

void mac4_idle_instr(unsigned pc)
{
    if (mac4_idle_rec) {
        /* most recorded instructions are neither checkpoints nor the anchor */
        if (pc != anchor && n_ins % CK_EVERY != 0 && n_ins < MAX_INSTR && CPU_INT_LEVEL == level0) {
            n_ins++;
            return;
        }
        rec_instr(pc);
    }
    else if (win.valid)
        try_skip(pc);
    else if (pc == anchor)
        start_recording(pc);
}

/* A new slice: between slices the host and the devices may have changed
 * anything, so the CPU's state is checked again before the next skip. */
void idle_slice_start(uint64_t at)
{
    slice_at = at;
    if (mac4_idle_rec && !allowed())
        rec_fail();
}

/* The host or the script wrote the DPRAM, an interrupt came: the CPU may
 * leave the window, and it is caught again at the anchor. */
void idle_diverted(void)
{
    if (mac4_idle_rec)
        rec_fail();
    else if (win.valid)
        watch(0);
}

void idle_reset(void)
{
    dp_written = idle_diverted;
    if (!anchor_looked) {
        anchor_looked = 1;
        uint32_t a;
        if (!profile_symbol("fw_main_step", &a) && !(a & 1))
            anchor = a;
    }
    fails = backoff = 0;
    anchor_at = last_pass = 0;
    short_pass = SHORT_PASS_FIRST;
    idle_invalidate();
}

void idle_print_stats(FILE *f)
{
    fprintf(f, "idle-skip recordings=%llu windows=%llu failed=%llu skips=%llu instructions=%llu cycles=%llu\n",
            (unsigned long long)idle_stats.recordings, (unsigned long long)idle_stats.windows,
            (unsigned long long)idle_stats.failed, (unsigned long long)idle_stats.skips,
            (unsigned long long)idle_stats.instructions, (unsigned long long)idle_stats.cycles);
}
