/*
 * ext_budget.c - the cycles per tick the extensions may take (ext.h,
 * docs/extensions.md): each asks here before it switches on.  A file of
 * its own below the dispatcher ext.c and the extensions, so that an
 * extension's one question does not call back into its dispatcher
 * (tools/callgraph.py).
 */
#include "card.h"
#include "ext.h"

uint32_t ext_load(void)
{
    uint32_t c = 0;
    int fb = 0;
    for (unsigned n = 0; n < MAC4_NAXES; n++) {
        if (ext_comp[n].on)
            c += ext_comp[n].rows ? EXT_W_TABLE2 : EXT_W_TABLE1;
        if (ext_pc[n].armed)
            c += EXT_W_COMPARE;
    }
    for (unsigned k = 0; k < EXT_FB_N; k++) {
        unsigned m = (ext_fb[k].setup >> 20) & 0xFu;
        if (m) {
            fb = 1;
            c += (m == FB_EXP || m == FB_TRACK) ? EXT_W_FB_FILTER : EXT_W_FB_SIMPLE;
        }
    }
    if (fb)
        c += EXT_W_FB_AXES;
    return c ? c + EXT_W_ROUND : 0;
}

/* the first extension switched on brings the round with it */
int ext_fits(uint32_t more)
{
    uint32_t load = ext_load();
    return (load ? load : EXT_W_ROUND) + more <= EXT_BUDGET;
}
