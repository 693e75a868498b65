/* timer.h - the state of the periodic timer and its microsecond counter
 * (timer.c, the only writer; perf.c's `perf hold` moves `next`). */
#ifndef TIMER_H
#define TIMER_H
#include <stdint.h>

typedef struct {
    uint16_t period_us, ctrl, status;
    uint64_t next;                 /* next expiry, CYC_NEVER when stopped */
    uint64_t last;                 /* last expiry (TMR_COUNT) */
    uint64_t irq_at;               /* TMR_CTRL_SSI_WAIT: the request waits for the SSI reads until then */
    uint16_t free_lo_latch;        /* TMR_FREE_LO, latched by reading TMR_FREE_HI */
} tmr_t;

#endif
