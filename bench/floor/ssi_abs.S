/* MAC4-SSI servo tick, floor: SSI at the connector, absolute on linear axes (MK_SSI_ABS; scenarios moving, ext_compare).
 * (bench/floor/README.md; the parts: servo.inc) */
#include "servo.inc"
    SV_TICK MEAS_SSI_ABS, lin, 0, %d0-%d1/%d3-%d5/%d7/%a0-%a2, %d0-%d7/%a0-%a3
