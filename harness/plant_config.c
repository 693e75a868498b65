/*
 * plant_config.c - the plant's parameters and their defaults, the machine
 * behind the output shaft (a leadscrew with its error), and the edits the
 * host script makes: the position turned by hand, encoder faults and jumps
 * (docs/plant.md, docs/host-script.md "Plant").
 */
#include <stddef.h>
#include <string.h>
#include "plant_int.h"

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
        axb_counter_freeze(s, n, now);
        p->ssi_frozen = plant_ssi_value(s, n, now);
    }
    if (was == PLANT_ENC_FROZEN) {
        p->enc_fault = PLANT_ENC_OK;
        if (is_ssi(s)) {
            uint64_t mod = 1ull << p->ssi_bits;
            int64_t cur = ifloor(plant_out_rev(s, n, now) * p->ssi_res + 0.5);
            p->ssi_off = (int64_t)(((uint64_t)p->ssi_frozen - (uint64_t)cur) & (mod - 1));
        } else {
            axb_counter_thaw(s, n, now);
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
    axb_counter_jump(s, n, by);
    p->ssi_off += by;
    p->ssi_frozen = (uint32_t)(((uint64_t)p->ssi_frozen + (uint64_t)by) & ((1ull << p->ssi_bits) - 1));
    axb_counter_mirror(s, n, now);
}


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
    p->t0 = p->t_sync = now;
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
