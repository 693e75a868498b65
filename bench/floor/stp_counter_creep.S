/* MAC4-STP tick, floor: the step counter, the creep phase beginning the fast
 * path (scenario creep_starts: four creep phases beginning in one tick).
 * (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_COUNTER, 0, 0, 0, %d0-%d7/%a0-%a2, 1
