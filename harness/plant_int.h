/* plant_int.h - what the plant's files share (plant.c, plant_servo.c,
 * plant_stepper.c, plant_config.c, plant_trace.c); not for the board or the
 * tools, which use plant.h. */
#ifndef PLANT_INT_H
#define PLANT_INT_H
#include "sim.h"
#include "plant.h"
#include "plant_math.h"

static inline int is_stp(sim_t *s) { return s->card == MAC4_CARD_STP; }
static inline int is_ssi(sim_t *s) { return s->card == MAC4_CARD_SSI; }
static inline cyc_t min_cyc(cyc_t a, cyc_t b) { return a < b ? a : b; }

/* positions of the current step, linear between t0 and t1 */
static inline double lerp_x(plant_axis_t *p, cyc_t t)
{
    if (p->t1 == CYC_NEVER || t <= p->t0)
        return p->x0;
    if (t >= p->t1)
        return p->x1;
    return p->x0 + (p->x1 - p->x0) * (double)(t - p->t0) / (double)(p->t1 - p->t0);
}

static inline double lerp_v(plant_axis_t *p, cyc_t t)
{
    if (p->t1 == CYC_NEVER || t <= p->t0)
        return p->v0;
    if (t >= p->t1)
        return p->v1;
    return p->v0 + (p->v1 - p->v0) * (double)(t - p->t0) / (double)(p->t1 - p->t0);
}

/* Stepper rotor position in steps (the generator must be clocked to t). */
static inline double stp_rotor(plant_axis_t *p, cyc_t t)
{
    return p->sync ? (double)(p->cmd + p->off) : lerp_x(p, t);
}

/* plant.c */
double plant_out_rev(sim_t *s, int n, cyc_t t);    /* output shaft revolutions */
int plant_drive_enabled(sim_t *s, int n);           /* /EN closed, no /STOP, no drive fault */
double plant_boost(sim_t *s, int n);                /* the stepper's ssf and accel factor now */
/* plant_servo.c: one step of the DC servo's mechanics */
void plant_servo_step(const plant_axis_t *p, double u, int en, double dt, double x, double w,
                      double *x1, double *w1);
int plant_servo_at_rest(const plant_axis_t *p, double u, int en);
/* plant_stepper.c: the stepper's sync rules and one step of its mechanics */
int plant_stp_can_sync(sim_t *s, int n, double f, double v);
void plant_stp_lose_sync(plant_axis_t *p, double v);
void plant_stp_try_resync(sim_t *s, int n);
void plant_stp_step(sim_t *s, int n, double dt);
int plant_stp_at_rest(sim_t *s, int n);
/* plant_trace.c */
void plant_trace_row(sim_t *s, int n, cyc_t t);

#endif
