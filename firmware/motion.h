/* motion.h - modes, profile generator and protective reactions (motion.c). */
#ifndef MOTION_H
#define MOTION_H
#include <stdint.h>

void motion_start(unsigned n, uint8_t mode, uint8_t from);  /* at E, interrupts masked */
void motion_hold(unsigned n);                 /* setpoint := actual position, at rest */
void motion_emergency(unsigned n, uint8_t then);  /* ramp <ed> from the next tick on, then STOP_* */
void motion_brake(unsigned n);                /* ramp <pd> from the next tick on (stop bits) */
void motion_profile_tick(unsigned n);         /* main loop, once per SP: the next segment */
int motion_segment(unsigned n);               /* STP tick, at the SP boundary; 1 if late */
int16_t motion_servo_tick(unsigned n, unsigned phase);  /* STP, every tick (INC/SSI: card.c) */
void motion_supervise(unsigned n);            /* main loop, after every tick: index, protection */
int motion_busy(unsigned n);                  /* a move that off-fly waits for (5.15) */
int motion_at_rest(unsigned n);

#endif
