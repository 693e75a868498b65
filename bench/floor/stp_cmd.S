/* MAC4-STP command path, floor: the VME host's reads through the queues, ROUT
 * in Steps/SP (bench/floor/README.md; the parts: cmd.inc) */
#define REC(f) ST_##f
#include "cmd.inc"
    CM_POLL %d2-%d7, 1
