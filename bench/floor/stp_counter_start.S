/* MAC4-STP tick, floor: the step counter, a new direction the fast path (scenario creep: four moves starting).
 * (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_COUNTER, 0, 1, 0, %d0-%d7/%a0-%a2
