/*
 * musashi_cnf.h - our configuration of the Musashi core (used through its
 * MUSASHI_CNF hook instead of the shipped m68kconf.h): a plain 68000 with
 * address errors, interrupt acknowledge and RTE reported to the emulator
 * for the interrupt cycle accounting, and illegal opcodes reported.
 */
#ifndef MAC4_MUSASHI_CNF_H
#define MAC4_MUSASHI_CNF_H

#define OPT_OFF             0
#define OPT_ON              1
#define OPT_SPECIFY_HANDLER 2

#define M68K_COMPILE_FOR_MAME       OPT_OFF
/* The core is a 68000 and nothing else (our patch 0010): constant address
 * mask and cycle table.  The stock core knows no such option. */
#define M68K_ONLY_68000             OPT_ON
#define M68K_EMULATE_010            OPT_OFF
#define M68K_EMULATE_EC020          OPT_OFF
#define M68K_EMULATE_020            OPT_OFF
#define M68K_EMULATE_030            OPT_OFF
#define M68K_EMULATE_040            OPT_OFF
#define M68K_SEPARATE_READS         OPT_OFF
#define M68K_SIMULATE_PD_WRITES     OPT_OFF

int mac4_int_ack(int level);
void mac4_rte(void);
int mac4_illegal(int opcode);
void mac4_reset_instr(void);

#define M68K_EMULATE_INT_ACK        OPT_SPECIFY_HANDLER
#define M68K_INT_ACK_CALLBACK(A)    mac4_int_ack(A)
#define M68K_EMULATE_BKPT_ACK       OPT_OFF
#define M68K_BKPT_ACK_CALLBACK()
#define M68K_EMULATE_TRACE          OPT_OFF
#define M68K_EMULATE_RESET          OPT_SPECIFY_HANDLER
#define M68K_RESET_CALLBACK()       mac4_reset_instr()
#define M68K_CMPILD_HAS_CALLBACK    OPT_OFF
#define M68K_CMPILD_CALLBACK(v, r)
#define M68K_RTE_HAS_CALLBACK       OPT_SPECIFY_HANDLER
#define M68K_RTE_CALLBACK()         mac4_rte()
#define M68K_TAS_HAS_CALLBACK       OPT_OFF
#define M68K_TAS_CALLBACK()         1
#define M68K_ILLG_HAS_CALLBACK      OPT_SPECIFY_HANDLER
#define M68K_ILLG_CALLBACK(opcode)  mac4_illegal(opcode)
#define M68K_EMULATE_FC             OPT_OFF
#define M68K_SET_FC_CALLBACK(A)
#define M68K_MONITOR_PC             OPT_OFF
#define M68K_SET_PC_CALLBACK(A)
/* The hook costs one predictable branch per instruction while profiling
 * is off (harness/profile.c). */
extern int mac4_profiling;
void mac4_profile_instr(unsigned pc);
#define M68K_INSTRUCTION_HOOK       OPT_SPECIFY_HANDLER
/* The gdb stub (harness/gdbstub.c) stops before an instruction: the hook
 * stands in m68k_execute's instruction loop, and `break` leaves the loop
 * before the instruction is fetched (no Musashi patch needed; the gdb
 * system test fails if the hook ever moves out of that loop). */
extern int mac4_gdb_on;
int mac4_gdb_instr(unsigned pc);
/* The idle skip (harness/idle.c): it watches one PC; while it records a
 * window it sees every instruction through mac4_profile_instr (bit 1 of
 * mac4_profiling).  Only in the core mac4sim and mac4bare share
 * (MAC4_IDLE_HOOK, Makefile MUSCFLAGS), not in the stock reference. */
extern unsigned mac4_idle_pc;
void mac4_idle_instr(unsigned pc);
/* One test per instruction: the PCs from mac4_hook_lo to mac4_hook_lo +
 * mac4_hook_span go to the hooks; mac4_hooks_update (cpu_m68k.c), called
 * whenever mac4_gdb_on, mac4_profiling or mac4_idle_pc changes, makes
 * that every PC while gdb or the profiler is on, else mac4_idle_pc. */
extern unsigned mac4_hook_lo, mac4_hook_span;
void mac4_hooks_update(void);
#ifdef MAC4_IDLE_HOOK
/* Our patch 0011: while neither gdb nor the profiler is on (mac4_hook_span
 * 0), m68k_execute's fast loop compares each PC with the idle skip's one
 * (mac4_hook_lo) and nothing else; mac4_hooks_update refuses to turn the
 * full hook on inside that loop other than from this callback. */
#define M68K_FAST_HOOK_PC           mac4_hook_lo
#define M68K_FAST_HOOK_OFF          (mac4_hook_span != 0)
#define M68K_FAST_HOOK_CALLBACK(pc) do { if ((pc) == mac4_idle_pc) mac4_idle_instr(pc); } while (0)
#define M68K_INSTRUCTION_CALLBACK(pc) \
    if (__builtin_expect((unsigned)(pc) - mac4_hook_lo <= mac4_hook_span, 0)) { \
        if (mac4_gdb_on && mac4_gdb_instr(pc)) break; else if (mac4_profiling) mac4_profile_instr(pc); \
        else if ((pc) == mac4_idle_pc) mac4_idle_instr(pc); }
#else
#define M68K_INSTRUCTION_CALLBACK(pc) \
    if (mac4_gdb_on && mac4_gdb_instr(pc)) break; else if (mac4_profiling) mac4_profile_instr(pc)
#endif
/* The bus cycles Musashi makes no memory callback for (our patch
 * harness/musashi-patches/0001-bus-cycles.patch; docs/cpu-timing.md):
 * n reads at address (n < 0: fewer).  Memory callbacks, a long one as
 * two, plus these are the 68000's bus cycles of each instruction. */
void mac4_bus_extra(unsigned address, int n);
#ifdef MAC4_IDLE_HOOK
/* In the EPROM and the SRAM, while the core's memory windows are on (our
 * patch 0008, harness/cpu_m68k.c), charged and counted there as
 * mac4_bus_extra would: one region each, no device behind them. */
#define M68K_BUS_EXTRA_CALLBACK(A, N) do { \
        unsigned mac4_xa = (A); \
        int mac4_xn = (N); \
        if (mac4_xn > 0 && mac4_xa - m68k_rom_window.base < m68k_rom_window.n1) \
            m68ki_window_charge(&m68k_rom_window, 0, mac4_xn); \
        else if (mac4_xn > 0 && mac4_xa - m68k_ram_window.base < m68k_ram_window.n1) \
            m68ki_window_charge(&m68k_ram_window, 0, mac4_xn); \
        else \
            mac4_bus_extra(mac4_xa, mac4_xn); \
    } while (0)
#else
#define M68K_BUS_EXTRA_CALLBACK(A, N) mac4_bus_extra(A, N)
#endif
/* The ROM window's memory is the EPROM's words in host order (our patch
 * 0013; harness/cpu_m68k.c keeps the copy), on a little-endian GCC host. */
#if defined(__GNUC__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define M68K_ROM_WINDOW_HOST_WORDS  OPT_ON
#else
#define M68K_ROM_WINDOW_HOST_WORDS  OPT_OFF
#endif
/* The emulator's bus errors are the 68000's (m68k_bus_error, our patch
 * 0007; cpu_m68k.c), which leave the registers as the instruction left
 * them, so the core saves none before every instruction (our patch
 * 0005-bus-error-save): Musashi's 68010 m68k_pulse_bus_error refuses. */
#define M68K_EMULATE_BUS_ERROR      OPT_OFF
#define M68K_EMULATE_PREFETCH       OPT_OFF
#define M68K_EMULATE_ADDRESS_ERROR  OPT_ON
#define M68K_ALINE_HOOK             OPT_OFF
#define M68K_ALINE_CALLBACK()
#define M68K_LOG_ENABLE             OPT_OFF
#define M68K_LOG_1010_1111          OPT_OFF
#define M68K_LOG_FILEHANDLE         stderr
#define M68K_EMULATE_PMMU           OPT_OFF
#define M68K_USE_64_BIT             OPT_ON

#endif
