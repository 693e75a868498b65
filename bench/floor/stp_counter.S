/* MAC4-STP tick, floor: the step counter, positioning on in the last direction (scenarios moving, ext_*).
 * (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_COUNTER, 0, 0, 0, %d0-%d7/%a0-%a2
