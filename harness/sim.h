/*
 * sim.h - the emulated MAC4 card: bus, peripheral models, scheduler,
 * interrupt accounting and the VME host.  One card per process.
 *
 * Time is counted in 68000 clock cycles at 16 MHz.  The CPU backend
 * (Musashi for the EPROM image, or the natively compiled firmware) runs in
 * slices that end at the next peripheral event, so every model sees the
 * cycle count at which the firmware touched it.
 */
#ifndef SIM_H
#define SIM_H
#include <stdint.h>
#include <stdio.h>
#include "mac4_map.h"

typedef uint64_t cyc_t;
#define CYC_NEVER UINT64_MAX
#define US_TO_CYC(us) ((cyc_t)(us) * MAC4_CYCLES_PER_US)
#define MS_TO_CYC(ms) ((cyc_t)(ms) * 1000u * MAC4_CYCLES_PER_US)
/* 4800 baud, 8N1: 10 bit times per character. */
#define UART_CHAR_CYC ((cyc_t)(MAC4_CPU_HZ * 10u / UART_BAUD))

/* the devices' states, each declared by its device (periph.c's table) */
#include "sysctl.h"
#include "timer.h"
#include "uart.h"
#include "virq.h"
#include "axisboard.h"
#include "plant.h"     /* what is wired to the axis boards */

/* Interrupt sources, for the accounting table. */
enum { SRC_UART, SRC_AXIS, SRC_TIMER, SRC_ESTOP, SRC_OTHER, SRC_COUNT };

typedef struct {
    uint64_t count;
    cyc_t min, max, sum;           /* acknowledge to end of RTE, nested ISRs included */
    cyc_t xmin, xmax, xsum;        /* the same without the time of nested ISRs */
    cyc_t worst_at;                /* cycle count when the worst case started */
    /* latency, request to acknowledge (the timer: its expiry, or the end of
     * the SSI reads it waits for); the other sources' requests are level
     * signals without a time of their own */
    uint64_t lat_count;
    cyc_t lat_max, lat_sum, lat_worst_at;
} irqstat_t;

/* Named signals between the device models (as simavr's IRQs): a device
 * raises one with a value, the devices periph_connect() wired to it at
 * sim_init react, in the order they were connected.  No device calls into
 * another's model for what a wire between the two carries. */
struct sim;
typedef void (*sim_sig_hook_t)(struct sim *s, uint64_t value);
#define SIM_SIG_HOOKS 4
typedef struct {
    const char *name;
    sim_sig_hook_t hook[SIM_SIG_HOOKS];
    unsigned n;
} sim_sig_t;
enum {
    SIG_TMR_EXPIRED,               /* timer -> axis board: it expired; value: the expiry's cycle count */
    SIG_SSI_BUSY,                  /* axis board -> timer: an SSI receiver reads until value (a cycle count) */
    SIG_STOP,                      /* /STOP input -> axis boards: value 1 active (it opens every /EN) */
    SIG_COUNT
};

typedef struct sim {
    int card;                      /* MAC4_CARD_* */
    uint8_t dpram[DPRAM_SIZE];
    uint8_t eprom[EPROM_SIZE];
    uint8_t eprom_words[EPROM_SIZE];   /* the same in host word order: the core's ROM window (cpu_m68k.c) */
    uint8_t sram[SRAM_SIZE];
    uint32_t sram_fault_addr;      /* fault injection: bits stuck at 1 in this word */
    uint16_t sram_fault_mask;
    uint16_t sysctl;               /* SYS_CTRL: its boot overlay bit is the line the address decoder reads */
    sim_sig_t sig[SIG_COUNT];      /* the wires between the devices (periph_connect) */

    /* ---- the devices' states (periph.c's table).  Each type is declared in
     * its device's header and written by its device's file (the script and
     * the tools set jumpers and inputs between runs); they are stored here,
     * by value, so that a copy of sim_t is a snapshot of the whole card
     * (the fuzz targets' fast boot). ---- */
    sys_t sys;                     /* sysctl.c: display, LEDs, /STOP, FC inputs */
    wdg_t wdg;                     /* sysctl.c: the watchdog */
    tmr_t tmr;                     /* timer.c */
    uart_t uart;                   /* uart.c */
    vme_t vme;                     /* virq.c */
    axis_hw_t ax[MAC4_NAXES];      /* axisboard.c: the axis interface boards */
    int ssi_clock;                 /* axisboard.c: the SSI clock jumper J2, 0..3 = A..D (table 2.8) */
    plant_t plant;                 /* plant.c: what is wired to them */

    cyc_t slice_base;              /* cycle count at the start of the CPU slice */
    cyc_t (*cpu_elapsed)(void);    /* cycles into the current slice */
    int in_reset_by_wdg;
    uint64_t resets;

    /* interrupt accounting */
    irqstat_t irq[SRC_COUNT];
    struct { int src; cyc_t start, nested; } active[8];
    int nactive;

    /* faults the emulator saw: unmapped access, EPROM write, address error ... */
    uint64_t faults;
    uint32_t (*cpu_pc)(void);

    /* the VME host model */
    int host_reads;                /* host dequeues responses */
    cyc_t host_next_poll;
    uint64_t vme_irqs;

    FILE *out;                     /* where events are printed */
    int timestamps;
    int quiet;                     /* `perf quiet on`: out is /dev/null, events are not even formatted */

    /* ---- added for measurement and the differential test (harness/perf.c,
     * docs/performance.md).  All hooks are NULL unless perf.c sets them. ---- */
    cyc_t irq_window_start;        /* `irqstats` load%: cycles counted from here */
    /* an ISR ended: its source, start, inclusive and exclusive cycles, and the
     * nesting depth left behind (0: it had interrupted the main loop) */
    void (*on_irq_leave)(struct sim *s, int src, cyc_t start, cyc_t dur, cyc_t excl, int depth);
    /* after every bus write (CPU or native firmware; not the host's DPRAM writes,
     * not the 68000's SRAM writes, which take cpu_m68k.c's fast path) */
    void (*on_bus_write)(struct sim *s, uint32_t addr, uint32_t v, int size);
    /* at the start of every scheduler slice, after the peripheral events and
     * the host's poll (host_polled: the host looked at the queue just now) */
    void (*on_slice)(struct sim *s, cyc_t now, int host_polled);
    /* Axis board on logical time (`perf axis-sync on`, the differential
     * test): the axis board and the plant advance one timer period at every
     * tick and AXIS_SYNC_STEP cycles at every access in between, so two CPUs
     * that make the same accesses in a different time see the same plant.
     * sim_axis_now(); perf.c also holds the timer while the card works on
     * host input.  Not for plant commands or resets while it runs. */
    int axis_sync;
    cyc_t axis_base;               /* logical time of the last tick */
    cyc_t axis_tick_seen;          /* tmr.last when it was taken */
    uint32_t axis_n;               /* accesses since */
    /* ---- end of measurement additions ---- */
    struct vcd *vcd;               /* `vcd FILE`: the waveform dump (harness/vcd.c), NULL when off */
    void (*on_display)(struct sim *s);   /* the display changed (the front panel, panel.c) */
    void (*on_fault)(struct sim *s);     /* after a `fault` line (gdbstub.c) */
} sim_t;

#define AXIS_SYNC_STEP 16u          /* axis clock cycles per axis-board access */

extern sim_t *g_sim;

/* bus.c */
uint32_t bus_read(sim_t *s, uint32_t addr, int size);           /* size 1, 2 or 4 */
void bus_write(sim_t *s, uint32_t addr, uint32_t v, int size);
void sim_fault(sim_t *s, const char *fmt, ...);
/* reads through the bus map (every CPU read but the memories' fast path):
 * the idle skip records no window after a pass that made one (idle.c) */
extern uint64_t bus_reads;
/* the last bus_read/bus_write got /BERR (no device acknowledged), at
 * bus_berr_addr (bus.c; docs/board.md "Bus errors") */
extern int bus_berr;
extern uint32_t bus_berr_addr;
int bus_decodes(uint32_t addr, int write, int size);   /* 1: a device acknowledges */

/* periph.c: the device table */
void periph_connect(sim_t *s);     /* wire the signals (sim_init) */
void sig_connect(sim_t *s, int sig, sim_sig_hook_t hook);
void sig_raise(sim_t *s, int sig, uint64_t value);
void periph_reset(sim_t *s);
cyc_t periph_next_event(sim_t *s);
void periph_events(sim_t *s, cyc_t now);
int sim_irq_level(sim_t *s);
unsigned sim_irq_lines(sim_t *s);  /* bit L set: a request at level L */
int sim_irq_source(int level);
void uart_feed(sim_t *s, const uint8_t *bytes, unsigned n);

/* sim.c */
void sim_init(sim_t *s, int card);
int sim_load_image(sim_t *s, const char *path);
cyc_t sim_now(sim_t *s);
void sim_printf(sim_t *s, const char *fmt, ...);
void irq_enter(sim_t *s, int level);
void irq_leave(sim_t *s, cyc_t extra);
void irq_print_table(sim_t *s, FILE *f);
cyc_t sim_axis_now(sim_t *s);      /* the time of an axis-board access (counts it) */
cyc_t sim_axis_peek(sim_t *s);     /* the same without counting an access */

/* host.c: the VME host's side of the DPRAM queues */
uint32_t dp_rd32(sim_t *s, uint32_t off);
uint16_t dp_rd16(sim_t *s, uint32_t off);
void dp_wr32(sim_t *s, uint32_t off, uint32_t v);
extern void (*dp_written)(void);   /* after every dp_wr16 (and a script's poke8), if set */
void dp_wr16(sim_t *s, uint32_t off, uint16_t v);
int host_send(sim_t *s, uint8_t axis, uint16_t code, uint32_t param, uint8_t source);
int host_poll_responses(sim_t *s);

#endif
