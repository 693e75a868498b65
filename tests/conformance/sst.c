/*
 * sst.c - the conformance lane (docs/cpu-timing.md): every test of the
 * SingleStepTests m68000 vector files (the binary format of their README)
 * through the Musashi core exactly as mac4sim builds it (the same objects,
 * compiled with harness/musashi_cnf.h: 68000, address errors on), one
 * instruction each; then the registers, SR, PC, RAM, the cycle count and
 * the number of bus cycles (reads, writes) compared with the reference.
 *
 *   sst [-n N] [-v] FILE|DIR...    N mismatched tests shown per file (default
 *                                  10, 0: all); -v names every test run
 *
 * Bus cycles are counted as the emulator's bus sees them (docs/cpu-timing.md,
 * "Bus cycles"): a byte or word callback is one bus cycle, a long callback
 * two, and mac4_bus_extra() (harness/musashi_cnf.h) the bus cycles the
 * patched core reports without a data callback (prefetch refills, the read
 * before a CLR's write, ...).
 *
 * Skipped, a fixed list: the files TAS (its read-modify-write timing is not
 * in the reference) and TRAPV (doubtful in the reference); tests whose
 * reference ends in an address error (counted on a line of their own).
 * Not compared: N and V after ABCD, SBCD, NBCD (undefined by Motorola).
 * Exit status 0 when nothing failed, 1 on a mismatch, 2 on bad input.
 */
#include <dirent.h>
#include <errno.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "m68k.h"
#include "m68kcpu.h"
#include "sstfile.h"

/* ---- the hooks harness/musashi_cnf.h names (cpu_m68k.c gives mac4sim's) -- */
int mac4_profiling;
int mac4_gdb_on;                                    /* no gdb stub here */
unsigned mac4_idle_pc = 1;                          /* no idle skip here: odd, never a PC */
unsigned mac4_hook_lo = 1, mac4_hook_span;             /* the hook: PC 1 alone (musashi_cnf.h) */
void mac4_idle_instr(unsigned pc) { (void)pc; }
int mac4_gdb_instr(unsigned pc) { (void)pc; return 0; }
void mac4_profile_instr(unsigned pc) { (void)pc; }
static unsigned nacks;
int mac4_int_ack(int level) { (void)level; nacks++; return (int)M68K_INT_ACK_AUTOVECTOR; }
void mac4_rte(void) {}
int mac4_illegal(int opcode) { (void)opcode; return 0; }
void mac4_reset_instr(void) {}
static unsigned nreads, nwrites;   /* bus cycles of the instruction */
void mac4_bus_extra(unsigned address, int n)
{
    (void)address;
    nreads += (unsigned)n;
}

/* ---- memory: the 68000's 16 MiB, cleared where a test touched it --------- */
static uint8_t mem[1u << 24];
#define MAXTOUCH 65536
static uint32_t touched[MAXTOUCH];
static unsigned ntouched;

static void touch(uint32_t a)
{
    if (ntouched < MAXTOUCH)
        touched[ntouched++] = a & 0xFFFFFF;
}
static unsigned rd(unsigned a) { return mem[a & 0xFFFFFF]; }
static void wr(unsigned a, unsigned v) { touch(a); mem[a & 0xFFFFFF] = (uint8_t)v; }

unsigned int m68k_read_memory_8(unsigned int a) { nreads += 1; return rd(a); }
unsigned int m68k_read_memory_16(unsigned int a) { nreads += 1; return rd(a) << 8 | rd(a + 1); }
unsigned int m68k_read_memory_32(unsigned int a)
{
    nreads += 2;
    return rd(a) << 24 | rd(a + 1) << 16 | rd(a + 2) << 8 | rd(a + 3);
}
void m68k_write_memory_8(unsigned int a, unsigned int v) { nwrites += 1; wr(a, v); }
void m68k_write_memory_16(unsigned int a, unsigned int v)
{
    nwrites += 1;
    wr(a, v >> 8);
    wr(a + 1, v);
}
void m68k_write_memory_32(unsigned int a, unsigned int v)
{
    nwrites += 2;
    wr(a, v >> 24);
    wr(a + 1, v >> 16);
    wr(a + 2, v >> 8);
    wr(a + 3, v);
}
unsigned int m68k_read_disassembler_8(unsigned int a) { return rd(a); }
unsigned int m68k_read_disassembler_16(unsigned int a) { return rd(a) << 8 | rd(a + 1); }
unsigned int m68k_read_disassembler_32(unsigned int a) { return rd(a) << 24 | rd(a + 1) << 16 | rd(a + 2) << 8 | rd(a + 3); }

/* ---- one test --------------------------------------------------------------- */
typedef struct {
    const char *file;
    unsigned run, failed, skipped, aerr;
    unsigned by_field[NREG + 4];   /* registers, ram, cycles, reads, writes */
    unsigned shown, max_shown;
    uint32_t sr_mask;              /* SR bits compared */
} fstat_t;
enum { F_RAM = NREG, F_CYCLES, F_READS, F_WRITES };
static const char *field_name(int f)
{
    static const char *const extra[] = {"ram", "cycles", "reads", "writes"};
    return f < NREG ? sst_reg_name[f] : extra[f - NREG];
}

static int mismatch(fstat_t *fs, const sst_test_t *t, int field, const char *fmt, ...)
{
    fs->by_field[field]++;
    if (fs->max_shown == 0 || fs->shown < fs->max_shown) {
        va_list ap;
        va_start(ap, fmt);
        printf("  MISMATCH %s \"%s\": %s ", fs->file, t->name, field_name(field));
        vprintf(fmt, ap);
        printf("\n");
        va_end(ap);
    }
    return 1;
}

static void load_ram(const sst_state_t *s)
{
    for (uint32_t i = 0; i < s->nram; i++) {
        uint32_t a = sst_le32(s->ram + 6 * i) & 0xFFFFFF;
        uint16_t w = sst_le16(s->ram + 6 * i + 4);
        wr(a, w >> 8);
        wr(a + 1, w);
    }
}

static int run_test(fstat_t *fs, const sst_test_t *t)
{
    const sst_state_t *in = &t->init, *out = &t->fin;
    load_ram(in);
    uint32_t pc = in->reg[R_PC] - 4;   /* the reference's pc is 4 ahead (two prefetched words) */
    wr(pc, in->prefetch[0] >> 8);
    wr(pc + 1, in->prefetch[0]);
    wr(pc + 2, in->prefetch[1] >> 8);
    wr(pc + 3, in->prefetch[1]);

    m68ki_cpu.stopped = 0;
    m68ki_cpu.run_mode = RUN_MODE_NORMAL;
    m68k_set_reg(M68K_REG_SR, in->reg[R_SR]);
    m68k_set_reg(M68K_REG_USP, in->reg[R_USP]);
    m68k_set_reg(M68K_REG_ISP, in->reg[R_SSP]);
    for (int i = 0; i < 8; i++)
        m68k_set_reg((m68k_register_t)(M68K_REG_D0 + i), in->reg[R_D0 + i]);
    for (int i = 0; i < 7; i++)
        m68k_set_reg((m68k_register_t)(M68K_REG_A0 + i), in->reg[R_A0 + i]);
    m68k_set_reg(M68K_REG_PC, pc);

    nreads = nwrites = 0;
    int cycles = m68k_execute(1);

    uint32_t seen[NREG];
    for (int i = 0; i < 8; i++)
        seen[R_D0 + i] = m68k_get_reg(NULL, (m68k_register_t)(M68K_REG_D0 + i));
    for (int i = 0; i < 7; i++)
        seen[R_A0 + i] = m68k_get_reg(NULL, (m68k_register_t)(M68K_REG_A0 + i));
    seen[R_USP] = m68k_get_reg(NULL, M68K_REG_USP);
    seen[R_SSP] = m68k_get_reg(NULL, M68K_REG_ISP);
    seen[R_SR] = m68k_get_reg(NULL, M68K_REG_SR);
    /* the reference's pc is where the prefetch goes on, 4 ahead of Musashi's;
     * after STOP the 68000 has not refilled its queue */
    seen[R_PC] = (m68k_get_reg(NULL, M68K_REG_PC) + (m68ki_cpu.stopped ? 0 : 4)) & 0xFFFFFF;

    int bad = 0;
    for (int i = 0; i < NREG; i++) {
        uint32_t e = out->reg[i], s = seen[i];
        if (i == R_SR) {
            e &= fs->sr_mask;
            s &= fs->sr_mask;
        }
        if (i == R_PC)
            e &= 0xFFFFFF;
        if (e != s)
            bad |= mismatch(fs, t, i, "expected $%08X seen $%08X", e, s);
    }
    for (uint32_t i = 0; i < out->nram; i++) {
        uint32_t a = sst_le32(out->ram + 6 * i) & 0xFFFFFF;
        unsigned e = sst_le16(out->ram + 6 * i + 4), s = rd(a) << 8 | rd(a + 1);
        if (e != s)
            bad |= mismatch(fs, t, F_RAM, "[$%06X] expected $%04X seen $%04X", a, e, s);
    }
    if ((uint32_t)cycles != t->cycles)
        bad |= mismatch(fs, t, F_CYCLES, "expected %u seen %d", t->cycles, cycles);
    if (nreads != t->reads)
        bad |= mismatch(fs, t, F_READS, "expected %u seen %u", t->reads, nreads);
    if (nwrites != t->writes)
        bad |= mismatch(fs, t, F_WRITES, "expected %u seen %u", t->writes, nwrites);

    for (unsigned i = 0; i < ntouched; i++)
        mem[touched[i]] = 0;
    ntouched = 0;
    return bad;
}

/* ---- files ---------------------------------------------------------------- */
static unsigned tot_pass, tot_fail, tot_skip, tot_aerr;
static char aerr_line[8192];
static int max_shown = 10;
static int verbose;

/* The instruction group of a file: its name up to ".json.bin". */
static void group_of(const char *path, char *out, size_t n)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    snprintf(out, n, "%s", b);
    char *e = strstr(out, ".json.bin");
    if (e)
        *e = 0;
}

static int run_file(const char *path)
{
    size_t len;
    uint8_t *buf = sst_slurp("sst", path, &len);
    if (!buf)
        return -1;
    char group[64];
    group_of(path, group, sizeof group);
    sst_reader_t r;
    fstat_t fs;
    memset(&fs, 0, sizeof fs);
    fs.file = group;
    fs.max_shown = (unsigned)max_shown;
    fs.sr_mask = 0xFFFF;
    int skip_file = !strcmp(group, "TAS") || !strcmp(group, "TRAPV");
    if (!strcmp(group, "ABCD") || !strcmp(group, "SBCD") || !strcmp(group, "NBCD"))
        fs.sr_mask &= ~0x000Au;   /* N and V: undefined (M68000PRM) */
    uint32_t count;
    if (sst_open(&r, "sst", path, buf, len, &count)) {
        free(buf);
        return -1;
    }
    sst_test_t t;
    for (uint32_t i = 0; i < count; i++) {
        if (sst_read_test(&r, &t, NULL, NULL)) {
            free(buf);
            return -1;
        }
        if (skip_file) {
            fs.skipped++;
            continue;
        }
        if (t.addr_error) {
            fs.aerr++;
            continue;
        }
        fs.run++;
        if (verbose)
            printf("  TEST %s \"%s\"\n", group, t.name);
        if (run_test(&fs, &t)) {
            fs.failed++;
            if (max_shown == 0 || fs.shown < (unsigned)max_shown)
                fs.shown++;
        }
    }
    if (sst_close(&r)) {
        free(buf);
        return -1;
    }
    free(buf);
    printf("%-12s %4u run, %4u failed", group, fs.run, fs.failed);
    if (fs.skipped)
        printf(", %u skipped", fs.skipped);
    if (fs.aerr)
        printf(", %u address error", fs.aerr);
    int first = 1;
    for (int f = 0; f < NREG + 4; f++)
        if (fs.by_field[f]) {
            printf("%s%s %u", first ? ": " : ", ", field_name(f), fs.by_field[f]);
            first = 0;
        }
    printf("\n");
    tot_pass += fs.run - fs.failed;
    tot_fail += fs.failed;
    tot_skip += fs.skipped + fs.aerr;
    tot_aerr += fs.aerr;
    if (fs.aerr) {
        size_t l = strlen(aerr_line);
        snprintf(aerr_line + l, sizeof aerr_line - l, " %s %u", group, fs.aerr);
    }
    return 0;
}

/* The interrupt is in no vector file: MC68000UM table 8-14 gives the
 * autovectored interrupt 44 cycles, 5 reads (the acknowledge, the vector's
 * two words, the refill's two) and 3 writes.  The core counts the refill's
 * second word through mac4_bus_extra(); the acknowledge is the int_ack
 * callback's (harness/cpu_m68k.c).  Level 6 from a NOP, into a NOP: the
 * slice of one instruction runs the interrupt and the handler's NOP. */
static int check_interrupt(void)
{
    uint32_t handler = 0x1000, pc = 0x2000, ssp = 0x8000;
    wr(0x78, 0); wr(0x79, 0); wr(0x7A, handler >> 8); wr(0x7B, handler);   /* vector 30 */
    wr(handler, 0x4E); wr(handler + 1, 0x71);
    wr(pc, 0x4E); wr(pc + 1, 0x71);
    m68ki_cpu.stopped = 0;
    m68k_set_reg(M68K_REG_SR, 0x2000);
    m68k_set_reg(M68K_REG_ISP, ssp);
    m68k_set_reg(M68K_REG_PC, pc);
    nreads = nwrites = nacks = 0;
    m68k_set_irq(6);
    int cycles = m68k_execute(1);
    m68k_set_irq(0);
    unsigned sp = m68k_get_reg(NULL, M68K_REG_ISP), npc = m68k_get_reg(NULL, M68K_REG_PC);
    for (unsigned i = 0; i < ntouched; i++)
        mem[touched[i]] = 0;
    ntouched = 0;
    int ok = cycles == 44 + 4 && nreads + nacks == 5 + 1 && nacks == 1 && nwrites == 3 && sp == ssp - 6 &&
             npc == handler + 2;
    if (!ok)
        printf("  MISMATCH interrupt \"level 6 autovector\": expected 48 cycles, 1 acknowledge, 5+1 reads, "
               "3 writes, pc $%06X; seen %d, %u, %u+%u, %u, pc $%06X\n",
               handler + 2, cycles, nacks, nreads, nacks, nwrites, npc);
    printf("interrupt    (MC68000UM table 8-14, not in the vectors): %s\n", ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static int run_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "sst: %s: %s\n", dir, strerror(errno));
        return -1;
    }
    char *names[1024];
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) && n < 1024) {
        size_t l = strlen(e->d_name);
        if (l > 9 && !strcmp(e->d_name + l - 9, ".json.bin")) {
            size_t pl = strlen(dir) + l + 2;
            names[n] = malloc(pl);
            snprintf(names[n], pl, "%s/%s", dir, e->d_name);
            n++;
        }
    }
    closedir(d);
    if (n == 0) {
        fprintf(stderr, "sst: %s: no *.json.bin vector files\n", dir);
        return -1;
    }
    qsort(names, (size_t)n, sizeof names[0], cmp_str);
    int rc = 0;
    for (int i = 0; i < n; i++) {
        if (run_file(names[i]))
            rc = -1;
        free(names[i]);
    }
    return rc;
}

int main(int argc, char **argv)
{
    int i = 1;
    for (; i < argc && argv[i][0] == '-'; i++) {
        if (!strcmp(argv[i], "-n") && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 0) {
                fprintf(stderr, "sst: -n wants a count, not '%s'\n", argv[i]);
                return 2;
            }
            max_shown = (int)v;
        } else if (!strcmp(argv[i], "-v")) {
            verbose = 1;
        } else {
            fprintf(stderr, "usage: sst [-n N] [-v] FILE|DIR...\n");
            return 2;
        }
    }
    if (i == argc) {
        fprintf(stderr, "usage: sst [-n N] [-v] FILE|DIR...\n");
        return 2;
    }
    m68k_init();
    m68k_set_cpu_type(M68K_CPU_TYPE_68000);
    m68k_pulse_reset();
    m68ki_cpu.reset_cycles = 0;   /* the reset's own cycles are not the first test's */
    int rc = 0;
    for (; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st)) {
            fprintf(stderr, "sst: %s: %s\n", argv[i], strerror(errno));
            return 2;
        }
        if ((S_ISDIR(st.st_mode) ? run_dir(argv[i]) : run_file(argv[i])) != 0)
            rc = 2;
    }
    if (rc)
        return rc;
    tot_fail += (unsigned)check_interrupt();
    printf("address error: %u tests skipped (they end in an address error):%s\n", tot_aerr,
           tot_aerr ? aerr_line : " none");
    printf("conformance: %u passed, %u failed, %u skipped\n", tot_pass, tot_fail, tot_skip);
    return tot_fail ? 1 : 0;
}
