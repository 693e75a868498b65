/* MAC4-STP tick, floor: encoders on the VMEbus, absolute, in increments, the tick's own brake the fast path
 * (scenario external: the brake's last ramp step on four axes).  (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_EXT, 1, 0, 1, %d0-%d7/%a0-%a3
