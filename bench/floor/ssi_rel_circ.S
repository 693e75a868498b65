/* MAC4-SSI servo tick, floor: SSI at the connector (MK_SSI), absolute on circular axes the fast path (scenarios circular, full).
 * (bench/floor/README.md; the parts: servo.inc) */
#include "servo.inc"
    SV_TICK MEAS_SSI_REL, circ, 0, %d0-%d5/%d7/%a0-%a3, %d0-%d7/%a0-%a3
