/* card.h - firmware state of the card and its four axes. */
#ifndef CARD_H
#define CARD_H
#include <stdint.h>
#include "status.h"

typedef struct {
    uint32_t ustat;     /* user status, manual 7.1.1 (RBS); bits 0-7 = mode */
    uint32_t sstat;     /* system status, manual 7.1.2 (RSS) */
    uint8_t mode;       /* mode in force (M_*) */
    uint8_t next_mode;  /* mode selected for the next E, or NO_MODE */
    uint16_t err_report;/* error code to give as the answer to the next command, 0 none */
    uint16_t ctrl;      /* shadow of AX_CTRL */
    int16_t out;        /* DAC word (INC/SSI) or step rate (STP) */
    uint16_t in;        /* last switch inputs, AX_IN */
    /* position measurement */
    int32_t pos;        /* actual position: measured + <ao> (RCP) */
    int32_t meas;       /* measured position without offset */
    uint32_t raw;       /* last raw value read (RED) */
    uint32_t counter;   /* last processed counter content (RCT) */
    int32_t vel;        /* actual velocity per servo period (RAV) */
    int32_t setpoint;
    int32_t ferr;
    int32_t zp_value;   /* last WZP value, read back by RZP */
} axis_t;

#define NO_MODE 0xFF

extern axis_t axes[MAC4_NAXES];
extern uint32_t card_ostat;     /* overall status, manual 7.1.3 (RAS) */
extern uint16_t card_err_report;/* 164/165 for the next command on any axis */
extern uint32_t card_ticks;     /* servo ticks since reset */

void card_reset(void);          /* outputs to reset state, defaults */
void card_start(void);          /* timer, serial, interrupts */
void card_profile_tick(void);   /* profile generator, every PROFILE_DIVIDER ticks */

/* Axis state changes used by commands and by the protective reactions. */
void axis_set_mode(unsigned n, uint8_t mode);
void axis_disable(unsigned n);             /* at once, no ramp */
void axis_error(unsigned n, uint32_t ubit, uint16_t code);  /* set bit, report code next */
int axis_standstill(unsigned n);
static inline int axis_initialised(unsigned n) { return (axes[n].ustat & UB(INIT)) != 0; }
void axis_init_measurement(unsigned n);    /* INIT: derive ea/eb/ec, zero relative position */

/* VMEbus interrupts (4.6): vector 0 = off. */
void vme_irq(uint8_t vector);
void vme_irq_service(void);

#endif
