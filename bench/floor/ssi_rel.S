/* MAC4-SSI servo tick, floor: SSI at the connector through measure_delta (MK_SSI), absolute on linear axes the fast path (scenarios ext_table, ext_feedback).
 * (bench/floor/README.md; the parts: servo.inc) */
#include "servo.inc"
    SV_TICK MEAS_SSI_REL, lin, 0, %d0-%d5/%d7/%a0-%a3, %d0-%d7/%a0-%a3
