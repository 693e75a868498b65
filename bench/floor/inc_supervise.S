/* MAC4-INC supervision after a tick, floor: card_supervise_tick on the path of
 * four axes at work (bench/floor/README.md; the parts: sup.inc) */
#include "sup.inc"
    SU_SUPERVISE 0, %d2-%d7/%a2-%a3
