/*
 * stp_motion.c - the MAC4-STP's out-of-line motion hooks (motion_card.h;
 * the servo cards' are servo_motion.c).
 */
#include "fw.h"
#include "mul16.h"
#include "card.h"
#include "params.h"
#include "motion.h"
#include "motion_priv.h"

int64_t stp_ssf_now;

int64_t vq(unsigned n, int32_t v)
{
    int32_t sf = PAR(n, SF);
    /* Hz -> steps per SP of 32 ms: x 0.032 = 134218 / 2^22 (2 ppm) */
    int64_t q = (int64_t)prof_umul32((uint32_t)(v < 0 ? -v : v), 134218u) >> 6;
    if (axes[n].sstat & SB(TURBO))
        q *= 10;                                 /* 4.1.3 */
    q >>= sf;
    return v < 0 ? -q : q;
}

void motion_plan_card(unsigned n, motion_plan_t *p)
{
    stp_motion_plan(n, vq(n, PAR(n, SSF)), &p->stp);   /* <ssf>, <lv>, TURBO (stepper.c) */
}
