/*
 * floorrun.h - the floor routines' runner (bench/floor/README.md): a 68000
 * (the emulator's Musashi core, our patches, the bus model of
 * harness/buswait.c) on a plain memory with the few device behaviours a
 * routine depends on, and the card modules (ref_servo.c, ref_stp.c, ...)
 * that generate inputs, run the firmware's C on them and compare.
 */
#ifndef FLOORRUN_H
#define FLOORRUN_H
#include <stddef.h>
#include <stdint.h>

/* ---- memory: 16 MiB, big-endian, no device, no cycles ------------------ */
extern uint8_t *fmem;
uint8_t m_rd8(uint32_t a);
uint16_t m_rd16(uint32_t a);
uint32_t m_rd32(uint32_t a);
void m_wr8(uint32_t a, uint8_t v);
void m_wr16(uint32_t a, uint16_t v);
void m_wr32(uint32_t a, uint32_t v);

/* ---- the devices: what both the routine and the firmware's C (through
 * hal.h, implemented here) see.  Everything not listed is plain memory.
 *  - VME_PAGE and the master window: a read at page:offset answers from a
 *    board of vme_boards[] (a 32-bit value, MSW at its address), else
 *    $FFFF and VME_STATUS.BERR, which a read of VME_STATUS clears;
 *  - AX_IN(n): AX_IN_SSI_BUSY for the next ssi_busy[n] reads. */
#define FLOOR_NBOARDS 4
typedef struct {
    uint32_t a24;       /* A24 address of the MSW, 0: none */
    uint32_t value;
} vme_board_t;
typedef struct {
    vme_board_t vme_boards[FLOOR_NBOARDS];
    uint16_t vme_page, vme_berr;
    unsigned ssi_busy[4];
} devstate_t;
extern devstate_t dev;
uint32_t dev_read(uint32_t a, int size);
void dev_write(uint32_t a, uint32_t v, int size);

/* ---- running a routine --------------------------------------------------- */
/* Load a routine (raw binary, linked at FLOOR_CODE). 0 or -1 with a message. */
int floor_load(const char *path);
/* The routine as an interrupt handler of level 6: the CPU waits at
 * FLOOR_IDLE with the mask at 0, the interrupt comes; cycles from the
 * acknowledge to the end of the RTE, the way harness/sim.c counts them.
 * The registers d0-a6 must come back as they were (checked).  Returns the
 * cycles, or 0 with err set (an exception, no RTE, a register changed). */
uint64_t floor_isr(uint32_t entry, char *err, size_t errlen);
/* The routine as a subroutine (JSR entry, ... RTS) with a0 = arg: cycles
 * from its first instruction to the return address, as perf.c's probes
 * count a function; d0-d1/a0-a1 may change (the C ABI's scratch). */
uint64_t floor_call(uint32_t entry, uint32_t a0, char *err, size_t errlen);

/* ---- comparing ------------------------------------------------------------ */
/* For a module's compare(): the routine's results are saved and the inputs
 * put back (memory, registers, devices) for the firmware's C to run on. */
void floor_restore_inputs(void);
/* After the C ran and its state was written back the routine's way: the
 * SRAM (but the stack), the DPRAM (but the vectors), the I/O registers and
 * the VMEbus state against the routine's.  fields names an axis record's bytes for the message. */
typedef struct {
    unsigned off, size;
    const char *name;
} field_t;
int floor_compare(char *msg, size_t len, const field_t *fields, unsigned nfields);

/* ---- random inputs ------------------------------------------------------- */
uint32_t rnd(void);
uint32_t rnd_below(uint32_t n);             /* 0 .. n-1 */
int32_t rnd_range(int32_t lo, int32_t hi);  /* lo .. hi */
int rnd_pct(unsigned pct);                  /* 1 with that probability */

/* ---- the card modules ---------------------------------------------------- */
typedef struct {
    const char *name;           /* the routine: DIR/NAME.bin */
    /* broad random inputs (check) or a scenario's (measure: scen >= 0) */
    void (*gen)(int scen);
    /* run the firmware's C on the inputs gen made (the same memory) and
     * compare with what the routine left; 0 equal, else 1 and a message */
    int (*compare)(char *msg, size_t len);
    int isr;                    /* 1: an interrupt handler, 0: a subroutine */
    uint32_t (*arg)(void);      /* a subroutine's a0 */
} routine_t;
typedef struct {
    const char *name;           /* tools/perfscen.py's scenario name */
    const char *routine;
    int scen;                   /* passed to gen */
    const char *what;           /* one line: the path */
    int baseline;               /* 0: the figure is the worst; else the mean beyond the least
                                 * of gen(baseline - 1) (a command pass beyond an idle pass) */
} scenario_t;
typedef struct {
    const char *card;           /* inc, ssi, stp */
    const char *kind;           /* tick, supervise, command */
    const routine_t *routines;
    unsigned nroutines;
    const scenario_t *scenarios;
    unsigned nscenarios;
} module_t;
/* every module of this card's runner (ref_*.c), NULL-terminated */
extern const module_t *const floor_modules[];

#endif
