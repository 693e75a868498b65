/* idle.h - the exact idle skip of the 68000's main loop (harness/idle.c,
 * docs/performance.md "The idle skip"). */
#ifndef IDLE_H
#define IDLE_H
#include <stdint.h>
#include <stdio.h>

typedef struct {
    uint64_t recordings, windows, failed;   /* windows recorded, closed, given up */
    uint64_t skips, instructions, cycles;   /* skips made, the instructions and cycles they stood for */
} idle_stats_t;
extern idle_stats_t idle_stats;
extern int mac4_idle_rec;           /* recording: cpu_m68k.c reports every access */
/* mac4_profiling's bit for the idle skip's recording: mac4_profile_instr
 * passes every instruction on to mac4_idle_instr (musashi_cnf.h) */
#define MAC4_PROFILING_IDLE 2
void mac4_idle_instr(unsigned pc);

void idle_reset(void);              /* a CPU reset: no window */
void idle_invalidate(void);
void idle_slice_start(uint64_t at); /* before each m68k_execute, at that cycle */
void idle_irq(void);                /* an interrupt acknowledge */
void idle_diverted(void);           /* the host or the script wrote the DPRAM */
/* a recorded instruction's accesses (cpu_m68k.c) */
void idle_rec_read(uint32_t addr, unsigned bytes);
void idle_rec_write(uint32_t addr, uint32_t v, unsigned bytes);
void idle_print_stats(FILE *f);
#endif
