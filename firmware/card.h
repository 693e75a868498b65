/* card.h - firmware state of the card and its four axes. */
#ifndef CARD_H
#define CARD_H
#include <stdint.h>

typedef struct {
    uint32_t ustat;     /* user status, manual 7.1.1 (RBS) */
    uint32_t sstat;     /* system status, manual 7.1.2 (RSS) */
    int32_t pos;        /* actual position */
    uint32_t counter;   /* last raw counter value */
    uint16_t ctrl;      /* shadow of the write-only bits of AX_CTRL */
    int16_t out;        /* DAC word (INC/SSI) or step rate (STP) */
} axis_t;

extern axis_t axes[4];
extern uint32_t card_ostat;   /* overall status, manual 7.1.3 (RAS) */
extern uint32_t card_ticks;   /* servo ticks since reset */

void card_reset(void);        /* outputs to reset state, defaults */
void card_start(void);        /* timer, serial, interrupts */
void card_profile_tick(void); /* profile generator, every PROFILE_DIVIDER ticks */

#endif
