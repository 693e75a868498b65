/*
 * cpu_m68k.c - Musashi as the IPC's 68000: memory callbacks onto the bus,
 * interrupt acknowledge (autovectors) and RTE for the accounting, bus
 * errors (a bus cycle no device acknowledged, our patch 0007) and the halt
 * of a double bus fault, and the detection of exceptions the firmware did
 * not expect (vector fetches that are not interrupt acknowledges) and
 * illegal opcodes.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "m68k.h"
#include "m68kcpu.h"
#include "cpu.h"
#include "periph.h"
#include "profile.h"
#include "buswait.h"
#include "gdbstub.h"
#include "idle.h"

int mac4_fast = 1;          /* mac4sim --no-fast: every speedup below off (cpu.h) */
static int expect_vector;   /* an interrupt acknowledge precedes its vector fetch */
static int in_slice;        /* m68k_cycles_run() is only meaningful inside m68k_execute */
static cyc_t slice_done;    /* cycles of the slice before a gdb stop (gdbstub.c) */

unsigned mac4_hook_lo = 1, mac4_hook_span;   /* musashi_cnf.h: PC 1 alone, as mac4_idle_pc */
extern int m68k_fast_hook_loop;   /* our patch 0011 (m68kcpu.h; MAC4_IDLE_HOOK is the core's alone) */

void mac4_hooks_update(void)
{
    /* --no-fast: every instruction through the full hook, as before the
     * fast loop (our patch 0011) */
    if (mac4_gdb_on || mac4_profiling || !mac4_fast) {
        /* Musashi's fast loop sees no hook turned on in it but from the idle
         * skip's callback, which clears the flag */
        if (m68k_fast_hook_loop) {
            fprintf(stderr, "mac4sim: instruction hook turned on inside a slice outside the idle hook\n");
            abort();
        }
        mac4_hook_lo = 0;
        mac4_hook_span = ~0u;
    } else {
        mac4_hook_lo = mac4_idle_pc;
        mac4_hook_span = 0;
    }
}

static cyc_t m68k_elapsed(void) { return in_slice ? slice_done + (cyc_t)m68k_cycles_run() : 0; }
static uint32_t m68k_pc(void) { return m68k_get_reg(NULL, M68K_REG_PPC); }

static const char *vector_name(unsigned v)
{
    switch (v) {
    case 2: return "bus error";
    case 3: return "address error";
    case 4: return "illegal instruction";
    case 5: return "zero divide";
    case 6: return "CHK";
    case 7: return "TRAPV";
    case 8: return "privilege violation";
    case 9: return "trace";
    case 10: return "line A";
    case 11: return "line F";
    case 24: return "spurious interrupt";
    }
    if (v >= 32 && v < 48)
        return "TRAP";
    return "unassigned vector";
}

static void check_vector_fetch(unsigned addr)
{
    if ((g_sim->sysctl & SYS_CTRL_OVERLAY) || addr >= 0x400)
        return;
    unsigned v = addr / 4;
    if (expect_vector && v >= 25 && v <= 31) {
        expect_vector = 0;
        return;
    }
    sim_fault(g_sim, "exception %u (%s)", v, vector_name(v));
}

/* Fast path (docs/performance.md, harness overhead): plain memory the bus
 * would only copy from - the EPROM, the SRAM without an injected fault, the
 * DPRAM once the boot overlay is gone - is read here directly, and the SRAM
 * written directly; everything else goes through the bus map.  Same
 * results, about a third less host time. */
static inline const uint8_t *mem_fast(unsigned a, unsigned n)
{
    if (a - EPROM_BASE <= EPROM_SIZE - n)
        return g_sim->eprom + (a - EPROM_BASE);
    if (a - SRAM_BASE <= SRAM_SIZE - n && !g_sim->sram_fault_mask)
        return g_sim->sram + (a - SRAM_BASE);
    if (a >= 0x400 && a <= DPRAM_SIZE - n && !(g_sim->sysctl & SYS_CTRL_OVERLAY))
        return g_sim->dpram + a;
    return NULL;
}

/* Bus timing (buswait.h, hal/mac4_map.h MAC4_BUS_TIMING): every bus
 * cycle's wait states are charged to the slice as it is made, and a DPRAM
 * access waits for a word the VME host holds.  The EPROM answers at $0
 * while the boot overlay is on. */
static inline __attribute__((always_inline)) void bus_cycles(unsigned a, int write, unsigned n)
{
    if (!in_slice)      /* the reset's vector fetch: Musashi counts no time for it */
        return;
    a &= 0xFFFFFF;
    unsigned w;
    if (a < DPRAM_SIZE && (g_sim->sysctl & SYS_CTRL_OVERLAY) && !write) {
        w = buswait_charge(EPROM_BASE + a, 0, n);
    } else {
        w = buswait_charge(a, write, n);
        if (a < DPRAM_SIZE)
            w += buswait_dpram_contention(g_sim->slice_base + m68k_elapsed(), a);
    }
    if (w)
        USE_CYCLES((int)w);
}

/* A bus cycle of the access at a got /BERR at bus_berr_addr (bus.c): the
 * card's bus timer ended it MAC4_BUS_TIMEOUT_CLOCKS after its start, and the
 * 68000 takes the bus error (m68k_bus_error, our patch 0007), which leaves
 * this callback by longjmp.  The registers stay as the instruction left
 * them, as on the 68000.  Time: Musashi adds an instruction's clocks at its
 * end, which a bus error never reaches, so the instruction's words fetched
 * before the fault are charged here at 4 clocks each (their wait states
 * were as they were made; its data cycles before the faulting one are not
 * known and not counted), then the faulting cycle's whole length, then the
 * exception's 50 (the patch).  A long access that faulted on its first word
 * made no second cycle: its charge is taken back.  Outside m68k_execute
 * (the reset's vector fetch, always from the EPROM) it stays a fault
 * report. */
static void bus_error(unsigned a, int write, int size)
{
    if (!in_slice)
        return;
    unsigned at = bus_berr_addr & 0xFFFFFF;
    unsigned r = buswait_page[at >> 8];
    unsigned ppc = REG_PPC & 0xFFFFFF, pc = REG_PC & 0xFFFFFF;
    unsigned words = CPU_INSTR_MODE == INSTRUCTION_NO ? 0          /* exception processing */
                   : at - ppc < pc - ppc ? (at - ppc) / 2           /* a fetch of the instruction */
                   : ((pc - ppc) & 0xFFFFFF) / 2;
    int extra = 4 * (int)words + MAC4_BUS_TIMEOUT_CLOCKS - (int)buswait_cfg.ws[r][write];
    if (size == 4 && at == (a & 0xFFFFFF)) {
        unsigned r2 = buswait_page[at >> 8], w2 = buswait_cfg.ws[r2][write];
        buswait_stats.cycles[r2][write]--;
        buswait_stats.wait[r2][write] -= w2;
        extra -= (int)w2;
    }
    if (extra > 0)
        buswait_stats.wait[r][write] += (unsigned)extra;
    USE_CYCLES(extra);
    idle_irq();                   /* the flow leaves the instruction: no idle window */
    m68k_bus_error(at, write);
}

/* The 68000's exception processing for a bus error, an address error or
 * the reset ends with the prefetch of the handler's first two words; a bus
 * error there is a double bus fault.  Musashi reads the first word with the
 * next instruction, so the refill of a group-0 exception (its
 * mac4_bus_extra at the handler + 2, still in the exception) checks both
 * and makes the bus error while the CPU is in that processing: the halt.
 * An odd handler is the patch's address error, next. */
static void group0_prefetch(unsigned a)
{
    a &= 0xFFFFFF;
    if (a & 1)
        return;
    unsigned words[2] = {(a - 2) & 0xFFFFFF, a};
    for (int i = 0; i < 2; i++) {
        if (!bus_decodes(words[i], 0, 2)) {
            sim_fault(g_sim, "unmapped read16 at $%06X", words[i]);
            m68ki_bus_program = 1;          /* a fetch: program space */
            m68k_bus_error(words[i], 0);
        }
    }
}

unsigned int m68k_read_memory_8(unsigned int a)
{
    bus_cycles(a, 0, 1);
    if (mac4_idle_rec)
        idle_rec_read(a, 1);
    if (mac4_gdb_watching)
        gdbstub_access(a, 1, 0);
    const uint8_t *m = mem_fast(a & 0xFFFFFF, 1);
    if (m)
        return m[0];
    unsigned v = bus_read(g_sim, a, 1);
    if (bus_berr)
        bus_error(a, 0, 1);
    return v;
}
unsigned int m68k_read_memory_16(unsigned int a)
{
    bus_cycles(a, 0, 1);
    if (mac4_idle_rec)
        idle_rec_read(a, 2);
    if (mac4_gdb_watching)
        gdbstub_access(a, 2, 0);
    const uint8_t *m = mem_fast(a & 0xFFFFFF, 2);
    if (m)
        return (unsigned)m[0] << 8 | m[1];
    unsigned v = bus_read(g_sim, a, 2);
    if (bus_berr)
        bus_error(a, 0, 2);
    return v;
}
unsigned int m68k_read_memory_32(unsigned int a)
{
    bus_cycles(a, 0, 2);
    if (mac4_idle_rec)
        idle_rec_read(a, 4);
    if (mac4_gdb_watching)
        gdbstub_access(a, 4, 0);
    const uint8_t *m = mem_fast(a & 0xFFFFFF, 4);
    if (m)
        return (unsigned)m[0] << 24 | (unsigned)m[1] << 16 | (unsigned)m[2] << 8 | m[3];
    if ((a & 0xFFFFFF) < 0x400)
        check_vector_fetch(a & 0xFFFFFF);
    unsigned v = bus_read(g_sim, a, 4);
    if (bus_berr)
        bus_error(a, 0, 4);
    return v;
}
static inline uint8_t *sram_fast(unsigned a, unsigned n)
{
    a &= 0xFFFFFF;
    return a - SRAM_BASE <= SRAM_SIZE - n ? g_sim->sram + (a - SRAM_BASE) : NULL;
}
void m68k_write_memory_8(unsigned int a, unsigned int v)
{
    bus_cycles(a, 1, 1);
    if (mac4_idle_rec)
        idle_rec_write(a, v, 1);
    if (mac4_gdb_watching)
        gdbstub_access(a, 1, 1);
    uint8_t *m = sram_fast(a, 1);
    if (m) {
        m[0] = (uint8_t)v;
        return;
    }
    bus_write(g_sim, a, v, 1);
    if (bus_berr)
        bus_error(a, 1, 1);
}
void m68k_write_memory_16(unsigned int a, unsigned int v)
{
    bus_cycles(a, 1, 1);
    if (mac4_idle_rec)
        idle_rec_write(a, v, 2);
    if (mac4_gdb_watching)
        gdbstub_access(a, 2, 1);
    uint8_t *m = sram_fast(a, 2);
    if (m) {
        m[0] = (uint8_t)(v >> 8);
        m[1] = (uint8_t)v;
    } else {
        bus_write(g_sim, a, v, 2);
        if (bus_berr)
            bus_error(a, 1, 2);
    }
}
void m68k_write_memory_32(unsigned int a, unsigned int v)
{
    bus_cycles(a, 1, 2);
    if (mac4_idle_rec)
        idle_rec_write(a, v, 4);
    if (mac4_gdb_watching)
        gdbstub_access(a, 4, 1);
    uint8_t *m = sram_fast(a, 4);
    if (m) {
        m[0] = (uint8_t)(v >> 24);
        m[1] = (uint8_t)(v >> 16);
        m[2] = (uint8_t)(v >> 8);
        m[3] = (uint8_t)v;
    } else {
        bus_write(g_sim, a, v, 4);
        if (bus_berr)
            bus_error(a, 1, 4);
    }
}

/* The memory windows of our patch 0008-memory-windows (m68k.h): opcode,
 * immediate and data reads of the EPROM, data reads and writes of the SRAM,
 * without the memory callbacks, the same wait states charged per bus cycle
 * as bus_cycles() would.  Off with --no-fast and under gdb, whose
 * watchpoints see every access; the SRAM's also while the idle skip records
 * (it sees every access) and with an injected SRAM fault (the bus map makes
 * it).  Set at every slice and when a recording starts or ends.  A window
 * counts its bus cycles itself; they go into buswait_stats before anything
 * reads those (buswait_sync) and at every change of a window. */
static int win_region[2];

static void windows_sync(void)
{
    m68k_mem_window_t *w[2] = {&m68k_rom_window, &m68k_ram_window};
    for (int i = 0; i < 2; i++)
        for (int rw = 0; rw < 2; rw++) {
            uint64_t n = w[i]->bus[rw];
            if (n) {
                buswait_stats.cycles[win_region[i]][rw] += n;
                buswait_stats.wait[win_region[i]][rw] += n * (uint64_t)w[i]->wait[rw];
                w[i]->bus[rw] = 0;
            }
        }
}

static void window_set(int i, m68k_mem_window_t *w, uint8_t *mem, unsigned base, unsigned size, int on)
{
    unsigned r = buswait_page[base >> 8];
    win_region[i] = (int)r;
    w->mem = mem;
    w->base = base;
    w->n1 = on ? size : 0;
    w->n2 = on ? size / 2 : 0;
    w->n4 = on ? size / 2 - 1 : 0;
    for (int rw = 0; rw < 2; rw++)
        w->wait[rw] = buswait_cfg.ws[r][rw];
}

/* The ROM window's memory (our patch 0013, musashi_cnf.h): the EPROM's
 * words in host order, in the card's sim_t beside the EPROM (a copy of the
 * sim_t, as the fuzz targets make, takes it along), made from the image at
 * every reset (nothing writes the EPROM: bus.c refuses, gdbstub.c too). */
#if M68K_ROM_WINDOW_HOST_WORDS
static uint8_t *rom_window_mem(sim_t *s, int remake)
{
    if (remake)
        for (unsigned i = 0; i < EPROM_SIZE; i += 2) {
            uint16_t w = (uint16_t)(s->eprom[i] << 8 | s->eprom[i + 1]);
            memcpy(s->eprom_words + i, &w, 2);
        }
    return s->eprom_words;
}
#else
static uint8_t *rom_window_mem(sim_t *s, int remake) { (void)remake; return s->eprom; }
#endif

void cpu_m68k_windows(void)
{
    int on = in_slice && mac4_fast && !mac4_gdb_on;
    windows_sync();
    buswait_sync = windows_sync;
    window_set(0, &m68k_rom_window, rom_window_mem(g_sim, 0), EPROM_BASE, EPROM_SIZE, on);
    window_set(1, &m68k_ram_window, g_sim->sram, SRAM_BASE, SRAM_SIZE,
               on && !mac4_idle_rec && !g_sim->sram_fault_mask);
}

/* The 68000's bus cycles that carry no data to the emulator (musashi_cnf.h,
 * docs/cpu-timing.md): prefetch refills, the read of CLR/Scc/MOVE from SR
 * before their write, MOVEM's extra word.  No device sees them: a read of
 * a register before CLR writes it has no side effect here.  The bus model
 * charges their wait states, per region of the address. */
void mac4_bus_extra(unsigned address, int n)
{
    if (n > 0) {
        bus_cycles(address, 0, (unsigned)n);
        if (m68ki_cpu.run_mode == RUN_MODE_BERR_AERR_RESET_WSF && in_slice)
            group0_prefetch(address);
    } else if (n < 0 && in_slice) {
        unsigned w = buswait_refund(address & 0xFFFFFF, (unsigned)-n);
        if (w)
            ADD_CYCLES((int)w);
    }
}

/* The disassembler reads without side effects. */
static unsigned peek(unsigned a, int size)
{
    a &= 0xFFFFFF;
    const uint8_t *m;
    unsigned off;
    if (a - EPROM_BASE < EPROM_SIZE) { m = g_sim->eprom; off = a - EPROM_BASE; }
    else if (a < DPRAM_SIZE) { m = (g_sim->sysctl & SYS_CTRL_OVERLAY) ? g_sim->eprom : g_sim->dpram; off = a; }
    else if (a - SRAM_BASE < SRAM_SIZE) { m = g_sim->sram; off = a - SRAM_BASE; }
    else return 0;
    unsigned v = 0;
    for (int i = 0; i < size; i++)
        v = v << 8 | m[(off + (unsigned)i) & 0xFFFF];
    return v;
}
unsigned int m68k_read_disassembler_8(unsigned int a) { return peek(a, 1); }
unsigned int m68k_read_disassembler_16(unsigned int a) { return peek(a, 2); }
unsigned int m68k_read_disassembler_32(unsigned int a) { return peek(a, 4); }

int mac4_int_ack(int level)
{
    if (level == IRQ_LEVEL_ESTOP) {
        estop_irq_ack(g_sim);
        /* The edge is taken: lower the line now.  Otherwise Musashi, which
         * also lets level 7 trigger by level, takes it again after the RTE
         * whenever the handler touched no I/O register. */
        sim_update_irq(g_sim);
    }
    idle_irq();
    irq_enter(g_sim, level);
    expect_vector = 1;
    /* the acknowledge cycle: through VPA, synchronised to E (buswait.h) */
    unsigned w = buswait_iack();
    if (in_slice)
        USE_CYCLES((int)w);
    return (int)M68K_INT_ACK_AUTOVECTOR;
}

void mac4_rte(void)
{
    /* Called before RTE's own 20 cycles are counted: add them. */
    irq_leave(g_sim, 20);
}

int mac4_illegal(int opcode)
{
    sim_fault(g_sim, "illegal opcode $%04X", (unsigned)opcode & 0xFFFF);
    return 0;   /* take the exception as the 68000 would */
}

void mac4_reset_instr(void) { /* RESET resets external devices only: none are wired */ }

static int reset_halt;       /* the reset's first fetch faulted: why the CPU halts */

static void m68k_cpu_reset(sim_t *s)
{
    (void)s;
    expect_vector = 0;
    idle_reset();
    m68k_pulse_reset();
    /* The reset's exception processing ends with the prefetch of the first
     * two words at the initial PC: an odd one is an address error, one no
     * device answers a bus error, each a double bus fault (MC68000UM 6.3.9). */
    unsigned pc = m68k_get_reg(NULL, M68K_REG_PC) & 0xFFFFFF;
    reset_halt = (pc & 1) ? 3 : !bus_decodes(pc, 0, 2) || !bus_decodes(pc + 2, 0, 2) ? 2 : 0;
    if (reset_halt) {
        m68ki_aerr_address = (pc & 1) || !bus_decodes(pc, 0, 2) ? pc : pc + 2;
        m68ki_aerr_write_mode = MODE_READ;
        m68ki_aerr_fc = 6;                   /* supervisor program */
        m68k_set_reg(M68K_REG_PPC, pc);      /* the report's pc= */
        m68k_pulse_halt();
    }
}

/* What halted the CPU, for run.c's report (once per halt). */
static void halt_reason(void)
{
    static const char *const what[] = {"the reset", "", "a bus error", "an address error"};
    unsigned first = reset_halt ? 0 : m68k_double_fault[0], second = reset_halt ? (unsigned)reset_halt : m68k_double_fault[1];
    snprintf(sim_halt_why, sizeof sim_halt_why, ": %s at $%06X (%s, FC %u) in the exception processing of %s",
             second == 2 ? "bus error" : "address error", m68ki_aerr_address & 0xFFFFFF,
             m68ki_aerr_write_mode == MODE_WRITE ? "write" : "read", m68ki_aerr_fc & 7,
             what[first < 4 ? first : 1]);
}

static cyc_t m68k_cpu_execute(sim_t *s, cyc_t max)
{
    (void)s;
    if (max > 0x7FFFFFF)
        max = 0x7FFFFFF;
    if (mac4_gdb_on)
        gdbstub_slice_start(s, (long long)max);   /* Ctrl-C, or a stop asked for between slices */
    in_slice = 1;
    slice_done = 0;
    for (;;) {
        cpu_m68k_windows();
        idle_slice_start(s->slice_base + slice_done);
        profile_slice_start();
        int ran = m68k_execute((int)(max - slice_done));
        profile_slice_end(ran);
        if (!gdbstub_stopped_in_slice()) {
            slice_done += (cyc_t)ran;
            break;
        }
        /* gdb stopped the CPU before an instruction: time stands still
         * while it is served, then the same slice goes on.  Even when the
         * slice's cycles are used up: a stop before the loop's first
         * instruction, after an interrupt taken at m68k_execute's entry
         * that used them all, must not end the slice there, as the 68000
         * (Musashi's do-while) runs that instruction in this slice before
         * the lines are sampled again.  A budget <= 0 runs just it. */
        slice_done += (cyc_t)ran;
        gdbstub_serve_stop(s, (long long)max - (long long)slice_done);
        gdbstub_resume_in_slice();
    }
    in_slice = 0;
    cpu_m68k_windows();     /* outside a slice (the reset's fetches): the callbacks */
    return slice_done;
}

/* m68k_set_irq only latches the level: Musashi takes an interrupt at
 * m68k_execute's entry (every slice, after the devices' events) and
 * whenever SR changes (m68ki_set_sr: RTE, MOVE/ANDI to SR, so the end of a
 * masked section such as serial.c's TXIE enable).  A line an I/O access
 * raises mid-slice with the mask already low waits for the slice's end;
 * in the timing and fast-identical scenarios the only such raise is the
 * SSI-delayed tick seen by the slice's last instruction, taken after it as
 * on the 68000.  The idle skip relies on this: no interrupt inside a
 * window run at the request level it was recorded under (idle.c). */
static void m68k_cpu_set_irq(int level) { m68k_set_irq((unsigned)level); }
static int m68k_cpu_halted(void)
{
    if (!(m68ki_cpu.stopped & STOP_LEVEL_HALT))
        return 0;
    halt_reason();
    return 1;
}

static void m68k_cpu_attach(void)
{
    static int done;
    if (done)
        return;
    done = 1;
    m68k_init();
    m68k_set_cpu_type(M68K_CPU_TYPE_68000);
    buswait_init();
    mac4_hooks_update();    /* mac4_fast is known now */
}

static void m68k_reset_wrapper(sim_t *s)
{
    m68k_cpu_attach();
    rom_window_mem(s, 1);
    s->cpu_elapsed = m68k_elapsed;
    s->cpu_pc = m68k_pc;
    m68k_cpu_reset(s);
}

const cpu_t cpu_m68k = {"m68000 (Musashi)", m68k_reset_wrapper, m68k_cpu_execute, m68k_cpu_set_irq,
                        m68k_cpu_halted};
