/* axisboard.h - the state of the four axis interface boards (axisboard.c,
 * the only writer): the registers the firmware sees and the board's own
 * logic behind them (the position counter chip, the SSI receiver, the step
 * generator and its pulse down-counter).  What is wired to a board (the
 * plant: motor, drive, encoder, switches) is reached through the lines of
 * plant.h's "wires" section only. */
#ifndef AXISBOARD_H
#define AXISBOARD_H
#include <stdint.h>

#define SSI_FRAME_BITS 26                /* clocks per SSI read (manual 2.3.2) */
#define SSI_FRAME_MASK 0x3FFFFFFu

enum { AXB_PULSES_FREE, AXB_PULSES_COUNTING, AXB_PULSES_DONE };

typedef struct {
    /* ---- registers ---- */
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
    int stop;                      /* the /STOP line (sys.stop): /EN open whatever AX_CTRL_EN says */
    /* ---- the counter chip: counter = raw + cnt_off (mod 2^24), raw the
     * encoder's increments or (STP, BR closed) the steps generated ---- */
    int64_t cnt_off;
    uint32_t cnt_frozen;           /* the value while the encoder's lines are stuck */
    uint32_t cnt_seen;             /* what we last left in `counter` */
    int64_t raw_seen;
    /* ---- STP step generator: 16-bit phase accumulator clocked at 50 or
     * 500 kHz, and the pulse down-counter ---- */
    uint32_t acc;
    uint64_t nco_t;                /* clock edges up to this cycle are done */
    int pmode;                     /* AXB_PULSES_* */
    uint32_t remaining;            /* AX_PULSES */
    int64_t gen;                   /* pulses generated, signed by DIR */
    /* ---- SSI receiver: one 26-clock read ---- */
    uint64_t ssi_start, ssi_end;
    uint32_t ssi_old, ssi_frame;
} axis_hw_t;

#endif
