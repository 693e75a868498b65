/* card.h - firmware state of the card and its four axes. */
#ifndef CARD_H
#define CARD_H
#include "inline.h"
#include <stdint.h>
#include "status.h"
#include "profile.h"
#include "servo.h"

/* One object per axis, in parts.  Each part says who writes it and when;
 * "masked" is with interrupts masked (hal_irq_save), which every main-loop
 * writer of a part the tick reads holds.  The `writers:` line before a
 * part or a field names every file that writes it (its inline code: the
 * header); make arch-check fails on any other, and on a part written by
 * more than one module (a .c file and its own header, axis.c and axis.h)
 * that tools/onewriter.allow does not explain: such a part is a hand-over
 * between them, and says which side writes what.  The others write a
 * part through its owner's functions (tools/onewriter.py,
 * docs/hardening.md). */
typedef struct {
    /* status (7.1): the stages set and clear their own bits through
     * axis.c (axis_set_mode, axis_error) and the commands (cmd*.c); the
     * supervision (supervise.c, motion_supervise.c) its switch and fault
     * bits, masked */
    /* writers: axis.c axis.h card.c cmd.c cmd_general.c ext_comp.c ext_compare.c stp_motion.h
     * motion.c motion_justify.c motion_profile.c motion_supervise.c stepper.c supervise.c
     * ssi_card.h
     * (bit by bit: status.def USTAT_BY/SSTAT_BY) */
    struct {
        uint32_t ustat;     /* user status, manual 7.1.1 (RBS); bits 0-7 = mode */
        uint32_t sstat;     /* system status, manual 7.1.2 (RSS) */
        /* writers: axis.c axis.h */
        uint16_t err_report;/* error code to give as the answer to the next command, 0 none:
                             * axis_error sets it, axis_error_reported clears it once given */
    };
    /* axis state: axis.c alone writes the mode (axis_set_mode, its body in
     * axis.h) and next_mode (axis.h axis_select_mode: a mode command,
     * cleared by E, INIT, DEINIT, a stop bit, a disable and a reset) */
    struct {
        /* writers: axis.h */
        uint8_t mode;       /* mode in force (M_*) */
        uint8_t next_mode;  /* mode selected for the next E, or NO_MODE */
    };
    /* outputs: the shadow of AX_CTRL is written with every write of the
     * register, masked or in an interrupt, through card.h axis_ctrl_set
     * (which names the contexts); `out` by the output stage alone (tick.h:
     * the tick, axis_disable, the reset) */
    struct {
        /* writers: card.h */
        uint16_t ctrl;      /* shadow of AX_CTRL */
        /* writers: tick.h */
        int16_t out;        /* DAC word (INC/SSI) or step rate (STP) */
    };
    /* position measurement, the measurement's (measure.c, measure.h): the
     * tick moves pos and meas and writes raw and counter (measure.h; the
     * STP's stepper.h through measure_raw_take); the supervision after it
     * derives vel and RED's raw on the counter path (supervise.c through
     * measure_vel_set, measure_red_counter); INIT starts them afresh and
     * measure_set_pos sets pos from meas and <ao> (main loop); a
     * compensation table (ext_comp.c) moves meas, and pos with it (axis.h
     * axis_moved_by), masked, through measure_meas_set and measure_pos_set,
     * and the STP's INIT converts meas to steps (stepper.c) the same way.  meas_sup and mk_tick
     * are axis.c's (axis.h's axis_supervised_at and axis_follow_init, which
     * the supervision inlines, axis_moved_by, and axis_measure_off at a
     * reset and INIT) */
    struct {
        /* writers: measure.h */
        int32_t pos;        /* actual position: measured + <ao> (RCP) */
        /* writers: measure.c measure.h */
        int32_t meas;       /* measured position without offset */
        /* writers: measure.c measure.h */
        uint32_t raw;       /* last raw value read (RED) */
        /* writers: measure.c measure.h */
        uint32_t counter;   /* last processed counter content (RCT) */
        /* writers: measure.c measure.h */
        int32_t vel;        /* actual velocity per servo period (RAV) */
        /* writers: axis.h */
        int32_t meas_sup;   /* meas at the last supervision: RAV of the counter path */
        /* writers: axis.h */
        uint8_t mk_tick;    /* what the tick measures: mk once initialised, else MK_NONE (card_supervise) */
    };
    /* the setpoint and following error the tick used: the supervision's on
     * the INC/SSI (servo_card.h tick_result), the tick's on the STP
     * (tick_stp.c, stp_rate.*), all through card.h axis_result_set and
     * axis_result_idle */
    /* writers: card.h */
    struct {
        int32_t setpoint;
        int32_t ferr;
    };
    /* writers: cmd_param.c */
    int32_t zp_value;       /* last WZP value, read back by RZP (cmd_param.c) */
    /* profile generator (motion*.c, main loop, masked), measurement frame, Q16 */
    /* writers: motion.c motion_profile.c motion_justify.c stepper.c servo_motion.h */
    prof_t prof;
    /* the hand-over of the next SP from the profile generator to the tick,
     * both sides through handover.h: motion_profile.c writes the segment
     * (nx_*) and publishes it with the next row (handover_rows,
     * handover_publish), masked; the tick takes them at the SP boundary and
     * clears nx_ready (tick_servo.c take_row, tick_stp.c stp_take_segment:
     * handover_take_row, handover_take_segment); motion.c drops a prepared
     * SP (handover_drop) and motion_hold / brake_done start both sides
     * again (handover_hold, the card's handover_rows_* or _segment_*) */
    struct {
        /* the next SP's segment split as the tick uses it: start, step per
         * tick and end, integer + Q16 fraction */
        /* writers: motion_profile.c */
        int32_t nx_start_i, nx_st_i, nx_end_i;
        uint16_t nx_start_f, nx_st_f, nx_end_f;
        /* writers: handover.h */
        volatile uint8_t nx_ready;
        /* INC/SSI: the setpoints of an SP, one per tick, rounded: the row the
         * tick uses and the next one (the tick swaps them) */
        /* writers: handover.h */
        int32_t sp_rows[2][PROFILE_DIVIDER];
        int32_t *sp_now, *sp_next;
        int32_t sp_vel, sp_vel_next;    /* the rows' velocity, Q16 per SP */
    };
    /* STP: the setpoint the tick interpolates in the segment it took, the
     * hand-over's tick side (handover.h): the tick's (tick_stp.c
     * handover_sp_set, stp_rate.h's creep handover_segment_at_end), set
     * again by motion.c's hold and the STP's brake_done (handover_hold,
     * handover_segment_at_brake), masked */
    struct {
        /* writers: handover.h */
        int32_t sp_i;       /* setpoint, integer part */
        uint16_t sp_f;      /* and Q16 fraction */
        uint16_t st_f;      /* the segment's step per tick, split the same way */
        int32_t st_i;
        int32_t start_i, end_i;   /* and its ends */
        uint16_t start_f, end_f;
    };
    /* the tick's own brake, for a stop that cannot wait for the profile
     * generator's next SP (protective reactions, stop bits): motion.c sets it
     * up (brake_now, masked) and ends it (brake_done); the tick steps br_v
     * and br_posh (tick.h brake_step) from the setpoint and speed of the
     * moment, with <ed> (or <pd>) per tick^2.  The ramp's position and
     * speed are tick.h's (brake_start, brake_step), its deceleration and
     * the flag motion.c's, the STP's <ssf> stp_motion.h's (brake_from_card) */
    struct {
        /* writers: tick.h */
        int64_t br_posh;                /* setpoint, Q16, plus one half: bits 16-47 the rounded setpoint */
        int32_t br_v;                   /* Q16 per tick (0 once the ramp has ended) */
        /* writers: motion.c */
        int32_t br_dec;                 /* Q16 per tick^2 (>= 1) */
        /* writers: stp_motion.h */
        int32_t br_ssf;                 /* STP: <ssf> per tick, Q16: from there it stops at once */
        /* writers: motion.c */
        volatile uint8_t braking;
        /* STP: the body of the tick that runs the axis (STP_PATH_*), which
         * follows the mode and braking: stepper.h stp_path_set (_for), called
         * by their writers (axis_set_mode through stp_variant.h
         * axis_mode_card; brake_now, brake_done, motion_hold) */
        /* writers: stepper.h */
        uint8_t stp_path;
        /* INC/SSI: the same (SERVO_PATH_*), which also follows the gains (K
         * only or the general filter): servo_card.h servo_path_set, called by
         * the writers of the mode, the brake and the gains (axis_set_mode;
         * brake_now, brake_done, motion_hold; motion_start_card) */
        /* writers: servo_card.h */
        uint8_t servo_path;
    };
    /* the mode's motion: the motion files' (motion*.c, main loop; stepper.c
     * the STP's creep phase), masked where the tick reads them.  motion.c
     * sets up the target and the settling time at E (motion_start); the
     * profile generator, the justification modes and the supervision's
     * index latch move the mode's progress on through motion_priv.h
     * (mode_done, edge_found, index_latched, trt_count_step,
     * justify_phase); the phase is the justification modes' and the STP's
     * creep's (stepper.c), motion.c zeroes it at E, all through card.h
     * axis_phase_set */
    struct {
        /* writers: motion.c motion_priv.h */
        int64_t target;     /* positioning target */
        int32_t edge;       /* justification: position of the edge / index found (edge_found) */
        /* writers: card.h */
        uint8_t phase;      /* phase of a justification mode (STP: of the creep) */
        /* writers: motion.c motion_priv.h */
        uint8_t done;       /* the move of the current mode is complete (mode_done) */
        uint8_t idx_seen;   /* index latched during a search (motion_priv.h index_latched) */
        uint16_t trt_count; /* SP in the target window so far (trt_count_step, _reset) */
        uint16_t trt_periods;   /* <trt> in SP, in the target window before pos_end (5.6) */
    };
    /* a protective stop: motion.c's, which begins it (motion_emergency),
     * watches it after every tick and ends it (motion_priv.h stop_watch,
     * inline in the supervision; stop_done, which the supervision and the
     * profile generator call); what follows it is the axis state's
     * (axis.h axis_stop_set, which motion.c calls; a disable ends it,
     * as it ends the mode selected).  INC/SSI:
     * a stop that ends only with the mechanics at rest under closed-loop
     * control, with its runaway guards */
    struct {
        /* writers: axis.h */
        uint8_t stop_then;  /* protective stop in progress: STOP_* */
        uint8_t stop_settle;    /* wait for the mechanics at rest before STOP_DISABLE/DEINIT */
        /* writers: motion.c motion_priv.h */
        uint8_t stop_rest;      /* supervised ticks in a row with |RAV| <= STOP_REST_VEL */
        uint16_t stop_ticks;    /* supervised ticks since the stop began */
        uint16_t stop_limit;    /* time bound in ticks, set when the setpoint ramp ends (brake_done) */
        int32_t stop_fmax;      /* |following error| beyond this: the loop runs away */
        int32_t stop_f0;        /* |following error| at the start of the stop */
        int32_t stop_flast;     /* ... at the last supervision */
        int32_t stop_vlast;     /* |RAV| at the last supervision */
        uint8_t stop_grow;      /* supervised ticks in a row it grew beyond stop_f0, the speed not falling */
        uint8_t stop_ferr;      /* the stop is the reaction to a following error: a guard that ends
                                 * it raises nothing more (the error was raised once, C may have come) */
    };
    /* the profile generator's Q16 velocities per SP of the common modes
     * (vq() of <pv>, <pa>, <pd>, <ed>), recomputed only when par_a or TURBO
     * changed; q_free: prof_free_distance(<pv>, <pd>).  motion.c's alone
     * (vq_compute), main loop; the positioning steps read q_l32 through a
     * const pointer (tools/onewriter.allow) */
    struct {
        /* writers: motion.c */
        int64_t q_pv, q_pa, q_pd, q_ed, q_free;
        int32_t q_pd_t, q_ed_t;   /* <pd>, <ed> per tick^2 (>= 1): the tick's brake (brake_now) */
        int64_t q_hi, q_lo; /* target -/+ max(q_free, q_pv) when <pv> and <pa> fit 32 bits (prof_cruise32) */
        uint8_t q_fast;     /* ... and then prof_cruise32 applies */
        uint8_t q_fit;      /* <pv>, <pa>, <pd> below 2^30: prof_step32 with q_l32 */
        prof_lim32_t q_l32;
        uint16_t q_gen;
        uint8_t q_turbo;
    };
    /* position controller (servo.c): the gains axis.c's alone
     * (axis_set_gains, at E masked), the filter's state the tick's
     * (tick_servo.c; motion.c resets it at E through tick_servo.h
     * tick_servo_reset, masked) */
    /* writers: axis.c */
    servo_gains_t gains;
    /* writers: tick_servo.c tick_servo.h */
    servo_state_t servo;
    /* the tick's and the supervision's copies of parameters, prepared by
     * axis.c (axis_prepare, axis_prepare_mode) at INIT and E so that neither
     * looks one up; a compensation table switches mk through axis.h
     * (axis_kind_relative, axis_kind_restore); in_eval is set by axis.c
     * and cleared by the supervision once it has looked at the inputs
     * (axis.h axis_inputs_evaluated, inline there) */
    struct {
        /* writers: axis.c axis.h */
        uint8_t mk;         /* measurement kind, MK_* */
        uint8_t linear;     /* <sh> == 1 */
        int32_t cr, lp, ln, mf;
        uint8_t in_eval;    /* evaluate the inputs at the next tick even if unchanged */
        uint16_t sw_en;     /* AX_IN bits of the switches that are configured */
        uint16_t sw_inv;    /* ... and those that are high active */
    };
    /* writers: supervise.c */
    uint16_t in;            /* last switch inputs, AX_IN (supervise.c) */
} axis_t;

#define MK_COUNTER 0    /* internal 24-bit counter: the fast path */
#define MK_OTHER 1      /* SSI, external VMEbus or DPRAM: measure.c */
#define MK_NONE 2       /* not initialised: position reads 0 (4.9) */
#define MK_SSI 3        /* MAC4-SSI, the encoder at the connector: measure_ssi_read() in the tick */
#define MK_SSI_ABS 4    /* the same, absolute on a linear axis (the SSI's defaults): the reading is the position */
#define MK_SSI_CIRC 5   /* the same, absolute on a circular axis: the motion the shorter way round */

/* in the order of precedence: a later stop only raises it */
#define STOP_NONE 0
#define STOP_HOLD 1     /* emergency ramp <ed>, then hold in mode brake */
#define STOP_DISABLE 2  /* emergency ramp <ed>, at rest, then disable */
#define STOP_DEINIT 3   /* DEINIT: stop with <ed>, at rest, disable, clear init (4.9) */

/* The end of a stop that disables (INC/SSI, motion_priv.h stop_watch): the
 * mechanics at rest, |RAV| <= STOP_REST_VEL for STOP_REST_TICKS ticks in a
 * row, at most 2 x the setpoint ramp's ticks + STOP_SETTLE_TICKS after the
 * stop began; /EN opens at once if |RFE| exceeds its value at the start of
 * the stop by more than <mf>/2, or grows beyond it for STOP_GROW_TICKS ticks
 * in a row while the measured speed does not fall (docs/interpretations.md) */
#define STOP_REST_VEL 1
#define STOP_REST_TICKS 4
#define STOP_SETTLE_TICKS 40
#define STOP_GROW_TICKS 4

#define NO_MODE 0xFF

/* Positions are 32-bit and wrap as on the 68000: their differences and sums
 * modulo 2^32, without C's undefined signed overflow. */
static inline int32_t pos_sub(int32_t a, int32_t b) { return (int32_t)((uint32_t)a - (uint32_t)b); }
static inline int32_t pos_add(int32_t a, int32_t b) { return (int32_t)((uint32_t)a + (uint32_t)b); }

/* The setpoint and following error the tick used, their one write: the
 * supervision's on the INC/SSI (servo_card.h tick_result), the tick's on
 * the STP (tick_stp.c, the rate stage stp_rate.*), one card's at a time -
 * the setpoint sp against the measurement, or the measurement itself (a
 * disabled axis follows no setpoint). */
FW_INLINE void axis_result_set(axis_t *x, int32_t sp)
{
    x->setpoint = sp;
    x->ferr = pos_sub(sp, x->meas);
}
FW_INLINE void axis_result_idle(axis_t *x)
{
    x->setpoint = x->meas;
    x->ferr = 0;
}
/* A Q16 position as the tick's integer part and fraction. */
static inline void split_q16(int64_t q, int32_t *i, uint16_t *f)
{
    *i = (int32_t)(q >> 16);
    *f = (uint16_t)q;
}

/* The shadow of AX_CTRL, its one write: every context that writes the
 * register writes it here too - the reset and the tick's output stage
 * (tick.h), /EN at a mode change (servo_card.h axis_mode_card), the SSI
 * receiver's sync at INIT (ssi_meas.c), the STP's creep interrupts
 * (stp_rate.c, the level 5 handler stp_rate.h stp_isr_axis) and the
 * index interrupt's fault path (supervise.c) - masked or in an interrupt,
 * so it is one register's copy, not a part each of them owns. */
FW_INLINE void axis_ctrl_set(axis_t *x, uint16_t ctrl) { x->ctrl = ctrl; }

/* The mode's phase byte, its one write: a justification mode's step of its
 * diagram (motion_priv.h justify_phase), the STP's creep phase of
 * positioning (stepper.c stp_positioning, stp_profile_end), zeroed at E
 * (motion.c motion_start); main loop, masked at E.  One byte for both: no
 * mode has both (stepper.c cannot call motion_priv.h's setter, motion.c
 * calls stepper.c: a cycle). */
FW_INLINE void axis_phase_set(axis_t *x, uint8_t phase) { x->phase = phase; }

/* The tick's own brake keeps its Q16 position plus one half (br_posh), so
 * that bits 16-47 are the rounded setpoint, one 32-bit part of it: these
 * are the only readers of that representation, tick.h's brake_start and
 * brake_step its writers. */
#define BR_HALF 0x8000u
static inline int64_t brake_pos(const axis_t *x) { return x->br_posh - BR_HALF; }
FW_INLINE int32_t brake_setpoint(const axis_t *x)
{
    return (int32_t)(x->br_posh >> 16);
}
/* brake_pos() as the integer part and fraction (split_q16) without a 64-bit
 * subtraction: the fraction's top bit flipped, a borrow below one half */
FW_INLINE void brake_split(const axis_t *x, int32_t *i, uint16_t *f)
{
    uint16_t lo = (uint16_t)x->br_posh;
    uint32_t hi = (uint32_t)(x->br_posh >> 16);
    if (lo < BR_HALF)                           /* a borrow: a test, not GCC's subtract-with-extend */
        hi--;
    *i = (int32_t)hi;
    *f = (uint16_t)(lo ^ BR_HALF);
}

extern axis_t axes[MAC4_NAXES];
/* &axes[n] by a table: sizeof(axis_t) is no power of two, and the 68000
 * would compute the product with a dozen shifts and adds where it matters */
extern axis_t *const axis_at[MAC4_NAXES];
extern uint32_t card_ostat;     /* overall status, manual 7.1.3 (RAS) */
extern uint16_t card_err_report;/* 164/165 for the next command on any axis */
extern uint32_t card_ticks;     /* servo ticks since reset */
/* INC/SSI: bit n set while axis n's gains take the general filter
 * (servo_gains_t.full), kept by axis_set_gains, the gains' only writer.
 * Clear, the tick runs its body for K-only gains on every axis, which saves
 * fewer registers and tests no axis' gains (tick_servo.c, tick()). */
extern uint8_t card_servo_general;

void card_reset(void);          /* outputs to reset state, defaults */
void card_start(void);          /* timer, serial, interrupts */
void card_profile_tick(void);   /* profile generator: the next SP's segments (main loop) */
extern volatile uint8_t card_profile_due;   /* axes still to step this SP: 4 at each SP boundary */
extern uint16_t card_profile_late;          /* SP boundaries without a prepared segment */
/* Main loop, once after every tick: switches, reactions, DPRAM data.  The
 * test is inline (it is made before every command and profile step); the
 * work is card_supervise_tick(). */
extern uint32_t card_supervised;            /* card_ticks at the last supervision */
void card_supervise_tick(void);
FW_INLINE int card_supervise_due(void)
{
    return *(volatile uint32_t *)&card_ticks != card_supervised;
}
FW_INLINE void card_supervise(void)
{
    if (card_supervise_due())
        card_supervise_tick();
}
extern uint16_t card_supervise_late;        /* ticks supervised late (the main loop was held up) */
void supervise_reset(void);                 /* card_reset: the supervision's own state */

/* Axis state changes used by commands and by the protective reactions. */
void axis_set_mode(unsigned n, uint8_t mode);
void axis_set_gains(unsigned n, const servo_gains_t *g);
void axis_disable(unsigned n);             /* at once, no ramp */
void axis_error(unsigned n, uint32_t ubit, uint16_t code);  /* set bit, report code next */
int axis_standstill(unsigned n);
static inline int axis_initialised(unsigned n) { return (axes[n].ustat & UB(INIT)) != 0; }
void axis_init_measurement(unsigned n);    /* INIT: derive ea/eb/ec, zero relative position */
void axis_prepare(unsigned n);             /* main loop: refresh the tick's copies */
void axis_prepare_mode(unsigned n);        /* ... of the mode parameters alone (E, initialised) */
/* axis.h: the writes of axis.c's parts that the commands, the supervision and the extensions make, inline */

/* VMEbus interrupts (4.6): vector 0 = off. */
void vme_irq(uint8_t vector);
/* Hand the next waiting interrupt to the interrupter once the host has
 * acknowledged the last one; the test is inline (every main-loop pass). */
extern volatile uint8_t vme_irq_waiting;
void vme_irq_service_do(void);
void vme_irq_reset(void);                   /* card_reset: nothing waiting */
extern uint32_t virq_lost;                  /* requests the FIFO had no room for (DPC_VME_IRQ_LOST) */
FW_INLINE void vme_irq_service(void)
{
    if (vme_irq_waiting)
        vme_irq_service_do();
}

#endif
