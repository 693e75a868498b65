/*
 * servo_motion.c - the INC/SSI cards' out-of-line motion hooks
 * (motion_card.h; the STP's are stp_motion.c).
 */
#include "fw.h"
#include "card.h"
#include "params.h"
#include "motion.h"
#include "motion_priv.h"

int64_t vq(unsigned n, int32_t v)
{
    return ((int64_t)v * 65536) >> PAR(n, SF);
}

void motion_plan_card(unsigned n, motion_plan_t *p)
{
    servo_set_gains(&p->gains, PAR(n, GA), PAR(n, ZE), PAR(n, PO), PAR(n, KI), PAR(n, KISC));
    servo_set_limit(&p->gains, PAR(n, SW));      /* <sw>, torque (force) limitation */
}
