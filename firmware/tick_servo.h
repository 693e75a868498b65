/*
 * tick_servo.h - what the INC/SSI tick (tick_servo.c) owns of an axis
 * beyond its own pass: the servo filter's state, which the tick steps
 * (servo_filter, servo_step_k) and motion.c starts afresh at an E that
 * switches the drive on (motion_start, masked).  On the STP the state is
 * there and unused; the tick itself is fw.h's fw_isr_tick.
 */
#ifndef TICK_SERVO_H
#define TICK_SERVO_H
#include "inline.h"
#include "card.h"
#include "servo.h"

/* The filter starts from rest: no jump when the drive comes on. */
FW_INLINE void tick_servo_reset(axis_t *x)
{
    servo_reset(&x->servo);
}

#endif
