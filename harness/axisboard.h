/* axisboard.h - the state of the four axis interface boards (axisboard.c;
 * the plant behind them writes only the lines it drives, plant.c). */
#ifndef AXISBOARD_H
#define AXISBOARD_H
#include <stdint.h>

typedef struct {
    uint32_t counter;              /* 24-bit position counter */
    uint16_t cnt_lo_latch;
    uint32_t idx_latch;
    uint16_t idx_lo_latch;
    int idx_latched;
    uint16_t in;                   /* switch inputs, AX_IN_* */
    uint16_t ctrl;
    int16_t dac;
    uint16_t rate;
    uint32_t ssi;                  /* last SSI shift register */
    int gray;                      /* SSI jumper J1 open */
    uint16_t pstat;                /* STP: AX_IN_PULSE, AX_IN_PULSE_OVR, AX_IN_PDONE */
} axis_hw_t;

#endif
