/*
 * m68k_bare.c - the bare Musashi core on an EPROM image, for `make bench`
 * (docs/performance.md): the same core, configuration and compiled objects
 * as build/mac4sim, but the whole 16 MiB address space is plain memory (the
 * image at $000000 for the reset vectors and at $100000), no peripheral, bus
 * map, plant or scheduler; the timer interrupt (level 6, autovector) is
 * raised every servo period so the firmware runs its tick as on the card.
 * The ratio of its speed to mac4sim's is the harness overhead.
 *
 *   mac4bare IMAGE SECONDS [PERIOD_US]     prints "bare cycles=N wall_s=W"
 */
#define _POSIX_C_SOURCE 199309L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "m68k.h"
#include "mac4_map.h"

static uint8_t *mem;
#define A(a) ((a) & 0xFFFFFFu)

unsigned int m68k_read_memory_8(unsigned int a) { return mem[A(a)]; }
unsigned int m68k_read_memory_16(unsigned int a) { return (unsigned)mem[A(a)] << 8 | mem[A(a + 1)]; }
unsigned int m68k_read_memory_32(unsigned int a)
{
    return (unsigned)mem[A(a)] << 24 | (unsigned)mem[A(a + 1)] << 16 | (unsigned)mem[A(a + 2)] << 8 | mem[A(a + 3)];
}
void m68k_write_memory_8(unsigned int a, unsigned int v) { mem[A(a)] = (uint8_t)v; }
void m68k_write_memory_16(unsigned int a, unsigned int v)
{
    mem[A(a)] = (uint8_t)(v >> 8);
    mem[A(a + 1)] = (uint8_t)v;
}
void m68k_write_memory_32(unsigned int a, unsigned int v)
{
    m68k_write_memory_16(a, v >> 16);
    m68k_write_memory_16(a + 2, v & 0xFFFF);
}
unsigned int m68k_read_disassembler_8(unsigned int a) { return m68k_read_memory_8(a); }
unsigned int m68k_read_disassembler_16(unsigned int a) { return m68k_read_memory_16(a); }
unsigned int m68k_read_disassembler_32(unsigned int a) { return m68k_read_memory_32(a); }

/* the hooks harness/musashi_cnf.h names */
int mac4_profiling;
int mac4_gdb_on;                                    /* no gdb stub here */
unsigned mac4_idle_pc = 1;                          /* no idle skip here: odd, never a PC */
unsigned mac4_hook_lo = 1, mac4_hook_span;             /* the hook: PC 1 alone (musashi_cnf.h) */
void mac4_idle_instr(unsigned pc) { (void)pc; }
int mac4_gdb_instr(unsigned pc) { (void)pc; return 0; }
void mac4_profile_instr(unsigned pc) { (void)pc; }
int mac4_int_ack(int level)
{
    (void)level;
    m68k_set_irq(0);                  /* the tick is acknowledged at once */
    return (int)M68K_INT_ACK_AUTOVECTOR;
}
void mac4_rte(void) {}
int mac4_illegal(int opcode) { (void)opcode; return 0; }
void mac4_reset_instr(void) {}
void mac4_bus_extra(unsigned address, int n) { (void)address; (void)n; }

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: mac4bare IMAGE SECONDS [PERIOD_US]\n");
        return 1;
    }
    double seconds = atof(argv[2]);
    unsigned period_us = argc > 3 ? (unsigned)atoi(argv[3]) : SERVO_PERIOD_US_SERVO;
    mem = calloc(1, 1u << 24);
    FILE *f = fopen(argv[1], "rb");
    if (!mem || !f) {
        fprintf(stderr, "mac4bare: cannot load %s\n", argv[1]);
        return 1;
    }
    size_t n = fread(mem + EPROM_BASE, 1, EPROM_SIZE, f);
    fclose(f);
    memcpy(mem, mem + EPROM_BASE, n);   /* the boot overlay, never released here */
    m68k_init();
    m68k_set_cpu_type(M68K_CPU_TYPE_68000);
    m68k_pulse_reset();
    const uint64_t total = (uint64_t)(seconds * MAC4_CPU_HZ);
    const int slice = (int)(period_us * MAC4_CYCLES_PER_US);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    uint64_t done = 0;
    while (done < total) {
        done += (uint64_t)m68k_execute(slice);
        m68k_set_irq(IRQ_LEVEL_TIMER);
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double wall = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) * 1e-9;
    printf("bare cycles=%llu wall_s=%.6f emulated_per_wall=%.2f\n", (unsigned long long)done, wall,
           (double)done / MAC4_CPU_HZ / wall);
    return 0;
}
