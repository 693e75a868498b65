/*
 * gdbstub.h - a GDB remote serial protocol stub for the emulated 68000
 * (docs/debugging.md).  `mac4sim --gdb PORT` or the script command
 * `gdb PORT` listen on 127.0.0.1:PORT and wait, with the CPU stopped, for
 * gdb-multiarch to connect.  While the CPU is stopped nothing in the card
 * advances: the stub serves gdb from inside the CPU's slice, where no model
 * runs.  Breakpoints are kept in the stub (never written into the EPROM).
 */
#ifndef GDBSTUB_H
#define GDBSTUB_H
#include "sim.h"

extern int mac4_gdb_on;             /* a gdb is attached: the instruction hook asks the stub */

/* The instruction hook (musashi_cnf.h): 1 = stop before the instruction at
 * pc (the hook then leaves m68k_execute's loop without executing it). */
int mac4_gdb_instr(unsigned pc);

/* Listen on 127.0.0.1:port (0 = any free port), print `gdb-port N`, wait
 * for gdb and serve it with the CPU stopped until it continues or detaches.
 * Returns 0, or -1 with a message on stderr. */
int gdbstub_attach(sim_t *s, int port);

/* cpu_m68k.c, around m68k_execute: */
void gdbstub_slice_start(sim_t *s, long long budget);   /* Ctrl-C and stops between slices */
int gdbstub_stopped_in_slice(void);   /* the last m68k_execute ended at a stop */
void gdbstub_serve_stop(sim_t *s, long long left);  /* serve gdb until it resumes the CPU */
void gdbstub_resume_in_slice(void);   /* before m68k_execute goes on with the same slice */
/* CPU data accesses, for watchpoints (only while watchpoints are set) */
extern int mac4_gdb_watching;
void gdbstub_access(unsigned addr, int size, int write);

/* After the script the card runs on while gdb is attached (panel.c
 * bench_serve, paced to the wall clock) until gdb detaches. */
int gdbstub_attached(void);
/* Wall-clock seconds spent stopped so far (pacing loops subtract them). */
double gdbstub_stopped_seconds(void);

#endif
