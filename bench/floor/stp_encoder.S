/* MAC4-STP tick, floor: the encoder on the motor, increments to steps the fast path (scenario encoder).
 * (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_COUNTER, 1, 0, 0, %d0-%d7/%a0-%a2
