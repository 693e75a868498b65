/*
 * plant.h - what sits behind the axis interface boards: DC servo motors with
 * their amplifiers (MAC4-INC/SSI), stepper motors with their drivers
 * (MAC4-STP), incremental and SSI encoders, limit and reference switches,
 * and the VME slave boards the card can read as a bus master.
 * docs/plant.md gives the equations, defaults and reasons.
 *
 * Included by sim.h (the plant lives inside sim_t), so it only uses
 * standard types and a forward declaration of struct sim.
 */
#ifndef PLANT_H
#define PLANT_H
#include <stdint.h>
#include <stdio.h>

struct sim;

/* The mechanics are integrated at a fixed step on a grid of absolute time
 * (multiples of PLANT_STEP_CYC 68000 cycles); an input change (DAC write,
 * enable, emergency stop, step-rate write) cuts the step at the cycle it
 * happens.  Between grid points positions are linear in time. */
#define PLANT_STEP_CYC 1600u             /* 100 us */

enum { PLANT_AMP_VELOCITY, PLANT_AMP_CURRENT };
enum { PLANT_ENC_OK, PLANT_ENC_FROZEN, PLANT_ENC_STUCK0, PLANT_ENC_STUCK1 };
enum { PLANT_SW_LP, PLANT_SW_LN, PLANT_SW_REF, PLANT_NSW };

typedef struct {
    int used;                  /* a switch is wired (else the input floats at 24 V) */
    int high;                  /* high active: 24 V when on (table 2.4) */
    int64_t pos;               /* lp: on at pos and beyond, ln: at pos and below */
    int64_t width;             /* ref: on for pos <= x < pos + width */
} plant_switch_t;

typedef struct {
    /* Parameters first, up to enc_fault; the state starts at t0
     * (plant_params_defaults copies the parameters only). */
    /* ---- DC servo: amplifier, motor and load (MAC4-INC/SSI) ---- */
    int amp;                   /* PLANT_AMP_VELOCITY or PLANT_AMP_CURRENT */
    double rpm10;              /* velocity mode: motor rpm commanded by +10 V */
    double tau;                /* velocity mode: speed-loop time constant, s */
    double amps10;             /* current mode: A commanded by +10 V */
    double imax;               /* amplifier current limit, A */
    double kt;                 /* torque constant, N m/A */
    double inertia;            /* at the motor shaft, kg m^2 */
    double visc;               /* viscous friction, N m s/rad */
    double coulomb;            /* Coulomb (and static) friction, N m */
    double load;               /* external torque, N m (positive pushes positive) */
    /* ---- stepper motor and driver (MAC4-STP) ---- */
    double steps_rev;          /* driver steps per motor revolution */
    double ssf;                /* start/stop frequency, Hz (largest rate jump it follows) */
    double accel;              /* torque limit as acceleration, steps/s^2 */
    double fmax;               /* no torque left at this rate, Hz (0: no limit) */
    double boost;              /* ssf and accel factor while BOOST is on */
    /* ---- mechanics shared by both ---- */
    double gear;               /* motor revolutions per output revolution */
    int reversed;              /* servo: motor leads swapped, a positive DAC word turns it negative */
    /* ---- sensors ---- */
    uint32_t lines;            /* incremental encoder lines per output revolution */
    uint32_t index;            /* the index increment within a revolution */
    int ssi_bits;              /* SSI encoder word width, 1..24 */
    double ssi_res;            /* SSI counts per output revolution */
    int br_steps;              /* STP: solder bridge BR closed, counter counts steps */
    plant_switch_t sw[PLANT_NSW];
    int df_high;               /* drive-fault line is high active */
    int drive_fault;           /* injected: DF active and the power stage off */
    int enc_fault;             /* PLANT_ENC_* */
    /* ---- the machine behind the output shaft: a leadscrew with a known
     * error, the load at L = u + amp sin(2 pi u / pitch) + ppm 1e-6 u for
     * the output shaft at u units (docs/plant.md, "Leadscrew") ---- */
    double lead_amp;           /* units; 0: no error */
    double lead_pitch;         /* units per period of the periodic error */
    double lead_ppm;           /* cumulative pitch error, parts per million */

    /* ---- state: mechanics, piecewise linear between t0 and t1 ---- */
    uint64_t t0, t1;           /* t1 = CYC_NEVER: at rest, nothing changes */
    double x0, v0, x1, v1;     /* servo: motor rev, rad/s; stepper: rotor steps, steps/s */
    double in_u;               /* inputs the current step was computed with */
    int in_en, in_boost;
    uint64_t in_key;           /* servo: the raw inputs in_u, in_en, in_boost come from (plant.c inputs_key) */
    uint64_t t_sync;           /* the models are up to date until here */
    /* stepper */
    int sync;                  /* the rotor follows the driver's field */
    int64_t cmd;               /* the driver's field position, steps (pulses while enabled) */
    int64_t gen;               /* pulses that came on STEP, signed by DIR */
    int64_t off;               /* rotor = cmd + off while in sync */
    int64_t lost_base;         /* gen - rotor after the last `plant N pos` */
    /* the encoder's index: where it crossed last, where it will */
    double idx_chk;            /* encoder position at the last index check ... */
    uint64_t idx_chk_t;        /* ... and when it was */
    uint64_t t_idx;            /* predicted index crossing */
    double idx_b;              /* ... at this boundary */
    int idx_dir;
    /* SSI encoder */
    int64_t ssi_off;
    uint32_t ssi_frozen;
    /* trace */
    FILE *trace;
    uint64_t trace_next, trace_iv;
    int trace_tick;            /* a row at every timer expiry instead of every trace_iv */
    int trace_card;            /* with the axis data the card publishes in the DPRAM */
    uint64_t trace_tick_seen;  /* tmr.last of the last row in tick mode */
} plant_axis_t;

#define PLANT_NVME 8
#define PLANT_VME_LOAD 2
typedef struct {
    int used;
    uint32_t base;             /* A24 address */
    int axis;                  /* the axis whose shaft turns it */
    int motor_shaft;           /* on the motor shaft instead of the output shaft; PLANT_VME_LOAD:
                                * a scale on the load behind the leadscrew (plant_load_units) */
    int bits;                  /* 1..32: one word up to 16 bits, two words above */
    double res;                /* counts per revolution */
    uint64_t turns;            /* revolutions before the value wraps (0: 2^bits wraps) */
    int64_t offset;
    uint32_t latch;            /* 32-bit boards: value latched by reading the LSW */
    int latched;
} plant_vme_t;

typedef struct plant {
    int init;                  /* defaults set (survives card resets, not sim_init) */
    plant_axis_t ax[4];
    plant_vme_t vme[PLANT_NVME];
} plant_t;

/* ---- the wires between an axis board (axisboard.c) and its plant --------
 * Everything the two tell each other, by line.  The plant samples what the
 * board drives; the board samples what the plant drives; the plant is
 * brought up to the cycle of every sample (plant_sync). */
/* board -> plant: what the board drives (axisboard.c) */
int axb_en(struct sim *s, int n);                /* /EN closed (AX_CTRL_EN, no /STOP) */
int axb_dir(struct sim *s, int n);               /* DIR (AX_CTRL_DIR) */
int axb_boost(struct sim *s, int n);             /* BOOST (AX_CTRL_BOOST) */
int16_t axb_dac(struct sim *s, int n);           /* DAC word, 12 bits */
double axb_dac_volts(struct sim *s, int n);      /* DAC out, V */
uint32_t axb_drive_lines(struct sim *s, int n);  /* DAC word, /EN (with /STOP) and BOOST as one word */
uint16_t axb_rate(struct sim *s, int n);         /* STP rate register */
double axb_step_hz(struct sim *s, int n);        /* STEP rate, signed by DIR; 0 when the down-counter stopped it */
int axb_step_running(struct sim *s, int n);      /* pulses are coming */
uint64_t axb_step_time(struct sim *s, int n, uint64_t j);   /* when the j-th pulse from now comes */
uint64_t axb_steps_left(struct sim *s, int n);   /* before the down-counter stops them (UINT64_MAX: free) */
int axb_index_armed(struct sim *s, int n);       /* the index latch waits for a pulse */
/* plant -> board: what the plant drives (plant.c) */
void plant_step_pulses(struct sim *s, int n, int64_t d);   /* d pulses on STEP/DIR (the board's push) */
void plant_index_armed(struct sim *s, int n, uint64_t now); /* the board armed its latch */
int plant_has_encoder(struct sim *s, int n);     /* A/B/Z lines wired (not SSI, not STP with BR closed) */
double plant_enc_e(struct sim *s, int n, uint64_t t);   /* encoder phase: the increment counted is floor(e) */
int plant_enc_stuck(struct sim *s, int n);       /* A/B lines stuck: nothing is counted */
uint16_t plant_inputs_word(struct sim *s, int n, uint64_t now);   /* switch and DF levels, AX_IN bits */
uint32_t plant_ssi_frame(struct sim *s, int n, uint64_t now, int gray);   /* SSI data for a read started now */
void plant_ssi_set(struct sim *s, int n, uint64_t now, uint32_t value);   /* set the SSI encoder's reading */
/* the board's index latch and counter, for the plant's index pulse and faults (axisboard.c) */
void axb_index_pulse(struct sim *s, int n, int64_t incr);  /* the index pulse at increment incr */
void axb_counter_freeze(struct sim *s, int n, uint64_t now);
void axb_counter_thaw(struct sim *s, int n, uint64_t now);
void axb_counter_jump(struct sim *s, int n, int64_t by);
int axb_step_advance(struct sim *s, int n, uint64_t to);   /* the step generator's clock; 1: the count ended */
uint64_t axb_step_done_time(struct sim *s, int n);
void axb_counter_poked(struct sim *s, int n);
void axb_counter_mirror(struct sim *s, int n, uint64_t t);

/* ---- plant.c: the models' clock, called by axisboard.c ---- */
void plant_power_on(struct sim *s);              /* defaults, at the first card reset */
void plant_board_reset(struct sim *s, int n, uint64_t now);   /* a card reset: the motors coast */
void plant_sync(struct sim *s, int n, uint64_t now);
void plant_inputs(struct sim *s, int n, uint64_t now);   /* after a register write */
uint64_t plant_next_event(struct sim *s, int n, int index_ie);
void plant_events(struct sim *s, uint64_t now);

/* ---- axisboard.c: the counter chip, SSI timing, the step clock (tools, vcd.c) ---- */
uint32_t axb_counter(struct sim *s, int n, uint64_t now);            /* synced */
uint32_t axb_counter_at(struct sim *s, int n, uint64_t t);
int64_t axb_counter_raw(struct sim *s, int n, uint64_t t);
void axb_counter_set(struct sim *s, int n, uint64_t now, uint32_t value);
uint64_t axb_ssi_cycles(int clock);              /* 26 SSI clocks in CPU cycles */
uint64_t axb_step_period(struct sim *s, int n);  /* STP step clock, cycles */
/* when the j-th pulse comes after the step clock stood at nco_t, accumulator acc */
uint64_t axb_step_pulse_time(struct sim *s, int n, uint64_t nco_t, uint32_t acc, uint64_t j);

/* configuration and observation (script_plant.c, tests) */
void plant_axis_defaults(struct sim *s, int n);     /* parameters and state */
void plant_params_defaults(struct sim *s, int n);   /* parameters only */
void plant_changed(struct sim *s, int n);        /* after editing plant_axis_t fields */
void plant_set_position(struct sim *s, int n, double units);
void plant_set_enc_fault(struct sim *s, int n, int mode);   /* PLANT_ENC_* */
void plant_enc_jump(struct sim *s, int n, int64_t by);
void plant_step_counts(struct sim *s, int n, int64_t *generated, int64_t *lost);   /* STP */
double plant_units(struct sim *s, int n, uint64_t t);        /* increments, SSI counts or steps */
double plant_units_per_s(struct sim *s, int n, uint64_t t);
double plant_load_units(struct sim *s, int n, uint64_t t);   /* the load behind the leadscrew, units */
double plant_lead_error(const plant_axis_t *p, double u);     /* L - u at the output shaft at u */
double plant_units_per_rev(struct sim *s, int n);            /* per output revolution */
double plant_motor_rpm(struct sim *s, int n, uint64_t t);
int plant_switch_active(struct sim *s, int n, int which, uint64_t t);
int plant_switch_at(const plant_axis_t *p, int which, int64_t x);     /* at x rounded units */
uint32_t plant_ssi_value(struct sim *s, int n, uint64_t t);  /* binary, before J1 coding */
int plant_trace_start(struct sim *s, int n, const char *path, uint64_t interval_cyc);
/* the same; tick: a row at every timer expiry (interval ignored); card: the
 * card-side columns too (docs/host-script.md, "Plant") */
int plant_trace_start_ex(struct sim *s, int n, const char *path, uint64_t interval_cyc, int tick, int card);
void plant_trace_stop(struct sim *s, int n);
void plant_format(struct sim *s, int n, char *buf, size_t len);   /* one line, no newline */

/* plant_vme.c: slave boards in the VMEbus master window */
int plant_vme_add(struct sim *s, uint32_t base, int axis, int bits, double res, uint64_t turns,
                  int64_t offset, int motor_shaft);
int plant_vme_remove(struct sim *s, uint32_t base);
uint32_t plant_vme_value(struct sim *s, const plant_vme_t *b, uint64_t t);
int plant_vme_rd16(struct sim *s, uint32_t addr, uint32_t *w);   /* 0: no board at addr */
int plant_vme_wr16(struct sim *s, uint32_t addr);

#endif
