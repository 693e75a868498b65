/* measure.h - position measurement (manual 4.4, table 4.3). */
#ifndef MEASURE_H
#define MEASURE_H
#include "inline.h"
#include <stdint.h>
#include "hal.h"
#include "mul16.h"
#include "card.h"
#include "params.h"

void measure_init(unsigned n);     /* INIT: derive <ea>/<eb>/<ec>, zero relative position */
void measure_set_pos(unsigned n);  /* main loop: pos from meas and <ao>, wrapped */
/* May an external position (<et> 3/4) be read at <ea> with <eb> significant
 * bits (eb 0: not known yet)?  The rule of docs/interpretations.md. */
int measure_ea_ok(uint32_t ea, int32_t eb);

/* ---- what INIT prepares for the tick (measure_init) ------------------------
 * Where an external position is read, validated once at INIT so that
 * measure_ext_read() never touches any other address (whatever <ea> holds later),
 * and the counter range in force, so that the tick needs no division. */
enum { EXT_NONE, EXT_DPRAM, EXT_VME16, EXT_VME32, EXT_SSI };
typedef struct {
    uint32_t addr;      /* EXT_DPRAM: offset of the value; EXT_VME*: window address of the MSW */
    uint32_t lim;       /* the largest valid value: <ec> - 1, or 2^<eb> - 1 */
    int32_t range;      /* relative modulo <ec> when <ec> < 2^<eb>, else 0 (2^<eb>: delta_eb) */
    int32_t half;       /* range / 2 */
    uint32_t mask;      /* 2^<eb> - 1 */
    uint32_t sign;      /* relative: bit <eb>-1, the sign of a delta (0: 32 bits) */
    uint16_t page;      /* EXT_VME*: VME_PAGE, A23-A20 */
    uint8_t path;       /* EXT_*; EXT_NONE for the INC/STP counter and a refused <ea> */
    uint8_t sc;         /* EXT_SSI: right shifts <sc> (4.4.2.2) */
    uint8_t abs;        /* absolute measurement (<et> 2, 4) */
    uint8_t failed;     /* an encoder error was raised and the axis has not run since (6.3.8;
                         * axis_set_mode clears it when the axis runs again) */
} meas_cfg_t;
extern meas_cfg_t meas_cfg[MAC4_NAXES];
void measure_encoder_error(unsigned n);   /* 6.3.8, once (measure.c) */

/* ---- per card: servo_meas.c (INC, SSI), stp_meas.c (STP) -------------------
 * The tick's external measurement (MK_OTHER), out of line so that the tick's
 * common paths keep their registers (the tick has the common case inline:
 * tick_servo.c tick_measure_ext); the pointers are the tick's
 * constants.  The STP turns the reading into steps (4.4.2.3). */
void measure_ext(axis_t *x, meas_cfg_t *c, unsigned n);
/* INC/SSI: the same for axis 0 .. 3, the tick's (tick_servo.c measure_ext_axis) */
void measure_ext_0(void);
void measure_ext_1(void);
void measure_ext_2(void);
void measure_ext_3(void);
/* INC/SSI: the encoder error of the tick's inline path, axis 0 .. 3 */
void measure_ext_error_0(void);
void measure_ext_error_1(void);
void measure_ext_error_2(void);
void measure_ext_error_3(void);
/* The end of INIT's set-up (measure_init), before the tick's copies: the
 * STP's ratio, tolerance and BR check; nothing on INC/SSI. */
void measure_init_card(unsigned n);

/* An external position (<et> 3/4, 3.5.2, 4.4.2.1) where INIT found it
 * (meas_cfg.path): 0 and the value, or -1 when the measurement failed.
 * INIT's first reading (measure.c) and the tick's (measure_ext_valid); vme32,
 * a constant: the caller knows the path is EXT_VME32. */
FW_INLINE int measure_ext_read_k(axis_t *x, unsigned n, const meas_cfg_t *c,
                                                                  uint32_t *raw, int vme32)
{
    uint32_t v;
    /* the paths in the order of their frequency: <eb> above 16 first */
    if (vme32 || c->path == EXT_VME32) {                /* LSW at <ea>+2 first (4.4.2.1) */
        hal_wr16(VME_PAGE, c->page);
        uint32_t lsw = hal_rd16(c->addr + 2u);
        v = ((uint32_t)hal_rd16(c->addr) << 16) | lsw;
    } else if (c->path == EXT_VME16) {                  /* external over the VMEbus, A24 window */
        hal_wr16(VME_PAGE, c->page);
        v = hal_rd16(c->addr);
    } else if (c->path == EXT_DPRAM) {                  /* external, via the DPRAM (3.5.2) */
        if (hal_rd16(c->addr - 2u) & 0x8000u) {
            x->raw = hal_rd32(c->addr);
            hal_wr16(c->addr - 2u, 0);                  /* the host may write the next one */
            vme_irq((uint8_t)PAR(n, IRQ6));
        }
        *raw = x->raw;
        return 0;
    } else {
        return -1;                                      /* no address INIT accepted: touch nothing */
    }
    if (hal_rd16(VME_STATUS) & VME_ST_BERR)
        return -1;
    *raw = v;
    return 0;
}

FW_INLINE int measure_ext_read(axis_t *x, unsigned n, const meas_cfg_t *c, uint32_t *raw)
{
    return measure_ext_read_k(x, n, c, raw, 0);
}

/* The tick's external reading within <eb> and <ec>: 0 and the value, or -1
 * when it is an encoder error (6.3.8), which the caller raises; RED shows a
 * value beyond <ec>. */
FW_INLINE int measure_ext_valid_k(axis_t *x, const meas_cfg_t *c, unsigned n,
                                                                   uint32_t *rawp, int vme32)
{
    uint32_t raw;
    if (measure_ext_read_k(x, n, c, &raw, vme32))
        return -1;
    raw &= c->mask;
    if (RARELY(raw > c->lim)) {                         /* beyond <ec> (4.4.2.1, 6.3.8) */
        x->raw = raw;
        return -1;
    }
    *rawp = raw;
    return 0;
}

FW_INLINE int measure_ext_valid(axis_t *x, const meas_cfg_t *c, unsigned n, uint32_t *rawp)
{
    return measure_ext_valid_k(x, c, n, rawp, 0);
}

/* ... and raised (measure_encoder_error) */
FW_INLINE int measure_ext_checked(axis_t *x, meas_cfg_t *c, unsigned n,
                                                                     uint32_t *rawp)
{
    if (measure_ext_valid(x, c, n, rawp)) {
        measure_encoder_error(n);
        return -1;
    }
    return 0;
}

FW_INLINE uint32_t gray_to_binary(uint32_t g)
{
    g ^= g >> 16;
    g ^= g >> 8;
    g ^= g >> 4;
    g ^= g >> 2;
    g ^= g >> 1;
    return g;
}

/* An absolute encoder on a circular axis (4.3.1.2): the reading goes round
 * with the axis, 0 .. <cr>-1, so the motion since the last reading is the
 * shorter way round (less than half a turn per tick); the measured position
 * runs on across the wrap, the displayed one wraps (measure_apply). */
FW_INLINE int32_t circular_delta(const axis_t *x, uint32_t raw)
{
    int32_t d = (int32_t)(raw - x->counter), half = x->cr >> 1;
    if (d > half)
        d -= x->cr;
    else if (d < -half)
        d += x->cr;
    return d;
}

/* A relative system's motion since the last reading raw (table 4.3): the
 * counter wraps at <ec> or at 2^<eb> (less than half of it per tick). */
FW_INLINE int32_t measure_delta_rel(const axis_t *x, const meas_cfg_t *c, uint32_t raw)
{
    if (c->range) {
        int32_t d = (int32_t)(raw - x->counter);
        if (d > c->half)
            d -= c->range;
        else if (d < -c->half)
            d += c->range;
        return d;
    }
    uint32_t u = (raw - x->counter) & c->mask;
    return (int32_t)((u ^ c->sign) - c->sign);          /* bit <eb>-1 the sign: extended */
}

/* The motion since the last reading raw (<eb> bits, within <ec>), the same
 * for every system: absolute on a linear axis the reading is the position;
 * on a circular one the encoder's wrap is the axis' (4.3.1.2); relative,
 * the counter wraps at <ec> or at 2^<eb> (table 4.3; less than half of it
 * per tick).  The STP's absolute systems count in increments (stp_meas.c).
 * abs_linear, a constant: the caller knows the axis is absolute and linear
 * (MK_SSI_ABS), so none of the tests is made. */
FW_INLINE int32_t measure_delta_k(const axis_t *x, const meas_cfg_t *c,
                                                                     uint32_t raw, int abs_linear)
{
    if (abs_linear || (c->abs && x->linear))
        return (int32_t)(raw - (uint32_t)x->meas);
    if (c->abs)
        return circular_delta(x, raw);
    return measure_delta_rel(x, c, raw);
}

FW_INLINE int32_t measure_delta(const axis_t *x, const meas_cfg_t *c,
                                                                   uint32_t raw)
{
    return measure_delta_k(x, c, raw, 0);
}

/* SSI at the connector, everything prepared at INIT (the tick's path; INIT
 * itself reads with ssi_meas.c's measure_read_enc): the receiver read the encoder at the timer's expiry
 * (AX_CTRL_SSI_SYNC) and the tick came when it was done (TMR_CTRL_SSI_WAIT;
 * the poll is the safety net).  0 and the reading, or -1 after an encoder
 * error. */
FW_INLINE int measure_ssi_read(axis_t *x, unsigned n, uint32_t *rawp)
{
    meas_cfg_t *c = &meas_cfg[n];
    /* the poll: at most 200 more reads, the count set up only when the first finds it busy */
    if (RARELY(hal_rd16(AX_REG(n, AX_IN)) & AX_IN_SSI_BUSY))
        for (unsigned i = 0; (hal_rd16(AX_REG(n, AX_IN)) & AX_IN_SSI_BUSY) && i < 199; i++)
            ;
    /* both words in one read: the 68000 makes it two word cycles, AX_SSI_HI
     * first (the lower address), then AX_SSI_LO, as two reads would */
    uint32_t raw = (hal_rd32(AX_REG(n, AX_SSI_HI)) >> c->sc) & c->mask;
    if (x->ustat & UB(GRAY))
        raw = gray_to_binary(raw);
    if (RARELY(raw > c->lim)) {                         /* beyond <ec> (4.4.2.1, 6.3.8) */
        x->raw = raw;
        measure_encoder_error(n);
        return -1;
    }
    *rawp = raw;
    return 0;
}


/* ... and the motion since the last reading (the floor runner's reference,
 * bench/floor/ref_servo.c; the tick's relative path is measure_rel_take) */
FW_INLINE int measure_ssi(axis_t *x, unsigned n, int32_t *dp, int abs_linear)
{
    uint32_t raw;
    if (measure_ssi_read(x, n, &raw))
        return -1;
    int32_t d = measure_delta_k(x, &meas_cfg[n], raw, abs_linear);
    x->raw = raw;
    x->counter = raw;
    *dp = d;
    return 0;
}

/* The internal 24-bit counter (INC, and the STP's step or encoder counter),
 * relative (table 4.3): one word, AX_CNT_LIVE, whose 16-bit difference to
 * the last reading is the period's motion (docs/memory-map.md); the 24-bit
 * value is the firmware's (RCT; RED follows in card_supervise). */
FW_INLINE int32_t measure_counter(axis_t *x, unsigned n)
{
    uint32_t c = x->counter;
    int32_t d = (int16_t)(uint16_t)(hal_rd16(AX_REG(n, AX_CNT_LIVE)) - (uint16_t)c);
    x->counter = (c + (uint32_t)d) & 0xFFFFFFu;
    return d;
}

/* The measured position and the displayed one are the measurement's: the
 * tick moves them (measure_apply_k), the main loop sets the position from
 * meas and <ao> (measure.c measure_set_pos); outside the tick, masked, a
 * compensation table moves meas (ext_comp.c) and the position with it
 * (axis.h axis_moved_by), and the STP's INIT converts meas to steps
 * (stepper.c). */
FW_INLINE void measure_pos_set(axis_t *x, int32_t pos) { x->pos = pos; }
FW_INLINE void measure_meas_set(axis_t *x, int32_t meas) { x->meas = meas; }

/* The motion d into the measured position and the displayed one, which a
 * circular axis keeps in 0 .. <cr>-1 (4.3.1.2).  RAV: card_supervise.
 * linear, a constant: the caller knows the axis is linear (MK_SSI_ABS). */
FW_INLINE int32_t measure_wrapped(const axis_t *x, int32_t pos)
{
    if ((uint32_t)pos >= (uint32_t)x->cr) {       /* one compare inside 0 .. <cr>-1 */
        while (pos >= x->cr)
            pos -= x->cr;
        while (pos < 0)
            pos += x->cr;
    }
    return pos;
}

FW_INLINE void measure_apply_k(axis_t *x, int32_t d, int linear)
{
    x->meas = pos_add(x->meas, d);
    int32_t pos = pos_add(x->pos, d);
    if (!linear && !x->linear)
        pos = measure_wrapped(x, pos);
    x->pos = pos;
}

FW_INLINE void measure_apply(axis_t *x, int32_t d) { measure_apply_k(x, d, 0); }

/* An external reading raw as the last one read (RED) and processed (RCT):
 * the tick's, here and in the STP's stepper.h stp_measure_ext. */
FW_INLINE void measure_raw_take(axis_t *x, uint32_t raw)
{
    x->raw = raw;
    x->counter = raw;
}

/* A valid absolute reading raw of a linear axis: it is the measured
 * position, and the displayed one moves by the motion since the last
 * reading; what measure_delta_k and measure_apply_k make of it, with the
 * position returned (the tick's setpoint difference takes it from there). */
FW_INLINE int32_t measure_abs_take(axis_t *x, uint32_t raw)
{
    x->pos = pos_add(x->pos, pos_sub((int32_t)raw, x->meas));
    measure_raw_take(x, raw);
    x->meas = (int32_t)raw;
    return (int32_t)raw;
}

/* ... and of a relative system (MK_SSI: <et> 1, or the absolute reading
 * followed as relative while a compensation table is on, ext_comp.c, which
 * clears abs before the kind changes; c->abs is 0 whenever the kind is
 * MK_SSI, so neither of measure_delta_k's absolute tests is made): the
 * motion into both positions, the displayed one wrapped on a circular axis;
 * the measured position returned. */
FW_INLINE int32_t measure_rel_take(axis_t *x, const meas_cfg_t *c, uint32_t raw)
{
    int32_t d = measure_delta_rel(x, c, raw);
    measure_raw_take(x, raw);
    int32_t meas = pos_add(x->meas, d);
    x->meas = meas;
    int32_t pos = pos_add(x->pos, d);
    if (!x->linear)
        pos = measure_wrapped(x, pos);
    x->pos = pos;
    return meas;
}

/* ... and of a circular axis (4.3.1.2): the motion the shorter way round
 * (circular_delta) into both positions, the displayed one wrapped; what
 * measure_delta_k and measure_apply_k make of it, the measured position
 * returned. */
FW_INLINE int32_t measure_circ_take(axis_t *x, uint32_t raw)
{
    int32_t d = circular_delta(x, raw);
    measure_raw_take(x, raw);
    int32_t meas = pos_add(x->meas, d);
    x->meas = meas;
    x->pos = measure_wrapped(x, pos_add(x->pos, d));
    return meas;
}

/* A valid reading raw into the measured position: the motion since the
 * last reading (measure_delta), then raw and counter.  abs_linear, a
 * constant: the axis is absolute and linear (the reading is the position). */
FW_INLINE void measure_ext_take(axis_t *x, const meas_cfg_t *c, uint32_t raw, int abs_linear)
{
    int32_t d = measure_delta_k(x, c, raw, abs_linear);
    measure_raw_take(x, raw);
    measure_apply_k(x, d, abs_linear);
}

/* What the supervision (card_supervise, once per tick) derives from the
 * tick's measurement, so that the tick keeps only meas and the counter:
 * RAV, the motion since the last supervision ... */
FW_INLINE void measure_vel_set(axis_t *x, int32_t vel)
{
    x->vel = vel;
}

/* ... and RED on the counter path, the counter's content. */
FW_INLINE void measure_red_counter(axis_t *x)
{
    x->raw = x->counter;
}

#endif
