/* MAC4-INC servo tick, floor: the 24-bit counter, linear axes the fast path (scenarios moving, ext_*).
 * (bench/floor/README.md; the parts: servo.inc) */
#include "servo.inc"
    SV_TICK MEAS_COUNTER, lin, 0, %d0-%d1/%d3-%d5/%d7/%a0/%a2, %d0-%d7/%a0/%a2-%a3
