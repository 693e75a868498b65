/* MAC4-STP tick, floor: the step counter, the tick's own brake the fast path (scenario braking).
 * (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_COUNTER, 0, 0, 1, %d0-%d7/%a0-%a2
