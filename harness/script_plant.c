/* script_plant.c - host-script commands of the plant models (docs/host-script.md). */
#include "script.h"

int script_plant(script_t *sc, sim_t *s, char **tok, int n)
{
    (void)sc;
    (void)s;
    (void)tok;
    (void)n;
    return SCRIPT_NOT_MINE;
}
