/*
 * plant.c - the plant behind the axis interface boards, wired to them by the
 * lines of plant.h's "wires" section: the clock of the models, the drive's
 * inputs, the position sensors (quadrature encoder with index, SSI absolute
 * encoder) and the switches.  The motors are in plant_servo.c (DC servo
 * with velocity- or current-mode amplifier, MAC4-INC/SSI) and
 * plant_stepper.c (stepper and driver, MAC4-STP); the parameters, the
 * leadscrew and the edits of the script in plant_config.c; the trace and the
 * one-line summary in plant_trace.c.  docs/plant.md has the equations,
 * defaults and reasons.
 *
 * Time: the models are brought up to date lazily, whenever a register is
 * accessed (plant_sync) and at every scheduler event (plant_events), so a
 * register read sees the state as of the cycle it happens.  Only what must
 * happen at its own time becomes a scheduler event: index pulses and pulse
 * interrupts the firmware enabled, the end of a pulse count, trace samples.
 *
 * Mechanics run on a fixed grid of PLANT_STEP_CYC cycles; each step is
 * predicted from the inputs at its start (x0,v0 at t0 -> x1,v1 at t1) and
 * positions in between are linear in time.  An input change cuts the step.
 *
 * No libm: the unit tests link the harness without it.
 */
#include "periph.h"
#include "plant_int.h"
#include "vcd.h"

/* ======================================================================== */
/* inputs                                                                    */
/* ======================================================================== */
int plant_drive_enabled(sim_t *s, int n)
{
    return axb_en(s, n) && !s->plant.ax[n].drive_fault;
}

double plant_boost(sim_t *s, int n)
{
    return axb_boost(s, n) ? s->plant.ax[n].boost : 1.0;
}

/* What the current step depends on; a change cuts the step. */
static double input_u(sim_t *s, int n)
{
    if (is_stp(s))
        return axb_step_hz(s, n);
    if (!plant_drive_enabled(s, n))
        return 0.0;
    /* reversed wiring (motor leads swapped): the amplifier's input inverted */
    return s->plant.ax[n].reversed ? 0.0 - axb_dac_volts(s, n) : axb_dac_volts(s, n);
}

/* ======================================================================== */
/* positions                                                                 */
/* ======================================================================== */
/* Output shaft revolutions. */
double plant_out_rev(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (is_stp(s))
        return stp_rotor(p, t) / p->steps_rev / p->gear;
    return lerp_x(p, t) / p->gear;
}

double plant_units_per_rev(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (is_stp(s))
        return p->steps_rev * p->gear;
    if (is_ssi(s))
        return p->ssi_res;
    return 4.0 * p->lines;
}

/* The continuous position in the axis' own units: increments (INC), SSI
 * counts (SSI), rotor steps (STP).  Sensors count floor(u + 0.5). */
double plant_units(sim_t *s, int n, cyc_t t)
{
    if (is_stp(s))
        return stp_rotor(&s->plant.ax[n], t);
    return plant_out_rev(s, n, t) * plant_units_per_rev(s, n);
}

double plant_units_per_s(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (is_stp(s))
        return p->sync ? axb_step_hz(s, n) * (plant_drive_enabled(s, n) ? 1.0 : 0.0) : lerp_v(p, t);
    return lerp_v(p, t) / TWO_PI / p->gear * plant_units_per_rev(s, n);
}

double plant_motor_rpm(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (is_stp(s))
        return plant_units_per_s(s, n, t) / p->steps_rev * 60.0;
    return lerp_v(p, t) * 60.0 / TWO_PI;
}

/* Incremental encoder: is one connected, and where is it (phase position:
 * the increment counted is floor(e)). */
int plant_has_encoder(sim_t *s, int n)
{
    if (is_ssi(s))
        return 0;
    return !is_stp(s) || !s->plant.ax[n].br_steps;
}

double plant_enc_e(sim_t *s, int n, cyc_t t)
{
    return plant_out_rev(s, n, t) * 4.0 * s->plant.ax[n].lines + 0.5;
}

/* The A/B lines stuck (an encoder fault): nothing is counted. */
int plant_enc_stuck(sim_t *s, int n) { return s->plant.ax[n].enc_fault != PLANT_ENC_OK && !is_ssi(s); }

/* ======================================================================== */
/* index pulse                                                               */
/* ======================================================================== */
static int idx_possible(sim_t *s, int n)
{
    return plant_has_encoder(s, n) && !plant_enc_stuck(s, n) && axb_index_armed(s, n);
}

/* Did the encoder enter the index increment between the last check and e?
 * Within one check interval the motion is monotone (linear pieces). */
static void idx_check_to(sim_t *s, int n, double e, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (idx_possible(s, n)) {
        double N = 4.0 * p->lines, I = (double)(p->index % (4u * p->lines));
        if (e > p->idx_chk) {
            double b = I + N * (floor_((p->idx_chk - I) / N) + 1.0);   /* first boundary above */
            if (b <= e)
                axb_index_pulse(s, n, (int64_t)b);
        } else if (e < p->idx_chk) {
            double b = I + 1.0 + N * floor_((p->idx_chk - I - 1.0) / N);   /* last one below */
            if (e < b)
                axb_index_pulse(s, n, (int64_t)b - 1);
        }
    }
    p->idx_chk = e;
    p->idx_chk_t = t;
}

/* Only while a latch is possible: arming takes a fresh position. */
static void idx_check(sim_t *s, int n, cyc_t t)
{
    if (idx_possible(s, n) && s->plant.ax[n].idx_chk_t != t)
        idx_check_to(s, n, plant_enc_e(s, n, t), t);
}

/* Predict when the index increment is entered, so its interrupt comes on
 * time: within the current linear step (servo, or stepper out of sync), or
 * at the pulse that carries the rotor there (stepper in sync). */
static void idx_predict(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    p->t_idx = CYC_NEVER;
    if (!idx_possible(s, n))
        return;
    double N = 4.0 * p->lines, I = (double)(p->index % (4u * p->lines));
    double e0 = p->idx_chk;
    if (is_stp(s) && p->sync) {
        if (!axb_step_running(s, n) || !plant_drive_enabled(s, n))
            return;
        double k = 4.0 * p->lines / (p->steps_rev * p->gear);   /* increments per step */
        double r0 = (double)(p->cmd + p->off);
        double j;
        if (axb_dir(s, n)) {
            double b = I + N * (floor_((e0 - I) / N) + 1.0);
            j = ceil_((b - 0.5) / k - r0 - 1e-9);
            p->idx_b = b;
            p->idx_dir = 1;
        } else {
            double b = I + 1.0 + N * floor_((e0 - I - 1.0) / N);
            j = floor_(r0 - (b - 0.5) / k + 1e-9) + 1.0;
            p->idx_b = b;
            p->idx_dir = -1;
        }
        if (j < 1.0)
            j = 1.0;
        if (j > 1e12 || j > (double)axb_steps_left(s, n))
            return;
        p->t_idx = axb_step_time(s, n, (uint64_t)j);
        return;
    }
    if (p->t1 == CYC_NEVER)
        return;
    /* linear from the last check (on this step's line) to the step's end */
    cyc_t tf = p->idx_chk_t > p->t0 ? p->idx_chk_t : p->t0;
    if (tf >= p->t1)
        return;
    double e1 = plant_out_rev(s, n, p->t1) * N + 0.5;
    double frac;
    if (e1 > e0) {
        double b = I + N * (floor_((e0 - I) / N) + 1.0);
        if (b > e1)
            return;
        frac = (b - e0) / (e1 - e0);
        p->idx_b = b;
        p->idx_dir = 1;
    } else if (e1 < e0) {
        double b = I + 1.0 + N * floor_((e0 - I - 1.0) / N);
        if (!(e1 < b))
            return;
        frac = (e0 - b) / (e0 - e1);
        p->idx_b = b;
        p->idx_dir = -1;
    } else {
        return;
    }
    cyc_t dt = (cyc_t)ceil_(frac * (double)(p->t1 - tf));
    if (dt < 1)
        dt = 1;
    p->t_idx = min_cyc(tf + dt, p->t1);
}

static void idx_event(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    double e = plant_enc_e(s, n, t);
    /* the crossing was computed exactly: do not let rounding miss it */
    if (p->idx_dir > 0 && e < p->idx_b)
        e = p->idx_b;
    if (p->idx_dir < 0 && e >= p->idx_b)
        e = p->idx_b - 1e-9;
    idx_check_to(s, n, e, t);
    p->t_idx = CYC_NEVER;
}

/* ======================================================================== */
/* stepping, cuts and the event loop                                         */
/* ======================================================================== */
/* A servo's inputs as the board's lines and the plant hold them: in_u,
 * in_en and in_boost are functions of these alone, so while they are the
 * same the step's inputs are too (inputs_changed).  Bit 63: a servo's key. */
static inline uint64_t inputs_key(sim_t *s, int n)
{
    const plant_axis_t *p = &s->plant.ax[n];
    return (uint64_t)axb_drive_lines(s, n) | (uint64_t)(p->drive_fault != 0) << 33 |
           (uint64_t)(p->reversed != 0) << 34 | 1ull << 63;
}

static void predict(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    p->in_key = is_stp(s) ? 0 : inputs_key(s, n);
    p->in_u = input_u(s, n);
    p->in_en = plant_drive_enabled(s, n);
    p->in_boost = axb_boost(s, n);
    int rest = is_stp(s) ? plant_stp_at_rest(s, n) : plant_servo_at_rest(p, p->in_u, p->in_en);
    if (rest) {
        p->t1 = CYC_NEVER;
        p->x1 = p->x0;
        p->v1 = p->v0;
    } else {
        p->t1 = (p->t0 / PLANT_STEP_CYC + 1) * PLANT_STEP_CYC;
        double dt = (double)(p->t1 - p->t0) / PLANT_CPU_HZ;
        if (is_stp(s))
            plant_stp_step(s, n, dt);
        else
            plant_servo_step(p, p->in_u, p->in_en, dt, p->x0, p->v0, &p->x1, &p->v1);
    }
    idx_predict(s, n);
}

/* The inputs changed at `now` (the models are synced to now). */
static void cut(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    double v = lerp_v(p, now);
    if (is_stp(s)) {
        if (!p->sync && s->vcd)
            vcd_piece(s, n, p->t0, p->x0, now, lerp_x(p, now));
        if (!p->sync)
            p->x0 = lerp_x(p, now);
        p->v0 = v;
        if (p->sync && !plant_stp_can_sync(s, n, axb_step_hz(s, n), v))
            plant_stp_lose_sync(p, v);
        plant_stp_try_resync(s, n);
    } else {
        if (s->vcd)
            vcd_piece(s, n, p->t0, p->x0, now, lerp_x(p, now));
        p->x0 = lerp_x(p, now);
        p->v0 = v;
    }
    p->t0 = now;
    predict(s, n);
}

static int inputs_changed(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->in_key && p->in_key == inputs_key(s, n))
        return 0;   /* a servo's same raw inputs: the same u, enable and boost */
    return p->in_u != input_u(s, n) || p->in_en != plant_drive_enabled(s, n) ||
           p->in_boost != axb_boost(s, n);
}

void plant_sync(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (now < p->t_sync)
        now = p->t_sync;
    axb_counter_poked(s, n);
    if (p->t1 == CYC_NEVER && p->t_idx == CYC_NEVER && !(is_stp(s) && axb_rate(s, n))) {
        /* fast path: at rest and no pulses, nothing can have moved */
        axb_step_advance(s, n, now);   /* no pulses: only the generator's clock moves on */
        p->t_sync = now;
        if (inputs_changed(s, n)) {
            cut(s, n, now);
            axb_counter_mirror(s, n, now);
        }
        if (s->vcd)
            vcd_synced(s, n);
        return;
    }
    for (;;) {
        cyc_t td = axb_step_done_time(s, n);
        cyc_t te = min_cyc(min_cyc(p->t1, p->t_idx), td);
        if (te > now)
            break;
        int ended = axb_step_advance(s, n, te);
        if (ended || te == td) {
            idx_check(s, n, te);
            cut(s, n, te);             /* the field stops: an abrupt stop */
        } else if (te == p->t_idx) {
            idx_event(s, n, te);
        } else {
            if (s->vcd && !(is_stp(s) && p->sync))
                vcd_piece(s, n, p->t0, p->x0, p->t1, p->x1);
            p->t0 = p->t1;
            p->x0 = p->x1;
            p->v0 = p->v1;
            if (is_stp(s))
                plant_stp_try_resync(s, n);
            if (idx_possible(s, n)) {
                /* the step's prediction found no crossing up to here (else the
                 * index event came first): just follow the encoder */
                p->idx_chk = plant_enc_e(s, n, p->t0);
                p->idx_chk_t = p->t0;
            }
            predict(s, n);
        }
    }
    axb_step_advance(s, n, now);
    idx_check(s, n, now);
    p->t_sync = now;
    if (inputs_changed(s, n))   /* e.g. the emergency stop, or a poked register */
        cut(s, n, now);
    axb_counter_mirror(s, n, now);
    if (s->vcd)
        vcd_synced(s, n);
}

void plant_inputs(sim_t *s, int n, cyc_t now)
{
    plant_sync(s, n, now);
    if (inputs_changed(s, n))
        cut(s, n, now);
    else
        idx_predict(s, n);   /* direction, arm or enable bits may matter */
}

/* After editing plant_axis_t (script, tests): restart the step from now. */
void plant_changed(sim_t *s, int n)
{
    cyc_t now = sim_now(s);
    plant_axis_t *p = &s->plant.ax[n];
    if (p->lines == 0)
        p->lines = 1;
    p->idx_chk = plant_has_encoder(s, n) ? plant_enc_e(s, n, now) : 0.0;
    p->idx_chk_t = now;
    cut(s, n, now);
    axb_counter_mirror(s, n, now);
}

int plant_switch_active(sim_t *s, int n, int which, cyc_t t)
{
    if (!s->plant.ax[n].sw[which].used)
        return 0;
    return plant_switch_at(&s->plant.ax[n], which, ifloor(plant_units(s, n, t) + 0.5));
}

/* Is the switch on with the axis at x (rounded units)? */
int plant_switch_at(const plant_axis_t *p, int which, int64_t x)
{
    const plant_switch_t *w = &p->sw[which];
    if (!w->used)
        return 0;
    switch (which) {
    case PLANT_SW_LP: return x >= w->pos;
    case PLANT_SW_LN: return x <= w->pos;
    default: return x >= w->pos && x - w->pos < w->width;
    }
}

/* AX_IN bits 0-3: 1 = input at 0 V.  A low-active switch pulls its input to
 * 0 V when on, a high-active one when off; an unwired input floats high. */
uint16_t plant_inputs_word(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    plant_sync(s, n, now);
    static const uint16_t bit[PLANT_NSW] = {AX_IN_IESP, AX_IN_IESN, AX_IN_RS};
    uint16_t in = 0;
    for (int w = 0; w < PLANT_NSW; w++)
        if (p->sw[w].used && (plant_switch_active(s, n, w, now) ^ p->sw[w].high))
            in |= bit[w];
    if (p->drive_fault ^ p->df_high)
        in |= AX_IN_DF;
    if (is_stp(s) && p->br_steps)
        in |= AX_IN_BR_STEPS;
    return in;
}

/* ---- SSI encoder ------------------------------------------------------- */
/* The frame the encoder sends when the receiver's clock starts: its reading
 * frozen at the first falling edge, Gray coded when J1 says so, MSB first
 * in SSI_FRAME_BITS clocks; a stuck data line sends all 0 or all 1. */
uint32_t plant_ssi_frame(sim_t *s, int n, cyc_t now, int gray)
{
    plant_axis_t *p = &s->plant.ax[n];
    uint32_t v = plant_ssi_value(s, n, now);
    if (gray)
        v ^= v >> 1;
    uint32_t frame = (v << (SSI_FRAME_BITS - p->ssi_bits)) & SSI_FRAME_MASK;
    if (p->enc_fault == PLANT_ENC_STUCK0)
        frame = 0;
    if (p->enc_fault == PLANT_ENC_STUCK1)
        frame = SSI_FRAME_MASK;
    return frame;
}

/* Set the encoder's reading (the counter command of the SSI card). */
void plant_ssi_set(sim_t *s, int n, cyc_t now, uint32_t value)
{
    plant_axis_t *p = &s->plant.ax[n];
    uint64_t mod = 1ull << p->ssi_bits;
    int64_t cur = ifloor(plant_units(s, n, now) + 0.5);
    p->ssi_off = (int64_t)(((uint64_t)value - (uint64_t)cur) & (mod - 1));
    p->ssi_frozen = value & (uint32_t)(mod - 1);
}
uint32_t plant_ssi_value(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    uint64_t mod = 1ull << p->ssi_bits;
    if (p->enc_fault == PLANT_ENC_FROZEN)
        return p->ssi_frozen;
    int64_t c = ifloor(plant_out_rev(s, n, t) * p->ssi_res + 0.5) + p->ssi_off;
    return (uint32_t)((uint64_t)c & (mod - 1));
}

/* ---- the lines from the board ------------------------------------------ */
/* d pulses on STEP (signed by DIR): a disabled driver ignores them. */
void plant_step_pulses(sim_t *s, int n, int64_t d)
{
    plant_axis_t *p = &s->plant.ax[n];
    p->gen += d;
    if (plant_drive_enabled(s, n))
        p->cmd += d;
}

/* The board armed its index latch: the next crossing counts from here. */
void plant_index_armed(sim_t *s, int n, cyc_t now)
{
    if (plant_has_encoder(s, n)) {
        s->plant.ax[n].idx_chk = plant_enc_e(s, n, now);
        s->plant.ax[n].idx_chk_t = now;
    }
    idx_predict(s, n);
}

/* ======================================================================== */
/* power-on, card reset, scheduler                                           */
/* ======================================================================== */
void plant_power_on(sim_t *s)
{
    s->plant.init = 1;
    for (int n = 0; n < MAC4_NAXES; n++)
        plant_axis_defaults(s, n);
}

/* A card reset (the board's, axisboard.c, which synced the plant and
 * cleared its counter chip): /EN opens, the motors coast on. */
void plant_board_reset(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (plant_has_encoder(s, n)) {
        p->idx_chk = plant_enc_e(s, n, now);
        p->idx_chk_t = now;
    }
    cut(s, n, now);
}

/* The plant's next event on axis n: a trace sample, and when the board's
 * index interrupt waits (index_ie), the predicted crossing or, between
 * grid points of a moving encoder, the step's end. */
cyc_t plant_next_event(sim_t *s, int n, int index_ie)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t t = CYC_NEVER;
    if (p->trace && !p->trace_tick)
        t = min_cyc(t, p->trace_next);
    if (index_ie) {
        t = min_cyc(t, p->t_idx);
        if (!(is_stp(s) && p->sync) && plant_has_encoder(s, n))
            t = min_cyc(t, p->t1);
    }
    return t;
}

void plant_events(sim_t *s, cyc_t now)
{
    for (int n = 0; n < MAC4_NAXES; n++) {
        plant_axis_t *p = &s->plant.ax[n];
        while (p->trace && !p->trace_tick && p->trace_next <= now) {
            plant_sync(s, n, p->trace_next);
            plant_trace_row(s, n, p->trace_next);
            p->trace_next += p->trace_iv;
        }
        plant_sync(s, n, now);
        /* tick mode: the timer expiry is a scheduler event of its own, so
         * the first call after it comes at the expiry's cycle */
        if (p->trace && p->trace_tick && s->tmr.last != p->trace_tick_seen && s->tmr.last <= now &&
            (s->tmr.ctrl & TMR_CTRL_RUN)) {
            p->trace_tick_seen = s->tmr.last;
            plant_trace_row(s, n, s->tmr.last);
        }
    }
}
