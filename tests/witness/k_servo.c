/* k_servo.c - witness kernel: the servo filter of firmware/servo.c (5.16). */
#include "witness.h"
#include "servo.c"

/* the gains of the manual's examples, then random ones in the ranges of commands.def */
static const int16_t manual[][5] = {
    {40, 0, 0, 0, 8}, {160, 200, 0, 0, 8}, {80, 230, -100, 20, 4}, {32767, 255, 255, 32767, 0},
    {1, 0, -255, 1, 15}, {0, 0, 0, 0, 0},
};

W_KERNEL(servo)
{
    w_rng_t r;
    w_seed(&r, "servo");
    for (uint32_t n = 0; n < 120; n++) {
        int32_t ga, ze, po, ki, kisc;
        if (n < sizeof manual / sizeof manual[0]) {
            ga = manual[n][0], ze = manual[n][1], po = manual[n][2], ki = manual[n][3], kisc = manual[n][4];
        } else {
            ga = (int32_t)(w_rand(&r) % 32768u);
            ze = (int32_t)(w_rand(&r) % 256u);
            po = (int32_t)(w_rand(&r) % 511u) - 255;
            ki = (w_rand(&r) & 1) ? 0 : (int32_t)(w_rand(&r) % 32768u);
            kisc = (int32_t)(w_rand(&r) % 16u);
        }
        servo_gains_t g;
        servo_state_t s;
        servo_set_gains(&g, ga, ze, po, ki, kisc);
        servo_reset(&s);
        w_begin("servo", "gains", n);
        w_u32((uint32_t)ga);
        w_u32((uint32_t)ze);
        w_u32((uint32_t)po);
        w_u32((uint32_t)ki);
        w_u32((uint32_t)kisc);
        w_u32((uint32_t)g.e_lim);
        w_end();
        int32_t e = 0;
        for (uint32_t k = 0; k < 200; k++) {
            switch ((w_rand(&r) >> 5) & 3u) {
            case 0: e = (int32_t)w_edgy(&r); break;               /* anything */
            case 1: e = (int32_t)((uint32_t)e + w_rand(&r) % 201u - 100u); break;   /* a random walk */
            default: break;                                      /* hold */
            }
            int16_t u = servo_step(&s, &g, e);
            w_begin("servo", "step", n << 8 | k);
            w_u32((uint32_t)e);
            w_u32((uint32_t)(int32_t)u);
            w_u32((uint32_t)s.u1);
            w_u32((uint32_t)s.u2);
            w_u32((uint32_t)s.u2_res);
            w_u32((uint32_t)(int32_t)s.e_prev);
            w_end();
        }
    }
}
