/* MAC4-SSI servo tick, floor: encoders on the VMEbus, absolute on linear axes the fast path (scenarios external, external_full, encoder_loss).
 * (bench/floor/README.md; the parts: servo.inc) */
#include "servo.inc"
    SV_TICK MEAS_EXT, lin, 0, %d0-%d5/%d7/%a0-%a3, %d0-%d7/%a0-%a3
