/*
 * plant_servo.c - the DC servo of the MAC4-INC/SSI: amplifier (velocity or
 * current mode, current limit), motor and load with viscous and Coulomb
 * friction, one fixed step at a time (plant.c's grid).  docs/plant.md.
 */
#include "plant_int.h"

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

void plant_servo_step(const plant_axis_t *p, double u, int en, double dt, double x, double w,
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

int plant_servo_at_rest(const plant_axis_t *p, double u, int en)
{
    if (p->v0 != 0.0)
        return 0;
    return fabs_(servo_torque(p, u, en, 0.0) + p->load) <= p->coulomb;
}
