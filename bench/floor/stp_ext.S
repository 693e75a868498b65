/* MAC4-STP tick, floor: encoders on the VMEbus, absolute, in increments (scenarios external, encoder_loss).
 * (bench/floor/README.md; the parts: stp.inc) */
#include "stp.inc"
    SM_TICK STM_EXT, 1, 0, 0, %d0-%d7/%a0-%a3
