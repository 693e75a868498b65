/*
 * plant.c - the plant behind the axis interface boards: DC servo motors with
 * velocity- or current-mode amplifiers (MAC4-INC/SSI), stepper motors with
 * their step generator and driver (MAC4-STP), the position sensors
 * (quadrature encoder with index, SSI absolute encoder, step counter) and the
 * switches.  docs/plant.md has the equations, defaults and reasons.
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
#include <stddef.h>
#include <string.h>
#include "sim.h"
#include "periph.h"
#include "plant.h"
#include "vcd.h"

#define TWO_PI 6.283185307179586
#define CPU_HZ 16000000.0
#define CNT_MASK 0xFFFFFFu

/* ---- arithmetic without libm ------------------------------------------- */
static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }
static double fabs_(double x) { return x < 0 ? -x : x; }
static double floor_(double x)
{
    if (x >= 4.0e18 || x <= -4.0e18 || x != x)
        return x != x ? 0.0 : x;
    double d = (double)(int64_t)x;
    return d > x ? d - 1.0 : d;
}
static double ceil_(double x) { return -floor_(-x); }
static int64_t ifloor(double x) { return (int64_t)clampd(floor_(x), -4.0e18, 4.0e18); }
static int64_t iround(double x) { return ifloor(x + 0.5); }
static double sgn(double x) { return (x > 0) - (x < 0); }

static int is_stp(sim_t *s) { return s->card == MAC4_CARD_STP; }
static int is_ssi(sim_t *s) { return s->card == MAC4_CARD_SSI; }
static uint32_t mask24(int64_t v) { return (uint32_t)((uint64_t)v & CNT_MASK); }
static cyc_t min_cyc(cyc_t a, cyc_t b) { return a < b ? a : b; }

/* ======================================================================== */
/* defaults                                                                  */
/* ======================================================================== */
static void fill_defaults(sim_t *s, plant_axis_t *p)
{
    /* DC servo: 3000 rpm at 10 V behind a 16:1 gearbox, 1000-line encoder on
     * the output: 12 500 increments/s at 10 V, 6.1 increments/s per DAC LSB
     * (docs/plant.md: why this keeps K = 1..50 stable at 2.5 ms). */
    p->amp = PLANT_AMP_VELOCITY;
    p->rpm10 = 3000.0;
    p->tau = 0.002;
    p->amps10 = 10.0;
    p->imax = 10.0;
    p->kt = 0.1;
    p->inertia = 5e-5;
    p->visc = 1e-5;
    p->coulomb = 0.005;
    p->load = 0.0;
    /* stepper: 500 steps/rev (manual 7.2), light load */
    p->steps_rev = 500.0;
    p->ssf = 1000.0;
    p->accel = 250000.0;
    p->fmax = 25000.0;
    p->boost = 1.0;
    p->gear = is_stp(s) ? 1.0 : 16.0;
    p->lines = 1000;
    p->index = 0;
    p->ssi_bits = 24;
    p->ssi_res = 4096.0;
    p->br_steps = 1;
    p->df_high = 0;
    p->drive_fault = 0;
    p->enc_fault = PLANT_ENC_OK;
    memset(p->sw, 0, sizeof p->sw);
}

/* Everything, state included: the axis at rest at position 0. */
void plant_axis_defaults(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    FILE *tr = p->trace;
    cyc_t iv = p->trace_iv, tn = p->trace_next, ts = p->trace_tick_seen;
    int tt = p->trace_tick, tc = p->trace_card;
    memset(p, 0, sizeof *p);
    p->trace = tr;
    p->trace_iv = iv;
    p->trace_next = tn;
    p->trace_tick = tt;
    p->trace_card = tc;
    p->trace_tick_seen = ts;
    fill_defaults(s, p);
    cyc_t now = sim_now(s);
    p->t0 = p->t_sync = p->nco_t = now;
    p->t1 = p->t_idx = CYC_NEVER;
    p->sync = 1;
    p->idx_chk = 0.5;
    p->idx_chk_t = now;
}

/* The parameters only (they come first in plant_axis_t), state kept. */
void plant_params_defaults(sim_t *s, int n)
{
    plant_axis_t d;
    plant_set_enc_fault(s, n, PLANT_ENC_OK);
    memset(&d, 0, sizeof d);
    fill_defaults(s, &d);
    memcpy(&s->plant.ax[n], &d, offsetof(plant_axis_t, t0));
}

/* ======================================================================== */
/* inputs                                                                    */
/* ======================================================================== */
static int drive_enabled(sim_t *s, int n)
{
    return (s->ax[n].ctrl & AX_CTRL_EN) && !s->sys.estop && !s->plant.ax[n].drive_fault;
}

static double dac_volts(sim_t *s, int n) { return (double)s->ax[n].dac * (10.0 / 2048.0); }

static double stp_clock_hz(sim_t *s, int n)
{
    return (s->ax[n].ctrl & AX_CTRL_TURBO) ? (double)STP_CLK_HZ_TURBO : (double)STP_CLK_HZ;
}

/* The rate the driver's field turns at, steps/s, signed by DIR; 0 when the
 * generator is stopped by the down-counter. */
static double stp_field_hz(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->pmode == PLANT_PULSES_DONE)
        return 0.0;
    double f = (double)s->ax[n].rate * stp_clock_hz(s, n) / 65536.0;
    return (s->ax[n].ctrl & AX_CTRL_DIR) ? f : 0.0 - f;   /* no -0 */
}

static double stp_boost(sim_t *s, int n)
{
    return (s->ax[n].ctrl & AX_CTRL_BOOST) ? s->plant.ax[n].boost : 1.0;
}

/* What the current step depends on; a change cuts the step. */
static double input_u(sim_t *s, int n)
{
    if (is_stp(s))
        return stp_field_hz(s, n);
    if (!drive_enabled(s, n))
        return 0.0;
    /* reversed wiring (motor leads swapped): the amplifier's input inverted */
    return s->plant.ax[n].reversed ? 0.0 - dac_volts(s, n) : dac_volts(s, n);
}

/* ======================================================================== */
/* step generator: phase accumulator, pulses counted analytically            */
/* ======================================================================== */
cyc_t plant_nco_period(sim_t *s, int n)
{
    return (s->ax[n].ctrl & AX_CTRL_TURBO) ? (cyc_t)(CPU_HZ / STP_CLK_HZ_TURBO)
                                           : (cyc_t)(CPU_HZ / STP_CLK_HZ);
}

static int nco_running(sim_t *s, int n)
{
    return is_stp(s) && s->ax[n].rate && s->plant.ax[n].pmode != PLANT_PULSES_DONE;
}

/* The cycle at which the j-th pulse comes (j >= 1) after the clock stood
 * at nco_t with the accumulator at acc. */
cyc_t plant_nco_pulse_time(sim_t *s, int n, cyc_t nco_t, uint32_t acc, uint64_t j)
{
    uint32_t rate = s->ax[n].rate;
    if (!rate || !j)
        return CYC_NEVER;
    cyc_t P = plant_nco_period(s, n);
    uint64_t need = j * 65536u - acc;
    uint64_t m = (need + rate - 1) / rate;
    return (nco_t / P + m) * P;
}

/* ... from now */
static cyc_t nco_pulse_time(sim_t *s, int n, uint64_t j)
{
    plant_axis_t *p = &s->plant.ax[n];
    return plant_nco_pulse_time(s, n, p->nco_t, p->acc, j);
}

static cyc_t nco_done_time(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (!is_stp(s) || p->pmode != PLANT_PULSES_COUNTING)
        return CYC_NEVER;
    return nco_pulse_time(s, n, p->remaining);
}

/* Clock the accumulator up to `to`; returns 1 if the down-counter ended. */
static int nco_advance(sim_t *s, int n, cyc_t to)
{
    plant_axis_t *p = &s->plant.ax[n];
    axis_hw_t *a = &s->ax[n];
    if (to <= p->nco_t)
        return 0;
    if (!is_stp(s) || !a->rate) {
        p->nco_t = to;
        return 0;
    }
    cyc_t P = plant_nco_period(s, n);
    uint64_t k = to / P - p->nco_t / P;
    cyc_t nco_t0 = p->nco_t;            /* for the waveform's STEP edges (vcd.c) */
    uint32_t acc0 = p->acc;
    p->nco_t = to;
    if (!k)
        return 0;
    uint64_t sum = p->acc + k * a->rate;
    uint64_t c = sum >> 16;
    p->acc = (uint32_t)(sum & 0xFFFF);
    int ended = 0;
    if (p->pmode == PLANT_PULSES_DONE)
        return 0;                       /* output gated off, accumulator keeps turning */
    if (p->pmode == PLANT_PULSES_COUNTING) {
        if (c >= p->remaining) {
            c = p->remaining;
            p->remaining = 0;
            p->pmode = PLANT_PULSES_DONE;
            a->pstat |= AX_IN_PDONE;
            ended = 1;
        } else {
            p->remaining -= (uint32_t)c;
        }
    }
    if (!c)
        return ended;
    int64_t d = (a->ctrl & AX_CTRL_DIR) ? (int64_t)c : -(int64_t)c;
    p->gen += d;
    if (drive_enabled(s, n))
        p->cmd += d;                    /* a disabled driver ignores its pulses */
    if (s->vcd)
        vcd_pulses(s, n, nco_t0, acc0, c);
    if (a->ctrl & AX_CTRL_PULSE_IE) {
        if ((a->pstat & AX_IN_PULSE) || c > 1)
            a->pstat |= AX_IN_PULSE_OVR;
        a->pstat |= AX_IN_PULSE;
    }
    return ended;
}

/* ======================================================================== */
/* positions                                                                 */
/* ======================================================================== */
static double lerp_x(plant_axis_t *p, cyc_t t)
{
    if (p->t1 == CYC_NEVER || t <= p->t0)
        return p->x0;
    if (t >= p->t1)
        return p->x1;
    return p->x0 + (p->x1 - p->x0) * (double)(t - p->t0) / (double)(p->t1 - p->t0);
}

static double lerp_v(plant_axis_t *p, cyc_t t)
{
    if (p->t1 == CYC_NEVER || t <= p->t0)
        return p->v0;
    if (t >= p->t1)
        return p->v1;
    return p->v0 + (p->v1 - p->v0) * (double)(t - p->t0) / (double)(p->t1 - p->t0);
}

/* Stepper rotor position in steps (the generator must be clocked to t). */
static double stp_rotor(plant_axis_t *p, cyc_t t)
{
    return p->sync ? (double)(p->cmd + p->off) : lerp_x(p, t);
}

/* Output shaft revolutions. */
static double out_rev(sim_t *s, int n, cyc_t t)
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
    return out_rev(s, n, t) * plant_units_per_rev(s, n);
}

/* sin(x) without libm (the fuzz targets link the plant without it): x
 * reduced to [-pi/2, pi/2], then Taylor to x^13 (error below 1e-9 there). */
static double lead_sin(double x)
{
    double turns = x / TWO_PI;
    x -= TWO_PI * (double)ifloor(turns + 0.5);       /* [-pi, pi] */
    if (x > TWO_PI / 4)
        x = TWO_PI / 2 - x;
    else if (x < -TWO_PI / 4)
        x = -TWO_PI / 2 - x;
    double x2 = x * x, term = x, sum = x;
    for (int k = 1; k <= 6; k++) {
        term *= -x2 / (double)((2 * k) * (2 * k + 1));
        sum += term;
    }
    return sum;
}

/* The leadscrew's error: where the load is for the output shaft at u. */
double plant_lead_error(const plant_axis_t *p, double u)
{
    double e = p->lead_ppm * 1e-6 * u;
    if (p->lead_amp != 0.0 && p->lead_pitch > 0.0)
        e += p->lead_amp * lead_sin(TWO_PI * u / p->lead_pitch);
    return e;
}

double plant_load_units(sim_t *s, int n, cyc_t t)
{
    double u = plant_units(s, n, t);
    return u + plant_lead_error(&s->plant.ax[n], u);
}

double plant_units_per_s(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (is_stp(s))
        return p->sync ? stp_field_hz(s, n) * (drive_enabled(s, n) ? 1.0 : 0.0) : lerp_v(p, t);
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
static int has_encoder(sim_t *s, int n)
{
    if (is_ssi(s))
        return 0;
    return !is_stp(s) || !s->plant.ax[n].br_steps;
}

static double enc_e(sim_t *s, int n, cyc_t t)
{
    return out_rev(s, n, t) * 4.0 * s->plant.ax[n].lines + 0.5;
}

static int64_t counter_raw(sim_t *s, int n, cyc_t t)
{
    if (is_ssi(s))
        return 0;
    if (is_stp(s) && s->plant.ax[n].br_steps)
        return s->plant.ax[n].gen;
    return ifloor(enc_e(s, n, t));
}

static int counter_frozen(sim_t *s, int n) { return s->plant.ax[n].enc_fault != PLANT_ENC_OK && !is_ssi(s); }

static uint32_t counter_at(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (counter_frozen(s, n))
        return p->cnt_frozen;
    return mask24(counter_raw(s, n, t) + p->cnt_off);
}

/* ======================================================================== */
/* index pulse                                                               */
/* ======================================================================== */
static int idx_possible(sim_t *s, int n)
{
    return has_encoder(s, n) && !counter_frozen(s, n) && !s->ax[n].idx_latched;
}

static void idx_latch(sim_t *s, int n, int64_t incr)
{
    axis_hw_t *a = &s->ax[n];
    a->idx_latched = 1;
    a->idx_latch = mask24(incr + s->plant.ax[n].cnt_off);
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
                idx_latch(s, n, (int64_t)b);
        } else if (e < p->idx_chk) {
            double b = I + 1.0 + N * floor_((p->idx_chk - I - 1.0) / N);   /* last one below */
            if (e < b)
                idx_latch(s, n, (int64_t)b - 1);
        }
    }
    p->idx_chk = e;
    p->idx_chk_t = t;
}

/* Only while a latch is possible: arming takes a fresh position. */
static void idx_check(sim_t *s, int n, cyc_t t)
{
    if (idx_possible(s, n) && s->plant.ax[n].idx_chk_t != t)
        idx_check_to(s, n, enc_e(s, n, t), t);
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
        if (!nco_running(s, n) || !drive_enabled(s, n))
            return;
        double k = 4.0 * p->lines / (p->steps_rev * p->gear);   /* increments per step */
        double r0 = (double)(p->cmd + p->off);
        double j;
        if (s->ax[n].ctrl & AX_CTRL_DIR) {
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
        if (j > 1e12 || (p->pmode == PLANT_PULSES_COUNTING && j > (double)p->remaining))
            return;
        p->t_idx = nco_pulse_time(s, n, (uint64_t)j);
        return;
    }
    if (p->t1 == CYC_NEVER)
        return;
    /* linear from the last check (on this step's line) to the step's end */
    cyc_t tf = p->idx_chk_t > p->t0 ? p->idx_chk_t : p->t0;
    if (tf >= p->t1)
        return;
    double e1 = out_rev(s, n, p->t1) * N + 0.5;
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
    double e = enc_e(s, n, t);
    /* the crossing was computed exactly: do not let rounding miss it */
    if (p->idx_dir > 0 && e < p->idx_b)
        e = p->idx_b;
    if (p->idx_dir < 0 && e >= p->idx_b)
        e = p->idx_b - 1e-9;
    idx_check_to(s, n, e, t);
    p->t_idx = CYC_NEVER;
}

/* ======================================================================== */
/* DC servo: amplifier, motor, friction                                      */
/* ======================================================================== */
static double servo_tmax(const plant_axis_t *p) { return p->kt * p->imax; }

/* Torque of the amplifier at motor speed w (rad/s) for u volts; a power
 * stage that is off (en = 0) gives none and the motor coasts. */
static double servo_torque(const plant_axis_t *p, double u, int en, double w)
{
    double T;
    if (!en)
        return 0.0;
    if (p->amp == PLANT_AMP_VELOCITY) {
        double wc = u / 10.0 * p->rpm10 * TWO_PI / 60.0;
        T = p->inertia / p->tau * (wc - w);
    } else {
        T = p->kt * clampd(u / 10.0 * p->amps10, -p->imax, p->imax);
    }
    return clampd(T, -servo_tmax(p), servo_tmax(p));
}

/* Implicit Euler for the linear part: J (w' - w)/dt = T(w') - visc w' - F,
 * F = Coulomb term - external load, with the amplifier's current limit. */
static double servo_w_next(const plant_axis_t *p, double u, int en, double w, double dt, double F)
{
    double m = p->inertia / dt;
    if (en && p->amp == PLANT_AMP_VELOCITY) {
        double kv = p->inertia / p->tau, wc = u / 10.0 * p->rpm10 * TWO_PI / 60.0;
        double wn = (m * w + kv * wc - F) / (m + kv + p->visc);
        double T = kv * (wc - wn);
        if (fabs_(T) <= servo_tmax(p))
            return wn;
        return (m * w + sgn(T) * servo_tmax(p) - F) / (m + p->visc);
    }
    return (m * w + servo_torque(p, u, en, w) - F) / (m + p->visc);
}

static void servo_step(const plant_axis_t *p, double u, int en, double dt, double x, double w,
                       double *x1, double *w1)
{
    double wn;
    if (w == 0.0) {
        double T0 = servo_torque(p, u, en, 0.0) + p->load;
        if (fabs_(T0) <= p->coulomb) {
            wn = 0.0;   /* static friction holds */
        } else {
            double sd = sgn(T0);
            wn = servo_w_next(p, u, en, 0.0, dt, p->coulomb * sd - p->load);
            if (wn * sd < 0)
                wn = 0.0;
        }
    } else {
        double sd = sgn(w);
        wn = servo_w_next(p, u, en, w, dt, p->coulomb * sd - p->load);
        if (wn * sd <= 0 || fabs_(wn) < 1e-9)
            wn = 0.0;   /* friction stops it; breakaway is looked at next step */
    }
    *w1 = wn;
    *x1 = x + dt * (w + wn) * 0.5 / TWO_PI;
}

static int servo_at_rest(const plant_axis_t *p, double u, int en)
{
    if (p->v0 != 0.0)
        return 0;
    return fabs_(servo_torque(p, u, en, 0.0) + p->load) <= p->coulomb;
}

/* ======================================================================== */
/* stepper motor                                                             */
/* ======================================================================== */
/* Sync rules (docs/plant.md): the rotor follows the field while the
 * frequency mismatch |f - v| stays within the start/stop frequency and f
 * within fmax; it catches up with the field at up to `accel`; out of sync it
 * coasts down at `accel` and locks in again once |f - v| <= ssf. */
static int stp_can_sync(sim_t *s, int n, double f, double v)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (!drive_enabled(s, n))
        return 0;
    if (p->fmax > 0 && fabs_(f) > p->fmax)
        return 0;
    return fabs_(f - v) <= p->ssf * stp_boost(s, n);
}

static void stp_lose_sync(plant_axis_t *p, double v)
{
    if (!p->sync)
        return;
    p->x0 = (double)(p->cmd + p->off);
    p->v0 = v;
    p->sync = 0;
}

static void stp_try_resync(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->sync || !stp_can_sync(s, n, stp_field_hz(s, n), p->v0))
        return;
    p->off = iround(p->x0) - p->cmd;   /* the rotor locks onto the nearest step */
    p->x0 = (double)(p->cmd + p->off);
    p->sync = 1;
}

static void stp_step(sim_t *s, int n, double dt)
{
    plant_axis_t *p = &s->plant.ax[n];
    double A = p->accel * stp_boost(s, n), v = p->v0;
    if (p->sync) {
        double f = stp_field_hz(s, n), a = A;
        if (fabs_(f) > fabs_(v) && f * v >= 0 && p->fmax > 0)
            a = A * clampd(1.0 - fabs_(v) / p->fmax, 0.05, 1.0);   /* torque falls with speed */
        double dv = clampd(f - v, -a * dt, a * dt);
        p->v1 = fabs_(f - (v + dv)) < 1e-9 ? f : v + dv;
        p->x1 = p->x0;
    } else {
        double dv = A * dt;
        p->v1 = fabs_(v) <= dv ? 0.0 : v - sgn(v) * dv;
        p->x1 = p->x0 + dt * (v + p->v1) * 0.5;
    }
}

static int stp_at_rest(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->sync)
        return p->v0 == stp_field_hz(s, n);
    return p->v0 == 0.0;   /* stalled or disabled, and resync already tried */
}

/* ======================================================================== */
/* stepping, cuts and the event loop                                         */
/* ======================================================================== */
static void predict(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    p->in_u = input_u(s, n);
    p->in_en = drive_enabled(s, n);
    p->in_boost = (s->ax[n].ctrl & AX_CTRL_BOOST) != 0;
    int rest = is_stp(s) ? stp_at_rest(s, n) : servo_at_rest(p, p->in_u, p->in_en);
    if (rest) {
        p->t1 = CYC_NEVER;
        p->x1 = p->x0;
        p->v1 = p->v0;
    } else {
        p->t1 = (p->t0 / PLANT_STEP_CYC + 1) * PLANT_STEP_CYC;
        double dt = (double)(p->t1 - p->t0) / CPU_HZ;
        if (is_stp(s))
            stp_step(s, n, dt);
        else
            servo_step(p, p->in_u, p->in_en, dt, p->x0, p->v0, &p->x1, &p->v1);
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
        if (p->sync && !stp_can_sync(s, n, stp_field_hz(s, n), v))
            stp_lose_sync(p, v);
        stp_try_resync(s, n);
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
    return p->in_u != input_u(s, n) || p->in_en != drive_enabled(s, n) ||
           p->in_boost != ((s->ax[n].ctrl & AX_CTRL_BOOST) != 0);
}

/* A test or tool may have written axis_hw_t.counter directly. */
static void counter_poked(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (s->ax[n].counter == p->cnt_seen)
        return;
    s->ax[n].counter &= CNT_MASK;
    p->cnt_frozen = s->ax[n].counter;
    p->cnt_off = (int64_t)s->ax[n].counter - p->raw_seen;
    p->cnt_seen = s->ax[n].counter;
}

static void mirror_counter(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    p->raw_seen = counter_raw(s, n, t);
    s->ax[n].counter = p->cnt_seen = counter_frozen(s, n) ? p->cnt_frozen : mask24(p->raw_seen + p->cnt_off);
}

void plant_sync(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (now < p->t_sync)
        now = p->t_sync;
    counter_poked(s, n);
    if (p->t1 == CYC_NEVER && p->t_idx == CYC_NEVER && !(is_stp(s) && s->ax[n].rate)) {
        /* fast path: at rest and no pulses, nothing can have moved */
        p->nco_t = p->t_sync = now;
        if (inputs_changed(s, n)) {
            cut(s, n, now);
            mirror_counter(s, n, now);
        }
        if (s->vcd)
            vcd_synced(s, n);
        return;
    }
    for (;;) {
        cyc_t td = nco_done_time(s, n);
        cyc_t te = min_cyc(min_cyc(p->t1, p->t_idx), td);
        if (te > now)
            break;
        int ended = nco_advance(s, n, te);
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
                stp_try_resync(s, n);
            if (idx_possible(s, n)) {
                /* the step's prediction found no crossing up to here (else the
                 * index event came first): just follow the encoder */
                p->idx_chk = enc_e(s, n, p->t0);
                p->idx_chk_t = p->t0;
            }
            predict(s, n);
        }
    }
    nco_advance(s, n, now);
    idx_check(s, n, now);
    p->t_sync = now;
    if (inputs_changed(s, n))   /* e.g. the emergency stop, or a poked register */
        cut(s, n, now);
    mirror_counter(s, n, now);
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
    p->idx_chk = has_encoder(s, n) ? enc_e(s, n, now) : 0.0;
    p->idx_chk_t = now;
    cut(s, n, now);
    mirror_counter(s, n, now);
}

/* ======================================================================== */
/* board registers                                                           */
/* ======================================================================== */
uint32_t plant_counter(sim_t *s, int n, cyc_t now)
{
    plant_sync(s, n, now);
    return counter_at(s, n, now);
}

void plant_counter_set(sim_t *s, int n, cyc_t now, uint32_t value)
{
    plant_axis_t *p = &s->plant.ax[n];
    plant_sync(s, n, now);
    value &= CNT_MASK;
    if (is_ssi(s)) {   /* no counter on the SSI board: set the encoder's reading */
        uint64_t mod = 1ull << p->ssi_bits;
        int64_t cur = ifloor(plant_units(s, n, now) + 0.5);
        p->ssi_off = (int64_t)(((uint64_t)value - (uint64_t)cur) & (mod - 1));
        p->ssi_frozen = value & (uint32_t)(mod - 1);
        return;
    }
    p->cnt_frozen = value;
    p->cnt_off = (int64_t)value - counter_raw(s, n, now);
    mirror_counter(s, n, now);
}

void plant_idx_arm(sim_t *s, int n, cyc_t now)
{
    plant_sync(s, n, now);
    s->ax[n].idx_latched = 0;
    if (has_encoder(s, n)) {
        s->plant.ax[n].idx_chk = enc_e(s, n, now);
        s->plant.ax[n].idx_chk_t = now;
    }
    idx_predict(s, n);
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

/* ---- SSI ---------------------------------------------------------------- */
static const double ssi_hz[4] = {93750.0, 187500.0, 375000.0, 750000.0};

uint64_t plant_ssi_cycles(int clock)
{
    return (uint64_t)ceil_(SSI_FRAME_BITS * CPU_HZ / ssi_hz[clock & 3]);
}

uint32_t plant_ssi_value(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    uint64_t mod = 1ull << p->ssi_bits;
    if (p->enc_fault == PLANT_ENC_FROZEN)
        return p->ssi_frozen;
    int64_t c = ifloor(out_rev(s, n, t) * p->ssi_res + 0.5) + p->ssi_off;
    return (uint32_t)((uint64_t)c & (mod - 1));
}

void plant_ssi_start(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (!is_ssi(s) || now < p->ssi_end)
        return;                          /* a read in progress runs on */
    plant_sync(s, n, now);
    p->ssi_old = plant_ssi_reg(s, n, now);
    /* the encoder freezes its position at the first falling clock edge */
    uint32_t v = plant_ssi_value(s, n, now);
    if (s->ax[n].gray)
        v ^= v >> 1;
    uint32_t frame = (v << (SSI_FRAME_BITS - p->ssi_bits)) & SSI_FRAME_MASK;
    if (p->enc_fault == PLANT_ENC_STUCK0)
        frame = 0;
    if (p->enc_fault == PLANT_ENC_STUCK1)
        frame = SSI_FRAME_MASK;
    p->ssi_frame = frame;
    p->ssi_start = now;
    p->ssi_end = now + plant_ssi_cycles(s->plant.ssi_clock);
}

int plant_ssi_busy(sim_t *s, int n, cyc_t now) { return now < s->plant.ax[n].ssi_end; }

/* The shift register: bits come in MSB first at the rising clock edges. */
uint32_t plant_ssi_reg(sim_t *s, int n, cyc_t now)
{
    plant_axis_t *p = &s->plant.ax[n];
    axis_hw_t *a = &s->ax[n];
    if (p->ssi_end == 0)
        return a->ssi & SSI_FRAME_MASK;
    if (now >= p->ssi_end) {
        a->ssi = p->ssi_frame;
        return a->ssi;
    }
    uint64_t k = (uint64_t)((double)(now - p->ssi_start) * ssi_hz[s->plant.ssi_clock & 3] / CPU_HZ);
    if (k == 0)
        return p->ssi_old;
    if (k >= SSI_FRAME_BITS)
        return p->ssi_frame;
    return (uint32_t)(((uint64_t)p->ssi_old << k | p->ssi_frame >> (SSI_FRAME_BITS - k)) & SSI_FRAME_MASK);
}

/* ---- STP pulse down-counter ------------------------------------------- */
void plant_pulses_write(sim_t *s, int n, cyc_t now, uint16_t v)
{
    plant_axis_t *p = &s->plant.ax[n];
    plant_sync(s, n, now);
    s->ax[n].pstat &= (uint16_t)~AX_IN_PDONE;
    p->remaining = v;
    p->pmode = v ? PLANT_PULSES_COUNTING : PLANT_PULSES_FREE;
    plant_inputs(s, n, now);
}

/* ======================================================================== */
/* reset, scheduler                                                          */
/* ======================================================================== */
static void plant_init(sim_t *s)
{
    plant_t *pl = &s->plant;
    pl->init = 1;
    pl->ssi_clock = 3;   /* J2 at D, 750 kHz: the bench default (docs/plant.md) */
    for (int n = 0; n < MAC4_NAXES; n++) {
        plant_axis_defaults(s, n);
        s->ax[n].gray = is_ssi(s);   /* J1 open: Gray code, the usual SSI encoder */
    }
}

/* A card reset: the axis boards' registers return to their reset state;
 * the motors keep turning (they coast, /EN is open). */
void plant_reset(sim_t *s)
{
    cyc_t now = sim_now(s);
    if (!s->plant.init)
        plant_init(s);
    for (int n = 0; n < MAC4_NAXES; n++) {
        plant_axis_t *p = &s->plant.ax[n];
        axis_hw_t *a = &s->ax[n];
        plant_sync(s, n, now);
        a->ctrl = 0;
        a->dac = 0;
        a->rate = 0;
        a->idx_latched = 0;
        a->idx_latch = 0;
        a->pstat = 0;
        a->ssi = 0;
        p->acc = 0;
        p->pmode = PLANT_PULSES_FREE;
        p->remaining = 0;
        p->ssi_end = 0;
        p->ssi_old = p->ssi_frame = 0;
        p->cnt_frozen = 0;
        p->cnt_off = -counter_raw(s, n, now);   /* the counter chip is cleared */
        if (has_encoder(s, n)) {
            p->idx_chk = enc_e(s, n, now);
            p->idx_chk_t = now;
        }
        cut(s, n, now);
        mirror_counter(s, n, now);
    }
}

static void trace_row(sim_t *s, int n, cyc_t t);

cyc_t plant_next_event(sim_t *s)
{
    cyc_t t = CYC_NEVER;
    for (int n = 0; n < MAC4_NAXES; n++) {
        plant_axis_t *p = &s->plant.ax[n];
        axis_hw_t *a = &s->ax[n];
        if (p->trace && !p->trace_tick)
            t = min_cyc(t, p->trace_next);
        if ((a->ctrl & AX_CTRL_IDX_IE) && !a->idx_latched) {
            t = min_cyc(t, p->t_idx);
            if (!(is_stp(s) && p->sync) && has_encoder(s, n))
                t = min_cyc(t, p->t1);
        }
        if (is_stp(s)) {
            if ((a->ctrl & AX_CTRL_PULSE_IE) && nco_running(s, n))
                t = min_cyc(t, nco_pulse_time(s, n, 1));
            if (a->ctrl & AX_CTRL_DONE_IE)
                t = min_cyc(t, nco_done_time(s, n));
        }
    }
    return t;
}

void plant_events(sim_t *s, cyc_t now)
{
    for (int n = 0; n < MAC4_NAXES; n++) {
        plant_axis_t *p = &s->plant.ax[n];
        while (p->trace && !p->trace_tick && p->trace_next <= now) {
            plant_sync(s, n, p->trace_next);
            trace_row(s, n, p->trace_next);
            p->trace_next += p->trace_iv;
        }
        plant_sync(s, n, now);
        /* tick mode: the timer expiry is a scheduler event of its own, so
         * the first call after it comes at the expiry's cycle */
        if (p->trace && p->trace_tick && s->tmr.last != p->trace_tick_seen && s->tmr.last <= now &&
            (s->tmr.ctrl & TMR_CTRL_RUN)) {
            p->trace_tick_seen = s->tmr.last;
            trace_row(s, n, s->tmr.last);
        }
    }
}

/* ======================================================================== */
/* observation                                                               */
/* ======================================================================== */
/* Move the mechanics to an absolute position (units of plant_units), as if
 * turned by hand: the sensors follow, no index pulse is latched. */
void plant_set_position(sim_t *s, int n, double units)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    if (is_stp(s)) {
        int64_t r = iround(units);
        if (p->sync)
            p->off = r - p->cmd;
        p->x0 = p->x1 = (double)r;
        p->lost_base = p->gen - r;   /* lost steps count from here */
    } else {
        p->x0 = p->x1 = units / plant_units_per_rev(s, n) * p->gear;
    }
    p->t0 = now;
    plant_changed(s, n);
}

/* Encoder faults: the counter (or SSI reading) stops where it is and goes
 * on from there when the fault is cleared; stuck data only on SSI. */
void plant_set_enc_fault(sim_t *s, int n, int mode)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    int was = p->enc_fault;
    if (!is_ssi(s) && mode != PLANT_ENC_OK)
        mode = PLANT_ENC_FROZEN;         /* A/B lines stuck: nothing is counted */
    if (was == mode)
        return;
    if (mode == PLANT_ENC_FROZEN) {
        p->cnt_frozen = counter_at(s, n, now);
        p->ssi_frozen = plant_ssi_value(s, n, now);
    }
    if (was == PLANT_ENC_FROZEN) {
        p->enc_fault = PLANT_ENC_OK;
        if (is_ssi(s)) {
            uint64_t mod = 1ull << p->ssi_bits;
            int64_t cur = ifloor(out_rev(s, n, now) * p->ssi_res + 0.5);
            p->ssi_off = (int64_t)(((uint64_t)p->ssi_frozen - (uint64_t)cur) & (mod - 1));
        } else {
            p->cnt_off = (int64_t)p->cnt_frozen - counter_raw(s, n, now);
        }
    }
    p->enc_fault = mode;
    plant_changed(s, n);
}

void plant_enc_jump(sim_t *s, int n, int64_t by)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    p->cnt_off += by;
    p->cnt_frozen = mask24((int64_t)p->cnt_frozen + by);
    p->ssi_off += by;
    p->ssi_frozen = (uint32_t)(((uint64_t)p->ssi_frozen + (uint64_t)by) & ((1ull << p->ssi_bits) - 1));
    mirror_counter(s, n, now);
}

void plant_step_counts(sim_t *s, int n, int64_t *generated, int64_t *lost)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    *generated = p->gen;
    *lost = p->gen - p->lost_base - iround(stp_rotor(p, now));
}

static const char *const trace_hdr_servo = "t_ms,dac,volts,en,position,velocity,motor_rpm,counter";
static const char *const trace_hdr_stp = "t_ms,rate,field_hz,en,generated,rotor,rotor_hz,lost,sync,counter";
/* the axis data the card publishes (hal/mac4_map.h DPA_*), as a host reads it */
static const char *const trace_hdr_card = ",card_pos,setpoint,ferr,out,ustat";

static void trace_row(sim_t *s, int n, cyc_t t)
{
    plant_axis_t *p = &s->plant.ax[n];
    axis_hw_t *a = &s->ax[n];
    double ms = (double)t / 16000.0;
    uint32_t cnt = is_ssi(s) ? plant_ssi_value(s, n, t) : counter_at(s, n, t);
    if (is_stp(s)) {
        double rot = stp_rotor(p, t);
        fprintf(p->trace, "%.3f,%u,%.3f,%d,%lld,%.3f,%.3f,%lld,%d,%u", ms, a->rate,
                stp_field_hz(s, n), drive_enabled(s, n), (long long)p->gen, rot,
                p->sync ? (drive_enabled(s, n) ? stp_field_hz(s, n) : 0.0) : lerp_v(p, t),
                (long long)(p->gen - p->lost_base - iround(rot)), p->sync, cnt);
    } else {
        fprintf(p->trace, "%.3f,%d,%.4f,%d,%.3f,%.3f,%.2f,%u", ms, a->dac, dac_volts(s, n),
                drive_enabled(s, n), plant_units(s, n, t), plant_units_per_s(s, n, t),
                plant_motor_rpm(s, n, t), cnt);
    }
    if (p->trace_card) {
        uint32_t d = DP_AXIS_DATA((uint32_t)n);
        fprintf(p->trace, ",%d,%d,%d,%d,0x%08X", (int32_t)dp_rd32(s, d + DPA_POS),
                (int32_t)dp_rd32(s, d + DPA_SETPOINT), (int32_t)dp_rd32(s, d + DPA_FERR),
                (int32_t)dp_rd32(s, d + DPA_OUT), dp_rd32(s, d + DPA_USTAT));
    }
    fputc('\n', p->trace);
}

int plant_trace_start_ex(sim_t *s, int n, const char *path, cyc_t iv, int tick, int card)
{
    plant_axis_t *p = &s->plant.ax[n];
    plant_trace_stop(s, n);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    cyc_t now = sim_now(s);
    plant_sync(s, n, now);
    p->trace = f;
    p->trace_iv = iv ? iv : 1;
    p->trace_next = now;
    p->trace_tick = tick;
    p->trace_card = card;
    p->trace_tick_seen = s->tmr.last;   /* from the next expiry on */
    fputs(is_stp(s) ? trace_hdr_stp : trace_hdr_servo, f);
    fputs(card ? trace_hdr_card : "", f);
    fputc('\n', f);
    return 0;
}

int plant_trace_start(sim_t *s, int n, const char *path, cyc_t iv)
{
    return plant_trace_start_ex(s, n, path, iv, 0, 0);
}

void plant_trace_stop(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->trace)
        fclose(p->trace);
    p->trace = NULL;
}

void plant_format(sim_t *s, int n, char *buf, size_t len)
{
    plant_axis_t *p = &s->plant.ax[n];
    cyc_t now = sim_now(s);
    uint16_t in = plant_inputs_word(s, n, now);   /* syncs */
    double u = plant_units(s, n, now);
    const char *unit = is_stp(s) ? "steps" : is_ssi(s) ? "counts" : "inc";
    int sw[PLANT_NSW];
    for (int w = 0; w < PLANT_NSW; w++)
        sw[w] = plant_switch_active(s, n, w, now);
    if (is_stp(s)) {
        int64_t made = iround(u);
        snprintf(buf, len,
                "plant %d pos=%lld %s rev=%.4f vel=%.1f steps/s rate=%u field=%.3fHz en=%d "
                "generated=%lld lost=%lld sync=%d counter=0x%06X "
                "lp=%d ln=%d ref=%d df=%d in=0x%04X",
                n, (long long)made, unit, out_rev(s, n, now), plant_units_per_s(s, n, now),
                s->ax[n].rate, stp_field_hz(s, n), drive_enabled(s, n), (long long)p->gen,
                (long long)(p->gen - p->lost_base - made), p->sync, counter_at(s, n, now), sw[0],
                sw[1], sw[2], p->drive_fault, in);
    } else {
        snprintf(buf, len,
                "plant %d pos=%lld %s rev=%.4f vel=%.1f %s/s rpm=%.1f dac=%d volts=%.3f en=%d "
                "%s=0x%06X lp=%d ln=%d ref=%d df=%d in=0x%04X",
                n, (long long)ifloor(u + 0.5), unit, out_rev(s, n, now), plant_units_per_s(s, n, now),
                unit, plant_motor_rpm(s, n, now), s->ax[n].dac, dac_volts(s, n), drive_enabled(s, n),
                is_ssi(s) ? "ssi" : "counter",
                is_ssi(s) ? plant_ssi_value(s, n, now) : counter_at(s, n, now), sw[0], sw[1], sw[2],
                p->drive_fault, in);
    }
    if (p->lead_amp != 0.0 || p->lead_ppm != 0.0) {   /* a leadscrew with an error: where the load is */
        size_t used = strlen(buf);
        if (used < len)
            snprintf(buf + used, len - used, " load=%.3f", u + plant_lead_error(p, u));
    }
}
