/*
 * floorrun.c - runs the floor routines of bench/floor (README.md there) on
 * the emulator's 68000 and holds them to the firmware's C.
 *
 *   floorrun-CARD DIR --check [N] [--seed S] [--routine NAME] [--bin FILE]
 *       N random inputs per routine (default 2000), each through the
 *       routine DIR/NAME.bin (or FILE) and through the firmware's C
 *       (servo.h, measure.h, ... compiled for the host); any difference in
 *       the memory the routine may write, the registers or the CPU's
 *       registers fails: "MISMATCH ..." and exit status 1.
 *   floorrun-CARD DIR --measure [N]
 *       per scenario of tools/perfscen.py the card's routine has: the
 *       worst cycles over N inputs of that scenario's path (default 200),
 *       "floor CARD KIND SCENARIO routine=NAME cycles=C" - and the check
 *       of those inputs as above; for the command path the mean of a
 *       command pass beyond the least of an idle pass (min, max, mean and
 *       idle beside it).
 *   floorrun-CARD --list    the scenarios and routines of this card
 *   --wait-states SPEC      the bus model as mac4sim's option of that name
 *   --trace                 every instruction of the routine and its cycles
 *                           (the last one's are not shown: RTE/RTS)
 *
 * The CPU is the emulator's (the same Musashi objects and patches as
 * build/mac4sim), its bus cycles charged with the wait states of
 * harness/buswait.c for the card's map (hal/mac4_map.h), as cpu_m68k.c
 * does - but for the DPRAM's contention with a VME host, which no routine
 * meets: the tick touches the DPRAM only for its vector.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "m68k.h"
#include "m68kcpu.h"
#include "buswait.h"
#include "hal.h"
#include "floor.h"
#include "floorrun.h"

uint8_t *fmem;
devstate_t dev;
#define A24(a) ((a) & 0xFFFFFFu)

uint8_t m_rd8(uint32_t a) { return fmem[A24(a)]; }
uint16_t m_rd16(uint32_t a) { return (uint16_t)(fmem[A24(a)] << 8 | fmem[A24(a + 1)]); }
uint32_t m_rd32(uint32_t a) { return (uint32_t)m_rd16(a) << 16 | m_rd16(a + 2); }
void m_wr8(uint32_t a, uint8_t v) { fmem[A24(a)] = v; }
void m_wr16(uint32_t a, uint16_t v)
{
    fmem[A24(a)] = (uint8_t)(v >> 8);
    fmem[A24(a + 1)] = (uint8_t)v;
}
void m_wr32(uint32_t a, uint32_t v)
{
    m_wr16(a, (uint16_t)(v >> 16));
    m_wr16(a + 2, (uint16_t)v);
}

/* ---- devices --------------------------------------------------------------- */
static int vme_word(uint32_t a, uint16_t *w)
{
    uint32_t a24 = ((uint32_t)(dev.vme_page & 0xF) << 20) | (a & 0xFFFFEu & (VME_WIN_SIZE - 1u));
    for (unsigned i = 0; i < FLOOR_NBOARDS; i++) {
        const vme_board_t *b = &dev.vme_boards[i];
        if (b->a24 && a24 == b->a24) {
            *w = (uint16_t)(b->value >> 16);
            return 1;
        }
        if (b->a24 && a24 == b->a24 + 2u) {
            *w = (uint16_t)b->value;
            return 1;
        }
    }
    return 0;
}

static uint16_t dev_rd16(uint32_t a)
{
    a = A24(a);
    if (a - VME_WIN_BASE < VME_WIN_SIZE) {
        uint16_t w;
        if (vme_word(a, &w))
            return w;
        dev.vme_berr = 1;
        return 0xFFFF;
    }
    if (a == VME_STATUS) {
        uint16_t st = dev.vme_berr ? VME_ST_BERR : 0;
        dev.vme_berr = 0;
        return st;
    }
    if (a - AXIS_BASE < MAC4_NAXES * AXIS_STRIDE && ((a & (AXIS_STRIDE - 1u)) == AX_SSI_HI ||
                                                     (a & (AXIS_STRIDE - 1u)) == AX_SSI_LO)) {
        unsigned n = (a - AXIS_BASE) / AXIS_STRIDE;
        return dev.ssi_busy[n] ? (uint16_t)~m_rd16(a) : m_rd16(a);   /* busy: the shift register moves */
    }
    if (a - AXIS_BASE < MAC4_NAXES * AXIS_STRIDE && (a & (AXIS_STRIDE - 1u)) == AX_IN) {
        unsigned n = (a - AXIS_BASE) / AXIS_STRIDE;
        uint16_t v = m_rd16(a);
        if (dev.ssi_busy[n]) {
            dev.ssi_busy[n]--;
            return v | AX_IN_SSI_BUSY;
        }
        return (uint16_t)(v & ~AX_IN_SSI_BUSY);
    }
    return m_rd16(a);
}

static void dev_wr16(uint32_t a, uint16_t v)
{
    a = A24(a);
    if (a == VME_PAGE)
        dev.vme_page = v & 0xF;
    if (a - VME_WIN_BASE < VME_WIN_SIZE) {
        uint16_t w;
        if (!vme_word(a, &w))
            dev.vme_berr = 1;
        return;
    }
    m_wr16(a, v);
}

static int is_dev(uint32_t a)
{
    a = A24(a);
    return a >= IO_BASE || a - VME_WIN_BASE < VME_WIN_SIZE;
}

uint32_t dev_read(uint32_t a, int size)
{
    if (size == 4)
        return (uint32_t)dev_read(a, 2) << 16 | dev_read(a + 2, 2);
    if (!is_dev(a))
        return size == 1 ? m_rd8(a) : m_rd16(a);
    if (size == 1) {
        uint16_t w = dev_rd16(a & ~1u);
        return (a & 1) ? (w & 0xFF) : (w >> 8);
    }
    return dev_rd16(a);
}

void dev_write(uint32_t a, uint32_t v, int size)
{
    if (size == 4) {
        dev_write(a, v >> 16, 2);
        dev_write(a + 2, v & 0xFFFF, 2);
        return;
    }
    if (!is_dev(a)) {
        if (size == 1)
            m_wr8(a, (uint8_t)v);
        else
            m_wr16(a, (uint16_t)v);
        return;
    }
    if (size == 1) {        /* the I/O blocks are word devices: the other byte kept */
        uint16_t w = m_rd16(a & ~1u);
        w = (a & 1) ? (uint16_t)((w & 0xFF00) | (v & 0xFF)) : (uint16_t)((w & 0x00FF) | (v & 0xFF) << 8);
        dev_wr16(a & ~1u, w);
        return;
    }
    dev_wr16(a, (uint16_t)v);
}

/* hal.h for the firmware's C (HAL_NATIVE): the same devices, no cycles */
uint8_t hal_rd8(uint32_t a) { return (uint8_t)dev_read(a, 1); }
uint16_t hal_rd16(uint32_t a) { return (uint16_t)dev_read(a, 2); }
uint32_t hal_rd32(uint32_t a) { return dev_read(a, 4); }
void hal_wr8(uint32_t a, uint8_t v) { dev_write(a, v, 1); }
void hal_wr16(uint32_t a, uint16_t v) { dev_write(a, v, 2); }
void hal_wr32(uint32_t a, uint32_t v) { dev_write(a, v, 4); }
static unsigned irq_mask;
unsigned hal_irq_save(void)
{
    unsigned p = irq_mask;
    irq_mask = 7;
    return p;
}
void hal_irq_restore(unsigned prev) { irq_mask = prev; }
void hal_irq_enable_all(void) { irq_mask = 0; }

/* ---- the CPU's bus ----------------------------------------------------------- */
static int in_run;
static unsigned fault_vector;        /* a vector other than the tick's was fetched */

static inline void bus_cycles(unsigned a, int write, unsigned n)
{
    if (!in_run)
        return;
    unsigned w = buswait_charge(A24(a), write, n);
    if (w)
        USE_CYCLES((int)w);
}

unsigned int m68k_read_memory_8(unsigned int a)
{
    bus_cycles(a, 0, 1);
    return dev_read(a, 1);
}
unsigned int m68k_read_memory_16(unsigned int a)
{
    bus_cycles(a, 0, 1);
    return dev_read(a, 2);
}
unsigned int m68k_read_memory_32(unsigned int a)
{
    bus_cycles(a, 0, 2);
    if (A24(a) < 0x400 && A24(a) != 4u * (24 + IRQ_LEVEL_TIMER) && in_run)
        fault_vector = A24(a) / 4;
    return dev_read(a, 4);
}
void m68k_write_memory_8(unsigned int a, unsigned int v)
{
    bus_cycles(a, 1, 1);
    dev_write(a, v, 1);
}
void m68k_write_memory_16(unsigned int a, unsigned int v)
{
    bus_cycles(a, 1, 1);
    dev_write(a, v, 2);
}
void m68k_write_memory_32(unsigned int a, unsigned int v)
{
    bus_cycles(a, 1, 2);
    dev_write(a, v, 4);
}
unsigned int m68k_read_disassembler_8(unsigned int a) { return m_rd8(a); }
unsigned int m68k_read_disassembler_16(unsigned int a) { return m_rd16(a); }
unsigned int m68k_read_disassembler_32(unsigned int a) { return m_rd32(a); }

/* the hooks harness/musashi_cnf.h names, as harness/cpu_m68k.c has them */
int mac4_profiling;
int mac4_gdb_on;
int mac4_gdb_instr(unsigned pc) { (void)pc; return 0; }
unsigned mac4_idle_pc = 1;                          /* no idle skip here: odd, never a PC */
/* every PC to the hooks (harness/musashi_cnf.h): mac4_profiling switches the tracing */
unsigned mac4_hook_lo = 0, mac4_hook_span = ~0u;
void mac4_idle_instr(unsigned pc) { (void)pc; }

static uint32_t call_entry, call_ret;
static int call_state;               /* 0 before the entry, 1 inside, 2 returned */
static int64_t call_start, call_end;
static int64_t cycles_now(void) { return (int64_t)m68k_cycles_run(); }

static int tracing;
static uint32_t trace_pc;
static int64_t trace_at;
static void trace_instr(unsigned pc)
{
    int64_t now = cycles_now();
    if (trace_pc) {
        char buf[128];
        m68k_disassemble(buf, trace_pc, M68K_CPU_TYPE_68000);
        printf("trace $%06X %4lld  %s\n", trace_pc, (long long)(now - trace_at), buf);
    }
    trace_pc = pc;
    trace_at = now;
}

void mac4_profile_instr(unsigned pc)
{
    if (tracing)
        trace_instr(pc);
    if (call_state == 0 && pc == call_entry) {
        call_state = 1;
        call_start = cycles_now();
    } else if (call_state == 1 && pc == call_ret) {
        call_state = 2;
        call_end = cycles_now();
        m68k_end_timeslice();
    }
}

static int64_t isr_start, isr_end;
static int isr_state;
int mac4_int_ack(int level)
{
    (void)level;
    m68k_set_irq(0);
    isr_state = 1;
    isr_start = cycles_now();
    unsigned w = buswait_iack();    /* through VPA, synchronised to E (buswait.h) */
    USE_CYCLES((int)w);
    return (int)M68K_INT_ACK_AUTOVECTOR;
}
void mac4_rte(void)
{
    if (isr_state == 1) {
        isr_end = cycles_now() + 20;    /* RTE's own cycles, as harness/cpu_m68k.c */
        isr_state = 2;
        m68k_end_timeslice();
    }
}
int mac4_illegal(int opcode)
{
    (void)opcode;
    return 0;
}
void mac4_reset_instr(void) {}
void mac4_bus_extra(unsigned address, int n)
{
    if (n > 0) {
        bus_cycles(address, 0, (unsigned)n);
    } else if (n < 0 && in_run) {
        unsigned w = buswait_refund(A24(address), (unsigned)-n);
        if (w)
            ADD_CYCLES((int)w);
    }
}

/* ---- running a routine ------------------------------------------------------- */
#define RUN_BUDGET 2000000

int floor_load(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "floorrun: cannot open %s\n", path);
        return -1;
    }
    memset(fmem + FLOOR_CODE, 0, FLOOR_IDLE - FLOOR_CODE);
    size_t n = fread(fmem + FLOOR_CODE, 1, FLOOR_IDLE - FLOOR_CODE, f);
    int more = fgetc(f) != EOF;
    fclose(f);
    if (!n || more) {
        fprintf(stderr, "floorrun: %s: %s\n", path, n ? "longer than the space for it" : "empty");
        return -1;
    }
    return 0;
}

static uint32_t regs_in[15];

static void cpu_prepare(void)
{
    for (int r = 0; r < 15; r++) {
        regs_in[r] = rnd();
        m68k_set_reg((m68k_register_t)(M68K_REG_D0 + r), regs_in[r]);
    }
    m68k_set_reg(M68K_REG_SR, 0x2000);
    m68k_set_reg(M68K_REG_SP, FLOOR_STACK_TOP);
    m68k_set_reg(M68K_REG_PC, FLOOR_IDLE);
    fault_vector = 0;
}

/* scratch: a subroutine may change d0-d1/a0-a1 (the C ABI's, as the
 * firmware's functions it stands for) */
static int cpu_check(char *err, size_t errlen, int scratch)
{
    if (fault_vector) {
        snprintf(err, errlen, "exception, vector %u (PC $%06X)", fault_vector, m68k_get_reg(NULL, M68K_REG_PPC));
        return -1;
    }
    for (int r = 0; r < 15; r++) {
        if (scratch && (r == 0 || r == 1 || r == 8 || r == 9))
            continue;
        uint32_t v = m68k_get_reg(NULL, (m68k_register_t)(M68K_REG_D0 + r));
        if (v != regs_in[r]) {
            snprintf(err, errlen, "register %c%d not restored ($%08X, was $%08X)", r < 8 ? 'd' : 'a', r & 7, v,
                     regs_in[r]);
            return -1;
        }
    }
    if (m68k_get_reg(NULL, M68K_REG_SP) != FLOOR_STACK_TOP) {
        snprintf(err, errlen, "stack pointer $%08X after the routine", m68k_get_reg(NULL, M68K_REG_SP));
        return -1;
    }
    return 0;
}

uint64_t floor_isr(uint32_t entry, char *err, size_t errlen)
{
    m_wr32(4u * (24 + IRQ_LEVEL_TIMER), entry);
    cpu_prepare();
    isr_state = 0;
    in_run = 1;
    mac4_profiling = tracing;
    trace_pc = 0;
    m68k_set_irq(IRQ_LEVEL_TIMER);
    m68k_execute(RUN_BUDGET);
    in_run = 0;
    mac4_profiling = 0;
    m68k_set_irq(0);
    if (isr_state != 2) {
        snprintf(err, errlen, "no RTE within %d cycles (PC $%06X)", RUN_BUDGET, m68k_get_reg(NULL, M68K_REG_PC));
        return 0;
    }
    if (cpu_check(err, errlen, 0))
        return 0;
    return (uint64_t)(isr_end - isr_start);
}

/* at FLOOR_IDLE: jsr (a1); bra.s * - the call the measurement brackets */
uint64_t floor_call(uint32_t entry, uint32_t a0, char *err, size_t errlen)
{
    cpu_prepare();
    m68k_set_reg(M68K_REG_SR, 0x2000);
    m68k_set_reg(M68K_REG_A0, a0);
    regs_in[8] = a0;
    m68k_set_reg(M68K_REG_A1, entry);
    regs_in[9] = entry;
    call_entry = entry;
    call_ret = FLOOR_IDLE + 2;
    call_state = 0;
    mac4_profiling = 1;
    in_run = 1;
    m68k_execute(RUN_BUDGET);
    in_run = 0;
    mac4_profiling = 0;
    if (call_state != 2) {
        snprintf(err, errlen, "no return within %d cycles (PC $%06X)", RUN_BUDGET, m68k_get_reg(NULL, M68K_REG_PC));
        return 0;
    }
    if (cpu_check(err, errlen, 1))
        return 0;
    return (uint64_t)(call_end - call_start);
}

/* ---- random numbers (xorshift, seeded) ------------------------------------- */
static uint32_t rs = 2463534242u;
uint32_t rnd(void)
{
    rs ^= rs << 13;
    rs ^= rs >> 17;
    rs ^= rs << 5;
    return rs;
}
uint32_t rnd_below(uint32_t n) { return n ? rnd() % n : 0; }
int32_t rnd_range(int32_t lo, int32_t hi)
{
    return (int32_t)((uint32_t)lo + rnd_below((uint32_t)hi - (uint32_t)lo + 1u));
}
int rnd_pct(unsigned pct) { return rnd_below(100) < pct; }

/* ---- main ---------------------------------------------------------------------- */
static uint8_t io_before[0x2000], sram_before[SRAM_SIZE], dpram_before[DPRAM_SIZE];
static devstate_t dev_before;

/* One input through the routine and the C: 0 equal, 1 different, -1 the
 * routine failed.  cycles: the routine's. */
static int one(const routine_t *r, const char *dir_bin, int scen, uint64_t *cycles, char *msg, size_t len)
{
    (void)dir_bin;
    r->gen(scen);
    memcpy(io_before, fmem + IO_BASE, sizeof io_before);
    memcpy(sram_before, fmem + SRAM_BASE, sizeof sram_before);
    memcpy(dpram_before, fmem + DPRAM_BASE, sizeof dpram_before);
    dev_before = dev;
    char err[256];
    uint64_t c = r->isr ? floor_isr(FLOOR_CODE, err, sizeof err)
                        : floor_call(FLOOR_CODE, r->arg ? r->arg() : 0, err, sizeof err);
    if (!c) {
        snprintf(msg, len, "%s", err);
        return -1;
    }
    *cycles = c;
    return r->compare(msg, len);
}

/* For compare(): the routine's results, and the inputs back in place. */
static uint8_t floor_out_io[0x2000], floor_out_sram[SRAM_SIZE], floor_out_dpram[DPRAM_SIZE];
static devstate_t floor_out_dev;
void floor_restore_inputs(void)
{
    memcpy(floor_out_io, fmem + IO_BASE, sizeof floor_out_io);
    memcpy(floor_out_sram, fmem + SRAM_BASE, sizeof floor_out_sram);
    memcpy(floor_out_dpram, fmem + DPRAM_BASE, sizeof floor_out_dpram);
    floor_out_dev = dev;
    memcpy(fmem + IO_BASE, io_before, sizeof io_before);
    memcpy(fmem + SRAM_BASE, sram_before, sizeof sram_before);
    memcpy(fmem + DPRAM_BASE, dpram_before, sizeof dpram_before);
    dev = dev_before;
}

static const char *field_at(const field_t *fields, unsigned nfields, uint32_t a, unsigned *off)
{
    if (a >= FLOOR_AX0 && a < FLOOR_AX(MAC4_NAXES)) {
        unsigned o = (a - FLOOR_AX0) % FLOOR_AX_SIZE;
        for (unsigned i = 0; i < nfields; i++)
            if (o >= fields[i].off && o < fields[i].off + fields[i].size) {
                *off = fields[i].off;
                return fields[i].name;
            }
        *off = o;
        return "(no field)";
    }
    *off = 0;
    return a >= FLOOR_CARD && a < FLOOR_CARD + 0x100 ? "card" : "(outside the records)";
}

int floor_compare(char *msg, size_t len, const field_t *fields, unsigned nfields)
{
    for (uint32_t a = SRAM_BASE; a < FLOOR_STACK_TOP - 0x200; a++)
        if (fmem[a] != floor_out_sram[a - SRAM_BASE]) {
            unsigned off;
            const char *f = field_at(fields, nfields, a, &off);
            int ax = a >= FLOOR_AX0 && a < FLOOR_AX(MAC4_NAXES) ? (int)((a - FLOOR_AX0) / FLOOR_AX_SIZE) : -1;
            uint32_t base = ax >= 0 ? FLOOR_AX(ax) + off : a;
            char fl[64] = "", rf[64] = "";
            for (uint32_t b = base; b < base + 8 && b <= a + 3; b++) {
                snprintf(fl + strlen(fl), sizeof fl - strlen(fl), "%02X", floor_out_sram[b - SRAM_BASE]);
                snprintf(rf + strlen(rf), sizeof rf - strlen(rf), "%02X", fmem[b]);
            }
            snprintf(msg, len, "axis %d %s (byte $%06X): floor %s, firmware %s", ax, f, (unsigned)a, fl, rf);
            return 1;
        }
    for (uint32_t a = 0x400; a < DPRAM_SIZE; a++)    /* the vectors below: the runner's */
        if (fmem[DPRAM_BASE + a] != floor_out_dpram[a]) {
            snprintf(msg, len, "DPRAM $%04X: floor $%02X, firmware $%02X", (unsigned)a, floor_out_dpram[a],
                     fmem[DPRAM_BASE + a]);
            return 1;
        }
    for (uint32_t o = 0; o < sizeof floor_out_io; o += 2) {
        uint16_t fl = (uint16_t)(floor_out_io[o] << 8 | floor_out_io[o + 1]);
        uint16_t rf = m_rd16(IO_BASE + o);
        if (fl != rf) {
            snprintf(msg, len, "register $%06X: floor $%04X, firmware $%04X", (unsigned)(IO_BASE + o), fl, rf);
            return 1;
        }
    }
    if (floor_out_dev.vme_berr != dev.vme_berr || floor_out_dev.vme_page != dev.vme_page) {
        snprintf(msg, len, "VMEbus: floor page %u berr %u, firmware page %u berr %u", floor_out_dev.vme_page,
                 floor_out_dev.vme_berr, dev.vme_page, dev.vme_berr);
        return 1;
    }
    return 0;
}

static const routine_t *find_routine(const module_t *m, const char *name)
{
    for (unsigned i = 0; i < m->nroutines; i++)
        if (!strcmp(m->routines[i].name, name))
            return &m->routines[i];
    return NULL;
}

static int load_routine(const char *dir, const char *name, const char *bin)
{
    char path[1024];
    if (bin)
        snprintf(path, sizeof path, "%s", bin);
    else
        snprintf(path, sizeof path, "%s/%s.bin", dir, name);
    return floor_load(path);
}

static int usage(void)
{
    fprintf(stderr, "usage: floorrun-CARD DIR --check [N] [--seed S] [--routine NAME] [--bin FILE]\n"
                    "       floorrun-CARD DIR --measure [N] [--seed S]\n"
                    "       (either with --wait-states SPEC, as mac4sim's)\n"
                    "       floorrun-CARD --list\n");
    return 2;
}

int main(int argc, char **argv)
{
    const char *dir = NULL, *only = NULL, *bin = NULL;
    int mode = 0;           /* 1 check, 2 measure, 3 list */
    long n = -1;
    buswait_init();
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--check"))
            mode = 1;
        else if (!strcmp(argv[i], "--measure"))
            mode = 2;
        else if (!strcmp(argv[i], "--list"))
            mode = 3;
        else if (!strcmp(argv[i], "--trace"))
            tracing = 1;
        else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
            rs = (uint32_t)strtoul(argv[++i], NULL, 0) | 1u;
        else if (!strcmp(argv[i], "--routine") && i + 1 < argc)
            only = argv[++i];
        else if (!strcmp(argv[i], "--bin") && i + 1 < argc)
            bin = argv[++i];
        else if (!strcmp(argv[i], "--wait-states") && i + 1 < argc) {
            char err[256];
            if (buswait_parse(argv[++i], err, sizeof err)) {
                fprintf(stderr, "floorrun: %s\n", err);
                return 2;
            }
        }
        else if (argv[i][0] != '-' && mode && n < 0 && strspn(argv[i], "0123456789") == strlen(argv[i]))
            n = atol(argv[i]);
        else if (argv[i][0] != '-' && !dir)
            dir = argv[i];
        else
            return usage();
    }
    if (!mode || (mode != 3 && !dir) || (bin && !only))
        return usage();
    fmem = calloc(1, 1u << 24);
    if (!fmem) {
        fprintf(stderr, "floorrun: out of memory\n");
        return 1;
    }
    m_wr16(FLOOR_IDLE, 0x4E91);                 /* jsr (a1) */
    m_wr16(FLOOR_IDLE + 2, 0x60FE);             /* bra.s * */
    m_wr32(0, FLOOR_STACK_TOP);
    m_wr32(4, FLOOR_IDLE + 2);
    m68k_init();
    m68k_set_cpu_type(M68K_CPU_TYPE_68000);
    m68k_pulse_reset();
    m68k_execute(100);                          /* the reset's cycles */

    int bad = 0, seen = 0;
    char msg[1024];
    for (const module_t *const *mp = floor_modules; *mp; mp++) {
        const module_t *m = *mp;
        if (mode == 3) {
            for (unsigned i = 0; i < m->nscenarios; i++)
                printf("scenario %s %s %s routine=%s  %s\n", m->card, m->kind, m->scenarios[i].name,
                       m->scenarios[i].routine, m->scenarios[i].what);
            for (unsigned i = 0; i < m->nroutines; i++)
                printf("routine %s %s %s\n", m->card, m->kind, m->routines[i].name);
            continue;
        }
        if (mode == 1) {
            for (unsigned i = 0; i < m->nroutines; i++) {
                const routine_t *r = &m->routines[i];
                if (only && strcmp(only, r->name))
                    continue;
                seen = 1;
                if (load_routine(dir, r->name, bin))
                    return 1;
                long k, count = n < 0 ? 2000 : n;
                uint64_t cmin = UINT64_MAX, cmax = 0;
                for (k = 0; k < count; k++) {
                    uint64_t c = 0;
                    int res = one(r, dir, -1, &c, msg, sizeof msg);
                    if (res) {
                        printf("MISMATCH %s %s %s sample %ld: %s\n", m->card, m->kind, r->name, k, msg);
                        bad = 1;
                        break;
                    }
                    cmin = c < cmin ? c : cmin;
                    cmax = c > cmax ? c : cmax;
                }
                if (k == count)
                    printf("check %s %s %s samples=%ld ok cycles=%llu..%llu\n", m->card, m->kind, r->name, count,
                           (unsigned long long)cmin, (unsigned long long)cmax);
            }
            continue;
        }
        for (unsigned i = 0; i < m->nscenarios; i++) {
            const scenario_t *s = &m->scenarios[i];
            const routine_t *r = find_routine(m, s->routine);
            if (!r) {
                fprintf(stderr, "floorrun: scenario %s names no routine %s\n", s->name, s->routine);
                return 1;
            }
            seen = 1;
            if (load_routine(dir, r->name, NULL))
                return 1;
            long count = n < 0 ? 200 : n;
            uint64_t cmax = 0, cmin = UINT64_MAX, csum = 0, bmin = UINT64_MAX;
            for (int pass = 0; pass < (s->baseline ? 2 : 1); pass++)
                for (long k = 0; k < count; k++) {
                    uint64_t c = 0;
                    int scen = pass ? s->baseline - 1 : s->scen;
                    if (one(r, dir, scen, &c, msg, sizeof msg)) {
                        printf("MISMATCH %s %s %s (%s) sample %ld: %s\n", m->card, m->kind, r->name, s->name, k, msg);
                        return 1;
                    }
                    if (pass) {
                        bmin = c < bmin ? c : bmin;
                        continue;
                    }
                    cmax = c > cmax ? c : cmax;
                    cmin = c < cmin ? c : cmin;
                    csum += c;
                }
            if (s->baseline) {
                uint64_t mean = (csum + (uint64_t)count / 2) / (uint64_t)count;
                printf("floor %s %s %s routine=%s cycles=%llu min=%llu max=%llu mean=%llu idle=%llu samples=%ld\n",
                       m->card, m->kind, s->name, r->name, (unsigned long long)(mean - bmin),
                       (unsigned long long)(cmin - bmin), (unsigned long long)(cmax - bmin), (unsigned long long)mean,
                       (unsigned long long)bmin, count);
                continue;
            }
            printf("floor %s %s %s routine=%s cycles=%llu min=%llu samples=%ld\n", m->card, m->kind, s->name,
                   r->name, (unsigned long long)cmax, (unsigned long long)cmin, count);
        }
    }
    if (only && !seen) {
        fprintf(stderr, "floorrun: no routine %s on this card\n", only);
        return 2;
    }
    return bad;
}
