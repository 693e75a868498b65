/* MAC4-SSI servo tick, floor: SSI absolute on linear axes, the tick's own brake the fast path (scenario braking).
 * (bench/floor/README.md; the parts: servo.inc) */
#include "servo.inc"
    SV_TICK MEAS_SSI_ABS, lin, 1, %d0-%d1/%d3-%d5/%d7/%a0-%a2, %d0-%d7/%a0-%a3
