/* sysctl.h - the state of the IPC's system control, its watchdog and the
 * /STOP input (sysctl.c, the only writer; the jumpers and inputs are set
 * by the script and the command line before the card runs).  The boot
 * overlay bit stays in sim_t: it is the line the address decoder reads. */
#ifndef SYSCTL_H
#define SYSCTL_H
#include <stdint.h>

typedef struct {
    uint16_t display, leds;
    int estop;                     /* /STOP active */
    int estop_edge;                /* /STOP is wired to the edge-triggered level 7 (NMI) */
    uint8_t fc;                    /* FC0-2 inputs */
} sys_t;

typedef struct {
    int j11;                       /* jumper J11 in: the watchdog may reset the card */
    uint64_t deadline;
    int reset_pending;
} wdg_t;

#endif
