/*
 * busvectors.c - the bus timing model (harness/buswait.c) against the
 * 68000 reference vectors (SingleStepTests m68000, ../shared/m68000-tests,
 * format in its README.md): every test is run through the Musashi core as
 * mac4sim builds it, once with no wait states and once with a different
 * number of wait states for each region of hal/mac4_map.h, reads and writes
 * apart, charged per bus cycle as in mac4sim (buswait_charge).  A test must
 * then take its reference length plus, for every bus transaction of the
 * reference, the wait states of that transaction's region and kind.
 *
 *   build/busvectors FILE...      prints per file and a summary line
 *
 * Per test three things are told apart: the charge itself (the cycles with
 * wait states minus those without must be the wait states of the bus cycles
 * the core made: "mechanism"), the core's bus cycles per region against the
 * reference's ("bus": where they differ, so do the wait states charged -
 * the conformance lane's business, not this one's), and the core's length
 * without wait states against the reference's ("length").  Skipped, and
 * counted: TAS and TRAPV (the reference's caveats), STOP (the core then waits for an
 * interrupt: its length is the rest of the slice) and the tests that end in
 * an address error.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "m68k.h"
#include "m68kcpu.h"
#include "buswait.h"
#include "sstfile.h"

static uint8_t *mem;                     /* 16 MiB, the 24-bit space */
static uint64_t made[BW_NREGIONS][2];    /* the core's bus cycles in this test */

/* musashi_cnf.h's hooks */
int mac4_profiling;
int mac4_gdb_on;                                    /* no gdb stub here */
unsigned mac4_idle_pc = 1;                          /* no idle skip here: odd, never a PC */
unsigned mac4_hook_lo = 1, mac4_hook_span;             /* the hook: PC 1 alone (musashi_cnf.h) */
void mac4_idle_instr(unsigned pc) { (void)pc; }
int mac4_gdb_instr(unsigned pc) { (void)pc; return 0; }
void mac4_profile_instr(unsigned pc) { (void)pc; }
int mac4_int_ack(int level) { (void)level; return (int)M68K_INT_ACK_AUTOVECTOR; }
void mac4_rte(void) {}
int mac4_illegal(int opcode) { (void)opcode; return 0; }
void mac4_reset_instr(void) {}
static void charge(unsigned a, int write, unsigned n);
/* the bus cycles the core makes no memory callback for (cpu_m68k.c) */
void mac4_bus_extra(unsigned address, int n)
{
    if (n > 0) {
        charge(address, 0, (unsigned)n);
    } else if (n < 0) {
        made[buswait_page[(address & 0xFFFFFF) >> 8]][0] -= (unsigned)-n;
        ADD_CYCLES((int)buswait_refund(address, (unsigned)-n));
    }
}

static void charge(unsigned a, int write, unsigned n)
{
    a &= 0xFFFFFF;
    made[buswait_page[a >> 8]][write] += n;
    unsigned w = buswait_charge(a, write, n);     /* as cpu_m68k.c's bus_cycles */
    if (w)
        USE_CYCLES((int)w);
}
static unsigned rd(unsigned a, int n)
{
    unsigned v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | mem[(a + (unsigned)i) & 0xFFFFFF];
    return v;
}
static void wr(unsigned a, unsigned v, int n)
{
    for (int i = n - 1; i >= 0; i--, v >>= 8)
        mem[(a + (unsigned)i) & 0xFFFFFF] = (uint8_t)v;
}
unsigned int m68k_read_memory_8(unsigned int a) { charge(a, 0, 1); return rd(a, 1); }
unsigned int m68k_read_memory_16(unsigned int a) { charge(a, 0, 1); return rd(a, 2); }
unsigned int m68k_read_memory_32(unsigned int a) { charge(a, 0, 2); return rd(a, 4); }
void m68k_write_memory_8(unsigned int a, unsigned int v) { charge(a, 1, 1); wr(a, v, 1); }
void m68k_write_memory_16(unsigned int a, unsigned int v) { charge(a, 1, 1); wr(a, v, 2); }
void m68k_write_memory_32(unsigned int a, unsigned int v) { charge(a, 1, 2); wr(a, v, 4); }
unsigned int m68k_read_disassembler_8(unsigned int a) { return rd(a, 1); }
unsigned int m68k_read_disassembler_16(unsigned int a) { return rd(a, 2); }
unsigned int m68k_read_disassembler_32(unsigned int a) { return rd(a, 4); }

/* ---- a test: the vector files through tests/conformance/sstfile.h ------- */
static void load(const sst_state_t *s)
{
    for (uint32_t i = 0; i < s->nram; i++) {
        const uint8_t *e = s->ram + 6 * i;
        wr(sst_le32(e) & 0xFFFFFE, sst_le16(e + 4), 2);
    }
    /* the two prefetched words are the instruction's first: at pc - 4 */
    wr((s->reg[R_PC] - 4) & 0xFFFFFE, s->prefetch[0], 2);
    wr((s->reg[R_PC] - 2) & 0xFFFFFE, s->prefetch[1], 2);
    m68k_set_reg(M68K_REG_SR, s->reg[R_SR]);
    m68k_set_reg(M68K_REG_ISP, s->reg[R_SSP]);
    m68k_set_reg(M68K_REG_USP, s->reg[R_USP]);
    for (int i = 0; i < 8; i++)
        m68k_set_reg((m68k_register_t)(M68K_REG_D0 + i), s->reg[R_D0 + i]);
    for (int i = 0; i < 7; i++)
        m68k_set_reg((m68k_register_t)(M68K_REG_A0 + i), s->reg[R_A0 + i]);
    m68k_set_reg(M68K_REG_A7, (s->reg[R_SR] & 0x2000) ? s->reg[R_SSP] : s->reg[R_USP]);
    m68k_set_reg(M68K_REG_PC, s->reg[R_PC] - 4);
}

static int run_one(const sst_state_t *init, uint64_t bus[BW_NREGIONS][2])
{
    memset(made, 0, sizeof made);
    CPU_STOPPED = 0;                    /* a STOP before must not hold this one */
    load(init);
    RESET_CYCLES = 0;
    int c = m68k_execute(1);
    memcpy(bus, made, sizeof made);
    return c;
}

static struct { long tests, exact, mech, bus, count, length, skipped; } tot;

/* the reference's bus cycles of a test by region and kind */
static void count_tx(void *ctx, unsigned kind, uint32_t address)
{
    uint64_t (*ref_bus)[2] = ctx;
    if (kind == SST_READ || kind == SST_WRITE)
        ref_bus[buswait_page[(address & 0xFFFFFF) >> 8]][kind == SST_WRITE]++;
}

static void file(const char *path, const buswait_cfg_t *zero, const buswait_cfg_t *ws)
{
    size_t n;
    uint8_t *buf = sst_slurp("busvectors", path, &n);
    sst_reader_t r;
    uint32_t count;
    if (!buf || sst_open(&r, "busvectors", path, buf, n, &count))
        exit(1);
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    /* TAS and TRAPV: the reference's own caveats; STOP: the core then waits
     * for an interrupt, and its length is the rest of the slice */
    int skip_file = !strncmp(base, "TAS.", 4) || !strncmp(base, "TRAPV.", 6) || !strncmp(base, "STOP.", 5);
    long t = 0, exact = 0, mech = 0, busd = 0, cntd = 0, lend = 0, skipped = 0;
    for (uint32_t k = 0; k < count; k++) {
        sst_test_t test;
        uint64_t ref_bus[BW_NREGIONS][2] = {{0}};
        if (sst_read_test(&r, &test, count_tx, ref_bus))
            exit(1);
        if (skip_file || test.tas || test.addr_error) {
            skipped++;
            continue;
        }
        const char *name = test.name;
        uint32_t ref_len = test.cycles;
        t++;
        uint64_t b0[BW_NREGIONS][2], b1[BW_NREGIONS][2];
        buswait_cfg = *zero;
        int c0 = run_one(&test.init, b0);
        buswait_cfg = *ws;
        int c1 = run_one(&test.init, b1);
        uint64_t by_core = 0, by_ref = 0, n_core[2] = {0, 0}, n_ref[2] = {0, 0};
        int same_bus = 1;
        for (int g = 0; g < BW_NREGIONS; g++)
            for (int w = 0; w < 2; w++) {
                by_core += b0[g][w] * ws->ws[g][w];
                by_ref += ref_bus[g][w] * ws->ws[g][w];
                n_core[w] += b0[g][w];
                n_ref[w] += ref_bus[g][w];
                if (b0[g][w] != ref_bus[g][w])
                    same_bus = 0;
            }
        cntd += n_core[0] != n_ref[0] || n_core[1] != n_ref[1];
        int m_ok = (uint64_t)(c1 - c0) == by_core;
        int exact_ok = (uint64_t)c1 == ref_len + by_ref;
        mech += !m_ok;
        busd += !same_bus;
        lend += (uint32_t)c0 != ref_len;
        exact += exact_ok;
        if (!m_ok)
            printf("busvectors: %s: mechanism: %d -> %d cycles, the core's bus cycles say +%llu\n", name, c0, c1,
                   (unsigned long long)by_core);
        else if (same_bus && (uint64_t)(c1 - c0) != by_ref)
            printf("busvectors: %s: +%d cycles, the reference's bus cycles say +%llu\n", name, c1 - c0,
                   (unsigned long long)by_ref);
    }
    if (sst_close(&r))
        exit(1);
    printf("busvectors-file %s tests=%ld exact=%ld mechanism_failed=%ld bus_differs=%ld count_differs=%ld "
           "length_differs=%ld skipped=%ld\n", base, t, exact, mech, busd, cntd, lend, skipped);
    tot.tests += t;
    tot.exact += exact;
    tot.mech += mech;
    tot.bus += busd;
    tot.count += cntd;
    tot.length += lend;
    tot.skipped += skipped;
    free(buf);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: busvectors FILE.json.bin...\n");
        return 1;
    }
    mem = calloc(1u << 24, 1);
    if (!mem)
        return 1;
    buswait_init();
    m68k_init();
    m68k_set_cpu_type(M68K_CPU_TYPE_68000);
    m68k_pulse_reset();
    buswait_cfg_t zero, ws;
    char err[200];
    buswait_parse("0", err, sizeof err);
    zero = buswait_cfg;
    /* every region its own number, reads and writes apart */
    for (int g = 0; g < BW_NREGIONS; g++) {
        ws.ws[g][0] = (uint8_t)(1 + g);
        ws.ws[g][1] = (uint8_t)(2 + 2 * g);
    }
    ws.iack = zero.iack;
    ws.iack_vectored_wait = zero.iack_vectored_wait;
    ws.host_clocks = zero.host_clocks;
    for (int i = 1; i < argc; i++)
        file(argv[i], &zero, &ws);
    printf("busvectors: %ld tests, %ld exact (length + wait states of every bus cycle by region), "
           "%ld mechanism failures, %ld where the core's bus cycles by region differ from the reference's "
           "(%ld in number), %ld where its length differs, %ld skipped (TAS, TRAPV, STOP, address errors)\n",
           tot.tests, tot.exact, tot.mech, tot.bus, tot.count, tot.length, tot.skipped);
    return tot.mech ? 2 : 0;
}
