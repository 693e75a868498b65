/* cpu.h - what the scheduler needs from a CPU: the EPROM image on Musashi
 * (cpu_m68k.c) or, later, the firmware compiled for the host. */
#ifndef CPU_H
#define CPU_H
#include "sim.h"

typedef struct {
    const char *name;
    void (*reset)(sim_t *s);                 /* hardware reset line */
    cyc_t (*execute)(sim_t *s, cyc_t max);   /* run up to max cycles, return cycles used */
    void (*set_irq)(int level);
    int (*halted)(void);
} cpu_t;

extern const cpu_t cpu_m68k;
/* 1 (default): the emulator's speedups (cpu_m68k.c, docs/performance.md);
 * 0 (mac4sim --no-fast): all off, every fetch through the memory
 * callbacks.  Outputs and cycle counts are the same either way. */
extern int mac4_fast;
/* cpu_m68k.c: the core's memory windows set anew for what watches memory
 * now (the idle skip's recording, gdb, an SRAM fault) */
void cpu_m68k_windows(void);

/* run.c: the scheduler */
void sim_attach_cpu(sim_t *s, const cpu_t *cpu);
void sim_reset(sim_t *s, const char *why);
void sim_run(sim_t *s, cyc_t cycles);
void sim_update_irq(sim_t *s);
extern int sim_halted;
/* why the CPU halted, set by its halted() for run.c's report: ": ..." or "" */
extern char sim_halt_why[200];

#endif
