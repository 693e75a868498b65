/* MAC4-INC command path, floor: the VME host's reads through the queues
 * (bench/floor/README.md; the parts: cmd.inc) */
#include "cmd.inc"
    CM_POLL %d2-%d7
