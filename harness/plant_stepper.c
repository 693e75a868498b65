/*
 * plant_stepper.c - the stepper motor and its driver of the MAC4-STP: the
 * rotor follows the driver's field (the pulses on STEP/DIR) while it can,
 * loses and regains sync by the rules of docs/plant.md.
 */
#include "plant_int.h"

/* ======================================================================== */
/* stepper motor                                                             */
/* ======================================================================== */
/* Sync rules (docs/plant.md): the rotor follows the field while the
 * frequency mismatch |f - v| stays within the start/stop frequency and f
 * within fmax; it catches up with the field at up to `accel`; out of sync it
 * coasts down at `accel` and locks in again once |f - v| <= ssf. */
int plant_stp_can_sync(sim_t *s, int n, double f, double v)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (!plant_drive_enabled(s, n))
        return 0;
    if (p->fmax > 0 && fabs_(f) > p->fmax)
        return 0;
    return fabs_(f - v) <= p->ssf * plant_boost(s, n);
}

void plant_stp_lose_sync(plant_axis_t *p, double v)
{
    if (!p->sync)
        return;
    p->x0 = (double)(p->cmd + p->off);
    p->v0 = v;
    p->sync = 0;
}

void plant_stp_try_resync(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->sync || !plant_stp_can_sync(s, n, axb_step_hz(s, n), p->v0))
        return;
    p->off = iround(p->x0) - p->cmd;   /* the rotor locks onto the nearest step */
    p->x0 = (double)(p->cmd + p->off);
    p->sync = 1;
}

void plant_stp_step(sim_t *s, int n, double dt)
{
    plant_axis_t *p = &s->plant.ax[n];
    double A = p->accel * plant_boost(s, n), v = p->v0;
    if (p->sync) {
        double f = axb_step_hz(s, n), a = A;
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

int plant_stp_at_rest(sim_t *s, int n)
{
    plant_axis_t *p = &s->plant.ax[n];
    if (p->sync)
        return p->v0 == axb_step_hz(s, n);
    return p->v0 == 0.0;   /* stalled or disabled, and resync already tried */
}
