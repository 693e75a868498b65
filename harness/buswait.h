/*
 * buswait.h - the card's bus timing in the emulator (hal/mac4_map.h
 * MAC4_BUS_TIMING, docs/memory-map.md "Bus timing"): the wait states of
 * every bus cycle by region and access kind, the DPRAM's contention with
 * the VME host, the interrupt acknowledge.  The 68000 core charges them as
 * it makes its bus cycles (cpu_m68k.c); a long access is two bus cycles.
 */
#ifndef BUSWAIT_H
#define BUSWAIT_H
#include <stdint.h>
#include <stdio.h>
#include "mac4_map.h"

/* Regions: the rows of MAC4_BUS_TIMING in order, then the unmapped rest. */
#define BW_COUNT(name, base, size, rd, wr) +1
enum { BW_UNMAPPED = 0 MAC4_BUS_TIMING(BW_COUNT), BW_NREGIONS };
#undef BW_COUNT

enum { BW_IACK_AUTOVECTOR, BW_IACK_VECTORED };

typedef struct {
    uint8_t ws[BW_NREGIONS][2];     /* wait states per bus cycle: [region][0 read, 1 write] */
    int iack;                       /* BW_IACK_* */
    unsigned iack_vectored_wait;    /* BW_IACK_VECTORED: the interrupter's wait states */
    unsigned host_clocks;           /* a VME host's access holds its DPRAM word this long */
} buswait_cfg_t;

typedef struct {
    uint64_t cycles[BW_NREGIONS][2];    /* bus cycles made */
    uint64_t wait[BW_NREGIONS][2];      /* wait-state clocks charged for them */
    uint64_t contention, contention_clocks;   /* DPRAM accesses that waited for the host */
    uint64_t iacks, iack_clocks;        /* interrupt acknowledges and their clocks beyond 4 */
} buswait_stats_t;

extern buswait_cfg_t buswait_cfg;
extern buswait_stats_t buswait_stats;
extern const uint8_t *buswait_page;     /* region of each 256-byte page of the 24-bit space */
extern const char *const buswait_names[BW_NREGIONS];
/* Bus cycles counted elsewhere (the core's memory windows, cpu_m68k.c)
 * put into buswait_stats: called before anything reads them. */
extern void (*buswait_sync)(void);

void buswait_init(void);                /* the defaults of hal/mac4_map.h */
/* "N" (every region, both kinds), or a comma list of REGION=N,
 * REGION.read=N, REGION.write=N, default; 0 or -1 with a message */
int buswait_parse(const char *spec, char *err, size_t errlen);
int buswait_parse_iack(const char *spec);   /* autovector | vectored */
void buswait_print(FILE *f);            /* the configuration, one line */
void buswait_print_stats(FILE *f);      /* `bus-stats` */
void buswait_reset_stats(void);
/* A copy of the counts and the cycle count at an instant (the display's
 * last change, sysctl.c): `bus-stats display` prints it. */
void buswait_mark(uint64_t now);
void buswait_print_mark(FILE *f);

/* The wait states of one access of `bus` bus cycles (1, or 2 for a long)
 * at addr, counted.  write: 0 or 1. */
static inline unsigned buswait_charge(uint32_t addr, int write, unsigned bus)
{
    unsigned r = buswait_page[(addr & 0xFFFFFF) >> 8];
    unsigned w = buswait_cfg.ws[r][write] * bus;
    buswait_stats.cycles[r][write] += bus;
    buswait_stats.wait[r][write] += w;
    return w;
}

/* The core's "n bus cycles fewer" (musashi_cnf.h M68K_BUS_EXTRA_CALLBACK
 * with n < 0: STOP's words were in the prefetch queue): their reads and
 * wait states taken back.  Returns the clocks to give back. */
static inline unsigned buswait_refund(uint32_t addr, unsigned bus)
{
    unsigned r = buswait_page[(addr & 0xFFFFFF) >> 8];
    unsigned w = buswait_cfg.ws[r][0] * bus;
    buswait_stats.cycles[r][0] -= bus;
    buswait_stats.wait[r][0] -= w;
    return w;
}

/* DPRAM contention: the host's accesses (host.c) occupy their words from
 * `at` on, one after the other; a card access at `now` to a word the host
 * holds waits until it is free.  Returns the clocks to wait (counted). */
void buswait_host_access(uint64_t at, uint32_t off);
unsigned buswait_dpram_contention(uint64_t now, uint32_t off);
/* the cycle from which no host access holds a DPRAM word (the idle skip) */
uint64_t buswait_host_free(void);
/* The clocks the interrupt acknowledge takes beyond the 4 of Musashi's
 * 44-cycle interrupt (counted). */
unsigned buswait_iack(void);

#endif
